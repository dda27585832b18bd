//! Segmented upload and download of [`Client`] (CiA 301 section 7.2.4.3,
//! SDO protocols: segmented SDO download and upload), feature
//! `sdo-client-segmented`: the segments after a non-expedited initiate,
//! their toggle and size checks, the per-segment straight path of
//! [`Machine::handle_frame`](crate::machine::Machine::handle_frame), and
//! the general response path (every response by the general decoder
//! `ServerCommand::of_frame`, the block responses included).

use super::super::abort::AbortCode;
use super::super::data::{InitiatePayload, Segment, SegmentData};
use super::super::segmented::{check_toggle, Segments};
use super::super::server::AbortOrigin;
use super::super::wire::{SdoResponse, ServerCommand};
use super::super::words;
use super::{Client, ClientEvent, State};
use crate::clock::Timestamp;
use crate::frame::CanFrame;

impl<D: AsRef<[u8]>, const EVENTS: usize> Client<D, EVENTS> {
    /// The initiate request of a download of `size` bytes other than 1..=4
    /// (segmented, with the size indicated; an empty value is one empty
    /// last segment).
    #[inline]
    pub(super) fn segmented_initiate(
        index: u16,
        sub: u8,
        size: u32,
    ) -> Result<u64, super::ClientError> {
        Ok(words::segmented(1, index, sub, size))
    }

    /// The server answered the upload initiate with the size (or without
    /// it): the first upload segment request (ccs = 3).
    fn segmented_upload(&mut self, now: Timestamp, index: u16, sub: u8, size: Option<u32>) {
        let rx = Segments::new(size.map(|s| usize::try_from(s).unwrap_or(usize::MAX)));
        self.send(0x60 | u64::from(rx.toggle()) << 4);
        self.state = State::Uploading { index, sub, rx };
        self.arm(now);
    }

    /// A data frame on the response identifier: the segment (or
    /// acknowledgement) of a running segmented transfer first, by its own
    /// straight path (the same decode, rules and answer as the general
    /// path gives it), every other response by the general path.
    #[inline(always)]
    pub(super) fn response(&mut self, now: Timestamp, frame: &CanFrame) {
        let [b0, ..] = frame.padded_data();
        if !self.segment_response(now, frame, b0) {
            self.handle_response(now, frame);
        }
    }

    /// The segment (or acknowledgement) of a running segmented transfer,
    /// by its own straight path: the same decode, rules and answer as the
    /// general path gives it. False for every other frame.
    #[inline]
    fn segment_response(&mut self, now: Timestamp, frame: &CanFrame, b0: u8) -> bool {
        match (&self.state, b0 >> 5) {
            (State::Uploading { .. }, 0) => {
                if let Ok(len) = SdoResponse::check_upload_segment(frame) {
                    self.upload_segment(now, &super::super::wire::segment_of_frame(frame, len));
                }
                true
            }
            (State::Downloading { .. }, 1) => {
                if frame.dlc() != 0 {
                    self.download_ack(now, b0 & 0x10 != 0);
                }
                true
            }
            _ => false,
        }
    }

    /// An upload segment (scs = 0) while uploading: checked by the segment
    /// rules, delivered, and the next one requested. The receive cursor is
    /// updated in place (no copy of the state per segment); the request is
    /// made as `SdoRequest::new` of `ClientCommand::UploadSegment` encodes it.
    fn upload_segment(&mut self, now: Timestamp, segment: &Segment) {
        let State::Uploading { index, sub, rx } = &mut self.state else {
            return;
        };
        let (index, sub) = (*index, *sub);
        let placed = match rx.on_segment(segment) {
            Ok(placed) => placed,
            Err(code) => return self.abort_object(index, sub, code),
        };
        let toggle = rx.toggle();
        if !segment.data.is_empty() {
            self.emit(ClientEvent::UploadData {
                index,
                sub,
                offset: placed.offset,
                data: segment.data,
            });
        }
        if segment.last {
            return self.finish(ClientEvent::Uploaded {
                index,
                sub,
                len: placed.total,
            });
        }
        self.send_bytes([0x60 | u8::from(toggle) << 4, 0, 0, 0, 0, 0, 0, 0], 8);
        self.arm(now);
    }

    /// The first download segment, after the initiate was confirmed.
    fn send_segment(&mut self, now: Timestamp, index: u16, sub: u8, data: D) {
        let (bytes, sent) = segment_frame(data.as_ref(), 0, false);
        self.send_bytes(bytes, 8);
        self.state = State::Downloading {
            index,
            sub,
            data,
            sent,
            toggle: false,
        };
        self.arm(now);
    }

