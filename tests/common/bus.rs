//! `Bus`: a charger and a battery module on one simulated CAN bus, with a
//! simulated clock from zero. Every frame reaches every other node after
//! `latency_us`; the test itself can inject frames (as an NMT master).
//! `run_until` fails on livelock.

use std::collections::VecDeque;

use canopen_codec::cia418::{BatteryEvent, BatteryModule};
use canopen_codec::cia419::{Charger, ChargerEvent};
use canopen_codec::{CanFrame, Timestamp};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sender {
    Charger,
    Battery,
    Test,
}

pub struct Bus {
    pub charger: Option<Charger>,
    pub battery: Option<BatteryModule>,
    pub now: Timestamp,
    pub latency_us: u64,
    /// Every frame on the bus: send time, sender, frame.
    pub log: Vec<(Timestamp, Sender, CanFrame)>,
    pub charger_events: Vec<(Timestamp, ChargerEvent)>,
    pub battery_events: Vec<(Timestamp, BatteryEvent)>,
    in_flight: VecDeque<(Timestamp, Sender, CanFrame)>,
}

impl Bus {
    pub fn new(charger: Option<Charger>, battery: Option<BatteryModule>) -> Self {
        Bus {
            charger,
            battery,
            now: Timestamp::ZERO,
            latency_us: 500,
            log: Vec::new(),
            charger_events: Vec::new(),
            battery_events: Vec::new(),
            in_flight: VecDeque::new(),
        }
    }

    pub fn boot_all(&mut self) {
        let now = self.now;
        if let Some(b) = &mut self.battery {
            b.boot(now);
        }
        if let Some(c) = &mut self.charger {
            c.boot(now);
        }
        self.collect();
    }

    /// Sends a frame from the test (e.g. an NMT command).
    pub fn inject(&mut self, frame: CanFrame) {
        self.log.push((self.now, Sender::Test, frame));
        self.in_flight
            .push_back((self.now.add_micros(self.latency_us), Sender::Test, frame));
    }

    fn collect(&mut self) {
        let now = self.now;
        if let Some(c) = &mut self.charger {
            while let Some(f) = c.poll_transmit() {
                self.log.push((now, Sender::Charger, f));
                self.in_flight
                    .push_back((now.add_micros(self.latency_us), Sender::Charger, f));
            }
            while let Some(e) = c.poll_event() {
                self.charger_events.push((now, e));
            }
        }
        if let Some(b) = &mut self.battery {
            while let Some(f) = b.poll_transmit() {
                self.log.push((now, Sender::Battery, f));
                self.in_flight
                    .push_back((now.add_micros(self.latency_us), Sender::Battery, f));
            }
            while let Some(e) = b.poll_event() {
                self.battery_events.push((now, e));
            }
        }
    }

    /// Runs the bus until `end` (inclusive of deadlines at `end`).
    pub fn run_until(&mut self, end: Timestamp) {
        for _ in 0..1_000_000 {
            self.collect();
            let next = [
                self.in_flight.iter().map(|(t, ..)| *t).min(),
                self.charger.as_ref().and_then(Charger::poll_timeout),
                self.battery.as_ref().and_then(BatteryModule::poll_timeout),
            ]
            .into_iter()
            .flatten()
            .min();
            let Some(next) = next.filter(|t| *t <= end) else {
                self.now = self.now.max(end);
                return;
            };
            self.now = self.now.max(next);
            while let Some(pos) = self.in_flight.iter().position(|(t, ..)| *t <= self.now) {
                let (_, from, f) = self.in_flight.remove(pos).unwrap();
                let now = self.now;
                if from != Sender::Charger {
                    if let Some(c) = &mut self.charger {
                        c.handle_frame(now, &f);
                    }
                }
                if from != Sender::Battery {
                    if let Some(b) = &mut self.battery {
                        b.handle_frame(now, &f);
                    }
                }
                self.collect();
            }
            let now = self.now;
            if let Some(c) = &mut self.charger {
                c.handle_timeout(now);
            }
            if let Some(b) = &mut self.battery {
                b.handle_timeout(now);
            }
        }
        panic!("livelock: the bus never reached {end}");
    }

    /// The log between two instants (ms, inclusive) as "ms sender frame" lines.
    pub fn lines(&self, from_ms: u64, to_ms: u64) -> Vec<String> {
        self.log
            .iter()
            .filter(|(t, ..)| t.as_millis() >= from_ms && t.as_millis() <= to_ms)
            .map(|(t, s, f)| {
                format!(
                    "{:>6}.{:03} {:?} {f}",
                    t.as_millis(),
                    t.as_micros() % 1000,
                    s
                )
            })
            .collect()
    }

    /// Frames with this identifier, as (send time in µs, data).
    pub fn frames_on(&self, id: u16) -> Vec<(u64, Vec<u8>)> {
        self.log
            .iter()
            .filter(|(_, _, f)| f.id() == canopen_codec::CanId::Standard(id))
            .map(|(t, _, f)| (t.as_micros(), f.data().to_vec()))
            .collect()
    }
}
