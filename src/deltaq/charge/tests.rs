//! One test per rule of [`ChargeControl`], citing the section of "Delta-Q
//! IC Series CANopen interface specification rev 2.0" it implements (or
//! "ours" where the document is silent).

use super::*;
use crate::deltaq::{ChargeIndication, ChargeStatusFlags, ChargeType, DeltaQCode, OverrideSource};
use crate::emcy::{ErrorCode, ErrorRegister};
use std::vec::Vec;

/// `n` seconds after the start.
pub(super) fn s(n: u64) -> Timestamp {
    Timestamp::from_millis(n * 1000)
}

/// A 24-cell lead-acid pack at `volts` on the output giving `amps`, AC on.
pub(super) fn pack(volts: u32, amps: u32) -> PowerStage {
    PowerStage {
        ac_mv: PowerStage::AC_NOMINAL_MV,
        voltage_mv: volts as i32 * 1000,
        current_ma: amps * 1000,
        temperature_c: 25,
        faults: StageFaults::empty(),
    }
}

/// A BMS present, ready, asking `amps` (6070h) with no voltage request.
pub(super) fn bms(amps: u16) -> BusInputs {
    BusInputs {
        battery_present: true,
        battery_status: 1,
        current_request: amps * 16,
        ..BusInputs::none(72_000)
    }
}

/// The BMS of [`bms`] saying it is not ready (6000h = 0).
fn bms_not_ready(amps: u16) -> BusInputs {
    BusInputs {
        battery_status: 0,
        ..bms(amps)
    }
}

/// The BMS of [`bms`] asking `mv` as well (2271h / 2276h).
fn bms_asking_volts(amps: u16, mv: u32) -> BusInputs {
    BusInputs {
        voltage_request_mv: mv,
        ..bms(amps)
    }
}

/// The battery module gone from the bus (no heartbeat).
fn bms_absent(amps: u16) -> BusInputs {
    BusInputs {
        battery_present: false,
        ..bms(amps)
    }
}

/// The power stage of [`pack`] with AC off.
fn ac_off(volts: u32) -> PowerStage {
    PowerStage {
        ac_mv: 0,
        ..pack(volts, 0)
    }
}

/// The battery module's emergency `code` with `register`, no
/// manufacturer bytes.
fn emcy(code: ErrorCode, register: ErrorRegister) -> Emergency {
    Emergency {
        code,
        register,
        manufacturer: [0; 5],
    }
}

/// The default configuration in `mode`.
pub(super) fn control(mode: OperatingMode) -> ChargeControl {
    ChargeControl::new(mode, ChargeConfig::example())
}

/// Local mode with a ready BMS heard at 0 s and `output` measured then.
pub(super) fn local_charge(output: PowerStage) -> ChargeControl {
    let mut c = control(OperatingMode::Local);
    c.handle_bus(s(0), bms(0));
    c.handle_power_stage(s(0), output);
    c
}

/// Remote mode: AC on at 0 s with a 50 V pack, no BMS heard yet.
pub(super) fn remote_idle() -> ChargeControl {
    let mut c = control(OperatingMode::Remote);
    c.handle_power_stage(s(0), pack(50, 0));
    c
}

/// [`remote_idle`], then at 1 s a ready BMS asking `amps`.
fn remote_charge(amps: u16) -> ChargeControl {
    let mut c = remote_idle();
    c.handle_bus(s(1), bms(amps));
    c
}

/// The events queued so far, drained.
pub(super) fn events(c: &mut ChargeControl) -> Vec<ChargeEvent> {
    core::iter::from_fn(|| c.poll_event()).collect()
}

fn alarms_raised(c: &mut ChargeControl) -> Vec<DeltaQCode> {
    events(c)
        .into_iter()
        .filter_map(|e| match e {
            ChargeEvent::Alarm {
                alarm,
                active: true,
            } => Some(alarm.code()),
            _ => None,
        })
        .collect()
}

// ---- remote mode (section 3.1.1; the three conditions) ----

