//! The sub-block rules of SDO block transfer, shared by the client and the
//! server (CiA 301 section 7.2.4.3, SDO protocols: SDO block download and
//! SDO block upload): one implementation of "which segment may come next"
//! for the sender and the receiver of the data, whichever machine that is.
//!
//! - A sub-block is 1..=`blksize` segments numbered 1..=`blksize`; byte 0 of
//!   a segment is the sequence number (bits 6-0) and the last flag c (bit 7),
//!   bytes 1-7 are data. The value is cut into 7-byte segments; the last one
//!   has c = 1 and its unused byte count travels in the end frame. An empty
//!   value is one segment with c = 1 and 7 unused bytes.
//! - The receiver answers after the segment numbered `blksize` or the one
//!   with c = 1 with the last sequence number it received in order (0: none)
//!   and the next block size; the sender goes on from the segment after it,
//!   numbering from 1 again.
//! - Nothing is buffered but one segment: the sender generates each segment
//!   when it is polled, from the data at the segment's offset; the receiver
//!   passes every in-order segment on at once except the one with c = 1,
//!   which it holds until the end frame says how many of its bytes are data.

use crate::abort::AbortCode;
use crate::bytes::Payload;
use crate::sdo::crc::crc16_update;
use crate::sdo::data::SegmentData;
#[cfg(feature = "sdo-block")]
use crate::sdo::wire::BlockSegment;
use crate::sdo::wire::SdoFrame;

/// The largest block size, CiA 301: 1..=127 segments per sub-block.
pub(crate) const MAX_BLOCK_SIZE: u8 = 127;

/// Data bytes per segment.
const SEGMENT: usize = 7;

/// True for an abort frame (byte 0 80h): in the sub-block phase every
/// other frame from the sender of the data is a segment (sequence number 0
/// with c = 1 is not a segment).
pub(crate) fn is_abort(bytes: &[u8]) -> bool {
    SdoFrame::new_checked(bytes).is_ok_and(|frame| frame.command() == 0x80)
}

/// Checks a block size from the peer: 05040002h unless it is 1..=127.
pub(crate) const fn check_block_size(blksize: u8) -> Result<u8, AbortCode> {
    if blksize >= 1 && blksize <= MAX_BLOCK_SIZE {
        Ok(blksize)
    } else {
        Err(AbortCode::InvalidBlockSize)
    }
}

#[cfg(feature = "sdo-block")]
/// A configured block size brought into 1..=127.
pub(crate) const fn clamp_block_size(blksize: u8) -> u8 {
    if blksize == 0 {
        1
    } else if blksize > MAX_BLOCK_SIZE {
        MAX_BLOCK_SIZE
    } else {
        blksize
    }
}

#[cfg(feature = "sdo-block")]
/// Segments of a value of `len` bytes (an empty value is one segment).
const fn segments_of(len: usize) -> usize {
    let n = len.div_ceil(SEGMENT);
    if n == 0 {
        1
    } else {
        n
    }
}

#[cfg(feature = "sdo-block")]
/// The next segment a [`Sender`] wants to send.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Planned {
    /// Offset of its first data byte in the value.
    pub offset: usize,
    /// Data bytes it carries (0..=7).
    pub len: usize,
}

#[cfg(feature = "sdo-block")]
/// What an acknowledgement means to the sender.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Acked {
    /// More segments follow: poll again.
    More,
    /// Every segment is acknowledged: send the end frame.
    Done {
        /// Unused bytes of the last segment (0..=7).
        unused: u8,
        /// The CRC of all data (0 when CRC is not in use).
        crc: u16,
    },
}

#[cfg(feature = "sdo-block")]
/// The sending side of the sub-block phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Sender {
    len: usize,
    /// Segment index (from 0) of sequence number 1 of this sub-block.
    first: usize,
    /// Segments generated in this sub-block.
    generated: u8,
    blksize: u8,
    crc_on: bool,
    crc: u16,
    /// Segments already in `crc` (every segment enters it once, in order).
    crc_upto: usize,
}

