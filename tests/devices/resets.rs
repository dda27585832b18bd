//! The NMT resets of both devices follow CiA 301 the same way (they share
//! the device core): reset node (81h) restores the communication objects
//! and the application's parameters (its `rw` objects, to their values at
//! boot; the `ro` measurements keep their last value), reset communication
//! (82h) restores only the communication objects and keeps the
//! application's; both are reported as `Reset`, send the boot-up message
//! and drop the PDO pairing / configuration changes.

use crate::common::ms;
use canopen_codec::cia418::{
    BatteryModule, BatteryModuleConfig, BatteryVoltage, PackedStringObject, StateOfCharge,
    Temperature,
};
#[cfg(feature = "heartbeat-consumer")]
use canopen_codec::deltaq::charge::PowerStage;
#[cfg(feature = "heartbeat-consumer")]
use canopen_codec::deltaq::{Charger, ChargerConfig, ChargerEvent};
use canopen_codec::device::DeviceEvent;
use canopen_codec::machine::Machine;
#[cfg(feature = "heartbeat-consumer")]
use canopen_codec::nmt::NmtState;
use canopen_codec::{CanFrame, NodeId};

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
    // 2002h is the charge control's reading of the power stage (19.48 A
    // = 137Ch in 1/256 A); 2060h an application value.
    c.handle_power_stage(
        ms(2),
        PowerStage {
            ac_mv: PowerStage::AC_NOMINAL_MV,
            voltage_mv: 52_000,
            current_ma: 19_484,
            temperature_c: 30,
            ..PowerStage::OFF
        },
    );
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
        "the charge control's readings kept"
    );
    assert_eq!(
        c.objects().ac_voltage,
        230 * 16,
        "2200h, the power stage's AC reading, kept"
    );
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
fn charger_reset_node_restores_parameters_from_boot_and_keeps_readings() {
    let mut c = charger();
    c.update(ms(0), |o| {
        o.charger_status = 0x01;
        o.voltage_request = 0x0001_2345;
    });
    c.boot(ms(0));
    c.update(ms(2), |o| {
        o.charger_status = 0x00;
        o.charging_current = 0x137C;
        o.voltage_request = 7;
    });
    c.handle_frame(ms(10), &nmt(0x81, 10));
    assert_eq!(
        c.objects().charging_current,
        0,
        "2002h: the charge control's reading, nothing measured"
    );
    assert_eq!(
        c.objects().voltage_request,
        MAX_VOLTAGE_Q10,
        "2271h: the voltage limit starts again at the charger's maximum"
    );
    assert_eq!(c.objects().charger_status, 0x00, "ro: the last value set");
    let events: Vec<ChargerEvent> = std::iter::from_fn(|| c.poll_event()).collect();
    assert!(events.contains(&ChargerEvent::Device(DeviceEvent::Reset { node: true })));
}

/// An expedited SDO download of `data` (1, 2 or 4 bytes) to `index` sub
/// `sub` of the node with the SDO request COB-ID `request`.
fn download(request: u16, index: u16, sub: u8, data: &[u8]) -> CanFrame {
    let cs = 0x23 | ((4 - data.len() as u8) << 2);
    let [lo, hi] = index.to_le_bytes();
    let mut bytes = [cs, lo, hi, sub, 0, 0, 0, 0];
    bytes[4..4 + data.len()].copy_from_slice(data);
    CanFrame::standard(request, &bytes).unwrap()
}

/// The battery module's `rw` objects, row by row: (index, sub, the value
/// the application set before boot, the value the charger writes after).
const BATTERY_RW: [(u16, u8, &[u8], &[u8]); 6] = [
    (0x6001, 0, &[0x01], &[0x02]),
    (0x6052, 0, &[0x10, 0x00], &[0x34, 0x12]),
    (0x6053, 0, &[0x20, 0x00], &[0x78, 0x56]),
    (0x6054, 1, &[0x3C, 0x00], &[0x9F, 0x05]),
    (0x6054, 2, &[0x05, 0x00], &[0xCD, 0xAB]),
    (0x6080, 0, &[50], &[80]),
];

