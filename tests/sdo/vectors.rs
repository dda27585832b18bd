//! Public SDO vectors V1-V16, byte-exact frame sequences taken from
//! python-canopen's `test/test_sdo.py` and CANopenNode's
//! `test/running_canopen/*.bats`, replayed frame by frame against our SDO
//! server and client. LENIENT vectors assert our
//! strict abort instead.

use crate::common;

use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, MemoryDictionary};
use canopen_codec::sdo::{
    AbortCode, AbortOrigin, Client, ClientConfig, ClientEvent, Server, ServerConfig, ServerEvent,
    TransferEnd,
};
use canopen_codec::{NodeId, Timestamp};
use common::frame;

fn server(node: u8, od: MemoryDictionary) -> Server<MemoryDictionary> {
    Server::new(ServerConfig::for_node(NodeId::new(node).unwrap()), od)
}

thread_local! {
    static EVENTS: std::cell::RefCell<Vec<ServerEvent>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// Feeds `req` (hex) to the server and asserts it answers exactly `resp`;
/// drains its events (see [`events`]).
fn exchange(s: &mut Server<MemoryDictionary>, node: u16, req: &str, resp: &str) {
    s.handle_frame(Timestamp::ZERO, &frame(0x600 + node, req));
    assert_eq!(
        s.poll_transmit(),
        Some(frame(0x580 + node, resp)),
        "answer to {req}"
    );
    assert_eq!(s.poll_transmit(), None);
    EVENTS.with(|e| e.borrow_mut().extend(std::iter::from_fn(|| s.poll_event())));
}

/// The server events since the last call.
fn events(s: &mut Server<MemoryDictionary>) -> Vec<ServerEvent> {
    assert_eq!(s.poll_event(), None);
    EVENTS.with(|e| std::mem::take(&mut *e.borrow_mut()))
}

fn client(node: u8) -> Client<Vec<u8>> {
    Client::new(ClientConfig::for_server(NodeId::new(node).unwrap()))
}

fn sent(c: &mut Client<Vec<u8>>) -> Vec<canopen_codec::CanFrame> {
    std::iter::from_fn(|| c.poll_transmit()).collect()
}

fn client_events(c: &mut Client<Vec<u8>>) -> Vec<ClientEvent> {
    std::iter::from_fn(|| c.poll_event()).collect()
}

fn data(index: u16, sub: u8, offset: usize, bytes: &[u8]) -> ClientEvent {
    ClientEvent::UploadData {
        index,
        sub,
        offset,
        data: canopen_codec::sdo::SegmentData::new(bytes).unwrap(),
    }
}

const TINY: &[u8] = b"Tiny Node - Mega Domains !";

// ---------------------------------------------------------------- server

#[test]
fn server_v1_v1b_v4_v15_expedited() {
    let mut od = MemoryDictionary::new();
    od.insert(0x1018, 0, Access::Const, &[4]);
    od.insert(0x1018, 2, Access::ReadOnly, &[0, 0, 0, 0]);
    od.insert(0x1400, 2, Access::ReadWrite, &[0xFE]);
    od.insert(0x1017, 0, Access::ReadWrite, &[0, 0]);
    let mut s = server(2, od);
    s.od_mut()
        .insert(0x1018, 1, Access::ReadOnly, &[4, 0, 0, 0]);
    exchange(&mut s, 2, "4018100100000000", "4318100104000000"); // V1
    exchange(&mut s, 2, "4000140200000000", "4F001402FE000000"); // V1b, our DLC 8
    exchange(&mut s, 2, "2B171000A00F0000", "6017100000000000"); // V4
    assert_eq!(s.od().get(0x1017, 0), Some(&[0xA0, 0x0F][..]));
    assert_eq!(
        events(&mut s),
        vec![
            ServerEvent::Uploaded {
                index: 0x1018,
                sub: 1,
                len: 4
            },
            ServerEvent::Uploaded {
                index: 0x1400,
                sub: 2,
                len: 1
            },
            ServerEvent::Downloaded {
                index: 0x1017,
                sub: 0,
                len: 2
            },
        ]
    );
    // V15: sub-index 3 does not exist.
    exchange(&mut s, 2, "4018100300000000", "8018100311000906");
}

#[test]
fn server_v5_v6_v7_canopennode_downloads() {
    let mut od = MemoryDictionary::new();
    od.insert(0x1017, 0, Access::ReadWrite, &[0xE8, 0x03]);
    od.insert(0x1400, 1, Access::ReadWrite, &[0x04, 0x02, 0, 0]);
    od.insert(0x1016, 2, Access::ReadWrite, &[0, 0, 0, 0]);
    let mut s = server(4, od);
    exchange(&mut s, 4, "2B17100000000000", "6017100000000000"); // V5
    exchange(&mut s, 4, "2300140104020080", "6000140100000000"); // V6
    exchange(&mut s, 4, "23161002F0000100", "6016100200000000"); // V7
    assert_eq!(s.od().get(0x1017, 0), Some(&[0, 0][..]));
    assert_eq!(s.od().get(0x1400, 1), Some(&[0x04, 0x02, 0x00, 0x80][..]));
    assert_eq!(s.od().get(0x1016, 2), Some(&[0xF0, 0x00, 0x01, 0x00][..]));
}

#[test]
fn server_v8_segmented_upload() {
    let mut od = MemoryDictionary::new();
    od.insert_variable(0x1008, 0, Access::Const, TINY, 64);
    let mut s = server(2, od);
    exchange(&mut s, 2, "4008100000000000", "410810001A000000");
    exchange(&mut s, 2, "6000000000000000", "0054696E79204E6F");
    exchange(&mut s, 2, "7000000000000000", "106465202D204D65");
    exchange(&mut s, 2, "6000000000000000", "00676120446F6D61");
    exchange(&mut s, 2, "7000000000000000", "15696E7320210000");
    assert_eq!(
        events(&mut s),
        vec![ServerEvent::Uploaded {
            index: 0x1008,
            sub: 0,
            len: 26
        }]
    );
    assert!(!s.is_busy());
}

#[test]
fn server_v11_v12_v13_v14_segmented_download() {
    let mut od = MemoryDictionary::new();
    od.insert_variable(0x2000, 0, Access::ReadWrite, b"", 64);
    od.insert_variable(0x2120, 0x0B, Access::ReadWrite, b"", 64);
    let mut s = server(2, od.clone());
    // V11 (our acks zero-fill the reserved bytes, as CANopenNode's V12 does).
    exchange(&mut s, 2, "210020000D000000", "6000200000000000");
    exchange(&mut s, 2, "0041206C6F6E6720", "2000000000000000");
    exchange(&mut s, 2, "13737472696E6700", "3000000000000000");
    assert_eq!(s.od().get(0x2000, 0), Some(&b"A long string"[..]));
    // V13: zero length.
    exchange(&mut s, 2, "2100200000000000", "6000200000000000");
    exchange(&mut s, 2, "0F00000000000000", "2000000000000000");
    assert_eq!(s.od().get(0x2000, 0), Some(&b""[..]));
    // V14: size not indicated, short non-final segment, empty last segment.
    exchange(&mut s, 2, "2000200000000000", "6000200000000000");
    exchange(&mut s, 2, "0031323334353637", "2000000000000000");
    exchange(&mut s, 2, "1A38390000000000", "3000000000000000");
    exchange(&mut s, 2, "0F00000000000000", "2000000000000000");
    assert_eq!(s.od().get(0x2000, 0), Some(&b"123456789"[..]));
    assert_eq!(
        events(&mut s),
        vec![
            ServerEvent::Downloaded {
                index: 0x2000,
                sub: 0,
                len: 13
            },
            ServerEvent::Downloaded {
                index: 0x2000,
                sub: 0,
                len: 0
            },
            ServerEvent::Downloaded {
                index: 0x2000,
                sub: 0,
                len: 9
            },
        ]
    );
    // V12: CANopenNode server node 4, byte-exact.
    let mut s = server(4, od);
    exchange(&mut s, 4, "2120210B13000000", "6020210B00000000");
    exchange(&mut s, 4, "0066696C65577269", "2000000000000000");
    exchange(&mut s, 4, "107474656E427944", "3000000000000000");
    exchange(&mut s, 4, "056F6D61696E0000", "2000000000000000");
    assert_eq!(s.od().get(0x2120, 0x0B), Some(&b"fileWrittenByDomain"[..]));
}

#[test]
fn server_v16_client_abort_without_multiplexer() {
    // python-canopen's abort frame carries index/sub 0: it still ends our
    // transfer, and nothing is sent back.
    let mut od = MemoryDictionary::new();
    od.insert_variable(0x1008, 0, Access::Const, TINY, 64);
    let mut s = server(2, od);
    exchange(&mut s, 2, "4008100000000000", "410810001A000000");
    s.handle_frame(Timestamp::ZERO, &frame(0x602, "8000000000000405"));
    assert_eq!(s.poll_transmit(), None);
    assert!(EVENTS.with(|e| e.borrow().is_empty()));
    assert_eq!(
        std::iter::from_fn(|| s.poll_event()).collect::<Vec<_>>(),
        vec![ServerEvent::Aborted {
            index: 0x1008,
            sub: 0,
            code: AbortCode::SdoProtocolTimedOut,
            origin: AbortOrigin::Peer
        }]
    );
}

// ---------------------------------------------------------------- client

#[test]
fn client_v1_v1b_v2_v3_expedited_uploads() {
    let cases: [(u16, u8, &str, &[u8]); 5] = [
        (0x1018, 1, "4318100104000000", &[4, 0, 0, 0]), // V1
        (0x1400, 2, "4F001402FE", &[0xFE]),             // V1b, DLC 5
        (0x1400, 2, "42001402FE000000", &[0xFE, 0, 0, 0]), // V1c / V2
        (0x2006, 0, "4B062000FEFDFCFB", &[0xFE, 0xFD]), // V3, n=2
        (0x2016, 0, "47162000FEFDFCFB", &[0xFE, 0xFD, 0xFC]), // V3, n=1
    ];
    for (index, sub, resp, value) in cases {
        let mut c = client(2);
        c.start_upload(Timestamp::ZERO, index, sub).unwrap();
        let [lo, hi] = index.to_le_bytes();
        assert_eq!(
            sent(&mut c),
            vec![frame(
                0x602,
                &format!("40{lo:02X}{hi:02X}{sub:02X}00000000")
            )]
        );
        c.handle_frame(Timestamp::from_millis(1), &frame(0x582, resp));
        assert_eq!(sent(&mut c), vec![]);
        assert_eq!(
            client_events(&mut c),
            vec![
                data(index, sub, 0, value),
                ClientEvent::Ended(TransferEnd::Uploaded {
                    index,
                    sub,
                    len: value.len()
                })
            ]
        );
        assert!(!c.is_busy());
    }
}

#[test]
fn client_v4_expedited_download() {
    let mut c = client(2);
    c.start_download(Timestamp::ZERO, 0x1017, 0, vec![0xA0, 0x0F])
        .unwrap();
    assert_eq!(sent(&mut c), vec![frame(0x602, "2B171000A00F0000")]);
    c.handle_frame(Timestamp::from_millis(1), &frame(0x582, "6017100000000000"));
    assert_eq!(
        client_events(&mut c),
        vec![ClientEvent::Ended(TransferEnd::Downloaded {
            index: 0x1017,
            sub: 0,
            len: 2
        })]
    );
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn client_v8_segmented_upload() {
    let mut c = client(2);
    c.start_upload(Timestamp::ZERO, 0x1008, 0).unwrap();
    assert_eq!(sent(&mut c), vec![frame(0x602, "4008100000000000")]);
    let script = [
        ("410810001A000000", "6000000000000000"),
        ("0054696E79204E6F", "7000000000000000"),
        ("106465202D204D65", "6000000000000000"),
        ("00676120446F6D61", "7000000000000000"),
    ];
    let mut ev = Vec::new();
    for (i, (resp, req)) in script.iter().enumerate() {
        c.handle_frame(Timestamp::from_millis(i as u64 + 1), &frame(0x582, resp));
        assert_eq!(sent(&mut c), vec![frame(0x602, req)]);
        ev.extend(client_events(&mut c));
    }
    c.handle_frame(Timestamp::from_millis(9), &frame(0x582, "15696E7320210000"));
    assert_eq!(sent(&mut c), vec![]);
    ev.extend(client_events(&mut c));
    assert_eq!(
        ev.last(),
        Some(&ClientEvent::Ended(TransferEnd::Uploaded {
            index: 0x1008,
            sub: 0,
            len: 26
        }))
    );
    let mut value = Vec::new();
    for e in &ev {
        if let ClientEvent::UploadData { data, .. } = e {
            value.extend_from_slice(data.as_slice());
        }
    }
    assert_eq!(value, TINY);
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn client_v9_lenient_too_much_data_is_aborted() {
    let mut c = client(2);
    c.start_upload(Timestamp::ZERO, 0x1008, 0).unwrap();
    let _ = sent(&mut c);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "4108100004000000"));
    assert_eq!(sent(&mut c), vec![frame(0x602, "6000000000000000")]);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "0554696E79200000"));
    // python-canopen truncates to "Tiny"; we abort 06070012h.
    assert_eq!(sent(&mut c), vec![frame(0x602, "8008100012000706")]);
    assert_eq!(
        client_events(&mut c),
        vec![ClientEvent::Ended(TransferEnd::Aborted {
            index: 0x1008,
            sub: 0,
            code: AbortCode::DataTypeLengthTooHigh,
            origin: AbortOrigin::Local
        })]
    );
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn client_v10_lenient_bogus_size_is_aborted() {
    let mut c = client(2);
    c.start_upload(Timestamp::ZERO, 0x201B, 0).unwrap();
    assert_eq!(sent(&mut c), vec![frame(0x602, "401B200000000000")]);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "411B2000FEFDFCFB"));
    assert_eq!(sent(&mut c), vec![frame(0x602, "6000000000000000")]);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "00B2012002911203"));
    assert_eq!(sent(&mut c), vec![frame(0x602, "7000000000000000")]);
    let mut ev = client_events(&mut c);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "1D192170FEFDFCFB"));
    // python-canopen returns 8 bytes; 8 < 0xFBFCFDFE, so we abort 06070013h.
    assert_eq!(sent(&mut c), vec![frame(0x602, "801B200013000706")]);
    ev.extend(client_events(&mut c));
    assert_eq!(
        ev.last(),
        Some(&ClientEvent::Ended(TransferEnd::Aborted {
            index: 0x201B,
            sub: 0,
            code: AbortCode::DataTypeLengthTooLow,
            origin: AbortOrigin::Local
        }))
    );
    assert_eq!(ev.iter().filter(|e| e.is_terminal()).count(), 1);
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn client_v11_v13_segmented_downloads() {
    let mut c = client(2);
    c.start_download(Timestamp::ZERO, 0x2000, 0, b"A long string".to_vec())
        .unwrap();
    assert_eq!(sent(&mut c), vec![frame(0x602, "210020000D000000")]);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "6000200000000000"));
    assert_eq!(sent(&mut c), vec![frame(0x602, "0041206C6F6E6720")]);
    // The fixture's ack has non-zero reserved bytes: ignored.
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "2000200000000000"));
    assert_eq!(sent(&mut c), vec![frame(0x602, "13737472696E6700")]);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "3000200000000000"));
    assert_eq!(
        client_events(&mut c),
        vec![ClientEvent::Ended(TransferEnd::Downloaded {
            index: 0x2000,
            sub: 0,
            len: 13
        })]
    );
    // V13: the empty value is one empty last segment.
    c.start_download(Timestamp::ZERO, 0x2000, 0, Vec::new())
        .unwrap();
    assert_eq!(sent(&mut c), vec![frame(0x602, "2100200000000000")]);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "6000200000000000"));
    assert_eq!(sent(&mut c), vec![frame(0x602, "0F00000000000000")]);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "2000000000000000"));
    assert_eq!(
        client_events(&mut c),
        vec![ClientEvent::Ended(TransferEnd::Downloaded {
            index: 0x2000,
            sub: 0,
            len: 0
        })]
    );
}

