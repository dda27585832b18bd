//! Every use case of "Delta-Q IC Series CANopen interface specification rev
//! 2.0", section 7, as a whole session ([`Scenario`]): what the bus shows
//! (the charger's TPDO 3 with 2002h / 2100h / 2006h, its TPDO 2 with 6001h
//! / 6052h / 6080h, the module's TPDOs with 6000h, 6070h and 6081h, the
//! EMCYs, the SDO writes of the BMS) asserted over time, and
//! `canopen-decode --summary-only --check` run on every session's log.

use canopen_codec::deltaq::charge::ChargePhase;
use canopen_codec::deltaq::{DeltaQCode, OperatingMode};
use canopen_codec::sim::{Scenario, ScenarioOptions, Session};
use canopen_codec::Timestamp;

/// A PDO or EMCY frame of the log: time in seconds and its data.
struct Seen {
    t: f64,
    data: Vec<u8>,
}

fn frames(s: &Session, cob: u32) -> Vec<Seen> {
    s.log()
        .iter()
        .filter(|l| l.frame.id().raw() == cob)
        .map(|l| Seen {
            t: l.at.as_micros() as f64 / 1e6,
            data: l.frame.data().to_vec(),
        })
        .collect()
}

fn u16_at(d: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([d[i], d[i + 1]])
}

/// The charger's TPDO 3 (48Ah): (time, 2002h amps, 2006h).
fn charger_status(s: &Session) -> Vec<(f64, f64, u16)> {
    frames(s, 0x48A)
        .iter()
        .map(|f| {
            (
                f.t,
                f64::from(u16_at(&f.data, 0)) / 256.0,
                u16_at(&f.data, 4),
            )
        })
        .collect()
}

/// The charger's TPDO 3 (48Ah): (time, 2100h volts).
fn charger_volts(s: &Session) -> Vec<(f64, f64)> {
    frames(s, 0x48A)
        .iter()
        .map(|f| (f.t, f64::from(u16_at(&f.data, 2)) / 1024.0))
        .collect()
}

/// The module's 3rd TPDO (381h): (time, 6070h amps, 6081h).
fn requests(s: &Session) -> Vec<(f64, f64, u8)> {
    frames(s, 0x381)
        .iter()
        .map(|f| (f.t, f64::from(u16_at(&f.data, 0)) / 16.0, f.data[2]))
        .collect()
}

/// The module's 1st TPDO (181h): (time, 6000h).
fn battery_status(s: &Session) -> Vec<(f64, u8)> {
    frames(s, 0x181).iter().map(|f| (f.t, f.data[2])).collect()
}

/// The charger's EMCYs: (time, EEC, Delta-Q code word).
fn emcys(s: &Session) -> Vec<(f64, u16, u16)> {
    frames(s, 0x08A)
        .iter()
        .map(|f| (f.t, u16_at(&f.data, 0), u16_at(&f.data, 3)))
        .collect()
}

/// An SDO expedited download the BMS made to the charger: (time, index, value).
fn sdo_writes(s: &Session) -> Vec<(f64, u16, u32)> {
    frames(s, 0x60A)
        .iter()
        .filter(|f| f.data[0] & 0xE0 == 0x20)
        .map(|f| {
            let v = u32::from_le_bytes([f.data[4], f.data[5], f.data[6], f.data[7]]);
            (f.t, u16_at(&f.data, 1), v)
        })
        .collect()
}

const INDICATION_BELOW_80: u16 = 1;
const INDICATION_ABOVE_80: u16 = 2;
const INDICATION_FINISHING: u16 = 3;
const INDICATION_COMPLETE: u16 = 4;
const INDICATION_RESTING: u16 = 5;

fn indication(status: u16) -> u16 {
    status >> 8 & 0xF
}

fn charge_type(status: u16) -> u16 {
    status >> 12
}

fn run(scenario: Scenario) -> Session {
    run_with(scenario, &ScenarioOptions::default())
}

fn run_with(scenario: Scenario, options: &ScenarioOptions) -> Session {
    let s = scenario.run(options).expect("a supported pack");
    #[cfg(feature = "cli")]
    decoder_check(scenario, &s);
    s
}

