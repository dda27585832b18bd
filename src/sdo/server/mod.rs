//! The SDO server: expedited and segmented transfers over a caller-owned
//! [`ObjectDictionary`], as a time-driven sans-IO state machine.
//!
//! # Driving it
//!
//! The server implements [`Machine`], the crate's state-machine contract
//! (call order and back-pressure rule: see [`crate::machine`]); it has no
//! commands. After every `handle_*` call, send what
//! [`Machine::poll_transmit`] returns.
//!
//! - **Events** go to a queue of `EVENTS` (four by default; one call
//!   leaves at most [`EVENTS_PER_CALL`]); when it is full the oldest event
//!   is dropped and counted ([`Machine::events_dropped`]). Requests are served
//!   whether or not events are read; a transfer's terminal event is pushed
//!   last, so it is the newest event kept until the next transfer reports.
//! - **Frames**: every call queues at most one frame (one response or abort
//!   per request, one abort per timeout; a superseded transfer ends without
//!   a frame), so the transmit queue holds one, and a caller that drains it
//!   after every call, as the contract asks, never loses a frame. A caller
//!   that does not loses the older, unsent frame, counted by
//!   [`Server::frames_dropped`]; the newest is kept, and frames that are
//!   sent are always in the order they were made. Why not refuse the
//!   request instead: SDO is confirmed request/response and the client
//!   waits for the answer to the request it sent last, so the newest
//!   response is the one it expects; ignoring the request would let the
//!   obsolete answer go out later, to a request the client has given up on.
//! - **Timer**: one, the timeout for the client's next frame, armed on
//!   every response of a running transfer and stopped when it ends.
//!
//! # Behaviour (CiA 301 section 7.2.4, SDO, and the choices made here)
//!
//! - One transfer at a time. A new *initiate* request while a transfer is
//!   running supersedes it: the old transfer ends with
//!   [`ServerEvent::Aborted`] (origin [`AbortOrigin::Superseded`], no frame
//!   sent, the dictionary's `abort_write` called for a download) and the new
//!   request is served. A client only re-initiates after giving up on the old
//!   transfer, so refusing would lock it out until our own timeout.
//! - Values of 1..=4 bytes are uploaded expedited, longer and empty values
//!   segmented with the size indicated.
//! - Every failure ends the transfer with exactly one [`ServerEvent::Aborted`]
//!   and, unless the client aborted, one abort frame carrying the transfer's
//!   index and sub-index.
//! - Block download and block upload (CiA 301 section 7.2.4.3, SDO
//!   protocols): the sub-block rules and the abort choices are in the
//!   [`sdo`](super) module docs. During a block upload's sub-block, [`Machine::poll_transmit`]
//!   yields one segment per call, read from the dictionary when polled.
//! - A segment request, or a command with an unknown specifier, while no
//!   transfer runs is answered with abort 05040001h carrying index and
//!   sub-index 0, and reported as an [`ServerEvent::Aborted`] for object 0:0.
//!   A received abort while idle is ignored.
//! - Download lengths are checked against the dictionary's [`SizeRule`]:
//!   too long 06070012h, too short 06070013h; an expedited download without
//!   size indicated to a fixed object longer than 4 bytes 06070010h (the
//!   length cannot match).
//! - Frames that do not decode (too short for their command) are ignored.
//! - **Time**: the timeout restarts on every frame of the transfer. A
//!   timestamp earlier than the last one never panics: the deadline is simply
//!   not reached yet. A timestamp far ahead expires the running transfer.

use core::time::Duration;

use super::data::InitiatePayload;
use super::end::{AbortOrigin, TransferEnd};
use super::rules::block::{is_abort, MAX_BLOCK_SIZE};
#[cfg(feature = "sdo-block")]
use super::rules::block::{Receiver, Sender};
use super::rules::segmented::Segments;
use super::wire::{ClientCommand, SdoFrame, ServerCommand};
use crate::abort::AbortCode;
use crate::clock::{Timers, Timestamp};
use crate::cob_id::{NodeId, SDO_RX_BASE, SDO_TX_BASE};
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;
use crate::od::{ObjectDictionary, ObjectInfo, SizeRule};
use crate::queue::{EventQueue, FrameSlot};