#[test]
fn remote_charges_only_with_heartbeat_ready_and_a_valid_request() {
    let mut c = remote_idle();
    assert_eq!(c.phase(), ChargePhase::Idle);
    // Each condition missing alone keeps the output off.
    for bus in [
        bms_absent(5),
        bms_not_ready(5),
        BusInputs {
            current_request: 0xFFFF,
            ..bms(5)
        },
    ] {
        c.handle_bus(s(1), bus);
        assert_eq!(c.phase(), ChargePhase::Idle, "{bus:?}");
        assert!(!c.set_points().enabled);
    }
    c.handle_bus(s(2), bms(5));
    assert_eq!(c.phase(), ChargePhase::Remote);
    // 5 A requested (80 x 1/16 A); the voltage request starts at the
    // maximum, and the set point never exceeds the active algorithm's
    // E-0-0-1 threshold (24 x 2.65 V).
    assert_eq!(
        c.set_points(),
        SetPoints {
            enabled: true,
            current_ma: 5000,
            voltage_mv: 63_600
        }
    );
    // The charger stops as soon as one goes false.
    c.handle_bus(s(3), bms_not_ready(5));
    assert!(!c.set_points().enabled);
}

#[test]
fn remote_status_is_bms_run_as_the_capture_shows() {
    // Section 5 (2006h): the real ICL1500 in remote mode reports 0050h
    // idle with AC and 0070h while delivering.
    let mut c = remote_idle();
    assert_eq!(c.status().extended.to_u16(), 0x0050);
    c.handle_bus(s(1), bms(20));
    assert_eq!(c.status().extended.to_u16(), 0x0070);
    assert_eq!(c.status().charger_status, 1);
}

#[test]
fn remote_voltage_request_is_the_set_point() {
    let mut c = remote_idle();
    c.handle_bus(s(1), bms_asking_volts(10, 54_600));
    assert_eq!(c.set_points().voltage_mv, 54_600);
    assert_eq!(c.set_points().current_ma, 10_000);
}

#[test]
fn remote_shuts_down_on_any_module_emcy_until_its_error_reset() {
    // Section 4.4.2: "in remote control mode the charger shall shutdown on
    // receiving any error code". Ours: until the module's error reset.
    let mut c = remote_charge(5);
    let heartbeat_lost = emcy(ErrorCode::HEARTBEAT, ErrorRegister::GENERIC);
    c.handle_battery_emcy(s(2), &heartbeat_lost);
    assert_eq!(c.phase(), ChargePhase::Terminated);
    assert!(!c.set_points().enabled);
    let reset = emcy(ErrorCode::NO_ERROR, ErrorRegister::empty());
    c.handle_battery_emcy(s(3), &reset);
    assert_eq!(c.phase(), ChargePhase::Remote);
}

#[test]
fn remote_stops_on_a_can_bus_error() {
    let mut c = remote_charge(5);
    c.handle_bus(
        s(2),
        BusInputs {
            bus_error: true,
            ..bms(5)
        },
    );
    assert!(!c.set_points().enabled);
    assert_eq!(alarms_raised(&mut c), [DeltaQCode::CAN_BUS_COMMUNICATION]);
}

// ---- local mode (section 3.1.2, section 7) ----

#[test]
fn local_without_can_charges_after_the_hold_off() {
    // Section 7: "local mode with CAN hold-off ... a different default algo
    // if no CAN available".
    let mut c = control(OperatingMode::Local);
    c.handle_power_stage(s(0), pack(48, 0));
    assert_eq!(c.phase(), ChargePhase::HoldOff);
    assert_eq!(c.poll_timeout(), Some(s(10)));
    c.handle_timeout(s(9));
    assert_eq!(c.phase(), ChargePhase::HoldOff);
    c.handle_timeout(s(10));
    assert_eq!(c.phase(), ChargePhase::Bulk);
    assert_eq!(c.active_algorithm(), Some(1));
    assert_eq!(c.set_points().voltage_mv, 24 * 2450);
}

#[test]
fn local_with_a_ready_bms_starts_at_once_and_a_not_ready_one_holds() {
    let mut c = control(OperatingMode::Local);
    c.handle_bus(s(0), bms_not_ready(0));
    c.handle_power_stage(s(0), pack(48, 0));
    assert_eq!(c.phase(), ChargePhase::Idle);
    c.handle_timeout(s(30));
    assert_eq!(
        c.phase(),
        ChargePhase::Idle,
        "no hold-off with a BMS present"
    );
    c.handle_bus(s(31), bms(0));
    assert_eq!(c.phase(), ChargePhase::Bulk);
}