#[cfg(feature = "sdo-block")]
impl Sender {
    /// A sender of `len` bytes with the receiver's first block size.
    pub(crate) const fn new(len: usize, blksize: u8, crc_on: bool) -> Self {
        Sender {
            len,
            first: 0,
            generated: 0,
            blksize,
            crc_on,
            crc: 0,
            crc_upto: 0,
        }
    }

    /// Bytes in the whole value.
    pub(crate) const fn len(&self) -> usize {
        self.len
    }

    /// The segment to send next, or `None` when the sub-block is out and
    /// the acknowledgement is due.
    pub(crate) const fn next(&self) -> Option<Planned> {
        let index = self.first + self.generated as usize;
        if self.generated >= self.blksize || index >= segments_of(self.len) {
            return None;
        }
        let offset = index * SEGMENT;
        let left = self.len.saturating_sub(offset);
        Some(Planned {
            offset,
            len: if left < SEGMENT { left } else { SEGMENT },
        })
    }

    /// Builds the segment `next` planned, with its `data` (read at the
    /// planned offset; at most 7 bytes are used), and counts it as sent.
    pub(crate) fn emit(&mut self, data: &[u8]) -> [u8; 8] {
        let index = self.first + usize::from(self.generated);
        let data = data.get(..data.len().min(SEGMENT)).unwrap_or(&[]);
        if self.crc_on && index == self.crc_upto {
            self.crc = crc16_update(self.crc, data);
            self.crc_upto += 1;
        }
        self.generated = self.generated.saturating_add(1);
        let segment = BlockSegment {
            seqno: self.generated,
            last: index + 1 >= segments_of(self.len),
            data: SegmentData::new(data).unwrap_or_default(),
        };
        let mut frame = [0u8; 8];
        segment.emit(&mut frame);
        frame
    }

    /// Takes the receiver's acknowledgement: `ackseq` segments of this
    /// sub-block arrived in order, `blksize` is the next block size.
    ///
    /// An `ackseq` above the number of segments sent in this sub-block is
    /// 05040003h; a block size outside 1..=127 is 05040002h, unless every
    /// segment is acknowledged (no further sub-block needs it).
    pub(crate) fn on_ack(&mut self, ackseq: u8, blksize: u8) -> Result<Acked, AbortCode> {
        if ackseq > self.generated {
            return Err(AbortCode::InvalidSequenceNumber);
        }
        let acked = self.first + usize::from(ackseq);
        let total = segments_of(self.len);
        if acked >= total {
            let unused = (total * SEGMENT).saturating_sub(self.len);
            return Ok(Acked::Done {
                unused: u8::try_from(unused).unwrap_or(0),
                crc: if self.crc_on { self.crc } else { 0 },
            });
        }
        self.blksize = check_block_size(blksize)?;
        self.first = acked;
        self.generated = 0;
        Ok(Acked::More)
    }
}

#[cfg(feature = "sdo-block")]
/// What one received segment asks the receiver's owner to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Step {
    /// Write (or report) these bytes at this offset.
    pub write: Option<(usize, SegmentData)>,
    /// Then acknowledge with this sequence number (and the block size).
    pub ack: Option<u8>,
}

/// How the end frame completed the transfer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Ended {
    /// The data bytes of the held last segment, at their offset.
    pub write: Option<(usize, SegmentData)>,
    /// Bytes in the whole value.
    pub total: usize,
}

/// The receiving side of the sub-block phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Receiver {
    blksize: u8,
    /// The next in-order sequence number.
    expected: u8,
    size: Option<usize>,
    /// Bytes passed on (the held segment not included).
    received: usize,
    crc_on: bool,
    crc: u16,
    /// The segment with c = 1, once received in order.
    held: Option<SegmentData>,
    /// The frame that completed the last sub-block, while nothing of the
    /// next one has arrived (to recognise its duplicate).
    acked_frame: Option<Payload>,
}

