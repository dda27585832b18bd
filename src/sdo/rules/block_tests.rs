//! Block transfer byte vectors (CiA 301 section 7.2.4.3, SDO protocols, frame
//! layouts; V17/V18 are python-canopen's test transfers) through the client
//! and the server, each direction on its own, and the crash sequences seen
//! in another Rust stack. No allocation needed.

use std::string::String;
use std::vec::Vec;

use super::{Acked, Planned, Receiver, Sender, Step};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::od::{Access, ObjectDictionary, ObjectInfo, SizeRule};
use crate::sdo::*;
use crate::NodeId;

const NODE: u8 = 2;

/// One variable object 2000h:00 (rw, up to 2048 bytes) and 1008h:00 (ro).
pub(super) struct Od {
    pub(super) value: [u8; 2048],
    pub(super) len: usize,
    pub(super) name: &'static [u8],
    pub(super) finished: Option<usize>,
    pub(super) aborted: usize,
}

impl Od {
    pub(super) fn new(name: &'static [u8]) -> Self {
        Od {
            value: [0; 2048],
            len: 0,
            name,
            finished: None,
            aborted: 0,
        }
    }
    pub(super) fn written(&self) -> &[u8] {
        &self.value[..self.len]
    }
}

impl ObjectDictionary for Od {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        match (index, sub) {
            (0x2000, 0) => Ok(ObjectInfo {
                size: SizeRule::Variable { max: 2048 },
                ..ObjectInfo::fixed(Access::ReadWrite, self.len)
            }),
            (0x1008, 0) => Ok(ObjectInfo::fixed(Access::ReadOnly, self.name.len())),
            _ => Err(AbortCode::ObjectDoesNotExist),
        }
    }
    fn read(
        &mut self,
        index: u16,
        _: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let src = if index == 0x1008 {
            self.name
        } else {
            self.written()
        };
        Ok(crate::od::read_at(src, offset, buf))
    }
    fn write(&mut self, _: u16, _: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        self.value[offset..offset + data.len()].copy_from_slice(data);
        self.len = self.len.max(offset + data.len());
        Ok(())
    }
    fn finish_write(&mut self, _: u16, _: u8, len: usize) -> Result<(), AbortCode> {
        self.finished = Some(len);
        Ok(())
    }
    fn abort_write(&mut self, _: u16, _: u8) {
        self.aborted += 1;
    }
}

pub(super) fn bytes(hex: &str) -> Vec<u8> {
    hex.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect()
}

pub(super) fn frame(id: u16, hex: &str) -> CanFrame {
    CanFrame::standard(id, &bytes(hex)).unwrap()
}

pub(super) fn hex(f: &CanFrame) -> String {
    let mut s = String::new();
    for (i, b) in f.data().iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        s.push_str(&std::format!("{b:02X}"));
    }
    s
}

/// Every frame the machine sends now, as hex.
pub(super) fn sent<M: Machine>(m: &mut M) -> Vec<String> {
    std::iter::from_fn(|| m.poll_transmit())
        .map(|f| hex(&f))
        .collect()
}

pub(super) fn events<M: Machine>(m: &mut M) -> Vec<M::Event> {
    std::iter::from_fn(|| m.poll_event()).collect()
}

pub(super) fn node() -> NodeId {
    NodeId::new(NODE).unwrap()
}

pub(super) fn client() -> Client<&'static [u8]> {
    Client::new(ClientConfig::for_server(node()))
}

pub(super) fn client_with(block_size: u8) -> Client<&'static [u8]> {
    Client::new(ClientConfig {
        block_size,
        ..ClientConfig::for_server(node())
    })
}

pub(super) fn server(od: Od) -> Server<Od> {
    Server::new(ServerConfig::for_node(node()), od)
}

pub(super) fn server_with(block_size: u8, od: Od) -> Server<Od> {
    Server::new(
        ServerConfig {
            block_size,
            ..ServerConfig::for_node(node())
        },
        od,
    )
}

pub(super) const T0: Timestamp = Timestamp::ZERO;

/// Feeds a request to the server and returns what it sends.
pub(super) fn req(s: &mut Server<Od>, hex: &str) -> Vec<String> {
    s.handle_frame(T0, &frame(0x602, hex));
    sent(s)
}

