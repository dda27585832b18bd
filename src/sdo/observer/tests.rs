//! Byte vectors for the observer, written from the CiA 301 frame layouts
//! (section 7.2.4.3, SDO protocols): every transfer type both ways, the
//! rule breaks with and without the abort that answers them, lost and
//! repeated block segments, and the end of a trace.

use super::*;
use crate::machine::assert_quiet_until;
use crate::sdo::crc16;

const NODE: u8 = 5;
const REQ: u16 = 0x600 + NODE as u16;
const RESP: u16 = 0x580 + NODE as u16;

fn node() -> NodeId {
    NodeId::new(NODE).unwrap()
}

/// What the observer made of a run: every event, and the value collected
/// from the data events (checked to arrive in order, without gaps).
#[derive(Debug)]
struct Seen {
    events: [Option<ObserverEvent>; 64],
    n: usize,
    value: [u8; 256],
    len: usize,
    observed: [Option<Observed>; 64],
    frames: usize,
}

impl Default for Seen {
    fn default() -> Self {
        Seen {
            events: [None; 64],
            n: 0,
            value: [0; 256],
            len: 0,
            observed: [None; 64],
            frames: 0,
        }
    }
}

impl Seen {
    fn push(&mut self, e: ObserverEvent) {
        if let ObserverEvent::Data { offset, data, .. } = e {
            assert_eq!(offset, self.len, "data out of order");
            self.value[self.len..self.len + data.len()].copy_from_slice(data.as_slice());
            self.len += data.len();
        }
        self.events[self.n] = Some(e);
        self.n += 1;
    }

    fn value(&self) -> &[u8] {
        &self.value[..self.len]
    }

    fn events(&self) -> impl Iterator<Item = &ObserverEvent> {
        self.events.iter().flatten()
    }

    fn terminal(&self) -> [ObserverEvent; 1] {
        let mut ends = self.events().filter(|e| e.is_terminal());
        let end = *ends.next().expect("no terminal event");
        assert!(
            ends.next().is_none(),
            "more than one end: {:?}",
            self.events
        );
        [end]
    }
}

fn feed(obs: &mut Observer, frames: &[(u16, &[u8])]) -> Seen {
    let mut seen = Seen::default();
    for (i, (id, data)) in frames.iter().enumerate() {
        let now = Timestamp::from_millis(i as u64);
        obs.handle_timeout(now);
        let frame = CanFrame::standard(*id, data).unwrap();
        seen.observed[seen.frames] = Some(obs.observe(now, &frame));
        seen.frames += 1;
        while let Some(e) = obs.poll_event() {
            seen.push(e);
        }
    }
    seen
}

fn run(frames: &[(u16, &[u8])]) -> Seen {
    feed(&mut Observer::default(), frames)
}

/// [`run`], then the end of the trace.
fn run_to_the_end(frames: &[(u16, &[u8])]) -> Seen {
    let mut obs = Observer::default();
    let mut seen = feed(&mut obs, frames);
    while let Some(e) = obs.end_of_trace() {
        seen.push(e);
    }
    seen
}

fn completed(seen: &Seen) -> (Transfer, usize, bool) {
    match seen.terminal() {
        [ObserverEvent::Completed {
            transfer,
            bytes,
            crc_checked,
        }] => (transfer, bytes, crc_checked),
        other => panic!("not completed: {other:?}"),
    }
}

#[test]
fn expedited_upload_with_and_without_size() {
    let seen = run(&[
        (REQ, &[0x40, 0x17, 0x10, 0, 0, 0, 0, 0]),
        (RESP, &[0x4B, 0x17, 0x10, 0, 0xE8, 0x03, 0, 0]),
    ]);
    let (t, bytes, crc) = completed(&seen);
    assert_eq!(
        (t.index, t.sub, t.direction),
        (0x1017, 0, Direction::Upload)
    );
    assert_eq!(
        t.kind,
        Some(TransferKind::Expedited {
            size_indicated: true
        })
    );
    assert_eq!((t.indicated, bytes, crc), (Some(2), 2, false));
    assert_eq!(seen.value(), [0xE8, 0x03]);
    assert!(matches!(seen.events[0], Some(ObserverEvent::Started(s)) if s.kind.is_none()));

    // s = 0: "up to 4 bytes", every data byte.
    let seen = run(&[
        (REQ, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]),
        (RESP, &[0x42, 0x00, 0x10, 0, 1, 2, 3, 4]),
    ]);
    let (t, bytes, _) = completed(&seen);
    assert_eq!(
        (t.kind, t.indicated, bytes),
        (
            Some(TransferKind::Expedited {
                size_indicated: false
            }),
            None,
            4
        )
    );
}

