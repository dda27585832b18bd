//! SDO transfer reassembly for the decoder, on the library's passive
//! [`Observer`]: the observer follows every transfer (expedited, segmented,
//! block; upload and download) on the default SDO channel of every node and
//! on the channels `--sdo` declares, by the same rules as the library's
//! client and server; this module collects each transfer's bytes and turns
//! its end into a [`Report`].
//!
//! A transfer ends complete, aborted (by either side), or incomplete: broken
//! off by a new initiate, by a frame that breaks a rule of CiA 301 with no
//! abort after it, by an acknowledgement the frames on the bus do not make,
//! by silence longer than [`TIMEOUT`], or by the end of the log
//! ([`Tracker::finish`]). Each is reported once.
//!
//! ## The program's transfer lines
//!
//! The decoder follows one SDO transfer per server node (requests on
//! 0x600 + node, responses on 0x580 + node) and, after the frame that ends
//! one, prints one extra line (in `--json`, one extra object):
//!
//! ```text
//! 1757100000.207750  transfer  -        SDO upload 1008h:00 from node 2: 26 bytes "Tiny Node - Mega Domains !" (manufacturer device name)
//! 1757100000.101350  transfer  -        SDO download 1017h:00 to node 2: A0 0F (producer heartbeat time: 4000 ms)
//! 1757100000.501350  transfer  -        SDO upload 1018h:01 from node 2 aborted: 06090011h Sub-index does not exist
//! ```
//!
//! - A transfer ends with the expedited response or acknowledgement, the
//!   last upload segment (c = 1), the acknowledgement of the last download
//!   segment, or an abort from either side (`aborted by the client` when the
//!   client sent it; the transfer's own index and sub-index are shown, not
//!   the abort frame's).
//! - A transfer broken off (a new initiate on its channel, a wrong toggle
//!   bit, a response for another object, a frame that does not fit, a
//!   malformed frame, or the end of the log) is reported once as
//!   `incomplete: <why> (N bytes transferred of M indicated)`. Frames with no
//!   transfer open (a stray segment, an abort) add no transfer line.
//! - An indicated size other than the bytes transferred is printed as
//!   `[size mismatch: ...]` (JSON `size_mismatch`, `indicated_size`, `size`);
//!   an expedited value with s = 0 as `[size not indicated]`. At most 64 KiB
//!   of a transfer are kept (`[truncated: ...]`, JSON `truncated`); the
//!   count goes on.
//! - The value is named and interpreted where the object is known: every
//!   object of the CiA 301 communication profile area 1000h-1FFFh on any
//!   node (1000h with the CiA 418 optional PDOs when its profile is 418,
//!   1003h with the Delta-Q code on a Delta-Q charger, 100Ch/100Dh, 1005h,
//!   1010h/1011h, 1029h, 1200h-12FFh, the PDO parameters 1400h-1BFFh
//!   numbered from 0 as the frame lines do: 1800h is TPDO0, 1F50h-1F57h,
//!   1F80h, ...; an unassigned index as reserved), and the profile objects
//!   of the node's catalogue: Delta-Q then CiA 418 on a Delta-Q charger,
//!   CiA 418/419 on a CiA 419 charger and on the battery node. A node with
//!   no role gets no profile names: bytes only.
//! - Block transfers are reassembled like segmented ones.
//!
//! JSON: `{"t","kind":"sdo_transfer","node","role","direction":"upload"|
//! "download","index","sub","status":"complete"|"aborted"|"incomplete",
//! "size","indicated_size","size_indicated","size_mismatch","truncated",
//! "bytes"(hex),"name","value","unit","meaning","text"}` plus
//! `"abort":{"code","meaning","by"}` or `"incomplete":"why"`; `value`,
//! `unit` and `meaning` are null unless the transfer completed.

use std::collections::HashMap;
use std::fmt::Write;
use std::prelude::rust_2021::*;
use std::time::Duration;

use crate::abort::AbortCode;
use crate::machine::Machine;
use crate::sdo::{
    self, BreakReason, ChannelError, Observed, Observer, ObserverConfig, ObserverEvent, SdoChannel,
    Transfer, TransferKind,
};
use crate::{CanFrame, NodeId, Timestamp};

