//! Node guarding on the simulated bus: a [`GuardingMaster`] guarding a
//! plain CiA 301 device (the device core's guarding slave). Lost and
//! restored when the slave is unplugged and plugged back, toggle errors, a
//! state mismatch, the slave's life guarding event when the master stops,
//! and heartbeat and guarding being exclusive (CiA 301 "CANopen application
//! layer and communication profile", section 7.2.8.3.2 "Error control
//! protocols").

use crate::common;

use core::time::Duration;

use crate::common::ms;
use canopen_codec::device::{Cia301Device, DeviceConfig, DeviceEvent};
use canopen_codec::nmt::guarding::{GuardingMaster, MasterGuardingEvent, SlaveGuardingEvent};
use canopen_codec::nmt::NmtState;
use canopen_codec::od::MemoryDictionary;
use canopen_codec::{CanFrame, NodeId};
use common::sim::{Bus, Handle};

type Slave = Cia301Device<MemoryDictionary>;

const SLAVE: &str = "Slave";
const MASTER: &str = "Master";

fn node() -> NodeId {
    NodeId::new(5).unwrap()
}

/// Heartbeat 0 (guarding allowed), guard time 100 ms, life time factor 3.
fn slave_config() -> DeviceConfig {
    DeviceConfig {
        heartbeat: Duration::ZERO,
        guard_time: Duration::from_millis(100),
        life_time_factor: 3,
        ..DeviceConfig::new(node())
    }
}

fn nmt(cs: u8) -> CanFrame {
    CanFrame::standard(0x000, &[cs, 5]).unwrap()
}

/// The slave booted and started at 0 ms, the master guarding from 10 ms
/// (guard time 100 ms, factor 3, expecting operational).
fn bus(config: DeviceConfig) -> (Bus, Handle<Slave>, Handle<GuardingMaster>) {
    let mut sim = common::sim::bus(200);
    let s = sim.add(SLAVE, Slave::plain(config, MemoryDictionary::new()));
    sim.with(s, |d, now| d.boot(now));
    sim.inject(nmt(0x01));
    let m = sim.add(
        MASTER,
        GuardingMaster::new(node(), Duration::from_millis(100), 3),
    );
    sim.run_until(ms(10)).unwrap();
    // The master heard the boot-up message.
    assert_eq!(sim.event_list(m), [MasterGuardingEvent::BootUp(node())]);
    sim.clear_events();
    sim.with(m, |g, now| {
        g.set_expected_state(Some(NmtState::Operational));
        g.start(now);
    });
    (sim, s, m)
}

/// The slave's guarding replies (data frames on 705h) as bytes.
fn replies(sim: &Bus) -> Vec<u8> {
    sim.sent_by(SLAVE)
        .filter(|s| !s.frame.is_remote() && s.frame.id() == canopen_codec::CanId::Standard(0x705))
        .flat_map(|s| s.frame.data().to_vec())
        .collect()
}

fn master_events(sim: &Bus, m: Handle<GuardingMaster>) -> Vec<(u64, MasterGuardingEvent)> {
    sim.events(m)
        .iter()
        .map(|(t, e)| (t.as_millis(), *e))
        .collect()
}

fn guarding_events(sim: &Bus, s: Handle<Slave>) -> Vec<(u64, SlaveGuardingEvent)> {
    sim.events(s)
        .iter()
        .filter_map(|(t, e)| match e {
            DeviceEvent::LifeGuarding(g) => Some((t.as_millis(), *g)),
            _ => None,
        })
        .collect()
}

#[test]
fn replies_alternate_and_lost_then_restored_when_unplugged() {
    let (mut sim, s, m) = bus(slave_config());
    sim.run_until(ms(1000)).unwrap();
    let r = replies(&sim);
    // Boot-up, then one reply per request (10, 110, ..., 910 ms), toggle
    // 0 first and alternating, state operational.
    assert_eq!(r.len(), 11, "{r:02X?}");
    assert_eq!(r[0], 0x00);
    for (i, b) in r[1..].iter().enumerate() {
        assert_eq!(*b, 0x05 | if i % 2 == 1 { 0x80 } else { 0 }, "reply {i}");
    }
    assert_eq!(master_events(&sim, m), []);

    // Unplugged at 1000 ms: requests at 1010, 1110, 1210 go unanswered;
    // the third miss is seen at the request of 1310 ms.
    let slave = sim.unplug(s).unwrap();
    sim.run_until(ms(1500)).unwrap();
    assert_eq!(
        master_events(&sim, m),
        [(1310, MasterGuardingEvent::Lost(node()))]
    );
    assert!(sim.machine(m).unwrap().is_lost());

    // Back at 1600 ms: the reply to the 1610 ms request restores it.
    sim.run_until(ms(1600)).unwrap();
    assert!(sim.plug(s, slave).is_ok());
    sim.run_until(ms(2000)).unwrap();
    assert_eq!(
        master_events(&sim, m)[1..],
        [(
            1610,
            MasterGuardingEvent::Restored {
                node: node(),
                state: NmtState::Operational
            }
        )]
    );
    // The slave, meanwhile, saw the master go quiet (its life time ran out
    // while it was off the bus) and come back.
    assert_eq!(
        guarding_events(&sim, s),
        [
            (1600, SlaveGuardingEvent::LifeGuardingLost),
            (1610, SlaveGuardingEvent::LifeGuardingResumed)
        ]
    );
    // Lost and restored alternate; one pair for one outage.
    let kinds: Vec<_> = master_events(&sim, m)
        .into_iter()
        .map(|(_, e)| matches!(e, MasterGuardingEvent::Lost(_)))
        .collect();
    assert_eq!(kinds, [true, false]);
}

