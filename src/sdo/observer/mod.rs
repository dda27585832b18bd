//! The passive SDO observer ([`Observer`]): its types and its channel
//! table; the transitions are in `transfer.rs`.

use core::time::Duration;

use super::data::SegmentData;
use super::server::DEFAULT_TIMEOUT;
pub use super::wire::Side;
use super::wire::{SdoRequest, SdoResponse};
use crate::abort::AbortCode;
use crate::clock::{earliest, timer_kind, MaybeTimestamp, Timers, Timestamp};
use crate::cob_id::{NodeId, SDO_RX_BASE, SDO_TX_BASE};
use crate::error::DecodeError;
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;
use crate::queue::EventQueue;
use sub_block::SubBlock;
pub use sub_block::SUB_BLOCK_BYTES;
use transfer::Open;

mod sub_block;
mod transfer;

/// How many events the observer keeps before dropping the oldest: room for
/// what one frame can make (a block acknowledgement of 127 segments makes
/// 127 data events, and a rule broken and an end) and a few more.
pub const OBSERVER_EVENT_CAPACITY: usize = 136;

/// Channels besides the default ones an [`Observer`] holds unless told
/// otherwise ([`Observer::with_extra_channels`]).
pub const OBSERVER_EXTRA_CHANNELS: usize = 8;

/// Sub-block buffers ([`SUB_BLOCK_BYTES`] each) an [`Observer`] shares
/// among its block transfers unless told otherwise: this many sub-blocks
/// can be in flight at once, on as many channels.
pub const OBSERVER_SUB_BLOCK_BUFFERS: usize = 4;

/// Nodes with a default SDO channel (1..=127).
const NODES: usize = 127;

/// One SDO channel: the COB-ID the client sends on and the one the server
/// answers on, and the node the server is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SdoChannel {
    /// The node whose server the channel reaches.
    pub node: NodeId,
    /// Client to server (the server's receive SDO): 600h + node by default.
    pub request: CanId,
    /// Server to client (the server's transmit SDO): 580h + node by default.
    pub response: CanId,
}

impl SdoChannel {
    /// The default SDO channel of `node` (CiA 301 pre-defined connection
    /// set): requests on 600h + node, responses on 580h + node.
    #[must_use]
    pub const fn default_for(node: NodeId) -> Self {
        let n = node.raw() as u16;
        SdoChannel {
            node,
            request: CanId::Standard(SDO_RX_BASE + n),
            response: CanId::Standard(SDO_TX_BASE + n),
        }
    }
}

/// Which way the value goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    /// Server to client (a read).
    Upload,
    /// Client to server (a write).
    Download,
}

/// The protocol a transfer uses, once known (an upload learns it from the
/// server's answer).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TransferKind {
    /// The value travels in the initiate frame; `size_indicated` is the s
    /// bit (without it the value is "up to 4 bytes": every data byte).
    Expedited {
        /// The s bit.
        size_indicated: bool,
    },
    /// Segments of up to 7 bytes, each answered.
    Segmented,
    /// Block transfer; `crc` when both sides announced CRC support.
    Block {
        /// The CRC is checked at the end.
        crc: bool,
    },
}

/// What is known of a transfer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Transfer {
    /// The channel it runs on.
    pub channel: SdoChannel,
    /// Upload or download.
    pub direction: Direction,
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The protocol; `None` for an upload the server has not answered yet.
    pub kind: Option<TransferKind>,
    /// The size the initiate frames indicated, if they did.
    pub indicated: Option<u32>,
}