/// Every `rw` object of the battery module written by SDO after boot is
/// back to its value at boot after reset node (and kept by reset
/// communication); the `ro` measurements and identity keep the last value
/// the application set, whichever the reset.
#[test]
fn battery_module_reset_node_restores_each_rw_object_and_keeps_measurements() {
    for (cs, node_reset) in [(0x81u8, true), (0x82, false)] {
        let mut m = BatteryModule::new(BatteryModuleConfig::new(NodeId::new(1).unwrap()));
        m.update(ms(0), |o| {
            o.charger_status = canopen_codec::cia418::ChargerStatus::from_bits_retain(0x01);
            o.ah_returned_during_last_charge =
                canopen_codec::cia418::EighthAmpHours::from_raw(0x10);
            o.ah_since_last_equalization = canopen_codec::cia418::EighthAmpHours::from_raw(0x20);
            o.date_of_last_equalization.minutes = 60;
            o.date_of_last_equalization.days = 5;
            o.charger_state_of_charge = StateOfCharge::from_raw(50);
            o.battery_voltage = BatteryVoltage::from_raw(48 * 1024);
        });
        m.set_text(PackedStringObject::BatteryId, "BOOT").unwrap();
        m.boot(ms(0));
        let _ = sent(&mut m);
        for (row, (index, sub, _, after)) in BATTERY_RW.iter().enumerate() {
            m.handle_frame(ms(1 + row as u64), &download(0x601, *index, *sub, after));
            let reply = sent(&mut m);
            assert_eq!(reply.len(), 1, "{index:04X}h.{sub}");
            assert!(
                reply[0].starts_with("581#60"),
                "{index:04X}h.{sub}: {reply:?}"
            );
        }
        m.set_temperature(ms(10), Temperature::from_celsius(30).unwrap());
        m.update(ms(10), |o| {
            o.battery_voltage = BatteryVoltage::from_raw(52 * 1024)
        });
        m.set_text(PackedStringObject::BatteryId, "LAST").unwrap();
        while m.poll_event().is_some() {}

        m.handle_frame(ms(20), &nmt(cs, 1));
        assert_eq!(sent(&mut m), ["701#00"]);
        for (row, (index, sub, before, after)) in BATTERY_RW.iter().enumerate() {
            let want = if node_reset { before } else { after };
            m.handle_frame(ms(30 + row as u64), &upload(0x601, *index, *sub));
            let reply = sent(&mut m);
            assert_eq!(reply.len(), 1, "{cs:02X}h {index:04X}h.{sub}");
            let hex: String = want.iter().map(|b| format!("{b:02X}")).collect();
            let [lo, hi] = index.to_le_bytes();
            let head = format!(
                "581#{:02X}{lo:02X}{hi:02X}{sub:02X}",
                0x43 | ((4 - want.len()) << 2)
            );
            assert!(
                reply[0].starts_with(&format!("{head}{hex}")),
                "{cs:02X}h {index:04X}h.{sub}: {reply:?}"
            );
        }
        let o = m.objects();
        assert_eq!(
            o.temperature,
            Temperature::from_celsius(30).unwrap(),
            "{cs:02X}h"
        );
        assert_eq!(
            o.battery_voltage,
            BatteryVoltage::from_raw(52 * 1024),
            "{cs:02X}h"
        );
        let id = o.packed_string(PackedStringObject::BatteryId).unwrap();
        assert_eq!(
            id,
            canopen_codec::cia418::PackedString::encode(PackedStringObject::BatteryId, "LAST")
                .unwrap()
        );
    }
}

/// An expedited SDO upload request.
fn upload(request: u16, index: u16, sub: u8) -> CanFrame {
    let [lo, hi] = index.to_le_bytes();
    CanFrame::standard(request, &[0x40, lo, hi, sub, 0, 0, 0, 0]).unwrap()
}

/// The example charger's maximum output voltage, 72 V, in 2271h's 1/1024 V.
#[cfg(feature = "heartbeat-consumer")]
const MAX_VOLTAGE_Q10: u32 = 72 * 1024;

/// The writable charger objects that are the charge control's readings
/// of the power stage and of the cycle, whatever was written: 2002h
/// current and 2101h voltage (nothing measured: 0), 6052h Ah returned (no
/// cycle: FFFFh).
#[cfg(feature = "heartbeat-consumer")]
fn reading(index: u16) -> Option<&'static [u8]> {
    Some(match index {
        0x2002 | 0x2101 => &[0x00, 0x00],
        0x6052 => &[0xFF, 0xFF],
        _ => return None,
    })
}

