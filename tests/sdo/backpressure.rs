//! The back-pressure rule for the SDO client and server: an undrained event
//! queue never changes protocol behaviour. The same transfers run on two
//! simulated buses, one whose events are read after every call and one
//! whose events are read on another pattern (or never); the frames on the
//! wire, with their times, must be identical, the terminal event must be
//! the newest one kept, and `events_dropped` must count exactly.
//!
//! Its own small bus (not `tests/common`): one client, one server, a
//! simulated clock from zero, per-frame latencies, in-order delivery per
//! direction.

use std::collections::VecDeque;

use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, MemoryDictionary};
use canopen_codec::sdo::{
    AbortCode, AbortOrigin, Client, ClientConfig, ClientEvent, Server, ServerConfig, ServerEvent,
    TransferEnd,
};
use canopen_codec::{CanFrame, NodeId, Timestamp};
use proptest::prelude::*;

/// The domain object every transfer reads or writes.
const OBJECT: (u16, u8) = (0x2000, 0);
const MAX_LEN: usize = 1000;
/// Bound on bus steps: a livelock fails the test instead of hanging it.
const MAX_STEPS: usize = 100_000;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Dir {
    ToServer,
    ToClient,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Transfer {
    Upload(usize),
    Download(usize),
}

/// When events are read: after call number `i`, iff `pattern[i % len]`.
#[derive(Debug, Clone)]
struct Drain {
    client: Vec<bool>,
    server: Vec<bool>,
}

impl Drain {
    fn always() -> Self {
        Drain {
            client: vec![true],
            server: vec![true],
        }
    }

    fn never() -> Self {
        Drain {
            client: vec![false],
            server: vec![false],
        }
    }
}

fn value(seed: usize, len: usize) -> Vec<u8> {
    (0..len).map(|i| (i * 7 + seed * 13) as u8).collect()
}

/// What one run leaves behind.
#[derive(Debug)]
struct Outcome {
    /// Every frame sent, with the time it was sent.
    wire: Vec<(Timestamp, Dir, CanFrame)>,
    /// Events read while running, then those still queued at the end.
    client_read: Vec<ClientEvent>,
    client_queued: Vec<ClientEvent>,
    client_dropped: u64,
    server_read: Vec<ServerEvent>,
    server_queued: Vec<ServerEvent>,
    server_dropped: u64,
    frames_dropped: (u64, u64),
    /// The object's value at the end.
    od_value: Vec<u8>,
    /// The bytes of the last upload, assembled from the events read.
    uploaded: Vec<u8>,
}

struct Bus {
    client: Client<Vec<u8>>,
    server: Server<MemoryDictionary>,
    now: Timestamp,
    /// One-way latency of frame `k` is `latencies[k % len]` microseconds.
    latencies: Vec<u64>,
    drain: Drain,
    calls: usize,
    in_flight: VecDeque<(Timestamp, Dir, CanFrame)>,
    last_arrival: [Timestamp; 2],
    wire: Vec<(Timestamp, Dir, CanFrame)>,
    client_read: Vec<ClientEvent>,
    server_read: Vec<ServerEvent>,
}

impl Bus {
    fn new(latencies: Vec<u64>, drain: Drain) -> Self {
        let node = NodeId::new(5).unwrap();
        let mut od = MemoryDictionary::new();
        od.insert_variable(OBJECT.0, OBJECT.1, Access::ReadWrite, &[], MAX_LEN);
        Bus {
            client: Client::new(ClientConfig::for_server(node)),
            server: Server::new(ServerConfig::for_node(node), od),
            now: Timestamp::ZERO,
            latencies,
            drain,
            calls: 0,
            in_flight: VecDeque::new(),
            last_arrival: [Timestamp::ZERO; 2],
            wire: Vec::new(),
            client_read: Vec::new(),
            server_read: Vec::new(),
        }
    }

    /// After every call: send every frame (the contract), then read events
    /// if the drain pattern says so.
    fn after_call(&mut self) {
        for (dir, frame) in std::iter::from_fn(|| self.client.poll_transmit())
            .map(|f| (Dir::ToServer, f))
            .collect::<Vec<_>>()
            .into_iter()
            .chain(
                std::iter::from_fn(|| self.server.poll_transmit())
                    .map(|f| (Dir::ToClient, f))
                    .collect::<Vec<_>>(),
            )
        {
            let latency = self.latencies[self.wire.len() % self.latencies.len()];
            let lane = dir as usize;
            // CAN keeps the order of frames on one identifier.
            let at = self.now.add_micros(latency).max(self.last_arrival[lane]);
            self.last_arrival[lane] = at;
            self.wire.push((self.now, dir, frame));
            self.in_flight.push_back((at, dir, frame));
        }
        let i = self.calls;
        self.calls += 1;
        if self.drain.client[i % self.drain.client.len()] {
            self.client_read
                .extend(std::iter::from_fn(|| self.client.poll_event()));
        }
        if self.drain.server[i % self.drain.server.len()] {
            self.server_read
                .extend(std::iter::from_fn(|| self.server.poll_event()));
        }
    }

    fn start(&mut self, seed: usize, transfer: Transfer) {
        match transfer {
            Transfer::Upload(len) => {
                assert!(self
                    .server
                    .od_mut()
                    .set(OBJECT.0, OBJECT.1, &value(seed, len)));
                self.client
                    .start_upload(self.now, OBJECT.0, OBJECT.1)
                    .unwrap();
            }
            Transfer::Download(len) => self
                .client
                .start_download(self.now, OBJECT.0, OBJECT.1, value(seed, len))
                .unwrap(),
        }
        self.after_call();
    }

    /// Advances to the next arrival or deadline and handles it; false when
    /// nothing is left to happen.
    fn step(&mut self) -> bool {
        let next = [
            self.in_flight.iter().map(|(at, ..)| *at).min(),
            self.client.poll_timeout(),
            self.server.poll_timeout(),
        ]
        .into_iter()
        .flatten()
        .min();
        let Some(next) = next else {
            return false;
        };
        self.now = self.now.max(next);
        while let Some(pos) = self.in_flight.iter().position(|(at, ..)| *at <= self.now) {
            let (_, dir, frame) = self.in_flight.remove(pos).unwrap();
            match dir {
                Dir::ToServer => self.server.handle_frame(self.now, &frame),
                Dir::ToClient => self.client.handle_frame(self.now, &frame),
            }
            self.after_call();
        }
        if self.client.poll_timeout().is_some_and(|t| t <= self.now) {
            self.client.handle_timeout(self.now);
            self.after_call();
        }
        if self.server.poll_timeout().is_some_and(|t| t <= self.now) {
            self.server.handle_timeout(self.now);
            self.after_call();
        }
        true
    }

    /// Runs `transfers` one after the other (each starts once the client
    /// is idle), then until the bus is quiet.
    fn run(mut self, transfers: &[Transfer]) -> Outcome {
        let mut steps = 0;
        for (seed, t) in transfers.iter().enumerate() {
            self.start(seed, *t);
            while self.client.is_busy() {
                assert!(self.step(), "client busy with nothing to wait for");
                steps += 1;
                assert!(steps < MAX_STEPS, "livelock");
            }
        }
        while self.step() {
            steps += 1;
            assert!(steps < MAX_STEPS, "livelock");
        }
        let uploaded = self.client_read.iter().fold(Vec::new(), |mut acc, e| {
            match e {
                ClientEvent::UploadData {
                    offset: 0, data, ..
                } => {
                    acc = data.as_slice().to_vec();
                }
                ClientEvent::UploadData { data, .. } => acc.extend_from_slice(data.as_slice()),
                _ => {}
            }
            acc
        });
        Outcome {
            wire: self.wire,
            client_read: self.client_read,
            client_queued: std::iter::from_fn(|| self.client.poll_event()).collect(),
            client_dropped: self.client.events_dropped(),
            server_read: self.server_read,
            server_queued: std::iter::from_fn(|| self.server.poll_event()).collect(),
            server_dropped: self.server.events_dropped(),
            frames_dropped: (self.client.frames_dropped(), self.server.frames_dropped()),
            od_value: self.server.od().get(OBJECT.0, OBJECT.1).unwrap().to_vec(),
            uploaded,
        }
    }
}

/// True if `sub` is `full` with some elements left out, in order.
fn is_subsequence<T: PartialEq>(sub: &[T], full: &[T]) -> bool {
    let mut it = full.iter();
    sub.iter().all(|x| it.any(|y| y == x))
}

/// Runs `transfers` drained and on `drain`, and checks everything the
/// back-pressure rule promises. Returns the drained outcome.
fn check_against_drained(transfers: &[Transfer], latencies: &[u64], drain: Drain) -> Outcome {
    let drained = Bus::new(latencies.to_vec(), Drain::always()).run(transfers);
    let other = Bus::new(latencies.to_vec(), drain).run(transfers);
    // Same frames, same times.
    assert_eq!(other.wire, drained.wire);
    assert_eq!(other.od_value, drained.od_value);
    assert_eq!(other.frames_dropped, (0, 0));
    assert_eq!(drained.frames_dropped, (0, 0));
    // Drained: nothing dropped, nothing left, one terminal event per transfer.
    assert_eq!((drained.client_dropped, drained.server_dropped), (0, 0));
    assert!(drained.client_queued.is_empty() && drained.server_queued.is_empty());
    let terminal = drained
        .client_read
        .iter()
        .filter(|e| e.is_terminal())
        .count();
    assert_eq!(terminal, transfers.len());
    // Undrained: what was kept is what the drained run saw, minus exactly
    // the dropped events, and the newest event kept is the newest there is.
    let client_kept: Vec<ClientEvent> =
        [other.client_read.clone(), other.client_queued.clone()].concat();
    let server_kept: Vec<ServerEvent> =
        [other.server_read.clone(), other.server_queued.clone()].concat();
    assert!(is_subsequence(&client_kept, &drained.client_read));
    assert!(is_subsequence(&server_kept, &drained.server_read));
    assert_eq!(
        client_kept.len() as u64 + other.client_dropped,
        drained.client_read.len() as u64
    );
    assert_eq!(
        server_kept.len() as u64 + other.server_dropped,
        drained.server_read.len() as u64
    );
    assert_eq!(client_kept.last(), drained.client_read.last());
    assert_eq!(server_kept.last(), drained.server_read.last());
    drained
}

const LAN: &[u64] = &[1_000];

#[test]
fn never_drained_expedited_and_segmented_transfers_match_drained_ones() {
    for (transfer, client_events) in [
        (Transfer::Upload(4), 2),
        (Transfer::Upload(100), 16),
        (Transfer::Upload(0), 1),
        (Transfer::Download(3), 1),
        (Transfer::Download(100), 1),
        (Transfer::Download(0), 1),
    ] {
        let drained = check_against_drained(&[transfer], LAN, Drain::never());
        let never = Bus::new(LAN.to_vec(), Drain::never()).run(&[transfer]);
        assert_eq!(drained.client_read.len(), client_events, "{transfer:?}");
        // Never drained: exactly the newest four are kept, the rest counted.
        let kept = client_events.min(4);
        assert_eq!(never.client_queued.len(), kept, "{transfer:?}");
        assert_eq!(never.client_dropped, (client_events - kept) as u64);
        assert_eq!(
            never.client_queued[..],
            drained.client_read[client_events - kept..]
        );
        assert!(never.client_queued.last().unwrap().is_terminal());
        assert_eq!(never.server_queued, drained.server_read);
        assert_eq!(never.server_dropped, 0);
        match transfer {
            Transfer::Upload(n) => assert_eq!(drained.uploaded, value(0, n)),
            Transfer::Download(n) => assert_eq!(never.od_value, value(0, n)),
        }
    }
}

#[test]
fn segmented_upload_wire_and_times_are_exact_when_never_drained() {
    // Three segments: four client events, more than the old client took
    // before it stopped answering.
    let never = Bus::new(vec![1_000], Drain::never()).run(&[Transfer::Upload(20)]);
    let frames: Vec<(u64, Dir, String)> = never
        .wire
        .iter()
        .map(|(t, d, f)| (t.as_micros(), *d, f.to_string()))
        .collect();
    let expected = [
        (0, Dir::ToServer, "605#4000200000000000"),
        (1_000, Dir::ToClient, "585#4100200014000000"),
        (2_000, Dir::ToServer, "605#6000000000000000"),
        (3_000, Dir::ToClient, "585#0000070E151C232A"),
        (4_000, Dir::ToServer, "605#7000000000000000"),
        (5_000, Dir::ToClient, "585#1031383F464D545B"),
        (6_000, Dir::ToServer, "605#6000000000000000"),
        (7_000, Dir::ToClient, "585#03626970777E8500"),
    ]
    .map(|(t, d, f)| (t, d, f.to_string()));
    assert_eq!(frames, expected);
    assert_eq!(never.client_dropped, 0);
    assert_eq!(never.client_queued.len(), 4);
    assert_eq!(
        never.client_queued.last(),
        Some(&ClientEvent::Ended(TransferEnd::Uploaded {
            index: 0x2000,
            sub: 0,
            len: 20
        }))
    );
}

#[test]
fn events_dropped_counts_exactly_over_many_transfers() {
    // Ten downloads, never drained: the server reports ten events, keeps
    // the newest four; the client likewise.
    let transfers = [Transfer::Download(9); 10];
    check_against_drained(&transfers, LAN, Drain::never());
    let never = Bus::new(LAN.to_vec(), Drain::never()).run(&transfers);
    assert_eq!((never.client_dropped, never.server_dropped), (6, 6));
    assert_eq!(
        never.server_queued,
        [ServerEvent::Downloaded {
            index: 0x2000,
            sub: 0,
            len: 9
        }; 4]
    );
}

#[test]
fn a_timeout_with_undrained_events_still_aborts_once() {
    // Four quick downloads fill the client's event queue; then the upload's
    // request takes longer than the 2000 ms timeout. The client still
    // starts it, gives up on time and sends one abort, drained or not.
    let transfers = [
        Transfer::Download(2),
        Transfer::Download(2),
        Transfer::Download(2),
        Transfer::Download(2),
        Transfer::Upload(20),
    ];
    let mut latencies = vec![1_000; 8];
    latencies.push(2_500_000);
    let drained = check_against_drained(&transfers, &latencies, Drain::never());
    let timed_out = ClientEvent::Ended(TransferEnd::Aborted {
        index: 0x2000,
        sub: 0,
        code: AbortCode::SdoProtocolTimedOut,
        origin: AbortOrigin::Local,
    });
    assert_eq!(drained.client_read.last(), Some(&timed_out));
    let aborts: Vec<&(Timestamp, Dir, CanFrame)> = drained
        .wire
        .iter()
        .filter(|(_, _, f)| f.to_string() == "605#8000200000000405")
        .collect();
    assert_eq!(aborts.len(), 1);
    assert_eq!(aborts[0].0, Timestamp::from_millis(2_000 + 8));
    let never = Bus::new(latencies, Drain::never()).run(&transfers);
    assert_eq!(never.client_queued.last(), Some(&timed_out));
    assert_eq!(never.client_dropped, 1);
}

fn transfer() -> impl Strategy<Value = Transfer> {
    prop_oneof![
        (0..=MAX_LEN).prop_map(Transfer::Upload),
        (0..=MAX_LEN).prop_map(Transfer::Download),
        // Expedited sizes often enough to matter.
        (0usize..=4).prop_map(Transfer::Upload),
        (0usize..=4).prop_map(Transfer::Download),
    ]
}

fn latency() -> impl Strategy<Value = u64> {
    prop_oneof![
        4 => 0u64..=20_000,
        // Now and then slower than the 2000 ms timeout.
        1 => 1_500_000u64..=2_600_000,
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: Some(Box::new(proptest::test_runner::FileFailurePersistence::Direct("tests/proptest-regressions/sdo_backpressure.txt"))), ..ProptestConfig::default() })]

    /// For random sizes, drain patterns and latencies, the frames on the
    /// wire are identical whether or not events are drained.
    #[test]
    fn wire_does_not_depend_on_draining_events(
        transfers in prop::collection::vec(transfer(), 1..=4),
        latencies in prop::collection::vec(latency(), 1..=6),
        client in prop::collection::vec(any::<bool>(), 1..=8),
        server in prop::collection::vec(any::<bool>(), 1..=8),
    ) {
        check_against_drained(&transfers, &latencies, Drain { client, server });
        check_against_drained(&transfers, &latencies, Drain::never());
    }
}