/// Why a transfer ended without completing or being aborted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum BreakReason {
    /// The client began another transfer on the channel.
    NewInitiate,
    /// A frame broke a rule (`code` is the abort a strict peer answers with,
    /// `by` the side that should have sent it) and no abort followed.
    Violation {
        /// The abort code the rule calls for.
        code: AbortCode,
        /// The side that should have aborted.
        by: Side,
    },
    /// The receiver of the data acknowledged segments the observer did
    /// not see (it missed frames the receiver got): the bytes from here on
    /// cannot be placed.
    AckMismatch {
        /// The segments seen without a gap from sequence number 1 (up to
        /// the last one).
        expected: u8,
        /// The sequence number acknowledged.
        got: u8,
    },
    /// A block transfer's segments came with every sub-block buffer of
    /// the observer lent to other transfers
    /// ([`Observer::with_capacity`]): they cannot be held until their
    /// acknowledgement, so the transfer is not followed.
    NoSubBlockBuffer {
        /// The observer's number of sub-block buffers.
        buffers: usize,
    },
    /// The transfer stopped (timeout, end of the trace) with sub-block
    /// segments seen that no acknowledgement confirmed: they are not
    /// delivered (the event's `pending` counts their bytes).
    AckNotSeen {
        /// Segments held.
        segments: u8,
        /// The trace ended ([`Observer::end_of_trace`]); otherwise the
        /// transfer timed out.
        trace_ended: bool,
    },
    /// No frame of the transfer for [`ObserverConfig::timeout`].
    Timeout,
    /// [`Observer::end_of_trace`]: the trace ended with the transfer open.
    EndOfTrace,
}

/// What the observer reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ObserverEvent {
    /// A client initiated a transfer.
    Started(Transfer),
    /// A piece of the value, in order: `data` at `offset`.
    Data {
        /// The channel of the transfer.
        channel: SdoChannel,
        /// Offset of `data` in the value.
        offset: usize,
        /// 1..=7 bytes.
        data: SegmentData,
    },
    /// A frame broke a rule of the transfer: the side `by` should answer
    /// with an abort of `code` (the transfer stays open until that abort
    /// or the next frame; see [`Observer`]).
    RuleBroken {
        /// The channel of the transfer.
        channel: SdoChannel,
        /// The abort code the rule calls for.
        code: AbortCode,
        /// The side that should abort.
        by: Side,
    },
    /// The transfer completed: both sides confirmed it.
    Completed {
        /// The transfer, as finally known.
        transfer: Transfer,
        /// Bytes delivered in [`ObserverEvent::Data`].
        bytes: usize,
        /// A block transfer's CRC was checked and matched.
        crc_checked: bool,
    },
    /// An abort frame ended the transfer.
    Aborted {
        /// The transfer, as known when it ended.
        transfer: Transfer,
        /// Bytes delivered before it.
        bytes: usize,
        /// Bytes of block segments seen but not acknowledged when it
        /// ended: not delivered.
        pending: usize,
        /// The code in the abort frame.
        code: AbortCode,
        /// Who sent the abort.
        by: Side,
        /// The code the observer expected, when it saw a rule broken first.
        expected: Option<AbortCode>,
    },
    /// The transfer ended otherwise.
    BrokenOff {
        /// The transfer, as known when it ended.
        transfer: Transfer,
        /// Bytes delivered before it.
        bytes: usize,
        /// Bytes of block segments seen but not acknowledged when it
        /// ended: not delivered.
        pending: usize,
        /// Why.
        reason: BreakReason,
    },
}

impl ObserverEvent {
    /// True for the events that end a transfer.
    #[must_use]
    pub const fn is_terminal(&self) -> bool {
        matches!(
            self,
            ObserverEvent::Completed { .. }
                | ObserverEvent::Aborted { .. }
                | ObserverEvent::BrokenOff { .. }
        )
    }

    /// The channel the event is about.
    #[must_use]
    pub const fn channel(&self) -> SdoChannel {
        match self {
            ObserverEvent::Started(t)
            | ObserverEvent::Completed { transfer: t, .. }
            | ObserverEvent::Aborted { transfer: t, .. }
            | ObserverEvent::BrokenOff { transfer: t, .. } => t.channel,
            ObserverEvent::Data { channel, .. } | ObserverEvent::RuleBroken { channel, .. } => {
                *channel
            }
        }
    }
}