#[test]
fn expedited_download_delivers_at_the_initiate_and_completes_at_the_answer() {
    let seen = run(&[
        (REQ, &[0x2B, 0x17, 0x10, 0, 0xA0, 0x0F, 0, 0]),
        (RESP, &[0x60, 0x17, 0x10, 0, 0, 0, 0, 0]),
    ]);
    let (t, bytes, _) = completed(&seen);
    assert_eq!(
        (t.direction, t.indicated, bytes),
        (Direction::Download, Some(2), 2)
    );
    assert_eq!(seen.value(), [0xA0, 0x0F]);
    assert!(matches!(
        seen.events[1],
        Some(ObserverEvent::Data { offset: 0, .. })
    ));
}

#[test]
fn segmented_upload_and_download() {
    let seen = run(&[
        (REQ, &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0]),
        (RESP, &[0x41, 0x08, 0x10, 0, 10, 0, 0, 0]),
        (REQ, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
        (RESP, &[0x00, b'I', b'C', b'L', b'1', b'5', b'0', b'0']),
        (REQ, &[0x70, 0, 0, 0, 0, 0, 0, 0]),
        (RESP, &[0x19, b' ', b'D', b'Q', 0, 0, 0, 0]),
    ]);
    let (t, bytes, _) = completed(&seen);
    assert_eq!(
        (t.kind, t.indicated, bytes),
        (Some(TransferKind::Segmented), Some(10), 10)
    );
    assert_eq!(seen.value(), b"ICL1500 DQ");

    let seen = run(&[
        (REQ, &[0x21, 0x00, 0x20, 1, 9, 0, 0, 0]),
        (RESP, &[0x60, 0x00, 0x20, 1, 0, 0, 0, 0]),
        (REQ, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
        (RESP, &[0x20, 0, 0, 0, 0, 0, 0, 0]),
        (REQ, &[0x1B, 8, 9, 0, 0, 0, 0, 0]),
        (RESP, &[0x30, 0, 0, 0, 0, 0, 0, 0]),
    ]);
    let (t, bytes, _) = completed(&seen);
    assert_eq!(
        (t.direction, t.indicated, bytes),
        (Direction::Download, Some(9), 9)
    );
    assert_eq!(seen.value(), [1, 2, 3, 4, 5, 6, 7, 8, 9]);
}

#[test]
fn a_repeated_toggle_waits_for_the_abort_it_calls_for() {
    let frames: [(u16, &[u8]); 5] = [
        (REQ, &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0]),
        (RESP, &[0x41, 0x08, 0x10, 0, 20, 0, 0, 0]),
        (REQ, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
        (RESP, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
        // The client asks with t = 0 again: the server must abort 05030000h.
        (REQ, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
    ];
    let mut obs: Observer = Observer::default();
    let mut seen = feed(&mut obs, &frames);
    assert!(seen.events().all(|e| !e.is_terminal()));
    let abort: [(u16, &[u8]); 1] = [(RESP, &[0x80, 0x08, 0x10, 0, 0, 0, 0x03, 0x05])];
    for e in feed(&mut obs, &abort).events() {
        seen.push(*e);
    }
    match seen.terminal() {
        [ObserverEvent::Aborted {
            code,
            by,
            expected,
            bytes,
            ..
        }] => {
            assert_eq!(
                (code, by, bytes),
                (AbortCode::ToggleBitNotAlternated, Side::Server, 7)
            );
            assert_eq!(expected, Some(AbortCode::ToggleBitNotAlternated));
        }
        other => panic!("{other:?}"),
    }

    // Without the abort: the next frame (a new initiate) ends it as the
    // violation, and the new transfer starts.
    let mut obs: Observer = Observer::default();
    feed(&mut obs, &frames);
    let next: [(u16, &[u8]); 1] = [(REQ, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0])];
    let seen = feed(&mut obs, &next);
    let mut events = seen.events();
    assert!(matches!(
        events.next(),
        Some(ObserverEvent::BrokenOff {
            reason: BreakReason::Violation {
                code: AbortCode::ToggleBitNotAlternated,
                by: Side::Server
            },
            ..
        })
    ));
    assert!(matches!(events.next(), Some(ObserverEvent::Started(t)) if t.index == 0x1000));
    assert_eq!(obs.open_transfers(), 1);
}

#[test]
fn sizes_and_objects_that_do_not_fit_are_rule_breaks() {
    // More than the indicated 3 bytes (06070012h for the client): flagged
    // and followed; the client's abort after it ends the transfer as the
    // abort the rule called for.
    let seen = run(&[
        (REQ, &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0]),
        (RESP, &[0x41, 0x08, 0x10, 0, 3, 0, 0, 0]),
        (REQ, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
        (RESP, &[0x01, 1, 2, 3, 4, 5, 6, 7]),
        (REQ, &[0x80, 0x08, 0x10, 0, 0x12, 0, 0x07, 0x06]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::Aborted {
            code: AbortCode::DataTypeLengthTooHigh,
            expected: Some(AbortCode::DataTypeLengthTooHigh),
            bytes: 7,
            ..
        }]
    ));
    // The same past a first full segment, 7 + 7 of 10 indicated, and no
    // abort (python-canopen's client reads on and keeps the indicated
    // size): the rule broken is reported, the transfer completes with
    // every byte the bus carried.
    let seen = run_to_the_end(&[
        (REQ, &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0]),
        (RESP, &[0x41, 0x08, 0x10, 0, 10, 0, 0, 0]),
        (REQ, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
        (RESP, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
        (REQ, &[0x70, 0, 0, 0, 0, 0, 0, 0]),
        (RESP, &[0x11, 8, 9, 10, 11, 12, 13, 14]),
    ]);
    assert!(seen.events().any(|e| matches!(
        e,
        ObserverEvent::RuleBroken {
            code: AbortCode::DataTypeLengthTooHigh,
            by: Side::Client,
            ..
        }
    )));
    assert_eq!(completed(&seen).1, 14);
    assert_eq!(
        seen.value(),
        [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14]
    );
    // The answer names another object: 06040043h.
    let seen = run(&[
        (REQ, &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0]),
        (RESP, &[0x4F, 0x09, 0x10, 0, 1, 0, 0, 0]),
        (REQ, &[0x80, 0x08, 0x10, 0, 0x43, 0, 0x04, 0x06]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::Aborted {
            expected: Some(AbortCode::GeneralParameterIncompatibility),
            ..
        }]
    ));
}

#[test]
fn a_new_initiate_breaks_off_the_open_transfer() {
    let seen = run(&[
        (REQ, &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0]),
        (REQ, &[0x40, 0x09, 0x10, 0, 0, 0, 0, 0]),
        (RESP, &[0x4F, 0x09, 0x10, 0, 7, 0, 0, 0]),
    ]);
    let ends: [_; 2] =
        core::array::from_fn(|i| *seen.events().filter(|e| e.is_terminal()).nth(i).unwrap());
    assert!(matches!(
        ends[0],
        ObserverEvent::BrokenOff {
            transfer: Transfer { index: 0x1008, .. },
            reason: BreakReason::NewInitiate,
            bytes: 0,
            pending: 0,
        }
    ));
    assert!(matches!(ends[1], ObserverEvent::Completed { bytes: 1, .. }));
}

#[test]
fn a_server_abort_and_a_client_abort() {
    let seen = run(&[
        (REQ, &[0x40, 0x99, 0x20, 0, 0, 0, 0, 0]),
        (RESP, &[0x80, 0x99, 0x20, 0, 0, 0, 0x02, 0x06]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::Aborted {
            code: AbortCode::ObjectDoesNotExist,
            by: Side::Server,
            expected: None,
            ..
        }]
    ));
    // A stray abort (no transfer open) ends nothing.
    let seen = run(&[(REQ, &[0x80, 0x99, 0x20, 0, 0, 0, 0x04, 0x05])]);
    assert_eq!(seen.n, 0);
}

/// A block download of `value` with CRC: the frames, sub-blocks of
/// `blksize`, optionally without segment `lose` of the first sub-block (the
/// server then acknowledges the one before, and the client resends).
fn block_download(value: &[u8], blksize: u8, lose: Option<u8>) -> ([[u8; 8]; 48], usize) {
    let mut frames = [[0u8; 8]; 48];
    let mut n = 0;
    let mut put = |f: [u8; 8]| {
        frames[n] = f;
        n += 1;
    };
    let size = (value.len() as u32).to_le_bytes();
    put([0xC6, 0x50, 0x1F, 1, size[0], size[1], size[2], size[3]]);
    put([0xA4, 0x50, 0x1F, 1, blksize, 0, 0, 0]);
    let segments: usize = value.len().div_ceil(7).max(1);
    let mut next = 0;
    let mut lost = lose;
    while next < segments {
        let mut seq = 0u8;
        let mut acked = None;
        while seq < blksize && next + usize::from(seq) < segments {
            let i = next + usize::from(seq);
            seq += 1;
            let last = i + 1 == segments;
            let mut f = [0u8; 8];
            f[0] = seq | if last { 0x80 } else { 0 };
            let chunk = &value[i * 7..value.len().min(i * 7 + 7)];
            f[1..1 + chunk.len()].copy_from_slice(chunk);
            if lost == Some(seq) {
                lost = None;
                acked.get_or_insert(seq - 1);
                continue;
            }
            put(f);
        }
        let ackseq = acked.unwrap_or(seq);
        put([0xA2, ackseq, blksize, 0, 0, 0, 0, 0]);
        next += usize::from(ackseq);
    }
    let unused = (segments * 7 - value.len()) as u8;
    let crc = crc16(value).to_le_bytes();
    put([0xC1 | unused << 2, crc[0], crc[1], 0, 0, 0, 0, 0]);
    put([0xA1, 0, 0, 0, 0, 0, 0, 0]);
    (frames, n)
}

fn frames_of(frames: &[[u8; 8]]) -> impl Iterator<Item = (u16, &[u8])> {
    frames.iter().map(|f| {
        // Every frame of the download goes client to server except the
        // server's answers (scs 5: A0h-A7h, and the aborts it sends).
        let from_server = matches!(f[0] & 0xE0, 0xA0);
        (if from_server { RESP } else { REQ }, &f[..])
    })
}

fn run_frames<'a>(frames: impl Iterator<Item = (u16, &'a [u8])>) -> Seen {
    let mut obs: Observer = Observer::default();
    let mut seen = Seen::default();
    for (i, (id, data)) in frames.enumerate() {
        let frame = CanFrame::standard(id, data).unwrap();
        seen.observed[seen.frames] = Some(obs.observe(Timestamp::from_millis(i as u64), &frame));
        seen.frames += 1;
        while let Some(e) = obs.poll_event() {
            seen.push(e);
        }
    }
    seen
}

