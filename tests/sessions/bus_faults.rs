//! The simulated bus's faults that need many frames or a window of time:
//! the seeded random loss, bus-off, delays and a disconnected machine.

use std::time::Duration;

use canopen_codec::sim::bus::{Bus, Fate, Handle, OUTSIDE};

use super::sim::{us, Probe};
use crate::common::{frame, ms};

/// A bus of `latency_us` with a machine "a" that sends 700#05 every
/// millisecond from 1 ms on, and a machine "b" that only listens.
fn ticking(latency_us: u64) -> (Bus, Handle<Probe>, Handle<Probe>) {
    let mut bus = Bus::new(Duration::from_micros(latency_us));
    let mut a = Probe::default();
    a.period_us = Some(1_000);
    a.send_at(ms(1), frame(0x700, "05"));
    let a = bus.add("a", a);
    let b = bus.add("b", Probe::default());
    (bus, a, b)
}

/// The send numbers of the frames lost to the random loss.
fn lost(bus: &Bus) -> Vec<usize> {
    bus.log()
        .iter()
        .filter(|s| s.fate == Fate::Lost)
        .map(|s| s.n)
        .collect()
}

#[test]
fn random_loss_drops_the_share_asked_for_and_the_same_frames_for_a_seed() {
    let run = |probability: f64, seed: u64| {
        let (mut bus, _, b) = ticking(100);
        bus.set_loss(probability, seed);
        // Until the last frame sent at 10 s has arrived.
        bus.run_until(us(10_000_100)).unwrap();
        assert_eq!(bus.log().len(), 10_000);
        let lost = lost(&bus);
        assert_eq!(
            bus.events(b).len(),
            10_000 - lost.len(),
            "lost frames arrive"
        );
        lost
    };
    let first = run(0.2, 7);
    // Binomial(10 000, 0.2): mean 2 000, standard deviation 40.
    assert!((1_800..=2_200).contains(&first.len()), "{}", first.len());
    assert_eq!(run(0.2, 7), first, "the same seed loses the same frames");
    let other = run(0.2, 8);
    assert!((1_800..=2_200).contains(&other.len()), "{}", other.len());
    assert_ne!(other, first, "another seed loses other frames");
    let rare = run(0.01, 7).len();
    assert!((50..=150).contains(&rare), "{rare}");
    assert!(run(0.0, 7).is_empty());
    assert!(run(f64::NAN, 7).is_empty());
    assert_eq!(run(1.0, 7).len(), 10_000);
}

#[test]
fn bus_off_loses_everything_in_its_window_and_the_bus_resumes_after() {
    // 1.5 ms latency: the frame sent at 9 ms falls due at 10.5 ms, inside
    // the window, and is lost in flight; the one sent at 8 ms arrives.
    let (mut bus, _, b) = ticking(1_500);
    bus.bus_off(ms(10), ms(20));
    assert!(!bus.is_off(us(9_999)) && bus.is_off(ms(10)) && bus.is_off(us(19_999)));
    assert!(!bus.is_off(ms(20)));
    bus.run_until(ms(30)).unwrap();
    let fates: Vec<(u64, Fate)> = bus
        .log()
        .iter()
        .map(|s| (s.at.as_millis(), s.fate))
        .collect();
    for (at, fate) in &fates {
        let off = (9..20).contains(at);
        assert_eq!(*fate == Fate::BusOff, off, "sent at {at} ms: {fate:?}");
    }
    assert_eq!(bus.lost_to_bus_off(), 11);
    // Heard: the frames sent at 1..=8 ms, and at 20..=28 ms (the one sent
    // at 29 ms is still in flight).
    let heard: Vec<u64> = bus
        .events(b)
        .iter()
        .map(|(t, _)| t.as_micros() - 1_500)
        .collect();
    let expected: Vec<u64> = (1..=8).chain(20..=28).map(|m| m * 1_000).collect();
    assert_eq!(heard, expected);
    assert_eq!(
        bus.lines(19, 20),
        ["    19.000 a 700#05 bus-off", "    20.000 a 700#05"]
    );
    // Injected frames are lost in a window too.
    bus.bus_off(ms(30), ms(31));
    bus.inject(frame(0x000, "0100"));
    assert_eq!(
        bus.log().last().map(|s| (s.from, s.fate)),
        Some((OUTSIDE, Fate::BusOff))
    );
    assert_eq!(bus.lost_to_bus_off(), 12);
}

#[test]
fn a_delayed_frame_arrives_behind_the_frames_sent_after_it() {
    let mut bus = Bus::new(Duration::from_micros(100));
    let a = bus.add("a", Probe::default());
    let b = bus.add("b", Probe::default());
    bus.delay_if(Duration::from_micros(500), |s| s.frame.data() == [1]);
    bus.with(a, |m, _| {
        for d in ["01", "02", "03"] {
            m.send(frame(0x180, d));
        }
    });
    bus.drive_bounded(10).unwrap();
    assert_eq!(
        bus.events(b),
        [
            (us(100), frame(0x180, "02")),
            (us(100), frame(0x180, "03")),
            (us(600), frame(0x180, "01")),
        ]
    );
    let delays: Vec<u64> = bus
        .log()
        .iter()
        .map(|s| s.delay.as_micros() as u64)
        .collect();
    assert_eq!(delays, [500, 0, 0]);
}

#[test]
fn a_disconnected_machine_runs_on_but_hears_and_reaches_nobody() {
    let (mut bus, a, b) = ticking(100);
    bus.set_connected(a, false);
    bus.with(b, |m, _| m.send(frame(0x200, "01")));
    bus.run_until(us(3_500)).unwrap();
    // a's timer runs on: it sent at 1, 2 and 3 ms, all lost.
    let fates: Vec<Fate> = bus.sent_by("a").map(|s| s.fate).collect();
    assert_eq!(fates, [Fate::Disconnected; 3]);
    assert!(bus.events(a).is_empty(), "a heard b");
    assert!(bus.events(b).is_empty(), "b heard a");
    // Connected again: both ways work.
    bus.set_connected(a, true);
    bus.run_until(us(4_500)).unwrap();
    assert_eq!(bus.events(b), [(us(4_100), frame(0x700, "05"))]);
    bus.with(b, |m, _| m.send(frame(0x200, "02")));
    bus.run_until(ms(5)).unwrap();
    assert_eq!(bus.events(a), [(us(4_600), frame(0x200, "02"))]);
}

#[test]
fn a_handle_of_another_type_finds_no_machine() {
    let mut bus = Bus::new(Duration::ZERO);
    let p = bus.add("p", Probe::default());
    let mut other = Bus::new(Duration::ZERO);
    let wrong = other.add_unplugged::<canopen_codec::nmt::heartbeat::HeartbeatProducer>("h");
    assert!(bus.machine(p).is_some());
    assert!(bus.machine(wrong).is_none());
    assert!(bus.with(wrong, |_, _| ()).is_none());
    assert_eq!(bus.name(wrong), Some("p"), "the place is p's");
    assert!(!bus.is_plugged(wrong));
    let producer = canopen_codec::nmt::heartbeat::HeartbeatProducer::new(
        canopen_codec::NodeId::new(1).unwrap(),
        Duration::from_millis(100),
    );
    assert!(bus.plug(wrong, producer).is_err(), "handed back");
    assert!(bus.unplug(p).is_some());
    assert!(bus.machine(p).is_none());
}