/// What one frame is, in the context of its channel ([`Observer::observe`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Observed {
    /// Not on a watched SDO channel (or a remote frame).
    Other,
    /// A client-to-server command.
    Request {
        /// The channel.
        channel: SdoChannel,
        /// The decoded frame.
        request: SdoRequest,
    },
    /// A server-to-client command.
    Response {
        /// The channel.
        channel: SdoChannel,
        /// The decoded frame.
        response: SdoResponse,
    },
    /// A sub-block segment of a block transfer (byte 0 is the sequence
    /// number and the last flag, not a command specifier).
    BlockSegment {
        /// The channel.
        channel: SdoChannel,
        /// The sender of the data.
        from: Side,
        /// Sequence number (bits 6-0 of byte 0).
        seqno: u8,
        /// The last flag c (bit 7 of byte 0).
        last: bool,
        /// The data bytes (1..=7).
        data: SegmentData,
    },
    /// A frame on a watched channel that does not decode as an SDO command;
    /// transfers ignore it, as the client and server do.
    Malformed {
        /// The channel.
        channel: SdoChannel,
        /// Its sender.
        from: Side,
        /// Why it does not decode.
        error: DecodeError,
    },
}

/// How the observer works.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObserverConfig {
    /// Watch the default channel of every node 1..=127.
    pub default_channels: bool,
    /// A transfer with no frame for this long is broken off; `None`: never
    /// (only a new initiate, an abort or the end of the trace end it).
    pub timeout: Option<Duration>,
}

impl Default for ObserverConfig {
    fn default() -> Self {
        ObserverConfig {
            default_channels: true,
            timeout: Some(Duration::from_millis(
                DEFAULT_TIMEOUT.as_millis() as u64 * 5 / 2,
            )),
        }
    }
}

/// Why [`Observer::add_channel`] refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ChannelError {
    /// Every extra channel slot is taken.
    #[error("no room for another SDO channel (at most {capacity})")]
    Full {
        /// The number of extra channels the observer holds.
        capacity: usize,
    },
    /// The request and response COB-IDs are the same.
    #[error("an SDO channel needs two COB-IDs, got {0:?} twice")]
    SameId(CanId),
    /// One of the COB-IDs is already watched as part of another channel.
    #[error("COB-ID {0:?} already belongs to an SDO channel")]
    Taken(CanId),
}

/// One watched channel and the transfer open on it.
#[derive(Debug, Clone, Copy)]
struct Slot {
    channel: SdoChannel,
    open: Option<Open>,
}

