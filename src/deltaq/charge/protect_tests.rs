//! One test per protection of [`ChargeControl`] (protect.rs): raised at the
//! right moment from the measurements, the output off, 2006h's bits, and
//! cleared or latched ("Delta-Q IC Series CANopen interface specification
//! rev 2.0", section 4.4.1 names the alarms; the thresholds and clearings
//! are ours, see the module docs).

use super::tests::{bms, events, local_charge, pack, remote_idle, s};
use super::*;
use crate::deltaq::{ChargeStatusFlags, DeltaQCode};
use crate::emcy::{ErrorCode, ErrorRegister};
use std::string::ToString;
use std::vec::Vec;

/// The alarms raised (`true`) or cleared since the last call, as codes.
fn changes(c: &mut ChargeControl) -> Vec<(DeltaQCode, bool)> {
    events(c)
        .into_iter()
        .filter_map(|e| match e {
            ChargeEvent::Alarm { alarm, active } => Some((alarm.code(), active)),
            ChargeEvent::Phase { .. } => None,
        })
        .collect()
}

/// Since the last events, alarm `alarm` alone was raised; the charge is in
/// `phase` and the output is off.
fn stopped_by(c: &mut ChargeControl, alarm: u8, phase: ChargePhase) {
    let code = DeltaQCode::Alarm(alarm);
    assert_eq!(changes(c), [(code, true)]);
    assert_eq!(c.phase(), phase, "{code}");
    assert!(!c.set_points().enabled, "{code}: the output is off");
}

/// 2006h's flags now.
fn flags(c: &ChargeControl) -> ChargeStatusFlags {
    c.status().extended.flags
}

/// Local mode, a ready BMS, the pack at `volts` taking `amps`: bulk.
fn bulk(volts: u32, amps: u32) -> ChargeControl {
    let mut c = local_charge(pack(volts, amps));
    assert_eq!(c.phase(), ChargePhase::Bulk);
    let _ = events(&mut c);
    c
}

/// The BMS of [`bms`] reporting `celsius` in 6010h.
fn bms_at(celsius: i16) -> BusInputs {
    BusInputs {
        battery_temperature: celsius * 8,
        ..bms(0)
    }
}

fn stage(f: impl FnOnce(&mut PowerStage)) -> PowerStage {
    let mut p = pack(50, 25);
    f(&mut p);
    p
}

#[test]
fn e_0_0_1_a_remote_bms_asking_too_much_never_gets_past_the_algorithm() {
    let mut c = remote_idle();
    // A faulty BMS asks 80 V: the set point stays at the algorithm's
    // 63.6 V (24 x 2.65 V), the charger's maximum being 72 V.
    c.handle_bus(
        s(1),
        BusInputs {
            voltage_request_mv: 80_000,
            ..bms(25)
        },
    );
    assert_eq!(c.set_points().voltage_mv, 63_600);
    let _ = events(&mut c);
    c.handle_power_stage(s(2), pack(63, 5));
    assert!(c.alarms().is_empty(), "below the threshold");
    c.handle_power_stage(
        s(3),
        PowerStage {
            voltage_mv: 63_600,
            ..pack(0, 5)
        },
    );
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(1), true)]);
    assert!(!c.set_points().enabled);
    let f = flags(&c);
    assert!(f.contains(ChargeStatusFlags::ALARM_ACTIVE | ChargeStatusFlags::HW_SHUTDOWN));
    assert!(!f.contains(ChargeStatusFlags::FAULT_ACTIVE));
}

#[test]
fn e_0_0_2_a_battery_below_the_low_voltage_is_not_charged() {
    // 20 V: detected (12 V) but below 24 x 0.97 V.
    let mut c = local_charge(pack(20, 0));
    stopped_by(&mut c, 2, ChargePhase::Idle);
    c.handle_power_stage(s(1), pack(24, 0));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(2), false)]);
    assert_eq!(c.phase(), ChargePhase::Bulk);
}

#[test]
fn e_0_0_3_bulk_past_the_safety_timer_terminates_until_the_cycle_ends() {
    // A pack that never reaches absorption (shorted cells): 12 h.
    let mut c = bulk(50, 25);
    c.handle_power_stage(s(12 * 3600 - 1), pack(52, 25));
    assert!(c.alarms().is_empty());
    c.handle_power_stage(s(12 * 3600), pack(52, 25));
    stopped_by(&mut c, 3, ChargePhase::Terminated);
    // Latched: the pack at rest changes nothing ...
    c.handle_power_stage(s(12 * 3600 + 60), pack(50, 0));
    assert_eq!(c.phase(), ChargePhase::Terminated);
    assert!(c.alarms().contains(ChargeAlarms::CHARGE_TIMEOUT));
    // ... until the battery is unplugged: a new cycle.
    c.handle_power_stage(s(12 * 3600 + 61), pack(0, 0));
    assert!(changes(&mut c).contains(&(DeltaQCode::Alarm(3), false)));
    c.handle_power_stage(s(12 * 3600 + 62), pack(50, 0));
    assert_eq!(c.phase(), ChargePhase::Bulk);
}

