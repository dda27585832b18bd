//! The passive observer beside our own block transfers under faults: the
//! client and the server on one simulated bus (`common::sim::Bus`), block
//! upload and block download of 1..=3000 bytes, random block sizes and CRC
//! support, and the data sender's frames dropped, duplicated and delayed
//! behind later ones (reordered). The observer is tapped at the receiver of
//! the data: it sees every frame the receiver takes and sends, in the
//! receiver's order.
//!
//! What must hold (CiA 301 section 7.2.4.3, SDO block download and upload:
//! the receiver's acknowledgement says which segments it took):
//!
//! - a transfer the observer reports complete carries, byte for byte, what
//!   the receiving endpoint delivered, and the receiver completed it;
//! - a transfer the receiver completed, the observer reports complete (one
//!   transfer at a time never runs out of sub-block buffers);
//! - whatever the end, the observer never delivered bytes the receiver did
//!   not take: its data is the start of the receiver's.
//!
//! Cases: 64 by default (CI); `SDO_OBSERVER_PROPS_CASES=N` for more.

use std::time::Duration;

use crate::common;

use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, MemoryDictionary};
use canopen_codec::sdo::{
    BreakReason, Client, ClientConfig, ClientEvent, Observer, ObserverConfig, ObserverEvent,
    Server, ServerConfig, ServerEvent, Transfer, TransferEnd,
};
use canopen_codec::{CanFrame, NodeId, Timestamp};
use common::sdo::{CLIENT, SERVER};
use common::sim::{bus, Sent};
use proptest::prelude::*;

const INDEX: u16 = 0x2E01;
const SUB: u8 = 1;
const NODE: u8 = 9;

/// A machine with an observer at its side: the observer takes every frame
/// the machine takes, before it, and every frame the machine sends, as it
/// goes out.
struct Tap<M> {
    inner: M,
    observer: Observer,
    seen: Vec<ObserverEvent>,
    now: Timestamp,
}

impl<M> Tap<M> {
    fn new(inner: M) -> Self {
        Tap {
            inner,
            // No timeout: the transfer ends by its frames or the end of
            // the trace, whatever the simulated clock does.
            observer: Observer::new(ObserverConfig {
                default_channels: true,
                timeout: None,
            }),
            seen: Vec::new(),
            now: Timestamp::ZERO,
        }
    }

    fn watch(&mut self, frame: &CanFrame) {
        self.observer.handle_frame(self.now, frame);
        while let Some(e) = self.observer.poll_event() {
            self.seen.push(e);
        }
    }

    /// The observer's events, the end of the trace included.
    fn finish(&mut self) -> Vec<ObserverEvent> {
        while let Some(e) = self.observer.end_of_trace() {
            self.seen.push(e);
        }
        assert_eq!(self.observer.events_dropped(), 0);
        std::mem::take(&mut self.seen)
    }
}

impl<M: Machine> Machine for Tap<M> {
    type Event = M::Event;

    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        self.now = now;
        self.watch(frame);
        self.inner.handle_frame(now, frame);
    }

    fn handle_timeout(&mut self, now: Timestamp) {
        self.now = now;
        self.inner.handle_timeout(now);
    }

    fn poll_transmit(&mut self) -> Option<CanFrame> {
        let frame = self.inner.poll_transmit()?;
        self.watch(&frame);
        Some(frame)
    }

    fn poll_timeout(&self) -> Option<Timestamp> {
        self.inner.poll_timeout()
    }

    fn poll_event(&mut self) -> Option<Self::Event> {
        self.inner.poll_event()
    }

    fn events_dropped(&self) -> u64 {
        self.inner.events_dropped()
    }

    fn frames_dropped(&self) -> u64 {
        self.inner.frames_dropped()
    }
}

/// A fault on one frame of the data sender.
#[derive(Debug, Clone, Copy)]
enum Fault {
    Drop,
    Duplicate,
    /// Delivered this many microseconds late, behind later frames.
    Delay(u64),
}

