//! The state-machine contract at the end of the clock: "a timestamp far
//! ahead expires every running timer once". A periodic timer re-armed at
//! `Timestamp::MAX` (its next deadline saturates there) would be due again
//! at once, for ever: a caller's "run every due timer" loop never ends.
//! Each test fails before the fix with `drive_timers` stopping at its
//! `u16::MAX`-run guard.

use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig};
#[cfg(feature = "heartbeat-consumer")]
use canopen_codec::deltaq::{Charger, ChargerConfig};
use canopen_codec::machine::{drive_timers, Machine};
use canopen_codec::nmt::heartbeat::HeartbeatProducer;
use canopen_codec::pdo::{PdoCobId, PdoCommParams, TpdoProducer};
use canopen_codec::{CanFrame, NodeId, Timestamp};
use core::time::Duration;

fn drain(m: &mut impl Machine) -> usize {
    std::iter::from_fn(|| m.poll_transmit()).count()
}

/// After `handle_timeout(MAX)` every timer has fired once; nothing is due
/// any more (there is no later time for it to be due at).
fn settles(m: &mut impl Machine) {
    m.handle_timeout(Timestamp::MAX);
    let _ = drain(m);
    let mut frames = 0;
    let runs = drive_timers(m, Timestamp::MAX, |_, _| frames += 1);
    assert!(runs <= 2, "{runs} timer runs ({frames} frames) at MAX");
    assert_eq!(m.poll_timeout(), None);
}

#[test]
fn heartbeat_producer_fires_once_at_max() {
    let mut p = HeartbeatProducer::new(NodeId::new(5).unwrap(), Duration::from_millis(1000));
    p.boot(Timestamp::ZERO);
    let _ = drain(&mut p);
    settles(&mut p);
    // Booted at the end of time: the boot-up message, no heartbeat timer.
    let mut p = HeartbeatProducer::new(NodeId::new(5).unwrap(), Duration::from_millis(1000));
    p.boot(Timestamp::MAX);
    assert_eq!(drain(&mut p), 1);
    settles(&mut p);
    // Just before the end: the next heartbeat would fall at or past the end
    // of the clock, so none is due (a period that ends past the clock does
    // not start).
    let mut p = HeartbeatProducer::new(NodeId::new(5).unwrap(), Duration::from_millis(1000));
    p.boot(Timestamp::from_micros(u64::MAX - 10));
    let _ = drain(&mut p);
    assert_eq!(p.poll_timeout(), None);
    settles(&mut p);
    // One period before the end: due once, at MAX - 1, and at MAX - 1 too
    // no later heartbeat is due (a deadline at the end of the clock would
    // be kept as MAX - 1 and be due again at once).
    let mut p = HeartbeatProducer::new(NodeId::new(5).unwrap(), Duration::from_millis(1));
    p.boot(Timestamp::from_micros(u64::MAX - 1001));
    let _ = drain(&mut p);
    assert_eq!(p.poll_timeout(), Some(Timestamp::from_micros(u64::MAX - 1)));
    let mut q = p.clone();
    settles(&mut p);
    let last = Timestamp::from_micros(u64::MAX - 1);
    q.handle_timeout(last);
    assert_eq!(drain(&mut q), 1);
    let runs = drive_timers(&mut q, last, |_, _| {});
    assert_eq!((runs, q.poll_timeout()), (0, None));
}

#[test]
fn tpdo_event_timer_fires_once_at_max() {
    let mut p = TpdoProducer::new();
    p.configure(
        Timestamp::ZERO,
        PdoCommParams::event_driven(PdoCobId::standard(0x18A), 200),
    );
    p.set_operational(Timestamp::ZERO, true);
    let _ = drain(&mut p);
    settles(&mut p);
}

#[test]
fn devices_settle_at_max() {
    let mut m = BatteryModule::new(BatteryModuleConfig::new(NodeId::new(1).unwrap()));
    m.boot(Timestamp::ZERO);
    m.handle_frame(
        Timestamp::ZERO,
        &CanFrame::standard(0x000, &[0x01, 0x00]).unwrap(),
    );
    let _ = drain(&mut m);
    settles(&mut m);
}

/// The charger (feature `heartbeat-consumer`) at the end of the clock.
#[cfg(feature = "heartbeat-consumer")]
#[test]
fn charger_settles_at_max() {
    let mut config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::new(1).unwrap());
    config.configure_cob_ids = false;
    config.self_start = true;
    let mut c = Charger::new(config);
    c.boot(Timestamp::ZERO);
    c.handle_frame(
        Timestamp::ZERO,
        &CanFrame::standard(0x701, &[0x05]).unwrap(),
    );
    assert!(c.is_configured());
    let _ = drain(&mut c);
    settles(&mut c);
}
