//! The pack model's tests.

use super::*;

fn lead_100() -> PackSpec {
    PackSpec::new(Chemistry::LeadAcid, 24, 100.0).unwrap()
}

/// A CC-CV charge of `spec` from `soc`: `bulk_a` up to `cv_cell`
/// volts a cell, until the current falls to `end_a` (at most 24 h);
/// the Ah that flowed in and the pack.
fn cc_cv(spec: PackSpec, soc: f64, cv_cell: f64, bulk_a: f64, end_a: f64) -> (f64, Pack) {
    let mut pack = Pack::new(spec, soc);
    let cv = cv_cell * f64::from(spec.cells);
    let mut ah = 0.0;
    for _ in 0..24 * 3600 {
        let i = pack.current_at(cv).min(bulk_a);
        if i < end_a {
            break;
        }
        assert!(pack.terminal_voltage(i) <= cv + 1e-6);
        pack.step(1.0, i);
        ah += i / 3600.0;
    }
    (ah, pack)
}

#[test]
fn at_rest_the_voltage_is_the_rest_curve() {
    let p = lead_100();
    assert!((p.cell_rest_voltage(0.0) - 1.94).abs() < 1e-9);
    assert!((p.cell_rest_voltage(0.55) - 2.05).abs() < 1e-9);
    assert!((p.cell_rest_voltage(1.0) - 2.12).abs() < 1e-9);
    assert!((p.cell_rest_voltage(7.0) - 2.12).abs() < 1e-9, "clamped");
    assert!((p.resistance_ohm - 0.144).abs() < 1e-12);
    let pack = Pack::new(p, 1.0);
    assert_eq!(pack.terminal_voltage(0.0), pack.rest_voltage());
    // A discharge: the ohmic drop.
    assert!((pack.terminal_voltage(-10.0) - (24.0 * 2.12 - 1.44)).abs() < 1e-9);
    let agm = PackSpec::of_type(BatteryType::from_name("agm").unwrap(), 24, 100.0).unwrap();
    assert!((agm.cell_rest_voltage(1.0) - 2.15).abs() < 1e-9);
}

#[test]
fn voltage_and_current_are_one_curve() {
    for (name, soc) in [
        ("flooded", 0.3),
        ("gel", 0.95),
        ("nicd", 0.6),
        ("li-ion", 0.99),
    ] {
        let t = BatteryType::from_name(name).unwrap();
        let pack = Pack::new(PackSpec::of_type(t, 10, 50.0).unwrap(), soc);
        for amps in [0.05, 1.0, 12.5, 40.0] {
            let v = pack.terminal_voltage(amps);
            assert!(v > pack.rest_voltage() - 0.05, "{name} {amps}");
            let back = pack.current_at(v);
            assert!(
                (back - amps).abs() < 1e-5 * amps.max(1.0),
                "{name} {amps}: {back}"
            );
        }
    }
}

#[test]
fn charge_is_stored_at_the_efficiency_and_heats_the_pack() {
    let mut pack = Pack::new(lead_100(), 0.2);
    for _ in 0..3600 {
        pack.step(1.0, 25.0);
    }
    assert!((pack.charged_ah() - 25.0).abs() < 1e-9);
    // 92 % of what the charge reaction took; the side reaction took
    // little this far from full.
    let side = pack.side_ah();
    assert!(side > 0.0 && side < 0.3, "{side}");
    assert!((pack.stored_ah() - (25.0 - side) * 0.92).abs() < 1e-9);
    assert!((pack.soc() - 0.2 - pack.stored_ah() / 100.0).abs() < 1e-9);
    // About 230 W of losses into 125 kJ/K for an hour.
    let t = pack.temperature_c();
    assert!(t > 28.0 && t < 32.0, "{t}");
    // It cools back toward ambient with no current.
    for _ in 0..200_000 {
        pack.step(1.0, 0.0);
    }
    assert!((pack.temperature_c() - 25.0).abs() < 0.1);
}

#[test]
fn constant_voltage_tapers_to_the_side_current() {
    let (_, pack) = cc_cv(lead_100(), 0.8, 2.45, 25.0, 0.0);
    // 25 A at 80 % (bulk ends there), then the taper: after 24 h the
    // pack is full and takes only the gassing current.
    assert!(Pack::new(lead_100(), 0.8).current_at(58.8) > 24.0);
    assert!(pack.soc() > 0.9999, "{}", pack.soc());
    let left = pack.current_at(58.8);
    assert!(left > 0.2 && left < 1.0, "{left}");
}

#[test]
fn float_holds_a_full_pack_with_a_small_real_current() {
    let mut pack = Pack::new(lead_100(), 1.0);
    let float = 24.0 * 2.27;
    let i = pack.current_at(float);
    // 0.06 % C at 2.27 V/cell: 60 mA for 100 Ah.
    assert!((i - 0.06).abs() < 1e-9, "{i}");
    for _ in 0..3600 {
        pack.step(1.0, pack.current_at(float));
    }
    assert_eq!(pack.soc(), 1.0);
    // All of it gas (and heat, which warms the pack a little and the
    // current with it).
    assert!(
        pack.side_ah() >= 0.06 && pack.side_ah() < 0.062,
        "{}",
        pack.side_ah()
    );
    pack.set_temperature_c(25.0);
    // Warm, the same voltage draws more; compensated by -4 mV/cell/K
    // it draws what it did at 25 degC.
    pack.set_temperature_c(40.0);
    assert!(pack.current_at(float) > 1.9 * i);
    let compensated = float - 24.0 * 0.004 * 15.0;
    assert!((pack.current_at(compensated) - i).abs() < 1e-9);
}

