//! The SDO client for one server: expedited and segmented uploads and
//! downloads as a time-driven sans-IO state machine.
//!
//! Segmented transfer needs the feature `sdo-client-segmented` (default
//! on; `sdo-block` implies it). Without it the client does expedited
//! transfers only (values of 1..=4 bytes): [`Client::start_download`] of
//! any other length returns [`ClientError::SegmentedUnsupported`] and
//! sends nothing, and a server that answers an upload initiate segmented
//! gets abort 05040001h (one [`TransferEnd::Aborted`], origin local).
//!
//! # Driving it
//!
//! The client implements [`Machine`], the crate's state-machine contract
//! (call order and back-pressure rule: see [`crate::machine`]). Its commands
//! are [`Client::start_upload`], [`Client::start_download`],
//! [`Client::start_block_upload`], [`Client::start_block_download`] and
//! [`Client::abort`] (the two block commands need the feature `sdo-block`;
//! without it they return [`ClientError::BlockUnsupported`]); after each of
//! them and after every `handle_*` call,
//! send what [`Machine::poll_transmit`] returns. During a block download's
//! sub-block, `poll_transmit` yields one segment per call, made from the
//! data when polled (the block rules: see the [`sdo`](super) module docs).
//!
//! - **Events** go to a queue of `EVENTS` (four by default; one call
//!   leaves at most [`EVENTS_PER_CALL`](super::EVENTS_PER_CALL)); when it
//!   is full the oldest event is dropped and counted
//!   ([`Machine::events_dropped`]). Transfers run by
//!   their own rules whether or not events are read; a transfer's terminal
//!   event is pushed last, so it is the newest event kept until the next
//!   transfer reports.
//! - **Frames**: every call queues at most one frame (a request, a segment
//!   or an abort), so the transmit queue holds one, and a caller that
//!   drains it after every call, as the contract asks, never loses a frame.
//!   A caller that does not loses the older, unsent frame, counted by
//!   [`Client::frames_dropped`]; the newest is kept, and frames that are
//!   sent are always in the order they were made. Why not refuse the input
//!   instead: SDO is confirmed request/response, so the newest frame is the
//!   one that matches the client's state (a timeout's abort replaces the
//!   request it gave up on), whereas holding input back would let the
//!   obsolete frame go out later, answering a state the transfer has left.
//! - **Timer**: one, the response timeout, armed when a request is queued
//!   and stopped when the transfer ends.
//!
//! # Data without allocation
//!
//! An upload is delivered as it arrives: one [`ClientEvent::UploadData`] per
//! frame (at most 7 bytes, with its offset), then [`TransferEnd::Uploaded`]
//! with the total length. A download reads from the caller's data `D`
//! (anything `AsRef<[u8]>`: a slice, an array, a `Vec`), which the client
//! holds until the transfer ends. With the `alloc` feature,
//! [`UploadBuffer`](super::UploadBuffer) collects an upload into a `Vec`.
//!
//! # Behaviour (CiA 301 section 7.2.4, SDO, and the choices made here)
//!
//! - Values of 1..=4 bytes are downloaded expedited with the size indicated;
//!   empty and longer values segmented with the size indicated (an empty value
//!   is one empty last segment; without `sdo-client-segmented`, refused).
//! - Every transfer ends in exactly one terminal event: `Uploaded`,
//!   `Downloaded` or `Aborted`. Failures detected here send exactly one abort
//!   frame with the transfer's index and sub-index: timeout 05040000h, wrong
//!   or unexpected command 05040001h, toggle 05030000h, more data than
//!   indicated 06070012h, less 06070013h, response for another object
//!   06040043h. A received abort ends the transfer with the server's code
//!   (code 0 is reported as 08000000h) and nothing is sent back.
//! - An expedited upload without size indicated reports all 4 data bytes.
//! - Frames on other identifiers, remote frames and frames too short for
//!   their command are ignored.
//! - **Time**: the timeout restarts on every frame sent. A timestamp earlier
//!   than the last one never panics: the deadline is simply not reached yet.
//!   A timestamp far ahead expires the transfer (abort 05040000h).

use core::time::Duration;

