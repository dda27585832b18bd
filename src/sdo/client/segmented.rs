//! Segmented upload and download of [`Client`] (CiA 301 section 7.2.4.3,
//! SDO protocols: segmented SDO download and upload), feature
//! `sdo-client-segmented`: the segments after a non-expedited initiate and
//! their toggle and size checks (the rules in `crate::sdo::rules`).

use super::{Client, ClientCommand, State, TransferEnd};
use crate::clock::Timestamp;
use crate::sdo::data::{Segment, SegmentData};
use crate::sdo::rules::segmented::{check_toggle, Segments};

impl<D: AsRef<[u8]>, const EVENTS: usize> Client<D, EVENTS> {
    /// The server answered the upload initiate with the size (or without
    /// it): the first upload segment request (ccs = 3).
    pub(super) fn segmented_upload(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
        size: Option<u32>,
    ) {
        let rx = Segments::new(size.map(|s| usize::try_from(s).unwrap_or(usize::MAX)));
        self.send(ClientCommand::UploadSegment {
            toggle: rx.toggle(),
        });
        self.wait(now, State::Uploading { index, sub, rx });
    }

    /// An upload segment (scs = 0) while uploading: checked by the segment
    /// rules, delivered, and the next one requested. The receive cursor is
    /// updated in place (no copy of the state per segment).
    pub(super) fn upload_segment(&mut self, now: Timestamp, segment: &Segment) {
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
            self.deliver(index, sub, placed.offset, segment.data);
        }
        if segment.last {
            return self.finish(TransferEnd::Uploaded {
                index,
                sub,
                len: placed.total,
            });
        }
        self.send(ClientCommand::UploadSegment { toggle });
        self.arm(now);
    }

    /// The first download segment, after the initiate was confirmed.
    pub(super) fn send_segment(&mut self, now: Timestamp, index: u16, sub: u8, data: D) {
        let (segment, sent) = segment_of(data.as_ref(), 0, false);
        self.send(ClientCommand::DownloadSegment(segment));
        self.wait(
            now,
            State::Downloading {
                index,
                sub,
                data,
                sent,
                toggle: false,
            },
        );
    }

    /// A download segment acknowledgement (scs = 1, toggle `t`) while
    /// downloading: the toggle checked, then the next segment or the end.
    /// The cursor is updated in place (no copy of the state per segment).
    pub(super) fn download_ack(&mut self, now: Timestamp, t: bool) {
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
            return self.finish(TransferEnd::Downloaded { index, sub, len });
        }
        *toggle = !*toggle;
        let (segment, next) = segment_of(value, *sent, *toggle);
        *sent = next;
        self.send(ClientCommand::DownloadSegment(segment));
        self.arm(now);
    }
}

/// The download segment of `value` from `from` with toggle `toggle`
/// (CiA 301: up to 7 bytes, the c bit on the one that reaches the end of
/// the value; an empty value is one empty last segment) and the offset
/// after it.
#[inline]
fn segment_of(value: &[u8], from: usize, toggle: bool) -> (Segment, usize) {
    let rest = value.get(from..).unwrap_or(&[]);
    let data = rest.get(..rest.len().min(7)).unwrap_or(&[]);
    let sent = from.saturating_add(data.len());
    let segment = Segment {
        toggle,
        last: sent >= value.len(),
        data: SegmentData::new(data).unwrap_or_default(),
    };
    (segment, sent)
}