#[test]
fn a_whole_charge_takes_each_chemistry_its_charge_factor() {
    // (type, cells, absorption V/cell, rest V/cell full, Ah in per Ah
    // missing).
    let rows = [
        ("flooded", 24, 2.45, (2.10, 2.13), (1.05, 1.30)),
        ("agm", 24, 2.40, (2.13, 2.16), (1.03, 1.15)),
        ("nicd", 40, 1.50, (1.30, 1.33), (1.20, 1.40)),
        ("nimh", 40, 1.48, (1.36, 1.39), (1.12, 1.40)),
        ("li-ion", 13, 4.15, (4.10, 4.18), (1.0, 1.02)),
    ];
    for (name, cells, cv, rest, factor) in rows {
        let t = BatteryType::from_name(name).unwrap();
        let spec = PackSpec::of_type(t, cells, 100.0).unwrap();
        let (ah, pack) = cc_cv(spec, 0.2, cv, 25.0, 1.25);
        let missing = (pack.soc() - 0.2) * 100.0;
        assert!(pack.soc() > 0.95, "{name}: {}", pack.soc());
        let f = ah / missing;
        assert!(f > factor.0 && f < factor.1, "{name}: {f}");
        let per_cell = pack.rest_voltage() / f64::from(cells);
        assert!(per_cell > rest.0 && per_cell < rest.1, "{name}: {per_cell}");
        assert!(
            pack.temperature_c() < 45.0,
            "{name}: {}",
            pack.temperature_c()
        );
    }
}

#[test]
fn lithium_ion_charged_below_freezing_plates() {
    let spec = PackSpec::new(Chemistry::LithiumIon, 13, 50.0).unwrap();
    let mut pack = Pack::new(spec, 0.5);
    pack.step(3600.0, 10.0);
    assert_eq!(pack.plated_ah(), 0.0);
    pack.set_temperature_c(-5.0);
    pack.step(360.0, 10.0);
    assert!((pack.plated_ah() - 1.0).abs() < 1e-9);
    assert_eq!(PackSpec::cells_for(Chemistry::LithiumIon, 48.0), 13);
    assert_eq!(PackSpec::cells_for(Chemistry::NickelCadmium, 48.0), 40);
    assert_eq!(PackSpec::cells_for(Chemistry::LeadAcid, 48.0), 24);
    assert_eq!(PackSpec::cells_for(Chemistry::MetalAir, 48.0), 0);
}

#[test]
fn a_set_temperature_holds_and_shorted_cells_take_their_voltage() {
    let mut pack = Pack::new(lead_100(), 0.5);
    pack.set_temperature_c(-10.0);
    for _ in 0..3600 {
        pack.step(1.0, 0.0);
    }
    assert!((pack.temperature_c() + 10.0).abs() < 1e-9);
    pack.set_temperature_c(f64::NAN);
    assert!((pack.temperature_c() + 10.0).abs() < 1e-9);

    let whole = pack.rest_voltage();
    let at_58 = pack.current_at(58.0);
    pack.short_cells(2);
    assert_eq!((pack.shorted_cells(), pack.working_cells()), (2, 22));
    let per_cell = pack.spec().cell_rest_voltage(0.5);
    assert!((whole - pack.rest_voltage() - 2.0 * per_cell).abs() < 1e-9);
    // The same charging voltage over fewer cells drives more current.
    assert!(pack.current_at(58.0) > at_58);
    pack.short_cells(u16::MAX);
    assert_eq!(pack.working_cells(), 0);
    assert_eq!(pack.rest_voltage(), 0.0);
}

#[test]
fn a_pack_of_a_named_type_keeps_its_byte() {
    let agm = BatteryType::from_name("agm").unwrap();
    let spec = PackSpec::of_type(agm, 24, 100.0).unwrap();
    assert_eq!(
        (spec.chemistry, spec.battery_type),
        (Chemistry::LeadAcid, agm)
    );
    assert_eq!(
        lead_100().battery_type,
        BatteryType::from_name("flooded").unwrap()
    );
}

#[test]
fn unsupported_chemistries_and_empty_packs_are_errors() {
    assert_eq!(
        PackSpec::new(Chemistry::MetalAir, 10, 10.0),
        Err(PackError::UnsupportedChemistry(Chemistry::MetalAir))
    );
    assert_eq!(
        PackSpec::new(Chemistry::LeadAcid, 0, 10.0),
        Err(PackError::Empty)
    );
    assert_eq!(
        PackSpec::new(Chemistry::LeadAcid, 1, f64::NAN),
        Err(PackError::Empty)
    );
}
