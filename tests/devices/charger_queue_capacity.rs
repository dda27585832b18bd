//! The charger's queues at the firmware's capacity (2,
//! `examples/firmware/charger`, whose loop drains both after every call):
//! the most frames one call queues (two EMCYs from one frame: an RPDO of
//! the wrong length on the module's SDO response identifier, whose answer
//! is refused) and the most events one call reports (an NMT reset; the
//! module's loss with the SDO server's own timeout) all come out, none
//! dropped; one slot fewer drops one. The module gone in the call of the
//! server's timeout reports three: one (informational) is dropped and
//! counted, no frame is.

use crate::common::ms;
use canopen_codec::deltaq::{Charger, ChargerConfig, ChargerEvent};
use canopen_codec::device::DeviceEvent;
use canopen_codec::machine::Machine;
use canopen_codec::nmt::NmtState;
use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};

/// The firmware's `QUEUE_CAPACITY`.
const FIRMWARE_CAPACITY: usize = 2;

fn frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::standard(id, data).unwrap()
}

fn frames<const Q: usize>(c: &mut Charger<Q>) -> Vec<CanFrame> {
    core::iter::from_fn(|| c.poll_transmit()).collect()
}

fn events<const Q: usize>(c: &mut Charger<Q>) -> Vec<ChargerEvent> {
    core::iter::from_fn(|| c.poll_event()).collect()
}

/// The EMCY error codes among `frames` (8Ah: node 10), in order.
fn emcy_codes(frames: &[CanFrame]) -> Vec<u16> {
    frames
        .iter()
        .filter(|f| f.id() == CanId::Standard(0x08A))
        .map(|f| match f.data() {
            [lo, hi, ..] => u16::from_le_bytes([*lo, *hi]),
            other => panic!("short EMCY {other:?}"),
        })
        .collect()
}

/// The firmware's charger (node 10, module 1), booted, operational, its
/// queues drained.
fn started<const Q: usize>() -> Charger<Q> {
    let config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::MIN);
    let mut c = Charger::<Q>::with_queue_capacity(config);
    c.boot(ms(0));
    frames(&mut c);
    events(&mut c);
    c.handle_frame(ms(0), &frame(0x000, &[0x01, 0x0A]));
    assert_eq!(c.nmt_state(), NmtState::Operational);
    frames(&mut c);
    events(&mut c);
    assert_eq!((c.frames_dropped(), c.events_dropped()), (0, 0));
    c
}

/// The worst `handle_frame`: the master sets the charger's RPDO 1 (7
/// bytes mapped) to 581h, the module's SDO response identifier; the module
/// is heard and answers the charger's read of 1000h with a short frame
/// naming profile 401, not 418. One call, two EMCYs: the RPDO's (8210h,
/// E-0-4-6) and the profile's E-0-4-2. Returns the frames.
fn worst_frame<const Q: usize>(c: &mut Charger<Q>) -> Vec<CanFrame> {
    // 1401h sub 1 = 581h (valid), by the charger's SDO server.
    c.handle_frame(
        ms(1),
        &frame(0x60A, &[0x23, 0x01, 0x14, 0x01, 0x81, 0x05, 0x00, 0x00]),
    );
    assert_eq!(
        frames(c).first().map(ToString::to_string).as_deref(),
        Some("58A#6001140100000000")
    );
    c.handle_frame(ms(2), &frame(0x701, &[0x05]));
    assert_eq!(
        frames(c).first().map(ToString::to_string).as_deref(),
        Some("601#4000100000000000")
    );
    events(c);
    // 1000h = 401 (0191h), expedited, 2 bytes indicated: 6 bytes, one
    // short of RPDO 1's mapping.
    c.handle_frame(ms(3), &frame(0x581, &[0x4B, 0x00, 0x10, 0x00, 0x91, 0x01]));
    frames(c)
}

#[test]
fn the_worst_frame_fits_the_firmware_capacity() {
    let mut c = started::<FIRMWARE_CAPACITY>();
    let sent = worst_frame(&mut c);
    let codes = emcy_codes(&sent);
    assert_eq!(codes.len(), 2, "{sent:?}");
    assert!(codes.contains(&0x8210), "{codes:x?}");
    assert!(events(&mut c)
        .iter()
        .any(|e| matches!(e, ChargerEvent::NotABatteryModule { device_type: 401 })));
    assert_eq!(c.frames_dropped(), 0);
}