use super::data::{ExpeditedData, InitiatePayload, SegmentData};
use super::end::TransferEnd;
use super::rules::block::MAX_BLOCK_SIZE;
#[cfg(feature = "sdo-block")]
use super::rules::block::{clamp_block_size, Receiver, Sender};
#[cfg(feature = "sdo-client-segmented")]
use super::rules::segmented::Segments;
use super::server::{DEFAULT_EVENT_CAPACITY, DEFAULT_TIMEOUT};
#[cfg(feature = "sdo-block")]
use super::wire::{BlockDataInitiate, BlockUploadInitiate, ClientBlockDownload, ClientBlockUpload};
use super::wire::{ClientCommand, SdoFrame, ServerCommand};
use crate::abort::AbortCode;
use crate::clock::{Timers, Timestamp};
use crate::cob_id::{NodeId, SDO_RX_BASE, SDO_TX_BASE};
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;
use crate::queue::{EventQueue, FrameSlot};

crate::clock::timer_kind! {
    /// The one timer.
    enum ClientTimer {
        /// The SDO timeout: the server's answer is due.
        Response,
    }
}

/// What the client reports: the value an upload reads, piece by piece,
/// then how the transfer ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ClientEvent {
    /// A piece of the value being uploaded, in order.
    UploadData {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Offset of `data` in the value.
        offset: usize,
        /// 1..=7 bytes.
        data: SegmentData,
    },
    /// The transfer ended: uploaded (`len`, the bytes delivered in
    /// `UploadData` events), downloaded (the server accepted `len` bytes)
    /// or aborted.
    Ended(TransferEnd),
}

impl From<TransferEnd> for ClientEvent {
    fn from(end: TransferEnd) -> Self {
        ClientEvent::Ended(end)
    }
}

impl ClientEvent {
    /// True for the events that end a transfer.
    #[must_use]
    pub const fn is_terminal(&self) -> bool {
        matches!(self, ClientEvent::Ended(_))
    }
}

/// Why a command was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ClientError {
    /// A transfer is already running.
    #[error("an SDO transfer is already in progress")]
    Busy,
    /// The value does not fit the 32-bit SDO size field.
    #[error("value of {len} bytes is too long for SDO")]
    TooLong {
        /// The length asked for.
        len: usize,
    },
    /// Block transfer is not built in (the crate's feature `sdo-block` is
    /// off): [`Client::start_block_upload`] and
    /// [`Client::start_block_download`] refuse to start, nothing is sent.
    #[error("SDO block transfer is not built in (feature sdo-block)")]
    BlockUnsupported,
    /// Segmented transfer is not built in (the crate's feature
    /// `sdo-client-segmented` is off): [`Client::start_download`] of a
    /// value that is not 1..=4 bytes (empty or longer: no expedited
    /// download carries it) refuses to start, nothing is sent.
    #[error("SDO download of {len} bytes needs segmented transfer, not built in (feature sdo-client-segmented)")]
    SegmentedUnsupported {
        /// The length asked for.
        len: usize,
    },
}

/// Identifiers and timeout of one SDO client channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClientConfig {
    /// Requests are sent on this identifier (default 0x600 + server node).
    pub request_id: CanId,
    /// Responses arrive on this identifier (default 0x580 + server node).
    pub response_id: CanId,
    /// How long to wait for each response (default 2000 ms).
    pub timeout: Duration,
    /// Block upload: segments per sub-block this client asks for, 1..=127
    /// (default 127; 0 counts as 1, above 127 as 127). CiA 301: the
    /// receiver of the data chooses the block size.
    pub block_size: u8,
    /// Block transfer: this client supports CRC (default true). CiA 301:
    /// the CRC is used only when both sides support it.
    pub crc: bool,
    /// Block upload: the protocol switch threshold sent in the initiate
    /// request (default 0, no switch). CiA 301: the server may answer a
    /// block upload of at most this many bytes with a normal upload.
    pub block_threshold: u8,
}

