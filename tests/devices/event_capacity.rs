//! The device core's internal event queues are sized to the largest burst
//! one call can make (the core drains each machine after every call): the
//! SYNC consumer's 1 (a SYNC frame is taken without its `Received` event,
//! so only a skipped counter is queued). Each test drives that burst and
//! fails if a slot is missing or an event comes out of order. The NMT
//! slave and the heartbeat consumer keep none: their events are reported
//! as made (the NMT slave's boot after a reset is held while the profile
//! sees the reset, and reported before a state change the profile makes).

use canopen_codec::cia418::{BatteryDictionary, BatteryObjects};
use canopen_codec::device::{
    Cia301Device, Device, DeviceConfig, DeviceEvent, DeviceSpec, Profile, ProfiledDevice,
};
use canopen_codec::machine::Machine;
use canopen_codec::nmt::NmtState;
use canopen_codec::sync::SyncEvent;
use canopen_codec::{CanFrame, NodeId, Timestamp};

/// A plain CiA 301 device over the CiA 418 objects.
type Plain = Cia301Device<BatteryDictionary>;

/// A profile that enters operational by itself after every reset (as the
/// Delta-Q charger does).
#[derive(Debug)]
struct SelfStart;

impl DeviceSpec for SelfStart {
    type Objects = BatteryDictionary;
    type Event = DeviceEvent;
    type PowerOn = DeviceConfig;
}

impl Profile<SelfStart> for SelfStart {
    fn on_event(&mut self, device: &mut Device<SelfStart>, now: Timestamp, event: &DeviceEvent) {
        if let DeviceEvent::Reset { .. } = event {
            device.set_nmt_state(now, NmtState::Operational, self);
        }
    }
}

fn nmt(cs: u8) -> CanFrame {
    CanFrame::standard(0x000, &[cs, 0x05]).unwrap()
}

fn events(dev: &mut impl Machine<Event = DeviceEvent>) -> Vec<DeviceEvent> {
    core::iter::from_fn(|| dev.poll_event()).collect()
}

#[test]
fn a_reset_with_a_self_start_reports_both_state_changes() {
    let node = NodeId::new(5).unwrap();
    let core = Device::new(
        DeviceConfig::new(node),
        BatteryDictionary::new(BatteryObjects::new()),
    );
    let mut dev = ProfiledDevice::<SelfStart>::from_parts(core, SelfStart);
    dev.boot(Timestamp::ZERO);
    dev.handle_frame(Timestamp::ZERO, &nmt(0x01));
    let _ = events(&mut dev);
    // Reset node from operational: the reset's own change (operational to
    // pre-operational) is still held when the profile starts the device
    // again: it is reported first.
    dev.handle_frame(Timestamp::from_millis(1), &nmt(0x81));
    assert_eq!(
        events(&mut dev),
        [
            DeviceEvent::Reset { node: true },
            DeviceEvent::NmtStateChanged {
                from: NmtState::Operational,
                to: NmtState::PreOperational,
            },
            DeviceEvent::NmtStateChanged {
                from: NmtState::PreOperational,
                to: NmtState::Operational,
            },
        ]
    );
    assert_eq!(dev.nmt_state(), NmtState::Operational);
    assert_eq!(dev.events_dropped(), 0);
}

#[test]
fn a_skipped_sync_counter_is_reported_and_nothing_is_dropped() {
    let mut config = DeviceConfig::new(NodeId::new(5).unwrap());
    config.sync_counter_overflow = 4;
    let mut dev = Plain::plain(config, BatteryDictionary::new(BatteryObjects::new()));
    dev.boot(Timestamp::ZERO);
    let _ = events(&mut dev);
    for (ms, counter) in [(1, 1), (2, 3), (3, 4), (4, 1)] {
        let sync = CanFrame::standard(0x080, &[counter]).unwrap();
        dev.handle_frame(Timestamp::from_millis(ms), &sync);
    }
    assert_eq!(
        events(&mut dev),
        [DeviceEvent::Sync(SyncEvent::CounterSkipped {
            expected: 2,
            got: 3
        })]
    );
    assert_eq!(
        dev.sync_consumer().last_sync(),
        Some(Timestamp::from_millis(4))
    );
    // Every SYNC and the skip went through a one-slot queue: none evicted.
    assert_eq!(dev.sync_consumer().events_dropped(), 0);
}

/// The device's heartbeat consumer keeps no events (feature
/// `heartbeat-consumer`): four nodes whose time runs out at once are four
/// `Lost` events of one timeout call, in 1016h's order, none dropped, and a
/// heartbeat's event is reported by the call that received it.
#[cfg(feature = "heartbeat-consumer")]
#[test]
fn four_nodes_lost_at_once_are_four_events_in_order() {
    use canopen_codec::nmt::heartbeat::{ConsumerEntry, HeartbeatEvent};
    use core::time::Duration;
    let n = |id| NodeId::new(id).unwrap();
    let nodes = [7, 3, 9, 2];
    let entries = nodes.map(|id| ConsumerEntry::new(n(id), Duration::from_millis(100)));
    let config = DeviceConfig::new(n(5)).with_consumers(&entries);
    let mut dev = Plain::plain(config, BatteryDictionary::new(BatteryObjects::new()));
    dev.boot(Timestamp::ZERO);
    let _ = events(&mut dev);
    for id in nodes {
        let boot_up = CanFrame::standard(0x700 + u16::from(id), &[0x00]).unwrap();
        dev.handle_frame(Timestamp::from_millis(1), &boot_up);
        assert_eq!(
            events(&mut dev),
            [DeviceEvent::Heartbeat(HeartbeatEvent::BootUp(n(id)))]
        );
    }
    dev.handle_timeout(Timestamp::from_millis(500));
    let lost = nodes.map(|id| DeviceEvent::Heartbeat(HeartbeatEvent::Lost(n(id))));
    assert_eq!(events(&mut dev), lost);
    assert_eq!(dev.events_dropped(), 0);
    assert!(nodes
        .iter()
        .all(|id| !dev.heartbeat_consumer().is_alive(n(*id))));
}