/// E-0-3-2 (8020h), E-0-3-0 (801Eh), E-0-4-5 (802Dh) as their EMCY words.
const E_0_3_2: u16 = 0x8020;
const E_0_3_0: u16 = 0x801E;
const E_0_4_5: u16 = 0x802D;

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    (a - b).abs() <= tolerance
}

#[test]
fn normal_local_charge_runs_bulk_absorption_rest_float() {
    let s = run(Scenario::NormalLocal);
    let status = charger_status(&s);
    // The indications in order, each for a while.
    let mut order: Vec<u16> = status.iter().map(|x| indication(x.2)).collect();
    order.dedup();
    let wanted = [
        INDICATION_BELOW_80,
        INDICATION_ABOVE_80,
        INDICATION_FINISHING,
        INDICATION_RESTING,
        INDICATION_COMPLETE,
    ];
    let mut it = order.iter();
    for w in wanted {
        assert!(it.any(|i| *i == w), "indication {w} missing in {order:?}");
    }
    // Bulk at the algorithm's 25 A (within 0.1 A); the current tapers in
    // absorption; float at maintenance with its small current.
    for (t, amps, st) in &status {
        if indication(*st) == INDICATION_BELOW_80 && *t > 2.0 {
            assert!(close(*amps, 25.0, 0.1), "{amps} A at {t} s in bulk");
        }
    }
    let cv: Vec<_> = status
        .iter()
        .filter(|x| matches!(indication(x.2), INDICATION_ABOVE_80 | INDICATION_FINISHING))
        .collect();
    assert!(
        cv.first().unwrap().1 > 20.0 && cv.last().unwrap().1 < 1.5,
        "taper"
    );
    // The absorption voltage follows the pack's temperature (6010h,
    // -4 mV/cell/degC in whole degrees): as the tapering pack cools a
    // degree the set point rises 96 mV and the current steps up, by less
    // than 0.1 A.
    let rises: Vec<_> = cv.windows(2).filter(|w| w[1].1 > w[0].1 + 0.1).collect();
    assert!(rises.is_empty(), "monotonic taper {rises:?}");
    let last = status.last().unwrap();
    assert_eq!(charge_type(last.2), 2, "maintenance");
    assert_eq!(last.2 & 0x30, 0x30, "enabled, AC present");
    assert!(last.1 <= 2.5);
    // The pack is full, 6052h says what was returned; no alarm.
    let soc = requests(&s).last().unwrap().2;
    assert!(soc >= 98, "{soc} %");
    let tpdo2 = frames(&s, 0x401);
    let ah = f64::from(u16_at(&tpdo2.last().unwrap().data, 1)) / 8.0;
    assert!(close(ah, s.result().ah, 0.2), "6052h {ah} Ah");
    assert!(emcys(&s).is_empty());
}

#[test]
fn normal_remote_charge_follows_the_bms_request_to_its_end() {
    let s = run(Scenario::NormalRemote);
    let status = charger_status(&s);
    let requests = requests(&s);
    // 2006h: the BMS runs the cycle (charge type none, inactive, external).
    assert!(status
        .iter()
        .all(|x| x.2 & 0xFFC0 == 0x0040 && x.2 & 0x10 != 0));
    // The current follows the request (the latest one before each
    // status), where the charger's 1.5 kW at the pack's voltage allow it.
    let volts = charger_volts(&s);
    let mut checked = 0;
    for ((t, amps, st), (_, v)) in status.iter().zip(&volts) {
        let Some(r) = requests.iter().rev().find(|r| r.0 < *t - 0.5) else {
            continue;
        };
        if st & 0x20 != 0 && *t > 5.0 {
            let expected = r.1.min(1500.0 / v);
            assert!(
                close(*amps, expected, 0.4),
                "{amps} A for {} A at {v} V at {t} s",
                r.1
            );
            checked += 1;
        }
    }
    assert!(checked > 1000, "{checked}");
    assert!(
        requests.iter().any(|r| r.1 < 5.0 && r.1 > 1.0),
        "the request tapers"
    );
    // The end: 6000h not ready, the charger off.
    assert_eq!(battery_status(&s).last().unwrap().1 & 1, 0);
    let last = status.last().unwrap();
    assert_eq!((last.1, last.2 & 0x20), (0.0, 0));
    assert!(s.pack.soc() > 0.97);
    assert!(emcys(&s).is_empty());
}