/// Feeds a response to the client and returns what it sends.
pub(super) fn resp<D: AsRef<[u8]>>(c: &mut Client<D>, hex: &str) -> Vec<String> {
    c.handle_frame(T0, &frame(0x582, hex));
    sent(c)
}

/// Each step's frame fed through `feed` (`req` or `resp`), and what the
/// machine sends then compared with the step's frames.
pub(super) fn script<M>(
    m: &mut M,
    feed: fn(&mut M, &str) -> Vec<String>,
    steps: &[(&str, &[&str])],
) {
    for &(input, output) in steps {
        assert_eq!(feed(m, input), output, "after {input}");
    }
}

pub(super) const V17: &[u8] = b"A really really long string...";
pub(super) const V17_SEGMENTS: [&str; 5] = [
    "01 41 20 72 65 61 6C 6C",
    "02 79 20 72 65 61 6C 6C",
    "03 79 20 6C 6F 6E 67 20",
    "04 73 74 72 69 6E 67 2E",
    "85 2E 2E 00 00 00 00 00",
];
pub(super) const V18: &[u8] = b"Tiny Node - Mega Domains !";
pub(super) const V18_SEGMENTS: [&str; 4] = [
    "01 54 69 6E 79 20 4E 6F",
    "02 64 65 20 2D 20 4D 65",
    "03 67 61 20 44 6F 6D 61",
    "84 69 6E 73 20 21 00 00",
];