///  A passive SDO observer: it follows every transfer on the SDO channels of
///  a bus from the frames of both sides (CiA 301 section 7.2.4.3, SDO
///  protocols) and reports each one as events, without ever sending.
///
///  Fed every frame of a trace with its timestamp, [`Observer`] watches the
///  default SDO channel of every node (requests on 600h + node, responses on
///  580h + node) and any channel added with [`Observer::add_channel`]. It
///  reports each expedited, segmented and block transfer, upload and
///  download, as [`ObserverEvent`]s:
///
///  - [`ObserverEvent::Started`] at the client's initiate frame;
///  - [`ObserverEvent::Data`] for each piece of the value, in order, with its
///    offset (collect or hash them without a heap);
///  - [`ObserverEvent::RuleBroken`] at a frame that breaks a rule;
///  - exactly one end: [`ObserverEvent::Completed`] (bytes seen against the
///    indicated size, the CRC checked for a block transfer),
///    [`ObserverEvent::Aborted`] (the code, by the client or the server) or
///    [`ObserverEvent::BrokenOff`] (a new initiate, a frame the protocol does
///    not allow that no abort followed, an acknowledgement the observer
///    cannot follow, a timeout, the end of the trace).
///
///  **One set of rules.** The observer takes each frame through the same
///  transition rules as [`Client`](super::Client) and
///  [`Server`](super::Server): the segment rules (toggle bit, indicated size)
///  and the sub-block rules of block transfer (which frame is a segment,
///  which sequence number comes next, what the acknowledgement must say, the
///  end frame's unused bytes and CRC) are the crate's one implementation,
///  so the observer's reading of a transfer is the receiving machine's.
///
///  **A frame that breaks a rule** is reported as
///  [`ObserverEvent::RuleBroken`] with the abort code a strict peer answers
///  it with, and does not end the transfer at once:
///
///  - after a rule the transfer cannot be followed past (a repeated toggle
///    bit, a command out of phase, a block size or sequence number out of
///    range, a response for another object) the observer waits for the
///    abort: the transfer ends as [`ObserverEvent::Aborted`] with the peer's
///    code and the one expected, or, at any other frame on the channel, the
///    timeout or the end of the trace, as [`BreakReason::Violation`];
///  - after a size or CRC rule (more or fewer bytes than indicated, a CRC
///    that does not match) the observer goes on as the peers do (lenient, as
///    a log reader must be: real devices accept such transfers): an abort
///    ends it as [`ObserverEvent::Aborted`] with the code expected, and a
///    transfer the peers finish is [`ObserverEvent::Completed`] (a segmented
///    upload, which nobody confirms, at the next frame on the channel).
///
///  **Timing.** A transfer with no frame for [`ObserverConfig::timeout`]
///  ends as [`BreakReason::Timeout`] at the next
///  [`Machine::handle_timeout`]; the default, 2.5 times the SDO default
///  timeout of 2000 ms, leaves the peers time to send their own 05040000h
///  abort first. Timestamps that go backwards are taken as they come
///  (nothing expires early, nothing panics).
///
///  **Back-pressure.** Events go into a queue of [`OBSERVER_EVENT_CAPACITY`]; when it
///  is full the oldest is dropped and counted
///  ([`Machine::events_dropped`]), and the transfers go on by their rules
///  whether or not anybody reads them. One frame makes at most 129 events
///  (a block acknowledgement: the data of 127 segments, a rule broken and
///  the end; or a broken-off transfer, and a new expedited one started,
///  delivered and completed), fewer than the queue holds; drain after
///  every frame.
///
///  ```
///  use canopen_codec::machine::Machine;
///  use canopen_codec::sdo::{Observer, ObserverEvent, Observed};
///  use canopen_codec::{CanFrame, Timestamp};
///
///  let mut obs = Observer::new(Default::default());
///  // Node 5: read 1008h by a segmented upload of "DQ 12".
///  let frames = [
///      (0x605, &[0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0][..]),
///      (0x585, &[0x41, 0x08, 0x10, 0x00, 5, 0, 0, 0][..]),
///      (0x605, &[0x60, 0, 0, 0, 0, 0, 0, 0][..]),
///      (0x585, &[0x05, b'D', b'Q', b' ', b'1', b'2', 0, 0][..]),
///  ];
///  let mut value = Vec::new();
///  for (i, (id, data)) in frames.iter().enumerate() {
///      let frame = CanFrame::standard(*id, data).unwrap();
///      let seen = obs.observe(Timestamp::from_millis(i as u64), &frame);
///      assert!(matches!(seen, Observed::Request { .. } | Observed::Response { .. }));
///      while let Some(event) = obs.poll_event() {
///          match event {
///              ObserverEvent::Data { data, .. } => value.extend_from_slice(data.as_slice()),
///              ObserverEvent::Completed { bytes, .. } => assert_eq!(bytes, 5),
///              _ => {}
///          }
///      }
///  }
///  assert_eq!(value, b"DQ 12");
///  ```
///
/// **Block transfers** are delivered at the receiver's acknowledgements:
/// the segments of a sub-block are held (in one of `BUFFERS` buffers of
/// [`SUB_BLOCK_BYTES`] the observer's block transfers share) until the
/// acknowledgement says how many of them the receiver took in order
/// (ackseq); exactly those are delivered, and the sender's resending of
/// the rest is read as the next sub-block (CiA 301 section 7.2.4.3, SDO
/// block download and SDO block upload). An acknowledgement of segments
/// the observer did not see is [`BreakReason::AckMismatch`]; segments with
/// no buffer free, [`BreakReason::NoSubBlockBuffer`]; a transfer that
/// stops before its acknowledgement, [`BreakReason::AckNotSeen`] (what was
/// held is counted as `pending`, never delivered). CiA 301 numbers the
/// segments of a sub-block but not the sub-blocks, so a sender that takes
/// a repeated acknowledgement for the one of the sub-block it just sent
/// runs a sub-block ahead: its next segments, or its end frame, come before
/// the receiver's own acknowledgement. The observer then reads the closed
/// sub-block as the sender did, acknowledged as far as the repeat says,
/// and takes the receiver's late acknowledgement as the one owed. An
/// acknowledgement after the last segment was acknowledged is out of phase
/// for the sender (05040001h is due from it), and a frame of command
/// specifier 4 whose unused bits are set is not an abort, as the crate's
/// client and server read them.
///
/// `EXTRA` is the number of channels besides the default ones that
/// [`Observer::add_channel`] can add. Implements [`Machine`]:
/// [`Machine::handle_frame`] is [`Observer::observe`] without its answer,
/// [`Machine::poll_transmit`] is always `None`.
#[derive(Debug, Clone)]
pub struct Observer<
    const EXTRA: usize = OBSERVER_EXTRA_CHANNELS,
    const BUFFERS: usize = OBSERVER_SUB_BLOCK_BUFFERS,
