//! End-to-end scenarios (the use cases of "Delta-Q IC Series CANopen
//! interface specification rev 2.0", section 7: normal charge, terminate
//! via 6000h, battery module lost and restored, ...): the charger and a CiA 418
//! battery module on one simulated bus (0.5 ms latency) with a simulated
//! clock from zero; the test plays the NMT master. Each scenario asserts the
//! exact frames and times on the bus.

use crate::common;

use crate::common::ms;
use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig, BatteryStatus, DeviceType};
use canopen_codec::deltaq::Reaction;
use canopen_codec::deltaq::{Charger, ChargerConfig, ChargerEvent};
use canopen_codec::device::DeviceEvent;
use canopen_codec::emcy::ErrorCode;
use canopen_codec::nmt::NmtState;
use canopen_codec::sdo::AbortCode;
use canopen_codec::{CanFrame, NodeId};
use common::devices::{boot_all, charger_bus};
use common::sim::{Bus, Handle};

fn charger() -> Charger {
    Charger::new(ChargerConfig::new(
        NodeId::new(10).unwrap(),
        NodeId::new(1).unwrap(),
    ))
}

fn battery_with(device_type: DeviceType) -> BatteryModule {
    let mut config = BatteryModuleConfig::new(NodeId::new(1).unwrap());
    config.device_type = device_type;
    BatteryModule::new(config)
}

fn battery() -> BatteryModule {
    battery_with(DeviceType::cia418(0))
}

/// The simulated bus with the charger and the battery module's place.
type Nodes = (Bus, Handle<Charger>, Handle<BatteryModule>);

fn start_all(bus: &mut Bus) {
    bus.inject(CanFrame::standard(0x000, &[0x01, 0x00]).unwrap());
}

/// Boots both, starts them at 100 ms.
fn started() -> Nodes {
    let (mut bus, c, b) = charger_bus(charger(), Some(battery()));
    boot_all(&mut bus, c, b);
    bus.run_until(ms(100)).unwrap();
    start_all(&mut bus);
    (bus, c, b)
}

fn events(bus: &Bus, c: Handle<Charger>) -> Vec<ChargerEvent> {
    bus.event_list(c)
}

#[test]
fn normal_start() {
    let (mut bus, c, _) = started();
    bus.run_until(ms(1000)).unwrap();
    // Boot-ups; the charger finds the module at its boot-up and reads 1000h
    // (418, no optional PDOs), then the module's RPDO 0 and TPDO 0 COB-IDs;
    // NMT start at 100 ms; both TPDO 0 at once and every 200 ms; heartbeats
    // at 1000 ms.
    assert_eq!(
        bus.lines(0, 1000),
        [
            "     0.000 Charger 70A#00",
            "     0.000 Battery 701#00",
            "     0.500 Charger 601#4000100000000000",
            "     1.000 Battery 581#43001000A2010000",
            "     1.500 Charger 601#4000140100000000",
            "     2.000 Battery 581#4300140101020000",
            "     2.500 Charger 601#4000180100000000",
            "     3.000 Battery 581#4300180181010000",
            "   100.000 Outside 000#0100",
            "   100.500 Charger 201#00",
            "   100.500 Battery 181#000000",
            "   300.500 Charger 201#00",
            "   300.500 Battery 181#000000",
            "   500.500 Charger 201#00",
            "   500.500 Battery 181#000000",
            "   700.500 Charger 201#00",
            "   700.500 Battery 181#000000",
            "   900.500 Charger 201#00",
            "   900.500 Battery 181#000000",
            "  1000.000 Charger 70A#05",
            "  1000.000 Battery 701#05",
        ]
    );
    assert_eq!(
        events(&bus, c)[..3],
        [
            ChargerEvent::Device(DeviceEvent::NmtStateChanged {
                from: canopen_codec::nmt::NmtState::BootUp,
                to: canopen_codec::nmt::NmtState::PreOperational
            }),
            ChargerEvent::BatteryFound {
                state: canopen_codec::nmt::NmtState::BootUp
            },
            ChargerEvent::Configured {
                tpdos: 0b1,
                rpdos: 0b1
            },
        ]
    );
    assert!(bus.machine(c).unwrap().is_configured());
    // The charger's TPDO 0 now uses the module's RPDO 0 identifier.
    let pdos = bus.machine(c).unwrap().pdo_config();
    let t0 = pdos
        .get(
            canopen_codec::pdo::PdoDirection::Transmit,
            canopen_codec::PdoNumber::P0,
        )
        .unwrap();
    assert_eq!(t0.comm.cob_id.to_u32(), 0x201);
}

