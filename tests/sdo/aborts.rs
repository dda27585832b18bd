//! Every SDO abort path, each asserting the exact abort frame (or, for a
//! received abort, that nothing is sent) and exactly one terminal event.

use crate::common;

use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, MemoryDictionary};
use canopen_codec::sdo::{
    AbortCode, AbortOrigin, Client, ClientConfig, ClientEvent, Server, ServerConfig, ServerEvent,
    TransferEnd,
};
use canopen_codec::{CanFrame, NodeId, Timestamp};
use common::frame;

const T0: Timestamp = Timestamp::ZERO;

fn od() -> MemoryDictionary {
    let mut od = MemoryDictionary::new();
    od.insert(0x1000, 0, Access::Const, &[0xA2, 0x01, 0x0F, 0x00]);
    od.insert(0x1017, 0, Access::ReadWrite, &[0xE8, 0x03]);
    od.insert(0x1018, 1, Access::ReadOnly, &[1, 2, 3, 4]);
    od.insert(0x2000, 0, Access::WriteOnly, &[0, 0, 0, 0]);
    od.insert(0x2001, 0, Access::ReadWrite, &[0; 8]);
    od.insert_variable(0x1008, 0, Access::ReadWrite, b"battery module", 20);
    od
}

fn server() -> Server<MemoryDictionary> {
    Server::new(ServerConfig::for_node(NodeId::new(1).unwrap()), od())
}

fn client() -> Client<Vec<u8>> {
    Client::new(ClientConfig::for_server(NodeId::new(1).unwrap()))
}

/// Feeds requests to a server; returns every frame it sent and its events.
fn serve(s: &mut Server<MemoryDictionary>, reqs: &[&str]) -> (Vec<CanFrame>, Vec<ServerEvent>) {
    let mut out = Vec::new();
    let mut ev = Vec::new();
    for r in reqs {
        s.handle_frame(T0, &frame(0x601, r));
        out.extend(std::iter::from_fn(|| s.poll_transmit()));
        ev.extend(std::iter::from_fn(|| s.poll_event()));
    }
    (out, ev)
}

fn server_abort(index: u16, sub: u8, code: AbortCode) -> ServerEvent {
    ServerEvent::Aborted {
        index,
        sub,
        code,
        origin: AbortOrigin::Local,
    }
}

fn client_abort(index: u16, sub: u8, code: AbortCode) -> ClientEvent {
    ClientEvent::Ended(TransferEnd::Aborted {
        index,
        sub,
        code,
        origin: AbortOrigin::Local,
    })
}

/// Asserts the last frame is `abort` and exactly one terminal event, the given one.
fn assert_server_abort(reqs: &[&str], abort: &str, event: ServerEvent) {
    let mut s = server();
    let (out, ev) = serve(&mut s, reqs);
    assert_eq!(out.last(), Some(&frame(0x581, abort)), "{reqs:?}");
    assert_eq!(ev, vec![event], "{reqs:?}");
    assert!(!s.is_busy());
    assert_eq!(s.poll_timeout(), None);
}

// ------------------------------------------------------------ server side

#[test]
fn server_timeout() {
    let mut s = server();
    let (_, ev) = serve(&mut s, &["4008100000000000"]);
    assert!(ev.is_empty());
    assert_eq!(s.poll_timeout(), Some(Timestamp::from_millis(2000)));
    s.handle_timeout(Timestamp::from_millis(1999));
    assert_eq!(s.poll_transmit(), None);
    s.handle_timeout(Timestamp::from_millis(2000));
    assert_eq!(s.poll_transmit(), Some(frame(0x581, "8008100000000405")));
    assert_eq!(
        s.poll_event(),
        Some(server_abort(0x1008, 0, AbortCode::SdoProtocolTimedOut))
    );
    assert_eq!(s.poll_event(), None);
    // A second handle_timeout is harmless.
    s.handle_timeout(Timestamp::from_millis(5000));
    assert_eq!(s.poll_transmit(), None);
}