impl ClientConfig {
    /// The default channel to `server`: 0x600/0x580 + node, 2000 ms.
    #[must_use]
    pub const fn for_server(server: NodeId) -> Self {
        ClientConfig {
            request_id: CanId::Standard(SDO_RX_BASE + server.raw() as u16),
            response_id: CanId::Standard(SDO_TX_BASE + server.raw() as u16),
            timeout: DEFAULT_TIMEOUT,
            block_size: MAX_BLOCK_SIZE,
            crc: true,
            block_threshold: 0,
        }
    }
}

#[derive(Debug)]
enum State<D> {
    Idle,
    UploadInitiated {
        index: u16,
        sub: u8,
    },
    #[cfg(feature = "sdo-client-segmented")]
    Uploading {
        index: u16,
        sub: u8,
        rx: Segments,
    },
    DownloadInitiated {
        index: u16,
        sub: u8,
        data: D,
        /// Without `sdo-client-segmented` every download is expedited.
        #[cfg(feature = "sdo-client-segmented")]
        expedited: bool,
    },
    #[cfg(feature = "sdo-client-segmented")]
    Downloading {
        index: u16,
        sub: u8,
        data: D,
        /// Bytes sent so far (including the segment awaiting its ack).
        sent: usize,
        toggle: bool,
    },
    /// Block download: the initiate request is out.
    #[cfg(feature = "sdo-block")]
    BlockDownloadInitiated {
        index: u16,
        sub: u8,
        data: D,
    },
    /// Block download: sub-blocks are being sent (segments are made when
    /// polled) and acknowledged.
    #[cfg(feature = "sdo-block")]
    BlockDownloading {
        index: u16,
        sub: u8,
        data: D,
        tx: Sender,
    },
    /// Block download: the end frame is out.
    #[cfg(feature = "sdo-block")]
    BlockDownloadEnding {
        index: u16,
        sub: u8,
        len: usize,
    },
    /// Block upload: the initiate request is out.
    #[cfg(feature = "sdo-block")]
    BlockUploadInitiated {
        index: u16,
        sub: u8,
    },
    /// Block upload: receiving sub-blocks, then the end frame.
    #[cfg(feature = "sdo-block")]
    BlockUploading {
        index: u16,
        sub: u8,
        rx: Receiver,
    },
}

/// An SDO client for one server. `D` is the type of download data.
///
/// ```
/// use canopen_codec::machine::Machine;
/// use canopen_codec::sdo::{Client, ClientConfig, ClientEvent, TransferEnd};
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
///
/// let server = NodeId::new(2).unwrap();
/// let mut client = Client::new(ClientConfig::for_server(server));
/// client.start_download(Timestamp::ZERO, 0x1017, 0, [0xA0, 0x0F]).unwrap();
/// assert_eq!(client.poll_transmit().unwrap(),
///            CanFrame::standard(0x602, &[0x2B, 0x17, 0x10, 0, 0xA0, 0x0F, 0, 0]).unwrap());
/// let ack = CanFrame::standard(0x582, &[0x60, 0x17, 0x10, 0, 0, 0, 0, 0]).unwrap();
/// client.handle_frame(Timestamp::from_millis(3), &ack);
/// assert_eq!(client.poll_event(), Some(ClientEvent::Ended(TransferEnd::Downloaded { index: 0x1017, sub: 0, len: 2 })));
/// ```
///
/// `EVENTS` is the capacity of the event queue (default
/// [`DEFAULT_EVENT_CAPACITY`](super::DEFAULT_EVENT_CAPACITY);
/// [`Client::with_event_capacity`] makes one with another).
#[derive(Debug)]
pub struct Client<D = &'static [u8], const EVENTS: usize = DEFAULT_EVENT_CAPACITY> {
    config: ClientConfig,
    /// `config.timeout` in microseconds, computed once.
    timeout_us: u64,
    /// What `CanFrame::word` gives for a data frame on `config.response_id`
    /// (`u32::MAX`, matching no frame, when it is out of range).
    response_filter: u32,
    /// The identifier it sends on is valid (checked once, not per frame).
    sends: bool,
    state: State<D>,
    timers: Timers<ClientTimer, 1>,
    /// One frame: every call produces at most one (see the module docs).
    transmit: FrameSlot,
    events: EventQueue<ClientEvent, EVENTS>,
}

