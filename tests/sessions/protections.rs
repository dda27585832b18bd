//! The charger's protections in whole sessions ("Delta-Q IC Series CANopen
//! interface specification rev 2.0", section 4.4.1; the thresholds are
//! ours, docs/CHARGING.md "Protections"): a faulty remote BMS asking too
//! much, and a battery too hot that pauses the charge and resumes it.

use canopen_codec::cia418::Chemistry;
use canopen_codec::deltaq::charge::{ChargeAlarms, ChargePhase};
use canopen_codec::deltaq::OperatingMode;
use canopen_codec::sim::{Session, SessionConfig};
use canopen_codec::Timestamp;

fn minutes(m: u64) -> Timestamp {
    Timestamp::from_millis(m * 60_000)
}

fn alarms(s: &Session) -> ChargeAlarms {
    s.charger()
        .map(|c| c.charge_control().alarms())
        .unwrap_or_default()
}

#[test]
fn a_remote_bms_asking_too_much_never_pushes_the_pack_past_the_algorithm() {
    // A 90 % lithium-ion pack (13 cells) whose BMS holds 25 A up to 57.2 V
    // (4.4 V/cell) and never ends the charge: the charger's algorithm 11
    // stops at 13 x 4.25 V.
    let config = SessionConfig::new(OperatingMode::Remote, Chemistry::LithiumIon, 100.0, 0.9)
        .expect("a supported pack");
    let mut s = Session::new(&config);
    s.bms.cv_volts = 57.2;
    s.bms.end_current_a = 0.0;
    s.start();
    let limit_v = 55.25;
    let mut highest: f64 = 0.0;
    let mut raised_at = None;
    s.run_while(minutes(180), |s| {
        let v = s.pack.terminal_voltage(s.stage.current_a);
        highest = highest.max(v);
        if raised_at.is_none() && alarms(s).contains(ChargeAlarms::HIGH_VOLTAGE) {
            raised_at = Some(s.now());
        }
        true
    });
    let raised_at = raised_at.expect("E-0-0-1 raised");
    assert!(
        highest <= limit_v + 0.01,
        "the pack reached {highest:.3} V, past {limit_v} V"
    );
    // On the bus: the EMCY with E-0-0-1 (8001h).
    let r = s.result();
    assert!(
        r.errors.iter().any(|(_, code)| code.raw() == 0x8001),
        "{:?}",
        r.errors
    );
    assert!(raised_at > minutes(1), "raised by the charge, not at once");
}

#[test]
fn a_battery_too_hot_pauses_the_charge_with_e_0_0_8_and_it_resumes() {
    // Lithium ion charges from 0 to 45 degC (ours). At 10 min the pack is
    // 50 degC (its BMS says not ready as well), at 20 min 25 degC again.
    let config = SessionConfig::new(OperatingMode::Local, Chemistry::LithiumIon, 100.0, 0.3)
        .expect("a supported pack");
    let mut s = Session::new(&config);
    s.start();
    s.run_until(minutes(10));
    assert!(
        s.stage.current_a > 20.0,
        "charging: {} A",
        s.stage.current_a
    );
    s.pack.set_temperature_c(50.0);
    s.run_until(minutes(11));
    assert!(alarms(&s).contains(ChargeAlarms::TEMPERATURE));
    assert_eq!(s.stage.current_a, 0.0, "paused");
    assert_ne!(s.phase(), ChargePhase::Terminated);
    s.run_until(minutes(20));
    assert_eq!(s.stage.current_a, 0.0, "still paused");
    s.pack.set_temperature_c(25.0);
    s.run_until(minutes(22));
    assert!(!alarms(&s).contains(ChargeAlarms::TEMPERATURE));
    assert!(s.stage.current_a > 20.0, "resumed: {} A", s.stage.current_a);
    assert_eq!(s.phase(), ChargePhase::Bulk);
    // E-0-0-8 (8008h) went out as an EMCY.
    assert!(s.result().errors.iter().any(|(_, c)| c.raw() == 0x8008));
}