#[test]
fn sender_and_receiver_cores() {
    let mut tx = Sender::new(15, 2, true);
    assert_eq!(tx.next(), Some(Planned { offset: 0, len: 7 }));
    assert_eq!(tx.emit(b"0123456")[0], 0x01);
    assert_eq!(tx.next(), Some(Planned { offset: 7, len: 7 }));
    assert_eq!(tx.emit(b"789abcd")[0], 0x02);
    assert_eq!(tx.next(), None);
    assert_eq!(tx.on_ack(3, 2), Err(AbortCode::InvalidSequenceNumber));
    assert_eq!(tx.on_ack(2, 0), Err(AbortCode::InvalidBlockSize));
    assert_eq!(tx.on_ack(2, 128), Err(AbortCode::InvalidBlockSize));
    assert_eq!(tx.on_ack(2, 2), Ok(Acked::More));
    assert_eq!(tx.next(), Some(Planned { offset: 14, len: 1 }));
    assert_eq!(tx.emit(b"e"), [0x81, b'e', 0, 0, 0, 0, 0, 0]);
    assert_eq!(tx.next(), None);
    // The last ack needs no valid block size.
    assert_eq!(
        tx.on_ack(1, 0),
        Ok(Acked::Done {
            unused: 6,
            crc: crc16(b"0123456789abcde")
        })
    );
    let mut empty = Sender::new(0, 127, false);
    assert_eq!(empty.next(), Some(Planned { offset: 0, len: 0 }));
    assert_eq!(empty.emit(&[]), [0x81, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(empty.on_ack(1, 127), Ok(Acked::Done { unused: 7, crc: 0 }));

    let mut rx = Receiver::new(2, Some(8), true);
    assert_eq!(
        rx.on_segment(&[0x00; 8]),
        Err(AbortCode::InvalidSequenceNumber)
    );
    assert_eq!(
        rx.on_segment(&[0x03; 8]),
        Err(AbortCode::InvalidSequenceNumber)
    );
    // Short non-last segment: ignored.
    assert_eq!(rx.on_segment(&[0x01, 1, 2]), Ok(Step::default()));
    let s = rx.on_segment(&[0x01, 1, 2, 3, 4, 5, 6, 7]).unwrap();
    assert_eq!(s.write.unwrap().0, 0);
    assert_eq!(s.ack, None);
    let s = rx.on_segment(&[0x82, 8, 0, 0, 0, 0, 0, 0]).unwrap();
    assert_eq!((s.write, s.ack), (None, Some(2)));
    assert!(rx.is_done() && rx.is_duplicate(&[0x82, 8, 0, 0, 0, 0, 0, 0]));
    assert_eq!(rx.on_end(6, 0), Err(AbortCode::CrcError));
    let ended = rx.on_end(6, crc16(&[1, 2, 3, 4, 5, 6, 7, 8])).unwrap();
    assert_eq!(ended.total, 8);
    assert_eq!(ended.write.unwrap().1.as_slice(), &[8]);
}

#[test]
fn v17_block_download_client_side() {
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    assert_eq!(sent(&mut c), ["C6 00 20 00 1E 00 00 00"]);
    // One segment per poll: the whole sub-block comes out of the drain.
    assert_eq!(resp(&mut c, "A4 00 20 00 7F 00 00 00"), V17_SEGMENTS);
    script(
        &mut c,
        resp,
        &[
            ("A2 05 7F 00 00 00 00 00", &["D5 45 69 00 00 00 00 00"]),
            ("A1 00 00 00 00 00 00 00", &[]),
        ],
    );
    assert_eq!(
        events(&mut c),
        [ClientEvent::Downloaded {
            index: 0x2000,
            sub: 0,
            len: 30
        }]
    );
    assert!(!c.is_busy() && c.poll_timeout().is_none());
}

#[test]
fn v17_block_download_server_side() {
    let mut s = server(Od::new(b""));
    assert_eq!(
        req(&mut s, "C6 00 20 00 1E 00 00 00"),
        ["A4 00 20 00 7F 00 00 00"]
    );
    for seg in &V17_SEGMENTS[..4] {
        assert_eq!(req(&mut s, seg), Vec::<String>::new());
    }
    assert_eq!(req(&mut s, V17_SEGMENTS[4]), ["A2 05 7F 00 00 00 00 00"]);
    assert_eq!(
        req(&mut s, "D5 45 69 00 00 00 00 00"),
        ["A1 00 00 00 00 00 00 00"]
    );
    assert_eq!(
        events(&mut s),
        [ServerEvent::Downloaded {
            index: 0x2000,
            sub: 0,
            len: 30
        }]
    );
    assert_eq!(s.od().written(), V17);
    assert_eq!(s.od().finished, Some(30));
}

#[test]
fn block_download_without_size_and_without_crc() {
    let mut s = server(Od::new(b""));
    // cc = 0, s = 0: no CRC, no size.
    script(
        &mut s,
        req,
        &[
            ("C0 00 20 00 00 00 00 00", &["A4 00 20 00 7F 00 00 00"]),
            ("81 41 42 43 00 00 00 00", &["A2 01 7F 00 00 00 00 00"]),
        ],
    );
    // CRC not in use: the CRC field is not checked.
    assert_eq!(
        req(&mut s, "D1 12 34 00 00 00 00 00"),
        ["A1 00 00 00 00 00 00 00"]
    );
    assert_eq!(s.od().written(), b"ABC");
}

#[test]
fn v18_block_upload_client_side() {
    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    assert_eq!(sent(&mut c), ["A4 08 10 00 7F 00 00 00"]);
    assert_eq!(
        resp(&mut c, "C6 08 10 00 1A 00 00 00"),
        ["A3 00 00 00 00 00 00 00"]
    );
    let mut seen = Vec::new();
    for seg in &V18_SEGMENTS[..3] {
        assert_eq!(resp(&mut c, seg), Vec::<String>::new());
        seen.extend(events(&mut c));
    }
    assert_eq!(resp(&mut c, V18_SEGMENTS[3]), ["A2 04 7F 00 00 00 00 00"]);
    assert_eq!(
        resp(&mut c, "C9 40 E1 00 00 00 00 00"),
        ["A1 00 00 00 00 00 00 00"]
    );
    seen.extend(events(&mut c));
    let mut value = Vec::new();
    for e in seen {
        match e {
            ClientEvent::UploadData { offset, data, .. } => {
                assert_eq!(offset, value.len());
                value.extend_from_slice(data.as_slice());
            }
            e => assert_eq!(
                e,
                ClientEvent::Uploaded {
                    index: 0x1008,
                    sub: 0,
                    len: 26
                }
            ),
        }
    }
    assert_eq!(value, V18);
}

#[test]
fn v18_block_upload_server_side() {
    let mut s = server(Od::new(V18));
    assert_eq!(
        req(&mut s, "A4 08 10 00 7F 00 00 00"),
        ["C6 08 10 00 1A 00 00 00"]
    );
    assert_eq!(req(&mut s, "A3 00 00 00 00 00 00 00"), V18_SEGMENTS);
    script(
        &mut s,
        req,
        &[
            ("A2 04 7F 00 00 00 00 00", &["C9 40 E1 00 00 00 00 00"]),
            ("A1 00 00 00 00 00 00 00", &[]),
        ],
    );
    assert_eq!(
        events(&mut s),
        [ServerEvent::Uploaded {
            index: 0x1008,
            sub: 0,
            len: 26
        }]
    );
}

#[test]
fn lost_segment_is_acknowledged_and_resent_download() {
    // Server as receiver, block size 3: segment 2 is lost.
    let mut s = server_with(3, Od::new(b""));
    assert_eq!(
        req(&mut s, "C6 00 20 00 1E 00 00 00"),
        ["A4 00 20 00 03 00 00 00"]
    );
    assert_eq!(req(&mut s, V17_SEGMENTS[0]), Vec::<String>::new());
    // Seq 3 (the block's last number) after a gap: ack the last in order.
    assert_eq!(
        req(&mut s, "03 79 20 6C 6F 6E 67 20"),
        ["A2 01 03 00 00 00 00 00"]
    );
    // The client resends from segment 2, numbering from 1.
    script(
        &mut s,
        req,
        &[
            ("01 79 20 72 65 61 6C 6C", &[]),
            ("02 79 20 6C 6F 6E 67 20", &[]),
            ("03 73 74 72 69 6E 67 2E", &["A2 03 03 00 00 00 00 00"]),
            ("81 2E 2E 00 00 00 00 00", &["A2 01 03 00 00 00 00 00"]),
            ("D5 45 69 00 00 00 00 00", &["A1 00 00 00 00 00 00 00"]),
        ],
    );
    assert_eq!(s.od().written(), V17);

    // Client as sender of the same exchange.
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    let _ = sent(&mut c);
    assert_eq!(resp(&mut c, "A4 00 20 00 03 00 00 00"), &V17_SEGMENTS[..3]);
    script(
        &mut c,
        resp,
        &[
            (
                "A2 01 03 00 00 00 00 00",
                &[
                    "01 79 20 72 65 61 6C 6C",
                    "02 79 20 6C 6F 6E 67 20",
                    "03 73 74 72 69 6E 67 2E",
                ],
            ),
            ("A2 03 03 00 00 00 00 00", &["81 2E 2E 00 00 00 00 00"]),
            ("A2 01 03 00 00 00 00 00", &["D5 45 69 00 00 00 00 00"]),
        ],
    );
}

#[test]
fn lost_segment_is_acknowledged_and_resent_upload() {
    let mut c = client_with(2);
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    assert_eq!(sent(&mut c), ["A4 08 10 00 02 00 00 00"]);
    let _ = resp(&mut c, "C6 08 10 00 1A 00 00 00");
    // Segment 1 lost: seq 2 ends the block, nothing in order.
    assert_eq!(resp(&mut c, V18_SEGMENTS[1]), ["A2 00 02 00 00 00 00 00"]);
    assert_eq!(resp(&mut c, V18_SEGMENTS[0]), Vec::<String>::new());

    let mut s = server(Od::new(V18));
    let _ = req(&mut s, "A4 08 10 00 02 00 00 00");
    assert_eq!(req(&mut s, "A3 00 00 00 00 00 00 00"), &V18_SEGMENTS[..2]);
    script(
        &mut s,
        req,
        &[
            (
                "A2 01 02 00 00 00 00 00",
                &["01 64 65 20 2D 20 4D 65", "02 67 61 20 44 6F 6D 61"],
            ),
            ("A2 02 02 00 00 00 00 00", &["81 69 6E 73 20 21 00 00"]),
            ("A2 01 02 00 00 00 00 00", &["C9 40 E1 00 00 00 00 00"]),
        ],
    );
}