/// How many events [`Server::new`] keeps before dropping the oldest (room
/// for a caller that drains less often than the contract asks; a caller
/// that drains after every call needs [`EVENTS_PER_CALL`], see
/// [`Server::with_event_capacity`]).
pub const DEFAULT_EVENT_CAPACITY: usize = 4;

/// The most events one call of the SDO [`Server`] or [`Client`](super::Client)
/// leaves to be read, so the event capacity a caller needs that reads them
/// all after every `handle_*` call and every command: the server reports a
/// superseded transfer and the new request's end, the client an upload's
/// last piece and `Uploaded`. A call that starts while a server's block
/// upload ended in `poll_transmit` (one event, unread) finds the server
/// idle, so it adds at most one. The tests drive both machines with this
/// capacity beside the default one on random input: the same events, none
/// dropped.
pub const EVENTS_PER_CALL: usize = 2;

crate::clock::timer_kind! {
    /// The one timer.
    enum ServerTimer {
        /// The SDO timeout: the client's next request is due.
        Request,
    }
}

/// What an initiate path gives (see `Server::initiate`): the response and
/// the transfer's end, or the abort code.
type Initiated = Result<(ServerCommand, Option<ServerEvent>), AbortCode>;

/// The default SDO timeout: 2000 ms, Delta-Q's recommendation.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_millis(2000);

/// What the server reports: how each transfer ended, the one type the
/// client reports it with too ([`TransferEnd`]).
pub type ServerEvent = TransferEnd;

/// Identifiers and timeout of one SDO server channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ServerConfig {
    /// Requests arrive on this identifier (default 0x600 + node).
    pub request_id: CanId,
    /// Responses are sent on this identifier (default 0x580 + node).
    pub response_id: CanId,
    /// How long to wait for the client's next frame.
    pub timeout: Duration,
    /// Block download: segments per sub-block this server asks for, 1..=127
    /// (default 127; 0 counts as 1, above 127 as 127). CiA 301: the
    /// receiver of the data chooses the block size.
    pub block_size: u8,
    /// Block transfer: this server supports CRC (default true). CiA 301:
    /// the CRC is used only when both sides support it.
    pub crc: bool,
}