#[test]
fn terminate_via_6000h_stops_the_charge_for_good() {
    let s = run(Scenario::Terminate6000h);
    let off = battery_status(&s).iter().find(|b| b.1 & 1 == 0).unwrap().0;
    assert!(close(off, 1200.0, 1.0), "{off}");
    for (t, amps, st) in charger_status(&s) {
        if t < off - 1.0 && t > 2.0 {
            assert!(close(amps, 25.0, 0.1) && st & 0x20 != 0);
        }
        if t > off + 1.5 {
            assert_eq!((amps, st & 0x20, indication(st)), (0.0, 0, 0), "at {t}");
        }
    }
    assert_eq!(s.phase(), ChargePhase::Terminated);
}

#[test]
fn complete_charge_via_the_float_algorithm() {
    let s = run(Scenario::CompleteFloat);
    let writes = sdo_writes(&s);
    assert_eq!(
        writes.iter().map(|w| (w.1, w.2)).collect::<Vec<_>>(),
        [(0x1803, 0x48A), (0x2241, 3)]
    );
    let at = writes[1].0;
    let after: Vec<_> = charger_status(&s)
        .into_iter()
        .filter(|x| x.0 > at + 1.5)
        .collect();
    assert!(!after.is_empty());
    for (t, amps, st) in after {
        assert_eq!(
            (charge_type(st), indication(st)),
            (2, INDICATION_COMPLETE),
            "at {t}"
        );
        assert!(amps <= 2.5 + 0.01, "float current {amps}");
    }
}

#[test]
fn reduce_current_and_voltage() {
    let s = run(Scenario::ReduceCurrentVoltage);
    let writes = sdo_writes(&s);
    let (at, index, q10) = *writes.last().unwrap();
    assert_eq!(index, 0x2271);
    let lowered_mv = (u64::from(q10) * 1000 + 512) / 1024;
    assert!(close(lowered_mv as f64, 56_800.0, 1.0), "{lowered_mv}");
    assert_eq!(
        u64::from(s.charger().unwrap().set_points().voltage_mv),
        lowered_mv,
        "the set point follows 2271h"
    );
    for (t, amps, _) in charger_status(&s) {
        if t > at + 2.0 {
            assert!(close(amps, 10.0, 0.1), "{amps} A at {t}");
        } else if t > 5.0 && t < at - 1.0 {
            assert!(close(amps, 25.0, 0.1), "{amps} A at {t}");
        }
    }
    assert!(requests(&s).last().unwrap().1 == 10.0);
}

#[test]
fn bms_lost_before_the_charge_starts_then_the_hold_off_charges() {
    let s = run(Scenario::BmsLostBefore);
    // The heartbeat is lost 2 s after the module's last one (at 5 s),
    // and with the 2000 ms consumer time the module is gone then too.
    let e = emcys(&s);
    assert_eq!(e.len(), 2, "{e:?}");
    assert!(
        close(e[0].0, 7.0, 0.01) && e[0].1 == 0x8130 && e[0].2 == E_0_3_2,
        "{e:?}"
    );
    assert!(
        close(e[1].0, 7.0, 0.01) && e[1].1 == 0x8130 && e[1].2 == E_0_3_0,
        "{e:?}"
    );
    // The charger left operational: its heartbeat says pre-operational.
    assert_eq!(frames(&s, 0x70A).last().unwrap().data, [0x7F]);
    // Not ready: no charge while it was there; then the no-CAN algorithm.
    let r = s.result();
    let bulk = r
        .phases
        .iter()
        .find(|p| p.1 == ChargePhase::Bulk)
        .unwrap()
        .0;
    assert_eq!(
        bulk,
        Timestamp::from_millis(17_000),
        "7 s + the 10 s hold-off"
    );
    assert!(close(s.stage.current_a, 25.0, 0.01));
    assert!(s.result().ah > 3.9);
}