#[test]
fn local_cycle_bulk_absorption_rest_float() {
    // Our three-stage profile (algorithm module docs).
    let mut c = local_charge(pack(50, 25));
    assert_eq!(c.phase(), ChargePhase::Bulk);
    assert_eq!(c.status().extended.indication, ChargeIndication::Below80);
    // The pack reaches 58.8 V - 0.5 %: absorption.
    c.handle_power_stage(s(100), pack(59, 25));
    assert_eq!(c.phase(), ChargePhase::Absorption);
    assert_eq!(c.status().extended.indication, ChargeIndication::Above80);
    // The current tapers to the termination current (1.25 A): not before
    // a minute in absorption.
    let tapered = PowerStage {
        current_ma: 1000,
        ..pack(59, 0)
    };
    c.handle_power_stage(s(130), tapered);
    assert_eq!(c.phase(), ChargePhase::Absorption);
    assert_eq!(c.status().extended.indication, ChargeIndication::Finishing);
    c.handle_power_stage(s(161), tapered);
    assert_eq!(c.phase(), ChargePhase::Rest);
    assert!(!c.set_points().enabled);
    assert_eq!(c.status().extended.indication, ChargeIndication::Resting);
    assert_eq!(c.poll_timeout(), Some(s(221)));
    c.handle_timeout(s(221));
    assert_eq!(c.phase(), ChargePhase::Float);
    assert_eq!(c.status().extended.charge_type, ChargeType::Maintenance);
    assert_eq!(c.set_points().voltage_mv, 24 * 2270);
    assert_eq!(c.status().charger_soc, 100);
}

#[test]
fn absorption_ends_at_its_safety_timer() {
    // At the absorption voltage already: bulk and absorption in one call.
    let mut c = local_charge(pack(59, 25));
    c.handle_power_stage(s(1), pack(59, 20));
    assert_eq!(c.phase(), ChargePhase::Absorption);
    assert_eq!(c.poll_timeout(), Some(s(4 * 3600)));
    c.handle_timeout(s(4 * 3600));
    assert_eq!(c.phase(), ChargePhase::Rest);
}

#[test]
fn lithium_has_no_float_and_completes() {
    let mut c = control(OperatingMode::Local);
    c.handle_bus(s(0), bms(0));
    c.request_algorithm(s(0), Some(AlgorithmRequest::new(11)));
    c.handle_power_stage(s(0), pack(54, 0));
    c.handle_power_stage(s(1), pack(54, 0));
    assert_eq!(c.phase(), ChargePhase::Absorption, "13 x 4.15 V = 53.95 V");
    c.handle_power_stage(s(100), pack(54, 1));
    c.handle_timeout(s(160));
    assert_eq!(c.phase(), ChargePhase::Complete);
    assert_eq!(c.status().extended.indication, ChargeIndication::Complete);
    assert!(!c.set_points().enabled);
}

#[test]
fn terminate_via_6000h_stays_terminated_after_the_bms_is_lost() {
    // Section 7: "terminate charge via battery ready status object 6000h";
    // section 7.1.6: communication failure after charge termination.
    let mut c = local_charge(pack(50, 25));
    assert_eq!(c.phase(), ChargePhase::Bulk);
    c.handle_bus(s(10), bms_not_ready(0));
    assert_eq!(c.phase(), ChargePhase::Terminated);
    assert!(!c.set_points().enabled);
    c.handle_bus(s(20), BusInputs::none(72_000));
    c.handle_timeout(s(60));
    assert_eq!(
        c.phase(),
        ChargePhase::Terminated,
        "no restart on the no-CAN algorithm"
    );
    // AC cycled: a new charge may begin.
    c.handle_power_stage(s(70), ac_off(50));
    c.handle_power_stage(s(71), pack(50, 0));
    assert_eq!(c.phase(), ChargePhase::HoldOff);
}

#[test]
fn restart_via_2241h_begins_a_new_cycle() {
    // Section 7: "restart charge via set active algo".
    let mut c = local_charge(pack(59, 25));
    c.handle_power_stage(s(3600), pack(59, 25));
    assert_eq!(c.phase(), ChargePhase::Absorption);
    assert!(c.status().ah_returned > 0);
    let _ = events(&mut c);
    c.request_algorithm(s(3601), Some(AlgorithmRequest::new(1)));
    // A new cycle: through bulk to absorption at once (the pack is there).
    let phases: Vec<_> = events(&mut c)
        .into_iter()
        .filter_map(|e| match e {
            ChargeEvent::Phase { to, .. } => Some(to),
            _ => None,
        })
        .collect();
    assert_eq!(
        phases,
        [
            ChargePhase::Idle,
            ChargePhase::Bulk,
            ChargePhase::Absorption
        ]
    );
    assert_eq!(c.status().ah_returned, 0);
    assert_eq!(c.status().elapsed, Duration::ZERO);
}

