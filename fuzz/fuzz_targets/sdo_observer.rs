//! The passive SDO observer under arbitrary frame sequences on three
//! channels (two default ones and one added pair of COB-IDs), steered
//! towards real commands of every transfer type, with time steps (forwards
//! and backwards) and the end of the trace.
//!
//! Invariants: no panic; nothing is ever sent; on each channel a transfer
//! starts, delivers data pieces in order (each at the offset where the last
//! ended) and ends at most once (a start while one is open only after that
//! one ended); the bytes delivered never exceed the bytes the channel's
//! frames carried since the start, and a terminal event's count is the sum
//! of its pieces; a block segment is only named while a block transfer is
//! open there; no event is dropped when drained after every step; after the
//! end of the trace nothing is open and every started transfer has ended.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::machine::Machine;
use canopen_codec::sdo::{Observed, Observer, ObserverConfig, ObserverEvent, SdoChannel, TransferKind};
use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};
use core::time::Duration;
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    /// A frame on `channel % 3`, from the server when `server`; `shape`
    /// picks a command to steer towards, `a`, `b`, `data` fill it.
    Frame { channel: u8, server: bool, shape: u8, a: u8, b: u8, data: [u8; 7], len: u8 },
    Remote { channel: u8 },
    Advance { micros: u32, backwards: bool },
}

#[derive(Default, Clone, Copy)]
struct Track {
    open: bool,
    block: bool,
    delivered: usize,
    carried: usize,
}

fn channels() -> [SdoChannel; 3] {
    [
        SdoChannel::default_for(NodeId::new(1).unwrap()),
        SdoChannel::default_for(NodeId::new(127).unwrap()),
        SdoChannel {
            node: NodeId::new(65).unwrap(),
            request: CanId::Standard(0x241),
            response: CanId::Standard(0x1C1),
        },
    ]
}

fn bytes(shape: u8, a: u8, b: u8, d: [u8; 7]) -> [u8; 8] {
    let [d0, d1, d2, d3, d4, d5, d6] = d;
    let (lo, hi) = if a & 1 == 0 { (0x00, 0x20) } else { (0x08, 0x10) };
    let t = (a & 2) << 3;
    match shape % 18 {
        0 => [0x40, lo, hi, 0, 0, 0, 0, 0],
        1 => [0x23 | (b & 3) << 2, lo, hi, 0, d0, d1, d2, d3],
        2 => [0x21, lo, hi, 0, b % 32, 0, 0, 0],
        3 => [0x41, lo, hi, 0, b % 32, 0, 0, 0],
        4 => [0x43 | (b & 3) << 2, lo, hi, 0, d0, d1, d2, d3],
        5 => [0x60 | t, 0, 0, 0, 0, 0, 0, 0],
        6 => [t | (b & 7) << 1 | (b >> 7), d0, d1, d2, d3, d4, d5, d6],
        7 => [0x20 | t, 0, 0, 0, 0, 0, 0, 0],
        8 => [0x60, lo, hi, 0, 0, 0, 0, 0],
        9 => [0xC0 | (b & 3) << 1 | (b & 4), lo, hi, 0, b >> 3, 0, 0, 0],
        10 => [0xA0 | (b & 4), lo, hi, 0, b >> 3, 0, 0, 0],
        11 => [b, d0, d1, d2, d3, d4, d5, d6],
        12 => [0xA2, a >> 1, b, 0, 0, 0, 0, 0],
        13 => [0xC1 | (b & 7) << 2, d0, d1, 0, 0, 0, 0, 0],
        14 => [0xA0 | (a & 4), lo, hi, 0, b, a >> 4, 0, 0],
        15 => [0xC0 | (b & 3) << 1 | (b & 4), lo, hi, 0, b >> 3, 0, 0, 0],
        16 => [[0xA3, 0xA1, 0x80, 0xA1][usize::from(b & 3)], 0, 0, 0, d0, d1, d2, d3],
        _ => [a, b, d0, d1, d2, d3, d4, d5],
    }
}

