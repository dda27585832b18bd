//! The client's one response path (CiA 301 section 7.2.4.3, SDO
//! protocols): every data frame on the response identifier is read by the
//! wire layer ([`ServerCommand::parse`]) and matched against the running
//! transfer. Without the feature `sdo-client-segmented` the segmented
//! arms are not built: a segmented answer to an upload initiate is a
//! command this client does not take (05040001h, the same code a server
//! without `sdo-block` gives a block initiate; 06070010h would only fit a
//! response with a size above 4, and CiA 301 lets a server answer
//! segmented without a size or for a short value too, so one code for
//! every case). Without `sdo-block` no block state can be entered.
//!
//! One call leaves at most two events (an expedited upload's data, then
//! `Uploaded`): [`EVENTS_PER_CALL`](crate::sdo::EVENTS_PER_CALL).

use super::{AbortCode, Client, SdoFrame, SegmentData, ServerCommand, State, TransferEnd};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::sdo::data::InitiatePayload;
use crate::sdo::rules::block::is_abort;
use crate::sdo::AbortOrigin;

impl<D: AsRef<[u8]>, const EVENTS: usize> Client<D, EVENTS> {
    /// A data frame on the response identifier. Frames too short for
    /// their command (and any frame while idle) are ignored; an abort ends
    /// the transfer with the server's code; a segment of the running
    /// segmented transfer goes to its rules with the state updated in
    /// place; every other response is matched against the state taken out.
    /// Out of line: a device routing its frames stays one loop.
    #[inline(never)]
    pub(super) fn response(&mut self, now: Timestamp, frame: &CanFrame) {
        if !self.is_busy() {
            return;
        }
        #[cfg(feature = "sdo-block")]
        if self.block_segment(now, frame) {
            return;
        }
        let Ok(command) = SdoFrame::of_frame(frame).and_then(|f| ServerCommand::parse(&f)) else {
            return;
        };
        match command {
            // Byte 0 80h exactly (CiA 301 section 7.2.4.3, SDO abort
            // transfer); with its unused bits set it is no abort.
            ServerCommand::Abort { code, .. } if is_abort(frame.data()) => {
                return self.aborted_by_peer(code)
            }
            #[cfg(feature = "sdo-client-segmented")]
            ServerCommand::UploadSegment(segment)
                if matches!(self.state, State::Uploading { .. }) =>
            {
                return self.upload_segment(now, &segment);
            }
            #[cfg(feature = "sdo-client-segmented")]
            ServerCommand::DownloadSegment { toggle }
                if matches!(self.state, State::Downloading { .. }) =>
            {
                return self.download_ack(now, toggle);
            }
            _ => {}
        }
        let (index, sub) = self.object();
        match &self.state {
            State::Idle => {}
            State::UploadInitiated { .. } => self.on_upload_initiated(now, index, sub, command),
            // Any response but the segment (or acknowledgement) taken above.
            #[cfg(feature = "sdo-client-segmented")]
            State::Uploading { .. } | State::Downloading { .. } => {
                self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
            }
            State::DownloadInitiated { .. } => self.on_download_initiated(now, index, sub, command),
            #[cfg(feature = "sdo-block")]
            _ => {
                let state = core::mem::replace(&mut self.state, State::Idle);
                self.on_block_response(now, state, command, frame.data());
            }
        }
    }

    /// The server aborted: the transfer ends with its code (0 reported as
    /// 08000000h), nothing is sent back.
    fn aborted_by_peer(&mut self, code: AbortCode) {
        let (index, sub) = self.object();
        let code = match code {
            AbortCode::Other(0) => AbortCode::GeneralError,
            c => c,
        };
        self.finish(TransferEnd::Aborted {
            index,
            sub,
            code,
            origin: AbortOrigin::Peer,
        });
    }

    /// The answer to an upload initiate (or a block upload's protocol
    /// switch): expedited data ends the transfer; a segmented answer starts
    /// the segments (without `sdo-client-segmented`, 05040001h).
    pub(super) fn on_upload_initiated(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
        cmd: ServerCommand,
    ) {
        let ServerCommand::InitiateUpload {
            index: ri,
            sub: rs,
            payload,
        } = cmd
        else {
            return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
        };
        if (ri, rs) != (index, sub) {
            return self.abort_object(index, sub, AbortCode::GeneralParameterIncompatibility);
        }
        match payload {
            InitiatePayload::Expedited { data, .. } => {
                if !data.is_empty() {
                    let piece = SegmentData::new(data.as_slice()).unwrap_or_default();
                    self.deliver(index, sub, 0, piece);
                }
                self.finish(TransferEnd::Uploaded {
                    index,
                    sub,
                    len: data.len(),
                });
            }
            #[cfg(feature = "sdo-client-segmented")]
            InitiatePayload::Segmented { size } => self.segmented_upload(now, index, sub, size),
            #[cfg(not(feature = "sdo-client-segmented"))]
            InitiatePayload::Segmented { .. } => {
                let _ = now;
                self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
            }
        }
    }

    /// The answer to a download initiate: an expedited download is done; a
    /// segmented one sends its first segment.
    fn on_download_initiated(&mut self, now: Timestamp, index: u16, sub: u8, cmd: ServerCommand) {
        let ServerCommand::InitiateDownload { index: ri, sub: rs } = cmd else {
            return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
        };
        if (ri, rs) != (index, sub) {
            return self.abort_object(index, sub, AbortCode::GeneralParameterIncompatibility);
        }
        #[cfg(feature = "sdo-client-segmented")]
        if let State::DownloadInitiated {
            expedited: false, ..
        } = self.state
        {
            if let State::DownloadInitiated { data, .. } =
                core::mem::replace(&mut self.state, State::Idle)
            {
                self.send_segment(now, index, sub, data);
            }
            return;
        }
        #[cfg(not(feature = "sdo-client-segmented"))]
        let _ = now;
        let len = match &self.state {
            State::DownloadInitiated { data, .. } => data.as_ref().len(),
            _ => 0,
        };
        self.finish(TransferEnd::Downloaded { index, sub, len })
    }
}
