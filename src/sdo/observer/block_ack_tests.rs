//! Block transfers read at the receiver's acknowledgement (CiA 301 section
//! 7.2.4.3, SDO block download: the acknowledgement carries ackseq, the
//! last segment the receiver took in order, and the sender resends the
//! ones after it in the next sub-block, numbered from 1): byte vectors of a
//! lost or late segment, a receiver that takes only what came in order and
//! one that takes a late segment too, duplicates, the end of a trace before
//! an acknowledgement, and a pool with no buffer free.

use super::*;
extern crate std;
use std::vec::Vec;

const REQ: u16 = 0x605;
const RESP: u16 = 0x585;

/// Node 5, block download of 2E01h sub 1, 392 bytes indicated, no CRC.
const INITIATE: [u8; 8] = [0xC2, 0x01, 0x2E, 1, 0x88, 0x01, 0, 0];
/// The server's answer: no CRC, block size 127.
const ANSWER: [u8; 8] = [0xA0, 0x01, 0x2E, 1, 127, 0, 0, 0];
/// 56 segments of 7 bytes.
const LEN: usize = 392;
/// The client's end frame: no unused bytes in the last segment, CRC 0.
const END: [u8; 8] = [0xC1, 0, 0, 0, 0, 0, 0, 0];
/// The server's confirmation.
const CONFIRM: [u8; 8] = [0xA1, 0, 0, 0, 0, 0, 0, 0];

fn value() -> [u8; LEN] {
    core::array::from_fn(|i| (i * 7 + 1) as u8)
}

/// Segment `seqno` carrying the value's segment `index` (0-based), with c
/// on the value's last one.
fn segment(seqno: u8, index: usize) -> [u8; 8] {
    let v = value();
    let mut f = [0u8; 8];
    f[0] = seqno | if index + 1 == LEN / 7 { 0x80 } else { 0 };
    f[1..].copy_from_slice(&v[index * 7..index * 7 + 7]);
    f
}

/// The server's acknowledgement of `ackseq` with block size 127.
fn ack(ackseq: u8) -> [u8; 8] {
    [0xA2, ackseq, 127, 0, 0, 0, 0, 0]
}

/// What the observer made of a run: the value from the data events (in
/// order, no gaps), and the terminal events.
struct Read {
    value: [u8; 1024],
    len: usize,
    ends: [Option<ObserverEvent>; 4],
    n_ends: usize,
}

impl Read {
    fn new() -> Self {
        Read {
            value: [0; 1024],
            len: 0,
            ends: [None; 4],
            n_ends: 0,
        }
    }

    fn take(&mut self, e: ObserverEvent) {
        match e {
            ObserverEvent::Data { offset, data, .. } => {
                assert_eq!(offset, self.len, "data out of order");
                self.value[self.len..self.len + data.len()].copy_from_slice(data.as_slice());
                self.len += data.len();
            }
            e if e.is_terminal() => {
                self.ends[self.n_ends] = Some(e);
                self.n_ends += 1;
            }
            _ => {}
        }
    }

    fn value(&self) -> &[u8] {
        &self.value[..self.len]
    }

    fn end(&self) -> ObserverEvent {
        assert_eq!(self.n_ends, 1, "{:?}", self.ends);
        self.ends[0].unwrap()
    }
}

/// Feeds `frames` (from the server when byte 0 is A0h-A2h, the answers
/// of a block download; no segment here is a last one numbered 32-34)
/// to `obs`, one millisecond apart, draining after every frame; then the
/// end of the trace when `end`.
fn feed<const E: usize, const B: usize>(
    obs: &mut Observer<E, B>,
    frames: &[[u8; 8]],
    end: bool,
) -> Read {
    let mut read = Read::new();
    feed_into(obs, frames, end, &mut read);
    read
}

/// [`feed`], adding to `read`.
fn feed_into<const E: usize, const B: usize>(
    obs: &mut Observer<E, B>,
    frames: &[[u8; 8]],
    end: bool,
    read: &mut Read,
) {
    for (i, f) in frames.iter().enumerate() {
        let id = if matches!(f[0], 0xA0..=0xA2) {
            RESP
        } else {
            REQ
        };
        let frame = CanFrame::standard(id, f).unwrap();
        obs.observe(Timestamp::from_millis(i as u64), &frame);
        while let Some(e) = obs.poll_event() {
            read.take(e);
        }
    }
    if end {
        while let Some(e) = obs.end_of_trace() {
            read.take(e);
        }
    }
}