#[test]
fn block_download_with_crc_is_reassembled_and_its_segments_named() {
    let value: [u8; 30] = core::array::from_fn(|i| i as u8 * 3);
    let (frames, n) = block_download(&value, 3, None);
    let seen = run_frames(frames_of(&frames[..n]));
    let (t, bytes, crc_checked) = completed(&seen);
    assert_eq!(seen.value(), value);
    assert_eq!(
        (t.kind, t.indicated, bytes, crc_checked),
        (Some(TransferKind::Block { crc: true }), Some(30), 30, true)
    );
    // Frame 2 is sequence number 1 of the first sub-block; the fifth
    // segment (sub-block 2, seq 2) ends the value with the last flag.
    assert!(matches!(
        seen.observed[2],
        Some(Observed::BlockSegment {
            seqno: 1,
            last: false,
            from: Side::Client,
            ..
        })
    ));
    let last_segment = seen
        .observed
        .iter()
        .flatten()
        .filter(|o| matches!(o, Observed::BlockSegment { last: true, .. }))
        .count();
    assert_eq!(last_segment, 1);
}

#[test]
fn a_lost_block_segment_and_its_retransmission() {
    let value: [u8; 40] = core::array::from_fn(|i| 200 - i as u8);
    let (frames, n) = block_download(&value, 4, Some(2));
    let seen = run_frames(frames_of(&frames[..n]));
    assert_eq!(seen.value(), value);
    let (_, bytes, crc) = completed(&seen);
    assert_eq!((bytes, crc), (40, true));
}