#[test]
fn change_algorithm_mid_charge() {
    // Section 7: "change algo to a different algo".
    let mut c = local_charge(pack(50, 25));
    c.request_algorithm(s(5), Some(AlgorithmRequest::new(2)));
    assert_eq!(c.active_algorithm(), Some(2));
    assert_eq!(c.phase(), ChargePhase::Bulk);
    assert_eq!(c.set_points().current_ma, 12_000);
}

#[test]
fn complete_via_the_float_algorithm() {
    // Section 7: "complete charge via set active algo to float 2241h".
    let mut c = local_charge(pack(50, 25));
    c.request_algorithm(s(5), Some(AlgorithmRequest::new(3)));
    assert_eq!(c.phase(), ChargePhase::Float);
    assert_eq!(c.set_points().voltage_mv, 24 * 2270);
    assert_eq!(c.status().extended.charge_type, ChargeType::Maintenance);
}

#[test]
fn an_unknown_algorithm_raises_e_0_2_8_and_stops() {
    // Section 4.4.1: E-0-2-8 incompatible algorithm.
    let mut c = local_charge(pack(50, 25));
    let _ = events(&mut c);
    c.request_algorithm(s(5), Some(AlgorithmRequest::new(77)));
    assert_eq!(alarms_raised(&mut c), [DeltaQCode::Alarm(28)]);
    assert!(!c.set_points().enabled);
    assert_eq!(c.active_algorithm(), Some(1), "the old one stays active");
    c.request_algorithm(s(6), Some(AlgorithmRequest::new(1)));
    assert!(c.alarms().is_empty());
    assert_eq!(c.phase(), ChargePhase::Bulk);
}

#[test]
fn no_active_algorithm_raises_e_0_2_0() {
    // Section 4.4.1: E-0-2-0 active algorithm not set.
    let config = ChargeConfig {
        permanent_algorithm: None,
        ..ChargeConfig::example()
    };
    let mut c = ChargeControl::new(OperatingMode::Local, config);
    c.handle_bus(s(0), bms(0));
    c.handle_power_stage(s(0), pack(50, 0));
    assert_eq!(alarms_raised(&mut c), [DeltaQCode::Alarm(20)]);
    assert_eq!(c.phase(), ChargePhase::Idle);
    c.request_algorithm(s(1), Some(AlgorithmRequest::new(1).permanent()));
    assert_eq!(c.phase(), ChargePhase::Bulk);
    assert!(c.alarms().is_empty());
}

#[test]
fn revert_after_ac_loss_goes_back_to_the_permanent_algorithm() {
    // Section 5, 2241h bit 30.
    let mut c = local_charge(pack(50, 0));
    let mut r = AlgorithmRequest::new(2);
    r.revert_after_ac_loss = true;
    c.request_algorithm(s(1), Some(r));
    assert_eq!(c.active_algorithm(), Some(2));
    c.handle_power_stage(s(2), ac_off(50));
    assert_eq!(c.active_algorithm(), Some(1));
    // Bit 31: stored permanently, survives AC loss.
    c.handle_power_stage(s(3), pack(50, 0));
    c.request_algorithm(s(4), Some(AlgorithmRequest::new(2).permanent()));
    c.handle_power_stage(s(5), ac_off(50));
    assert_eq!(c.active_algorithm(), Some(2));
}

#[test]
fn ah_target_completes_the_charge() {
    // Section 4.1 / section 7: "set Ah target" (object 2250h ours).
    let mut c = control(OperatingMode::Local);
    c.handle_bus(
        s(0),
        BusInputs {
            ah_target: 10 * 8,
            ..bms(0)
        },
    );
    c.handle_power_stage(s(0), pack(50, 20));
    // 20 A for 30 min = 10 Ah.
    c.handle_power_stage(s(1799), pack(50, 20));
    assert_eq!(c.phase(), ChargePhase::Bulk);
    c.handle_power_stage(s(1800), pack(50, 20));
    assert_eq!(c.phase(), ChargePhase::Rest);
    assert_eq!(c.status().ah_returned, 80);
}

