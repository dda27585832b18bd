//! [`EVENTS_PER_CALL`]: the SDO server and client, driven on random input
//! the way a device drives them (every event read after every `handle_*`
//! call and command, `poll_transmit` drained in between, its events left
//! for the next read), never leave more than that many events, so a queue
//! of that capacity drops none: beside a machine of the default capacity
//! on the same input, the same frames and the same events come out.

use std::vec;
use std::vec::Vec;

use proptest::prelude::*;

use super::*;
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::od::{Access, ObjectDictionary, ObjectInfo, SizeRule};
use crate::NodeId;

/// 2000h 4 bytes, 2001h 20 bytes, 2002h up to 30 bytes (all read-write),
/// 2003h 20 bytes whose reads from offset 7 on fail, 2004h read-only.
#[derive(Debug, Clone)]
struct Od {
    values: [[u8; 30]; 5],
    lens: [usize; 5],
}

impl Od {
    fn new() -> Self {
        Od {
            values: [[0x5A; 30]; 5],
            lens: [4, 20, 10, 20, 2],
        }
    }
    fn slot(index: u16, sub: u8) -> Result<usize, AbortCode> {
        match (index, sub) {
            (0x2000..=0x2004, 0) => Ok(usize::from(index - 0x2000)),
            _ => Err(AbortCode::ObjectDoesNotExist),
        }
    }
}

impl ObjectDictionary for Od {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        let slot = Self::slot(index, sub)?;
        let len = self.lens[slot];
        Ok(match slot {
            2 => ObjectInfo {
                size: SizeRule::Variable { max: 30 },
                ..ObjectInfo::fixed(Access::ReadWrite, len)
            },
            4 => ObjectInfo::fixed(Access::ReadOnly, len),
            _ => ObjectInfo::fixed(Access::ReadWrite, len),
        })
    }
    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let slot = Self::slot(index, sub)?;
        if slot == 3 && offset >= 7 {
            return Err(AbortCode::HardwareError);
        }
        let value = self.values[slot].get(..self.lens[slot]).unwrap_or(&[]);
        Ok(crate::od::read_at(value, offset, buf))
    }
    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        let slot = Self::slot(index, sub)?;
        let dst = self.values[slot]
            .get_mut(offset..offset + data.len())
            .ok_or(AbortCode::DataTypeLengthTooHigh)?;
        dst.copy_from_slice(data);
        Ok(())
    }
    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        self.lens[Self::slot(index, sub)?] = len;
        Ok(())
    }
}

const NODE: u8 = 3;

/// One input: a frame on the request (server) or response (client)
/// identifier, time passing, or (client only) a command.
#[derive(Debug, Clone)]
enum Op {
    Frame(Vec<u8>),
    Later(u16),
    Start(u8, u16),
}

/// Frames that mean something to an SDO machine (every command specifier,
/// both toggles, the block sub-commands) over the five objects, and any
/// bytes at all.
fn frame() -> impl Strategy<Value = Vec<u8>> {
    let b0 = prop_oneof![
        prop::sample::select(vec![
            0x00, 0x01, 0x10, 0x11, 0x0B, 0x1D, 0x20, 0x23, 0x2B, 0x21, 0x22, 0x30, 0x40, 0x41,
            0x43, 0x4B, 0x60, 0x70, 0x80, 0xA0, 0xA1, 0xA2, 0xA3, 0xA4, 0xC0, 0xC1, 0xC2, 0xC6,
            0xC5, 0xE0,
        ]),
        any::<u8>(),
    ];
    (
        b0,
        0x2000u16..=0x2005,
        any::<[u8; 4]>(),
        0usize..=8,
        any::<bool>(),
    )
        .prop_map(|(b0, index, tail, dlc, full)| {
            let [lo, hi] = index.to_le_bytes();
            let mut bytes = vec![b0, lo, hi, 0, tail[0], tail[1], tail[2], tail[3]];
            // Block segments and acks: a small sequence number or block size.
            if b0 & 0x80 != 0 && b0 & 0x7F < 8 {
                bytes[1] = tail[0] % 4;
                bytes[2] = tail[1] % 4 + 1;
            }
            bytes.truncate(if full { 8 } else { dlc });
            bytes
        })
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        6 => frame().prop_map(Op::Frame),
        1 => prop::sample::select(vec![0u16, 1, 1999, 2000, 2001, 5000]).prop_map(Op::Later),
        2 => (0u8..6, 0x2000u16..=0x2004).prop_map(|(k, i)| Op::Start(k, i)),
    ]
}

