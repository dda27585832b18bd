//! Block transfer byte vectors (CiA 301 section 7.2.4.3, SDO protocols, frame
//! layouts; V17/V18 are python-canopen's test transfers) through the client
//! and the server, each direction on its own, and the crash sequences seen
//! in another Rust stack. The exchanges are transcripts of the bus
//! (`block_transcripts.txt`), one per case, and one runner checks a client
//! or a server against them; no allocation needed in the machines.

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

/// How a transfer ended, in the same words for the client and the server,
/// as a transcript's `=` line writes it: `downloaded 2000:00 30`,
/// `uploaded 1008:00 26`, `aborted 2000:00 05040004 Local` (the abort code
/// as CiA 301 section 7.2.4.3.17 lists it, and who aborted).
pub(super) trait Ending {
    /// The words for an event that ends a transfer; `None` for the others.
    fn ending(&self) -> Option<String>;
}

fn ended(what: &str, index: u16, sub: u8, detail: impl core::fmt::Display) -> String {
    std::format!("{what} {index:04X}:{sub:02X} {detail}")
}

fn aborted(index: u16, sub: u8, code: AbortCode, origin: AbortOrigin) -> String {
    let detail = std::format!("{:08X} {origin:?}", code.to_u32());
    ended("aborted", index, sub, detail)
}

impl Ending for ClientEvent {
    fn ending(&self) -> Option<String> {
        Some(match *self {
            ClientEvent::UploadData { .. } => return None,
            ClientEvent::Ended(TransferEnd::Uploaded { index, sub, len }) => {
                ended("uploaded", index, sub, len)
            }
            ClientEvent::Ended(TransferEnd::Downloaded { index, sub, len }) => {
                ended("downloaded", index, sub, len)
            }
            ClientEvent::Ended(TransferEnd::Aborted {
                index,
                sub,
                code,
                origin,
            }) => aborted(index, sub, code, origin),
        })
    }
}

impl Ending for ServerEvent {
    fn ending(&self) -> Option<String> {
        let (index, sub) = self.object();
        Some(match *self {
            ServerEvent::Downloaded { len, .. } => ended("downloaded", index, sub, len),
            ServerEvent::Uploaded { len, .. } => ended("uploaded", index, sub, len),
            ServerEvent::Aborted { code, origin, .. } => aborted(index, sub, code, origin),
        })
    }
}

/// The block exchanges, one section a case (the file's head gives the
/// format).
const TRANSCRIPTS: &str = include_str!("block_transcripts.txt");

/// The transcript of the case `name` (its `## name` section).
pub(super) fn transcript(name: &str) -> &'static str {
    let section = |s: &'static str| s.strip_prefix(name)?.strip_prefix('\n');
    let found = TRANSCRIPTS.split("\n## ").find_map(section);
    found.unwrap_or_else(|| panic!("no transcript {name}"))
}