#[test]
fn a_crc_mismatch_is_due_an_abort_05040004h() {
    let value = [7u8; 12];
    let (mut frames, n) = block_download(&value, 127, None);
    frames[n - 2][1] ^= 0xFF;
    frames[n - 1] = [0x80, 0x50, 0x1F, 1, 0x04, 0, 0x04, 0x05];
    let seen = run_frames(frames[..n].iter().map(|f| {
        let from_server = matches!(f[0] & 0xE0, 0xA0) || f == &frames[n - 1];
        (if from_server { RESP } else { REQ }, &f[..])
    }));
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::Aborted {
            code: AbortCode::CrcError,
            by: Side::Server,
            expected: Some(AbortCode::CrcError),
            ..
        }]
    ));
}

#[test]
fn an_acknowledgement_of_segments_not_seen_breaks_the_transfer_off() {
    // Segment 2 is not in the trace, the receiver acknowledges 2.
    let seen = run(&[
        (REQ, &[0xC6, 0x50, 0x1F, 1, 21, 0, 0, 0]),
        (RESP, &[0xA4, 0x50, 0x1F, 1, 3, 0, 0, 0]),
        (REQ, &[0x01, 1, 2, 3, 4, 5, 6, 7]),
        (REQ, &[0x83, 15, 16, 17, 18, 19, 20, 21]),
        (RESP, &[0xA2, 0x02, 3, 0, 0, 0, 0, 0]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::BrokenOff {
            reason: BreakReason::AckMismatch {
                expected: 1,
                got: 2
            },
            bytes: 0,
            pending: 0,
            ..
        }]
    ));
    assert_eq!(seen.value(), b"");
}