#[test]
fn duplicated_request_is_one_toggle_error_and_no_loss() {
    let (mut sim, _s, m) = bus(slave_config());
    // The master's third request (210 ms) reaches the slave twice: it
    // replies twice, and its next reply repeats the toggle the master saw.
    sim.duplicate_if(move |x| x.from == MASTER && x.at == ms(210));
    sim.run_until(ms(1000)).unwrap();
    let events = master_events(&sim, m);
    assert_eq!(
        events,
        [(
            310,
            MasterGuardingEvent::ToggleError {
                node: node(),
                toggle: false
            }
        )],
        "{:#?}",
        sim.lines(200, 320)
    );
    assert!(!sim.machine(m).unwrap().is_lost());
}

#[test]
fn state_mismatch_when_the_node_is_stopped() {
    let (mut sim, _s, m) = bus(slave_config());
    sim.run_until(ms(500)).unwrap();
    sim.inject(nmt(0x02));
    sim.run_until(ms(1000)).unwrap();
    assert_eq!(
        master_events(&sim, m),
        [(
            510,
            MasterGuardingEvent::StateMismatch {
                node: node(),
                expected: NmtState::Operational,
                reported: NmtState::Stopped
            }
        )]
    );
    // Guarding goes on in stopped: replies report 04h.
    assert_eq!(replies(&sim).last().map(|b| b & 0x7F), Some(0x04));
    // Reset communication: boot-up, and the toggle starts at 0 again.
    sim.inject(nmt(0x82));
    sim.run_until(ms(1300)).unwrap();
    let events = master_events(&sim, m);
    assert_eq!(events[1], (1000, MasterGuardingEvent::BootUp(node())));
    assert!(
        events[2..]
            .iter()
            .all(|(_, e)| matches!(e, MasterGuardingEvent::StateMismatch { .. })),
        "{events:?}"
    );
    let r = replies(&sim);
    assert_eq!(r[r.len() - 4..], [0x00, 0x7F, 0xFF, 0x7F]);
}

#[test]
fn slave_reports_life_guarding_when_the_master_stops() {
    let (mut sim, s, m) = bus(slave_config());
    sim.run_until(ms(505)).unwrap();
    sim.with(m, |g, _| g.stop());
    sim.run_until(ms(2000)).unwrap();
    // Last request at 410 ms (received 410.2): life time 300 ms.
    assert_eq!(
        guarding_events(&sim, s),
        [(710, SlaveGuardingEvent::LifeGuardingLost)]
    );
    assert!(sim.machine(s).unwrap().guarding().is_master_lost());
    sim.with(m, |g, now| g.start(now));
    sim.run_until(ms(2100)).unwrap();
    assert_eq!(
        guarding_events(&sim, s)[1..],
        [(2000, SlaveGuardingEvent::LifeGuardingResumed)]
    );
    // Life time factor 0: no life guarding at all.
    let (mut sim, s, m) = bus(DeviceConfig {
        life_time_factor: 0,
        ..slave_config()
    });
    sim.run_until(ms(300)).unwrap();
    sim.with(m, |g, _| g.stop());
    sim.run_until(ms(5000)).unwrap();
    assert_eq!(guarding_events(&sim, s), []);
}

#[test]
fn heartbeat_and_guarding_are_exclusive() {
    let (mut sim, s, _m) = bus(DeviceConfig {
        heartbeat: Duration::from_millis(250),
        ..slave_config()
    });
    sim.run_until(ms(1000)).unwrap();
    // Only the boot-up message and heartbeats (toggle 0) on 705h: no
    // request is answered.
    let r = replies(&sim);
    assert_eq!(r, [0x00, 0x05, 0x05, 0x05, 0x05], "{r:02X?}");
    assert!(!sim.machine(s).unwrap().guarding().life_guarding_active());
    // 1017h written to 0 over SDO: the next request is answered.
    sim.inject(CanFrame::standard(0x605, &[0x2B, 0x17, 0x10, 0, 0, 0, 0, 0]).unwrap());
    sim.run_until(ms(1200)).unwrap();
    let r = replies(&sim);
    assert_eq!(r.len(), 7, "{r:02X?}");
    assert!(sim.machine(s).unwrap().guarding().life_guarding_active());
    // Back to a heartbeat: no more replies, no life guarding event.
    sim.inject(CanFrame::standard(0x605, &[0x2B, 0x17, 0x10, 0, 0x64, 0, 0, 0]).unwrap());
    sim.run_until(ms(2000)).unwrap();
    assert!(replies(&sim)[7..].iter().all(|b| *b == 0x05));
    assert_eq!(guarding_events(&sim, s), []);
}