#[test]
fn server_bad_command_specifier() {
    // ccs = 7 while a segmented upload of 1008h runs.
    assert_server_abort(
        &["4008100000000000", "E000000000000000"],
        "8008100001000405",
        server_abort(0x1008, 0, AbortCode::InvalidCommandSpecifier),
    );
    // A block upload start with no block upload initiated.
    assert_server_abort(
        &["A300000000000000"],
        "8000000001000405",
        server_abort(0, 0, AbortCode::InvalidCommandSpecifier),
    );
    // A download segment while an upload runs.
    assert_server_abort(
        &["4008100000000000", "0041414141414141"],
        "8008100001000405",
        server_abort(0x1008, 0, AbortCode::InvalidCommandSpecifier),
    );
    // An upload segment request with no transfer running.
    assert_server_abort(
        &["6000000000000000"],
        "8000000001000405",
        server_abort(0, 0, AbortCode::InvalidCommandSpecifier),
    );
    // An upload segment request while a segmented download of 2001h runs.
    assert_server_abort(
        &["2101200008000000", "6000000000000000"],
        "8001200001000405",
        server_abort(0x2001, 0, AbortCode::InvalidCommandSpecifier),
    );
}

#[test]
fn server_toggle_errors() {
    // Upload: second request repeats t=0.
    assert_server_abort(
        &["4008100000000000", "6000000000000000", "6000000000000000"],
        "8008100000000305",
        server_abort(0x1008, 0, AbortCode::ToggleBitNotAlternated),
    );
    // Download: first segment with t=1.
    assert_server_abort(
        &["2108100009000000", "1041414141414141"],
        "8008100000000305",
        server_abort(0x1008, 0, AbortCode::ToggleBitNotAlternated),
    );
}

#[test]
fn server_more_data_than_indicated() {
    assert_server_abort(
        &["2108100005000000", "0041414141414141"],
        "8008100012000706",
        server_abort(0x1008, 0, AbortCode::DataTypeLengthTooHigh),
    );
    // No size indicated, but longer than the object's 20-byte maximum.
    assert_server_abort(
        &[
            "2008100000000000",
            "0041414141414141",
            "1041414141414141",
            "0041414141414141",
        ],
        "8008100012000706",
        server_abort(0x1008, 0, AbortCode::DataTypeLengthTooHigh),
    );
}

#[test]
fn server_less_data_than_indicated() {
    assert_server_abort(
        &["2108100009000000", "0141414141414141"],
        "8008100013000706",
        server_abort(0x1008, 0, AbortCode::DataTypeLengthTooLow),
    );
}

#[test]
fn server_object_and_sub_missing() {
    assert_server_abort(
        &["4000300000000000"],
        "8000300000000206",
        server_abort(0x3000, 0, AbortCode::ObjectDoesNotExist),
    );
    assert_server_abort(
        &["4018100200000000"],
        "8018100211000906",
        server_abort(0x1018, 2, AbortCode::SubIndexDoesNotExist),
    );
    assert_server_abort(
        &["2B00300000000000"],
        "8000300000000206",
        server_abort(0x3000, 0, AbortCode::ObjectDoesNotExist),
    );
}

#[test]
fn server_read_only_and_write_only() {
    assert_server_abort(
        &["2318100101000000"],
        "8018100102000106",
        server_abort(0x1018, 1, AbortCode::WriteOfReadOnlyObject),
    );
    // Const objects are never writable.
    assert_server_abort(
        &["2300100001000000"],
        "8000100002000106",
        server_abort(0x1000, 0, AbortCode::WriteOfReadOnlyObject),
    );
    assert_server_abort(
        &["4000200000000000"],
        "8000200001000106",
        server_abort(0x2000, 0, AbortCode::ReadOfWriteOnlyObject),
    );
}

#[test]
fn server_length_mismatch() {
    // 3 bytes to a 2-byte object: too high.
    assert_server_abort(
        &["2717100001020300"],
        "8017100012000706",
        server_abort(0x1017, 0, AbortCode::DataTypeLengthTooHigh),
    );
    // 1 byte to a 2-byte object: too low.
    assert_server_abort(
        &["2F17100001000000"],
        "8017100013000706",
        server_abort(0x1017, 0, AbortCode::DataTypeLengthTooLow),
    );
    // Segmented, size 9, to an 8-byte object: too high at initiate.
    assert_server_abort(
        &["2101200009000000"],
        "8001200012000706",
        server_abort(0x2001, 0, AbortCode::DataTypeLengthTooHigh),
    );
    // Expedited without size to an 8-byte object: cannot match.
    assert_server_abort(
        &["2201200001020304"],
        "8001200010000706",
        server_abort(0x2001, 0, AbortCode::DataTypeLengthMismatch),
    );
    // Segmented without size, ending short of a fixed object.
    assert_server_abort(
        &["2001200000000000", "0741414141000000"],
        "8001200013000706",
        server_abort(0x2001, 0, AbortCode::DataTypeLengthTooLow),
    );
}