#[test]
fn e_0_0_4_a_trickle_that_does_not_reach_the_minimum_voltage() {
    // 40 V is below 24 x 1.75 V: a tenth of the bulk current.
    let mut c = bulk(40, 2);
    assert_eq!(c.set_points().current_ma, 2500);
    c.handle_power_stage(s(3599), pack(41, 2));
    assert!(c.alarms().is_empty());
    c.handle_power_stage(s(3600), pack(41, 2));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(4), true)]);
    assert_eq!(c.phase(), ChargePhase::Terminated);
    // One that gets there charges at the full current.
    let mut c = bulk(40, 2);
    c.handle_power_stage(s(1800), pack(43, 2));
    assert_eq!(c.set_points().current_ma, 25_000);
    c.handle_power_stage(s(3600), pack(44, 25));
    assert!(c.alarms().is_empty());
}

#[test]
fn e_0_0_7_the_ah_limit_ends_a_remote_charge_until_the_bms_stops() {
    // Algorithm 1: 12 h of 25 A, 300 Ah (2400 in Q3).
    let mut c = remote_idle();
    c.handle_bus(s(0), bms(25));
    c.handle_power_stage(s(0), pack(50, 25));
    let _ = events(&mut c);
    // Measured every minute (the meter bounds a longer gap).
    for minute in 1..12 * 60 {
        c.handle_power_stage(s(minute * 60), pack(50, 25));
    }
    assert!(c.alarms().is_empty(), "{:?}", c.status().ah_returned);
    c.handle_power_stage(s(12 * 3600), pack(50, 25));
    stopped_by(&mut c, 7, ChargePhase::Terminated);
    // The BMS says not ready: the charge is over, the alarm clears.
    c.handle_bus(
        s(12 * 3600 + 1),
        BusInputs {
            battery_status: 0,
            ..bms(25)
        },
    );
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(7), false)]);
}

#[test]
fn e_0_0_8_out_of_range_pauses_and_resumes_when_back() {
    let mut c = bulk(50, 25);
    c.handle_bus(s(1), bms_at(51));
    // Paused, not terminated.
    stopped_by(&mut c, 8, ChargePhase::Bulk);
    // The BMS, too hot as well, says not ready: still only paused.
    c.handle_bus(
        s(2),
        BusInputs {
            battery_status: 0,
            ..bms_at(51)
        },
    );
    assert_eq!(c.phase(), ChargePhase::Bulk);
    // 49 degC is in range but not 2 degC inside: still paused.
    c.handle_bus(s(3), bms_at(49));
    assert!(c.alarms().contains(ChargeAlarms::TEMPERATURE));
    c.handle_bus(s(4), bms_at(47));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(8), false)]);
    assert!(c.set_points().enabled);
    assert_eq!(c.phase(), ChargePhase::Bulk);
    // Below the range too (lead acid: -20 degC).
    c.handle_bus(s(5), bms_at(-21));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(8), true)]);
}

#[test]
fn e_0_0_8_ignores_a_reading_that_is_no_temperature() {
    // A module whose PDOs alternate 6010h between 2432 degC (bytes of
    // another object where 6010h is expected) and 25 degC: no alarm.
    let mut c = bulk(50, 25);
    for i in 1..=6 {
        let t = if i % 2 == 0 { 25 } else { 2432 };
        c.handle_bus(s(i), bms_at(t));
        assert!(!c.alarms().contains(ChargeAlarms::TEMPERATURE), "{t} degC");
    }
    assert!(changes(&mut c).is_empty());
    assert!(c.set_points().enabled);
    // Raised by a real reading, it stands through implausible ones and
    // clears at a plausible one back inside.
    c.handle_bus(s(7), bms_at(51));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(8), true)]);
    c.handle_bus(s(8), bms_at(-41));
    c.handle_bus(s(9), bms_at(126));
    assert!(c.alarms().contains(ChargeAlarms::TEMPERATURE));
    c.handle_bus(s(10), bms_at(25));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(8), false)]);
}

#[test]
fn e_0_1_2_reverse_polarity() {
    let mut c = local_charge(PowerStage {
        voltage_mv: -48_000,
        ..pack(0, 0)
    });
    // The BMS says ready but no battery shows: E-0-4-5 as well.
    let raised = changes(&mut c);
    assert!(
        raised.contains(&(DeltaQCode::Alarm(12), true)),
        "{raised:?}"
    );
    assert!(!c.set_points().enabled);
    assert_eq!(c.phase(), ChargePhase::Idle);
    c.handle_power_stage(s(1), pack(48, 0));
    assert!(c.alarms().is_empty());
    assert_eq!(c.phase(), ChargePhase::Bulk);
}