impl ServerConfig {
    /// The default channel of `node`: 0x600/0x580 + node, 2000 ms.
    #[must_use]
    pub const fn for_node(node: NodeId) -> Self {
        ServerConfig {
            request_id: CanId::Standard(SDO_RX_BASE + node.raw() as u16),
            response_id: CanId::Standard(SDO_TX_BASE + node.raw() as u16),
            timeout: DEFAULT_TIMEOUT,
            block_size: MAX_BLOCK_SIZE,
            crc: true,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Idle,
    Uploading {
        index: u16,
        sub: u8,
        offset: usize,
        len: usize,
        toggle: bool,
    },
    Downloading {
        index: u16,
        sub: u8,
        rx: Segments,
        /// The object's size rule (all of its `ObjectInfo` the segments
        /// need: 8 bytes instead of 16).
        size: SizeRule,
    },
    /// Block upload: initiate answered, waiting for the start command.
    #[cfg(feature = "sdo-block")]
    BlockUploadInitiated {
        index: u16,
        sub: u8,
        len: usize,
        crc: bool,
        blksize: u8,
    },
    /// Block upload: sub-blocks are being sent (segments are made when
    /// polled) and acknowledged.
    #[cfg(feature = "sdo-block")]
    BlockUploading {
        index: u16,
        sub: u8,
        tx: Sender,
    },
    /// Block upload: the end frame is out.
    #[cfg(feature = "sdo-block")]
    BlockUploadEnding {
        index: u16,
        sub: u8,
        len: usize,
    },
    /// Block download: receiving sub-blocks, then the end frame.
    #[cfg(feature = "sdo-block")]
    BlockDownloading {
        index: u16,
        sub: u8,
        info: ObjectInfo,
        rx: Receiver,
    },
}

/// An SDO server over the dictionary `D`. See the module docs for the
/// driving loop and behaviour.
///
/// ```
/// # #[cfg(feature = "alloc")] { // MemoryDictionary needs `alloc`
/// use canopen_codec::machine::Machine;
/// use canopen_codec::sdo::{Server, ServerConfig, ServerEvent};
/// use canopen_codec::od::{Access, MemoryDictionary};
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
///
/// let mut od = MemoryDictionary::new();
/// od.insert(0x1017, 0, Access::ReadWrite, &1000u16.to_le_bytes());
/// let node = NodeId::new(1).unwrap();
/// let mut server = Server::new(ServerConfig::for_node(node), od);
/// // Upload 1017h sub 0.
/// let req = CanFrame::standard(0x601, &[0x40, 0x17, 0x10, 0, 0, 0, 0, 0]).unwrap();
/// server.handle_frame(Timestamp::ZERO, &req);
/// let resp = server.poll_transmit().unwrap();
/// assert_eq!(resp, CanFrame::standard(0x581, &[0x4B, 0x17, 0x10, 0, 0xE8, 0x03, 0, 0]).unwrap());
/// assert_eq!(server.poll_event(), Some(ServerEvent::Uploaded { index: 0x1017, sub: 0, len: 2 }));
/// # }
/// ```
///
/// `EVENTS` is the capacity of the event queue (default
/// [`DEFAULT_EVENT_CAPACITY`]; [`Server::with_event_capacity`] makes one
/// with another).
#[derive(Debug)]
pub struct Server<D, const EVENTS: usize = DEFAULT_EVENT_CAPACITY> {
    config: Channel,
    /// The configuration's timeout in microseconds, computed once (the
    /// one copy of it the server keeps).
    timeout_us: u64,
    /// What `CanFrame::word` gives for a data frame on `config.request_id`
    /// (`u32::MAX`, matching no frame, when it is out of range).
    request_filter: u32,
    od: D,
    state: State,
    timers: Timers<ServerTimer, 1>,
    /// One frame: every call produces at most one (see the module docs).
    transmit: FrameSlot,
    events: EventQueue<ServerEvent, EVENTS>,
}

/// What a server keeps of its [`ServerConfig`] besides the timeout (held
/// once, in microseconds, not also as a 16-byte `Duration`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Channel {
    request_id: CanId,
    response_id: CanId,
    block_size: u8,
    crc: bool,
    /// The identifier it sends on is valid (checked once, not per frame).
    sends: bool,
}

impl Channel {
    fn new(config: &ServerConfig) -> Self {
        Channel {
            request_id: config.request_id,
            response_id: config.response_id,
            block_size: config.block_size,
            crc: config.crc,
            sends: crate::frame::check_id(config.response_id).is_ok(),
        }
    }
}

impl<D: ObjectDictionary> Server<D> {
    /// A server on `config`'s identifiers serving `od`, with an event queue
    /// of [`DEFAULT_EVENT_CAPACITY`].
    pub fn new(config: ServerConfig, od: D) -> Self {
        Self::with_event_capacity(config, od)
    }
}

impl<D: ObjectDictionary, const EVENTS: usize> Server<D, EVENTS> {
    /// A server on `config`'s identifiers serving `od`, with an event queue
    /// of `EVENTS` (1 or more; [`EVENTS_PER_CALL`] for a caller that reads
    /// every event after every call, as a device does).
    ///
    /// ```
    /// use canopen_codec::device::CommObjects;
    /// use canopen_codec::sdo::{Server, ServerConfig, EVENTS_PER_CALL};
    /// use canopen_codec::NodeId;
    ///
    /// let node = NodeId::new(1).unwrap();
    /// let server: Server<_, EVENTS_PER_CALL> =
    ///     Server::with_event_capacity(ServerConfig::for_node(node), CommObjects::new(node));
    /// assert!(!server.is_busy());
    /// ```
    pub fn with_event_capacity(config: ServerConfig, od: D) -> Self {
        let mut server = Self::unconfigured(od);
        server.restart(config);
        server
    }