/// At most this many bytes of one transfer are kept; the rest are counted.
pub const MAX_BYTES: usize = 64 * 1024;

/// A transfer with no frame for this long is reported incomplete.
pub const TIMEOUT: Duration = Duration::from_secs(5);

/// Channels `--sdo` can declare.
pub const EXTRA_CHANNELS: usize = 32;

/// Block transfers whose sub-blocks the decoder holds at once (889 bytes
/// each; a sub-block holds one from its first segment to its
/// acknowledgement): more than a bus runs side by side.
pub const SUB_BLOCK_BUFFERS: usize = 16;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
/// Which way a transfer moves the value.
pub enum Direction {
    /// From the server to the client.
    Upload,
    /// From the client to the server.
    Download,
}

impl Direction {
    /// `upload` / `download`.
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
    /// The SDO client.
    Client,
    /// The SDO server.
    Server,
}

impl Side {
    /// `client` / `server`.
    pub fn name(self) -> &'static str {
        match self {
            Side::Client => "client",
            Side::Server => "server",
        }
    }
}

impl From<sdo::Side> for Side {
    fn from(s: sdo::Side) -> Self {
        match s {
            sdo::Side::Client => Side::Client,
            sdo::Side::Server => Side::Server,
        }
    }
}

/// How a transfer ended.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum End {
    /// The transfer completed.
    Complete,
    /// Aborted.
    Aborted {
        /// The abort code.
        code: AbortCode,
        /// Who aborted.
        by: Side,
    },
    /// Broken off, and why in words.
    Incomplete(String),
}

/// One finished (or broken-off) transfer.
#[derive(Clone, Debug)]
pub struct Report {
    /// Time of the frame that ended it (the last frame seen of it when the
    /// log ended).
    pub t: Option<Timestamp>,
    /// The server's node.
    pub node: NodeId,
    /// Upload or download.
    pub direction: Direction,
    /// A block transfer.
    pub block: bool,
    /// The object's index.
    pub index: u16,
    /// The object's sub-index.
    pub sub: u8,
    /// The data, at most [`MAX_BYTES`].
    pub bytes: Vec<u8>,
    /// Bytes transferred (more than `bytes.len()` when truncated).
    pub total: usize,
    /// The size the initiate frames indicated.
    pub indicated: Option<u32>,
    /// False for an expedited transfer with s = 0 ("up to 4 bytes").
    pub size_indicated: bool,
    /// A block transfer's CRC was checked and matched.
    pub crc_checked: bool,
    /// A rule of CiA 301 the transfer broke and went on past (the peer
    /// accepted it), in words.
    pub broken: Option<String>,
    /// How it ended.
    pub end: End,
}

impl Report {
    /// More bytes were transferred than kept ([`MAX_BYTES`]; an upload of
    /// more bytes than indicated keeps the indicated size, as
    /// python-canopen does, and is not truncated by that).
    pub fn truncated(&self) -> bool {
        let value = match (self.direction, self.indicated) {
            (Direction::Upload, Some(n)) => {
                self.total.min(usize::try_from(n).unwrap_or(usize::MAX))
            }
            _ => self.total,
        };
        value > self.bytes.len()
    }

    /// The indicated size when it differs from what was transferred.
    pub fn size_mismatch(&self) -> Option<u32> {
        self.indicated
            .filter(|&n| usize::try_from(n) != Ok(self.total))
    }

    /// `upload` / `block download` ...
    pub fn protocol(&self) -> String {
        if self.block {
            format!("block {}", self.direction.name())
        } else {
            self.direction.name().to_string()
        }
    }
}

/// What is collected of a transfer open on a channel.
#[derive(Default)]
struct Collect {
    bytes: Vec<u8>,
    total: usize,
    last_t: Option<Timestamp>,
    /// The frame that broke a rule, in words, and the abort it called for.
    broken: Option<String>,
}

impl Collect {
    fn append(&mut self, data: &[u8]) {
        let room = MAX_BYTES.saturating_sub(self.bytes.len());
        self.bytes
            .extend_from_slice(data.get(..room.min(data.len())).unwrap_or_default());
        self.total = self.total.saturating_add(data.len());
    }
}