/// Up to 80 frames.
struct Frames {
    f: [[u8; 8]; 80],
    n: usize,
}

impl Frames {
    fn new() -> Self {
        let mut f = Frames {
            f: [[0; 8]; 80],
            n: 0,
        };
        f.put(INITIATE);
        f.put(ANSWER);
        f
    }
    fn put(&mut self, frame: [u8; 8]) {
        self.f[self.n] = frame;
        self.n += 1;
    }
    fn all(&self) -> &[[u8; 8]] {
        &self.f[..self.n]
    }
    /// Segments numbered `seqs`, each carrying the value's segment of its
    /// number (the first sub-block, as the sender sends it).
    fn segments(&mut self, seqs: impl IntoIterator<Item = u8>) {
        for seq in seqs {
            self.put(segment(seq, usize::from(seq) - 1));
        }
    }
    /// After an acknowledgement of 50: the sender's next sub-block,
    /// segments 51..=56 of the value numbered 1..=6, its acknowledgement,
    /// and the end.
    fn resent_from_51(&mut self) {
        for seq in 1..=6u8 {
            self.put(segment(seq, 49 + usize::from(seq)));
        }
        self.put(ack(6));
        self.end();
    }
    /// The client's end frame and the server's confirmation.
    fn end(&mut self) {
        self.put(END);
        self.put(CONFIRM);
    }
}

/// [`feed`] of `frames` to a fresh observer, to the end of the trace.
fn feed_fresh(frames: &[[u8; 8]]) -> Read {
    feed(&mut Observer::new(ObserverConfig::default()), frames, true)
}

/// The whole value was delivered and the transfer completed (no CRC).
fn assert_completed(read: &Read) {
    assert_eq!(read.value(), value());
    let end = read.end();
    assert!(
        matches!(
            end,
            ObserverEvent::Completed {
                bytes: LEN,
                crc_checked: false,
                ..
            }
        ),
        "{end:?}"
    );
}

#[test]
fn a_lost_segment_acknowledged_at_50_and_resent_from_51() {
    // Segment 51 is lost; 52..=56 come out of order and the receiver takes
    // none of them: it acknowledges 50. The sender resends segments 51..=56
    // of the value as sequence numbers 1..=6 of the next sub-block.
    let mut f = Frames::new();
    f.segments(1..=50u8);
    f.segments(52..=56u8);
    f.put(ack(50));
    let mut obs: Observer = Observer::default();
    let first = feed(&mut obs, f.all(), false);
    // Exactly the first 50 segments are delivered, at the acknowledgement.
    assert_eq!(first.value(), &value()[..350]);
    assert_eq!(first.n_ends, 0);

    let mut f = Frames::new();
    f.resent_from_51();
    let mut read = first;
    feed_into(&mut obs, &f.all()[2..], true, &mut read);
    assert_completed(&read);
}

#[test]
fn a_late_segment_a_receiver_took_is_delivered_as_acknowledged() {
    // Segment 51 comes after 52: a receiver that buffers takes it and
    // acknowledges 56 (the ack decides); one that does not acknowledges
    // 50 and the sender resends from 51.
    let mut f = Frames::new();
    f.segments((1..=50u8).chain([52, 51]).chain(53..=56));
    let segments_end = f.n;
    f.put(ack(56));
    f.end();
    assert_completed(&feed_fresh(f.all()));

    // The in-order receiver: ack 50, then 51..=56 again as 1..=6.
    let mut f2 = Frames::new();
    for frame in &f.all()[2..segments_end] {
        f2.put(*frame);
    }
    f2.put(ack(50));
    f2.resent_from_51();
    assert_completed(&feed_fresh(f2.all()));
}

