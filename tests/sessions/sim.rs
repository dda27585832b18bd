//! The simulated bus itself (`canopen_codec::sim::bus::Bus`): delivery to every other
//! machine after the latency and in send order, the clock steps, faults,
//! unplugging, and the back-pressure rule of `canopen_codec::machine`
//! checked through it.

use crate::common;

use std::collections::VecDeque;
use std::time::Duration;

#[cfg(feature = "heartbeat-consumer")]
use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig};
#[cfg(feature = "heartbeat-consumer")]
use canopen_codec::deltaq::{Charger, ChargerConfig, ChargerEvent};
use canopen_codec::machine::Machine;
use canopen_codec::nmt::heartbeat::{
    ConsumerEntry, HeartbeatConsumer, HeartbeatEvent, HeartbeatProducer,
};
use canopen_codec::nmt::NmtState;
use canopen_codec::{CanFrame, NodeId, Timestamp};
#[cfg(feature = "heartbeat-consumer")]
use common::devices::{boot_all, charger_bus};
use common::sim::{bus, Bus, Fate, Handle, OUTSIDE};
use common::{frame, ms};

pub(crate) fn us(n: u64) -> Timestamp {
    Timestamp::from_micros(n)
}

/// A machine that reports every frame it hears as an event, sends what it
/// is told to, optionally answers every frame on `echo`, and has one timer
/// that sends `on_timer` when due (re-armed every `period_us` if set).
#[derive(Default)]
pub(crate) struct Probe {
    out: VecDeque<CanFrame>,
    heard: VecDeque<CanFrame>,
    echo: Option<u16>,
    due: Option<Timestamp>,
    on_timer: Option<CanFrame>,
    pub(crate) period_us: Option<u64>,
}

impl Probe {
    pub(crate) fn echoing(id: u16) -> Self {
        Probe {
            echo: Some(id),
            ..Probe::default()
        }
    }

    pub(crate) fn send(&mut self, frame: CanFrame) {
        self.out.push_back(frame);
    }

    pub(crate) fn send_at(&mut self, due: Timestamp, frame: CanFrame) {
        self.due = Some(due);
        self.on_timer = Some(frame);
    }
}

impl Machine for Probe {
    type Event = CanFrame;
    fn handle_frame(&mut self, _now: Timestamp, frame: &CanFrame) {
        self.heard.push_back(*frame);
        if let Some(id) = self.echo {
            self.out
                .push_back(CanFrame::standard(id, frame.data()).unwrap());
        }
    }
    fn handle_timeout(&mut self, now: Timestamp) {
        if self.due.is_some_and(|d| now.has_reached(d)) {
            self.due = self.period_us.map(|p| now.add_micros(p));
            self.out.extend(self.on_timer);
        }
    }
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.out.pop_front()
    }
    fn poll_timeout(&self) -> Option<Timestamp> {
        self.due
    }
    fn poll_event(&mut self) -> Option<CanFrame> {
        self.heard.pop_front()
    }
    fn events_dropped(&self) -> u64 {
        0
    }

    fn frames_dropped(&self) -> u64 {
        0
    }
}

#[test]
fn frames_reach_every_other_machine_in_send_order_after_the_latency() {
    let mut sim = bus(250);
    let a = sim.add("a", Probe::default());
    let b = sim.add("b", Probe::default());
    let c = sim.add("c", Probe::default());
    sim.with(a, |m, _| {
        m.send(frame(0x100, "01"));
        m.send(frame(0x100, "02"));
    });
    sim.with(b, |m, _| m.send(frame(0x200, "")));
    sim.inject(frame(0x000, "0100"));
    sim.run_until(ms(1)).unwrap();
    let t = us(250);
    assert_eq!(
        sim.events(a),
        [(t, frame(0x200, "")), (t, frame(0x000, "0100"))]
    );
    assert_eq!(
        sim.events(b),
        [
            (t, frame(0x100, "01")),
            (t, frame(0x100, "02")),
            (t, frame(0x000, "0100"))
        ]
    );
    assert_eq!(
        sim.event_list(c),
        [
            frame(0x100, "01"),
            frame(0x100, "02"),
            frame(0x200, ""),
            frame(0x000, "0100")
        ]
    );
    assert_eq!(
        sim.lines(0, 1),
        [
            "     0.000 a 100#01",
            "     0.000 a 100#02",
            "     0.000 b 200#",
            "     0.000 Outside 000#0100",
        ]
    );
    assert_eq!(
        sim.log().iter().map(|s| s.n).collect::<Vec<_>>(),
        [0, 1, 2, 3]
    );
    assert_eq!(sim.sent_by(OUTSIDE).count(), 1);
    assert_eq!(sim.now(), ms(1));
    // Events can be taken or cleared.
    assert_eq!(sim.take_events(a).len(), 2);
    assert!(sim.events(a).is_empty());
    sim.clear_events();
    assert!(sim.events(b).is_empty() && sim.events(c).is_empty());
}