#[test]
fn fewer_segments_acknowledged_than_seen_commit_only_those() {
    // Both segments seen, the receiver takes only the first: 7 bytes are
    // delivered at the ack, the last segment waits for its resending, and
    // the trace ends before it.
    let seen = run_to_the_end(&[
        (REQ, &[0xC6, 0x50, 0x1F, 1, 14, 0, 0, 0]),
        (RESP, &[0xA4, 0x50, 0x1F, 1, 2, 0, 0, 0]),
        (REQ, &[0x01, 1, 2, 3, 4, 5, 6, 7]),
        (REQ, &[0x82, 8, 9, 10, 11, 12, 13, 14]),
        (RESP, &[0xA2, 0x01, 2, 0, 0, 0, 0, 0]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::BrokenOff {
            reason: BreakReason::EndOfTrace,
            bytes: 7,
            pending: 0,
            ..
        }]
    ));
    assert_eq!(seen.value(), [1, 2, 3, 4, 5, 6, 7]);
}

#[test]
fn crash_sequences_end_in_the_abort_they_call_for() {
    // Block size 0 in the initiate response: 05040002h from the client.
    let seen = run(&[
        (REQ, &[0xC6, 0x50, 0x1F, 1, 14, 0, 0, 0]),
        (RESP, &[0xA4, 0x50, 0x1F, 1, 0, 0, 0, 0]),
        (REQ, &[0x80, 0x50, 0x1F, 1, 0x02, 0, 0x04, 0x05]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::Aborted {
            expected: Some(AbortCode::InvalidBlockSize),
            ..
        }]
    ));
    // A segment numbered above the block size: 05040003h from the server;
    // the frames after it (no abort came) complete nothing.
    let seen = run(&[
        (REQ, &[0xC6, 0x50, 0x1F, 1, 3, 0, 0, 0]),
        (RESP, &[0xA4, 0x50, 0x1F, 1, 1, 0, 0, 0]),
        (REQ, &[0x82, 1, 2, 3, 0, 0, 0, 0]),
        (RESP, &[0xA2, 1, 1, 0, 0, 0, 0, 0]),
        (REQ, &[0xD1, 0, 0, 0, 0, 0, 0, 0]),
        (RESP, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::BrokenOff {
            reason: BreakReason::Violation {
                code: AbortCode::InvalidSequenceNumber,
                by: Side::Server
            },
            ..
        }]
    ));
    // Two negative acknowledgements in a row (ackseq 0 twice) of a segment
    // that was on the bus: the receiver took nothing either time, so
    // nothing is delivered; then the abort.
    let seen = run(&[
        (REQ, &[0xC6, 0x50, 0x1F, 1, 3, 0, 0, 0]),
        (RESP, &[0xA4, 0x50, 0x1F, 1, 1, 0, 0, 0]),
        (REQ, &[0x81, 1, 2, 3, 0, 0, 0, 0]),
        (RESP, &[0xA2, 0, 1, 0, 0, 0, 0, 0]),
        (REQ, &[0x81, 1, 2, 3, 0, 0, 0, 0]),
        (RESP, &[0xA2, 0, 1, 0, 0, 0, 0, 0]),
        (REQ, &[0x81, 1, 2, 3, 0, 0, 0, 0]),
        (REQ, &[0x80, 0x50, 0x1F, 1, 0, 0, 0x04, 0x05]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::Aborted {
            code: AbortCode::SdoProtocolTimedOut,
            by: Side::Client,
            bytes: 0,
            // The last segment's 7 data bytes (its end frame would say how
            // many are the value's).
            pending: 7,
            ..
        }]
    ));
    assert_eq!(seen.value(), b"");
    // An abort in the middle of a sub-block.
    let seen = run(&[
        (REQ, &[0xC2, 0x50, 0x1F, 1, 21, 0, 0, 0]),
        (RESP, &[0xA0, 0x50, 0x1F, 1, 127, 0, 0, 0]),
        (REQ, &[0x01, 1, 2, 3, 4, 5, 6, 7]),
        (REQ, &[0x80, 0x50, 0x1F, 1, 0, 0, 0, 0x08]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::Aborted {
            by: Side::Client,
            // Segment 1 was never acknowledged: held, not delivered.
            bytes: 0,
            pending: 7,
            expected: None,
            ..
        }]
    ));
    // An end frame claiming more than 7 unused bytes... cannot be encoded
    // (n is 3 bits); claiming more than the last segment leaves: 05040001h.
    let seen = run(&[
        (REQ, &[0xC2, 0x50, 0x1F, 1, 2, 0, 0, 0]),
        (RESP, &[0xA0, 0x50, 0x1F, 1, 127, 0, 0, 0]),
        (REQ, &[0x81, 1, 2, 0, 0, 0, 0, 0]),
        (RESP, &[0xA2, 1, 127, 0, 0, 0, 0, 0]),
        (REQ, &[0xDD, 0, 0, 0, 0, 0, 0, 0]),
        (RESP, &[0x80, 0x50, 0x1F, 1, 0x01, 0, 0x04, 0x05]),
    ]);
    assert!(matches!(
        seen.terminal(),
        [ObserverEvent::Aborted {
            expected: Some(AbortCode::DataTypeLengthTooLow),
            ..
        }] | [ObserverEvent::Aborted {
            expected: Some(AbortCode::InvalidCommandSpecifier),
            ..
        }]
    ));
}