#[test]
fn client_v15_received_abort() {
    let mut c = client(2);
    c.start_upload(Timestamp::ZERO, 0x1018, 1).unwrap();
    let _ = sent(&mut c);
    c.handle_frame(Timestamp::ZERO, &frame(0x582, "8018100111000906"));
    assert_eq!(sent(&mut c), vec![], "nothing is sent back");
    assert_eq!(
        client_events(&mut c),
        vec![ClientEvent::Ended(TransferEnd::Aborted {
            index: 0x1018,
            sub: 1,
            code: AbortCode::SubIndexDoesNotExist,
            origin: AbortOrigin::Peer
        })]
    );
}

#[test]
fn client_v16_timeout_abort_carries_the_multiplexer() {
    let mut c = client(2);
    c.start_upload(Timestamp::ZERO, 0x1018, 1).unwrap();
    let _ = sent(&mut c);
    assert_eq!(c.poll_timeout(), Some(Timestamp::from_millis(2000)));
    c.handle_timeout(Timestamp::from_millis(1999));
    assert_eq!(sent(&mut c), vec![]);
    c.handle_timeout(Timestamp::from_millis(2000));
    // CiA-conformant form (CANopenNode, Lely), not python-canopen's 80 00 00 00.
    assert_eq!(sent(&mut c), vec![frame(0x602, "8018100100000405")]);
    assert_eq!(
        client_events(&mut c),
        vec![ClientEvent::Ended(TransferEnd::Aborted {
            index: 0x1018,
            sub: 1,
            code: AbortCode::SdoProtocolTimedOut,
            origin: AbortOrigin::Local
        })]
    );
    assert_eq!(c.poll_timeout(), None);
}

/// CiA 301 section 7.2.4.3.13: the server says it will send a CRC (sc) only
/// when the client asked for one (cc). python-canopen checks a CRC it is told
/// of even when it did not ask, and the CRC of the end frame is then zero.
#[test]
fn server_block_upload_sets_sc_only_when_the_client_asked_for_crc() {
    let mut od = MemoryDictionary::new();
    od.insert(0x2000, 0, Access::ReadOnly, b"0123456789");
    let mut s = server(2, od);
    // ccs 5, cc 0, cs 0; blksize 127, pst 0: sc 0, s 1, size 10.
    exchange(
        &mut s,
        2,
        "A0 00 20 00 7F 00 00 00",
        "C2 00 20 00 0A 00 00 00",
    );
    s.handle_frame(Timestamp::ZERO, &frame(0x602, "80 00 20 00 00 00 04 05"));
    while s.poll_transmit().is_some() {}
    while s.poll_event().is_some() {}
    // ccs 5, cc 1, cs 0: sc 1.
    exchange(
        &mut s,
        2,
        "A4 00 20 00 7F 00 00 00",
        "C6 00 20 00 0A 00 00 00",
    );
}