#[test]
fn server_received_abort_sends_nothing() {
    let mut s = server();
    let (out, ev) = serve(&mut s, &["4008100000000000", "8008100000000008"]);
    assert_eq!(out, vec![frame(0x581, "410810000E000000")]);
    assert_eq!(
        ev,
        vec![ServerEvent::Aborted {
            index: 0x1008,
            sub: 0,
            code: AbortCode::GeneralError,
            origin: AbortOrigin::Peer
        }]
    );
    // Code 0 is reported as a general error.
    let (_, ev) = serve(&mut s, &["4008100000000000", "8008100000000000"]);
    assert_eq!(
        ev,
        vec![ServerEvent::Aborted {
            index: 0x1008,
            sub: 0,
            code: AbortCode::GeneralError,
            origin: AbortOrigin::Peer
        }]
    );
    // An abort with no transfer running is ignored.
    let (out, ev) = serve(&mut s, &["8008100000000008"]);
    assert!(out.is_empty() && ev.is_empty());
}

#[test]
fn server_new_initiate_supersedes() {
    let mut s = server();
    let (out, ev) = serve(
        &mut s,
        &["2108100009000000", "0041414141414141", "4017100000000000"],
    );
    assert_eq!(out.last(), Some(&frame(0x581, "4B171000E8030000")));
    assert_eq!(
        ev,
        vec![
            ServerEvent::Aborted {
                index: 0x1008,
                sub: 0,
                code: AbortCode::GeneralError,
                origin: AbortOrigin::Superseded
            },
            ServerEvent::Uploaded {
                index: 0x1017,
                sub: 0,
                len: 2
            }
        ]
    );
    // The superseded download left the value untouched.
    assert_eq!(s.od().get(0x1008, 0), Some(&b"battery module"[..]));
}

#[test]
fn server_ignores_other_ids_short_frames_and_remote() {
    let mut s = server();
    for f in [
        frame(0x602, "4008100000000000"),
        frame(0x581, "4008100000000000"),
        frame(0x601, ""),
        frame(0x601, "4008"),
        frame(0x601, "23171000E803"),
        CanFrame::remote(canopen_codec::CanId::Standard(0x601), 8).unwrap(),
        CanFrame::new(
            canopen_codec::CanId::Extended(0x601),
            &[0x40, 0x08, 0x10, 0],
        )
        .unwrap(),
    ] {
        s.handle_frame(T0, &f);
        assert_eq!(s.poll_transmit(), None, "{f}");
        assert_eq!(s.poll_event(), None, "{f}");
    }
}

// ------------------------------------------------------------ client side

fn client_run(
    start: impl FnOnce(&mut Client<Vec<u8>>),
    resps: &[&str],
) -> (Vec<CanFrame>, Vec<ClientEvent>) {
    let mut c = client();
    start(&mut c);
    let mut out: Vec<CanFrame> = std::iter::from_fn(|| c.poll_transmit()).collect();
    let mut ev = Vec::new();
    for r in resps {
        c.handle_frame(T0, &frame(0x581, r));
        out.extend(std::iter::from_fn(|| c.poll_transmit()));
        ev.extend(std::iter::from_fn(|| c.poll_event()));
    }
    assert!(!c.is_busy());
    (out, ev)
}

fn upload(index: u16, sub: u8) -> impl FnOnce(&mut Client<Vec<u8>>) {
    move |c| c.start_upload(T0, index, sub).unwrap()
}

fn download(index: u16, sub: u8, v: &[u8]) -> impl FnOnce(&mut Client<Vec<u8>>) {
    let v = v.to_vec();
    move |c| c.start_download(T0, index, sub, v).unwrap()
}

