//! A sender a sub-block ahead of the receiver's acknowledgements (CiA 301
//! section 7.2.4.3 numbers the segments of a sub-block, not the
//! sub-blocks): it took a repeated acknowledgement for the one of the
//! sub-block it had just sent, so the next sub-block, or its end frame,
//! is on the bus before the receiver's own acknowledgement. The receiver
//! takes those segments (it numbers from 1 again after each sub-block it
//! acknowledged), and so must the observer: byte vectors of a block
//! download of 56 bytes (8 segments) in sub-blocks of 2 segments, no CRC.

use super::*;
extern crate std;
use std::vec::Vec;

const REQ: u16 = 0x605;
const RESP: u16 = 0x585;
/// Block download of 1F50h sub 1, 56 bytes indicated, no CRC.
const INITIATE: [u8; 8] = [0xC2, 0x50, 0x1F, 1, LEN as u8, 0, 0, 0];
const LEN: usize = 56;
/// The server's answer: no CRC, block size 2.
const ANSWER: [u8; 8] = [0xA0, 0x50, 0x1F, 1, 2, 0, 0, 0];
/// The server's acknowledgement of 2 segments, block size 2.
const ACK: [u8; 8] = [0xA2, 2, 2, 0, 0, 0, 0, 0];
/// The client's end frame: no unused bytes, CRC 0 (not in use).
const END: [u8; 8] = [0xC1, 0, 0, 0, 0, 0, 0, 0];
/// The server's confirmation.
const CONFIRM: [u8; 8] = [0xA1, 0, 0, 0, 0, 0, 0, 0];

/// The value's bytes 1..=56.
fn value() -> [u8; LEN] {
    core::array::from_fn(|i| i as u8 + 1)
}

/// Sub-block segment `seqno` carrying the value's segment `index`
/// (0-based, of 8), c on the last.
fn segment(seqno: u8, index: usize) -> [u8; 8] {
    let mut f = [0u8; 8];
    f[0] = seqno | if index == 7 { 0x80 } else { 0 };
    f[1..].copy_from_slice(&value()[index * 7..index * 7 + 7]);
    f
}

/// The value the observer delivered and its one terminal event, after
/// `frames` (requests and responses by their first byte) and the end of
/// the trace.
fn observe(frames: &[[u8; 8]]) -> (usize, [u8; LEN], ObserverEvent) {
    let mut obs: Observer = Observer::default();
    let mut value = [0u8; LEN];
    let mut len = 0;
    let mut ends = 0;
    let mut end = None;
    let mut take = |e: ObserverEvent| match e {
        ObserverEvent::Data { offset, data, .. } => {
            assert_eq!(offset, len, "data out of order");
            value[len..len + data.len()].copy_from_slice(data.as_slice());
            len += data.len();
        }
        e if e.is_terminal() => {
            ends += 1;
            end = Some(e);
        }
        _ => {}
    };
    for (i, f) in frames.iter().enumerate() {
        let id = if f[0] & 0xE0 == 0xA0 { RESP } else { REQ };
        obs.observe(
            Timestamp::from_millis(i as u64),
            &CanFrame::standard(id, f).unwrap(),
        );
        while let Some(e) = obs.poll_event() {
            take(e);
        }
    }
    while let Some(e) = obs.end_of_trace() {
        take(e);
    }
    assert_eq!(ends, 1, "not one terminal event");
    (len, value, end.unwrap())
}

/// Segments `from..to` of the value, numbered from 1 within sub-blocks
/// of 2 as the client sends them.
fn sub_blocks(from: usize, to: usize) -> impl Iterator<Item = [u8; 8]> {
    (from..to).map(|i| segment(if i % 2 == 0 { 1 } else { 2 }, i))
}

fn frames(parts: &[&[[u8; 8]]]) -> Vec<[u8; 8]> {
    parts.concat()
}

/// The client a sub-block ahead: the first acknowledgement comes twice,
/// the client sends segments 3-6 at once; then `acks` from the server,
/// segments 7-8 and `closing`.
fn one_sub_block_ahead(acks: &[[u8; 8]], closing: &[[u8; 8]]) -> Vec<[u8; 8]> {
    frames(&[
        &[INITIATE, ANSWER],
        &sub_blocks(0, 2).collect::<Vec<_>>(),
        &[ACK, ACK],
        &sub_blocks(2, 6).collect::<Vec<_>>(),
        acks,
        &sub_blocks(6, 8).collect::<Vec<_>>(),
        closing,
    ])
}

