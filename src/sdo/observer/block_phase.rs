//! The sub-block phase of the observer's block transfers: segments held in
//! a buffer of the pool until the receiver's acknowledgement commits them
//! (the `sub_block` module), the acknowledgement, and the end
//! frame.

use super::{End, Open, Phase};
use crate::bytes::Payload;
use crate::sdo::abort::AbortCode;
use crate::sdo::data::SegmentData;
use crate::sdo::observer::sub_block::{self, Seen, SubBlock};
use crate::sdo::observer::{BreakReason, Observed, SdoChannel, Side, Sink};
use crate::sdo::rules::block::{check_block_size, is_abort, Receiver};
use crate::sdo::wire::{BlockSegment, SdoFrame};

/// The sub-block phase of a block transfer, between acknowledgements.
#[derive(Debug, Clone, Copy)]
pub(super) struct Blocks {
    /// The receiver's reading of the value: what is committed, the CRC,
    /// the block size, the held last segment.
    rx: Receiver,
    /// A repeat of this frame (the one that ended the last sub-block, or
    /// the initiate frame) is a duplicate while no segment has come since.
    dup: Option<Payload>,
    /// The last segment seen in this sub-block.
    recent: Option<Payload>,
    /// The last acknowledgement: a repeat of it with no segment between
    /// is ignored.
    last_ack: Option<Payload>,
}

impl Blocks {
    pub(super) fn new(rx: Receiver) -> Self {
        Blocks {
            rx,
            dup: rx.acked_frame(),
            recent: None,
            last_ack: None,
        }
    }
}

/// A sub-block segment from the sender of the data, held until the
/// receiver acknowledges it; `None` when the frame is a command. The
/// reason is given when the segment ends the transfer (no buffer free).
pub(super) fn block_segment(
    open: &mut Option<Open>,
    channel: SdoChannel,
    from: Side,
    bytes: &[u8],
    pool: &mut [SubBlock],
) -> Option<(Observed, Option<BreakReason>)> {
    let o = open.as_mut()?;
    let sender = o.data_sender();
    let segment = match SdoFrame::new_checked(bytes) {
        Ok(frame) => BlockSegment::parse(&frame),
        Err(_) => BlockSegment {
            seqno: 0,
            last: false,
            data: SegmentData::EMPTY,
        },
    };
    let mut end = None;
    let taken = match &mut o.phase {
        Phase::SubBlocks(b) if from == sender => {
            // An abort is a command in any phase; once the last segment is
            // acknowledged the end frame is next (a repeat of the segment
            // acknowledged last aside, which the receiver ignores).
            let dup = b.dup.is_some_and(|d| d.as_slice() == bytes);
            if is_abort(bytes) || (b.rx.is_done() && !dup) {
                return None;
            }
            let blksize = b.rx.block_size();
            if dup || bytes.is_empty() {
                // A repeat of the frame that ended the last sub-block (or
                // no data at all): the receiver ignores it.
            } else if segment.seqno == 0 || segment.seqno > blksize {
                o.violate(AbortCode::InvalidSequenceNumber, sender.other());
            } else if !segment.last && segment.data.len() < 7 {
                // Without c and shorter than 8 bytes: its data is not all
                // there; the receiver ignores it.
            } else if let Some(buffer) = sub_block::lend(pool, channel) {
                buffer.hold(Seen {
                    seqno: segment.seqno,
                    last: segment.last,
                    data: segment.data,
                });
                o.pending = (buffer.bytes(), buffer.segments());
                b.dup = None;
                b.recent = Payload::new(bytes);
            } else {
                end = Some(BreakReason::NoSubBlockBuffer {
                    buffers: pool.len(),
                });
            }
            true
        }
        Phase::Violated {
            segments_from: Some(side),
            ..
        } if *side == from => !is_abort(bytes),
        _ => false,
    };
    if !taken {
        return None;
    }
    let seen = Observed::BlockSegment {
        channel,
        from,
        seqno: segment.seqno,
        last: segment.last,
        data: segment.data,
    };
    Some((seen, end))
}

/// The receiver of the data (`from`) acknowledged a sub-block: segments
/// 1..=`ackseq` are committed (delivered, in order), the others seen are
/// forgotten (the sender resends them from sequence number 1); the block
/// size must be valid unless the last segment is in.
pub(super) fn ack(
    o: &mut Open,
    (ackseq, blksize): (u8, u8),
    bytes: &[u8],
    from: Side,
    pool: &mut [SubBlock],
    out: &mut Sink,
) -> Option<End> {
    let Phase::SubBlocks(mut b) = o.phase else {
        o.violate(AbortCode::InvalidCommandSpecifier, from.other());
        return None;
    };
    let channel = o.transfer.channel;
    let held = sub_block::held(pool, channel).copied();
    sub_block::give_back(pool, channel);
    o.pending = (0, 0);
    let segments = held.map_or(0, |h| h.segments());
    if segments == 0 && b.last_ack.is_some_and(|a| a.as_slice() == bytes) {
        // The same acknowledgement again, nothing sent between: the
        // sender's business; nothing more is confirmed.
        return None;
    }
    let have = held.map_or(0, |h| h.contiguous());
    if ackseq > have {
        return Some(End::Broken(BreakReason::AckMismatch {
            expected: have,
            got: ackseq,
        }));
    }
    for seqno in 1..=ackseq {
        let Some((data, last)) = held.and_then(|h| h.segment(seqno)) else {
            break;
        };
        match b.rx.commit(data, last) {
            Ok(Some((offset, data))) => o.deliver(offset, data, out),
            Ok(None) => {}
            Err(code) => {
                o.violate(code, from);
                return None;
            }
        }
    }
    // The receiver ignores a repeat of the segment that completed the
    // sub-block in order (the one acknowledged), not of one it dropped.
    b.dup = b
        .recent
        .take()
        .filter(|r| ackseq > 0 && r.as_slice().first().map(|b0| b0 & 0x7F) == Some(ackseq));
    b.last_ack = Payload::new(bytes);
    if b.rx.is_done() {
        o.phase = Phase::SubBlocks(b);
        return None;
    }
    match check_block_size(blksize) {
        Ok(size) => {
            b.rx.set_block_size(size);
            o.phase = Phase::SubBlocks(b);
        }
        Err(code) => o.violate(code, from.other()),
    }
    None
}

/// The sender's end frame; `checker` is the receiver of the data.
pub(super) fn end(
    o: &mut Open,
    (unused, crc): (u8, u16),
    bytes: &[u8],
    checker: Side,
    out: &mut Sink,
) {
    let Phase::SubBlocks(Blocks { mut rx, .. }) = o.phase else {
        return o.violate(AbortCode::InvalidCommandSpecifier, checker);
    };
    if !rx.is_done() {
        return o.violate(AbortCode::InvalidCommandSpecifier, checker);
    }
    match rx.on_end_lenient(unused, crc) {
        Ok((ended, broken)) => {
            if let Some(code) = broken {
                o.flag(code, checker);
            }
            if let Some((offset, data)) = ended.write {
                o.deliver(offset, data, out);
            }
            o.phase = Phase::EndAckDue {
                crc_checked: rx.crc_on() && broken != Some(AbortCode::CrcError),
                end: Payload::new(bytes).unwrap_or_default(),
            };
        }
        Err(code) => o.violate(code, checker),
    }
}
