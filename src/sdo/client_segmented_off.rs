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
//! - One response path: the client's own decoder of the responses an
//!   expedited client can get (`wire_expedited.rs`: initiate upload
//!   response expedited or segmented, initiate download response, abort,
//!   every other command only checked for its length), then one match of
//!   the response against the running transfer. One call leaves at most
//!   two events (an expedited upload's data, then `Uploaded`):
//!   [`EVENTS_PER_CALL`](super::super::EVENTS_PER_CALL) is the capacity
//!   for a caller that reads every event after every call (the tests prove
//!   the bound on every response).

use super::super::abort::AbortCode;
use super::super::data::SegmentData;
use super::super::server::AbortOrigin;
use super::{Client, ClientError, ClientEvent, State};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use wire::Response;

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

    /// A data frame on the response identifier, the one response path:
    /// decoded by the expedited decoder, then one match of the response
    /// against the running transfer. An abort ends the transfer with the
    /// server's code (0 as 08000000h); the initiate response the transfer
    /// waits for ends it (an expedited upload with its data first, then
    /// `Uploaded`; a download with `Downloaded`), unless it is for another
    /// object (06040043h); everything else, a segmented upload response
    /// among it, is a command that does not fit (05040001h, see the
    /// module docs). At most two events: the bound of
    /// [`EVENTS_PER_CALL`](super::super::EVENTS_PER_CALL).
    #[inline]
    pub(super) fn response(&mut self, now: Timestamp, frame: &CanFrame) {
        let _ = now;
        let (index, sub, upload, written) = match &self.state {
            State::Idle => return,
            State::UploadInitiated { index, sub } => (*index, *sub, true, 0),
            State::DownloadInitiated {
                index, sub, data, ..
            } => (*index, *sub, false, data.as_ref().len()),
        };
        let Some(response) = wire::response(frame) else {
            return;
        };
        let mux = u32::from(index) | u32::from(sub) << 16;
        let code = match response {
            Response::Abort(code) => {
                return self.finish(ClientEvent::Aborted {
                    index,
                    sub,
                    code,
                    origin: AbortOrigin::Peer,
                });
            }
            Response::Expedited { mux: m, .. } | Response::Segmented { mux: m }
                if upload && m != mux =>
            {
                AbortCode::GeneralParameterIncompatibility
            }
            Response::Downloaded { mux: m } if !upload && m != mux => {
                AbortCode::GeneralParameterIncompatibility
            }
            Response::Expedited { data, len, .. } if upload => {
                if len != 0 {
                    self.emit(ClientEvent::UploadData {
                        index,
                        sub,
                        offset: 0,
                        data: SegmentData::from_le_word(u64::from(data), len),
                    });
                }
                return self.finish(ClientEvent::Uploaded { index, sub, len });
            }
            Response::Downloaded { .. } if !upload => {
                return self.finish(ClientEvent::Downloaded {
                    index,
                    sub,
                    len: written,
                });
            }
            // A segmented upload response, a response of the other
            // initiate, a segment or a block command.
            _ => AbortCode::InvalidCommandSpecifier,
        };
        self.abort_object(index, sub, code);
    }
}

#[path = "wire_expedited.rs"]
mod wire;

#[cfg(test)]
#[path = "client_segmented_off_tests.rs"]
mod tests;