#[test]
fn voltage_request_limits_in_local_mode() {
    // Delta-Q's object list, 2271h: "limit in local mode".
    let mut c = control(OperatingMode::Local);
    c.handle_bus(s(0), bms_asking_volts(0, 56_000));
    c.handle_power_stage(s(0), pack(50, 0));
    assert_eq!(c.set_points().voltage_mv, 56_000);
    assert_eq!(
        c.status().extended.override_source,
        OverrideSource::External
    );
}

#[test]
fn local_override_takes_the_current_request_as_a_limit_and_equalize() {
    // Section 3.1 "local override" (application note 740-0024 not public; ours).
    let mut c = control(OperatingMode::LocalOverride);
    c.handle_bus(s(0), bms(10));
    c.handle_power_stage(s(0), pack(50, 10));
    assert_eq!(c.set_points().current_ma, 10_000);
    // Plain local mode ignores 6070h.
    let mut l = control(OperatingMode::Local);
    l.handle_bus(s(0), bms(10));
    l.handle_power_stage(s(0), pack(50, 10));
    assert_eq!(l.set_points().current_ma, 25_000);
    // Equalize asked (4201h bit 0) after absorption.
    c.handle_bus(
        s(1),
        BusInputs {
            external_override: ExternalOverride::EQUALIZE,
            ..bms(10)
        },
    );
    c.handle_power_stage(s(2), pack(59, 10));
    c.handle_power_stage(s(70), pack(59, 1));
    assert_eq!(c.phase(), ChargePhase::Equalize);
    assert_eq!(c.status().extended.indication, ChargeIndication::Equalize);
    c.handle_timeout(s(70 + 2 * 3600));
    assert_eq!(c.phase(), ChargePhase::Rest);
}

#[test]
fn reduce_current_and_voltage() {
    // Section 7: "reduce current and voltage" (remote: the set points follow).
    let mut c = remote_charge(20);
    assert_eq!(c.set_points().current_ma, 20_000);
    c.handle_bus(s(2), bms_asking_volts(8, 52_000));
    assert_eq!(c.set_points().current_ma, 8_000);
    assert_eq!(c.set_points().voltage_mv, 52_000);
}

#[test]
fn losing_the_bms_during_a_local_charge_carries_on() {
    // Section 7.1.4, "communication failure default".
    let mut c = local_charge(pack(50, 25));
    c.handle_bus(s(5), BusInputs::none(72_000));
    assert_eq!(c.phase(), ChargePhase::Bulk);
    assert!(c.set_points().enabled);
}

#[test]
fn losing_the_bms_before_the_start_falls_back_to_the_hold_off() {
    // Section 7: "lose battery controller – before charge starts".
    let mut c = control(OperatingMode::Local);
    c.handle_bus(s(0), bms_not_ready(0));
    c.handle_power_stage(s(0), pack(50, 0));
    assert_eq!(c.phase(), ChargePhase::Idle);
    c.handle_bus(s(5), BusInputs::none(72_000));
    assert_eq!(c.phase(), ChargePhase::HoldOff);
    c.handle_timeout(s(15));
    assert_eq!(c.phase(), ChargePhase::Bulk);
}

#[test]
fn remote_loses_the_bms_and_stops() {
    let mut c = remote_charge(10);
    c.handle_bus(s(2), bms_absent(10));
    assert_eq!(c.phase(), ChargePhase::Idle);
    assert!(!c.set_points().enabled);
    // Communication restored (section 7.1.7): charging resumes.
    c.handle_bus(s(3), bms(10));
    assert_eq!(c.phase(), ChargePhase::Remote);
}

#[test]
fn remote_counts_a_new_charge_after_the_battery_was_unplugged() {
    // Ours: 6052h is the Ah of the charge that runs; a loss of the BMS
    // (idle, then remote again) goes on counting, a battery taken off the
    // output ends the charge and the next counts from zero.
    let mut c = remote_charge(10);
    c.handle_power_stage(s(2), pack(50, 10));
    c.handle_power_stage(s(362), pack(50, 10));
    let one_hour_tenth = c.status().ah_returned;
    assert_eq!(one_hour_tenth, 8, "10 A for 360 s: 1 Ah (Q3)");
    c.handle_bus(s(363), bms_absent(10));
    c.handle_bus(s(364), bms(10));
    assert_eq!(c.phase(), ChargePhase::Remote);
    assert_eq!(c.status().ah_returned, one_hour_tenth, "the same charge");
    // Unplugged, then another battery.
    c.handle_power_stage(s(365), pack(0, 0));
    assert_eq!(c.phase(), ChargePhase::Idle);
    c.handle_power_stage(s(366), pack(50, 0));
    assert_eq!(c.phase(), ChargePhase::Remote);
    assert_eq!(c.status().ah_returned, 0, "a new charge");
    assert_eq!(c.status().elapsed, Duration::ZERO);
}