/// Runs the transcripts of `cases`, one after the other, against one side of the
/// exchange: `incoming` marks the frames it receives, fed through `feed`;
/// after each (and at the start) it must send exactly the frames of the
/// other arrow that follow, before the next frame it receives. So one
/// transcript checks both sides of an exchange: [`serve`] feeds the server
/// the `>` frames, [`drive`] the client the `<` frames. A `lost` frame
/// counts only for its sender. The transfers must end as the `=` lines say.
/// Returns every event of the run.
fn run<M>(
    m: &mut M,
    feed: fn(&mut M, &str) -> Vec<String>,
    incoming: char,
    cases: &[&str],
) -> Vec<M::Event>
where
    M: Machine,
    M::Event: Ending,
{
    let mut seen = Vec::new();
    let (mut ends, mut expected) = (Vec::new(), Vec::<&str>::new());
    let (mut after, mut out) = ("the start", sent(m));
    let outgoing = if incoming == '>' { '<' } else { '>' };
    let lines = cases
        .iter()
        .flat_map(|c| transcript(c).lines())
        .map(str::trim);
    for line in lines.filter(|l| !l.is_empty() && !l.starts_with('#')) {
        let (mark, rest) = line.split_at(1);
        let rest = rest.trim();
        let (frame, lost) = match rest.strip_suffix("lost") {
            Some(frame) => (frame.trim(), true),
            None => (rest, false),
        };
        match mark.chars().next() {
            Some('=') => ends.push(rest),
            Some(c) if c == incoming && lost => {}
            Some(c) if c == incoming || c == '~' => {
                assert_eq!(out, expected, "{cases:?}, after {after}");
                expected.clear();
                out = if c == '~' {
                    let due = m.poll_timeout().expect("a deadline to pass");
                    m.handle_timeout(due);
                    sent(m)
                } else {
                    feed(m, frame)
                };
                after = line;
                seen.extend(events(m));
            }
            Some(c) if c == outgoing => expected.push(frame),
            _ => panic!("{cases:?}: no frame, deadline or end: {line}"),
        }
    }
    assert_eq!(out, expected, "{cases:?}, after {after}");
    let endings: Vec<String> = seen.iter().filter_map(Ending::ending).collect();
    assert_eq!(endings, ends, "{cases:?}: how the transfers ended");
    seen
}

/// Runs the transcripts of `cases` against the server (see [`run`]).
pub(super) fn serve(s: &mut Server<Od>, cases: &[&str]) -> Vec<ServerEvent> {
    run(s, req, '>', cases)
}

/// Runs the transcripts of `cases` against a client just started (see
/// [`run`]): their first frames are the ones the start sends.
pub(super) fn drive<D: AsRef<[u8]>>(c: &mut Client<D>, cases: &[&str]) -> Vec<ClientEvent> {
    run(c, resp, '<', cases)
}

/// The value an upload delivered, from its `UploadData` events in order.
fn uploaded(events: &[ClientEvent]) -> Vec<u8> {
    let mut value = Vec::new();
    for e in events {
        if let ClientEvent::UploadData { offset, data, .. } = e {
            assert_eq!(*offset, value.len());
            value.extend_from_slice(data.as_slice());
        }
    }
    value
}

/// V17, python-canopen's block download value (30 bytes).
pub(super) const V17: &[u8] = b"A really really long string...";

/// V18, python-canopen's block upload value, 1008h (26 bytes).
pub(super) const V18: &[u8] = b"Tiny Node - Mega Domains !";

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
fn v17_block_download_both_sides() {
    let v17 = ["v17 sub-block", "v17 end"];
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    drive(&mut c, &v17);
    assert!(!c.is_busy() && c.poll_timeout().is_none());
    let mut s = server(Od::new(b""));
    serve(&mut s, &v17);
    assert_eq!((s.od().written(), s.od().finished), (V17, Some(30)));
}

#[test]
fn block_download_without_size_and_without_crc() {
    let mut s = server(Od::new(b""));
    serve(&mut s, &["download without size and without crc"]);
    assert_eq!(s.od().written(), b"ABC");
}

#[test]
fn v18_block_upload_both_sides() {
    let v18 = ["v18 sub-block", "v18 end"];
    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    assert_eq!(uploaded(&drive(&mut c, &v18)), V18);
    serve(&mut server(Od::new(V18)), &v18);
}

#[test]
fn lost_segment_is_acknowledged_and_resent_download() {
    let lost = ["lost segment, download"];
    let mut s = server_with(3, Od::new(b""));
    serve(&mut s, &lost);
    assert_eq!(s.od().written(), V17);
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    drive(&mut c, &lost);
}

#[test]
fn lost_segment_is_acknowledged_and_resent_upload() {
    let mut c = client_with(2);
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    drive(&mut c, &["lost segment, upload to the client"]);
    let from_server = ["lost segment, upload from the server"];
    serve(&mut server(Od::new(V18)), &from_server);
}