#[test]
fn an_answer_is_sent_when_the_request_arrives() {
    for latency in [0u64, 1_000] {
        let mut sim = bus(latency);
        let client = sim.add("client", Probe::default());
        let _server = sim.add("server", Probe::echoing(0x581));
        sim.with(client, |m, _| m.send(frame(0x601, "40")));
        sim.drive_bounded(10).unwrap();
        let times: Vec<(u64, &str)> = sim
            .log()
            .iter()
            .map(|s| (s.at.as_micros(), s.from))
            .collect();
        assert_eq!(times, [(0, "client"), (latency, "server")]);
        assert_eq!(sim.events(client), [(us(2 * latency), frame(0x581, "40"))]);
        assert_eq!(sim.now(), us(2 * latency));
    }
}

#[test]
fn frames_are_dropped_by_number_or_predicate_and_duplicated() {
    let mut sim = bus(100);
    let a = sim.add("a", Probe::default());
    let b = sim.add("b", Probe::default());
    let c = sim.add("c", Probe::default());
    sim.drop_nth(0);
    sim.drop_if(|s| s.from == "b");
    sim.duplicate_nth(2);
    sim.duplicate_nth(3); // dropped anyway: sent by b
    sim.with(a, |m, _| {
        for d in ["00", "01", "02"] {
            m.send(frame(0x180, d));
        }
    });
    sim.with(b, |m, _| m.send(frame(0x280, "03")));
    sim.drive_bounded(10).unwrap();
    assert_eq!(
        sim.event_list(c),
        [frame(0x180, "01"), frame(0x180, "02"), frame(0x180, "02")]
    );
    assert!(sim.events(a).is_empty(), "b's frame was lost");
    let fates: Vec<Fate> = sim.log().iter().map(|s| s.fate).collect();
    assert_eq!(
        fates,
        [
            Fate::Dropped,
            Fate::Delivered,
            Fate::Duplicated,
            Fate::Dropped
        ]
    );
    assert_eq!(
        sim.lines(0, 0),
        [
            "     0.000 a 180#00 dropped",
            "     0.000 a 180#01",
            "     0.000 a 180#02 duplicated",
            "     0.000 b 280#03 dropped",
        ]
    );
}

#[test]
fn run_until_runs_what_is_due_at_end_and_nothing_later() {
    let mut sim = bus(500);
    let a = sim.add("a", Probe::default());
    let b = sim.add("b", Probe::default());
    sim.with(a, |m, _| m.send_at(ms(10), frame(0x701, "05")));
    sim.run_until(ms(9)).unwrap();
    assert!(sim.log().is_empty());
    assert_eq!(sim.now(), ms(9));
    sim.run_until(ms(10)).unwrap();
    assert_eq!(sim.lines(0, 10), ["    10.000 a 701#05"]);
    assert!(sim.events(b).is_empty(), "still in flight");
    assert_eq!(sim.now(), ms(10));
    sim.run_until(us(10_499)).unwrap();
    assert!(sim.events(b).is_empty());
    sim.run_until(us(10_500)).unwrap();
    assert_eq!(sim.events(b), [(us(10_500), frame(0x701, "05"))]);
    // The clock never goes back.
    sim.run_until(ms(1)).unwrap();
    assert_eq!(sim.now(), us(10_500));
}