fn completes_with_every_byte(frames: &[[u8; 8]]) {
    let (len, got, end) = observe(frames);
    assert_eq!((len, &got[..]), (LEN, &value()[..]));
    assert!(
        matches!(end, ObserverEvent::Completed { bytes: LEN, .. }),
        "{end:?}"
    );
}

#[test]
fn sub_blocks_sent_before_the_acknowledgement_of_the_one_before_are_delivered() {
    // The first acknowledgement comes twice; the client takes the repeat
    // for the acknowledgement of segments 3-4, sent in reply to the first,
    // and sends 5-6 at once: both are on the bus before the server's
    // acknowledgement of 3-4.
    completes_with_every_byte(&one_sub_block_ahead(&[ACK, ACK], &[ACK, END, CONFIRM]));
    // Still a sub-block ahead at the end: the client's end frame comes
    // before the server's acknowledgement of the last sub-block, which the
    // client, waiting for the end confirmation, answers with 05040001h.
    let abort = [0x80, 0x50, 0x1F, 1, 0x01, 0x00, 0x04, 0x05];
    let (len, got, end) = observe(&one_sub_block_ahead(&[ACK, ACK], &[END, ACK, abort]));
    assert_eq!((len, &got[..]), (LEN, &value()[..]));
    assert!(
        matches!(
            end,
            ObserverEvent::Aborted {
                code: AbortCode::InvalidCommandSpecifier,
                by: Side::Client,
                bytes: LEN,
                ..
            }
        ),
        "{end:?}"
    );
}

#[test]
fn a_sender_ahead_whose_acknowledgement_is_lost_stays_one_behind_and_delivers_everything() {
    // Of the server's acknowledgements of 3-4 and 5-6 one is lost: the
    // client, a sub-block ahead, takes the other for the one of 5-6 and is
    // in step again; the observer reads each later acknowledgement as the
    // one of the sub-block before (the bytes are the same) and the end
    // frame as the client's word that the last one was taken.
    completes_with_every_byte(&one_sub_block_ahead(&[ACK], &[ACK, END, CONFIRM]));
}

#[test]
fn a_sender_going_on_past_segments_not_seen_breaks_the_transfer_off() {
    // Sub-blocks of 3: the second one's segment 2 is not in the trace, its
    // closing segment 3 is; the client goes on with a new segment 1 as if
    // the repeated acknowledgement (3) were the one of the second
    // sub-block: that acknowledges a segment the observer did not see.
    let answer = [0xA0, 0x50, 0x1F, 1, 3, 0, 0, 0];
    let ack = [0xA2, 3, 3, 0, 0, 0, 0, 0];
    let (len, _, end) = observe(&[
        INITIATE,
        answer,
        segment(1, 0),
        segment(2, 1),
        segment(3, 2),
        ack,
        ack,
        segment(1, 3),
        segment(3, 5),
        segment(1, 6),
    ]);
    assert_eq!(len, 21);
    assert!(
        matches!(
            end,
            ObserverEvent::BrokenOff {
                reason: BreakReason::AckMismatch {
                    expected: 1,
                    got: 3
                },
                bytes: 21,
                ..
            }
        ),
        "{end:?}"
    );
}

#[test]
fn a_segment_delayed_behind_the_closing_one_fills_its_gap() {
    // Segment 1 of the second sub-block arrives after its closing segment
    // 2 (reordered): it fills the gap, it does not begin a sub-block.
    let head = frames(&[
        &[INITIATE, ANSWER],
        &sub_blocks(0, 2).collect::<Vec<_>>(),
        &[ACK],
    ]);
    completes_with_every_byte(&frames(&[
        &head,
        &[segment(2, 3), segment(1, 2), ACK],
        &sub_blocks(4, 8).collect::<Vec<_>>()[..2],
        &[ACK],
        &sub_blocks(6, 8).collect::<Vec<_>>(),
        &[ACK, END, CONFIRM],
    ]));
}
