//! The SDO server under an arbitrary sequence of received frames and time
//! steps, run on two copies side by side: one whose events are read after
//! every call, one whose events are read only when the input says so.
//! Invariants: no panic; at most one transfer in progress; every frame sent
//! is on the server's response identifier with DLC 8, and each drain of the
//! transmit queue is at most one valid SDO response followed by at most one
//! block upload sub-block (segments numbered 1, 2, .. up to 127, only the
//! last may carry the last flag); both copies send exactly the same frames, keep the same
//! timers and end with the same dictionary (an undrained event queue never
//! changes protocol behaviour); the undrained copy's events are the drained
//! copy's with exactly `events_dropped` of them left out; a running
//! transfer ends in exactly one terminal event; the dictionary only ever
//! holds values the size rules allow.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, MemoryDictionary, ObjectDictionary};
use canopen_codec::sdo::{AbortOrigin, SdoResponse, Server, ServerCommand, ServerConfig, ServerEvent};
use canopen_codec::{CanFrame, CanId, Codec, NodeId, Timestamp};
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    /// A request frame; `shape` picks a well-formed command to steer the fuzzer.
    Frame { other: bool, remote: bool, shape: u8, data: [u8; 8], len: u8 },
    Advance { micros: u32, backwards: bool },
    /// A well-formed block transfer request on a known object.
    BlockRequest { kind: u8, object: u8, a: u8, b: u8, data: [u8; 7] },
    /// Read the second copy's events now.
    ReadUndrained,
}

const NODE: u8 = 4;
const OBJECTS: [u16; 6] = [0x1000, 0x1017, 0x2000, 0x2001, 0x1008, 0x2002];

fn dictionary() -> MemoryDictionary {
    let mut od = MemoryDictionary::new();
    od.insert(0x1000, 0, Access::Const, &[0xA2, 0x01, 0x0F, 0x00]);
    od.insert(0x1017, 0, Access::ReadWrite, &[0xE8, 0x03]);
    od.insert(0x2000, 0, Access::WriteOnly, &[0; 4]);
    od.insert(0x2001, 0, Access::ReadWrite, &[0; 8]);
    od.insert_variable(0x1008, 0, Access::ReadWrite, b"battery module", 20);
    od.insert_variable(0x2002, 0, Access::ReadWrite, &[], 0);
    od
}

/// A valid SDO response (not a sub-block segment).
fn is_response(f: &CanFrame) -> bool {
    SdoResponse::parse(f.data()).is_ok_and(|r| !matches!(r.command, ServerCommand::Unknown(_)))
}

/// Segments numbered 1, 2, .. (at most 127), the last flag only on the last.
fn is_sub_block(frames: &[CanFrame]) -> bool {
    frames.len() <= 127
        && frames.iter().enumerate().all(|(i, f)| {
            let b0 = f.data()[0];
            usize::from(b0 & 0x7F) == i + 1 && (b0 & 0x80 == 0 || i + 1 == frames.len())
        })
}

/// `sub` is `full` with some elements left out, in order.
fn is_subsequence<T: PartialEq>(sub: &[T], full: &[T]) -> bool {
    let mut it = full.iter();
    sub.iter().all(|x| it.any(|y| y == x))
}