/// What reset node makes of the voltage limit: it starts again at the
/// charger's maximum (2271h, 2276h: 72 V; the voltage request of remote
/// mode, Delta-Q IC Series CANopen interface specification rev 2.0,
/// 3.1.1, as `deltaq::charge` reads it).
#[cfg(feature = "heartbeat-consumer")]
fn voltage_limit_after_reset_node(index: u16) -> Option<&'static [u8]> {
    Some(match index {
        0x2271 => &[0x00, 0x20, 0x01, 0x00],
        0x2276 => &[0x00, 0x48],
        _ => return None,
    })
}

/// The charger's writable objects, row by row: (index, the value the
/// application set before boot, the value written after).
const CHARGER_RW: [(u16, &[u8], &[u8]); 13] = [
    (0x6000, &[0x01], &[0x02]),
    (0x6010, &[0x10, 0x01], &[0x20, 0x02]),
    (0x6052, &[0x11, 0x00], &[0x22, 0x00]),
    (0x6060, &[0x00, 0xC0, 0x00, 0x00], &[0x00, 0xD0, 0x00, 0x00]),
    (0x6070, &[0x40, 0x01], &[0x80, 0x02]),
    (0x6081, &[40], &[60]),
    (0x2002, &[0x00, 0x10], &[0x00, 0x20]),
    (0x2101, &[0x00, 0x30], &[0x00, 0x34]),
    (0x2241, &[1, 0, 0, 0], &[2, 0, 0, 0]),
    (0x2250, &[0x40, 0x01], &[0x80, 0x02]),
    (0x2271, &[0x00, 0x00, 0xC0, 0x00], &[0x00, 0x00, 0xD0, 0x00]),
    (0x2276, &[0x00, 0x38], &[0x00, 0x3C]),
    (0x4201, &[0x01], &[0x00]),
];

/// Every writable charger object written by SDO after boot is back to its
/// value at boot after reset node (kept by reset communication), but the
/// charge control's readings and the voltage limit (see [`reading`] and
/// [`voltage_limit_after_reset_node`]); the application's read-only
/// readings (2200h, the power stage's AC voltage) keep their value.
#[cfg(feature = "heartbeat-consumer")]
#[test]
fn charger_reset_node_restores_each_writable_object_and_keeps_readings() {
    use canopen_codec::od::ObjectDictionary;
    for (cs, node_reset) in [(0x81u8, true), (0x82, false)] {
        let mut c = charger();
        c.update(ms(0), |o| {
            for (index, before, _) in CHARGER_RW {
                o.write(index, 0, 0, before).unwrap();
                o.finish_write(index, 0, before.len()).unwrap();
            }
        });
        c.boot(ms(0));
        let _ = sent(&mut c);
        for (row, (index, _, after)) in CHARGER_RW.iter().enumerate() {
            c.handle_frame(ms(1 + row as u64), &download(0x60A, *index, 0, after));
            let reply: Vec<String> = sent(&mut c)
                .into_iter()
                .filter(|f| f.starts_with("58A#"))
                .collect();
            assert_eq!(reply.len(), 1, "{index:04X}h");
            assert!(reply[0].starts_with("58A#60"), "{index:04X}h: {reply:?}");
        }
        // The charge control publishes its readings (over what was written).
        let on = PowerStage {
            ac_mv: PowerStage::AC_NOMINAL_MV,
            ..PowerStage::OFF
        };
        c.handle_power_stage(ms(15), on);
        while c.poll_event().is_some() {}

        c.handle_frame(ms(30), &nmt(cs, 10));
        let _ = sent(&mut c);
        // A copy of the charger's dictionary, to read its objects by SDO rules.
        let mut o = canopen_codec::od::FixedDictionary::new(*c.objects().objects());
        for (index, before, after) in CHARGER_RW {
            let want = match (
                node_reset,
                reading(index),
                voltage_limit_after_reset_node(index),
            ) {
                (_, Some(reading), _) => reading,
                (true, None, Some(limit)) => limit,
                (true, None, None) => before,
                (false, None, _) => after,
            };
            let mut buf = [0u8; 4];
            assert_eq!(o.read(index, 0, 0, &mut buf), Ok(want.len()));
            assert_eq!(&buf[..want.len()], want, "{cs:02X}h {index:04X}h");
        }
        assert_eq!(
            o.ac_voltage, 0x0E60,
            "{cs:02X}h: 2200h, the power stage's reading (230 V)"
        );
        // 6080h and 2006h are the charge control's: what it says now. Its
        // 6080h is the module's 6081h: restored to 40 % by reset node,
        // the 60 % written kept by reset communication.
        let status = c.charge_control().status();
        assert_eq!(o.charger_soc, status.charger_soc, "{cs:02X}h");
        assert_eq!(o.charger_soc, if node_reset { 40 } else { 60 }, "{cs:02X}h");
        assert_eq!(o.extended_status, status.extended.to_u16(), "{cs:02X}h");
    }
}