#[test]
fn drive_bounded_stops_when_quiescent_and_fails_on_livelock() {
    let mut sim = bus(1_000);
    let a = sim.add("a", Probe::default());
    let b = sim.add("b", Probe::default());
    assert_eq!(sim.drive_bounded(1), Ok(()), "nothing to do");
    sim.with(a, |m, _| m.send(frame(0x100, "")));
    // One step delivers the frame, the next finds nothing to do.
    assert!(sim.drive_bounded(1).is_err());
    assert_eq!(sim.events(b).len(), 1);
    assert_eq!(sim.drive_bounded(1), Ok(()));
    // A timer that always re-arms is never quiescent.
    let mut periodic = Probe {
        period_us: Some(1_000),
        ..Probe::default()
    };
    periodic.send_at(ms(1), frame(0x700, ""));
    let p = sim.add("periodic", periodic);
    let err = sim.drive_bounded(50).unwrap_err();
    assert_eq!(err.steps, 50);
    assert!(err.to_string().starts_with("livelock"), "{err}");
    assert_eq!(sim.sent_by(sim.name(p).unwrap()).count(), 50);
    // The heartbeat producer too: with no latency a frame sent at a timer
    // is delivered in the next step, at the same time (two steps a period).
    let mut sim = bus(0);
    let h = sim.add(
        "heartbeat",
        HeartbeatProducer::new(NodeId::new(1).unwrap(), Duration::from_millis(100)),
    );
    sim.with(h, |m, now| m.boot(now));
    assert!(sim.drive_bounded(20).is_err());
    assert_eq!(sim.now(), ms(1000));
}

#[test]
fn an_unplugged_machine_hears_nothing_and_its_timers_stop() {
    let mut sim = bus(1_000);
    let a = sim.add("a", Probe::default());
    let b = sim.add("b", Probe::default());
    sim.with(b, |m, _| {
        m.send(frame(0x200, "01"));
        m.send_at(ms(5), frame(0x200, "02"));
    });
    let old = sim.unplug(b).unwrap();
    assert!(!sim.is_plugged(b));
    assert_eq!(old.due, Some(ms(5)));
    sim.with(a, |m, _| m.send(frame(0x100, "")));
    sim.run_until(ms(10)).unwrap();
    // What b sent before it was unplugged still arrives.
    assert_eq!(sim.events(a), [(ms(1), frame(0x200, "01"))]);
    assert_eq!(
        sim.lines(0, 10),
        ["     0.000 b 200#01", "     0.000 a 100#"]
    );
    assert!(sim.events(b).is_empty());
    // A new machine in b's place hears what is sent from now on.
    assert!(sim.plug(b, Probe::default()).is_ok());
    sim.with(a, |m, _| m.send(frame(0x100, "02")));
    sim.run_until(ms(20)).unwrap();
    assert_eq!(sim.events(b), [(ms(11), frame(0x100, "02"))]);
}

/// What the consumer says of the producer: its state, and whether alive.
type Seen = (Option<NmtState>, bool);

/// Runs a heartbeat producer (node 1, 100 ms, reporting every state change
/// at once) and a consumer watching it (250 ms) for 5 s: the producer
/// changes its state every 120 ms and is unplugged at 4 s. Returns the
/// simulation, the consumer and its state and liveness at every 50 ms.
fn heartbeat_session(drain: bool) -> (Bus, Handle<HeartbeatConsumer<1>>, Vec<Seen>) {
    let node = NodeId::new(1).unwrap();
    let mut sim = bus(300);
    let mut producer = HeartbeatProducer::new(node, Duration::from_millis(100));
    producer.send_on_change = true;
    let p = sim.add("producer", producer);
    let mut consumer: HeartbeatConsumer<1> = HeartbeatConsumer::new();
    assert!(consumer.set_entry(
        Timestamp::ZERO,
        0,
        ConsumerEntry::new(node, Duration::from_millis(250))
    ));
    let c = sim.add("consumer", consumer);
    sim.set_drain_events(c, drain);
    sim.with(p, |m, now| m.boot(now));
    let mut seen = Vec::new();
    let mut k = 0u64;
    for step in 1..=100u64 {
        let t = ms(step * 50);
        if t >= ms(4000) && sim.is_plugged(p) {
            sim.unplug(p);
        }
        if sim.is_plugged(p) && step % 12 == 0 {
            k += 1;
            let state = if k.is_multiple_of(2) {
                NmtState::PreOperational
            } else {
                NmtState::Operational
            };
            sim.with(p, |m, now| m.set_state(now, state));
        }
        sim.run_until(t).unwrap();
        let consumer = sim.machine(c).unwrap();
        seen.push((consumer.state(node), consumer.is_alive(node)));
    }
    (sim, c, seen)
}