#[derive(Debug, Clone)]
struct Run {
    value: Vec<u8>,
    upload: bool,
    client_blksize: u8,
    server_blksize: u8,
    client_crc: bool,
    server_crc: bool,
    /// (fault, which of the sender's frames: a seed)
    faults: Vec<(Fault, usize)>,
    latency_us: u64,
}

/// What the observer reported of the last transfer of the object: its
/// value (data events in order) and the ends of the transfers of the
/// object. (A segment that arrives after the transfer ended reads as a
/// command, to the receiver as to the observer: transfers of other objects
/// are such strays, not part of the check.)
fn observed(events: &[ObserverEvent]) -> (Vec<u8>, Vec<ObserverEvent>) {
    let ours = |t: &Transfer| (t.index, t.sub) == (INDEX, SUB);
    let mut value = Vec::new();
    let mut ends = Vec::new();
    let mut current = false;
    for e in events {
        match *e {
            ObserverEvent::Started(t) => {
                current = ours(&t);
                if current {
                    value.clear();
                }
            }
            ObserverEvent::Data { offset, data, .. } if current => {
                assert_eq!(offset, value.len(), "observer data out of order");
                value.extend_from_slice(data.as_slice());
            }
            ObserverEvent::Completed { transfer, .. }
            | ObserverEvent::Aborted { transfer, .. }
            | ObserverEvent::BrokenOff { transfer, .. }
                if ours(&transfer) =>
            {
                ends.push(*e);
            }
            _ => {}
        }
    }
    (value, ends)
}

fn run(r: &Run) {
    let node = NodeId::new(NODE).unwrap();
    let mut od = MemoryDictionary::new();
    let initial: &[u8] = if r.upload { &r.value } else { b"" };
    od.insert_variable(INDEX, SUB, Access::ReadWrite, initial, 4_000);
    let mut sim = bus(r.latency_us);
    let client = sim.add(
        CLIENT,
        Tap::new(Client::<Vec<u8>>::new(ClientConfig {
            block_size: r.client_blksize,
            crc: r.client_crc,
            ..ClientConfig::for_server(node)
        })),
    );
    let server = sim.add(
        SERVER,
        Tap::new(Server::new(
            ServerConfig {
                block_size: r.server_blksize,
                crc: r.server_crc,
                ..ServerConfig::for_node(node)
            },
            od,
        )),
    );
    // Faults on the sender's frames after its first (the initiate or its
    // answer): segments, mostly, and now and then the end frame.
    let sender = if r.upload { SERVER } else { CLIENT };
    let frames = r.value.len() / 7 + 3;
    for &(fault, seed) in &r.faults {
        let k = 1 + seed % frames;
        let mut count = 0usize;
        let nth_of_sender = move |s: &Sent| {
            if s.from != sender {
                return false;
            }
            count += 1;
            count - 1 == k
        };
        match fault {
            Fault::Drop => sim.drop_if(nth_of_sender),
            Fault::Duplicate => sim.duplicate_if(nth_of_sender),
            Fault::Delay(us) => sim.delay_if(Duration::from_micros(us), nth_of_sender),
        }
    }
    let value = r.value.clone();
    if r.upload {
        sim.with(client, |c, now| c.inner.start_block_upload(now, INDEX, SUB))
            .unwrap()
            .unwrap();
    } else {
        sim.with(client, |c, now| {
            c.inner.start_block_download(now, INDEX, SUB, value)
        })
        .unwrap()
        .unwrap();
    }
    sim.drive_bounded(100_000).unwrap();

    // What the receiver of the data delivered, and whether it completed.
    let (received, receiver_completed, events) = if r.upload {
        let mut data = Vec::new();
        let mut done = false;
        for (_, e) in sim.events(client) {
            match e {
                ClientEvent::UploadData {
                    offset, data: d, ..
                } => {
                    assert_eq!(*offset, data.len());
                    data.extend_from_slice(d.as_slice());
                }
                ClientEvent::Ended(TransferEnd::Uploaded { .. }) => done = true,
                _ => {}
            }
        }
        (data, done, sim.machine_mut(client).unwrap().finish())
    } else {
        let done = sim
            .event_list(server)
            .iter()
            .any(|e| matches!(e, ServerEvent::Downloaded { .. }));
        let stored = sim
            .machine(server)
            .unwrap()
            .inner
            .od()
            .get(INDEX, SUB)
            .unwrap()
            .to_vec();
        (stored, done, sim.machine_mut(server).unwrap().finish())
    };
    let (delivered, ends) = observed(&events);
    let log = || sim.lines(0, u64::MAX);
    let Some(last) = ends.last() else {
        panic!("observer: no end {events:?}\n{:#?}", log());
    };
    match last {
        ObserverEvent::Completed { bytes, .. } => {
            assert!(receiver_completed, "observer completed alone\n{:#?}", log());
            assert_eq!(*bytes, received.len());
            assert_eq!(delivered, received, "observer and receiver differ");
        }
        ObserverEvent::BrokenOff {
            reason: BreakReason::NoSubBlockBuffer { .. },
            ..
        } => panic!("one transfer ran out of sub-block buffers"),
        e => {
            assert!(
                !receiver_completed,
                "receiver completed, observer: {e:?}\n{:#?}",
                log()
            );
            // The receiver's delivered bytes of a failed download are not
            // visible (the old value stays): an upload's are. The observer
            // took the segments the client acknowledged, as it did; the
            // last one it may have delivered at the end frame, which the
            // client refused (a CRC or size it checks before writing).
            if r.upload {
                let common = delivered.len().min(received.len());
                assert_eq!(
                    delivered[..common],
                    received[..common],
                    "observer and client differ"
                );
                assert!(
                    delivered.len() <= received.len() + 7,
                    "observer delivered bytes the client did not take ({} of {})",
                    delivered.len(),
                    received.len()
                );
            }
        }
    }
    if r.faults.is_empty() {
        assert!(receiver_completed);
        assert_eq!(received, r.value);
    }
}