#[test]
fn bms_lost_during_a_remote_charge_stops_it_with_e_0_3_2() {
    let s = run(Scenario::BmsLostDuring);
    let e = emcys(&s);
    assert_eq!(
        e.iter().map(|x| x.2).collect::<Vec<_>>(),
        [E_0_3_2, E_0_3_0]
    );
    assert!(close(e[0].0, 602.0, 0.01) && close(e[1].0, 602.0, 0.01));
    let status = charger_status(&s);
    assert!(
        close(status.last().unwrap().1, 25.0, 0.1),
        "charging until the loss"
    );
    assert!(status.last().unwrap().0 < 602.5, "TPDOs stop at the loss");
    assert_eq!(s.stage.current_a, 0.0);
    assert_eq!(s.phase(), ChargePhase::Idle);
}

#[test]
fn bms_lost_during_a_local_charge_carries_on() {
    let options = ScenarioOptions {
        mode: Some(OperatingMode::Local),
        ..ScenarioOptions::default()
    };
    let s = run_with(Scenario::BmsLostDuring, &options);
    assert_eq!(
        emcys(&s).iter().map(|x| x.2).collect::<Vec<_>>(),
        [E_0_3_2, E_0_3_0]
    );
    // Pre-operational, so no TPDOs, but the local charge goes on.
    assert_eq!(frames(&s, 0x70A).last().unwrap().data, [0x7F]);
    assert_eq!(s.phase(), ChargePhase::Bulk);
    assert!(close(s.stage.current_a, 25.0, 0.01));
}

#[test]
fn can_bus_error_stops_a_remote_charge_while_it_lasts() {
    // The bus is off for a minute from 5 min after the start (at 20 ms):
    // nothing reaches it, the charger's
    // controller goes bus-off at its first frame in the window (E-0-2-9,
    // whose EMCY is lost with the rest) and recovers 128 x 11 bits at
    // 125 kbit/s after the bus is back.
    let s = run(Scenario::CanBusError);
    let at = |l: &canopen_codec::sim::Logged| l.at.as_micros() as f64 / 1e6;
    let inside: Vec<_> = s
        .log()
        .iter()
        .filter(|l| (300.021..360.02).contains(&at(l)))
        .collect();
    assert!(inside.is_empty(), "{inside:?}");
    let bus_error: Vec<(f64, bool)> = s
        .alarm_changes()
        .iter()
        .filter(|c| c.code == DeltaQCode::CAN_BUS_COMMUNICATION)
        .map(|c| (c.at.as_micros() as f64 / 1e6, c.raised))
        .collect();
    assert_eq!(bus_error.len(), 2, "{bus_error:?}");
    assert!(bus_error[0].1 && (300.0..301.0).contains(&bus_error[0].0));
    assert!(!bus_error[1].1 && close(bus_error[1].0, 360.031_264, 1e-6));
    // No EMCY got out during the window; the error reset once every
    // alarm has cleared after it.
    let e = emcys(&s);
    assert!(e.iter().all(|x| !(300.021..360.02).contains(&x.0)), "{e:?}");
    assert!(e.iter().any(|x| x.0 > 360.0 && x.1 == 0), "{e:?}");
    let status = charger_status(&s);
    // The first status after the window shows the output stopped, and the
    // charge back at 25 A once the BMS is configured again.
    let after: Vec<_> = status.iter().filter(|x| x.0 > 360.0).collect();
    assert_eq!(after.first().map(|x| x.1), Some(0.0), "{after:?}");
    for (t, amps, st) in status {
        if t > 365.0 || (t < 299.5 && t > 5.0) {
            assert!(close(amps, 25.0, 0.1), "{amps} A at {t}");
            assert_eq!(st & 0x02, 0);
        }
    }
}