#[test]
fn battery_module_resets_the_same_way() {
    for (cs, node_reset) in [(0x81u8, true), (0x82, false)] {
        let mut m = BatteryModule::new(BatteryModuleConfig::new(NodeId::new(1).unwrap()));
        m.set_temperature(ms(0), Temperature::from_celsius(20).unwrap());
        m.update(ms(0), |o| {
            o.charger_state_of_charge = StateOfCharge::from_raw(50)
        });
        m.boot(ms(0));
        m.set_temperature(ms(1), Temperature::from_celsius(30).unwrap());
        m.update(ms(1), |o| {
            o.charger_state_of_charge = StateOfCharge::from_raw(80)
        });
        m.set_temperature_sensor_fault(ms(1), true);
        m.update_comm(ms(1), |c| c.heartbeat_ms = 100);
        let _ = sent(&mut m);
        while m.poll_event().is_some() {}
        m.handle_frame(ms(5), &nmt(cs, 1));
        // 6010h is a measurement (ro): kept by both resets; 6080h is a
        // parameter (rw): back to its value at boot after reset node.
        assert_eq!(
            m.objects().temperature,
            Temperature::from_celsius(30).unwrap(),
            "{cs:02X}h"
        );
        let soc = if node_reset { 50 } else { 80 };
        assert_eq!(
            m.objects().charger_state_of_charge,
            StateOfCharge::from_raw(soc),
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

/// The row tables above are every writable object of each dictionary
/// (2FFAh, the charger's padding, stores nothing): an object made
/// writable later without a row (and a place in the power-on values)
/// fails here.
#[test]
fn the_rw_tables_are_every_writable_object() {
    use canopen_codec::cia418::{
        BatteryObjects, BATTERY_OBJECT_INDEXES, BATTERY_PARAMETERS_RESTORED,
    };
    use canopen_codec::deltaq::{ChargerObjects, CHARGER_PARAMETERS_RESTORED};
    use canopen_codec::od::{FixedDictionary, ObjectDictionary};
    let battery = FixedDictionary::new(BatteryObjects::new());
    let mut writable = Vec::new();
    for index in BATTERY_OBJECT_INDEXES {
        for sub in 0..=u8::MAX {
            if battery
                .info(index, sub)
                .is_ok_and(|i| i.access.is_writable())
            {
                writable.push((index, sub));
            }
        }
    }
    let rows: Vec<(u16, u8)> = BATTERY_RW.iter().map(|r| (r.0, r.1)).collect();
    assert_eq!(writable, rows);
    // What reset node restores is every writable object.
    let mut restored = BATTERY_PARAMETERS_RESTORED.to_vec();
    restored.sort_unstable();
    assert_eq!(writable, restored);

    let charger = FixedDictionary::new(ChargerObjects::new());
    let mut writable = Vec::new();
    for index in 0x1000..=u16::MAX {
        for sub in 0..=2 {
            if index != 0x2FFA
                && charger
                    .info(index, sub)
                    .is_ok_and(|i| i.access.is_writable())
            {
                writable.push(index);
            }
        }
    }
    writable.sort_unstable();
    let mut rows: Vec<u16> = CHARGER_RW.iter().map(|r| r.0).collect();
    rows.sort_unstable();
    assert_eq!(writable, rows);
    let mut restored: Vec<u16> = CHARGER_PARAMETERS_RESTORED.iter().map(|r| r.0).collect();
    restored.sort_unstable();
    assert_eq!(writable, restored);
}
