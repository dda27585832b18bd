//! Expedited and segmented download of [`Server`] (CiA 301 section
//! 7.2.4.3, SDO protocols: SDO download initiate and SDO download segment):
//! the initiate checked against the object and, expedited, written at
//! once; the segments checked by the segment rules and the object's size
//! rule and written from the frame, one per request.

use super::super::segmented::Segments;
use super::server_wire::Download;
use super::{
    AbortCode, Initiated, ObjectDictionary, ObjectInfo, Server, ServerEvent, SizeRule, State,
};
use crate::clock::Timestamp;

impl<D: ObjectDictionary, const EVENTS: usize> Server<D, EVENTS> {
    /// An initiate download of the object `info` describes: an expedited
    /// one written (the response and the `Downloaded` event), a segmented
    /// one started (the response; the state set). An error is the abort
    /// code to answer with (nothing changed, nothing left written).
    pub(super) fn initiate_download(
        &mut self,
        index: u16,
        sub: u8,
        info: ObjectInfo,
        payload: Download,
    ) -> Initiated {
        if !info.access.is_writable() {
            return Err(AbortCode::WriteOfReadOnlyObject);
        }
        // The length to check against the size rule (one check for both
        // forms): the expedited value's, or the indicated size.
        let len = match payload {
            // Size not indicated: "up to 4 bytes", the object decides.
            Download::Expedited {
                len: carried,
                size_indicated: false,
                ..
            } => match info.size {
                SizeRule::Fixed(n) if n <= carried => Some(n),
                // A fixed object longer than the frame can carry: the
                // length cannot match, and is not known to be short.
                SizeRule::Fixed(_) => return Err(AbortCode::DataTypeLengthMismatch),
                SizeRule::Variable { .. } => Some(carried),
            },
            Download::Expedited { len, .. } => Some(len),
            Download::Segmented { size } => size.map(|s| usize::try_from(s).unwrap_or(usize::MAX)),
        };
        if let Some(len) = len {
            info.check_download_len(len)?;
        }
        match (payload, len) {
            // Both answered with scs = 3 (byte 60h) and bytes 4..=7 zero.
            (Download::Expedited { data, .. }, Some(len)) => {
                let bytes = data.to_le_bytes();
                let bytes = bytes.get(..len).unwrap_or(&[]);
                let result = self
                    .od
                    .write(index, sub, 0, bytes)
                    .and_then(|()| self.od.finish_write(index, sub, len));
                if result.is_err() {
                    self.od.abort_write(index, sub);
                }
                result?;
                Ok((0x60, 0, Some(ServerEvent::Downloaded { index, sub, len })))
            }
            // Segmented (an expedited download always has its length).
            (_, size) => {
                self.state = State::Downloading {
                    index,
                    sub,
                    rx: Segments::new(size),
                    size: info.size,
                };
                Ok((0x60, 0, None))
            }
        }
    }

    /// A download segment, the frame's `bytes` with `len` data bytes (as
    /// `SdoRequest::check_download_segment` found): checked by the segment
    /// rules and the object's size rule, written straight from the frame,
    /// acknowledged. The receive cursor is updated in place (no copy of the
    /// state per segment, no `Segment` made of the frame); the
    /// acknowledgement is made as `SdoResponse::new` of
    /// `ServerCommand::DownloadSegment` encodes it. Out of line (see
    /// `upload_segment`).
    #[inline(never)]
    pub(super) fn download_segment(&mut self, now: Timestamp, bytes: [u8; 8], len: usize) {
        let State::Downloading {
            index,
            sub,
            rx,
            size,
        } = &mut self.state
        else {
            // Not reached: `handle_frame` calls it in this state only.
            return;
        };
        let (index, sub) = (*index, *sub);
        // The size rule's bound, and whether it is also the least length
        // (`ObjectInfo::check_download_len` in two halves: too long after
        // every segment, too short after the last).
        let (bound, exact) = match *size {
            SizeRule::Fixed(n) => (n, true),
            SizeRule::Variable { max } => (max, false),
        };
        let [b0, data @ ..] = bytes;
        let toggle = b0 & 0x10 != 0;
        let last = b0 & 0x01 != 0;
        let placed = match rx.on_parts(toggle, last, len) {
            Ok(placed) => placed,
            Err(code) => return self.abort_local(code),
        };
        let end = placed.total;
        if end > bound {
            return self.abort_local(AbortCode::DataTypeLengthTooHigh);
        }
        let data = data.get(..len).unwrap_or(&[]);
        if let Err(code) = self.od.write(index, sub, placed.offset, data) {
            return self.abort_local(code);
        }
        let ack = [0x20 | u8::from(toggle) << 4, 0, 0, 0, 0, 0, 0, 0];
        if !last {
            self.send_bytes(ack, 8);
            return self.arm(now);
        }
        if exact && end < bound {
            return self.abort_local(AbortCode::DataTypeLengthTooLow);
        }
        if let Err(code) = self.od.finish_write(index, sub, end) {
            return self.abort_local(code);
        }
        self.send_bytes(ack, 8);
        self.finish(ServerEvent::Downloaded {
            index,
            sub,
            len: end,
        });
    }
}
