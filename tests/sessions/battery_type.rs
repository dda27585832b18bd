//! The charger reads the module's 6020h (battery type, Ah capacity,
//! cells) and charges with the algorithm for that battery; its 6080h is
//! its own estimate of the state of charge (issue 35, "chemistries and
//! honest physics"). The charger has no permanent algorithm here and a
//! no-CAN default of the wrong kind (algorithm 2, flooded lead acid at
//! 12 A), so only the module's answer gives the right voltages.

use core::time::Duration;

use canopen_codec::cia418::BatteryType;
use canopen_codec::deltaq::charge::algorithm::select;
use canopen_codec::deltaq::charge::ChargePhase;
use canopen_codec::deltaq::OperatingMode;
use canopen_codec::sim::{PackSpec, Session, SessionConfig};
use canopen_codec::Timestamp;

/// A local-mode session of a 100 Ah pack of `name` (a 6020h name) with
/// `cells` cells from 20 %, the charger choosing by 6020h.
fn session(name: &str, cells: u16) -> Session {
    let t = BatteryType::from_name(name).unwrap();
    let mut config = SessionConfig::new(OperatingMode::Local, t.chemistry(), 100.0, 0.2).unwrap();
    config.pack = PackSpec::of_type(t, cells, 100.0).unwrap();
    config.charger.charge.permanent_algorithm = None;
    config.charger.charge.no_can_algorithm = Some(2);
    config.tick = Duration::from_secs(1);
    let mut s = Session::new(&config);
    s.start();
    s
}

#[test]
fn the_pack_sees_the_voltages_of_the_algorithm_for_its_chemistry() {
    for (name, cells) in [("flooded", 24u16), ("li-ion", 13), ("nicd", 40)] {
        let mut s = session(name, cells);
        let t = BatteryType::from_name(name).unwrap();
        let chosen = select(
            &canopen_codec::deltaq::charge::EXAMPLE_ALGORITHMS,
            t.into(),
            cells,
        )
        .unwrap();
        // Bulk at the chosen algorithm's 25 A (the default's would be 12 A).
        let bulk = s.run_while(Timestamp::from_millis(600_000), |s| {
            s.phase() != ChargePhase::Bulk
        });
        assert!(bulk, "{name}: no bulk");
        s.run_until(s.now().add_millis(60_000));
        assert!(
            (s.stage.current_a - 25.0).abs() < 0.5,
            "{name}: {} A",
            s.stage.current_a
        );
        let absorption = s.run_while(Timestamp::from_millis(12 * 3_600_000), |s| {
            s.phase() != ChargePhase::Absorption
        });
        assert!(absorption, "{name}: no absorption");
        s.run_until(s.now().add_millis(600_000));
        let c = s.charger().unwrap();
        assert_eq!(
            c.charge_control().active_algorithm(),
            Some(chosen.id),
            "{name}"
        );
        // 2241h reads back the algorithm chosen.
        assert_eq!(
            c.objects().objects().algorithm_request,
            u32::from(chosen.id)
        );
        // The set point is the chosen algorithm's absorption voltage,
        // compensated for the module's 6010h, and the pack is held there.
        let celsius = c.objects().objects().temperature >> 3;
        let want = chosen.compensated(chosen.absorption_mv, Some(celsius));
        assert_eq!(c.set_points().voltage_mv, want, "{name}");
        let pack = s.pack.terminal_voltage(s.stage.current_a);
        let want_v = f64::from(want) / 1000.0;
        assert!(
            (pack - want_v).abs() < want_v * 0.005,
            "{name}: {pack} V for {want_v} V"
        );
    }
}

#[test]
fn the_charger_soc_follows_the_pack_and_says_100_only_at_the_end() {
    let mut s = session("flooded", 24);
    let charger_soc = |s: &Session| s.charger().unwrap().objects().objects().charger_soc;
    // Mid-bulk, checked every simulated 10 minutes: the charger's
    // estimate (rest voltage at the start, Ah times 90 % efficiency over
    // the 100 Ah 6020h gave) is within 8 points of the pack's true state.
    let mut checked = 0;
    let mut next = 600_000;
    let limit = Timestamp::from_millis(12 * 3_600_000);
    s.run_while(limit, |s| {
        let phase = s.phase();
        let soc = charger_soc(s);
        if phase == ChargePhase::Bulk && s.now().as_millis() >= next {
            next += 600_000;
            let truth = s.pack.soc() * 100.0;
            assert!(
                (f64::from(soc) - truth).abs() <= 8.0,
                "6080h {soc} % with the pack at {truth:.1} % at {} s",
                s.now().as_millis() / 1000
            );
            checked += 1;
        }
        if !matches!(phase, ChargePhase::Float | ChargePhase::Complete) {
            assert!(soc < 100, "6080h 100 % in {phase:?}");
        }
        phase != ChargePhase::Float
    });
    assert!(checked >= 6, "{checked} checks in bulk");
    // Float: the cycle is done, 100 %.
    assert_eq!(s.phase(), ChargePhase::Float);
    assert_eq!(charger_soc(&s), 100);
}
