//! Unit tests of the charger session (charger.rs).

use super::*;
use crate::frame::{CanFrame, CanId};
use crate::pdo::{PdoCobId, PdoSlot};
use core::mem::MaybeUninit;
use std::string::{String, ToString};
use std::vec::Vec;

#[test]
fn alarms_carry_the_eec_of_their_table_row() {
    for code in [
        DeltaQCode::BATTERY_MODULE_COMMUNICATION,
        DeltaQCode::HEARTBEAT_LOST,
        DeltaQCode::CAN_CONFIGURATION,
    ] {
        let Alarm(c, eec) = Alarm::of(code);
        assert_eq!(c, code);
        assert_eq!(Some(eec), code.entry().map(|e| e.eec), "{code}");
    }
    // E-0-3-2 is 8130h (heartbeat error), as the real capture shows.
    assert_eq!(Alarm::of(DeltaQCode::HEARTBEAT_LOST).1, ErrorCode(0x8130));
    // A code without a row: the generic EEC.
    let unlisted = DeltaQCode::alarm(0, 5).unwrap();
    assert_eq!(unlisted.entry(), None);
    assert_eq!(Alarm::of(unlisted).1, ErrorCode::GENERIC);
}

/// Everything a charger sends and reports from boot through a whole
/// configuration (1000h of a module with every optional PDO, every COB-ID
/// read), the module's loss and its return.
fn transcript(c: &mut Charger<4>) -> Vec<String> {
    let mut out = Vec::new();
    let drain = |c: &mut Charger<4>, out: &mut Vec<String>| {
        while let Some(f) = c.poll_transmit() {
            out.push(f.to_string());
        }
        while let Some(e) = c.poll_event() {
            out.push(std::format!("{e:?}"));
        }
        out.push(std::format!("timeout {:?}", c.poll_timeout()));
    };
    let ms = Timestamp::from_millis;
    let frame = |id: u16, data: &[u8]| CanFrame::standard(id, data).unwrap();
    c.boot(ms(0));
    drain(c, &mut out);
    c.handle_frame(ms(1), &frame(0x000, &[0x01, 0x0C]));
    drain(c, &mut out);
    c.handle_frame(ms(2), &frame(0x701, &[0x05]));
    drain(c, &mut out);
    // 1000h: profile 418 with RPDO 1/2, TPDO 1/2 and Delta-Q's bit 20.
    let device_type = 418u32 | 0x1F << 16;
    let [a, b, c2, d] = device_type.to_le_bytes();
    c.handle_frame(ms(3), &frame(0x581, &[0x43, 0x00, 0x10, 0, a, b, c2, d]));
    drain(c, &mut out);
    for at in 4..12u16 {
        let Some(request) = out.iter().rev().find(|l| l.starts_with("601#40")).cloned() else {
            break;
        };
        let bytes: Vec<u8> = (0..8)
            .map(|i| u8::from_str_radix(&request[4 + 2 * i..6 + 2 * i], 16).unwrap())
            .collect();
        let cob = 0x180 + u32::from(at);
        let [w, x, y, z] = cob.to_le_bytes();
        c.handle_frame(
            ms(u64::from(at)),
            &frame(0x581, &[0x43, bytes[1], bytes[2], bytes[3], w, x, y, z]),
        );
        drain(c, &mut out);
        if c.is_configured() {
            break;
        }
    }
    for t in [250, 1_000] {
        c.handle_timeout(ms(t));
        drain(c, &mut out);
    }
    // The module is lost, then heard again.
    c.handle_timeout(ms(5_000));
    drain(c, &mut out);
    c.handle_frame(ms(5_001), &frame(0x701, &[0x00]));
    drain(c, &mut out);
    out
}

