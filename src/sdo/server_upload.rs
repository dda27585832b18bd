//! Expedited and segmented upload of [`Server`] (CiA 301 section 7.2.4.3,
//! SDO protocols: SDO upload initiate and SDO upload segment): the initiate
//! answered from the dictionary and the segments read from it at the
//! transfer's offset, one per request.

use super::super::segmented::check_toggle;
use super::super::words;
use super::{AbortCode, Initiated, ObjectDictionary, ObjectInfo, Server, ServerEvent, State};
use crate::clock::Timestamp;

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
            // The bytes past `n` zero, as the frame has them.
            let mask = u32::MAX.checked_shr(32 - 8 * n.min(4) as u32).unwrap_or(0);
            let data = u32::from_le_bytes(buf) & mask;
            return Ok((
                words::expedited_b0(2, n),
                data,
                Some(ServerEvent::Uploaded { index, sub, len: n }),
            ));
        }
        let size = u32::try_from(info.len).map_err(|_| AbortCode::OutOfMemory)?;
        self.state = State::Uploading {
            index,
            sub,
            offset: 0,
            len: info.len,
            toggle: false,
        };
        Ok((words::segmented_b0(2), size, None))
    }

    /// An upload segment request (ccs = 3, toggle `toggle`): the next
    /// segment, read from the dictionary at the transfer's offset. The
    /// frame is made in place, as `SdoResponse::new` of
    /// `ServerCommand::UploadSegment` would make it, and only the offset and
    /// toggle of the state change (no copy of the state per segment).
    ///
    /// Out of line, as `download_segment`: inlined into `handle_frame`, their
    /// only caller, both segmented transfers took 4-6 % more instructions
    /// per segment (callgrind, benches/sdo_count.rs) and the firmware's
    /// flash was about the same.
    #[inline(never)]
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
        // The frame made in place: byte 0 the command, the data read
        // straight into bytes 1..=7 (zero past n: n < want aborts below).
        let mut frame = [0u8; 8];
        let [command, data @ ..] = &mut frame;
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
        *command = words::upload_segment(toggle, n, last);
        self.send_bytes(frame, 8);
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