fuzz_target!(|ops: Vec<Op>| {
    let chans = channels();
    // Two sub-block buffers for three channels: block transfers can run
    // out of them (NoSubBlockBuffer) as well as complete.
    let mut obs: Observer<8, 2> = Observer::with_capacity(ObserverConfig {
        default_channels: true,
        timeout: Some(Duration::from_millis(50)),
    });
    obs.add_channel(chans[2]).unwrap();
    let mut now = Timestamp::from_millis(1_000);
    let mut track = [Track::default(); 3];
    let mut started = 0usize;
    let mut ended = 0usize;
    let which = |c: SdoChannel| chans.iter().position(|x| *x == c).expect("an unknown channel");
    // `frame_bytes`: what the frame just taken could carry of a value (a
    // transfer it started counts from there).
    let mut check = |e: ObserverEvent, track: &mut [Track; 3], frame_bytes: usize| {
        let t = &mut track[which(e.channel())];
        match e {
            ObserverEvent::Started(tr) => {
                assert!(!t.open, "started while one was open");
                *t = Track {
                    open: true,
                    block: matches!(tr.kind, Some(TransferKind::Block { .. })),
                    delivered: 0,
                    carried: frame_bytes,
                };
                started += 1;
            }
            ObserverEvent::Data { offset, data, .. } => {
                assert!(t.open, "data with nothing open");
                assert_eq!(offset, t.delivered, "data out of order");
                assert!(!data.is_empty());
                t.delivered += data.len();
                assert!(t.delivered <= t.carried, "more bytes delivered than carried");
            }
            ObserverEvent::RuleBroken { .. } => assert!(t.open, "a rule broken with nothing open"),
            ObserverEvent::Completed { bytes, .. }
            | ObserverEvent::Aborted { bytes, .. }
            | ObserverEvent::BrokenOff { bytes, .. } => {
                assert!(t.open, "ended twice");
                assert_eq!(bytes, t.delivered);
                // Segments held for an acknowledgement that never came
                // were carried by frames too, and are not delivered.
                if let ObserverEvent::Aborted { pending, .. }
                | ObserverEvent::BrokenOff { pending, .. } = e
                {
                    assert!(t.block || pending == 0, "pending bytes outside a block transfer");
                    assert!(bytes + pending <= t.carried, "more bytes held than carried");
                }
                t.open = false;
                ended += 1;
            }
            _ => {}
        }
    };
    for op in ops.into_iter().take(512) {
        let mut frame_bytes = 0;
        match op {
            Op::Frame { channel, server, shape, a, b, data, len } => {
                let c = chans[usize::from(channel % 3)];
                let id = if server { c.response } else { c.request };
                let full = bytes(shape, a, b, data);
                let len = if shape & 0x80 != 0 { usize::from(len % 9) } else { 8 };
                let frame = CanFrame::new(id, &full[..len]).unwrap();
                let i = usize::from(channel % 3);
                // What the frame could carry of a value: up to 7 bytes.
                frame_bytes = len.saturating_sub(1);
                track[i].carried += frame_bytes;
                let seen = obs.observe(now, &frame);
                if let Observed::BlockSegment { channel, .. } = seen {
                    let t = track[which(channel)];
                    assert!(t.open && t.block, "a block segment outside a block transfer");
                }
                assert!(!matches!(seen, Observed::Other));
            }
            Op::Remote { channel } => {
                let c = chans[usize::from(channel % 3)];
                let frame = CanFrame::remote(c.request, 8).unwrap();
                assert_eq!(obs.observe(now, &frame), Observed::Other);
            }
            Op::Advance { micros, backwards } => {
                now = if backwards {
                    Timestamp::from_micros(now.as_micros().saturating_sub(u64::from(micros)))
                } else {
                    now.add_micros(u64::from(micros) * 4)
                };
                obs.handle_timeout(now);
            }
        }
        while let Some(e) = obs.poll_event() {
            check(e, &mut track, frame_bytes);
        }
        assert_eq!(obs.poll_transmit(), None);
        assert_eq!(obs.events_dropped(), 0);
    }
    while let Some(e) = obs.end_of_trace() {
        check(e, &mut track, 0);
    }
    assert_eq!(obs.open_transfers(), 0);
    assert_eq!(started, ended, "a started transfer did not end");
});