fn assert_client_abort(
    start: impl FnOnce(&mut Client<Vec<u8>>),
    resps: &[&str],
    abort: &str,
    event: ClientEvent,
) {
    let (out, ev) = client_run(start, resps);
    assert_eq!(out.last(), Some(&frame(0x601, abort)));
    assert_eq!(
        ev.iter().filter(|e| e.is_terminal()).collect::<Vec<_>>(),
        vec![&event]
    );
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn client_timeout_restarts_on_every_frame() {
    let mut c = client();
    c.start_upload(T0, 0x1008, 0).unwrap();
    let _ = c.poll_transmit();
    c.handle_frame(
        Timestamp::from_millis(1500),
        &frame(0x581, "4108100010000000"),
    );
    assert_eq!(c.poll_transmit(), Some(frame(0x601, "6000000000000000")));
    assert_eq!(c.poll_timeout(), Some(Timestamp::from_millis(3500)));
    c.handle_timeout(Timestamp::from_millis(3000));
    assert_eq!(c.poll_transmit(), None);
    c.handle_timeout(Timestamp::from_millis(3500));
    assert_eq!(c.poll_transmit(), Some(frame(0x601, "8008100000000405")));
    assert_eq!(
        c.poll_event(),
        Some(client_abort(0x1008, 0, AbortCode::SdoProtocolTimedOut))
    );
    assert_eq!(c.poll_event(), None);
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn client_bad_command_specifier() {
    // A download ack while uploading.
    assert_client_abort(
        upload(0x1017, 0),
        &["6017100000000000"],
        "8017100001000405",
        client_abort(0x1017, 0, AbortCode::InvalidCommandSpecifier),
    );
    // scs = 7.
    assert_client_abort(
        download(0x1017, 0, &[1, 2]),
        &["E000000000000000"],
        "8017100001000405",
        client_abort(0x1017, 0, AbortCode::InvalidCommandSpecifier),
    );
    // An upload segment while a segmented download waits for its ack.
    assert_client_abort(
        download(0x1008, 0, b"12345678"),
        &["6008100000000000", "0041414141414141"],
        "8008100001000405",
        client_abort(0x1008, 0, AbortCode::InvalidCommandSpecifier),
    );
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn client_toggle_errors() {
    assert_client_abort(
        upload(0x1008, 0),
        &["410810000E000000", "1041414141414141"],
        "8008100000000305",
        client_abort(0x1008, 0, AbortCode::ToggleBitNotAlternated),
    );
    assert_client_abort(
        download(0x1008, 0, b"12345678"),
        &["6008100000000000", "3000000000000000"],
        "8008100000000305",
        client_abort(0x1008, 0, AbortCode::ToggleBitNotAlternated),
    );
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn client_more_and_less_data_than_indicated() {
    assert_client_abort(
        upload(0x1008, 0),
        &["4108100008000000", "0041414141414141", "1541414141414141"],
        "8008100012000706",
        client_abort(0x1008, 0, AbortCode::DataTypeLengthTooHigh),
    );
    assert_client_abort(
        upload(0x1008, 0),
        &["4108100009000000", "0141414141414141"],
        "8008100013000706",
        client_abort(0x1008, 0, AbortCode::DataTypeLengthTooLow),
    );
}

#[test]
fn client_response_for_another_object() {
    assert_client_abort(
        upload(0x1018, 1),
        &["4318100204000000"],
        "8018100143000406",
        client_abort(0x1018, 1, AbortCode::GeneralParameterIncompatibility),
    );
    assert_client_abort(
        download(0x1017, 0, &[1, 2]),
        &["6016100000000000"],
        "8017100043000406",
        client_abort(0x1017, 0, AbortCode::GeneralParameterIncompatibility),
    );
}

#[test]
fn client_received_abort_sends_nothing() {
    let (out, ev) = client_run(upload(0x2000, 0), &["8000200001000106"]);
    assert_eq!(out, vec![frame(0x601, "4000200000000000")]);
    assert_eq!(
        ev,
        vec![ClientEvent::Ended(TransferEnd::Aborted {
            index: 0x2000,
            sub: 0,
            code: AbortCode::ReadOfWriteOnlyObject,
            origin: AbortOrigin::Peer
        })]
    );
    let (_, ev) = client_run(download(0x1017, 0, &[1]), &["8017100000000000"]);
    assert_eq!(
        ev,
        vec![ClientEvent::Ended(TransferEnd::Aborted {
            index: 0x1017,
            sub: 0,
            code: AbortCode::GeneralError,
            origin: AbortOrigin::Peer
        })]
    );
}

#[test]
fn client_local_abort_command() {
    let mut c = client();
    assert!(!c.abort(T0, AbortCode::GeneralError));
    c.start_upload(T0, 0x1008, 0).unwrap();
    assert_eq!(
        c.start_upload(T0, 0x1008, 0),
        Err(canopen_codec::sdo::ClientError::Busy)
    );
    let _ = c.poll_transmit();
    assert!(c.abort(T0, AbortCode::DataCannotBeStoredLocalControl));
    assert_eq!(c.poll_transmit(), Some(frame(0x601, "8008100021000008")));
    assert_eq!(
        c.poll_event(),
        Some(client_abort(
            0x1008,
            0,
            AbortCode::DataCannotBeStoredLocalControl
        ))
    );
    assert!(!c.is_busy());
}

#[test]
fn client_ignores_short_foreign_and_remote_frames() {
    let mut c = client();
    c.start_upload(T0, 0x1018, 1).unwrap();
    let _ = c.poll_transmit();
    for f in [
        frame(0x582, "4318100104000000"),
        frame(0x601, "4318100104000000"),
        frame(0x581, ""),
        frame(0x581, "43181001"),
        frame(0x581, "801810011100"),
        CanFrame::remote(canopen_codec::CanId::Standard(0x581), 8).unwrap(),
    ] {
        c.handle_frame(T0, &f);
        assert_eq!(c.poll_transmit(), None, "{f}");
        assert_eq!(c.poll_event(), None, "{f}");
        assert!(c.is_busy());
    }
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn time_going_backwards_never_panics_or_expires() {
    let mut c = client();
    c.start_upload(Timestamp::from_millis(10_000), 0x1008, 0)
        .unwrap();
    let _ = c.poll_transmit();
    c.handle_timeout(Timestamp::ZERO);
    c.handle_frame(Timestamp::from_millis(5), &frame(0x581, "4108100010000000"));
    assert_eq!(c.poll_transmit(), Some(frame(0x601, "6000000000000000")));
    // The deadline now counts from the earlier timestamp.
    assert_eq!(c.poll_timeout(), Some(Timestamp::from_millis(2005)));
    c.handle_timeout(Timestamp::MAX);
    assert_eq!(
        c.poll_event(),
        Some(client_abort(0x1008, 0, AbortCode::SdoProtocolTimedOut))
    );
    let mut s = server();
    s.handle_frame(Timestamp::MAX, &frame(0x601, "4008100000000000"));
    // The timeout saturates at the end of the clock, which the server's
    // timer table keeps as the microsecond before it.
    assert_eq!(s.poll_timeout(), Some(Timestamp::from_micros(u64::MAX - 1)));
    s.handle_timeout(Timestamp::ZERO);
    assert!(s.is_busy());
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn undrained_events_never_stall_a_transfer() {
    // A client whose events are never drained goes on taking responses:
    // every segment is requested, the oldest events are dropped and
    // counted, and a stalled server still ends in one timeout abort.
    let mut c = client();
    c.start_upload(T0, 0x1008, 0).unwrap();
    assert_eq!(c.poll_transmit(), Some(frame(0x601, "4008100000000000")));
    c.handle_frame(T0, &frame(0x581, "4108100064000000"));
    let mut toggle = false;
    for _ in 0..10 {
        let (req, seg) = if toggle { ("70", "10") } else { ("60", "00") };
        assert_eq!(
            c.poll_transmit(),
            Some(frame(0x601, &format!("{req}00000000000000")))
        );
        c.handle_frame(T0, &frame(0x581, &format!("{seg}41414141414141")));
        toggle = !toggle;
    }
    assert_eq!(c.poll_transmit(), Some(frame(0x601, "6000000000000000")));
    let events: Vec<ClientEvent> = std::iter::from_fn(|| c.poll_event()).collect();
    let offsets: Vec<usize> = events
        .iter()
        .map(|e| match e {
            ClientEvent::UploadData { offset, .. } => *offset,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(offsets, [42, 49, 56, 63]);
    assert_eq!(c.events_dropped(), 6);
    assert_eq!(c.frames_dropped(), 0);
    assert!(c.is_busy());
    c.handle_timeout(Timestamp::from_millis(2000));
    assert_eq!(c.poll_transmit(), Some(frame(0x601, "8008100000000405")));
}