> {
    config: ConfigParts,
    defaults: [Option<Open>; NODES],
    extra: [Option<Slot>; EXTRA],
    /// Slots of `extra` in use (they fill from the front).
    extra_used: usize,
    /// The sub-block buffers, lent to one block transfer at a time.
    buffers: [SubBlock; BUFFERS],
    /// Its timer ([`ObserverTimer`]).
    timers: Timers<ObserverTimer, 1>,
    events: EventQueue<ObserverEvent, OBSERVER_EVENT_CAPACITY>,
}

timer_kind! {
    /// The observer's one timer: the open transfers' deadlines (each
    /// [`ObserverConfig::timeout`] after its last frame) are many, in the
    /// channels' slots; the timer is the earliest of them.
    enum ObserverTimer {
        /// No open transfer's deadline is before this (a lower bound, as
        /// a transfer's frame only moves its deadline later; exact after
        /// every [`Machine::handle_timeout`] that reaches it).
        Inactivity,
    }
}

#[derive(Debug, Clone, Copy)]
struct ConfigParts {
    config: ObserverConfig,
    timeout_us: Option<u64>,
}

/// A filler for the event queue's free slots (never returned).
const FILLER: ObserverEvent = ObserverEvent::Data {
    channel: SdoChannel::default_for(NodeId::MIN),
    offset: 0,
    data: SegmentData::EMPTY,
};

impl Observer {
    /// An observer with no transfer open and room for
    /// [`OBSERVER_EXTRA_CHANNELS`] channels besides the default ones.
    #[must_use]
    pub fn new(config: ObserverConfig) -> Self {
        Observer::with_extra_channels(config)
    }
}

impl<const EXTRA: usize, const BUFFERS: usize> Observer<EXTRA, BUFFERS> {
    /// An observer with no transfer open and room for `EXTRA` channels
    /// besides the default ones (`Observer::<32>::with_extra_channels(..)`);
    /// the same as [`Observer::with_capacity`].
    #[must_use]
    pub fn with_extra_channels(config: ObserverConfig) -> Self {
        Self::with_capacity(config)
    }