#[test]
fn terminate_charge_via_battery_status() {
    let (mut bus, c, b) = started();
    bus.run_until(ms(2000)).unwrap();
    bus.with(b, |m, now| {
        m.set_battery_status(now, BatteryStatus::READY_TO_CHARGE)
    });
    bus.run_until(ms(2500)).unwrap();
    assert_eq!(bus.machine(c).unwrap().objects().battery_status, 0x01);
    // The BMS withdraws "ready to charge": an event, sent at once.
    bus.with(b, |m, now| {
        m.set_battery_status(now, BatteryStatus::empty())
    });
    bus.run_until(ms(2600)).unwrap();
    assert_eq!(
        bus.lines(2000, 2600)
            .into_iter()
            .filter(|l| l.contains("181#"))
            .collect::<Vec<_>>(),
        [
            // A changed value is sent at once and restarts the event timer.
            "  2000.000 Battery 181#000001",
            "  2200.000 Battery 181#000001",
            "  2400.000 Battery 181#000001",
            "  2500.000 Battery 181#000000",
        ]
    );
    assert_eq!(bus.machine(c).unwrap().objects().battery_status, 0x00);
}

#[test]
fn battery_lost_during_charge_then_restored() {
    let (mut bus, c, b) = started();
    bus.run_until(ms(2000)).unwrap();
    // Unplugged right after its 2000 ms heartbeat.
    bus.unplug(b);
    bus.run_until(ms(5000)).unwrap();
    // Last heartbeat received at 2000.5: lost at 4000.5, E-0-3-2 as in the
    // real capture; the charger's TPDOs stop. With the 2000 ms consumer
    // time the module is gone at once after it: E-0-3-0 (the capture's
    // second EMCY) and the charger leaves operational.
    assert_eq!(
        bus.frames_on(0x08A),
        [
            (4_000_500, vec![0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0]),
            (4_000_501, vec![0x30, 0x81, 0x01, 0x1E, 0x80, 0, 0, 0]),
        ]
    );
    let tpdos = bus.frames_on(0x201);
    assert_eq!(tpdos.last().unwrap().0, 3_900_500, "no TPDO after the loss");
    let charger = bus.machine(c).unwrap();
    // 1003h, newest first.
    assert_eq!(charger.comm().errors(), &[0x1E80_8130, 0x2080_8130]);
    assert!(!charger.is_configured());
    assert_eq!(charger.nmt_state(), NmtState::PreOperational);
    let seen = events(&bus, c);
    let lost = seen.iter().position(|e| *e == ChargerEvent::BatteryLost);
    let gone = seen.iter().position(|e| *e == ChargerEvent::BatteryGone);
    assert!(lost.is_some() && gone > lost, "{seen:?}");
    // Communication restored: a new module boots at 6000 ms; the charger
    // re-reads the configuration and clears the error; the BMS starts it
    // again and its TPDO resumes.
    assert!(bus.plug(b, battery()).is_ok());
    bus.run_until(ms(6000)).unwrap();
    bus.with(b, |m, now| m.boot(now));
    bus.run_until(ms(6100)).unwrap();
    bus.inject(CanFrame::standard(0x000, &[0x01, 0x0A]).unwrap());
    bus.run_until(ms(6300)).unwrap();
    assert_eq!(
        bus.lines(6000, 6300),
        [
            "  6000.000 Charger 70A#7F",
            "  6000.000 Battery 701#00",
            "  6000.500 Charger 601#4000100000000000",
            "  6001.000 Battery 581#43001000A2010000",
            "  6001.500 Charger 601#4000140100000000",
            "  6002.000 Battery 581#4300140101020000",
            "  6002.500 Charger 601#4000180100000000",
            "  6003.000 Battery 581#4300180181010000",
            "  6003.500 Charger 08A#0000000000000000",
            "  6100.000 Outside 000#010A",
            "  6100.500 Charger 201#00",
        ]
    );
    assert!(bus.machine(c).unwrap().is_configured());
}