/// The observer and the bytes of every open transfer.
pub struct Tracker {
    observer: Observer<EXTRA_CHANNELS, SUB_BLOCK_BUFFERS>,
    open: HashMap<SdoChannel, Collect>,
    reports: Vec<Report>,
    /// The frame just taken, for the words of a rule it breaks.
    last_seen: Observed,
}

impl Default for Tracker {
    fn default() -> Self {
        Tracker {
            observer: Observer::with_extra_channels(ObserverConfig {
                default_channels: true,
                timeout: Some(TIMEOUT),
            }),
            open: HashMap::new(),
            reports: Vec::new(),
            last_seen: Observed::Other,
        }
    }
}

/// `initiate upload`, `block download`, ... for "new ..." reasons.
fn initiate_name(t: &Transfer) -> &'static str {
    let block = matches!(t.kind, Some(TransferKind::Block { .. }));
    match (t.direction, block) {
        (sdo::Direction::Upload, false) => "initiate upload",
        (sdo::Direction::Download, false) => "initiate download",
        (sdo::Direction::Upload, true) => "block upload",
        (sdo::Direction::Download, true) => "block download",
    }
}

impl Tracker {
    /// Watches one more SDO channel (`--sdo`).
    pub fn add_channel(&mut self, channel: SdoChannel) -> Result<(), ChannelError> {
        self.observer.add_channel(channel)
    }

    /// Feeds one frame of the log: what the frame is on its SDO channel.
    pub fn handle(&mut self, t: Option<Timestamp>, frame: &CanFrame) -> Observed {
        let now = t.unwrap_or(Timestamp::ZERO);
        if t.is_some() {
            self.observer.handle_timeout(now);
            self.drain(t);
        }
        let seen = self.observer.observe(now, frame);
        let channel = match seen {
            Observed::Other => return seen,
            Observed::Request { channel, .. }
            | Observed::Response { channel, .. }
            | Observed::BlockSegment { channel, .. }
            | Observed::Malformed { channel, .. } => channel,
        };
        self.last_seen = seen;
        if let Some(c) = self.open.get_mut(&channel) {
            c.last_t = t;
        }
        self.drain(t);
        seen
    }

    /// The frame just taken, in words.
    fn last_words(&self) -> String {
        match &self.last_seen {
            Observed::Request { request, .. } => format!("the client's {}", request.command),
            Observed::Response { response, .. } => format!("the server's {}", response.command),
            Observed::BlockSegment { seqno, .. } => format!("block segment seq {seqno}"),
            _ => "a frame".to_string(),
        }
    }