    /// A server over `od` with no channel yet (constants only): it serves
    /// and sends nothing until [`restart`](Self::restart) configures it (a
    /// device's construction, whose reset path does).
    pub(crate) const fn unconfigured(od: D) -> Self {
        Server {
            config: Channel {
                request_id: CanId::Standard(0),
                response_id: CanId::Standard(0),
                // Zero bytes (`restart` sets the channel before any use).
                block_size: 0,
                crc: false,
                sends: false,
            },
            timeout_us: 0,
            // No frame matches this (see `data_frame_identity`).
            request_filter: u32::MAX,
            od,
            state: State::Idle,
            timers: Timers::new(),
            transmit: FrameSlot::new(),
            events: EventQueue::new(ServerEvent::Uploaded {
                index: 0,
                sub: 0,
                len: 0,
            }),
        }
    }

    /// Starts over on `config` with the dictionary it has: what
    /// [`new`](Self::new) would give (no transfer, frame or event; a
    /// running download is aborted in the dictionary, as
    /// [`cancel`](Self::cancel) does), without building a second server
    /// (a device's NMT reset).
    pub fn restart(&mut self, config: ServerConfig) {
        self.cancel();
        self.config = Channel::new(&config);
        self.timeout_us = u64::try_from(config.timeout.as_micros()).unwrap_or(u64::MAX);
        self.request_filter = crate::frame::data_frame_identity(config.request_id);
        self.timers = Timers::new();
        self.transmit = FrameSlot::new();
        self.events = EventQueue::new(ServerEvent::Uploaded {
            index: 0,
            sub: 0,
            len: 0,
        });
    }

    /// The configuration, its timeout as the server keeps and runs it: in
    /// whole microseconds (what is finer is not kept).
    ///
    /// ```
    /// use canopen_codec::device::CommObjects;
    /// use canopen_codec::sdo::{Server, ServerConfig};
    /// use canopen_codec::NodeId;
    /// use core::time::Duration;
    ///
    /// let node = NodeId::new(1).unwrap();
    /// let config = ServerConfig { timeout: Duration::from_millis(250), ..ServerConfig::for_node(node) };
    /// let mut server = Server::new(config, CommObjects::new(node));
    /// assert_eq!(server.config(), config);
    /// let fine = ServerConfig { timeout: Duration::from_nanos(1_500), ..config };
    /// server.restart(fine);
    /// assert_eq!(server.config().timeout, Duration::from_micros(1));
    /// ```
    #[must_use]
    pub const fn config(&self) -> ServerConfig {
        ServerConfig {
            request_id: self.config.request_id,
            response_id: self.config.response_id,
            timeout: Duration::from_micros(self.timeout_us),
            block_size: self.config.block_size,
            crc: self.config.crc,
        }
    }

    /// The dictionary.
    pub const fn od(&self) -> &D {
        &self.od
    }

    /// The dictionary, mutably (the application updates its values here).
    pub fn od_mut(&mut self) -> &mut D {
        &mut self.od
    }

    /// Gives the dictionary back.
    pub fn into_inner(self) -> D {
        self.od
    }

    /// True while a transfer is in progress.
    #[must_use]
    pub const fn is_busy(&self) -> bool {
        !matches!(self.state, State::Idle)
    }

    /// Whether `frame` is a request on this server's channel (the frames
    /// [`handle_frame`](Machine::handle_frame) acts on).
    #[must_use]
    pub(crate) fn is_request(&self, frame: &CanFrame) -> bool {
        frame.identity() == self.request_filter
    }

    /// Turns the answer to the download that just completed (the one its
    /// [`ServerEvent::Downloaded`] reported, not sent yet) into an abort of
    /// `index`/`sub` with `code`: for a device whose write takes effect
    /// after the dictionary accepted it (1010h, store parameters, CiA 301
    /// section 7.5.2.13: a storage that fails is 06060000h). Does nothing
    /// while a transfer runs.
    pub fn refuse_completed_download(&mut self, index: u16, sub: u8, code: AbortCode) {
        if matches!(self.state, State::Idle) && self.transmit.pop().is_some() {
            self.send(ServerCommand::Abort { index, sub, code });
        }
    }