#[test]
fn new_in_builds_what_new_builds() {
    let mut config = ChargerConfig::new(NodeId::new(12).unwrap(), NodeId::MIN);
    config.device_name = "DQ-12";
    config.tpdo_periods = [150, 250, 350, 1200].map(core::time::Duration::from_millis);
    let mut slot = MaybeUninit::<Charger<4>>::uninit();
    let built_in = Charger::new_in(&mut slot, config);
    let mut built = Charger::<4>::with_queue_capacity(config);
    assert_eq!(built_in.config(), built.config());
    assert_eq!(built_in.comm(), built.comm());
    assert_eq!(built_in.comm().device_name, "DQ-12");
    assert_eq!(built_in.comm().heartbeat_ms, 1000);
    assert_eq!(built_in.pdo_config(), built.pdo_config());
    assert_eq!(built_in.objects().objects(), built.objects().objects());
    assert_eq!(built_in.nmt_state(), built.nmt_state());
    assert_eq!(built_in.poll_timeout(), built.poll_timeout());
    let expected = transcript(&mut built);
    assert_eq!(expected.first().map(String::as_str), Some("70C#00"));
    for seen in [
        "Configured { tpdos: 15, rpdos: 7 }",
        "70C#05",
        "BatteryLost",
    ] {
        assert!(expected.iter().any(|l| l == seen), "{seen}: {expected:?}");
    }
    // The TPDOs run on the paired COB-IDs.
    assert!(
        expected.iter().any(|l| l.starts_with("184#")),
        "{expected:?}"
    );
    assert_eq!(transcript(built_in), expected);
}

#[test]
fn the_device_name_is_written_once_and_kept_by_both_resets() {
    let mut config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::MIN);
    config.device_name = "DQ-10";
    let mut c = Charger::<4>::with_queue_capacity(config);
    assert_eq!(
        c.config(),
        ChargerPowerOn::from(config).config(c.comm(), config.charge)
    );
    c.boot(Timestamp::ZERO);
    for (at, cs) in [(1, 0x81), (2, 0x82)] {
        c.handle_frame(
            Timestamp::from_millis(at),
            &CanFrame::standard(0x000, &[cs, 0x0A]).unwrap(),
        );
        assert_eq!(c.comm().device_name, "DQ-10");
        assert_eq!(c.config().device_name, "DQ-10");
    }
    // The core's configuration has it too.
    assert_eq!(config.device_config().device_name, "DQ-10");
}

#[test]
fn the_kept_times_are_the_crates_whole_milliseconds() {
    use crate::clock::{millis_u16, millis_u32};
    use core::time::Duration;
    for d in [
        Duration::ZERO,
        Duration::from_micros(999),
        Duration::from_micros(1_500_700),
        Duration::from_millis(65_535),
        Duration::from_millis(65_536),
        Duration::from_millis(u64::from(u32::MAX) + 1),
        Duration::MAX,
    ] {
        let mut config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::MIN);
        config.heartbeat = d;
        config.battery_timeout = d;
        config.tpdo_periods = [d; 4];
        config.sdo_timeout = d;
        let kept = ChargerPowerOn::from(config);
        let ms = millis_u16(d);
        assert_eq!(
            (
                kept.heartbeat_ms,
                kept.battery_timeout_ms,
                kept.tpdo_periods_ms
            ),
            (ms, ms, [ms; 4]),
            "{d:?}"
        );
        assert_eq!(kept.sdo_timeout_ms, millis_u32(d), "{d:?}");
    }
}