#[test]
fn battery_unplugged_with_can_connected_raises_e_0_4_5() {
    // Section 7.1.8, "CAN connected with battery unplugged".
    let mut c = control(OperatingMode::Remote);
    c.handle_power_stage(s(0), pack(0, 0));
    c.handle_bus(s(1), bms(10));
    assert_eq!(alarms_raised(&mut c), [DeltaQCode::BATTERY_DISCONNECTED]);
    assert!(!c.set_points().enabled);
    c.handle_power_stage(s(2), pack(50, 0));
    assert!(c.alarms().is_empty());
    assert!(c.set_points().enabled);
}

#[test]
fn high_voltage_stops_the_output_with_e_0_0_1_and_hysteresis() {
    // Section 4.4.1: E-0-0-1 "battery high voltage (threshold from the algorithm)".
    let mut c = local_charge(pack(50, 25));
    let _ = events(&mut c);
    c.handle_power_stage(s(1), pack(64, 0)); // above 24 x 2.65 V = 63.6 V
    assert_eq!(alarms_raised(&mut c), [DeltaQCode::Alarm(1)]);
    assert!(!c.set_points().enabled);
    assert!(c
        .status()
        .extended
        .flags
        .contains(ChargeStatusFlags::ALARM_ACTIVE));
    c.handle_power_stage(
        s(2),
        PowerStage {
            voltage_mv: 63_000,
            ..pack(0, 0)
        },
    );
    assert!(!c.alarms().is_empty(), "not yet 2 % below");
    c.handle_power_stage(s(3), pack(58, 0));
    assert!(c.alarms().is_empty());
    assert!(c.set_points().enabled);
}

#[test]
fn local_emcy_outside_8xxx_terminates_and_8xxx_does_not() {
    // Section 4.4.2: local mode terminates on any code but 8xxxh.
    let mut c = local_charge(pack(50, 25));
    let generic = |code| emcy(ErrorCode(code), ErrorRegister::GENERIC);
    c.handle_battery_emcy(s(1), &generic(0x8130));
    assert_eq!(c.phase(), ChargePhase::Bulk);
    c.handle_battery_emcy(s(2), &generic(0x3100));
    assert_eq!(c.phase(), ChargePhase::Terminated);
}

#[test]
fn temperature_sensor_fault_halves_the_current() {
    // Section 4.4.2 (5010h's section is missing; ours: derate by half).
    let mut c = local_charge(pack(50, 20));
    let fault = emcy(ErrorCode::TEMPERATURE_SENSOR_FAULT, ErrorRegister::GENERIC);
    c.handle_battery_emcy(s(1), &fault);
    assert_eq!(c.set_points().current_ma, 12_500);
    assert_eq!(c.status().derate, DerateReasons::TEMPERATURE);
    assert!(c
        .status()
        .extended
        .flags
        .contains(ChargeStatusFlags::DERATING));
}

#[test]
fn derating_by_temperature_and_power() {
    // Ours: linear from 70 to 90 degC; 1.5 kW at the output.
    let mut c = local_charge(PowerStage {
        temperature_c: 80,
        ..pack(50, 0)
    });
    assert_eq!(c.set_points().current_ma, 12_500);
    assert_eq!(c.status().derate, DerateReasons::TEMPERATURE);
    c.handle_power_stage(s(1), pack(62, 0));
    assert_eq!(c.set_points().current_ma, 1_500_000 / 62);
    assert_eq!(c.status().derate, DerateReasons::AC_CURRENT_LIMIT);
}