fn faults() -> impl Strategy<Value = Fault> {
    prop_oneof![
        Just(Fault::Drop),
        Just(Fault::Duplicate),
        (1u64..=20_000).prop_map(Fault::Delay),
    ]
}

fn runs() -> impl Strategy<Value = Run> {
    (
        proptest::collection::vec(any::<u8>(), 1..=3_000),
        any::<bool>(),
        1u8..=127,
        1u8..=127,
        any::<bool>(),
        any::<bool>(),
        proptest::collection::vec((faults(), any::<usize>()), 0..=4),
        0u64..=2_000,
    )
        .prop_map(
            |(
                value,
                upload,
                client_blksize,
                server_blksize,
                client_crc,
                server_crc,
                faults,
                latency_us,
            )| Run {
                value,
                upload,
                client_blksize,
                server_blksize,
                client_crc,
                server_crc,
                faults,
                latency_us,
            },
        )
}

fn cases() -> u32 {
    std::env::var("SDO_OBSERVER_PROPS_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(64)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: cases(),
        failure_persistence: Some(Box::new(proptest::test_runner::FileFailurePersistence::Direct("tests/proptest-regressions/sdo_observer_props.txt"))),
        ..ProptestConfig::default()
    })]

    #[test]
    fn observer_reports_what_the_receiver_took(r in runs()) {
        run(&r);
    }
}

#[test]
fn a_delayed_segment_is_resent_and_read_as_acknowledged() {
    // 40 segments in one sub-block of 127; the 10th is delivered after the
    // rest: the receiver acknowledges 9, the sender resends from the 10th.
    for upload in [false, true] {
        for delay in [1u64, 3_000, 50_000] {
            run(&Run {
                value: (0..280).map(|i| (i * 13 + 5) as u8).collect(),
                upload,
                client_blksize: 127,
                server_blksize: 127,
                client_crc: true,
                server_crc: true,
                faults: vec![(Fault::Delay(delay), 9)],
                latency_us: 500,
            });
        }
    }
}