/// The default PDO set a reset writes is every published row of the
/// Delta-Q table, as `PdoSlot::new` makes it from the row's mapping (the
/// compact table is the rows'), with the configured periods; RPDO 3 has
/// none.
#[test]
fn the_default_pdos_are_the_tables_rows() {
    use crate::deltaq::CHARGER_DEFAULT_PDOS;
    use crate::pdo::{PdoCommParams, PdoConfig};
    for configure_cob_ids in [true, false] {
        let mut config = ChargerConfig::new(NodeId::new(12).unwrap(), NodeId::MIN);
        config.configure_cob_ids = configure_cob_ids;
        config.tpdo_periods = [150, 250, 350, 1200].map(core::time::Duration::from_millis);
        let kept = ChargerPowerOn::from(config);
        let mut pdos = PdoConfig::<4, 4>::new();
        config::default_pdos(&kept, &mut pdos);
        for d in &CHARGER_DEFAULT_PDOS {
            let want = d.mapping().map(|mapping| {
                let cob = PdoCobId::from_u32(d.cob_id(config.node)).with_valid(!configure_cob_ids);
                let period = match d.direction {
                    PdoDirection::Transmit => kept.tpdo_periods_ms[usize::from(d.number.raw())],
                    PdoDirection::Receive => 0,
                };
                PdoSlot::new(PdoCommParams::event_driven(cob, period), &mapping)
            });
            assert_eq!(pdos.get(d.direction, d.number), want.as_ref(), "{d:?}");
        }
        assert_eq!(
            pdos.get(PdoDirection::Receive, PdoNumber::P3),
            None,
            "RPDO 3 is not published"
        );
    }
}

/// The module's EMCY is a data frame on 080h + its node: a remote frame
/// or an extended frame on that identifier reports nothing.
#[test]
fn only_a_data_frame_on_the_modules_emcy_identifier_is_its_emcy() {
    let config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::new(1).unwrap());
    let mut c = Charger::<4>::with_queue_capacity(config);
    let ms = Timestamp::from_millis;
    c.boot(ms(0));
    let emcy = [0x10, 0x50, 0x21, 0, 0, 0, 0, 0];
    let ignored = [
        CanFrame::remote(CanId::Standard(0x081), 8).unwrap(),
        CanFrame::new(CanId::Extended(0x081), &emcy).unwrap(),
        CanFrame::standard(0x082, &emcy).unwrap(),
    ];
    for frame in ignored {
        c.handle_frame(ms(1), &frame);
        while let Some(e) = c.poll_event() {
            assert!(!matches!(e, ChargerEvent::BatteryEmcy { .. }), "{frame:?}");
        }
    }
    c.handle_frame(ms(2), &CanFrame::standard(0x081, &emcy).unwrap());
    let mut reported = 0;
    while let Some(e) = c.poll_event() {
        if let ChargerEvent::BatteryEmcy { emcy, .. } = e {
            assert_eq!(emcy.code, ErrorCode(0x5010));
            reported += 1;
        }
    }
    assert_eq!(reported, 1);
}

/// The frames `c` sends, as candump strings.
fn sent(c: &mut Charger<4>) -> Vec<String> {
    core::iter::from_fn(|| c.poll_transmit())
        .map(|f| f.to_string())
        .collect()
}

/// Runs `c`'s timers up to `until`, one call per due deadline (as the
/// firmware's loop does); returns what it sent, each with its time in ms.
fn run_timers(c: &mut Charger<4>, until: Timestamp) -> Vec<(u64, String)> {
    let mut out = Vec::new();
    while let Some(due) = c.poll_timeout().filter(|t| *t <= until) {
        c.handle_timeout(due);
        out.extend(sent(c).into_iter().map(|f| (due.as_micros() / 1000, f)));
    }
    out
}

/// The battery module's (node 1) operational heartbeat.
fn battery_heartbeat() -> CanFrame {
    CanFrame::standard(0x701, &[0x05]).unwrap()
}

/// A charger on its default COB-IDs (as in the capture), booted; the
/// master starts it unless it starts itself.
fn booted(self_start: bool, battery_timeout_ms: u64) -> Charger<4> {
    let mut config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::MIN);
    config.configure_cob_ids = false;
    config.self_start = self_start;
    config.battery_timeout = core::time::Duration::from_millis(battery_timeout_ms);
    let mut c = Charger::<4>::with_queue_capacity(config);
    c.boot(Timestamp::ZERO);
    if !self_start {
        let start = CanFrame::standard(0x000, &[0x01, 0x0A]).unwrap();
        c.handle_frame(Timestamp::ZERO, &start);
    }
    assert_eq!(c.nmt_state(), NmtState::Operational);
    c
}

