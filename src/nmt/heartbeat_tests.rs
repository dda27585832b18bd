use super::*;
use crate::machine::Machine;
use core::time::Duration;
use std::vec::Vec;

fn ms(n: u64) -> Timestamp {
    Timestamp::from_millis(n)
}

use crate::cob_id::test_node as n;

fn hb(node: u8, state: u8) -> CanFrame {
    CanFrame::standard(0x700 + u16::from(node), &[state]).unwrap()
}

fn events<const N: usize>(c: &mut HeartbeatConsumer<N>) -> Vec<HeartbeatEvent> {
    core::iter::from_fn(|| c.poll_event()).collect()
}

#[test]
fn producer_boot_then_period() {
    let mut p = HeartbeatProducer::new(n(10), Duration::from_millis(1000));
    assert_eq!(p.poll_timeout(), None);
    p.boot(ms(0));
    assert_eq!(p.poll_timeout(), Some(ms(1000)));
    assert_eq!(p.poll_transmit(), Some(hb(10, 0x00)));
    assert_eq!(p.state(), NmtState::PreOperational);
    let mut sent = Vec::new();
    while let Some(now) = p.poll_timeout().filter(|t| *t <= ms(3500)) {
        if now == ms(2000) {
            // NMT start between heartbeats: reported at the next period.
            p.set_state(now, NmtState::Operational);
        }
        p.handle_timeout(now);
        sent.extend(core::iter::from_fn(|| p.poll_transmit()).map(|f| (now.as_millis(), f)));
    }
    assert_eq!(
        sent,
        vec![
            (1000, hb(10, 0x7F)),
            (2000, hb(10, 0x05)),
            (3000, hb(10, 0x05))
        ]
    );
}

#[test]
fn producer_options() {
    let mut p = HeartbeatProducer::new(n(1), Duration::from_millis(100));
    p.send_on_change = true;
    p.boot(ms(0));
    let _ = p.poll_transmit();
    p.set_state(ms(30), NmtState::Operational);
    assert_eq!(p.poll_transmit(), Some(hb(1, 0x05)));
    assert_eq!(p.poll_timeout(), Some(ms(130)));
    p.set_state(ms(40), NmtState::Operational);
    assert_eq!(p.poll_transmit(), None, "no change, nothing sent");
    p.set_period(ms(50), Duration::ZERO);
    assert_eq!(p.poll_timeout(), None);
    p.handle_timeout(ms(1000));
    assert_eq!(p.poll_transmit(), None);
}

#[test]
fn consumer_entries() {
    assert_eq!(
        ConsumerEntry::from_u32(0x0001_07D0),
        ConsumerEntry {
            node: 1,
            time_ms: 2000
        }
    );
    assert_eq!(
        ConsumerEntry {
            node: 1,
            time_ms: 2000
        }
        .to_u32(),
        0x0001_07D0
    );
    assert!(!ConsumerEntry {
        node: 0,
        time_ms: 2000
    }
    .is_enabled());
    assert!(!ConsumerEntry {
        node: 1,
        time_ms: 0
    }
    .is_enabled());
    assert!(!ConsumerEntry {
        node: 128,
        time_ms: 10
    }
    .is_enabled());
    let mut c: HeartbeatConsumer<2> = HeartbeatConsumer::new();
    assert!(c.set_entry(
        ms(0),
        0,
        ConsumerEntry {
            node: 1,
            time_ms: 2000
        }
    ));
    assert!(
        !c.set_entry(
            ms(0),
            1,
            ConsumerEntry {
                node: 1,
                time_ms: 500
            }
        ),
        "duplicate node"
    );
    assert!(
        !c.set_entry(
            ms(0),
            2,
            ConsumerEntry {
                node: 2,
                time_ms: 500
            }
        ),
        "no slot 2"
    );
    assert!(c.set_entry(
        ms(0),
        1,
        ConsumerEntry {
            node: 2,
            time_ms: 0
        }
    ));
    assert_eq!(
        c.entry(0),
        Some(ConsumerEntry {
            node: 1,
            time_ms: 2000
        })
    );
}

