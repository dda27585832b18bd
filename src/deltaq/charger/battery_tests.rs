//! The charger reads the module's 6020h and charges with the algorithm
//! for its battery (battery.rs).

use super::*;
use crate::deltaq::charge::algorithm::{select, EXAMPLE_ALGORITHMS};
use crate::deltaq::charge::{ChargePhase, PowerStage};
use std::string::{String, ToString};
use std::vec::Vec;

const fn ms(n: u64) -> Timestamp {
    Timestamp::from_millis(n)
}

fn frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::standard(id, data).unwrap()
}

/// The SDO requests to the module the charger sent and what it reported
/// since the last call.
fn drain(c: &mut Charger<8>) -> (Vec<String>, Vec<ChargerEvent>) {
    let frames = core::iter::from_fn(|| c.poll_transmit())
        .map(|f| f.to_string())
        .filter(|f| f.starts_with("601#") || f.starts_with("58A#"))
        .collect();
    (frames, core::iter::from_fn(|| c.poll_event()).collect())
}

/// A local-mode charger (no COB-ID configuration, self-starting) with
/// `permanent` as its permanent algorithm and algorithm 2 (flooded, 12 A)
/// as its no-CAN default; AC on and a 48 V battery on its output, the
/// module's RPDO 0 saying ready (6000h = 1) at 25 degC.
fn charger(permanent: Option<u16>) -> Charger<8> {
    let mut config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::MIN);
    config.configure_cob_ids = false;
    config.self_start = true;
    config.charge.permanent_algorithm = permanent;
    config.charge.no_can_algorithm = Some(2);
    let mut c = Charger::<8>::with_queue_capacity(config);
    c.boot(ms(0));
    let stage = PowerStage {
        ac_mv: PowerStage::AC_NOMINAL_MV,
        voltage_mv: 48_000,
        ..PowerStage::OFF
    };
    c.handle_power_stage(ms(1), stage);
    c.handle_frame(ms(2), &frame(0x20A, &[200, 0, 1]));
    let _ = drain(&mut c);
    c
}

/// A charger without a permanent algorithm that found the module (its
/// heartbeat at 10 ms) and asked for 6020h sub 1.
fn asked() -> Charger<8> {
    let mut c = charger(None);
    c.handle_frame(ms(10), &frame(0x701, &[0x05]));
    let _ = drain(&mut c);
    c
}

/// The module's answer to the charger's upload of 6020h `sub`: `value`
/// (1 or 2 bytes, expedited).
fn answer(c: &mut Charger<8>, at: u64, sub: u8, value: &[u8]) -> (Vec<String>, Vec<ChargerEvent>) {
    let cs = if value.len() == 1 { 0x4F } else { 0x4B };
    let mut data = [cs, 0x20, 0x60, sub, 0, 0, 0, 0];
    for (d, v) in data[4..].iter_mut().zip(value) {
        *d = *v;
    }
    c.handle_frame(ms(at), &frame(0x581, &data));
    drain(c)
}

/// The upload request of 6020h `sub`, as the charger sends it.
fn request(sub: u8) -> String {
    std::format!("601#402060{sub:02X}00000000")
}

#[test]
fn the_charger_charges_with_the_algorithm_for_the_modules_battery() {
    // Flooded lead acid 24 cells, lithium ion 13 cells, NiCd 40 cells.
    for (battery_type, cells, ah) in [(0x10u8, 24u16, 200u16), (0xA0, 13, 100), (0x20, 40, 150)] {
        let mut c = charger(None);
        // The module's first heartbeat: the charger asks for 6020h sub 1
        // and charges nothing meanwhile.
        c.handle_frame(ms(10), &frame(0x701, &[0x05]));
        let (frames, _) = drain(&mut c);
        assert_eq!(frames, [request(1)], "{battery_type:02X}h");
        assert_eq!(c.charge_control().phase(), ChargePhase::Idle);
        assert!(!c.set_points().enabled);
        let (frames, _) = answer(&mut c, 11, 1, &[battery_type]);
        assert_eq!(frames, [request(2)]);
        let (frames, _) = answer(&mut c, 12, 2, &ah.to_le_bytes());
        assert_eq!(frames, [request(4)]);
        let (_, events) = answer(&mut c, 13, 4, &cells.to_le_bytes());
        let chosen = select(&EXAMPLE_ALGORITHMS, battery_type, cells).unwrap();
        let battery = BatteryIdentity {
            battery_type,
            capacity_ah: ah,
            cells,
        };
        assert!(
            events.contains(&ChargerEvent::BatteryIdentified {
                battery,
                algorithm: Some(chosen.id)
            }),
            "{events:?}"
        );
        assert_eq!(c.charge_control().active_algorithm(), Some(chosen.id));
        // 2241h reads back the chosen algorithm.
        assert_eq!(
            c.objects().objects().algorithm_request,
            u32::from(chosen.id)
        );
        // The cycle runs with the chosen algorithm's voltage.
        assert_eq!(c.charge_control().phase(), ChargePhase::Bulk);
        assert_eq!(c.set_points().voltage_mv, chosen.absorption_mv);
    }
}

