//! `Pair`: an SDO client and server on one simulated bus, with a simulated
//! clock from zero, latency and dropped frames; `drive_bounded` fails on
//! livelock.

use std::collections::VecDeque;

use canopen_codec::machine::Machine;
use canopen_codec::od::{MemoryDictionary, ObjectDictionary};
use canopen_codec::sdo::{Client, ClientConfig, ClientEvent, Server, ServerConfig, ServerEvent};
use canopen_codec::{CanFrame, NodeId, Timestamp};

/// Which way a frame travels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dir {
    ToServer,
    ToClient,
}

pub struct Pair<D = MemoryDictionary> {
    pub client: Client<Vec<u8>>,
    pub server: Server<D>,
    pub now: Timestamp,
    /// One-way latency in microseconds.
    pub latency_us: u64,
    /// Frames are numbered from 0 in the order they are sent; these are dropped.
    pub drop: Vec<usize>,
    /// Every frame sent, with its send time and whether it was dropped.
    pub wire: Vec<(Timestamp, Dir, CanFrame, bool)>,
    pub client_events: Vec<ClientEvent>,
    pub server_events: Vec<ServerEvent>,
    in_flight: VecDeque<(Timestamp, Dir, CanFrame)>,
}

impl<D: ObjectDictionary> Pair<D> {
    pub fn new(node: u8, od: D) -> Self {
        let node = NodeId::new(node).unwrap();
        Pair {
            client: Client::new(ClientConfig::for_server(node)),
            server: Server::new(ServerConfig::for_node(node), od),
            now: Timestamp::ZERO,
            latency_us: 1_000,
            drop: Vec::new(),
            wire: Vec::new(),
            client_events: Vec::new(),
            server_events: Vec::new(),
            in_flight: VecDeque::new(),
        }
    }

    fn collect(&mut self) {
        loop {
            let mut moved = false;
            while let Some(f) = self.client.poll_transmit() {
                self.put(Dir::ToServer, f);
                moved = true;
            }
            while let Some(f) = self.server.poll_transmit() {
                self.put(Dir::ToClient, f);
                moved = true;
            }
            while let Some(e) = self.client.poll_event() {
                self.client_events.push(e);
                moved = true;
            }
            while let Some(e) = self.server.poll_event() {
                self.server_events.push(e);
                moved = true;
            }
            if !moved {
                break;
            }
        }
    }

    fn put(&mut self, dir: Dir, f: CanFrame) {
        let n = self.wire.len();
        let dropped = self.drop.contains(&n);
        self.wire.push((self.now, dir, f, dropped));
        if !dropped {
            self.in_flight
                .push_back((self.now.add_micros(self.latency_us), dir, f));
        }
    }

    /// Runs until nothing is in flight and no timer is armed. Fails after
    /// `max_steps` clock steps (livelock).
    pub fn drive_bounded(&mut self, max_steps: usize) -> Result<(), String> {
        for _ in 0..max_steps {
            self.collect();
            let next_delivery = self.in_flight.iter().map(|(t, ..)| *t).min();
            let next = [
                next_delivery,
                self.client.poll_timeout(),
                self.server.poll_timeout(),
            ]
            .into_iter()
            .flatten()
            .min();
            let Some(next) = next else {
                return Ok(());
            };
            self.now = self.now.max(next);
            // Deliver everything due, in send order.
            while let Some(pos) = self.in_flight.iter().position(|(t, ..)| *t <= self.now) {
                let (_, dir, f) = self.in_flight.remove(pos).unwrap();
                match dir {
                    Dir::ToServer => self.server.handle_frame(self.now, &f),
                    Dir::ToClient => self.client.handle_frame(self.now, &f),
                }
                self.collect();
            }
            self.client.handle_timeout(self.now);
            self.server.handle_timeout(self.now);
        }
        Err(format!("livelock: not quiescent after {max_steps} steps"))
    }

    /// The value collected from the client's upload events.
    pub fn uploaded(&self) -> Vec<u8> {
        let mut v = Vec::new();
        for e in &self.client_events {
            if let ClientEvent::UploadData { offset, data, .. } = e {
                assert_eq!(*offset, v.len(), "upload pieces out of order");
                v.extend_from_slice(data.as_slice());
            }
        }
        v
    }

    pub fn clear_events(&mut self) {
        self.client_events.clear();
        self.server_events.clear();
    }
}
