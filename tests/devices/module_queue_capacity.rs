//! The battery module's frame queue at the firmware's capacity (2,
//! `examples/firmware/battery_module`): the most frames one turn of the
//! firmware loop can queue between two drains (a sensor fault change, then
//! an RPDO of the wrong length, then the timers) all come out, none
//! dropped; one slot fewer drops one.

use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig};
use canopen_codec::machine::Machine;
use canopen_codec::nmt::NmtState;
use canopen_codec::{CanFrame, Timestamp};

/// The firmware's `QUEUE_CAPACITY`.
const FIRMWARE_CAPACITY: usize = 2;

fn drain<const Q: usize>(m: &mut BatteryModule<Q>) -> Vec<CanFrame> {
    core::iter::from_fn(|| m.poll_transmit()).collect()
}

/// A module at node 1, operational, its queues drained.
fn started<const Q: usize>() -> BatteryModule<Q> {
    let mut m = BatteryModule::<Q>::with_queue_capacity(BatteryModuleConfig::default());
    m.boot(Timestamp::ZERO);
    m.handle_frame(
        Timestamp::ZERO,
        &CanFrame::standard(0x000, &[0x01, 0x01]).unwrap(),
    );
    assert_eq!(m.nmt_state(), NmtState::Operational);
    drain(&mut m);
    while m.poll_event().is_some() {}
    m
}

/// The EMCY error codes among `frames` (81h: node 1), in order.
fn emcy_codes(frames: &[CanFrame]) -> Vec<u16> {
    frames
        .iter()
        .filter(|f| f.id() == canopen_codec::CanId::Standard(0x081))
        .map(|f| match f.data() {
            [lo, hi, ..] => u16::from_le_bytes([*lo, *hi]),
            other => panic!("short EMCY {other:?}"),
        })
        .collect()
}

/// One turn of the firmware loop, worst case: the fault changes to `fault`
/// and an RPDO 0 (201h, one byte mapped) arrives empty.
fn worst_turn<const Q: usize>(
    m: &mut BatteryModule<Q>,
    now: Timestamp,
    fault: bool,
) -> Vec<CanFrame> {
    m.set_temperature_sensor_fault(now, fault);
    m.handle_frame(now, &CanFrame::standard(0x201, &[]).unwrap());
    if m.poll_timeout().is_some_and(|due| due <= now) {
        m.handle_timeout(now);
    }
    drain(m)
}

#[test]
fn the_worst_turn_fits_the_firmware_capacity() {
    let mut m = started::<FIRMWARE_CAPACITY>();
    let now = Timestamp::from_millis(50);
    let frames = worst_turn(&mut m, now, true);
    assert_eq!(emcy_codes(&frames), [0x5010, 0x8210]);
    // The error reset of the fault, then the RPDO's EMCY again.
    let frames = worst_turn(&mut m, Timestamp::from_millis(60), false);
    assert_eq!(emcy_codes(&frames), [0x0000, 0x8210]);
    assert_eq!(m.frames_dropped(), 0);
}

#[test]
fn a_reset_node_queues_no_frame_of_its_own() {
    let mut m = started::<FIRMWARE_CAPACITY>();
    let now = Timestamp::from_millis(50);
    m.set_temperature_sensor_fault(now, true);
    m.handle_frame(now, &CanFrame::standard(0x000, &[0x81, 0x01]).unwrap());
    m.handle_frame(now, &CanFrame::standard(0x201, &[]).unwrap());
    let frames = drain(&mut m);
    // The boot-up message (the heartbeat's slot), then the fault's EMCY; the
    // RPDO is not processed in pre-operational.
    assert_eq!(
        frames.first().map(ToString::to_string).as_deref(),
        Some("701#00")
    );
    assert_eq!(emcy_codes(&frames), [0x5010]);
    assert_eq!(m.frames_dropped(), 0);
}

#[test]
fn one_slot_fewer_drops_a_frame() {
    let mut m = started::<{ FIRMWARE_CAPACITY - 1 }>();
    let frames = worst_turn(&mut m, Timestamp::from_millis(50), true);
    assert_eq!(emcy_codes(&frames), [0x8210]);
    assert_eq!(m.frames_dropped(), 1);
}