#[test]
fn never_can_local_charges_on_its_own_algorithm() {
    let s = run(Scenario::NeverCan);
    assert!(s
        .log()
        .iter()
        .all(|l| l.frame.id().raw() == 0x70A || l.frame.id().raw() == 0));
    let r = s.result();
    assert_eq!(r.phases[1], (Timestamp::ZERO, ChargePhase::HoldOff));
    assert_eq!(
        r.phases[2],
        (Timestamp::from_millis(10_000), ChargePhase::Bulk)
    );
    assert!(r.end_soc > 0.98 && matches!(s.phase(), ChargePhase::Float));
    assert!(r.errors.is_empty());
}

#[test]
fn never_can_remote_never_charges() {
    let options = ScenarioOptions {
        mode: Some(OperatingMode::Remote),
        ..ScenarioOptions::default()
    };
    let s = run_with(Scenario::NeverCan, &options);
    assert_eq!(s.result().ah, 0.0);
    assert_eq!(s.phase(), ChargePhase::Idle);
}

#[test]
fn change_algorithm_mid_charge() {
    let s = run(Scenario::ChangeAlgorithm);
    let at = sdo_writes(&s).iter().find(|w| w.1 == 0x2241).unwrap().0;
    assert_eq!(sdo_writes(&s).last().unwrap().2, 2);
    for (t, amps, st) in charger_status(&s) {
        if t > at + 1.5 {
            assert!(close(amps, 12.0, 0.1), "{amps} at {t}");
            assert_eq!(indication(st), INDICATION_BELOW_80);
        } else if t > 5.0 && t < at - 0.5 {
            assert!(close(amps, 25.0, 0.1), "{amps} at {t}");
        }
    }
}

#[test]
fn ah_target_completes_the_charge() {
    let s = run(Scenario::AhTarget);
    assert!(sdo_writes(&s)
        .iter()
        .any(|w| (w.1, w.2 & 0xFFFF) == (0x2250, 160)));
    let rest = charger_status(&s)
        .into_iter()
        .find(|x| indication(x.2) == INDICATION_RESTING)
        .expect("resting");
    let tpdo2 = frames(&s, 0x401);
    let at_rest = tpdo2.iter().rfind(|f| f.t <= rest.0).unwrap();
    let ah = f64::from(u16_at(&at_rest.data, 1)) / 8.0;
    assert!((20.0..20.5).contains(&ah), "6052h {ah} Ah at rest");
    assert!(close(s.result().ah, 20.0, 0.6));
    assert_eq!(s.phase(), ChargePhase::Float);
}

#[test]
fn communication_restored_reconfigures_and_resumes() {
    let s = run(Scenario::CommunicationRestored);
    let e = emcys(&s);
    assert_eq!(e.len(), 3, "{e:?}");
    assert!(close(e[0].0, 302.0, 0.01) && e[0].2 == E_0_3_2);
    assert!(close(e[1].0, 302.0, 0.01) && e[1].2 == E_0_3_0);
    assert!(
        e[2].1 == 0 && e[2].0 > 330.0 && e[2].0 < 331.1,
        "error reset on reconfiguration"
    );
    // Gone, the charger left operational; the BMS started it again at
    // its first pre-operational heartbeat after the module came back.
    let states: Vec<(f64, u8)> = frames(&s, 0x70A).iter().map(|f| (f.t, f.data[0])).collect();
    assert!(
        states
            .iter()
            .any(|&(t, st)| t > 302.0 && t < 331.0 && st == 0x7F),
        "{states:?}"
    );
    assert_eq!(states.last().unwrap().1, 0x05);
    let starts: Vec<f64> = frames(&s, 0x000)
        .iter()
        .filter(|f| f.data == [0x01, 0x0A])
        .map(|f| f.t)
        .collect();
    assert!(starts.iter().any(|&t| t > 330.0 && t < 332.0), "{starts:?}");
    // The charger read the module's device type again when it came back.
    let reads: Vec<f64> = frames(&s, 0x601)
        .iter()
        .filter(|f| f.data[..4] == [0x40, 0x00, 0x10, 0x00])
        .map(|f| f.t)
        .collect();
    assert_eq!(reads.len(), 2);
    assert!(reads[1] > 330.0);
    let last = *charger_status(&s).last().unwrap();
    assert!(close(last.1, 25.0, 0.1) && last.0 > 625.0);
}