#[test]
fn consumer_lifecycle() {
    let mut c: HeartbeatConsumer<4> = HeartbeatConsumer::new();
    c.set_entry(
        ms(0),
        0,
        ConsumerEntry {
            node: 1,
            time_ms: 2000,
        },
    );
    // Not monitored before the first heartbeat.
    assert_eq!(c.poll_timeout(), None);
    c.handle_timeout(ms(100_000));
    assert_eq!(events(&mut c), vec![]);
    c.handle_frame(ms(100_000), &hb(1, 0x00));
    assert_eq!(events(&mut c), vec![HeartbeatEvent::BootUp(n(1))]);
    c.handle_frame(ms(100_100), &hb(1, 0x7F));
    assert_eq!(
        events(&mut c),
        vec![HeartbeatEvent::StateChanged {
            node: n(1),
            state: NmtState::PreOperational
        }]
    );
    c.handle_frame(ms(100_200), &hb(1, 0x7F));
    assert_eq!(events(&mut c), vec![]);
    assert!(c.is_alive(n(1)));
    assert_eq!(c.poll_timeout(), Some(ms(102_200)));
    c.handle_timeout(ms(102_199));
    assert_eq!(events(&mut c), vec![]);
    c.handle_timeout(ms(102_200));
    assert_eq!(events(&mut c), vec![HeartbeatEvent::Lost(n(1))]);
    assert!(!c.is_alive(n(1)));
    c.handle_timeout(ms(110_000));
    assert_eq!(events(&mut c), vec![], "lost once per silence");
    c.handle_frame(ms(110_000), &hb(1, 0x05));
    assert_eq!(
        events(&mut c),
        vec![HeartbeatEvent::Restored {
            node: n(1),
            state: NmtState::Operational
        }]
    );
    assert_eq!(c.state(n(1)), Some(NmtState::Operational));
    // Other nodes, guarding requests and malformed frames are ignored.
    c.handle_frame(ms(110_001), &hb(2, 0x05));
    c.handle_frame(ms(110_001), &CanFrame::standard(0x701, &[]).unwrap());
    c.handle_frame(
        ms(110_001),
        &CanFrame::remote(CanId::Standard(0x701), 1).unwrap(),
    );
    c.handle_frame(ms(110_001), &CanFrame::standard(0x181, &[5]).unwrap());
    assert_eq!(events(&mut c), vec![]);
    assert_eq!(c.poll_timeout(), Some(ms(112_000)));
}

#[test]
fn consumer_time_backwards_and_far_ahead() {
    let mut c: HeartbeatConsumer<1> = HeartbeatConsumer::new();
    c.set_entry(
        ms(0),
        0,
        ConsumerEntry {
            node: 5,
            time_ms: 100,
        },
    );
    c.handle_frame(ms(5000), &hb(5, 0x05));
    c.handle_timeout(ms(0));
    assert_eq!(events(&mut c), vec![]);
    c.handle_timeout(Timestamp::MAX);
    assert_eq!(events(&mut c), vec![HeartbeatEvent::Lost(n(5))]);
}

#[test]
fn producer_period_does_not_drift_when_called_late() {
    let mut p = HeartbeatProducer::new(n(3), Duration::from_millis(100));
    p.boot(ms(0));
    let _ = p.poll_transmit();
    // Called 30 ms late: sent now, the next one still at 200 ms.
    p.handle_timeout(ms(130));
    assert_eq!(p.poll_transmit(), Some(hb(3, 0x7F)));
    assert_eq!(p.poll_timeout(), Some(ms(200)));
    // Called more than a period late: one heartbeat, then a period from now.
    p.handle_timeout(ms(450));
    assert_eq!(p.poll_transmit(), Some(hb(3, 0x7F)));
    assert_eq!(p.poll_transmit(), None);
    assert_eq!(p.poll_timeout(), Some(ms(550)));
}

fn entry(node: u8, time_ms: u16) -> ConsumerEntry {
    ConsumerEntry { node, time_ms }
}