#[test]
fn battery_lost_before_charge() {
    let (mut bus, c, b) = charger_bus(charger(), Some(battery()));
    boot_all(&mut bus, c, b);
    // Unplugged right after its boot-up message: the configuration read is
    // never answered.
    bus.unplug(b);
    bus.run_until(ms(2500)).unwrap();
    assert_eq!(
        bus.lines(0, 2500),
        [
            "     0.000 Charger 70A#00",
            "     0.000 Battery 701#00",
            "     0.500 Charger 601#4000100000000000",
            "  1000.000 Charger 70A#7F",
            "  2000.000 Charger 70A#7F",
            // Boot-up heard at 0.5 ms: lost at 2000.5 ms, E-0-3-2; the
            // configuration transfer is given up with a general-error abort.
            "  2000.500 Charger 08A#3081012080000000",
            "  2000.500 Charger 601#8000100000000008",
            // Gone (already pre-operational, so no state change).
            "  2000.501 Charger 08A#3081011E80000000",
        ]
    );
}

#[test]
fn can_connected_with_battery_unplugged() {
    let (mut bus, c, b) = charger_bus(charger(), None);
    boot_all(&mut bus, c, b);
    bus.run_until(ms(100)).unwrap();
    start_all(&mut bus);
    bus.run_until(ms(3500)).unwrap();
    // Only heartbeats: no configuration, no TPDO, no EMCY (monitoring starts
    // at the module's first heartbeat).
    assert_eq!(
        bus.lines(0, 3500),
        [
            "     0.000 Charger 70A#00",
            "   100.000 Outside 000#0100",
            "  1000.000 Charger 70A#05",
            "  2000.000 Charger 70A#05",
            "  3000.000 Charger 70A#05",
        ]
    );
}

#[test]
fn module_with_every_optional_pdo() {
    let all = DeviceType::cia418(
        DeviceType::RPDO_2ND | DeviceType::RPDO_3RD | DeviceType::TPDO_2ND | DeviceType::TPDO_3RD,
    );
    let (mut bus, c, b) = charger_bus(charger(), Some(battery_with(all)));
    boot_all(&mut bus, c, b);
    bus.run_until(ms(50)).unwrap();
    let reads: Vec<String> = bus
        .lines(0, 50)
        .into_iter()
        .filter(|l| l.contains("Charger 601#40"))
        .collect();
    assert_eq!(
        reads,
        [
            "     0.500 Charger 601#4000100000000000",
            "     1.500 Charger 601#4000140100000000",
            "     2.500 Charger 601#4000180100000000",
            "     3.500 Charger 601#4001140100000000",
            "     4.500 Charger 601#4002140100000000",
            "     5.500 Charger 601#4001180100000000",
            "     6.500 Charger 601#4002180100000000",
        ]
    );
    assert!(events(&bus, c).contains(&ChargerEvent::Configured {
        tpdos: 0b111,
        rpdos: 0b111
    }));
    start_all(&mut bus);
    bus.run_until(ms(400)).unwrap();
    // Charger TPDOs 0-2 on the module's RPDO identifiers, every 200 ms.
    for id in [0x201u16, 0x301, 0x401] {
        let times: Vec<u64> = bus.frames_on(id).iter().map(|(t, _)| *t).collect();
        assert_eq!(times, [50_500, 250_500], "{id:X}");
    }
}

