//! The NMT resets of both devices follow CiA 301 the same way (they share
//! the device core): reset node (81h) restores every object, reset
//! communication (82h) restores only the communication objects and keeps
//! the application's; both are reported as `Reset`, send the boot-up
//! message and drop the PDO pairing / configuration changes.

use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig, Temperature};
#[cfg(feature = "heartbeat-consumer")]
use canopen_codec::deltaq::{Charger, ChargerConfig, ChargerEvent};
use canopen_codec::device::DeviceEvent;
use canopen_codec::machine::Machine;
#[cfg(feature = "heartbeat-consumer")]
use canopen_codec::nmt::NmtState;
use canopen_codec::{CanFrame, NodeId, Timestamp};

fn ms(n: u64) -> Timestamp {
    Timestamp::from_millis(n)
}

fn nmt(cs: u8, node: u8) -> CanFrame {
    CanFrame::standard(0x000, &[cs, node]).unwrap()
}

fn sent(m: &mut impl Machine) -> Vec<String> {
    std::iter::from_fn(|| m.poll_transmit())
        .map(|f| f.to_string())
        .collect()
}

#[cfg(feature = "heartbeat-consumer")]
fn charger() -> Charger {
    Charger::new(ChargerConfig::new(
        NodeId::new(10).unwrap(),
        NodeId::new(1).unwrap(),
    ))
}

/// The bug this pins: the charger rebuilt its whole dictionary from its
/// config on reset communication (application values lost) and reported no
/// reset.
#[cfg(feature = "heartbeat-consumer")]
#[test]
fn charger_reset_communication_keeps_application_values_and_reports_it() {
    let mut c = charger();
    c.boot(ms(0));
    c.handle_frame(ms(1), &nmt(0x01, 10));
    c.update(ms(2), |o| {
        o.charging_current = 0x137C;
        o.ac_voltage = 0x07B1;
    });
    // An SDO write of 1017h (a communication object): 500 ms.
    c.handle_frame(
        ms(3),
        &CanFrame::standard(0x60A, &[0x2B, 0x17, 0x10, 0, 0xF4, 0x01, 0, 0]).unwrap(),
    );
    assert_eq!(c.comm().heartbeat_ms, 500);
    let _ = (sent(&mut c), std::iter::from_fn(|| c.poll_event()).count());

    c.handle_frame(ms(10), &nmt(0x82, 0));
    assert_eq!(
        c.objects().charging_current,
        0x137C,
        "application objects kept"
    );
    assert_eq!(c.objects().ac_voltage, 0x07B1);
    assert_eq!(c.comm().heartbeat_ms, 1000, "1017h restored");
    assert_eq!(c.nmt_state(), NmtState::PreOperational);
    assert_eq!(sent(&mut c), ["70A#00"]);
    let events: Vec<ChargerEvent> = std::iter::from_fn(|| c.poll_event()).collect();
    assert_eq!(
        events,
        [
            ChargerEvent::Device(DeviceEvent::Reset { node: false }),
            ChargerEvent::Device(DeviceEvent::NmtStateChanged {
                from: NmtState::Operational,
                to: NmtState::PreOperational
            }),
        ]
    );
    assert_eq!(
        c.poll_timeout(),
        Some(ms(1010)),
        "heartbeat restarted at 1000 ms"
    );
}

#[cfg(feature = "heartbeat-consumer")]
#[test]
fn charger_reset_node_restores_application_values_from_boot() {
    let mut c = charger();
    c.update(ms(0), |o| o.charger_status = 0x01);
    c.boot(ms(0));
    c.update(ms(2), |o| {
        o.charger_status = 0x00;
        o.charging_current = 0x137C;
    });
    c.handle_frame(ms(10), &nmt(0x81, 10));
    assert_eq!(c.objects().charger_status, 0x01, "the value at boot");
    assert_eq!(c.objects().charging_current, 0, "the power-on value");
    let events: Vec<ChargerEvent> = std::iter::from_fn(|| c.poll_event()).collect();
    assert!(events.contains(&ChargerEvent::Device(DeviceEvent::Reset { node: true })));
}

#[test]
fn battery_module_resets_the_same_way() {
    for (cs, node_reset) in [(0x81u8, true), (0x82, false)] {
        let mut m = BatteryModule::new(BatteryModuleConfig::new(NodeId::new(1).unwrap()));
        m.set_temperature(ms(0), Temperature::from_celsius(20).unwrap());
        m.boot(ms(0));
        m.set_temperature(ms(1), Temperature::from_celsius(30).unwrap());
        m.set_temperature_sensor_fault(ms(1), true);
        m.update_comm(ms(1), |c| c.heartbeat_ms = 100);
        let _ = sent(&mut m);
        while m.poll_event().is_some() {}
        m.handle_frame(ms(5), &nmt(cs, 1));
        let want = if node_reset { 20 } else { 30 };
        assert_eq!(
            m.objects().temperature,
            Temperature::from_celsius(want).unwrap(),
            "{cs:02X}h"
        );
        assert!(m.error_register().is_empty(), "1001h restored");
        assert!(!m.temperature_sensor_fault());
        assert_eq!(m.comm().heartbeat_ms, 1000);
        assert_eq!(sent(&mut m), ["701#00"]);
        assert_eq!(
            m.poll_event(),
            Some(DeviceEvent::Reset { node: node_reset })
        );
    }
}
