//! SDO transfer reassembly for the decoder: one transfer per SDO channel
//! (server node; requests on 0x600 + node, responses on 0x580 + node).
//!
//! The library's codec is stateless; the state of each transfer lives here.
//! A transfer ends in an expedited response or acknowledgement, the last
//! segment (upload) or the acknowledgement of the last segment (download),
//! or an abort from either side; then [`Tracker::handle`] returns a
//! [`Report`]. A transfer broken off by a new initiate, a wrong toggle bit or
//! a frame that does not fit is reported once as [`End::Incomplete`]; so is
//! one still open when the log ends ([`Tracker::finish`]). Frames that belong
//! to no transfer (a stray segment) are left to the per-frame line.
//!
//! Block transfers are followed (so their data frames are not misread as
//! segments) but not reassembled: only an abort of one is reported.

use canopen_codec::cob_id::CobKind;
use canopen_codec::sdo::{
    AbortCode, ClientBlockDownload, ClientBlockUpload, ClientCommand, InitiatePayload,
    ServerBlockDownload, ServerCommand,
};
use canopen_codec::{DecodeError, Message, NodeId, Timestamp};

/// At most this many bytes of one transfer are kept; the rest are counted.
pub const MAX_BYTES: usize = 64 * 1024;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Direction {
    Upload,
    Download,
}

impl Direction {
    pub fn name(self) -> &'static str {
        match self {
            Direction::Upload => "upload",
            Direction::Download => "download",
        }
    }

    /// `from node 2` / `to node 2`.
    pub fn preposition(self) -> &'static str {
        match self {
            Direction::Upload => "from",
            Direction::Download => "to",
        }
    }
}

/// Which side sent a frame.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Side {
    Client,
    Server,
}

impl Side {
    pub fn name(self) -> &'static str {
        match self {
            Side::Client => "client",
            Side::Server => "server",
        }
    }
}

/// How a transfer ended.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum End {
    Complete,
    Aborted { code: AbortCode, by: Side },
    Incomplete(String),
}

/// One finished (or broken-off) transfer.
#[derive(Clone, Debug)]
pub struct Report {
    /// Time of the frame that ended it (the last frame seen of it when the
    /// log ended).
    pub t: Option<Timestamp>,
    pub node: NodeId,
    pub direction: Direction,
    pub index: u16,
    pub sub: u8,
    /// The data, at most [`MAX_BYTES`].
    pub bytes: Vec<u8>,
    /// Bytes transferred (more than `bytes.len()` when truncated).
    pub total: usize,
    /// The size the initiate frame indicated (segmented, s = 1).
    pub indicated: Option<u32>,
    /// False for an expedited transfer with s = 0 ("up to 4 bytes").
    pub size_indicated: bool,
    pub end: End,
}

impl Report {
    pub fn truncated(&self) -> bool {
        self.total > self.bytes.len()
    }

    /// The indicated size when it differs from what was transferred.
    pub fn size_mismatch(&self) -> Option<u32> {
        self.indicated
            .filter(|&n| usize::try_from(n) != Ok(self.total))
    }
}

#[derive(Clone, Copy, Debug)]
enum Phase {
    /// Initiate sent, waiting for the server's initiate response;
    /// `expedited` for a download whose data came in the initiate.
    Initiated { expedited: bool },
    /// Segmented upload: the next segment carries `toggle`.
    UploadSegments { toggle: bool },
    /// Segmented download: the next segment carries `toggle`; `pending` is
    /// the c bit of a segment sent but not yet acknowledged.
    DownloadSegments { toggle: bool, pending: Option<bool> },
    /// Block transfer, not reassembled: data frames are skipped until the
    /// end command or an abort.
    Block,
}

#[derive(Debug)]
struct Transfer {
    direction: Direction,
    index: u16,
    sub: u8,
    phase: Phase,
    bytes: Vec<u8>,
    total: usize,
    indicated: Option<u32>,
    size_indicated: bool,
    last_t: Option<Timestamp>,
}

impl Transfer {
    fn new(direction: Direction, index: u16, sub: u8, phase: Phase) -> Self {
        Transfer {
            direction,
            index,
            sub,
            phase,
            bytes: Vec::new(),
            total: 0,
            indicated: None,
            size_indicated: true,
            last_t: None,
        }
    }