#[test]
fn module_whose_sdo_server_aborts() {
    // Device type says "RPDO 3 (Delta-Q manufacturer)", but the module has
    // no 1403h: the read is aborted, the configuration fails with E-0-3-0.
    let (mut bus, c, b) = charger_bus(
        charger(),
        Some(battery_with(DeviceType::cia418(
            canopen_codec::deltaq::device_type::RPDO_3,
        ))),
    );
    boot_all(&mut bus, c, b);
    bus.run_until(ms(100)).unwrap();
    start_all(&mut bus);
    bus.run_until(ms(1500)).unwrap();
    let l = bus.lines(0, 10);
    assert_eq!(
        l[l.len() - 3..],
        [
            "     3.500 Charger 601#4003140100000000",
            "     4.000 Battery 581#8003140100000206",
            "     4.500 Charger 08A#3081011E80000000",
        ]
    );
    assert!(
        events(&bus, c).contains(&ChargerEvent::ConfigurationFailed {
            index: 0x1403,
            sub: 1,
            code: AbortCode::ObjectDoesNotExist
        })
    );
    assert!(
        bus.frames_on(0x201).is_empty(),
        "no TPDO without a configuration"
    );
    assert_eq!(bus.machine(c).unwrap().comm().errors(), &[0x1E80_8130]);
}

#[test]
fn battery_emcy_is_reported_with_the_policy_reaction() {
    let (mut bus, c, b) = started();
    bus.run_until(ms(500)).unwrap();
    bus.with(b, |m, now| m.set_temperature_sensor_fault(now, true));
    bus.run_until(ms(600)).unwrap();
    assert_eq!(
        bus.frames_on(0x081),
        [(500_000, vec![0x10, 0x50, 0x21, 0, 0, 0, 0, 0])]
    );
    let reported: Vec<(ErrorCode, Reaction)> = events(&bus, c)
        .into_iter()
        .filter_map(|e| match e {
            ChargerEvent::BatteryEmcy { emcy, reaction } => Some((emcy.code, reaction)),
            _ => None,
        })
        .collect();
    assert_eq!(
        reported,
        [(
            ErrorCode::TEMPERATURE_SENSOR_FAULT,
            Reaction::TemperatureSensorFault
        )]
    );
}

#[test]
fn without_cob_id_configuration_defaults_are_used() {
    // As in the real capture: no SDO at all, TPDOs on the charger's own ids.
    let mut config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::new(1).unwrap());
    config.configure_cob_ids = false;
    let (mut bus, c, b) = charger_bus(Charger::new(config), Some(battery()));
    boot_all(&mut bus, c, b);
    bus.run_until(ms(100)).unwrap();
    start_all(&mut bus);
    bus.run_until(ms(1000)).unwrap();
    assert!(bus.lines(0, 1000).iter().all(|l| !l.contains("601#")));
    let times: Vec<u64> = bus.frames_on(0x18A).iter().map(|(t, _)| *t).collect();
    assert_eq!(times, [100_500, 300_500, 500_500, 700_500, 900_500]);
    // The module's TPDO 0 (181h) is not one of the charger's RPDOs here.
    assert!(!events(&bus, c)
        .iter()
        .any(|e| matches!(e, ChargerEvent::Device(DeviceEvent::RpdoReceived { .. }))));
}

#[test]
fn module_reset_while_configured_is_configured_again() {
    let (mut bus, c, _) = started();
    bus.run_until(ms(500)).unwrap();
    // The BMS resets the module's communication: it boots again (default
    // PDOs), and the charger pairs again without raising any error.
    bus.inject(CanFrame::standard(0x000, &[0x82, 0x01]).unwrap());
    bus.run_until(ms(700)).unwrap();
    let l = bus.lines(500, 510);
    assert_eq!(
        l,
        [
            "   500.000 Outside 000#8201",
            "   500.500 Battery 701#00",
            // The charger's TPDO period falls here, before the boot-up arrives.
            "   500.500 Charger 201#00",
            "   501.000 Charger 601#4000100000000000",
            "   501.500 Battery 581#43001000A2010000",
            "   502.000 Charger 601#4000140100000000",
            "   502.500 Battery 581#4300140101020000",
            "   503.000 Charger 601#4000180100000000",
            "   503.500 Battery 581#4300180181010000",
            "   504.000 Charger 201#00",
        ]
    );
    assert!(
        bus.frames_on(0x08A).is_empty(),
        "no EMCY for a reset module"
    );
    let configured = events(&bus, c)
        .iter()
        .filter(|e| matches!(e, ChargerEvent::Configured { .. }))
        .count();
    assert_eq!(configured, 2);
}
