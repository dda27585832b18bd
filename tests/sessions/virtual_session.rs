//! `tests/data/virtual-session.log`: a recorded session of the charger and
//! the battery module (the state machines the `charger` and
//! `battery_module` programs run), on the simulated bus with a fixed epoch:
//! a normal start, a heartbeat loss (the module unplugged at 5 s) and a
//! recovery (a module boots again at 9 s). This test regenerates the session
//! and compares it with the file, so the file is real output; run with
//! `REGENERATE_SESSION=1` to rewrite it after a deliberate change.

use crate::common;

use crate::common::ms;
use canopen_codec::cia418::{
    BatteryModule, BatteryModuleConfig, BatteryStatus, BatteryVoltage, StateOfCharge, Temperature,
};
use canopen_codec::deltaq::charge::PowerStage;
use canopen_codec::deltaq::{Charger, ChargerConfig};
use canopen_codec::trace::candump::LogLineDisplay;
use canopen_codec::{CanFrame, NodeId, Timestamp};
use common::devices::{boot_all, charger_bus};

const EPOCH_US: u64 = 1_763_800_000_000_000;
const FILE: &str = "tests/data/virtual-session.log";

fn battery(now: Timestamp) -> BatteryModule {
    let mut b = BatteryModule::new(BatteryModuleConfig::new(NodeId::new(1).unwrap()));
    b.update(now, |o| {
        o.battery_status = BatteryStatus::READY_TO_CHARGE;
        o.temperature = Temperature::from_raw(200); // 25 degC
        o.battery_voltage = BatteryVoltage::from_raw(49_152); // 48 V
        o.battery_state_of_charge = StateOfCharge::from_raw(55);
    });
    b
}

fn session() -> String {
    let charger = Charger::new(ChargerConfig::new(
        NodeId::new(10).unwrap(),
        NodeId::new(1).unwrap(),
    ));
    let (mut bus, c, b) = charger_bus(charger, Some(battery(ms(0))));
    boot_all(&mut bus, c, b);
    // The power stage: AC on, 19.5 A into a 48 V pack (local mode: the
    // charge control starts bulk once the module says ready).
    let stage = PowerStage {
        ac_mv: PowerStage::AC_NOMINAL_MV,
        voltage_mv: 48_000,
        current_ma: 19_500,
        ..PowerStage::OFF
    };
    bus.with(c, |m, now| m.handle_power_stage(now, stage));
    bus.run_until(ms(20)).unwrap();
    // The BMS starts every node.
    bus.inject(CanFrame::standard(0x000, &[0x01, 0x00]).unwrap());
    bus.run_until(ms(5000)).unwrap();
    bus.unplug(b);
    bus.run_until(ms(9000)).unwrap();
    assert!(bus.plug(b, battery(ms(9000))).is_ok());
    bus.with(b, |m, now| m.boot(now));
    bus.run_until(ms(9020)).unwrap();
    bus.inject(CanFrame::standard(0x000, &[0x01, 0x00]).unwrap());
    bus.run_until(ms(12_000)).unwrap();
    let mut out = String::new();
    for s in bus.log() {
        let line = LogLineDisplay {
            timestamp: Timestamp::from_micros(EPOCH_US + s.at.as_micros()),
            interface: "vcan0",
            frame: &s.frame,
        };
        out.push_str(&format!("{line}\n"));
    }
    out
}

#[test]
fn recorded_session_is_what_the_nodes_produce() {
    let fresh = session();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(FILE);
    if std::env::var_os("REGENERATE_SESSION").is_some() {
        std::fs::write(&path, &fresh).unwrap();
    }
    let recorded = std::fs::read_to_string(&path).expect("tests/data/virtual-session.log");
    assert_eq!(
        recorded, fresh,
        "regenerate with REGENERATE_SESSION=1 if the change is deliberate"
    );
    // It shows what it should: configuration reads, the loss, the recovery.
    assert!(fresh.contains("vcan0 601#4000100000000000"));
    assert!(fresh.contains("vcan0 08A#3081012080000000"));
    assert!(fresh.contains("vcan0 08A#3081011E80000000"));
    assert!(fresh.contains("vcan0 08A#0000000000000000"));
    assert_eq!(
        fresh.matches("vcan0 701#00").count(),
        2,
        "two boot-ups of the module"
    );
}