/// A self-starting charger whose module was heard at 100 ms only: gone
/// at 2100 ms, it left operational.
fn self_started_then_gone() -> Charger<4> {
    let mut c = booted(true, 2000);
    c.handle_frame(Timestamp::from_millis(100), &battery_heartbeat());
    run_timers(&mut c, Timestamp::from_millis(2200));
    assert_eq!(c.nmt_state(), NmtState::PreOperational, "gone at 2100 ms");
    c
}

#[test]
fn a_lost_module_is_gone_2000_ms_after_its_last_heartbeat() {
    // The capture's charger: 340 ms battery consumer time, default COB-IDs,
    // started by the BMS. E-0-3-2 342 ms and E-0-3-0 2014 ms after the
    // last battery heartbeat there; here 340 ms and 2000 ms.
    let mut c = booted(false, 340);
    let heartbeat = battery_heartbeat();
    for t in (100..=1000).step_by(100) {
        run_timers(&mut c, Timestamp::from_millis(t));
        c.handle_frame(Timestamp::from_millis(t), &heartbeat);
    }
    assert_eq!(c.nmt_state(), NmtState::Operational);
    while c.poll_event().is_some() {}
    let emcys: Vec<(u64, String)> = run_timers(&mut c, Timestamp::from_millis(4000))
        .into_iter()
        .filter(|(_, f)| f.starts_with("08A#"))
        .collect();
    assert_eq!(
        emcys,
        [
            (1340, "08A#3081012080000000".to_string()),
            (3000, "08A#3081011E80000000".to_string()),
        ]
    );
    assert_eq!(c.nmt_state(), NmtState::PreOperational);
    let events: Vec<ChargerEvent> = core::iter::from_fn(|| c.poll_event()).collect();
    assert_eq!(
        events,
        [
            ChargerEvent::BatteryLost,
            ChargerEvent::BatteryGone,
            ChargerEvent::Device(DeviceEvent::NmtStateChanged {
                from: NmtState::Operational,
                to: NmtState::PreOperational,
            }),
        ]
    );
    // Back before it is gone: no E-0-3-0, still operational.
    let mut c = booted(false, 340);
    c.handle_frame(Timestamp::from_millis(100), &heartbeat);
    let lost = run_timers(&mut c, Timestamp::from_millis(1500));
    assert!(
        lost.iter()
            .any(|(t, f)| *t == 440 && f == "08A#3081012080000000"),
        "{lost:?}"
    );
    let mut after = Vec::new();
    for t in (1500..=5000).step_by(100) {
        after.extend(run_timers(&mut c, Timestamp::from_millis(t)));
        c.handle_frame(Timestamp::from_millis(t), &heartbeat);
        after.extend(sent(&mut c).into_iter().map(|f| (t, f)));
    }
    assert!(
        after.contains(&(1500, "08A#0000000000000000".to_string())),
        "{after:?}"
    );
    assert!(
        !after.iter().any(|(_, f)| f.starts_with("08A#30810")),
        "{after:?}"
    );
    assert_eq!(c.nmt_state(), NmtState::Operational);
}

#[test]
fn a_self_starting_charger_starts_again_when_the_module_is_back() {
    let mut c = self_started_then_gone();
    c.handle_frame(Timestamp::from_millis(3000), &battery_heartbeat());
    assert_eq!(c.nmt_state(), NmtState::Operational);
    assert!(c.is_configured());
}

#[test]
fn a_self_starting_charger_keeps_the_masters_word_after_a_gone_module() {
    let mut c = self_started_then_gone();
    // The master starts it, then sends it to pre-operational: the module's
    // return leaves it there.
    for (t, cmd) in [(2300, 0x01), (2400, 0x80)] {
        c.handle_frame(
            Timestamp::from_millis(t),
            &CanFrame::standard(0x000, &[cmd, 0x0A]).unwrap(),
        );
    }
    assert_eq!(c.nmt_state(), NmtState::PreOperational);
    c.handle_frame(Timestamp::from_millis(3000), &battery_heartbeat());
    assert_eq!(c.nmt_state(), NmtState::PreOperational);
    assert!(c.is_configured());
}