    fn append(&mut self, data: &[u8]) {
        let room = MAX_BYTES.saturating_sub(self.bytes.len());
        self.bytes
            .extend_from_slice(data.get(..room.min(data.len())).unwrap_or_default());
        self.total = self.total.saturating_add(data.len());
    }

    fn report(self, node: NodeId, t: Option<Timestamp>, end: End) -> Report {
        Report {
            t,
            node,
            direction: self.direction,
            index: self.index,
            sub: self.sub,
            bytes: self.bytes,
            total: self.total,
            indicated: self.indicated,
            size_indicated: self.size_indicated,
            end,
        }
    }
}

/// The open transfer of each SDO channel (node 1..=127).
pub struct Tracker {
    channels: Vec<Option<Transfer>>,
}

impl Default for Tracker {
    fn default() -> Self {
        Tracker {
            channels: (0..128).map(|_| None).collect(),
        }
    }
}

/// What one SDO frame is, for the tracker.
enum Frame<'a> {
    Client(&'a ClientCommand),
    Server(&'a ServerCommand),
    Malformed(Side),
}

fn bit(b: bool) -> u8 {
    u8::from(b)
}

impl Tracker {
    /// Feeds one decoded frame; returns the transfer it ended, if any.
    /// `first` is the frame's first data byte.
    pub fn handle(
        &mut self,
        t: Option<Timestamp>,
        kind: CobKind,
        first: Option<u8>,
        msg: &Result<Message, DecodeError>,
    ) -> Option<Report> {
        let (node, frame) = match (kind, msg) {
            (_, Ok(Message::SdoRequest { node, sdo })) => (*node, Frame::Client(&sdo.command)),
            (_, Ok(Message::SdoResponse { node, sdo })) => (*node, Frame::Server(&sdo.command)),
            (CobKind::SdoRx(node), Err(_)) => (node, Frame::Malformed(Side::Client)),
            (CobKind::SdoTx(node), Err(_)) => (node, Frame::Malformed(Side::Server)),
            _ => return None,
        };
        let slot = self.channels.get_mut(usize::from(node.raw()))?;
        let current = slot.take();
        let (next, report) = step(current, node, t, first, frame);
        *slot = next.map(|mut tr| {
            tr.last_t = t;
            tr
        });
        report
    }

    /// Reports every transfer still open at the end of the log.
    pub fn finish(&mut self) -> Vec<Report> {
        let mut out = Vec::new();
        for (n, slot) in self.channels.iter_mut().enumerate() {
            let Some(tr) = slot.take() else { continue };
            let Some(node) = u8::try_from(n).ok().and_then(NodeId::new) else {
                continue;
            };
            if matches!(tr.phase, Phase::Block) {
                continue;
            }
            let t = tr.last_t;
            out.push(tr.report(node, t, End::Incomplete("the log ends".into())));
        }
        out
    }
}

/// One transition: the transfer after the frame, and the report if the
/// frame ended one.
fn step(
    current: Option<Transfer>,
    node: NodeId,
    t: Option<Timestamp>,
    first: Option<u8>,
    frame: Frame<'_>,
) -> (Option<Transfer>, Option<Report>) {
    let broken = |tr: Transfer, why: String| tr.report(node, t, End::Incomplete(why));
    // A new initiate breaks off whatever was open.
    let start = |current: Option<Transfer>, new: Transfer, what: &str| {
        let report = current.map(|tr| {
            let why = format!("new {what} {:04X}h:{:02X}", new.index, new.sub);
            // Block transfers are not reported, only their aborts.
            (!matches!(tr.phase, Phase::Block)).then(|| broken(tr, why))
        });
        (Some(new), report.flatten())
    };
    let Some(mut tr) = current else {
        // No transfer open: only an initiate starts one.
        return match frame {
            Frame::Client(c) => match initiate(c) {
                Some((new, what)) => start(None, new, what),
                None => (None, None),
            },
            _ => (None, None),
        };
    };

    if let Phase::Block = tr.phase {
        return block(tr, node, t, first, frame);
    }
    match frame {
        Frame::Client(c) => {
            if let Some((new, what)) = initiate(c) {
                return start(Some(tr), new, what);
            }
            match (c, tr.phase) {
                (ClientCommand::Abort { code, .. }, _) => {
                    let end = End::Aborted {
                        code: *code,
                        by: Side::Client,
                    };
                    (None, Some(tr.report(node, t, end)))
                }
                (
                    ClientCommand::UploadSegment { toggle },
                    Phase::UploadSegments { toggle: want },
                ) if tr.direction == Direction::Upload => {
                    if *toggle == want {
                        (Some(tr), None)
                    } else {
                        let why = format!(
                            "upload segment request with toggle {}, expected {}",
                            bit(*toggle),
                            bit(want)
                        );
                        (None, Some(broken(tr, why)))
                    }
                }
                (
                    ClientCommand::DownloadSegment(s),
                    Phase::DownloadSegments {
                        toggle,
                        pending: None,
                    },
                ) => {
                    if s.toggle != toggle {
                        let why = format!(
                            "download segment with toggle {}, expected {}",
                            bit(s.toggle),
                            bit(toggle)
                        );
                        return (None, Some(broken(tr, why)));
                    }
                    tr.append(s.data.as_slice());
                    tr.phase = Phase::DownloadSegments {
                        toggle,
                        pending: Some(s.last),
                    };
                    (Some(tr), None)
                }
                (c, _) => {
                    let why = format!("unexpected client frame ({})", client_name(c));
                    (None, Some(broken(tr, why)))
                }
            }
        }
        Frame::Server(s) => match (s, tr.phase) {
            (ServerCommand::Abort { code, .. }, _) => {
                let end = End::Aborted {
                    code: *code,
                    by: Side::Server,
                };
                (None, Some(tr.report(node, t, end)))
            }
            (
                ServerCommand::InitiateUpload {
                    index,
                    sub,
                    payload,
                },
                Phase::Initiated { .. },
            ) if tr.direction == Direction::Upload => {
                if (*index, *sub) != (tr.index, tr.sub) {
                    let why = format!("the response names {index:04X}h:{sub:02X}");
                    return (None, Some(broken(tr, why)));
                }
                match payload {
                    InitiatePayload::Expedited {
                        data,
                        size_indicated,
                    } => {
                        tr.append(data.as_slice());
                        tr.size_indicated = *size_indicated;
                        (None, Some(tr.report(node, t, End::Complete)))
                    }
                    InitiatePayload::Segmented { size } => {
                        tr.indicated = *size;
                        tr.phase = Phase::UploadSegments { toggle: false };
                        (Some(tr), None)
                    }
                }
            }
            (ServerCommand::InitiateDownload { index, sub }, Phase::Initiated { expedited })
                if tr.direction == Direction::Download =>
            {
                if (*index, *sub) != (tr.index, tr.sub) {
                    let why = format!("the response names {index:04X}h:{sub:02X}");
                    return (None, Some(broken(tr, why)));
                }
                if expedited {
                    return (None, Some(tr.report(node, t, End::Complete)));
                }
                tr.phase = Phase::DownloadSegments {
                    toggle: false,
                    pending: None,
                };
                (Some(tr), None)
            }
            (ServerCommand::UploadSegment(seg), Phase::UploadSegments { toggle }) => {
                if seg.toggle != toggle {
                    let why = format!(
                        "upload segment with toggle {}, expected {}",
                        bit(seg.toggle),
                        bit(toggle)
                    );
                    return (None, Some(broken(tr, why)));
                }
                tr.append(seg.data.as_slice());
                if seg.last {
                    return (None, Some(tr.report(node, t, End::Complete)));
                }
                tr.phase = Phase::UploadSegments { toggle: !toggle };
                (Some(tr), None)
            }
            (
                ServerCommand::DownloadSegment { toggle: ack },
                Phase::DownloadSegments {
                    toggle,
                    pending: Some(last),
                },
            ) => {
                if *ack != toggle {
                    let why = format!(
                        "download acknowledgement with toggle {}, expected {}",
                        bit(*ack),
                        bit(toggle)
                    );
                    return (None, Some(broken(tr, why)));
                }
                if last {
                    return (None, Some(tr.report(node, t, End::Complete)));
                }
                tr.phase = Phase::DownloadSegments {
                    toggle: !toggle,
                    pending: None,
                };
                (Some(tr), None)
            }
            (s, _) => {
                let why = format!("unexpected server frame ({})", server_name(s));
                (None, Some(broken(tr, why)))
            }
        },
        Frame::Malformed(side) => {
            let why = format!("malformed {} frame", side.name());
            (None, Some(broken(tr, why)))
        }
    }
}

/// A client frame that starts a transfer: the transfer and its words.
fn initiate(c: &ClientCommand) -> Option<(Transfer, &'static str)> {
    match *c {
        ClientCommand::InitiateUpload { index, sub } => Some((
            Transfer::new(
                Direction::Upload,
                index,
                sub,
                Phase::Initiated { expedited: false },
            ),
            "initiate upload",
        )),
        ClientCommand::InitiateDownload {
            index,
            sub,
            payload,
        } => {
            let mut tr = Transfer::new(
                Direction::Download,
                index,
                sub,
                Phase::Initiated { expedited: false },
            );
            match payload {
                InitiatePayload::Expedited {
                    data,
                    size_indicated,
                } => {
                    tr.append(data.as_slice());
                    tr.size_indicated = size_indicated;
                    tr.phase = Phase::Initiated { expedited: true };
                }
                InitiatePayload::Segmented { size } => tr.indicated = size,
            }
            Some((tr, "initiate download"))
        }
        ClientCommand::BlockUpload(ClientBlockUpload::Initiate { index, sub, .. }) => Some((
            Transfer::new(Direction::Upload, index, sub, Phase::Block),
            "block upload",
        )),
        ClientCommand::BlockDownload(ClientBlockDownload::Initiate { index, sub, .. }) => Some((
            Transfer::new(Direction::Download, index, sub, Phase::Block),
            "block download",
        )),
        _ => None,
    }
}

/// A frame during a block transfer. The side that sends the data sends
/// frames the stateless codec cannot tell from commands (sequence number 5
/// with the last bit, 85h, reads as an abort), so from that side only a
/// frame whose first byte is exactly 80h counts as an abort; from the other
/// side its end command and aborts are looked at.
fn block(
    tr: Transfer,
    node: NodeId,
    t: Option<Timestamp>,
    first: Option<u8>,
    frame: Frame<'_>,
) -> (Option<Transfer>, Option<Report>) {
    let aborted = |tr: Transfer, code: AbortCode, by| tr.report(node, t, End::Aborted { code, by });
    let data_side = matches!(
        (tr.direction, &frame),
        (Direction::Download, Frame::Client(_))
            | (Direction::Upload, Frame::Server(_))
            | (_, Frame::Malformed(_))
    );
    if data_side && first != Some(0x80) {
        return (Some(tr), None);
    }
    match (tr.direction, frame) {
        (_, Frame::Client(ClientCommand::Abort { code, .. })) => {
            (None, Some(aborted(tr, *code, Side::Client)))
        }
        (_, Frame::Server(ServerCommand::Abort { code, .. })) => {
            (None, Some(aborted(tr, *code, Side::Server)))
        }
        (Direction::Upload, Frame::Client(ClientCommand::BlockUpload(ClientBlockUpload::End))) => {
            (None, None)
        }
        (
            Direction::Download,
            Frame::Server(ServerCommand::BlockDownload(ServerBlockDownload::End)),
        ) => (None, None),
        // A new initiate from the client while it is not sending data.
        (Direction::Upload, Frame::Client(c)) => match initiate(c) {
            Some((new, _)) => (Some(new), None),
            None => (Some(tr), None),
        },
        // The server answering something other than a block download:
        // the block transfer is over (its end was not seen).
        (Direction::Download, Frame::Server(s))
            if !matches!(s, ServerCommand::BlockDownload(_)) =>
        {
            (None, None)
        }
        _ => (Some(tr), None),
    }
}

fn client_name(c: &ClientCommand) -> &'static str {
    match c {
        ClientCommand::DownloadSegment(_) => "download segment",
        ClientCommand::InitiateDownload { .. } => "initiate download",
        ClientCommand::InitiateUpload { .. } => "initiate upload",
        ClientCommand::UploadSegment { .. } => "upload segment request",
        ClientCommand::Abort { .. } => "abort",
        ClientCommand::BlockUpload(_) => "block upload",
        ClientCommand::BlockDownload(_) => "block download",
        ClientCommand::Unknown(_) => "invalid command specifier",
    }
}

fn server_name(s: &ServerCommand) -> &'static str {
    match s {
        ServerCommand::UploadSegment(_) => "upload segment",
        ServerCommand::DownloadSegment { .. } => "download acknowledgement",
        ServerCommand::InitiateUpload { .. } => "initiate upload response",
        ServerCommand::InitiateDownload { .. } => "initiate download response",
        ServerCommand::Abort { .. } => "abort",
        ServerCommand::BlockDownload(_) => "block download",
        ServerCommand::BlockUpload(_) => "block upload",
        ServerCommand::Unknown(_) => "invalid command specifier",
    }
}
