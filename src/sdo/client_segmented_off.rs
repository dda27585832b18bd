//! [`Client`] without segmented transfer (feature `sdo-client-segmented`
//! off): expedited uploads and downloads only (CiA 301 section 7.2.4.3,
//! SDO protocols: expedited transfer, at most 4 bytes in the initiate
//! frame). For a node whose client only reads and writes values of up to 4
//! bytes (the charger reads 1000h and the battery module's PDO COB-IDs).
//!
//! - [`Client::start_download`] of a value that is not 1..=4 bytes (empty
//!   or longer) refuses with [`ClientError::SegmentedUnsupported`]; nothing
//!   is sent and the client stays idle.
//! - A server that answers an upload initiate with a segmented
//!   (non-expedited) response, with or without the size, gets an abort
//!   frame with 05040001h ("client/server command specifier not valid or
//!   unknown") for the transfer's object, and the client reports one
//!   [`ClientEvent::Aborted`](super::ClientEvent::Aborted) with that code
//!   and origin local. **Choice**: from this client's side the response is
//!   a command it does not take, the same code the server without
//!   `sdo-block` gives a block initiate; 06070010h ("length of service
//!   parameter does not match") would only fit a response with a size
//!   above 4, and CiA 301 lets a server answer segmented without a size or
//!   for a short value too, so one code for every case.

use super::super::abort::AbortCode;
use super::super::wire::ServerCommand;
use super::{Client, ClientError};
use crate::frame::CanFrame;
use crate::time::Timestamp;
use crate::DecodeError;

impl<D: AsRef<[u8]>, const EVENTS: usize> Client<D, EVENTS> {
    /// A download of `size` bytes other than 1..=4 needs segmented
    /// transfer: refused.
    #[inline]
    pub(super) fn segmented_initiate(index: u16, sub: u8, size: u32) -> Result<u64, ClientError> {
        let _ = (index, sub);
        Err(ClientError::SegmentedUnsupported {
            len: usize::try_from(size).unwrap_or(usize::MAX),
        })
    }

    /// The server answered the upload initiate segmented: aborted with
    /// 05040001h (see the module docs).
    pub(super) fn segmented_upload(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
        size: Option<u32>,
    ) {
        let _ = (now, size);
        self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
    }

    /// A response for the general path: the commands this client takes
    /// decoded, the others only checked for their length (see
    /// `ServerCommand::of_frame_expedited`).
    #[inline(always)]
    pub(super) fn decode_response(frame: &CanFrame) -> Result<ServerCommand, DecodeError> {
        ServerCommand::of_frame_expedited(frame)
    }

    /// No segmented transfer runs: every frame takes the general path.
    #[inline]
    pub(super) fn segment_response(&mut self, now: Timestamp, frame: &CanFrame, b0: u8) -> bool {
        let _ = (now, frame, b0);
        false
    }
}

#[cfg(test)]
#[path = "client_segmented_off_tests.rs"]
mod tests;
