//! The sub-block phase of the observer's block transfers: segments held in
//! a buffer of the pool until the receiver's acknowledgement commits them
//! (the `sub_block` module), the acknowledgement, and the end
//! frame.
//!
//! A sender can run a sub-block ahead of the receiver's acknowledgements:
//! CiA 301 numbers the segments of a sub-block but not the sub-blocks, so
//! a sender that takes a repeated acknowledgement for the one of the
//! sub-block it just sent goes on with the next one before the receiver's
//! own acknowledgement is on the bus; the receiver, numbering from 1
//! again after each sub-block it acknowledged, takes those segments. So
//! when the sender goes on (a segment of a new sub-block, or its end
//! frame) after a sub-block was closed (its segment at the block size, or
//! the one with c = 1, was seen) with no acknowledgement between, the
//! observer reads the closed sub-block as the sender did: acknowledged as
//! far as the repeat of the last acknowledgement says. The receiver's own
//! acknowledgement of it is then owed, and the next one seen is taken as
//! that one.

use super::{End, Open, Phase};
use crate::abort::AbortCode;
use crate::bytes::Payload;
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
    /// The segment that closes the sub-block held (the block size, or
    /// c = 1) was seen: the receiver has sent its acknowledgement.
    closed: bool,
    /// Sub-blocks read as acknowledged by a repeat (the sender went on)
    /// whose receiver's own acknowledgement has not been seen yet.
    owed: u8,
}