#[test]
fn e_0_1_3_a_battery_that_takes_no_current() {
    let mut c = bulk(50, 0);
    c.handle_power_stage(s(1), pack(50, 0));
    c.handle_power_stage(s(60), pack(50, 0));
    assert!(c.alarms().is_empty(), "59 s without current");
    c.handle_power_stage(s(61), pack(50, 0));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(13), true)]);
    assert_eq!(c.phase(), ChargePhase::Terminated);
    // Current that flows resets the wait.
    let mut c = bulk(50, 0);
    c.handle_power_stage(s(1), pack(50, 0));
    c.handle_power_stage(s(50), pack(50, 20));
    c.handle_power_stage(s(51), pack(50, 0));
    c.handle_power_stage(s(100), pack(50, 0));
    assert!(c.alarms().is_empty());
}

#[test]
fn e_0_1_4_more_cells_than_the_algorithm() {
    // 61 V at rest: above 24 x 2.385 V (halfway from 2.12 to 2.65 V).
    let mut c = local_charge(pack(61, 0));
    stopped_by(&mut c, 14, ChargePhase::Terminated);
    c.handle_power_stage(s(1), pack(0, 0));
    assert!(changes(&mut c).contains(&(DeltaQCode::Alarm(14), false)));
}

#[test]
fn e_0_2_3_high_ac_stops_the_output_while_it_stands() {
    let mut c = bulk(50, 25);
    c.handle_power_stage(s(1), stage(|p| p.ac_mv = 270_000));
    assert!(c.alarms().is_empty(), "270 V is the limit");
    c.handle_power_stage(s(2), stage(|p| p.ac_mv = 275_000));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(23), true)]);
    assert!(!c.set_points().enabled);
    assert_eq!(c.phase(), ChargePhase::Bulk);
    c.handle_power_stage(s(3), stage(|p| p.ac_mv = 240_000));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(23), false)]);
    assert!(c.set_points().enabled);
}

#[test]
fn e_0_2_5_ac_dropping_out_three_times_in_a_minute() {
    let mut c = bulk(50, 25);
    let off = stage(|p| p.ac_mv = 60_000);
    for t in [10, 20, 30] {
        c.handle_power_stage(s(t), off);
        c.handle_power_stage(s(t + 1), pack(50, 25));
    }
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(25), true)]);
    assert!(!c.set_points().enabled);
    // AC stays up a minute: cleared.
    c.handle_power_stage(s(90), pack(50, 25));
    assert!(c.alarms().contains(ChargeAlarms::AC_OSCILLATION));
    c.handle_power_stage(s(91), pack(50, 25));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(25), false)]);
    // Drops further apart than the window do not count.
    let mut c = bulk(50, 25);
    for t in [10, 80, 150] {
        c.handle_power_stage(s(t), off);
        c.handle_power_stage(s(t + 1), pack(50, 25));
    }
    assert!(c.alarms().is_empty());
}

#[test]
fn e_0_3_6_the_modules_temperature_sensor_fault_until_its_error_reset() {
    let mut c = bulk(50, 20);
    let emcy = |code| Emergency {
        code: ErrorCode(code),
        register: ErrorRegister::GENERIC,
        manufacturer: [0; 5],
    };
    c.handle_battery_emcy(s(1), &emcy(0x5010));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(36), true)]);
    assert!(c.set_points().enabled, "charges on at half current");
    c.handle_battery_emcy(s(2), &emcy(0x0000));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(36), false)]);
}

#[test]
fn each_stage_fault_stops_the_output_while_the_stage_reports_it() {
    for (n, fault) in StageFaults::all().iter().enumerate() {
        let mut c = bulk(50, 25);
        c.handle_power_stage(s(1), stage(|p| p.faults = fault));
        let code = DeltaQCode::Fault(n as u8 + 1);
        assert_eq!(changes(&mut c), [(code, true)]);
        assert!(!c.set_points().enabled, "{code}");
        let f = flags(&c);
        assert!(f.contains(ChargeStatusFlags::FAULT_ACTIVE | ChargeStatusFlags::HW_SHUTDOWN));
        assert!(!f.contains(ChargeStatusFlags::ALARM_ACTIVE), "{code}");
        assert_eq!(c.alarms().displayed().code(), code);
        c.handle_power_stage(s(2), pack(50, 25));
        assert_eq!(changes(&mut c), [(code, false)]);
        assert!(c.set_points().enabled);
    }
}

