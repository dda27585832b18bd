//! Expedited and segmented upload of [`Server`] (CiA 301 section 7.2.4.3,
//! SDO protocols: SDO upload initiate and SDO upload segment): the initiate
//! answered from the dictionary and the segments read from it at the
//! transfer's offset, one per request.

use super::{
    AbortCode, InitiatePayload, Initiated, ObjectDictionary, ObjectInfo, Server, ServerCommand,
    ServerEvent, State,
};
use crate::clock::Timestamp;
use crate::sdo::data::{ExpeditedData, Segment, SegmentData};
use crate::sdo::rules::segmented::check_toggle;

impl<D: ObjectDictionary, const EVENTS: usize> Server<D, EVENTS> {
    /// Reads up to `buf.len()` bytes at `offset`, looping over short reads
    /// (nothing is read into an empty `buf`).
    #[inline]
    pub(super) fn read_full(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        if buf.is_empty() {
            return Ok(0);
        }
        let mut got = self.od.read(index, sub, offset, buf)?.min(buf.len());
        // A short read: ask for the rest until the dictionary has no more.
        while got < buf.len() {
            let Some(rest) = buf.get_mut(got..) else {
                break;
            };
            let n = self
                .od
                .read(index, sub, offset.saturating_add(got), rest)?
                .min(rest.len());
            if n == 0 {
                break;
            }
            got += n;
        }
        Ok(got)
    }

    /// An initiate upload of the object `info` describes: 1..=4 bytes
    /// answered expedited (the response and the `Uploaded` event), any
    /// other length started segmented (the response; the state set). An
    /// error is the abort code to answer with.
    pub(super) fn initiate_upload(&mut self, index: u16, sub: u8, info: ObjectInfo) -> Initiated {
        if !info.access.is_readable() {
            return Err(AbortCode::ReadOfWriteOnlyObject);
        }
        if (1..=4).contains(&info.len) {
            let mut buf = [0u8; 4];
            let want = buf.get_mut(..info.len).unwrap_or(&mut []);
            let n = self.read_full(index, sub, 0, want)?;
            if n == 0 {
                return Err(AbortCode::NoDataAvailable);
            }
            let data = ExpeditedData::new(buf.get(..n).unwrap_or(&[])).unwrap_or_default();
            let response = ServerCommand::InitiateUpload {
                index,
                sub,
                payload: InitiatePayload::Expedited {
                    data,
                    size_indicated: true,
                },
            };
            return Ok((response, Some(ServerEvent::Uploaded { index, sub, len: n })));
        }
        let size = u32::try_from(info.len).map_err(|_| AbortCode::OutOfMemory)?;
        self.state = State::Uploading {
            index,
            sub,
            offset: 0,
            len: info.len,
            toggle: false,
        };
        let response = ServerCommand::InitiateUpload {
            index,
            sub,
            payload: InitiatePayload::Segmented { size: Some(size) },
        };
        Ok((response, None))
    }

    /// An upload segment request (ccs = 3, toggle `toggle`): the next
    /// segment, read from the dictionary at the transfer's offset; only
    /// the offset and toggle of the state change.
    pub(super) fn upload_segment(&mut self, now: Timestamp, toggle: bool) {
        let State::Uploading {
            index,
            sub,
            offset,
            len,
            toggle: expected,
        } = self.state
        else {
            // Not reached: `handle_frame` calls it in this state only.
            return;
        };
        if let Err(code) = check_toggle(toggle, expected) {
            return self.abort_local(code);
        }
        let mut data = [0u8; 7];
        let want = len.saturating_sub(offset).min(7);
        let n = match self.read_full(index, sub, offset, data.get_mut(..want).unwrap_or(&mut [])) {
            Ok(n) => n,
            Err(code) => return self.abort_local(code),
        };
        if n < want {
            // The dictionary ran dry before the size it announced.
            return self.abort_local(AbortCode::GeneralError);
        }
        let offset = offset.saturating_add(n);
        let last = offset >= len;
        self.send(ServerCommand::UploadSegment(Segment {
            toggle,
            last,
            data: SegmentData::new(data.get(..n).unwrap_or(&[])).unwrap_or_default(),
        }));
        if last {
            return self.finish(ServerEvent::Uploaded { index, sub, len });
        }
        if let State::Uploading {
            offset: at,
            toggle: next,
            ..
        } = &mut self.state
        {
            *at = offset;
            *next = !toggle;
        }
        self.arm(now);
    }
}