#[test]
fn battery_unplugged_with_can_connected() {
    let s = run(Scenario::BatteryUnplugged);
    let e = emcys(&s);
    assert_eq!(e[0].2, E_0_4_5, "{e:?}");
    assert!(
        e.iter().any(|x| x.1 == 0 && close(x.0, 120.0, 0.05)),
        "cleared at plug-in: {e:?}"
    );
    for (t, amps, st) in charger_status(&s) {
        if t < 119.9 {
            assert_eq!(amps, 0.0);
        }
        if t > 1.0 && t < 119.9 {
            assert_ne!(st & 0x02, 0, "alarm bit at {t}");
        }
        if t > 121.0 {
            assert!(close(amps, 25.0, 0.1));
        }
    }
}

#[test]
fn restart_charge_via_2241h_after_float() {
    let s = run(Scenario::RestartCharge);
    let at = sdo_writes(&s).last().unwrap().0;
    let status = charger_status(&s);
    let before = status.iter().rfind(|x| x.0 < at).unwrap();
    assert_eq!(charge_type(before.2), 2, "floating before");
    let after: Vec<_> = status.iter().filter(|x| x.0 > at + 1.5).collect();
    assert_eq!(charge_type(after[0].2), 1, "a new normal cycle");
    assert!(matches!(
        indication(after[0].2),
        INDICATION_ABOVE_80 | INDICATION_FINISHING
    ));
    // 6052h starts again from zero.
    let ah_after = frames(&s, 0x401)
        .into_iter()
        .find(|f| f.t > at + 0.5)
        .map(|f| u16_at(&f.data, 1))
        .unwrap();
    assert!(ah_after < 8, "{ah_after}");
}

#[test]
fn every_scenario_has_a_name_and_lithium_runs_too() {
    for s in Scenario::ALL {
        assert_eq!(Scenario::from_name(s.name()), Some(s));
    }
    let options = ScenarioOptions {
        chemistry: canopen_codec::cia418::Chemistry::LithiumIon,
        capacity_ah: 40.0,
        soc: 0.5,
        ..ScenarioOptions::default()
    };
    let s = run_with(Scenario::NormalLocal, &options);
    // Lithium ion completes without float (algorithm 11).
    assert_eq!(s.phase(), ChargePhase::Complete);
    assert!(s.pack.soc() > 0.9);
}

/// `canopen-decode --summary-only --check` on the session's log: no bad
/// line, and an open problem exactly where the session leaves one (a
/// module lost for good: its silence and the charger's E-0-3-2).
#[cfg(feature = "cli")]
fn decoder_check(scenario: Scenario, s: &Session) {
    use std::fmt::Write as _;
    let mut text = String::new();
    for line in s.candump("vcan0") {
        let _ = writeln!(text, "{line}");
    }
    let dir = std::env::temp_dir().join(format!("charge-sessions-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!(
        "{}-{:?}.log",
        scenario,
        s.charger().unwrap().charge_control().mode()
    ));
    std::fs::write(&path, text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_canopen-decode"))
        .args(["--summary-only", "--check"])
        .arg(&path)
        .output()
        .unwrap();
    let summary = String::from_utf8_lossy(&out.stdout);
    let lost_for_good = matches!(scenario, Scenario::BmsLostBefore | Scenario::BmsLostDuring);
    let expected = if lost_for_good { Some(3) } else { Some(0) };
    assert_eq!(out.status.code(), expected, "{scenario}: {summary}");
    assert!(!summary.contains("bad line"), "{summary}");
    assert!(!summary.contains("aborted: 1"), "{summary}");
    if lost_for_good {
        assert!(summary.contains("until the end of the log"), "{summary}");
        assert!(summary.contains("8130h life guard error or heartbeat error (not cleared)"));
    }
    let _ = std::fs::remove_file(&path);
}