    /// An observer with no transfer open, room for `EXTRA` channels besides
    /// the default ones and `BUFFERS` sub-block buffers for block transfers
    /// in flight at once (`Observer::<8, 16>::with_capacity(..)`).
    #[must_use]
    pub fn with_capacity(config: ObserverConfig) -> Self {
        let timeout_us = config
            .timeout
            .map(|d| u64::try_from(d.as_micros()).unwrap_or(u64::MAX));
        Observer {
            config: ConfigParts { config, timeout_us },
            defaults: [None; NODES],
            extra: [None; EXTRA],
            extra_used: 0,
            buffers: [sub_block::FREE; BUFFERS],
            timers: Timers::new(),
            events: EventQueue::new(FILLER),
        }
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &ObserverConfig {
        &self.config.config
    }

    /// Watches one more channel (an SDO server on other COB-IDs than the
    /// default, or a second server of a node). Frames on its identifiers
    /// count for it even when they are another node's default channel.
    pub fn add_channel(&mut self, channel: SdoChannel) -> Result<(), ChannelError> {
        if channel.request == channel.response {
            return Err(ChannelError::SameId(channel.request));
        }
        for slot in self.extra.iter().flatten() {
            for id in [channel.request, channel.response] {
                if id == slot.channel.request || id == slot.channel.response {
                    return Err(ChannelError::Taken(id));
                }
            }
        }
        let Some(free) = self.extra.iter_mut().find(|s| s.is_none()) else {
            return Err(ChannelError::Full { capacity: EXTRA });
        };
        *free = Some(Slot {
            channel,
            open: None,
        });
        self.extra_used += 1;
        Ok(())
    }

    /// The transfer open on `channel`, if any.
    #[must_use]
    pub fn open_transfer(&self, channel: SdoChannel) -> Option<Transfer> {
        self.slots()
            .find(|(c, _)| *c == channel)
            .and_then(|(_, open)| open.map(|o| o.transfer()))
    }

    /// The number of transfers open now.
    #[must_use]
    pub fn open_transfers(&self) -> usize {
        self.slots().filter(|(_, open)| open.is_some()).count()
    }

    fn slots(&self) -> impl Iterator<Item = (SdoChannel, &Option<Open>)> + '_ {
        let defaults = self
            .defaults
            .iter()
            .enumerate()
            .filter(|_| self.config.config.default_channels)
            .filter_map(|(i, open)| {
                let node = u8::try_from(i + 1).ok().and_then(NodeId::new)?;
                Some((SdoChannel::default_for(node), open))
            });
        self.extra
            .iter()
            .flatten()
            .map(|s| (s.channel, &s.open))
            .chain(defaults)
    }

    /// Takes one frame of the trace at `now`: follows the transfer on its
    /// channel (queueing events) and says what the frame is there. Frames
    /// on other identifiers and remote frames are [`Observed::Other`].
    pub fn observe(&mut self, now: Timestamp, frame: &CanFrame) -> Observed {
        if frame.is_remote() {
            return Observed::Other;
        }
        let timeout = self.config.timeout_us;
        let Some((channel, from, open)) = route(
            &mut self.extra,
            self.extra_used,
            &mut self.defaults,
            self.config.config.default_channels,
            frame.id(),
        ) else {
            return Observed::Other;
        };
        let mut out = Sink {
            queue: &mut self.events,
            pool: &mut self.buffers,
        };
        // Only a transfer in the sub-block phase holds a buffer: one that
        // leaves it (or ends) gives it back.
        let held = open.as_ref().is_some_and(Open::holds_segments);
        let seen = transfer::step(open, channel, from, frame, &mut out);
        if let Some(broken) = open.as_mut().and_then(Open::rule_broken) {
            out.push(broken);
        }
        if held && !open.as_ref().is_some_and(Open::holds_segments) {
            sub_block::give_back(out.pool, channel);
        }
        if let Some(o) = open.as_mut() {
            // Kept as the timer table keeps it (the end of the clock a
            // microsecond early), so the transfer expires when its timer does.
            o.deadline = timeout.and_then(|us| MaybeTimestamp::new(Some(now.add_micros(us))).get());
            let next = earliest([self.timers.get(ObserverTimer::Inactivity), o.deadline]);
            self.timers.set(ObserverTimer::Inactivity, next);
        }
        seen
    }

    /// Ends one transfer still open at the end of the trace (after handing
    /// out the queued events first): call until `None`. Each open transfer
    /// ends once, as [`BreakReason::EndOfTrace`]; none is lost to a full
    /// queue.
    pub fn end_of_trace(&mut self) -> Option<ObserverEvent> {
        if let Some(event) = self.events.pop() {
            return Some(event);
        }
        let defaults = self.config.config.default_channels;
        let extra = self
            .extra
            .iter_mut()
            .flatten()
            .map(|s| &mut s.open)
            .find(|o| o.is_some());
        let open = match extra {
            Some(open) => open,
            None if defaults => self.defaults.iter_mut().find(|o| o.is_some())?,
            None => return None,
        };
        let o = open.take()?;
        sub_block::give_back(&mut self.buffers, o.transfer().channel);
        Some(o.ended(BreakReason::EndOfTrace))
    }

