//! Expedited and segmented download of [`Server`] (CiA 301 section
//! 7.2.4.3, SDO protocols: SDO download initiate and SDO download segment):
//! the initiate checked against the object and, expedited, written at
//! once; the segments checked by the segment rules and the object's size
//! rule and written from the frame, one per request.

use super::{
    AbortCode, InitiatePayload, Initiated, ObjectDictionary, ObjectInfo, Server, ServerCommand,
    ServerEvent, SizeRule, State,
};
use crate::clock::Timestamp;
use crate::sdo::data::Segment;
use crate::sdo::rules::segmented::Segments;

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
        payload: InitiatePayload,
    ) -> Initiated {
        if !info.access.is_writable() {
            return Err(AbortCode::WriteOfReadOnlyObject);
        }
        // The length to check against the size rule (one check for both
        // forms): the expedited value's, or the indicated size.
        let len = match payload {
            // Size not indicated: "up to 4 bytes", the object decides.
            InitiatePayload::Expedited {
                data,
                size_indicated: false,
            } => match info.size {
                SizeRule::Fixed(n) if n <= data.len() => Some(n),
                // A fixed object longer than the frame can carry: the
                // length cannot match, and is not known to be short.
                SizeRule::Fixed(_) => return Err(AbortCode::DataTypeLengthMismatch),
                SizeRule::Variable { .. } => Some(data.len()),
            },
            InitiatePayload::Expedited { data, .. } => Some(data.len()),
            InitiatePayload::Segmented { size } => {
                size.map(|s| usize::try_from(s).unwrap_or(usize::MAX))
            }
        };
        if let Some(len) = len {
            info.check_download_len(len)?;
        }
        // Both forms are answered with the initiate download response.
        let response = ServerCommand::InitiateDownload { index, sub };
        match (payload, len) {
            (InitiatePayload::Expedited { data, .. }, Some(len)) => {
                let bytes = data.as_slice().get(..len).unwrap_or(&[]);
                let result = self
                    .od
                    .write(index, sub, 0, bytes)
                    .and_then(|()| self.od.finish_write(index, sub, len));
                if result.is_err() {
                    self.od.abort_write(index, sub);
                }
                result?;
                Ok((response, Some(ServerEvent::Downloaded { index, sub, len })))
            }
            // Segmented (an expedited download always has its length).
            (_, size) => {
                self.state = State::Downloading {
                    index,
                    sub,
                    rx: Segments::new(size),
                    size: info.size,
                };
                Ok((response, None))
            }
        }
    }

    /// A download segment: checked by the segment rules and the object's
    /// size rule, written to the dictionary, acknowledged. The receive
    /// cursor is updated in place (no copy of the state per segment).
    pub(super) fn download_segment(&mut self, now: Timestamp, segment: &Segment) {
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
        let Segment { toggle, last, data } = segment;
        let (toggle, last) = (*toggle, *last);
        let placed = match rx.on_segment(segment) {
            Ok(placed) => placed,
            Err(code) => return self.abort_local(code),
        };
        let end = placed.total;
        if end > bound {
            return self.abort_local(AbortCode::DataTypeLengthTooHigh);
        }
        if let Err(code) = self.od.write(index, sub, placed.offset, data.as_slice()) {
            return self.abort_local(code);
        }
        let ack = ServerCommand::DownloadSegment { toggle };
        if !last {
            self.send(ack);
            return self.arm(now);
        }
        if exact && end < bound {
            return self.abort_local(AbortCode::DataTypeLengthTooLow);
        }
        if let Err(code) = self.od.finish_write(index, sub, end) {
            return self.abort_local(code);
        }
        self.send(ack);
        self.finish(ServerEvent::Downloaded {
            index,
            sub,
            len: end,
        });
    }
}