impl<D: AsRef<[u8]>> Client<D> {
    /// An idle client on `config`'s identifiers, with an event queue of
    /// [`DEFAULT_EVENT_CAPACITY`](super::DEFAULT_EVENT_CAPACITY).
    pub fn new(config: ClientConfig) -> Self {
        Self::with_event_capacity(config)
    }
}

impl<D: AsRef<[u8]>, const EVENTS: usize> Client<D, EVENTS> {
    /// An idle client on `config`'s identifiers, with an event queue of
    /// `EVENTS` (1 or more; [`EVENTS_PER_CALL`](super::EVENTS_PER_CALL) for
    /// a caller that reads every event after every call and command).
    ///
    /// ```
    /// use canopen_codec::sdo::{Client, ClientConfig, EVENTS_PER_CALL};
    /// use canopen_codec::NodeId;
    ///
    /// let config = ClientConfig::for_server(NodeId::new(2).unwrap());
    /// let client: Client<&[u8], EVENTS_PER_CALL> = Client::with_event_capacity(config);
    /// assert!(!client.is_busy());
    /// ```
    pub fn with_event_capacity(config: ClientConfig) -> Self {
        Client {
            config,
            timeout_us: crate::clock::micros_of(config.timeout),
            response_filter: crate::frame::data_frame_identity(config.response_id),
            sends: crate::frame::check_id(config.request_id).is_ok(),
            state: State::Idle,
            timers: Timers::new(),
            transmit: FrameSlot::new(),
            events: Self::no_events(),
        }
    }

    /// An empty event queue; the filler (never returned) as zero bytes:
    /// cleared with the rest of the state.
    const fn no_events() -> EventQueue<ClientEvent, EVENTS> {
        EventQueue::new(ClientEvent::UploadData {
            index: 0,
            sub: 0,
            offset: 0,
            data: SegmentData::EMPTY,
        })
    }