/// The device's path: `load_entries` keeps the watches of unchanged slots
/// running, restarts changed ones (and all with `restart`), disables the
/// slots past the entries; of two slots for one node only the first is
/// fed, the second never starts.
#[cfg(feature = "heartbeat-consumer")]
#[test]
fn consumer_load_entries() {
    let mut c: HeartbeatConsumer<3, 0> = HeartbeatConsumer::new();
    c.load_entries(&[entry(1, 100), entry(2, 100), entry(3, 100)], false);
    for node in 1..=3 {
        assert_eq!(c.take_frame(ms(0), &hb(node, 0x05)), None);
    }
    assert!((1..=3).all(|node| c.is_alive(n(node))));
    // Slot 1 changes, slot 2 is gone: slot 0 runs on.
    c.load_entries(&[entry(1, 100), entry(2, 200)], false);
    assert_eq!(
        (c.is_alive(n(1)), c.is_alive(n(2)), c.is_alive(n(3))),
        (true, false, false)
    );
    assert_eq!(
        (c.entry(2), c.poll_timeout()),
        (Some(entry(0, 0)), Some(ms(100)))
    );
    // A restart waits for every node's next heartbeat.
    c.load_entries(&[entry(1, 100), entry(2, 200)], true);
    assert_eq!((c.is_alive(n(1)), c.poll_timeout()), (false, None));
    // A duplicate: slot 0 is fed, slot 1 never armed.
    c.load_entries(&[entry(4, 100), entry(4, 300)], false);
    assert_eq!(c.take_frame(ms(10), &hb(4, 0x05)), None);
    assert_eq!(c.poll_timeout(), Some(ms(110)));
    assert_eq!(
        (c.expire_one(ms(500)), c.expire_one(ms(500))),
        (Some(n(4)), None)
    );
    // Its time is a 16-bit millisecond count: 65535 ms at most.
    c.load_entries(&[entry(5, u16::MAX)], false);
    let _ = c.take_frame(ms(1), &hb(5, 0x05));
    assert_eq!(c.poll_timeout(), Some(ms(65_536)));
}

/// One frame changes one watch, so it makes at most one event
/// (`take_frame` returns it); one timeout call reports every node whose
/// time ran out, once each, in slot order, even when all run out at once.
#[test]
fn consumer_events_per_call() {
    let mut c: HeartbeatConsumer<4, 0> = HeartbeatConsumer::new();
    for (slot, (node, time)) in [(4, 300), (3, 100), (2, 200), (1, 100)]
        .into_iter()
        .enumerate()
    {
        assert!(c.set_entry(ms(0), slot, entry(node, time)));
    }
    for node in [1, 2, 3, 4] {
        assert_eq!(
            c.take_frame(ms(0), &hb(node, 0x00)),
            Some(HeartbeatEvent::BootUp(n(node)))
        );
    }
    assert_eq!(c.take_frame(ms(1), &hb(3, 0x05)).map(|_| ()), Some(()));
    let lost = |c: &mut HeartbeatConsumer<4, 0>, at| {
        core::iter::from_fn(|| c.expire_one(ms(at))).collect::<Vec<_>>()
    };
    assert_eq!(lost(&mut c, 99), []);
    assert_eq!(lost(&mut c, 100), [n(1)]);
    assert_eq!(lost(&mut c, 10_000), [n(4), n(3), n(2)]);
    assert_eq!(lost(&mut c, 20_000), [], "lost once per silence");
    assert_eq!(
        c.take_frame(ms(20_000), &hb(2, 0x05)),
        Some(HeartbeatEvent::Restored {
            node: n(2),
            state: NmtState::Operational
        })
    );
    // The public machine queues the same events.
    let mut m: HeartbeatConsumer<4> = HeartbeatConsumer::new();
    for (slot, node) in [4, 3, 2, 1].into_iter().enumerate() {
        assert!(m.set_entry(ms(0), slot, entry(node, 100)));
        m.handle_frame(ms(0), &hb(node, 0x05));
    }
    assert_eq!(m.poll_timeout(), Some(ms(100)));
    m.handle_timeout(ms(100));
    assert_eq!(m.poll_timeout(), None);
    let all = [4, 3, 2, 1].map(|node| HeartbeatEvent::Lost(n(node)));
    assert_eq!((events(&mut m), m.events_dropped()), (all.to_vec(), 0));
}

/// 1017h's milliseconds as the device writes them: the same period and
/// timer as `set_period` with the `Duration`; zero stops the heartbeat; at
/// the end of the clock the one due heartbeat is sent, and no later one.
#[test]
fn producer_period_in_milliseconds() {
    let mut a = HeartbeatProducer::new(n(3), Duration::from_millis(100));
    let mut b = a.clone();
    a.set_period(ms(10), Duration::from_millis(65_535));
    b.set_period_ms(ms(10), u16::MAX);
    assert_eq!(
        (a.period(), a.poll_timeout()),
        (b.period(), b.poll_timeout())
    );
    assert_eq!(b.poll_timeout(), Some(ms(65_545)));
    b.set_period_ms(ms(20), 0);
    assert_eq!((b.period(), b.poll_timeout()), (Duration::ZERO, None));
    b.set_period_ms(Timestamp::from_micros(u64::MAX - 1_500), 1);
    b.handle_timeout(Timestamp::MAX);
    assert_eq!(b.poll_transmit(), Some(hb(3, 0x00)));
    assert_eq!((b.poll_transmit(), b.poll_timeout()), (None, None));
}
