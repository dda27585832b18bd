//! The segments of one sub-block of a block transfer, held until the
//! receiver's acknowledgement says which of them it took (CiA 301 section
//! 7.2.4.3, SDO protocols: SDO block download and SDO block upload: the
//! acknowledgement carries ackseq, the last sequence number the receiver
//! took in order, and the sender resends every segment after it in the
//! next sub-block, numbering from 1 again).
//!
//! A receiver may drop everything after an out-of-order segment (the
//! crate's own client and server do) or keep later ones; only its
//! acknowledgement tells. So the observer commits nothing when a segment is
//! seen: it keeps each sequence number's 7 bytes in a [`SubBlock`] taken
//! from the observer's pool, and at the acknowledgement delivers exactly
//! segments 1..=ackseq and forgets the rest.

use crate::sdo::data::SegmentData;
use crate::sdo::observer::SdoChannel;

/// Data bytes a sub-block can carry: 127 segments (the largest block
/// size, CiA 301) of 7 bytes.
pub const SUB_BLOCK_BYTES: usize = 127 * SEGMENT;

/// Data bytes per segment.
const SEGMENT: usize = 7;

/// The segments of one sub-block seen on the bus and not yet acknowledged;
/// one of the observer's pool, lent to one channel at a time.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SubBlock {
    /// The channel whose transfer holds it (`None`: free).
    owner: Option<SdoChannel>,
    /// Segment `n`'s data at `(n - 1) * 7`.
    data: [u8; SUB_BLOCK_BYTES],
    /// Bit `n - 1` is set when segment `n` is held.
    present: u128,
    /// The held segment with the last flag c: its number and data bytes.
    last: Option<(u8, u8)>,
    /// The sequence number a receiver taking segments in order expects
    /// next: a copy of it replaces the one held (that is the copy such a
    /// receiver takes); a copy of any other number only fills a gap.
    expected: u8,
}

/// A free buffer (the pool's filler).
pub(crate) const FREE: SubBlock = SubBlock {
    owner: None,
    data: [0; SUB_BLOCK_BYTES],
    present: 0,
    last: None,
    expected: 1,
};

/// A sub-block segment, as the observer read it: 1..=127, its last flag
/// and its data bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Seen {
    pub seqno: u8,
    pub last: bool,
    pub data: SegmentData,
}

impl SubBlock {
    /// Takes one segment (`seqno` 1..=127; others are ignored).
    pub(crate) fn hold(&mut self, seg: Seen) {
        let Some(bit) = bit(seg.seqno) else {
            return;
        };
        let in_order = seg.seqno == self.expected;
        if !in_order && self.present & bit != 0 {
            return;
        }
        let at = usize::from(seg.seqno - 1) * SEGMENT;
        let Some(slot) = self.data.get_mut(at..at + SEGMENT) else {
            return;
        };
        let bytes = seg.data.as_slice();
        slot.fill(0);
        if let Some(dst) = slot.get_mut(..bytes.len()) {
            dst.copy_from_slice(bytes);
        }
        self.present |= bit;
        if seg.last {
            self.last = Some((seg.seqno, u8::try_from(bytes.len()).unwrap_or(0)));
        } else if self.last.is_some_and(|(n, _)| n == seg.seqno) {
            self.last = None;
        }
        if in_order {
            self.expected = self.expected.saturating_add(1);
        }
    }

    /// Segments 1..=n held without a gap (up to the one with c = 1).
    pub(crate) fn contiguous(&self) -> u8 {
        let run = (!self.present).trailing_zeros();
        let run = u8::try_from(run).unwrap_or(127).min(127);
        match self.last {
            Some((n, _)) => run.min(n),
            None => run,
        }
    }

    /// The sequence number of the held segment with c = 1, if any.
    pub(crate) fn closing(&self) -> Option<u8> {
        self.last.map(|(n, _)| n)
    }

    /// Segment `seqno` as held: its data and whether it has c = 1.
    pub(crate) fn segment(&self, seqno: u8) -> Option<(SegmentData, bool)> {
        let bit = bit(seqno)?;
        if self.present & bit == 0 {
            return None;
        }
        let at = usize::from(seqno - 1) * SEGMENT;
        let (len, last) = match self.last {
            Some((n, len)) if n == seqno => (usize::from(len), true),
            _ => (SEGMENT, false),
        };
        let data = self.data.get(at..at + len)?;
        Some((SegmentData::new(data)?, last))
    }

    /// Segments held.
    pub(crate) fn segments(&self) -> u8 {
        u8::try_from(self.present.count_ones()).unwrap_or(u8::MAX)
    }

    /// Data bytes held.
    pub(crate) fn bytes(&self) -> usize {
        let full = usize::from(self.segments()) * SEGMENT;
        match self.last {
            Some((_, len)) => full.saturating_sub(SEGMENT) + usize::from(len),
            None => full,
        }
    }
}

/// The bit of sequence number `seqno` (1..=127).
fn bit(seqno: u8) -> Option<u128> {
    (1..=127).contains(&seqno).then(|| 1u128 << (seqno - 1))
}

/// The buffer `channel` holds, or a free one lent to it now; `None` when
/// every buffer is lent.
pub(crate) fn lend(pool: &mut [SubBlock], channel: SdoChannel) -> Option<&mut SubBlock> {
    let at = pool
        .iter()
        .position(|b| b.owner == Some(channel))
        .or_else(|| pool.iter().position(|b| b.owner.is_none()))?;
    let buffer = pool.get_mut(at)?;
    if buffer.owner.is_none() {
        *buffer = SubBlock {
            owner: Some(channel),
            ..FREE
        };
    }
    Some(buffer)
}

/// The buffer `channel` holds, if any.
pub(crate) fn held(pool: &[SubBlock], channel: SdoChannel) -> Option<&SubBlock> {
    pool.iter().find(|b| b.owner == Some(channel))
}

/// Gives back the buffer `channel` holds (its segments are forgotten).
pub(crate) fn give_back(pool: &mut [SubBlock], channel: SdoChannel) {
    for b in pool.iter_mut().filter(|b| b.owner == Some(channel)) {
        b.owner = None;
    }
}