    /// Starts over on the same configuration: a running transfer ends
    /// silently (no abort frame, no event), and the queued frame, the
    /// events and the drop counters are cleared, as
    /// [`with_event_capacity`](Self::with_event_capacity) of
    /// [`config`](Self::config) would make the client, without building a
    /// second one (a node's NMT reset).
    ///
    /// ```
    /// use canopen_codec::machine::Machine;
    /// use canopen_codec::sdo::{Client, ClientConfig};
    /// use canopen_codec::{NodeId, Timestamp};
    ///
    /// let mut client: Client = Client::new(ClientConfig::for_server(NodeId::new(2).unwrap()));
    /// client.start_upload(Timestamp::ZERO, 0x1000, 0).unwrap();
    /// // Not drained: the timeout's abort replaces the request, then a
    /// // second request replaces the abort.
    /// client.handle_timeout(Timestamp::from_millis(5000));
    /// client.start_upload(Timestamp::from_millis(5000), 0x1018, 1).unwrap();
    /// assert_eq!(client.frames_dropped(), 2);
    /// client.reset();
    /// assert!(!client.is_busy());
    /// assert_eq!((client.poll_transmit(), client.poll_timeout()), (None, None));
    /// assert_eq!((client.poll_event(), client.frames_dropped()), (None, 0));
    /// ```
    pub fn reset(&mut self) {
        self.state = State::Idle;
        self.timers = Timers::new();
        self.transmit = FrameSlot::new();
        self.events = Self::no_events();
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &ClientConfig {
        &self.config
    }

    /// True while a transfer is in progress.
    #[must_use]
    pub const fn is_busy(&self) -> bool {
        !matches!(self.state, State::Idle)
    }

    /// The object of the running transfer.
    #[must_use]
    pub const fn current(&self) -> Option<(u16, u8)> {
        if self.is_busy() {
            Some(self.object())
        } else {
            None
        }
    }

    /// The object of the running transfer, (0, 0) when idle: the one match
    /// over the states.
    const fn object(&self) -> (u16, u8) {
        match self.state {
            State::Idle => (0, 0),
            State::UploadInitiated { index, sub } | State::DownloadInitiated { index, sub, .. } => {
                (index, sub)
            }
            #[cfg(feature = "sdo-client-segmented")]
            State::Uploading { index, sub, .. } | State::Downloading { index, sub, .. } => {
                (index, sub)
            }
            #[cfg(feature = "sdo-block")]
            State::BlockDownloadInitiated { index, sub, .. }
            | State::BlockDownloading { index, sub, .. }
            | State::BlockDownloadEnding { index, sub, .. }
            | State::BlockUploadInitiated { index, sub }
            | State::BlockUploading { index, sub, .. } => (index, sub),
        }
    }

    /// Starts reading `index`/`sub` from the server.
    pub fn start_upload(&mut self, now: Timestamp, index: u16, sub: u8) -> Result<(), ClientError> {
        self.check_idle()?;
        let command = ClientCommand::InitiateUpload { index, sub };
        self.open(now, command, State::UploadInitiated { index, sub })
    }

    /// Starts writing `data` to `index`/`sub` on the server.
    pub fn start_download(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
        data: D,
    ) -> Result<(), ClientError> {
        let size = self.download_size(&data)?;
        let bytes = data.as_ref();
        // CiA 301: 1..=4 bytes go expedited with the size indicated; an
        // empty value (the n field cannot say 0 bytes) and longer ones
        // segmented, with the size.
        let expedited = matches!(bytes.len(), 1..=4);
        let payload = match ExpeditedData::new(bytes) {
            Some(data) if expedited => InitiatePayload::Expedited {
                data,
                size_indicated: true,
            },
            #[cfg(feature = "sdo-client-segmented")]
            _ => InitiatePayload::Segmented { size: Some(size) },
            #[cfg(not(feature = "sdo-client-segmented"))]
            _ => {
                let _ = size;
                return Err(ClientError::SegmentedUnsupported { len: bytes.len() });
            }
        };
        let state = State::DownloadInitiated {
            index,
            sub,
            data,
            #[cfg(feature = "sdo-client-segmented")]
            expedited,
        };
        let command = ClientCommand::InitiateDownload {
            index,
            sub,
            payload,
        };
        self.open(now, command, state)
    }

    /// Starts reading `index`/`sub` from the server by block upload (CiA
    /// 301 section 7.2.4.3, SDO block upload), asking for sub-blocks of
    /// [`ClientConfig::block_size`] segments, with CRC if
    /// [`ClientConfig::crc`] and the protocol switch threshold
    /// [`ClientConfig::block_threshold`]. The value arrives as
    /// [`ClientEvent::UploadData`] pieces, as in a segmented upload, then
    /// [`TransferEnd::Uploaded`].
    ///
    /// Without the feature `sdo-block` it refuses with
    /// [`ClientError::BlockUnsupported`] and sends nothing (use
    /// [`Client::start_upload`]).
    ///
    /// ```
    /// use canopen_codec::sdo::{Client, ClientConfig, ClientError};
    /// use canopen_codec::{NodeId, Timestamp};
    ///
    /// let mut client: Client = Client::new(ClientConfig::for_server(NodeId::new(2).unwrap()));
    /// let started = client.start_block_upload(Timestamp::ZERO, 0x1008, 0);
    /// # #[cfg(not(feature = "sdo-block"))]
    /// assert_eq!(started, Err(ClientError::BlockUnsupported));
    /// # #[cfg(feature = "sdo-block")]
    /// assert_eq!(started, Ok(()));
    /// ```
    pub fn start_block_upload(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
    ) -> Result<(), ClientError> {
        #[cfg(feature = "sdo-block")]
        {
            self.check_idle()?;
            let command =
                ClientCommand::BlockUpload(ClientBlockUpload::Initiate(BlockUploadInitiate {
                    index,
                    sub,
                    crc: self.config.crc,
                    blksize: clamp_block_size(self.config.block_size),
                    pst: self.config.block_threshold,
                }));
            self.open(now, command, State::BlockUploadInitiated { index, sub })
        }
        #[cfg(not(feature = "sdo-block"))]
        {
            let _ = (now, index, sub);
            Err(ClientError::BlockUnsupported)
        }
    }

    /// Starts writing `data` to `index`/`sub` by block download (CiA 301
    /// section 7.2.4.3, SDO block download), with the size indicated and
    /// CRC if [`ClientConfig::crc`]; the server chooses the block size.
    /// Values of any length, 0 included, go by block.
    ///
    /// Without the feature `sdo-block` it refuses with
    /// [`ClientError::BlockUnsupported`], sends nothing and drops `data`
    /// (use [`Client::start_download`]).
    pub fn start_block_download(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
        data: D,
    ) -> Result<(), ClientError> {
        #[cfg(feature = "sdo-block")]
        {
            let size = self.download_size(&data)?;
            let command =
                ClientCommand::BlockDownload(ClientBlockDownload::Initiate(BlockDataInitiate {
                    index,
                    sub,
                    crc: self.config.crc,
                    size: Some(size),
                }));
            self.open(
                now,
                command,
                State::BlockDownloadInitiated { index, sub, data },
            )
        }
        #[cfg(not(feature = "sdo-block"))]
        {
            let _ = (now, index, sub, data);
            Err(ClientError::BlockUnsupported)
        }
    }

    /// Aborts the running transfer with `code`: sends the abort frame and
    /// reports [`TransferEnd::Aborted`]. Returns false (and does nothing)
    /// when idle.
    pub fn abort(&mut self, now: Timestamp, code: AbortCode) -> bool {
        let _ = now;
        if !self.is_busy() {
            return false;
        }
        self.abort_local(code);
        true
    }

    fn check_idle(&self) -> Result<(), ClientError> {
        if self.is_busy() {
            Err(ClientError::Busy)
        } else {
            Ok(())
        }
    }

    /// The size of a value to write, once the client is idle: a value
    /// longer than the 32-bit size CiA 301 can indicate is refused.
    fn download_size(&self, data: &D) -> Result<u32, ClientError> {
        self.check_idle()?;
        let len = data.as_ref().len();
        u32::try_from(len).map_err(|_| ClientError::TooLong { len })
    }

    /// Sends the command that opens a transfer and waits for the server's
    /// answer in `state`.
    fn open(
        &mut self,
        now: Timestamp,
        command: ClientCommand,
        state: State<D>,
    ) -> Result<(), ClientError> {
        self.send(command);
        self.wait(now, state);
        Ok(())
    }

    /// Waits in `state` for the server's next answer (the SDO timeout
    /// restarted).
    fn wait(&mut self, now: Timestamp, state: State<D>) {
        self.state = state;
        self.arm(now);
    }

    /// Reports a piece of the value an upload reads, at its offset.
    fn deliver(&mut self, index: u16, sub: u8, offset: usize, data: SegmentData) {
        self.emit(ClientEvent::UploadData {
            index,
            sub,
            offset,
            data,
        });
    }

    /// Queues `command` as a frame of 8 bytes on the request identifier
    /// (every byte the command leaves undefined zero).
    #[inline]
    fn send(&mut self, command: ClientCommand) {
        self.queue(command.to_bytes());
    }

    /// Queues the 8 data bytes of a frame on the request identifier.
    fn queue(&mut self, bytes: [u8; 8]) {
        if self.sends {
            super::queue_frame(&mut self.transmit, self.config.request_id, bytes);
        }
    }

    fn abort_local(&mut self, code: AbortCode) {
        let (index, sub) = self.object();
        self.abort_object(index, sub, code);
    }

    fn abort_object(&mut self, index: u16, sub: u8, code: AbortCode) {
        self.send(ClientCommand::Abort { index, sub, code });
        self.finish(TransferEnd::local_abort(index, sub, code));
    }
}

super::sdo_endpoint_machine!(
    Client<D: AsRef<[u8]>>,
    ClientEvent,
    ClientTimer::Response,
    response_filter,
    response
);

#[cfg(feature = "sdo-block")]
mod block;
mod response;
#[cfg(feature = "sdo-client-segmented")]
mod segmented;

#[cfg(all(test, not(feature = "sdo-client-segmented")))]
mod expedited_only_tests;

#[cfg(all(test, not(feature = "sdo-block")))]
mod without_block_tests;
