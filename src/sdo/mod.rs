//! Service data objects (SDO), CiA 301: abort codes and the frame codec.
//!
//! # Where to look
//!
//! - `wire`: the one SDO wire layer, the checked view [`SdoFrame`] and the
//!   typed commands [`ClientCommand`] / [`ServerCommand`] (and their block
//!   families) with `parse` and `emit`; [`needed`], the one length rule.
//!   Everything below reads and writes frames through it.
//! - `rules`: the segment rules (toggle, indicated size) and the block
//!   rules (sub-blocks, sequence numbers, CRC), shared by the client, the
//!   server and the observer.
//! - `client`, `server`, `observer`: the state machines.
//! - [`AbortCode`], [`crc16`], the data carriers and, with `alloc`,
//!   `UploadBuffer`.
//!
//! [`Client`] and [`Server`] are the sans-IO state machines for expedited,
//! segmented and block transfers; both implement the state-machine contract
//! of [`crate::machine`].
//!
//! The client's segmented transfers need the feature
//! `sdo-client-segmented` (default on; without it the client does
//! expedited transfers only, see [`Client`]'s module docs on
//! [`ClientError::SegmentedUnsupported`]); the server always has them.
//!
//! # Block transfer (CiA 301 section 7.2.4.3, SDO protocols)
//!
//! With the crate's feature `sdo-block` (default on),
//! [`Client::start_block_download`] and [`Client::start_block_upload`] move a
//! value in sub-blocks of 1..=127 segments of 7 bytes, numbered from 1; the
//! receiver of the data chooses the block size ([`ClientConfig::block_size`]
//! for uploads, [`ServerConfig::block_size`] for downloads) and, after the
//! segment with the block's last number or the last flag, acknowledges the
//! last sequence number it received in order; the sender goes on from the
//! segment after it. The end frame carries the unused bytes of the last
//! segment and the CRC ([`crc16`]: CRC-16/CCITT, polynomial 1021h, initial
//! value 0, over all data bytes), used only when both sides announced CRC
//! support. The server answers a block upload of at most the client's
//! protocol switch threshold bytes with a normal upload. Without the
//! feature the server refuses a block initiate (05040001h) and the client
//! refuses to start one ([`ClientError::BlockUnsupported`]); the
//! [`Observer`] follows block transfers either way.
//!
//! **One frame per poll, nothing buffered**: a block sender makes each
//! segment when [`Machine::poll_transmit`](crate::machine::Machine::poll_transmit)
//! is called, from the data at the segment's offset (the server reads its
//! dictionary there), so a whole sub-block comes out of one drain of the
//! transmit queue while the queue itself holds one frame. A block receiver
//! passes every in-order segment on at once (the client as
//! [`ClientEvent::UploadData`], the server as a dictionary write) and holds
//! only the segment with the last flag until the end frame says how many of
//! its bytes are data.
//!
//! **Aborts and the choices made where CiA 301 leaves room**:
//!
//! - Block size 0 or above 127 in an initiate or an acknowledgement:
//!   05040002h. The block size of the acknowledgement that confirms the last
//!   segment is not checked (no sub-block follows).
//! - Sequence number 0 (other than the abort frame 80h) or above the block
//!   size: 05040003h. An acknowledgement with an `ackseq` above the number
//!   of segments sent in the sub-block: 05040003h (the receiver claims
//!   segments that were never sent). `ackseq` 0 (nothing received) is
//!   legal: the sender resends the whole sub-block, as often as asked; a
//!   receiver that stops answering is ended by the timeout.
//! - Out-of-order segments are ignored, except that one carrying the
//!   block's last number or the last flag makes the receiver acknowledge
//!   the last in-order one (the segment after it is resent). A segment
//!   without the last flag shorter than 8 bytes is ignored (its data is not
//!   all there). A frame byte-identical to the one that completed the
//!   previous sub-block (or the initiate frame that opened the transfer),
//!   before anything newer arrived, is a duplicate and ignored.
//! - While a sub-block is being received every frame but an abort (byte 0
//!   80h) is a segment; a new initiate is only recognised between
//!   sub-blocks and after the last one.
//! - End frame: CRC mismatch 05040004h; more unused bytes claimed than the
//!   last segment lets be data (it carried fewer than 7 - n bytes) or an end
//!   frame before the last segment: 05040001h; a total above / below the
//!   indicated size 06070012h / 06070013h, as for segmented transfers.
//! - A command that does not fit the phase (a start while idle, an ack
//!   before the start, a segmented response to a block download initiate):
//!   05040001h. A response for another object: 06040043h. A normal upload
//!   answer to a block upload initiate is followed as the protocol switch
//!   even when the value is above the threshold offered, or none was
//!   (lenient: python-canopen's server answers every block upload so, and
//!   the value arrives intact).
//! - Timeout 05040000h; the timer restarts on every frame received and on
//!   every sub-block begun.
//! - An empty value is one segment with the last flag and 7 unused bytes.
//!
//! **Repeated frames**: CiA 301 numbers the segments of a sub-block but not
//! the sub-blocks, so a repeated acknowledgement cannot be told from the
//! next one; a sender that takes it runs a sub-block ahead of the receiver
//! and a later loss makes it resend the wrong segments. Only the CRC
//! catches that (05040004h): leave [`ClientConfig::crc`] and
//! [`ServerConfig::crc`] on where frames can repeat. Immediate repeats of
//! the frame that opened the transfer or closed a sub-block are recognised
//! and ignored (see above).