#[test]
fn undrained_consumer_events_change_no_protocol_behaviour() {
    let (drained, c, seen_drained) = heartbeat_session(true);
    let (mut undrained, cu, seen_undrained) = heartbeat_session(false);
    assert_eq!(drained.log(), undrained.log());
    assert_eq!(seen_drained, seen_undrained);
    // The session really has state changes and the loss in it.
    let node = NodeId::new(1).unwrap();
    let events = drained.event_list(c);
    assert_eq!(events.first(), Some(&HeartbeatEvent::BootUp(node)));
    assert_eq!(events.last(), Some(&HeartbeatEvent::Lost(node)));
    assert!(events.len() > 8, "{events:?}");
    assert_eq!(
        seen_drained.last(),
        Some(&(Some(NmtState::PreOperational), false))
    );
    // Undrained: nothing recorded, the latest 8 kept, the rest counted.
    assert!(undrained.events(cu).is_empty());
    let kept: Vec<HeartbeatEvent> =
        std::iter::from_fn(|| undrained.machine_mut(cu).unwrap().poll_event()).collect();
    assert_eq!(kept, events[events.len() - 8..]);
    assert_eq!(
        undrained.machine(cu).unwrap().events_dropped(),
        (events.len() - 8) as u64
    );
}

/// The charger and the battery module for 8 s: configuration, NMT start,
/// a communication reset of the module at 3 s, the module unplugged at
/// 5 s. Events of the two are drained or not as asked.
#[cfg(feature = "heartbeat-consumer")]
fn device_session(drain_charger: bool, drain_battery: bool) -> Session {
    let charger = Charger::new(ChargerConfig::new(
        NodeId::new(10).unwrap(),
        NodeId::new(1).unwrap(),
    ));
    let battery = BatteryModule::new(BatteryModuleConfig::new(NodeId::new(1).unwrap()));
    let (mut sim, c, b) = charger_bus(charger, Some(battery));
    sim.set_drain_events(c, drain_charger);
    sim.set_drain_events(b, drain_battery);
    boot_all(&mut sim, c, b);
    sim.run_until(ms(100)).unwrap();
    sim.inject(frame(0x000, "0100"));
    sim.run_until(ms(3000)).unwrap();
    sim.inject(frame(0x000, "8201"));
    sim.run_until(ms(5000)).unwrap();
    let unplugged = sim.unplug(b).unwrap();
    sim.run_until(ms(8000)).unwrap();
    Session {
        sim,
        charger: c,
        battery: b,
        unplugged,
    }
}

#[cfg(feature = "heartbeat-consumer")]
struct Session {
    sim: Bus,
    charger: Handle<Charger>,
    battery: Handle<BatteryModule>,
    /// The module, as it was when unplugged.
    unplugged: BatteryModule,
}

/// An undrained machine kept the newest of the events a drained one
/// reported (the oldest were dropped), and reported them nowhere else.
#[cfg(feature = "heartbeat-consumer")]
fn kept_newest<E: PartialEq + std::fmt::Debug>(all: &[E], kept: &[E]) {
    assert!(
        !kept.is_empty() && kept.len() < all.len(),
        "{} of {}",
        kept.len(),
        all.len()
    );
    assert_eq!(kept, &all[all.len() - kept.len()..]);
}

#[cfg(feature = "heartbeat-consumer")]
#[test]
fn undrained_device_events_change_no_protocol_behaviour() {
    let Session {
        sim: drained,
        charger: c,
        battery: b,
        ..
    } = device_session(true, true);
    let lines = drained.lines(0, 8000);
    // The session has what it should: configuration, TPDOs, the loss EMCY.
    assert!(lines
        .iter()
        .any(|l| l.contains("Charger 601#4000100000000000")));
    assert!(lines.iter().any(|l| l.contains("Battery 181#")));
    assert!(lines
        .iter()
        .any(|l| l.contains("Charger 08A#3081012080000000")));
    let charger_events = drained.event_list(c);
    assert!(charger_events.contains(&ChargerEvent::BatteryLost));
    let battery_events = drained.event_list(b);
    for (drain_charger, drain_battery) in [(false, true), (true, false), (false, false)] {
        let Session {
            sim: mut undrained,
            mut unplugged,
            ..
        } = device_session(drain_charger, drain_battery);
        assert_eq!(
            undrained.lines(0, 8000),
            lines,
            "charger drained {drain_charger}, battery drained {drain_battery}"
        );
        if !drain_charger {
            assert!(undrained.events(c).is_empty());
            let kept: Vec<_> =
                std::iter::from_fn(|| undrained.machine_mut(c).unwrap().poll_event()).collect();
            kept_newest(&charger_events, &kept);
        }
        if !drain_battery {
            assert!(undrained.events(b).is_empty());
            let kept: Vec<_> = std::iter::from_fn(|| unplugged.poll_event()).collect();
            kept_newest(&battery_events, &kept);
        }
    }
}
