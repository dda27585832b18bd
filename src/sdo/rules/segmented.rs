//! The segment rules of SDO segmented transfers, shared by the client, the
//! server and the observer (CiA 301 section 7.2.4.3, SDO protocols: SDO
//! download segment and SDO upload segment): one implementation of "which
//! segment may come next" for whichever machine receives the data, and of
//! the toggle rule for the frame that answers or requests each segment.
//!
//! - The toggle bit t of the first segment is 0 and alternates with every
//!   segment; an upload segment request and a download segment
//!   acknowledgement carry the t of the segment they ask for or confirm.
//!   A t that does not fit is 05030000h.
//! - With the size indicated in the initiate frame, more data than that is
//!   06070012h, and a last segment (c = 1) that leaves the total below it
//!   is 06070013h.

use crate::abort::AbortCode;
use crate::sdo::data::Segment;

/// The toggle rule for a request or acknowledgement: it must carry the
/// toggle bit of the segment it belongs to (05030000h otherwise).
pub(crate) const fn check_toggle(got: bool, want: bool) -> Result<(), AbortCode> {
    if got == want {
        Ok(())
    } else {
        Err(AbortCode::ToggleBitNotAlternated)
    }
}

/// Where a received segment goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Placed {
    /// Offset of its first data byte in the value.
    pub offset: usize,
    /// Bytes of the value received with it included.
    pub total: usize,
}

/// The receiving side of a segmented transfer (the client's upload, the
/// server's download): the toggle bit the next segment carries and the
/// bytes received against the indicated size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Segments {
    /// The indicated size (0 when not indicated: see `indicated`). Apart
    /// from the flag, not an `Option`: 12 bytes instead of 16 on 32-bit
    /// targets, in the state of every segmented transfer.
    size: usize,
    received: usize,
    toggle: bool,
    indicated: bool,
}

impl Segments {
    /// A transfer of `size` bytes when indicated; the first segment has t = 0.
    pub(crate) const fn new(size: Option<usize>) -> Self {
        let (size, indicated) = match size {
            Some(size) => (size, true),
            None => (0, false),
        };
        Segments {
            size,
            received: 0,
            toggle: false,
            indicated,
        }
    }

    /// The toggle bit the next segment (and its request or acknowledgement)
    /// carries.
    pub(crate) const fn toggle(&self) -> bool {
        self.toggle
    }

    /// Bytes received so far.
    #[cfg(test)]
    pub(crate) const fn received(&self) -> usize {
        self.received
    }

    /// The indicated size.
    #[cfg(test)]
    pub(crate) const fn size(&self) -> Option<usize> {
        if self.indicated {
            Some(self.size)
        } else {
            None
        }
    }

    /// Takes one segment: its toggle must be the expected one (05030000h),
    /// the total may not exceed the indicated size (06070012h), and a last
    /// segment may not leave it short (06070013h). On success the toggle
    /// alternates and the segment's place in the value is returned; on an
    /// error nothing changes.
    #[inline]
    pub(crate) fn on_segment(&mut self, segment: &Segment) -> Result<Placed, AbortCode> {
        self.check(segment)?;
        Ok(self.accept(segment))
    }

    /// The rules of [`Segments::on_segment`], without taking the segment.
    #[inline]
    pub(crate) fn check(&self, segment: &Segment) -> Result<(), AbortCode> {
        check_toggle(segment.toggle, self.toggle)?;
        let last = segment.last;
        let total = self.received.saturating_add(segment.data.len());
        if self.indicated && total > self.size {
            return Err(AbortCode::DataTypeLengthTooHigh);
        }
        if last && self.indicated && total < self.size {
            return Err(AbortCode::DataTypeLengthTooLow);
        }
        Ok(())
    }

    /// Takes a segment whatever the rules say (an observer following a
    /// peer that accepted it): the toggle alternates, the bytes count.
    #[inline]
    pub(crate) fn accept(&mut self, segment: &Segment) -> Placed {
        let offset = self.received;
        let total = offset.saturating_add(segment.data.len());
        self.received = total;
        self.toggle = !self.toggle;
        Placed { offset, total }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sdo::SegmentData;

    fn seg(toggle: bool, last: bool, data: &[u8]) -> Segment {
        Segment {
            toggle,
            last,
            data: SegmentData::new(data).unwrap(),
        }
    }

    #[test]
    fn toggles_alternate_from_zero() {
        let mut s = Segments::new(None);
        assert!(!s.toggle());
        assert_eq!(
            s.on_segment(&seg(false, false, &[1; 7])),
            Ok(Placed {
                offset: 0,
                total: 7
            })
        );
        assert!(s.toggle());
        assert_eq!(
            s.on_segment(&seg(true, true, &[2; 3])),
            Ok(Placed {
                offset: 7,
                total: 10
            })
        );
        assert_eq!(s.received(), 10);
    }

    #[test]
    fn a_repeated_toggle_is_05030000h_and_changes_nothing() {
        let mut s = Segments::new(None);
        s.on_segment(&seg(false, false, &[1; 7])).unwrap();
        assert_eq!(
            s.on_segment(&seg(false, false, &[1; 7])),
            Err(AbortCode::ToggleBitNotAlternated)
        );
        assert_eq!((s.received(), s.toggle()), (7, true));
        assert_eq!(
            check_toggle(true, false),
            Err(AbortCode::ToggleBitNotAlternated)
        );
        assert_eq!(check_toggle(true, true), Ok(()));
    }

    #[test]
    fn the_indicated_size_bounds_the_total_both_ways() {
        let mut s = Segments::new(Some(9));
        s.on_segment(&seg(false, false, &[0; 7])).unwrap();
        assert_eq!(
            s.clone().on_segment(&seg(true, false, &[0; 3])),
            Err(AbortCode::DataTypeLengthTooHigh)
        );
        assert_eq!(
            s.clone().on_segment(&seg(true, true, &[0; 1])),
            Err(AbortCode::DataTypeLengthTooLow)
        );
        assert!(s.on_segment(&seg(true, true, &[0; 2])).is_ok());
        assert_eq!(s.size(), Some(9));
    }
}