fuzz_target!(|ops: Vec<Op>| {
    let node = NodeId::new(NODE).unwrap();
    let config = ServerConfig::for_node(node);
    let mut server = Server::new(config, dictionary());
    let mut undrained = Server::new(config, dictionary());
    let mut now = Timestamp::from_millis(10_000);
    let mut all_events: Vec<ServerEvent> = Vec::new();
    let mut read_undrained: Vec<ServerEvent> = Vec::new();
    for op in ops.into_iter().take(256) {
        let was_busy = server.is_busy();
        match op {
            Op::Frame { other, remote, shape, mut data, len } => {
                let id = if other { CanId::Standard(0x600 + u16::from(NODE) + 1) } else { config.request_id };
                // Steer byte 0/1/2 towards real commands on known objects.
                if shape & 0x80 != 0 {
                    let objects = [0x1000u16, 0x1017, 0x2000, 0x2001, 0x1008, 0x2002, 0x3000];
                    let [lo, hi] = objects[usize::from(shape & 7) % objects.len()].to_le_bytes();
                    data[1] = lo;
                    data[2] = hi;
                    data[3] = 0;
                }
                let len = usize::from(len % 9);
                let frame = if remote {
                    CanFrame::remote(id, len as u8).unwrap()
                } else {
                    CanFrame::new(id, &data[..len]).unwrap()
                };
                server.handle_frame(now, &frame);
                undrained.handle_frame(now, &frame);
            }
            Op::Advance { micros, backwards } => {
                now = if backwards {
                    Timestamp::from_micros(now.as_micros().saturating_sub(u64::from(micros)))
                } else {
                    now.add_micros(u64::from(micros) * 16)
                };
                server.handle_timeout(now);
                undrained.handle_timeout(now);
            }
            Op::BlockRequest { kind, object, a, b, data } => {
                let objects = [0x1000u16, 0x1017, 0x2000, 0x2001, 0x1008, 0x2002, 0x3000];
                let [lo, hi] = objects[usize::from(object) % objects.len()].to_le_bytes();
                let [d0, d1, d2, d3, d4, d5, d6] = data;
                let bytes = match kind % 7 {
                    // Block upload initiate: cc = a bit 0, blksize b, pst from a.
                    0 => [0xA0 | (a & 1) << 2, lo, hi, 0, b, a >> 4, 0, 0],
                    // Block upload start.
                    1 => [0xA3, 0, 0, 0, 0, 0, 0, 0],
                    // Block upload sub-block ack.
                    2 => [0xA2, a, b, 0, 0, 0, 0, 0],
                    // Block upload end.
                    3 => [0xA1, 0, 0, 0, 0, 0, 0, 0],
                    // Block download initiate with size a (s = b bit 0, cc = b bit 1).
                    4 => [0xC0 | (b & 2) << 1 | (b & 1) << 1, lo, hi, 0, a, 0, 0, 0],
                    // Sub-block segment: seqno and last flag from a.
                    5 => [a, d0, d1, d2, d3, d4, d5, d6],
                    // Block download end: unused bytes and CRC.
                    _ => [0xC1 | (a & 7) << 2, b, d0, 0, 0, 0, 0, 0],
                };
                let frame = CanFrame::new(config.request_id, &bytes).unwrap();
                server.handle_frame(now, &frame);
                undrained.handle_frame(now, &frame);
            }
            Op::ReadUndrained => read_undrained.extend(std::iter::from_fn(|| undrained.poll_event())),
        }
        let mut frames = Vec::new();
        while let Some(f) = server.poll_transmit() {
            assert_eq!(undrained.poll_transmit(), Some(f), "the copies' frames differ");
            assert_eq!(f.id(), config.response_id);
            assert_eq!(f.dlc(), 8);
            frames.push(f);
            assert!(frames.len() <= 128, "more than a response and a sub-block");
        }
        assert_eq!(undrained.poll_transmit(), None, "the copies' frames differ");
        assert!(
            is_sub_block(&frames) || (is_response(&frames[0]) && is_sub_block(&frames[1..])),
            "not one response and one sub-block: {frames:?}"
        );
        assert_eq!((server.frames_dropped(), undrained.frames_dropped()), (0, 0));
        assert_eq!(undrained.poll_timeout(), server.poll_timeout());
        assert_eq!(undrained.is_busy(), server.is_busy());
        let events: Vec<ServerEvent> = std::iter::from_fn(|| server.poll_event()).collect();
        assert_eq!(server.events_dropped(), 0, "a drained server drops no events");
        all_events.extend_from_slice(&events);
        assert!(events.len() <= 2);
        if events.len() == 2 {
            assert!(matches!(events[0], ServerEvent::Aborted { origin: AbortOrigin::Superseded, .. }));
        }
        if was_busy && !server.is_busy() {
            assert!(!events.is_empty(), "a running transfer ended without an event");
        }
        if !was_busy && server.is_busy() {
            assert!(events.is_empty());
        }
        assert_eq!(server.is_busy(), server.poll_timeout().is_some());
        // Values always fit their objects.
        for (index, max) in [(0x1017u16, 2usize), (0x2001, 8), (0x1008, 20), (0x2002, 0)] {
            let info = server.od().info(index, 0).unwrap();
            if index == 0x1008 || index == 0x2002 {
                assert!(info.len <= max);
            } else {
                assert_eq!(info.len, max);
            }
        }
    }
    for index in OBJECTS {
        assert_eq!(undrained.od().get(index, 0), server.od().get(index, 0));
    }
    read_undrained.extend(std::iter::from_fn(|| undrained.poll_event()));
    assert!(is_subsequence(&read_undrained, &all_events));
    assert_eq!(read_undrained.len() as u64 + undrained.events_dropped(), all_events.len() as u64);
    assert_eq!(read_undrained.last(), all_events.last());
});