    /// A download segment acknowledgement (scs = 1, toggle `t`) while
    /// downloading: the toggle checked, then the next segment (made as
    /// `SdoRequest::new` of `ClientCommand::DownloadSegment` encodes it) or the end.
    /// The cursor is updated in place (no copy of the state per segment).
    fn download_ack(&mut self, now: Timestamp, t: bool) {
        let State::Downloading {
            index,
            sub,
            data,
            sent,
            toggle,
        } = &mut self.state
        else {
            return;
        };
        let (index, sub) = (*index, *sub);
        if let Err(code) = check_toggle(t, *toggle) {
            return self.abort_object(index, sub, code);
        }
        let value = data.as_ref();
        let len = value.len();
        if *sent >= len {
            return self.finish(ClientEvent::Downloaded { index, sub, len });
        }
        *toggle = !*toggle;
        let (bytes, next) = segment_frame(value, *sent, *toggle);
        *sent = next;
        self.send_bytes(bytes, 8);
        self.arm(now);
    }

    /// The server aborted: the transfer ends with its code (0 reported as
    /// 08000000h), nothing is sent back.
    fn aborted_by_peer(&mut self, code: AbortCode) {
        let (index, sub) = self.object();
        let code = match code {
            AbortCode::Other(0) => AbortCode::GeneralError,
            c => c,
        };
        self.finish(ClientEvent::Aborted {
            index,
            sub,
            code,
            origin: AbortOrigin::Peer,
        });
    }

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
                    self.emit(ClientEvent::UploadData {
                        index,
                        sub,
                        offset: 0,
                        data: SegmentData::new(data.as_slice()).unwrap_or_default(),
                    });
                }
                self.finish(ClientEvent::Uploaded {
                    index,
                    sub,
                    len: data.len(),
                });
            }
            InitiatePayload::Segmented { size } => self.segmented_upload(now, index, sub, size),
        }
    }

    fn on_download_initiated(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
        data: D,
        expedited: bool,
        cmd: ServerCommand,
    ) {
        let ServerCommand::InitiateDownload { index: ri, sub: rs } = cmd else {
            return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
        };
        if (ri, rs) != (index, sub) {
            return self.abort_object(index, sub, AbortCode::GeneralParameterIncompatibility);
        }
        if !expedited {
            return self.send_segment(now, index, sub, data);
        }
        let len = data.as_ref().len();
        self.finish(ClientEvent::Downloaded { index, sub, len })
    }

    /// Every response but the segment (or acknowledgement) of a running
    /// segmented transfer (out of line: the per-segment path stays small).
    #[inline(never)]
    fn handle_response(&mut self, now: Timestamp, frame: &CanFrame) {
        if !self.is_busy() {
            return;
        }
        if self.block_segment(now, frame.data()) {
            return;
        }
        // The general decoder alone: the segment path of `decode_frame` is
        // `handle_frame`'s own.
        let Ok(command) = ServerCommand::of_frame(frame) else {
            return;
        };
        if let ServerCommand::Abort { code, .. } = command {
            return self.aborted_by_peer(code);
        }
        match core::mem::replace(&mut self.state, State::Idle) {
            State::Idle => {}
            State::UploadInitiated { index, sub } => {
                self.on_upload_initiated(now, index, sub, command);
            }
            // The segment itself took the path above.
            State::Uploading { index, sub, .. } | State::Downloading { index, sub, .. } => {
                self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
            }
            State::DownloadInitiated {
                index,
                sub,
                data,
                expedited,
            } => self.on_download_initiated(now, index, sub, data, expedited, command),
            #[cfg(feature = "sdo-block")]
            state => self.on_block_response(now, state, command, frame.data()),
        }
    }
}

/// The download segment frame of `value` from `from` with toggle `toggle`
/// (as [`SdoRequest::encode`](super::super::SdoRequest::encode) of
/// `ClientCommand::DownloadSegment` makes it: DLC 8, unused bytes zero) and
/// the offset after it.
#[inline]
fn segment_frame(value: &[u8], from: usize, toggle: bool) -> ([u8; 8], usize) {
    let rest = value.get(from..).unwrap_or(&[]);
    // A full segment (every one but the last) as one word, built in
    // registers from two overlapping loads: no byte-wise copy for the
    // frame to be read back from.
    let (data, n) = match rest {
        [a, b, c, d, e, f, g, ..] => {
            let lo = u32::from_le_bytes([*a, *b, *c, *d]);
            let hi = u32::from_le_bytes([*d, *e, *f, *g]);
            (u64::from(lo) | u64::from(hi) << 24, 7)
        }
        short => {
            let mut word = [0u8; 8];
            crate::bytes::copy_payload(&mut word, short);
            (u64::from_le_bytes(word), short.len())
        }
    };
    let sent = from.saturating_add(n);
    // n is at most 7: the 3-bit count of unused bytes is 7 - n.
    let unused = 7u8.saturating_sub(n as u8);
    let b0 = u8::from(toggle) << 4 | unused << 1 | u8::from(sent >= value.len());
    ((data << 8 | u64::from(b0)).to_le_bytes(), sent)
}