mod client;
#[cfg(feature = "alloc")]
mod collect;
pub(crate) mod crc;
mod data;
mod end;
mod observer;
mod program_download;
mod rules;
mod server;
pub(crate) mod wire;

pub use crate::abort::{AbortCode, ALL_ABORT_CODES};
pub use client::{Client, ClientConfig, ClientError, ClientEvent};
#[cfg(feature = "alloc")]
pub use collect::{Collected, UploadBuffer};
pub use crc::{crc16, crc16_update};
pub use data::{ExpeditedData, InitiatePayload, InlineData, Segment, SegmentData};
pub use end::{AbortOrigin, TransferEnd};
pub use observer::{
    BreakReason, ChannelError, Direction, Observed, Observer, ObserverConfig, ObserverEvent,
    SdoChannel, Transfer, TransferKind, OBSERVER_EVENT_CAPACITY, OBSERVER_EXTRA_CHANNELS,
    OBSERVER_SUB_BLOCK_BUFFERS, SUB_BLOCK_BYTES,
};
pub use program_download::{
    ProgramDownload, ProgramDownloadConfig, ProgramDownloadError, ProgramDownloadEvent, ProgramStep,
};
pub use server::{
    Server, ServerConfig, ServerEvent, DEFAULT_EVENT_CAPACITY, DEFAULT_TIMEOUT, EVENTS_PER_CALL,
};
pub use wire::{
    abort_code_of, needed, BlockDataCommand, BlockDataInitiate, BlockDownloadAccept, BlockSegment,
    BlockUploadInitiate, ClientBlockDownload, ClientBlockUpload, ClientCommand, SdoFrame,
    SdoRequest, SdoResponse, ServerBlockDownload, ServerBlockUpload, ServerCommand, Side,
};

/// Queues an SDO frame of 8 data bytes on `id` (checked when the machine
/// was configured) in a machine's one-frame transmit queue: CiA 301 SDO
/// frames are always sent with all 8 bytes. At most one frame per call: a
/// drained queue always has room. One copy for the client and the server.
#[inline(never)]
fn queue_frame(transmit: &mut crate::queue::FrameSlot, id: crate::frame::CanId, bytes: [u8; 8]) {
    transmit.push(crate::frame::CanFrame::from_parts(id, bytes, 8));
}