#[test]
fn block_upload_of_an_empty_object_and_the_protocol_switch() {
    let seen = run(&[
        (REQ, &[0xA4, 0x08, 0x10, 0, 127, 0, 0, 0]),
        (RESP, &[0xC6, 0x08, 0x10, 0, 0, 0, 0, 0]),
        (REQ, &[0xA3, 0, 0, 0, 0, 0, 0, 0]),
        (RESP, &[0x81, 0, 0, 0, 0, 0, 0, 0]),
        (REQ, &[0xA2, 1, 127, 0, 0, 0, 0, 0]),
        (RESP, &[0xDD, 0, 0, 0, 0, 0, 0, 0]),
        (REQ, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
    ]);
    let (t, bytes, crc) = completed(&seen);
    assert_eq!(
        (t.direction, t.indicated, bytes, crc),
        (Direction::Upload, Some(0), 0, true)
    );
    assert!(matches!(
        seen.observed[3],
        Some(Observed::BlockSegment {
            seqno: 1,
            last: true,
            from: Side::Server,
            ..
        })
    ));
    // The server answers a block upload with a normal (expedited) upload.
    let seen = run(&[
        (REQ, &[0xA4, 0x17, 0x10, 0, 127, 4, 0, 0]),
        (RESP, &[0x4B, 0x17, 0x10, 0, 0xE8, 0x03, 0, 0]),
    ]);
    let (t, bytes, _) = completed(&seen);
    assert_eq!(
        (t.kind, bytes),
        (
            Some(TransferKind::Expedited {
                size_indicated: true
            }),
            2
        )
    );
}

#[test]
fn silence_breaks_a_transfer_off_at_the_timeout() {
    let mut obs: Observer = Observer::new(ObserverConfig {
        default_channels: true,
        timeout: Some(Duration::from_millis(100)),
    });
    let f = CanFrame::standard(REQ, &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0]).unwrap();
    obs.observe(Timestamp::from_millis(10), &f);
    while obs.poll_event().is_some() {}
    assert_quiet_until(&mut obs, Timestamp::from_millis(110));
    assert_eq!(obs.poll_event(), None);
    obs.handle_timeout(Timestamp::from_millis(110));
    assert!(matches!(
        obs.poll_event(),
        Some(ObserverEvent::BrokenOff {
            reason: BreakReason::Timeout,
            ..
        })
    ));
    assert_eq!(obs.poll_timeout(), None);
    assert_eq!(obs.open_transfers(), 0);
}