#[test]
fn the_module_gone_timer_is_the_profiles_deadline_until_the_module_is_back() {
    let ms = Timestamp::from_millis;
    let own = |c: &Charger<4>| Profile::<ChargerProfile, 4, 4, 3>::poll_timeout(c.profile());
    let mut c = booted(false, 340);
    c.handle_frame(ms(100), &battery_heartbeat());
    // No timer of the profile's runs (idle client, no charge).
    assert_eq!(own(&c), None);
    while c.poll_event().is_some() {}
    c.handle_timeout(ms(440));
    assert_eq!(c.poll_event(), Some(ChargerEvent::BatteryLost));
    // Gone 2000 ms after the last heartbeat: the profile's one deadline,
    // and not run before it.
    assert_eq!(own(&c), Some(ms(2100)));
    c.handle_timeout(Timestamp::from_micros(2_099_999));
    assert!(!sent(&mut c).iter().any(|f| f.starts_with("08A#3081011E")));
    assert_eq!(own(&c), Some(ms(2100)));
    // Back before it: the timer is stopped.
    c.handle_frame(ms(2000), &battery_heartbeat());
    assert_eq!(own(&c), None);
    c.handle_timeout(ms(2100));
    assert!(!sent(&mut c).iter().any(|f| f.starts_with("08A#3081011E")));
    assert_eq!(c.nmt_state(), NmtState::Operational);
}

#[test]
fn protections_go_out_as_delta_q_emcys_with_their_1003h_and_2060h_entries() {
    use crate::deltaq::charge::StageFaults;
    use crate::deltaq::ChargeStatusFlags;
    let ms = Timestamp::from_millis;
    let on = PowerStage {
        ac_mv: 230_000,
        voltage_mv: 48_000,
        ..PowerStage::OFF
    };
    // What the stage measures, the EMCY (EEC, error register 01h, the
    // Delta-Q code little-endian) and the 1003h / 2060h entry, as the
    // alarm table of the Delta-Q IC Series CANopen interface specification,
    // section 4.4.1, gives them (E-0-2-3 17809000h,
    // E-0-1-2 0C809000h, F-0-0-5 05C05000h).
    let cases = [
        (
            PowerStage {
                ac_mv: 275_000,
                ..on
            },
            "08A#0090011780000000",
            0x1780_9000_u32,
            ChargeStatusFlags::ALARM_ACTIVE,
        ),
        (
            PowerStage {
                voltage_mv: -48_000,
                ..on
            },
            "08A#0090010C80000000",
            0x0C80_9000,
            ChargeStatusFlags::ALARM_ACTIVE,
        ),
        (
            PowerStage {
                faults: StageFaults::RELAY,
                ..on
            },
            "08A#00500105C0000000",
            0x05C0_5000,
            ChargeStatusFlags::FAULT_ACTIVE,
        ),
    ];
    for (stage, frame, entry, flag) in cases {
        let mut c = booted(false, 2000);
        c.handle_power_stage(ms(10), on);
        let _ = sent(&mut c);
        c.handle_power_stage(ms(20), stage);
        assert_eq!(sent(&mut c), [frame]);
        assert_eq!(c.comm().errors().first(), Some(&entry), "{frame}");
        assert_eq!(c.objects().displayed_error, entry, "{frame}");
        let status = c.objects().extended_status;
        let want = u16::from((flag | ChargeStatusFlags::HW_SHUTDOWN).bits());
        assert_eq!(status & want, want, "{frame}: {status:04X}");
        c.handle_power_stage(ms(30), on);
        assert_eq!(c.objects().displayed_error, 0, "{frame}: cleared");
        assert_eq!(c.objects().extended_status & 0x07, 0, "{frame}");
    }
}