/// `ops` played on both machines side by side (frames on `function` plus
/// the node, times, and what `start` does with a start), each step's
/// events and frames compared by [`beside`].
fn play<S, B, E>(
    small: &mut S,
    big: &mut B,
    function: u16,
    ops: Vec<Op>,
    start: impl Fn(&mut S, &mut B, u8, Timestamp, u16),
) where
    S: Machine<Event = E>,
    B: Machine<Event = E>,
    E: PartialEq + core::fmt::Debug,
{
    let mut now = Timestamp::ZERO;
    for op in ops {
        match op {
            Op::Frame(bytes) => {
                let frame = CanFrame::standard(function + u16::from(NODE), &bytes).unwrap();
                beside(small, big, |m| m.handle_frame(now, &frame));
            }
            Op::Later(ms) => {
                now = now.add_micros(u64::from(ms) * 1000);
                beside(small, big, |m| m.handle_timeout(now));
            }
            Op::Start(kind, index) => {
                start(small, big, kind, now, index);
                beside(small, big, |_| {});
            }
        }
    }
}

/// Runs `small` (capacity [`EVENTS_PER_CALL`]) beside `big` (the default)
/// on the same input: the same frames and events, at most
/// `EVENTS_PER_CALL` read after each call, none dropped by `small`.
fn beside<S, B, E>(small: &mut S, big: &mut B, call: impl Fn(&mut dyn Machine<Event = E>))
where
    S: Machine<Event = E>,
    B: Machine<Event = E>,
    E: PartialEq + core::fmt::Debug,
{
    call(small);
    call(big);
    // The events first (with any the last drain of the transmit queue
    // left), then the frames: a device's order.
    let mut read = 0;
    loop {
        let (a, b) = (small.poll_event(), big.poll_event());
        assert_eq!(a, b);
        if a.is_none() {
            break;
        }
        read += 1;
    }
    assert!(read <= EVENTS_PER_CALL, "{read} events after one call");
    loop {
        let (a, b) = (small.poll_transmit(), big.poll_transmit());
        assert_eq!(a, b);
        if a.is_none() {
            break;
        }
    }
    assert_eq!(small.events_dropped(), 0);
    assert_eq!(big.events_dropped(), 0);
}

proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 512,
        ..crate::testing::proptest_config("tests/proptest-regressions/src-sdo-capacity_tests.txt")
    })]

    #[test]
    fn the_server_leaves_at_most_events_per_call(ops in prop::collection::vec(op(), 1..60)) {
        let node = NodeId::new(NODE).unwrap();
        let config = ServerConfig { block_size: 3, ..ServerConfig::for_node(node) };
        let mut small: Server<Od, EVENTS_PER_CALL> = Server::with_event_capacity(config, Od::new());
        let mut big = Server::new(config, Od::new());
        play(&mut small, &mut big, 0x600, ops, |_, _, _, _, _| {});
    }

    #[test]
    fn the_client_leaves_at_most_events_per_call(ops in prop::collection::vec(op(), 1..60)) {
        let config = ClientConfig { block_size: 3, ..ClientConfig::for_server(NodeId::new(NODE).unwrap()) };
        let mut small: Client<&'static [u8], EVENTS_PER_CALL> = Client::with_event_capacity(config);
        let mut big: Client = Client::new(config);
        play(&mut small, &mut big, 0x580, ops, |small, big, kind, now, index| {
            let start = |c: &mut dyn Starts| c.start(kind, now, index);
            assert_eq!(start(small), start(big));
        });
    }
}

/// The client's commands, for both capacities.
trait Starts {
    fn start(&mut self, kind: u8, now: Timestamp, index: u16) -> Result<bool, ClientError>;
}

impl<const N: usize> Starts for Client<&'static [u8], N> {
    fn start(&mut self, kind: u8, now: Timestamp, index: u16) -> Result<bool, ClientError> {
        // Expedited, one segment, three segments.
        let data: &'static [u8] = match index % 3 {
            0 => &[1, 2],
            1 => &[3; 7],
            _ => &[4; 20],
        };
        match kind {
            0 => self.start_upload(now, index, 0).map(|()| true),
            1 => self.start_download(now, index, 0, data).map(|()| true),
            2 => self.start_block_upload(now, index, 0).map(|()| true),
            3 => self
                .start_block_download(now, index, 0, data)
                .map(|()| true),
            _ => Ok(self.abort(now, AbortCode::GeneralError)),
        }
    }
}