impl Blocks {
    pub(super) fn new(rx: Receiver) -> Self {
        Blocks {
            rx,
            dup: rx.acked_frame(),
            recent: None,
            last_ack: None,
            closed: false,
            owed: 0,
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
    out: &mut Sink,
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
    if let Phase::SubBlocks(b) = o.phase {
        let repeat = b.dup.is_some_and(|d| d.as_slice() == bytes)
            || b.recent.is_some_and(|r| r.as_slice() == bytes);
        let segment_of_a_sub_block = !b.rx.is_done()
            && (1..=b.rx.block_size()).contains(&segment.seqno)
            && (segment.last || segment.data.len() == 7);
        if from == sender && b.closed && !repeat && !is_abort(bytes) {
            let held = sub_block::held(out.pool, channel).copied();
            let blksize = b.rx.block_size();
            // The closed sub-block holds every segment up to its closing one.
            let complete = held.is_some_and(|h| match h.closing() {
                Some(n) => h.contiguous() == n,
                None => h.contiguous() >= blksize,
            });
            let last_held = held.is_some_and(|h| h.closing().is_some());
            if last_held && segment.seqno != 1 && (complete || segment.seqno > blksize) {
                // After the last sub-block the sender resends from 1 or
                // sends its end frame: a command.
                return None;
            }
            // A segment numbered 1 other than the one held begins the next
            // sub-block; any other number fills a gap of the closed one
            // (a segment delayed behind later ones).
            let next_sub_block = segment.seqno == 1
                && held.is_some_and(|h| {
                    h.segment(1)
                        .is_some_and(|(data, last)| (data, last) != (segment.data, segment.last))
                });
            if segment_of_a_sub_block && next_sub_block {
                if let Some(End::Broken(reason)) = went_on(o, out) {
                    end = Some(reason);
                }
            }
        }
    }
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
            if end.is_some() {
                // The sender went on past an acknowledgement of segments
                // the observer did not see.
            } else if dup || bytes.is_empty() {
                // A repeat of the frame that ended the last sub-block (or
                // no data at all): the receiver ignores it.
            } else if segment.seqno == 0 || segment.seqno > blksize {
                o.violate(AbortCode::InvalidSequenceNumber, sender.other());
            } else if !segment.last && segment.data.len() < 7 {
                // Without c and shorter than 8 bytes: its data is not all
                // there; the receiver ignores it.
            } else if let Some(buffer) = sub_block::lend(out.pool, channel) {
                buffer.hold(Seen {
                    seqno: segment.seqno,
                    last: segment.last,
                    data: segment.data,
                });
                o.pending = (buffer.bytes(), buffer.segments());
                b.dup = None;
                b.recent = Payload::new(bytes);
                b.closed |= segment.last || segment.seqno == blksize;
            } else {
                end = Some(BreakReason::NoSubBlockBuffer {
                    buffers: out.pool.len(),
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
    out: &mut Sink,
) -> Option<End> {
    let Phase::SubBlocks(mut b) = o.phase else {
        // After the end frame too: the sender, waiting for the end
        // confirmation, aborts (05040001h), also when the
        // acknowledgement is the receiver's own of the last sub-block of a
        // sender that went on.
        o.violate(AbortCode::InvalidCommandSpecifier, from.other());
        return None;
    };
    if b.rx.is_done() {
        // The last segment is acknowledged: the sender has sent its end
        // frame, or is sending it, and waits for the end confirmation; an
        // acknowledgement now, a repeat of the last one included, is out
        // of phase for it (05040001h).
        o.violate(AbortCode::InvalidCommandSpecifier, from.other());
        return None;
    }
    if b.owed > 0 {
        // The receiver's own acknowledgement of a sub-block the sender
        // went on from (read at that point): nothing more is confirmed.
        b.owed -= 1;
        b.last_ack = Payload::new(bytes);
        return next_block_size(o, b, blksize, from);
    }
    let channel = o.transfer.channel;
    let held = sub_block::held(out.pool, channel).copied();
    sub_block::give_back(out.pool, channel);
    o.pending = (0, 0);
    b.closed = false;
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
    if let Some(h) = held {
        if !commit(o, &mut b, &h, ackseq, from, out) {
            return None;
        }
    }
    // The receiver ignores a repeat of the segment that completed the
    // sub-block in order (the one acknowledged), not of one it dropped.
    b.dup = b
        .recent
        .take()
        .filter(|r| ackseq > 0 && r.as_slice().first().map(|b0| b0 & 0x7F) == Some(ackseq));
    b.last_ack = Payload::new(bytes);
    next_block_size(o, b, blksize, from)
}

/// The sender of the data went on after a closed sub-block with no
/// acknowledgement seen between (the module's doc says why): the sub-block
/// is committed as far as the last acknowledgement seen, which the sender
/// took again, says (at most to its closing segment), and the receiver's
/// own acknowledgement of it is owed. Before any acknowledgement there is
/// nothing the sender can have taken, and the segments stay held.
fn went_on(o: &mut Open, out: &mut Sink) -> Option<End> {
    let Phase::SubBlocks(mut b) = o.phase else {
        return None;
    };
    let ackseq = b.last_ack.and_then(|a| a.as_slice().get(1).copied())?;
    let channel = o.transfer.channel;
    let held = sub_block::held(out.pool, channel).copied()?;
    let n = ackseq.min(held.closing().unwrap_or(ackseq));
    let have = held.contiguous();
    sub_block::give_back(out.pool, channel);
    o.pending = (0, 0);
    if n > have {
        return Some(End::Broken(BreakReason::AckMismatch {
            expected: have,
            got: n,
        }));
    }
    let receiver = o.data_sender().other();
    if !commit(o, &mut b, &held, n, receiver, out) {
        return None;
    }
    b.closed = false;
    b.owed = b.owed.saturating_add(1);
    b.dup = None;
    b.recent = None;
    o.phase = Phase::SubBlocks(b);
    None
}

/// Delivers segments 1..=`n` of `held` as the receiver (`receiver`) took
/// them; false when that breaks a rule (the transfer is then violated).
fn commit(
    o: &mut Open,
    b: &mut Blocks,
    held: &SubBlock,
    n: u8,
    receiver: Side,
    out: &mut Sink,
) -> bool {
    for seqno in 1..=n {
        let Some((data, last)) = held.segment(seqno) else {
            break;
        };
        match b.rx.commit(data, last) {
            Ok(Some((offset, data))) => o.deliver(offset, data, out),
            Ok(None) => {}
            Err(code) => {
                o.violate(code, receiver);
                return false;
            }
        }
    }
    true
}

/// After an acknowledgement from `from`: the block size it gives for the
/// next sub-block must be valid unless the last segment is in.
fn next_block_size(o: &mut Open, mut b: Blocks, blksize: u8, from: Side) -> Option<End> {
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

/// The sender's end frame; `checker` is the receiver of the data. Sent
/// right after the last sub-block closed, it says the sender went on (see
/// [`went_on`]).
pub(super) fn end(
    o: &mut Open,
    (unused, crc): (u8, u16),
    bytes: &[u8],
    checker: Side,
    out: &mut Sink,
) -> Option<End> {
    if matches!(o.phase, Phase::SubBlocks(b) if b.closed && !b.rx.is_done()) {
        if let Some(broken) = went_on(o, out) {
            return Some(broken);
        }
    }
    let Phase::SubBlocks(Blocks { mut rx, .. }) = o.phase else {
        o.violate(AbortCode::InvalidCommandSpecifier, checker);
        return None;
    };
    if !rx.is_done() {
        o.violate(AbortCode::InvalidCommandSpecifier, checker);
        return None;
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
    None
}