/// The [`Machine`](crate::machine::Machine) of an SDO endpoint, the client
/// or the server: frames on its one receive identifier (one compare against
/// `$filter`, the data-frame identity of that identifier) go to `$receive`;
/// the one timer `$timer` running out aborts the transfer with 05040000h
/// (SDO protocol timed out, CiA 301 section 7.2.4.3.4); the one-frame queue
/// comes first, then, with block transfer, the next segment of the running
/// sub-block, made when the caller asks for it. Its events are queued and a
/// transfer is timed and finished the same way for both.
macro_rules! sdo_endpoint_machine {
    ($endpoint:ident<$d:ident: $bound:path>, $event:ty, $timer:expr, $filter:ident, $receive:ident) => {
        impl<$d: $bound, const EVENTS: usize> Machine for $endpoint<$d, EVENTS> {
            type Event = $event;

            /// Tells the endpoint time has passed; expires a stalled
            /// transfer with abort 05040000h.
            fn handle_timeout(&mut self, now: Timestamp) {
                if self.timers.expire($timer, now) {
                    self.abort_local(AbortCode::SdoProtocolTimedOut);
                }
            }

            /// Feeds a received frame. Frames on other identifiers, remote
            /// frames and frames too short for their command are ignored.
            fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
                if frame.identity() != self.$filter {
                    return;
                }
                self.$receive(now, frame);
            }

            /// The queued frame, else the next segment of the running
            /// block transfer's sub-block, made now.
            fn poll_transmit(&mut self) -> Option<CanFrame> {
                let queued = self.transmit.pop();
                #[cfg(feature = "sdo-block")]
                let queued = queued.or_else(|| self.next_block_segment());
                queued
            }

            /// Frames of the one-frame queue dropped unsent.
            fn frames_dropped(&self) -> u64 {
                self.transmit.dropped()
            }

            // The deadline of the running transfer (`None` when idle).
            crate::machine::queued_outputs!(timers: timers, @events events);
        }

        impl<$d: $bound, const EVENTS: usize> $endpoint<$d, EVENTS> {
            /// Queues an event (when the queue is full the oldest is
            /// dropped and counted).
            fn emit(&mut self, event: impl Into<$event>) {
                self.events.push(event.into());
            }

            /// Restarts the SDO timeout: the peer's next frame is due
            /// within the configured timeout of `now` (CiA 301: the timer
            /// restarts on every frame of the transfer).
            fn arm(&mut self, now: Timestamp) {
                self.timers
                    .set($timer, Some(now.add_micros(self.timeout_us)));
            }

            /// Ends the running transfer as `end` says: idle, no deadline,
            /// its one terminal event.
            fn finish(&mut self, end: crate::sdo::TransferEnd) {
                self.state = State::Idle;
                self.timers.set($timer, None);
                self.emit(end);
            }
        }
    };
}
use sdo_endpoint_machine;

/// The [`Machine`](crate::machine::Machine) of a master machine that runs
/// a sequence of SDO transfers on its own [`Client`], in the field
/// `client` (the PDO reconfiguration of CiA 301 section 7.5.2.35, the
/// program download of CiA 302-3): received frames and timeouts go to the
/// client, then its events to the machine's `drain(now)`, which moves the
/// sequence on; the frames sent are the client's; the machine's own
/// events are in the queue `$events`. A machine with a deadline of its
/// own keeps it in a timer table (`own $timers: $timer => $on`): `$on(now)`
/// runs when it expires, and the deadline is the earlier of it and the
/// client's.
macro_rules! sdo_client_sequence_machine {
    (impl $([$($generics:tt)*])? Machine for $machine:ty, $event:ty, $events:ident $(, own $timers:ident: $timer:expr => $on:ident)?) => {
        impl $(<$($generics)*>)? $crate::machine::Machine for $machine {
            type Event = $event;

            /// Feeds a received frame (the server's SDO responses).
            fn handle_frame(
                &mut self,
                now: $crate::clock::Timestamp,
                frame: &$crate::frame::CanFrame,
            ) {
                self.client.handle_frame(now, frame);
                self.drain(now);
            }

            /// The SDO timeout of the running transfer, then the
            /// machine's own deadline.
            fn handle_timeout(&mut self, now: $crate::clock::Timestamp) {
                self.client.handle_timeout(now);
                self.drain(now);
                $(if self.$timers.expire($timer, now) {
                    self.$on(now);
                })?
            }

            /// The client's frames.
            fn poll_transmit(&mut self) -> Option<$crate::frame::CanFrame> {
                self.client.poll_transmit()
            }

            /// The earlier of the client's deadline and the machine's own.
            fn poll_timeout(&self) -> Option<$crate::clock::Timestamp> {
                $crate::clock::earliest([
                    self.client.poll_timeout(),
                    $(self.$timers.next(),)?
                ])
            }

            fn frames_dropped(&self) -> u64 {
                self.client.frames_dropped()
            }

            $crate::machine::queued_outputs!(@events $events);
        }
    };
}
pub(crate) use sdo_client_sequence_machine;

#[cfg(test)]
mod capacity_tests;
#[cfg(test)]
mod machine_tests;