    /// Ends the running transfer without a frame or an event, as the
    /// owner's NMT state requires (CiA 301: no SDO in stopped; a reset
    /// drops it); for a download the dictionary's `abort_write` is called.
    /// Does nothing while idle.
    pub fn cancel(&mut self) {
        if self.is_writing() {
            let (index, sub) = self.object();
            self.od.abort_write(index, sub);
        }
        self.state = State::Idle;
        self.timers.set(ServerTimer::Request, None);
    }

    fn object(&self) -> (u16, u8) {
        match self.state {
            State::Idle => (0, 0),
            State::Uploading { index, sub, .. } | State::Downloading { index, sub, .. } => {
                (index, sub)
            }
            #[cfg(feature = "sdo-block")]
            State::BlockUploadInitiated { index, sub, .. }
            | State::BlockUploading { index, sub, .. }
            | State::BlockUploadEnding { index, sub, .. }
            | State::BlockDownloading { index, sub, .. } => (index, sub),
        }
    }

    /// True while a download (segmented or block) has written to the
    /// dictionary or may write to it.
    const fn is_writing(&self) -> bool {
        #[cfg(feature = "sdo-block")]
        let writing = matches!(
            self.state,
            State::Downloading { .. } | State::BlockDownloading { .. }
        );
        #[cfg(not(feature = "sdo-block"))]
        let writing = matches!(self.state, State::Downloading { .. });
        writing
    }

    /// Queues `command` as a frame of 8 bytes on the response identifier
    /// (every byte the command leaves undefined zero). Inlined: every call
    /// site but the initiate answer sends one known command.
    #[inline(always)]
    fn send(&mut self, command: ServerCommand) {
        self.queue(command.to_bytes());
    }

    /// Queues the 8 data bytes of a frame on the response identifier.
    fn queue(&mut self, bytes: [u8; 8]) {
        if self.config.sends {
            super::queue_frame(&mut self.transmit, self.config.response_id, bytes);
        }
    }

    /// Ends the running transfer (or answers a stray request) with an abort
    /// frame and, for a running transfer, an Aborted event.
    fn abort_local(&mut self, code: AbortCode) {
        let (index, sub) = self.object();
        self.abort_object(index, sub, code);
    }

    fn abort_object(&mut self, index: u16, sub: u8, code: AbortCode) {
        self.cancel();
        self.send(ServerCommand::Abort { index, sub, code });
        self.emit(TransferEnd::local_abort(index, sub, code));
    }

    fn abort_by_peer(&mut self, code: AbortCode) {
        // CiA 301 code 0 is not a code; report it as a general error.
        let code = match code {
            AbortCode::Other(0) => AbortCode::GeneralError,
            c => c,
        };
        self.end_transfer(code, AbortOrigin::Peer);
    }

    fn supersede(&mut self) {
        self.end_transfer(AbortCode::GeneralError, AbortOrigin::Superseded);
    }

    /// Ends the running transfer without a frame (the peer aborted it, or
    /// a new request replaced it): the dictionary's `abort_write` for a
    /// download, one Aborted event. Does nothing while idle.
    fn end_transfer(&mut self, code: AbortCode, origin: AbortOrigin) {
        if !self.is_busy() {
            return;
        }
        let (index, sub) = self.object();
        self.cancel();
        self.emit(ServerEvent::Aborted {
            index,
            sub,
            code,
            origin,
        });
    }

    /// A new transfer of `index`/`sub` (an upload when `download` is
    /// `None`): the running one superseded, the object looked up, and every
    /// failure answered by one abort frame for the object (one call site of
    /// the abort for both initiate paths).
    ///
    /// Both paths give the response and the transfer's end (an expedited transfer) or `None` (a segmented one,
    /// its state set): one call site of the response, the event and the
    /// timer.
    fn initiate(&mut self, now: Timestamp, index: u16, sub: u8, download: Option<InitiatePayload>) {
        self.supersede();
        let result = match self.od.info(index, sub) {
            Ok(info) => match download {
                None => self.initiate_upload(index, sub, info),
                Some(payload) => self.initiate_download(index, sub, info, payload),
            },
            Err(code) => Err(code),
        };
        self.answer_initiate(now, index, sub, result);
    }