    fn expire(&mut self, now: Timestamp) {
        let mut next: Option<Timestamp> = None;
        let events = &mut self.events;
        let opens = self
            .extra
            .iter_mut()
            .flatten()
            .map(|s| &mut s.open)
            .chain(self.defaults.iter_mut());
        for open in opens {
            let Some(deadline) = open.as_ref().and_then(|o| o.deadline) else {
                continue;
            };
            if now.has_reached(deadline) {
                if let Some(o) = open.take() {
                    sub_block::give_back(&mut self.buffers, o.transfer().channel);
                    events.push(o.ended(BreakReason::Timeout));
                }
            } else {
                next = earliest([next, Some(deadline)]);
            }
        }
        self.timers.set(ObserverTimer::Inactivity, next);
    }
}

/// The channel a frame identifier belongs to, the side that sent it, and
/// the channel's open transfer.
fn route<'a>(
    extra: &'a mut [Option<Slot>],
    extra_used: usize,
    defaults: &'a mut [Option<Open>; NODES],
    default_channels: bool,
    id: CanId,
) -> Option<(SdoChannel, Side, &'a mut Option<Open>)> {
    let extra = extra.get_mut(..extra_used).unwrap_or(&mut []);
    for slot in extra.iter_mut().flatten() {
        if id == slot.channel.request {
            return Some((slot.channel, Side::Client, &mut slot.open));
        }
        if id == slot.channel.response {
            return Some((slot.channel, Side::Server, &mut slot.open));
        }
    }
    if !default_channels {
        return None;
    }
    let CanId::Standard(raw) = id else {
        return None;
    };
    let (side, n) = match raw {
        0x601..=0x67F => (Side::Client, raw - SDO_RX_BASE),
        0x581..=0x5FF => (Side::Server, raw - SDO_TX_BASE),
        _ => return None,
    };
    let node = u8::try_from(n).ok().and_then(NodeId::new)?;
    let open = defaults.get_mut(usize::from(n).checked_sub(1)?)?;
    Some((SdoChannel::default_for(node), side, open))
}

impl<const EXTRA: usize, const BUFFERS: usize> Default for Observer<EXTRA, BUFFERS> {
    fn default() -> Self {
        Observer::with_capacity(ObserverConfig::default())
    }
}

/// What the transitions of one frame write to: the observer's event queue
/// and its pool of sub-block buffers (a block transfer's segments are held
/// there until the receiver acknowledges them).
pub(super) struct Sink<'a> {
    queue: &'a mut EventQueue<ObserverEvent, OBSERVER_EVENT_CAPACITY>,
    pool: &'a mut [SubBlock],
}

impl Sink<'_> {
    pub(super) fn push(&mut self, event: ObserverEvent) {
        self.queue.push(event);
    }
}

impl<const EXTRA: usize, const BUFFERS: usize> Machine for Observer<EXTRA, BUFFERS> {
    type Event = ObserverEvent;

    /// [`Observer::observe`], its answer dropped.
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        let _ = self.observe(now, frame);
    }

    /// Breaks off every transfer with no frame for the timeout.
    fn handle_timeout(&mut self, now: Timestamp) {
        if self.timers.expire(ObserverTimer::Inactivity, now) {
            self.expire(now);
        }
    }

    // The observer only listens: no frame to send, none dropped.
    // When the next open transfer may time out (possibly earlier than any
    // does: an extra [`Machine::handle_timeout`] is harmless).
    crate::machine::queued_outputs!(timers: timers, frames: none, events: events);
}

#[cfg(test)]
mod tests;

#[cfg(test)]
#[path = "block_ack_tests.rs"]
mod block_ack_tests;

#[cfg(test)]
#[path = "run_ahead_tests.rs"]
mod run_ahead_tests;

#[cfg(test)]
#[path = "timer_tests.rs"]
mod timer_tests;
