//! The simulated bus's per-delivery observer (`Bus::run_until_observed`):
//! it sees each frame handed to each machine, before and after, with the
//! machine's state and the answer it sent at that moment.

use std::time::Duration;

use canopen_codec::nmt::guarding::{GuardingMaster, GuardingSlave};
use canopen_codec::nmt::NmtState;
use canopen_codec::sim::bus::{Bus, Delivery, OUTSIDE};
use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};

use crate::common::ms;

#[test]
fn an_observer_sees_each_delivery_before_and_after_with_the_reply_on_the_log() {
    let node = NodeId::new(10).unwrap();
    let mut bus = Bus::new(Duration::from_micros(200));
    let master = bus.add(
        "Master",
        GuardingMaster::new(node, Duration::from_millis(100), 3),
    );
    let slave = bus.add("Slave", GuardingSlave::new(node));
    bus.with(slave, |s, _| s.set_state(NmtState::Operational));
    bus.with(master, |m, now| m.start(now));
    // (send number, from, to, handled, frames the slave had sent by then)
    let mut seen: Vec<(usize, &str, &str, bool, usize)> = Vec::new();
    bus.run_until_observed(ms(150), &mut |d: &Delivery, bus: &Bus| {
        assert_eq!(d.at, bus.now());
        assert!(bus.machine(slave).is_some());
        seen.push((d.n, d.from, d.to, d.handled, bus.sent_by("Slave").count()));
    })
    .unwrap();
    // The master's remote request at 0 and 100 ms, each answered by the
    // slave the moment it handles it; the answers reach the master.
    assert_eq!(
        seen,
        [
            (0, "Master", "Slave", false, 0),
            (0, "Master", "Slave", true, 1),
            (1, "Slave", "Master", false, 1),
            (1, "Slave", "Master", true, 1),
            (2, "Master", "Slave", false, 1),
            (2, "Master", "Slave", true, 2),
            (3, "Slave", "Master", false, 2),
            (3, "Slave", "Master", true, 2),
        ]
    );
    let toggles: Vec<u8> = bus
        .sent_by("Slave")
        .map(|s| s.frame.data()[0] & 0x80)
        .collect();
    assert_eq!(toggles, [0x00, 0x80]);

    // An injected frame reaches both machines, each seen twice; an
    // unobserved run after it sees nothing.
    bus.inject(CanFrame::standard(0x000, &[0x01, 0x00]).unwrap());
    let mut injected = Vec::new();
    bus.step_observed(Timestamp::from_millis(151), &mut |d, _| {
        injected.push((d.from, d.to, d.handled, d.frame.id()));
    });
    assert_eq!(
        injected,
        [
            (OUTSIDE, "Master", false, CanId::Standard(0)),
            (OUTSIDE, "Master", true, CanId::Standard(0)),
            (OUTSIDE, "Slave", false, CanId::Standard(0)),
            (OUTSIDE, "Slave", true, CanId::Standard(0)),
        ]
    );
}