#[test]
fn the_end_of_a_trace_reports_every_open_transfer_once_even_beyond_the_queue() {
    let mut obs: Observer = Observer::default();
    for index in [0x08u8, 0x09] {
        for n in 1..=127u16 {
            let f = CanFrame::standard(0x600 + n, &[0x40, index, 0x10, 0, 0, 0, 0, 0]).unwrap();
            obs.observe(Timestamp::ZERO, &f);
        }
    }
    // 127 started events, then 127 broken off and 127 started again, into
    // a queue of 136: the oldest are dropped (the last ones are starts).
    assert_eq!(
        obs.events_dropped(),
        3 * 127 - OBSERVER_EVENT_CAPACITY as u64
    );
    assert_eq!(obs.open_transfers(), 127);
    let (mut broken, mut started, mut superseded) = (0, 0, 0);
    while let Some(e) = obs.end_of_trace() {
        match e {
            ObserverEvent::BrokenOff {
                reason: BreakReason::EndOfTrace,
                ..
            } => broken += 1,
            ObserverEvent::BrokenOff {
                reason: BreakReason::NewInitiate,
                ..
            } => superseded += 1,
            ObserverEvent::Started(_) => started += 1,
            other => panic!("{other:?}"),
        }
    }
    let kept = OBSERVER_EVENT_CAPACITY / 2;
    assert_eq!((broken, started, superseded), (127, kept, kept));
    assert_eq!(obs.open_transfers(), 0);
}

#[test]
fn extra_channels_and_what_is_not_sdo() {
    let mut obs: Observer<2> = Observer::with_extra_channels(ObserverConfig {
        default_channels: false,
        timeout: None,
    });
    let ch = SdoChannel {
        node: NodeId::new(65).unwrap(),
        request: CanId::Standard(0x241),
        response: CanId::Standard(0x1C1),
    };
    obs.add_channel(ch).unwrap();
    assert_eq!(
        obs.add_channel(ch),
        Err(ChannelError::Taken(CanId::Standard(0x241)))
    );
    let same = SdoChannel {
        response: ch.request,
        ..ch
    };
    assert_eq!(obs.add_channel(same), Err(ChannelError::SameId(ch.request)));
    obs.add_channel(SdoChannel::default_for(node())).unwrap();
    let third = SdoChannel::default_for(NodeId::new(6).unwrap());
    assert_eq!(
        obs.add_channel(third),
        Err(ChannelError::Full { capacity: 2 })
    );

    let f = CanFrame::standard(0x241, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]).unwrap();
    assert!(
        matches!(obs.observe(Timestamp::ZERO, &f), Observed::Request { channel, .. } if channel == ch)
    );
    assert_eq!(obs.open_transfer(ch).map(|t| t.index), Some(0x1000));
    let f = CanFrame::standard(0x1C1, &[0x43, 0x00, 0x10, 0, 0x92, 1, 2, 0]).unwrap();
    assert!(matches!(
        obs.observe(Timestamp::ZERO, &f),
        Observed::Response { .. }
    ));
    assert!(matches!(obs.poll_event(), Some(ObserverEvent::Started(_))));
    assert!(matches!(obs.poll_event(), Some(ObserverEvent::Data { .. })));
    assert!(matches!(
        obs.poll_event(),
        Some(ObserverEvent::Completed { bytes: 4, .. })
    ));
    // Defaults off: node 6's channel is not watched.
    let f = CanFrame::standard(0x606, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]).unwrap();
    assert_eq!(obs.observe(Timestamp::ZERO, &f), Observed::Other);
    // A remote frame and a frame too short for its command.
    let r = CanFrame::remote(CanId::Standard(0x605), 8).unwrap();
    assert_eq!(obs.observe(Timestamp::ZERO, &r), Observed::Other);
    let short = CanFrame::standard(0x605, &[0x40, 0x00]).unwrap();
    assert!(matches!(
        obs.observe(Timestamp::ZERO, &short),
        Observed::Malformed {
            from: Side::Client,
            ..
        }
    ));
    assert_eq!(obs.poll_transmit(), None);
}

#[cfg(feature = "alloc")]
#[path = "pair_tests.rs"]
mod pair;