#[test]
fn a_fault_is_displayed_before_an_alarm() {
    let both = ChargeAlarms::HIGH_VOLTAGE | ChargeAlarms::FAULT_RELAY;
    assert_eq!(both.displayed(), ChargeAlarms::FAULT_RELAY);
    let alarms = ChargeAlarms::TEMPERATURE | ChargeAlarms::HIGH_AC;
    assert_eq!(alarms.displayed(), ChargeAlarms::TEMPERATURE);
    assert!(ChargeAlarms::empty().displayed().is_empty());
}

#[test]
fn every_flag_has_its_rows_code() {
    // Each flag's code is a row of the section 4.4.1 table.
    for flag in ChargeAlarms::all().iter() {
        let code = flag.code();
        assert!(code.entry().is_some(), "{flag:?}: {code}");
    }
    assert_eq!(ChargeAlarms::REVERSE_POLARITY.code().to_string(), "E-0-1-2");
    assert_eq!(
        ChargeAlarms::FAULT_OUTPUT_CURRENT.code().to_string(),
        "F-0-0-6"
    );
    assert_eq!(
        StageFaults::from_label("relay"),
        Some(StageFaults::RELAY),
        "by name"
    );
    assert_eq!(
        StageFaults::from_label("F-0-0-4"),
        Some(StageFaults::CURRENT_MEASUREMENT)
    );
    assert_eq!(StageFaults::from_label("fan"), None);
}

#[test]
fn e_0_0_8_in_absorption_keeps_the_phase_and_its_clock() {
    let mut c = bulk(50, 25);
    c.handle_power_stage(s(100), pack(59, 25));
    assert_eq!(c.phase(), ChargePhase::Absorption);
    // Too hot after two minutes of absorption: paused, output off, and
    // the 0 A it now reads is no termination current.
    c.handle_bus(s(220), bms_at(51));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(8), true)]);
    for t in [230, 400, 900] {
        c.handle_power_stage(s(t), pack(57, 0));
        assert_eq!(c.phase(), ChargePhase::Absorption, "paused at {t} s");
    }
    // Cooled after 800 s: absorption goes on where it was, two minutes
    // in, and ends on its tapered current.
    c.handle_power_stage(s(1019), pack(58, 20));
    assert_eq!(c.phase(), ChargePhase::Absorption);
    c.handle_bus(s(1020), bms_at(40));
    assert_eq!(changes(&mut c), [(DeltaQCode::Alarm(8), false)]);
    assert_eq!(c.phase(), ChargePhase::Absorption);
    let tapered = PowerStage {
        current_ma: 1000,
        ..pack(59, 0)
    };
    c.handle_power_stage(s(1021), tapered);
    assert_eq!(c.phase(), ChargePhase::Rest);
}

#[test]
fn a_known_capacity_widens_the_safety_timer_and_the_ah_limit_never_narrows_them() {
    let flooded = ChargeConfig::example().algorithm(1).unwrap();
    let own = ProtectionLimits::of(flooded);
    assert_eq!(
        (own.safety_time.as_secs(), own.ah_limit_q3),
        (12 * 3600, 2400)
    );
    // 600 Ah: 150 % is 900 Ah (7200 in Q3), 36 h of 25 A.
    let big = own.for_capacity(600, 25_000);
    assert_eq!(
        (big.safety_time.as_secs(), big.ah_limit_q3),
        (36 * 3600, 7200)
    );
    assert_eq!(big.min_voltage_mv, own.min_voltage_mv);
    // Unknown (0) or small enough for the algorithm's own: unchanged.
    assert_eq!(own.for_capacity(0, 25_000), own);
    assert_eq!(own.for_capacity(100, 25_000), own);
    // Rounded up to whole hours; a zero bulk current divides by one.
    assert_eq!(
        own.for_capacity(210, 25_000).safety_time.as_secs(),
        13 * 3600
    );
    assert_eq!(own.for_capacity(65_535, 0).ah_limit_q3, 786_420);
}

#[test]
fn a_600_ah_pack_from_6020h_is_still_in_bulk_after_the_algorithms_12_h() {
    let mut c = bulk(50, 25);
    let big = BatteryIdentity {
        battery_type: 0x10,
        capacity_ah: 600,
        cells: 24,
    };
    c.handle_identification(s(1), Identification::Known(big));
    for minute in 1..=13 * 60 {
        c.handle_power_stage(s(minute * 60), pack(52, 25));
    }
    // 13 h and 325 Ah: past algorithm 1's 12 h and 300 Ah, not this pack's.
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    assert_eq!(c.phase(), ChargePhase::Bulk);
    // Its own 36 h still end a bulk that never reaches absorption.
    for minute in 13 * 60 + 1..=36 * 60 {
        c.handle_power_stage(s(minute * 60), pack(52, 25));
    }
    assert_eq!(c.phase(), ChargePhase::Terminated);
    assert!(c.alarms().contains(ChargeAlarms::CHARGE_TIMEOUT));
}