/// The read of sub 1 failed with `code` (reported) and the charger
/// charges with its no-CAN default, algorithm 2, which 2241h reads back.
fn charges_with_the_default_after(c: &Charger<8>, events: &[ChargerEvent], code: AbortCode) {
    let failed = ChargerEvent::IdentificationFailed { sub: 1, code };
    assert!(events.contains(&failed), "{events:?}");
    assert_eq!(c.charge_control().active_algorithm(), Some(2));
    assert_eq!(c.objects().objects().algorithm_request, 2);
    assert_eq!(c.charge_control().phase(), ChargePhase::Bulk);
}

/// The module's heartbeat (operational) at each second from `from` to
/// `to` s, each followed by the charger's timeout 10 ms later; the SDO
/// requests it sent to the module and its events meanwhile.
fn heartbeats(c: &mut Charger<8>, from: u64, to: u64) -> (Vec<String>, Vec<ChargerEvent>) {
    let (mut frames, mut events) = (Vec::new(), Vec::new());
    for t in from..=to {
        c.handle_frame(ms(t * 1_000), &frame(0x701, &[0x05]));
        c.handle_timeout(ms(t * 1_000 + 10));
        let (f, e) = drain(c);
        frames.extend(f);
        events.extend(e);
    }
    (frames, events)
}

fn failures(events: &[ChargerEvent]) -> usize {
    events
        .iter()
        .filter(|e| matches!(e, ChargerEvent::IdentificationFailed { .. }))
        .count()
}

#[test]
fn a_module_that_aborts_the_read_leaves_the_default() {
    let mut c = asked();
    // 0602 0000h: the object does not exist.
    c.handle_frame(ms(11), &frame(0x581, &[0x80, 0x20, 0x60, 0x01, 0, 0, 2, 6]));
    let (frames, events) = drain(&mut c);
    assert!(frames.is_empty(), "{frames:?}");
    charges_with_the_default_after(&c, &events, AbortCode::ObjectDoesNotExist);
    // The module said no: it is not asked again while it stays.
    let (frames, events) = heartbeats(&mut c, 1, 20);
    assert!(frames.is_empty(), "{frames:?}");
    assert_eq!(failures(&events), 0);
    assert_eq!(c.charge_control().active_algorithm(), Some(2));
}

#[test]
fn a_module_that_never_answers_times_out_to_the_default() {
    let mut c = asked();
    // The SDO timeout (2000 ms) runs out, the module's heartbeat still
    // heard: the charger aborts the read and asks again, three reads in
    // all (ATTEMPTS), then charges with its default; then no more.
    let (frames, events) = heartbeats(&mut c, 1, 7);
    let abort = "601#8020600100000405";
    assert_eq!(
        frames.iter().filter(|f| *f == abort).count(),
        3,
        "{frames:?}"
    );
    assert_eq!(frames.iter().filter(|f| **f == request(1)).count(), 2);
    assert_eq!(failures(&events), 1, "{events:?}");
    charges_with_the_default_after(&c, &events, AbortCode::SdoProtocolTimedOut);
    let (frames, _) = heartbeats(&mut c, 8, 20);
    assert!(frames.is_empty(), "{frames:?}");
}

#[test]
fn a_read_that_timed_out_is_asked_again_and_the_answer_chooses() {
    let mut c = asked();
    let _ = answer(&mut c, 11, 1, &[0xA0]);
    // Sub 2 is not answered: at its timeout the charger asks for sub 2
    // again (what it has read stands) and holds the start meanwhile.
    let (frames, events) = heartbeats(&mut c, 1, 3);
    assert_eq!(frames, ["601#8020600200000405".to_string(), request(2)]);
    assert_eq!(failures(&events), 0);
    assert_eq!(c.charge_control().phase(), ChargePhase::Idle);
    let (frames, _) = answer(&mut c, 3_100, 2, &100u16.to_le_bytes());
    assert_eq!(frames, [request(4)]);
    let (_, events) = answer(&mut c, 3_101, 4, &13u16.to_le_bytes());
    assert!(
        events.iter().any(|e| matches!(
            e,
            ChargerEvent::BatteryIdentified {
                algorithm: Some(11),
                ..
            }
        )),
        "{events:?}"
    );
    assert_eq!(c.charge_control().phase(), ChargePhase::Bulk);
}