#[test]
fn one_frame_slot_fewer_drops_one() {
    let mut c = started::<{ FIRMWARE_CAPACITY - 1 }>();
    let sent = worst_frame(&mut c);
    assert_eq!(emcy_codes(&sent).len(), 1, "{sent:?}");
    assert_eq!(c.frames_dropped(), 1);
}

/// The worst calls for events: an NMT reset node (the reset, then the
/// state change), then a timeout where the module's heartbeat is lost and
/// the SDO server's upload of 1008h (segmented, left open by the master)
/// expires at once. Returns each call's events.
fn worst_events<const Q: usize>(c: &mut Charger<Q>) -> [Vec<ChargerEvent>; 2] {
    c.handle_frame(ms(10), &frame(0x000, &[0x81, 0x0A]));
    frames(c);
    let reset = events(c);
    // The module is heard at 1000 ms; the master opens an upload of 1008h
    // at the same moment: both expire at 3000 ms (2000 ms each).
    c.handle_frame(ms(1_000), &frame(0x701, &[0x05]));
    c.handle_frame(
        ms(1_000),
        &frame(0x60A, &[0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0]),
    );
    frames(c);
    events(c);
    c.handle_timeout(ms(3_000));
    frames(c);
    [reset, events(c)]
}

#[test]
fn the_worst_events_fit_the_firmware_capacity() {
    let mut c = started::<FIRMWARE_CAPACITY>();
    let [reset, timeout] = worst_events(&mut c);
    assert_eq!(
        reset,
        [
            ChargerEvent::Device(DeviceEvent::Reset { node: true }),
            ChargerEvent::Device(DeviceEvent::NmtStateChanged {
                from: NmtState::Operational,
                to: NmtState::PreOperational,
            }),
        ]
    );
    assert_eq!(timeout.len(), 2, "{timeout:?}");
    assert!(timeout.contains(&ChargerEvent::BatteryLost), "{timeout:?}");
    assert!(
        timeout.iter().any(|e| matches!(
            e,
            ChargerEvent::Device(DeviceEvent::SdoAborted { index: 0x1008, .. })
        )),
        "{timeout:?}"
    );
    assert_eq!(c.events_dropped(), 0);
}

#[test]
fn one_event_slot_fewer_drops_one() {
    let mut c = started::<{ FIRMWARE_CAPACITY - 1 }>();
    let [reset, timeout] = worst_events(&mut c);
    assert_eq!((reset.len(), timeout.len()), (1, 1));
    assert_eq!(c.events_dropped(), 2);
}

/// The module gone in the same call as the SDO server's own timeout (the
/// master's upload of 1008h opened 2000 ms before the gone, to the
/// microsecond): three events, `BatteryGone`, the change to
/// pre-operational and the server's abort. At the firmware's capacity the
/// oldest is dropped and counted (events are informational); both frames,
/// the server's abort and E-0-3-0, still go out.
#[test]
fn the_gone_call_with_a_server_timeout_drops_one_event_and_no_frame() {
    let mut c = started::<FIRMWARE_CAPACITY>();
    c.handle_frame(ms(1_000), &frame(0x701, &[0x05]));
    frames(&mut c);
    events(&mut c);
    // Lost at 3000 ms (2000 ms consumer time); gone 1 us later.
    c.handle_timeout(ms(3_000));
    assert!(events(&mut c).contains(&ChargerEvent::BatteryLost));
    frames(&mut c);
    let gone_at = Timestamp::from_micros(3_000_001);
    assert_eq!(c.poll_timeout(), Some(gone_at));
    c.handle_frame(
        Timestamp::from_micros(1_000_001),
        &frame(0x60A, &[0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0]),
    );
    frames(&mut c);
    events(&mut c);
    c.handle_timeout(gone_at);
    let sent: Vec<String> = frames(&mut c).iter().map(ToString::to_string).collect();
    assert!(
        sent.contains(&"08A#3081011E80000000".to_string()),
        "{sent:?}"
    );
    assert!(
        sent.iter().any(|f| f.starts_with("58A#80081000")),
        "{sent:?}"
    );
    assert_eq!(
        events(&mut c),
        [
            ChargerEvent::BatteryGone,
            ChargerEvent::Device(DeviceEvent::NmtStateChanged {
                from: NmtState::Operational,
                to: NmtState::PreOperational,
            }),
        ]
    );
    assert_eq!(c.events_dropped(), 1);
    assert_eq!(c.nmt_state(), NmtState::PreOperational);
}