    /// The transfers ended by the frames handed in since the last call.
    pub fn reports(&mut self) -> std::vec::Drain<'_, Report> {
        self.reports.drain(..)
    }

    /// True when [`Tracker::reports`] has something.
    pub fn has_reports(&self) -> bool {
        !self.reports.is_empty()
    }

    fn drain(&mut self, t: Option<Timestamp>) {
        let mut pending_new: Option<Report> = None;
        while let Some(e) = self.observer.poll_event() {
            self.event(e, t, &mut pending_new);
        }
        if let Some(r) = pending_new {
            self.reports.push(r);
        }
    }

    fn event(&mut self, e: ObserverEvent, t: Option<Timestamp>, pending_new: &mut Option<Report>) {
        match e {
            ObserverEvent::Started(transfer) => {
                if let Some(mut r) = pending_new.take() {
                    r.end = End::Incomplete(format!(
                        "new {} {:04X}h:{:02X}",
                        initiate_name(&transfer),
                        transfer.index,
                        transfer.sub
                    ));
                    self.reports.push(r);
                }
                self.open.insert(
                    transfer.channel,
                    Collect {
                        last_t: t,
                        ..Collect::default()
                    },
                );
            }
            ObserverEvent::Data { channel, data, .. } => {
                let c = self.open.entry(channel).or_default();
                c.append(data.as_slice());
                c.last_t = t;
            }
            ObserverEvent::RuleBroken { channel, code, by } => {
                let what = self.last_words();
                let c = self.open.entry(channel).or_default();
                c.broken = Some(format!(
                    "{what} breaks CiA 301 (the {} should abort with {code})",
                    Side::from(by).name()
                ));
            }
            ObserverEvent::Completed {
                transfer,
                crc_checked,
                ..
            } => {
                let r = self.report(transfer, t, End::Complete, crc_checked);
                self.reports.push(r);
            }
            ObserverEvent::Aborted {
                transfer, code, by, ..
            } => {
                let end = End::Aborted {
                    code,
                    by: by.into(),
                };
                let r = self.report(transfer, t, end, false);
                self.reports.push(r);
            }
            ObserverEvent::BrokenOff {
                transfer,
                reason,
                pending,
                ..
            } => {
                let broken = self
                    .open
                    .get_mut(&transfer.channel)
                    .and_then(|c| c.broken.take());
                let why = match reason {
                    // Named after the initiate that follows (same frame).
                    BreakReason::NewInitiate => String::new(),
                    BreakReason::Violation { code, by } => broken.map_or_else(
                        || {
                            format!(
                                "the {} should have aborted with {code}",
                                Side::from(by).name()
                            )
                        },
                        |b| format!("{b}, and no abort followed"),
                    ),
                    BreakReason::AckMismatch { expected, got } => format!(
                        "acknowledgement of sequence number {got} where the log holds segments \
                         1 to {expected} of the sub-block (frames the receiver got are missing \
                         from the log; the bytes from here on cannot be placed)"
                    ),
                    BreakReason::NoSubBlockBuffer { buffers } => format!(
                        "a sub-block while all {buffers} sub-block buffers of the decoder hold \
                         other block transfers (this one is not followed)"
                    ),
                    BreakReason::AckNotSeen {
                        segments,
                        trace_ended,
                    } => format!(
                        "{} before the block acknowledgement of {segments} segment{} \
                         ({pending} bytes, not counted)",
                        if trace_ended {
                            "the log ends".to_string()
                        } else {
                            format!("no frame for {} s", TIMEOUT.as_secs())
                        },
                        if segments == 1 { "" } else { "s" },
                    ),
                    BreakReason::Timeout => {
                        let mut s = String::new();
                        let _ = write!(s, "no frame for {} s", TIMEOUT.as_secs());
                        s
                    }
                    BreakReason::EndOfTrace => "the log ends".to_string(),
                };
                let at = if matches!(
                    reason,
                    BreakReason::EndOfTrace | BreakReason::Timeout | BreakReason::AckNotSeen { .. }
                ) {
                    self.open.get(&transfer.channel).and_then(|c| c.last_t)
                } else {
                    t
                };
                let r = self.report(transfer, at, End::Incomplete(why), false);
                if reason == BreakReason::NewInitiate {
                    if let Some(p) = pending_new.replace(r) {
                        self.reports.push(p);
                    }
                } else {
                    self.reports.push(r);
                }
            }
        }
    }

    fn report(&mut self, tr: Transfer, t: Option<Timestamp>, end: End, crc: bool) -> Report {
        let mut c = self.open.remove(&tr.channel).unwrap_or_default();
        let broken = if end == End::Complete {
            c.broken.take()
        } else {
            None
        };
        // An upload of more bytes than indicated keeps the indicated size,
        // as python-canopen's client does (the total transferred stays, and
        // the report names the size mismatch).
        if let (Some(n), sdo::Direction::Upload) = (tr.indicated, tr.direction) {
            let n = usize::try_from(n).unwrap_or(usize::MAX);
            if c.total > n && c.bytes.len() > n {
                c.bytes.truncate(n);
            }
        }
        Report {
            t,
            node: tr.channel.node,
            direction: match tr.direction {
                sdo::Direction::Upload => Direction::Upload,
                sdo::Direction::Download => Direction::Download,
            },
            block: matches!(tr.kind, Some(TransferKind::Block { .. })),
            index: tr.index,
            sub: tr.sub,
            bytes: c.bytes,
            total: c.total,
            indicated: tr.indicated,
            size_indicated: !matches!(
                tr.kind,
                Some(TransferKind::Expedited {
                    size_indicated: false
                })
            ),
            crc_checked: crc,
            broken,
            end,
        }
    }

    /// Reports every transfer still open at the end of the log.
    pub fn finish(&mut self) -> Vec<Report> {
        let mut pending_new = None;
        while let Some(e) = self.observer.end_of_trace() {
            self.event(e, None, &mut pending_new);
        }
        if let Some(r) = pending_new {
            self.reports.push(r);
        }
        self.reports.drain(..).collect()
    }
}