#[test]
fn a_module_found_while_stopped_is_asked_once_the_charger_may_use_sdo() {
    let mut c = charger(None);
    // The NMT master stops the charger (000#020A) and the module is found
    // meanwhile: no SDO in stopped (CiA 301), so the question waits, and
    // so does the ready BMS's start.
    c.handle_frame(ms(5), &frame(0x000, &[0x02, 0x0A]));
    c.handle_frame(ms(10), &frame(0x701, &[0x05]));
    let (frames, events) = heartbeats(&mut c, 1, 5);
    assert!(frames.is_empty(), "{frames:?}");
    assert_eq!(failures(&events), 0, "{events:?}");
    assert_eq!(c.charge_control().phase(), ChargePhase::Idle);
    // Started (000#010A): the read starts.
    c.handle_frame(ms(5_500), &frame(0x000, &[0x01, 0x0A]));
    let (frames, _) = drain(&mut c);
    assert_eq!(frames, [request(1)]);
    // Stopped during the read: it ends silently; pre-operational
    // (000#800A) asks again from the start.
    c.handle_frame(ms(5_600), &frame(0x000, &[0x02, 0x0A]));
    let (frames, _) = drain(&mut c);
    assert!(frames.is_empty(), "{frames:?}");
    c.handle_frame(ms(5_700), &frame(0x000, &[0x80, 0x0A]));
    let (frames, _) = drain(&mut c);
    assert_eq!(frames, [request(1)]);
    let _ = answer(&mut c, 5_701, 1, &[0x20]);
    let _ = answer(&mut c, 5_702, 2, &150u16.to_le_bytes());
    let (_, events) = answer(&mut c, 5_703, 4, &40u16.to_le_bytes());
    assert_eq!(failures(&events), 0);
    assert_eq!(c.charge_control().active_algorithm(), Some(21));
    assert_eq!(c.charge_control().phase(), ChargePhase::Bulk);
}

#[test]
fn without_a_module_the_no_can_default_charges_after_the_hold_off() {
    let mut c = charger(None);
    c.handle_timeout(ms(9_000));
    assert_eq!(c.charge_control().phase(), ChargePhase::HoldOff);
    c.handle_timeout(ms(10_001));
    let (frames, _) = drain(&mut c);
    assert!(frames.is_empty(), "{frames:?}");
    assert_eq!(c.charge_control().phase(), ChargePhase::Bulk);
    assert_eq!(c.charge_control().active_algorithm(), Some(2));
    assert_eq!(c.set_points().current_ma, 12_000);
}

#[test]
fn a_permanent_algorithm_wins_over_the_modules_battery() {
    // Set in the configuration: the charger does not ask.
    let mut c = charger(Some(1));
    c.handle_frame(ms(10), &frame(0x701, &[0x05]));
    let (frames, _) = drain(&mut c);
    assert!(frames.is_empty(), "{frames:?}");
    assert_eq!(c.charge_control().active_algorithm(), Some(1));
    assert_eq!(c.charge_control().phase(), ChargePhase::Bulk);
    // Stored by the user (2241h with bit 31, algorithm 4 AGM) before the
    // module is heard: it stands, and a lithium-ion module changes nothing.
    let mut c = charger(None);
    c.handle_frame(ms(5), &frame(0x60A, &[0x23, 0x41, 0x22, 0, 4, 0, 0, 0x80]));
    let (frames, _) = drain(&mut c);
    assert_eq!(frames, ["58A#6041220000000000"]);
    c.handle_frame(ms(10), &frame(0x701, &[0x05]));
    let (frames, _) = drain(&mut c);
    assert!(frames.is_empty(), "{frames:?}");
    assert_eq!(c.charge_control().permanent_algorithm(), Some(4));
    assert_eq!(c.charge_control().active_algorithm(), Some(4));
}

#[test]
fn a_battery_no_algorithm_fits_is_not_charged() {
    // NiCd of 24 cells: the table has NiCd for 40 cells only. No other
    // chemistry's curve: E-0-2-0, no output.
    let mut c = asked();
    let _ = answer(&mut c, 11, 1, &[0x20]);
    let _ = answer(&mut c, 12, 2, &100u16.to_le_bytes());
    let (_, events) = answer(&mut c, 13, 4, &24u16.to_le_bytes());
    assert!(events.iter().any(|e| matches!(
        e,
        ChargerEvent::BatteryIdentified {
            algorithm: None,
            ..
        }
    )));
    assert_eq!(c.charge_control().active_algorithm(), None);
    assert!(!c.set_points().enabled);
    assert!(c
        .charge_control()
        .alarms()
        .contains(crate::deltaq::charge::ChargeAlarms::ALGORITHM_NOT_SET));
}