impl Receiver {
    /// A receiver expecting sub-blocks of `blksize` segments and `size`
    /// bytes in total when indicated.
    pub(crate) const fn new(blksize: u8, size: Option<usize>, crc_on: bool) -> Self {
        Receiver {
            blksize,
            expected: 1,
            size,
            received: 0,
            crc_on,
            crc: 0,
            held: None,
            acked_frame: None,
        }
    }

    /// The same receiver, treating a repeat of `frame` (the initiate frame
    /// that opened the transfer) as a duplicate until the first segment.
    pub(crate) fn after(mut self, frame: &[u8]) -> Self {
        self.acked_frame = Payload::new(frame);
        self
    }

    /// The block size this receiver announces.
    pub(crate) const fn block_size(&self) -> u8 {
        self.blksize
    }

    /// The frame a repeat of which is ignored as a duplicate while nothing
    /// of the next sub-block has arrived.
    pub(crate) const fn acked_frame(&self) -> Option<Payload> {
        if self.expected == 1 {
            self.acked_frame
        } else {
            None
        }
    }

    /// True once the segment with c = 1 arrived in order and was
    /// acknowledged: the end frame comes next.
    pub(crate) const fn is_done(&self) -> bool {
        self.held.is_some()
    }

    /// True if `bytes` repeat the frame that completed the last sub-block
    /// while nothing newer arrived: a duplicate, to be ignored.
    pub(crate) fn is_duplicate(&self, bytes: &[u8]) -> bool {
        self.acked_frame
            .is_some_and(|f| self.expected == 1 && f.as_slice() == bytes)
    }

    #[cfg(feature = "sdo-block")]
    /// Takes a frame from the sender of the data while sub-blocks are being
    /// received: `None` when it is not a segment but a command for the
    /// normal path (an abort, byte 0 80h, or any frame once the last
    /// segment is in: the end frame comes next); otherwise what
    /// [`Receiver::on_segment`] makes of it (a duplicate of the frame that
    /// completed the last sub-block is ignored).
    pub(crate) fn take(&mut self, bytes: &[u8]) -> Option<Result<Step, AbortCode>> {
        if self.is_duplicate(bytes) {
            return Some(Ok(Step::default()));
        }
        if self.is_done() || is_abort(bytes) {
            return None;
        }
        Some(self.on_segment(bytes))
    }

    /// Sets the block size announced from now on (an observer follows the
    /// size each acknowledgement gives).
    pub(crate) fn set_block_size(&mut self, blksize: u8) {
        self.blksize = blksize;
    }

    /// Whether the CRC is checked at the end.
    pub(crate) const fn crc_on(&self) -> bool {
        self.crc_on
    }

    #[cfg(feature = "sdo-block")]
    /// Takes one sub-block segment (the whole frame data).
    ///
    /// Sequence number 0 or above the block size is 05040003h. A duplicate
    /// of the frame that completed the previous sub-block is ignored. An
    /// in-order segment is passed on (or held, with c = 1); at the block's
    /// last number or c = 1 the acknowledgement is due. An out-of-order
    /// segment is ignored, except that at the block's last number or c = 1
    /// it triggers the acknowledgement of the last in-order one. A segment
    /// without c shorter than 8 bytes is ignored (its data is not all
    /// there). More data than indicated is 06070012h.
    pub(crate) fn on_segment(&mut self, bytes: &[u8]) -> Result<Step, AbortCode> {
        let Ok(frame) = SdoFrame::new_checked(bytes) else {
            return Ok(Step::default());
        };
        let BlockSegment {
            seqno: seq,
            last,
            data: seg,
        } = BlockSegment::parse(&frame);
        if seq == 0 || seq > self.blksize {
            return Err(AbortCode::InvalidSequenceNumber);
        }
        if self.is_duplicate(bytes) || self.is_done() {
            return Ok(Step::default());
        }
        let ends_block = last || seq == self.blksize;
        if seq != self.expected {
            if !ends_block {
                return Ok(Step::default());
            }
            let ackseq = self.expected.saturating_sub(1);
            self.expected = 1;
            self.acked_frame = None;
            return Ok(Step {
                write: None,
                ack: Some(ackseq),
            });
        }
        if !last && seg.len() < SEGMENT {
            return Ok(Step::default());
        }
        let mut step = Step {
            write: self.commit(seg, last)?,
            ack: None,
        };
        self.acked_frame = None;
        if ends_block {
            step.ack = Some(seq);
            self.expected = 1;
            self.acked_frame = Payload::new(bytes);
        } else {
            self.expected = seq + 1;
        }
        Ok(step)
    }