    /// Answers an initiate of `index`/`sub` with what `initiate_upload` /
    /// `initiate_download` gave (see `initiate`); an error with the abort
    /// frame and event `abort_object` makes. The server is idle here (the
    /// running transfer superseded, a failed path leaves no state), so
    /// the end of a transfer is its event alone.
    fn answer_initiate(&mut self, now: Timestamp, index: u16, sub: u8, result: Initiated) {
        let (response, end) = match result {
            Ok(answer) => answer,
            Err(code) => (
                ServerCommand::Abort { index, sub, code },
                Some(TransferEnd::local_abort(index, sub, code)),
            ),
        };
        self.send(response);
        match end {
            Some(event) => self.emit(event),
            None => self.arm(now),
        }
    }

    /// A data frame on the request identifier: a block download's
    /// sub-block segment goes to the block rules; every other frame is
    /// read by the wire layer ([`ClientCommand::parse`]; frames too short
    /// for their command are ignored) and matched against the running
    /// transfer. The segment of a running segmented transfer updates the
    /// state in place. Out of line: a device routing its frames stays one
    /// loop.
    #[inline(never)]
    fn handle_request(&mut self, now: Timestamp, frame: &CanFrame) {
        #[cfg(feature = "sdo-block")]
        if self.block_segment(now, frame.data()) {
            return;
        }
        let Ok(request) = SdoFrame::of_frame(frame).and_then(|f| ClientCommand::parse(&f)) else {
            return;
        };
        // One call site of `initiate` for both directions.
        let (index, sub, download) = match request {
            ClientCommand::UploadSegment { toggle }
                if matches!(self.state, State::Uploading { .. }) =>
            {
                return self.upload_segment(now, toggle);
            }
            ClientCommand::DownloadSegment(segment)
                if matches!(self.state, State::Downloading { .. }) =>
            {
                return self.download_segment(now, &segment);
            }
            ClientCommand::InitiateUpload { index, sub } => (index, sub, None),
            ClientCommand::InitiateDownload {
                index,
                sub,
                payload,
            } => (index, sub, Some(payload)),
            // CiA 301 section 7.2.4.3 (SDO abort transfer): byte 0 is
            // 80h, its low bits "not used, always 0". A frame of command
            // specifier 4 with them set is not taken as an abort (it is a
            // sub-block segment out of phase, seen when a block sender
            // resends after the last acknowledgement): an unknown command.
            ClientCommand::Abort { code, .. } if is_abort(frame.data()) => {
                return self.abort_by_peer(code)
            }
            #[cfg(feature = "sdo-block")]
            ClientCommand::BlockUpload(b) => return self.on_block_upload(now, b),
            #[cfg(feature = "sdo-block")]
            ClientCommand::BlockDownload(b) => return self.on_block_download(now, b, frame.data()),
            // CiA 301 section 7.2.4.3 makes block transfer optional: a
            // server without it answers a block request like any command it
            // does not know, 05040001h. A block initiate is a new request:
            // it ends the running transfer (superseded) and is refused for
            // its own object; any other block command aborts the running
            // transfer, as an unknown command does.
            #[cfg(not(feature = "sdo-block"))]
            ClientCommand::BlockUpload(crate::sdo::ClientBlockUpload::Initiate(
                crate::sdo::BlockUploadInitiate { index, sub, .. },
            ))
            | ClientCommand::BlockDownload(crate::sdo::ClientBlockDownload::Initiate(
                crate::sdo::BlockDataInitiate { index, sub, .. },
            )) => {
                self.supersede();
                return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
            }
            // A segment request outside the transfer it belongs to, ccs =
            // 7 (not a command), and without `sdo-block` any block command
            // but an initiate: the command does not fit.
            _ => return self.abort_local(AbortCode::InvalidCommandSpecifier),
        };
        self.initiate(now, index, sub, download);
    }
}

super::sdo_endpoint_machine!(
    Server<D: ObjectDictionary>,
    ServerEvent,
    ServerTimer::Request,
    request_filter,
    handle_request
);

#[cfg(feature = "sdo-block")]
mod block;
mod download;
mod upload;

#[cfg(all(test, not(feature = "sdo-block")))]
mod without_block_tests;