#[test]
fn monitoring_takes_no_command_from_the_bus() {
    // Section 3.1: monitoring only.
    let mut c = control(OperatingMode::MonitoringOnly);
    c.handle_power_stage(s(0), pack(50, 0));
    assert_eq!(c.phase(), ChargePhase::Bulk, "no hold-off");
    c.request_algorithm(s(1), Some(AlgorithmRequest::new(2)));
    assert_eq!(c.active_algorithm(), Some(1));
    c.handle_bus(
        s(2),
        BusInputs {
            battery_status: 0,
            voltage_request_mv: 50_000,
            ..bms(1)
        },
    );
    assert_eq!(c.phase(), ChargePhase::Bulk);
    assert_eq!(c.set_points().voltage_mv, 24 * 2450);
}

#[test]
fn local_can_bus_error_carries_on_without_the_bus() {
    // Section 7: "CAN bus error" (ours: local mode ignores the bus while it lasts).
    let mut c = local_charge(pack(50, 25));
    c.handle_bus(
        s(1),
        BusInputs {
            bus_error: true,
            battery_status: 0,
            ..bms(0)
        },
    );
    assert_eq!(c.phase(), ChargePhase::Bulk);
    assert!(c.alarms().contains(ChargeAlarms::BUS_ERROR));
}

#[test]
fn ah_and_elapsed_follow_the_delivered_current() {
    let mut c = remote_idle();
    assert_eq!(c.status().ah_returned, 0xFFFF, "no charge yet: no value");
    c.handle_bus(s(0), bms(16));
    c.handle_power_stage(s(0), pack(50, 16));
    c.handle_power_stage(s(900), pack(50, 16));
    // 16 A for 15 min = 4 Ah = 32 in Q3.
    assert_eq!(c.status().ah_returned, 32);
    assert_eq!(c.status().elapsed, Duration::from_secs(900));
}

#[test]
fn the_event_queue_drops_the_oldest_and_counts() {
    let mut c = remote_idle();
    for i in 0..10 {
        let status = (i % 2) as u8;
        c.handle_bus(
            s(i),
            BusInputs {
                battery_status: status,
                ..bms(5)
            },
        );
    }
    assert!(c.events_dropped() > 0);
    assert_eq!(events(&mut c).len(), 4);
    // Behaviour unchanged by the undrained queue.
    assert_eq!(c.phase(), ChargePhase::Remote);
}

#[test]
fn the_meter_counts_in_32_bits_and_bounds_a_gap() {
    let mut m = CycleMeter::default();
    // 25 A for 1 ms steps over 36 s: 0.25 Ah = 2 in Q3, 36 s.
    for _ in 0..36_000 {
        m.add(25_000, 1000);
    }
    assert_eq!((m.q3, m.seconds), (2, 36));
    // A gap of five hours counts as one.
    let mut m = CycleMeter::default();
    m.add(25_000, 5 * 3_600_000_000);
    assert_eq!((m.q3, m.seconds), (200, 3600));
    // The largest current and gap do not overflow.
    m.add(u32::MAX, u64::MAX);
    assert_eq!(m.seconds, 7200);
    assert_eq!(m.q3, 200 + (1u64 << 20) as u32 * 3600 / 450_000);
}

#[test]
fn zero_length_phases_run_through_and_no_timer_is_left_behind() {
    // Ours: a rest of zero goes straight on to float in the same call.
    let config = ChargeConfig {
        rest: Duration::ZERO,
        ..ChargeConfig::example()
    };
    let mut c = ChargeControl::new(OperatingMode::Local, config);
    c.handle_bus(s(0), bms(0));
    c.handle_power_stage(s(0), pack(59, 25));
    c.handle_power_stage(s(100), pack(59, 1));
    assert_eq!(c.phase(), ChargePhase::Float);
    assert_eq!(c.poll_timeout(), None);
}

#[test]
fn no_algorithm_at_all_after_the_hold_off_is_e_0_2_0_and_idle() {
    let config = ChargeConfig {
        permanent_algorithm: None,
        no_can_algorithm: None,
        ..ChargeConfig::example()
    };
    let mut c = ChargeControl::new(OperatingMode::Local, config);
    c.handle_power_stage(s(0), pack(50, 0));
    assert_eq!(c.phase(), ChargePhase::HoldOff);
    c.handle_timeout(s(10));
    assert_eq!(c.phase(), ChargePhase::Idle);
    assert_eq!(c.poll_timeout(), None);
    assert_eq!(c.alarms(), ChargeAlarms::ALGORITHM_NOT_SET);
}