#[test]
fn segments_repeated_around_the_acknowledgement_are_held_once() {
    // Each sub-block (by sequence number) is acknowledged at 56, with
    // `after` between the acknowledgement and the end frame: the bytes are
    // those of each sequence number, once.
    let in_order: Vec<u8> = (1..=56).collect();
    // Segment 3 twice, 10 twice after an out-of-order 12.
    let duplicated: Vec<u8> = [1, 2, 3, 3, 4, 5, 6, 7, 8, 9, 10, 12, 10, 11]
        .into_iter()
        .chain(13..=56)
        .collect();
    // The receiver ignores a repeat of the segment it acknowledged last;
    // after the last one it is not the end frame either.
    let repeated_last = [segment(56, 55)];
    for (seqs, after) in [(&duplicated, &[][..]), (&in_order, &repeated_last[..])] {
        let mut f = Frames::new();
        f.segments(seqs.iter().copied());
        f.put(ack(56));
        for frame in after {
            f.put(*frame);
        }
        f.end();
        assert_completed(&feed_fresh(f.all()));
    }
}

/// The observer delivered nothing and broke the transfer off: the bytes
/// it held back unacknowledged, and why.
fn broken_off_undelivered(read: &Read) -> (usize, BreakReason) {
    assert_eq!(read.value(), b"");
    match read.end() {
        ObserverEvent::BrokenOff {
            bytes: 0,
            pending,
            reason,
            ..
        } => (pending, reason),
        e => panic!("{e:?}"),
    }
}

#[test]
fn segments_never_acknowledged_are_not_delivered() {
    let mut f = Frames::new();
    f.segments(1..=20u8);
    // The trace ends before the acknowledgement.
    let not_seen = |trace_ended| BreakReason::AckNotSeen {
        segments: 20,
        trace_ended,
    };
    assert_eq!(
        broken_off_undelivered(&feed_fresh(f.all())),
        (140, not_seen(true))
    );
    // Silence instead: the timeout says the same.
    let mut obs: Observer = Observer::new(ObserverConfig {
        default_channels: true,
        timeout: Some(Duration::from_millis(100)),
    });
    let mut read = feed(&mut obs, f.all(), false);
    obs.handle_timeout(Timestamp::from_millis(1_000));
    while let Some(e) = obs.poll_event() {
        read.take(e);
    }
    assert_eq!(broken_off_undelivered(&read), (140, not_seen(false)));
    // An acknowledgement of 0: nothing taken, nothing delivered, the
    // transfer goes on.
    let mut f = Frames::new();
    f.put(segment(2, 1));
    f.put(ack(0));
    assert_eq!(
        broken_off_undelivered(&feed_fresh(f.all())),
        (0, BreakReason::EndOfTrace)
    );
}

#[test]
fn with_every_buffer_lent_a_block_transfer_ends_as_no_sub_block_buffer() {
    // One buffer; node 5 holds it with a sub-block in flight when node 6's
    // first segment comes.
    let mut obs: Observer<0, 1> = Observer::with_capacity(ObserverConfig::default());
    let mut read = feed(&mut obs, &[INITIATE, ANSWER, segment(1, 0)], false);
    let node6 = |f: [u8; 8], from_server: bool| {
        CanFrame::standard(if from_server { 0x586 } else { 0x606 }, &f).unwrap()
    };
    for (f, s) in [(INITIATE, false), (ANSWER, true), (segment(1, 0), false)] {
        obs.observe(Timestamp::from_millis(10), &node6(f, s));
        while let Some(e) = obs.poll_event() {
            read.take(e);
        }
    }
    match read.end() {
        ObserverEvent::BrokenOff {
            transfer,
            reason: BreakReason::NoSubBlockBuffer { buffers: 1 },
            pending: 0,
            ..
        } => assert_eq!(transfer.channel.node.raw(), 6),
        e => panic!("{e:?}"),
    }
    // Node 5's acknowledgement frees it: node 6's next transfer has it.
    let more = feed(&mut obs, &[ack(1)], false);
    assert_eq!(more.value(), &value()[..7]);
    for (f, s) in [
        (INITIATE, false),
        (ANSWER, true),
        (segment(1, 0), false),
        (ack(1), true),
    ] {
        obs.observe(Timestamp::from_millis(20), &node6(f, s));
    }
    let mut data = 0;
    while let Some(e) = obs.poll_event() {
        assert!(!e.is_terminal(), "{e:?}");
        data += usize::from(matches!(e, ObserverEvent::Data { .. }));
    }
    assert_eq!(data, 1);
}