    /// Takes one segment of the value in order, as confirmed (the
    /// receiver's own in-order reading, or an acknowledgement an observer
    /// saw): the one with c = 1 is held for the end frame; any other must
    /// carry 7 bytes (a shorter one is 05040001h) and is passed on at its
    /// offset, counted in the CRC. More data than indicated is 06070012h.
    pub(crate) fn commit(
        &mut self,
        seg: SegmentData,
        last: bool,
    ) -> Result<Option<(usize, SegmentData)>, AbortCode> {
        if last {
            self.held = Some(seg);
            return Ok(None);
        }
        let data = seg.as_slice();
        if data.len() < SEGMENT {
            return Err(AbortCode::InvalidCommandSpecifier);
        }
        let end = self.received.saturating_add(SEGMENT);
        if self.size.is_some_and(|s| end > s) {
            return Err(AbortCode::DataTypeLengthTooHigh);
        }
        if self.crc_on {
            self.crc = crc16_update(self.crc, data);
        }
        let at = self.received;
        self.received = end;
        Ok(Some((at, seg)))
    }

    #[cfg(feature = "sdo-block")]
    /// Takes the end frame: `unused` bytes of the held last segment carry
    /// no data, `crc` is the sender's CRC.
    ///
    /// Before the last segment arrived, or with more unused bytes than the
    /// held segment lets be data (7 minus its data bytes), it is 05040001h;
    /// a total above / below the indicated size 06070012h / 06070013h; a
    /// CRC mismatch (CRC in use) 05040004h.
    pub(crate) fn on_end(&mut self, unused: u8, crc: u16) -> Result<Ended, AbortCode> {
        match self.on_end_lenient(unused, crc)? {
            (ended, None) => Ok(ended),
            (_, Some(code)) => Err(code),
        }
    }

    /// The rules of [`Receiver::on_end`], for an observer: the end frames
    /// that cannot be read (05040001h) are errors; the size and CRC rules
    /// give the transfer as it ended and the code they call for, since a
    /// peer may accept it anyway.
    pub(crate) fn on_end_lenient(
        &mut self,
        unused: u8,
        crc: u16,
    ) -> Result<(Ended, Option<AbortCode>), AbortCode> {
        let Some(held) = self.held else {
            return Err(AbortCode::InvalidCommandSpecifier);
        };
        if usize::from(unused) > SEGMENT {
            return Err(AbortCode::InvalidCommandSpecifier);
        }
        let keep = SEGMENT - usize::from(unused);
        let Some(data) = held.as_slice().get(..keep) else {
            return Err(AbortCode::InvalidCommandSpecifier);
        };
        let total = self.received.saturating_add(data.len());
        let broken = match self.size {
            Some(s) if total > s => Some(AbortCode::DataTypeLengthTooHigh),
            Some(s) if total < s => Some(AbortCode::DataTypeLengthTooLow),
            _ if self.crc_on && crc16_update(self.crc, data) != crc => Some(AbortCode::CrcError),
            _ => None,
        };
        let ended = Ended {
            write: (!data.is_empty())
                .then(|| (self.received, SegmentData::new(data).unwrap_or_default())),
            total,
        };
        Ok((ended, broken))
    }
}

// Both drive the server's block transfer too (feature `sdo-block`).
#[cfg(all(test, feature = "sdo-block"))]
#[path = "block_tests.rs"]
mod tests;

#[cfg(all(test, feature = "sdo-block"))]
#[path = "block_abort_tests.rs"]
mod abort_tests;
