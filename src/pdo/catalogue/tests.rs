//! Catalogue: exact numbers, markers, bit fields in words, widths, short
//! frames, the per-device meaning of 6052h, and totality.

use std::string::{String, ToString};
use std::vec::Vec;

use proptest::prelude::*;

use super::*;

fn one(cat: Catalogue, index: u16, sub: u8, bits: u8, raw: u64) -> NamedField {
    cat.interpret(MappingEntry::new(index, sub, bits), raw)
}

fn dq(index: u16, bits: u8, raw: u64) -> String {
    one(Catalogue::DeltaQCharger, index, 0, bits, raw).to_string()
}

#[test]
fn fixed_exact_and_rounded() {
    let cases: &[(i64, u8, &str, &str)] = &[
        (0x1374, 8, "19.453125", "19.45"),
        (0x4E45, 8, "78.26953125", "78.27"),
        (0x07BA, 4, "123.625", "123.63"),
        (0, 8, "0", "0.00"),
        (-320, 3, "-40", "-40.00"),
        (-1, 3, "-0.125", "-0.13"),
        (-1, 10, "-0.0009765625", "0.00"),
        (0xFFFF_FFFF, 10, "4194303.9990234375", "4194304.00"),
        (
            i64::MIN,
            0,
            "-9223372036854775808",
            "-9223372036854775808.00",
        ),
        (
            i64::MAX,
            32,
            "2147483647.99999999976716935634613037109375",
            "2147483648.00",
        ),
        (7, 0, "7", "7.00"),
    ];
    for &(raw, q, exact, two) in cases {
        let v = Fixed::new(raw, q);
        assert_eq!(v.to_string(), exact, "{raw} q{q}");
        assert_eq!(format!("{v:.2}"), two, "{raw} q{q}");
    }
    assert_eq!(format!("{:.0}", Fixed::new(12, 3)), "2"); // 1.5 rounds away from zero
    assert_eq!(format!("{:.0}", Fixed::new(-12, 3)), "-2");
    assert_eq!(format!("{:.30}", Fixed::new(1, 1)), "0.500000000000000000"); // capped at 18
    assert_eq!(Fixed::new(1, 200).frac_bits(), 32);
    // `#`: at most that many places.
    assert_eq!(format!("{:#.2}", Fixed::new(0x5200, 8)), "82");
    assert_eq!(format!("{:#.2}", Fixed::new(0x07BA, 4)), "123.63");
    assert_eq!(format!("{:#.3}", Fixed::new(0x07BA, 4)), "123.625");
    assert_eq!(format!("{:#.2}", Fixed::new(-12, 3)), "-1.5");
    assert_eq!(format!("{:#.2}", Fixed::new(-1, 10)), "0");
    assert_eq!(format!("{:#}", Fixed::new(-1, 3)), "-0.125");
    assert_eq!(Fixed::new(-3, 3).to_f64(), -0.375);
}

#[test]
fn deltaq_scaled_objects() {
    assert_eq!(dq(0x2002, 16, 0x1374), "2002h charging current 19.453125 A");
    assert_eq!(
        dq(0x2100, 16, 0xC800),
        "2100h battery voltage (legacy) 50 V"
    );
    assert_eq!(dq(0x2101, 16, 0x5200), "2101h battery voltage 82 V");
    assert_eq!(dq(0x2200, 16, 0x07BA), "2200h AC voltage 123.625 V");
    assert_eq!(dq(0x2271, 32, 0xE000), "2271h voltage request 56 V");
    assert_eq!(dq(0x2276, 16, 0x5200), "2276h voltage request 82 V");
    assert_eq!(dq(0x2275, 8, 12), "2275h cable resistance 12 mOhm");
    assert_eq!(
        dq(0x2002, 16, 0xFFFF),
        "2002h charging current: no value (raw FFFFh)"
    );
    assert_eq!(
        dq(0x2271, 32, 0xFFFF_FFFF),
        "2271h voltage request: no value (raw FFFFFFFFh)"
    );
    let f = one(Catalogue::DeltaQCharger, 0x2002, 0, 16, 0x1374);
    assert_eq!(format!("{f:.2}"), "2002h charging current 19.45 A");
    let g = one(Catalogue::DeltaQCharger, 0x2101, 0, 16, 0x5200);
    assert_eq!(format!("{g:#.2}"), "2101h battery voltage 82 V");
    assert_eq!(format!("{:#.2}", g.value), "82 V");
    assert_eq!(f.value.unit(), Some(Unit::Ampere));
    assert_eq!(f.value.number(), Some(Fixed::new(0x1374, 8)));
    assert_eq!(f.value.kind(), "scaled");
}

#[test]
fn deltaq_words() {
    assert_eq!(
        dq(0x2006, 16, 0x0070),
        "2006h extended charge status: AC present, charger enabled, override external (BMS)"
    );
    assert_eq!(
        dq(0x2006, 16, 0x1133),
        "2006h extended charge status: fault active, alarm active, AC present, charger enabled, \
         override internal, below 80 %, normal charge"
    );
    assert_eq!(
        dq(0x2006, 16, 0xF8CC),
        "2006h extended charge status: hardware shutdown, de-rating, override source 3, \
         indication 8, charge type 15"
    );
    assert_eq!(
        dq(0x2006, 16, 0x2600),
        "2006h extended charge status: override internal, equalize, maintenance charge"
    );
    assert_eq!(dq(0x2008, 8, 0), "2008h derate reasons: none");
    assert_eq!(
        dq(0x2008, 8, 0x85),
        "2008h derate reasons: AC voltage, temperature, other bits 80h"
    );
    assert_eq!(dq(0x4201, 8, 0x01), "4201h external override: equalize");
    assert_eq!(dq(0x4201, 8, 0x00), "4201h external override: none");
    assert_eq!(dq(0x2060, 32, 0), "2060h displayed error: none");
    assert_eq!(
        dq(0x2060, 32, 0x2080_8130),
        "2060h displayed error: E-0-3-2 heartbeat lost (EEC 8130h)"
    );
    assert_eq!(
        dq(0x2241, 32, 0x8000_000B),
        "2241h algorithm request: algorithm 11 variant 0, store permanently"
    );
    assert_eq!(
        dq(0x2241, 32, 0xFFFF_FFFF),
        "2241h algorithm request: no value (raw FFFFFFFFh)"
    );
    assert_eq!(
        one(Catalogue::DeltaQCharger, 0x2FFA, 1, 8, 0).to_string(),
        "2FFAh:01 padding (8 bits)"
    );
    assert_eq!(
        one(Catalogue::DeltaQCharger, 0x2FFA, 2, 8, 0).to_string(),
        "2FFAh:02 padding (8 bits)"
    );
}

#[test]
fn cia418_objects() {
    let b =
        |index, sub, bits, raw| one(Catalogue::BatteryModule, index, sub, bits, raw).to_string();
    assert_eq!(b(0x6000, 0, 8, 1), "6000h battery status: ready to charge");
    assert_eq!(
        b(0x6000, 0, 8, 0x80),
        "6000h battery status: not ready to charge, other bits 80h"
    );
    assert_eq!(b(0x6001, 0, 8, 1), "6001h charger status: enabled");
    assert_eq!(b(0x6001, 0, 8, 0), "6001h charger status: not enabled");
    assert_eq!(b(0x6090, 0, 8, 1), "6090h water level status: full");
    assert_eq!(b(0x6090, 0, 8, 0), "6090h water level status: low");
    assert_eq!(b(0x6010, 0, 16, 0x0230), "6010h temperature 70 degC");
    assert_eq!(b(0x6010, 0, 16, 0xFEC0), "6010h temperature -40 degC");
    assert_eq!(b(0x6010, 0, 16, 0xFFFF), "6010h temperature -0.125 degC");
    assert_eq!(
        b(0x6020, 1, 8, 0x10),
        "6020h:01 battery type: lead acid (10h)"
    );
    assert_eq!(b(0x6020, 2, 16, 400), "6020h:02 Ah capacity 400 Ah");
    assert_eq!(b(0x6020, 4, 16, 24), "6020h:04 number of cells 24");
    assert_eq!(
        b(0x6030, 1, 32, 0x5454_4142),
        "6030h:01 battery serial number: \"BATT\""
    );
    assert_eq!(
        b(0x6030, 2, 32, 0x0059_5245),
        "6030h:02 battery serial number: \"ERY\""
    );
    assert_eq!(
        b(0x6031, 5, 32, 0x2201_5C41),
        "6031h:05 battery ID: \"A\\x5C\\x01\\x22\""
    );
    assert_eq!(
        b(0x6050, 0, 32, 10_000),
        "6050h cumulative total Ah charge 10000 Ah"
    );
    assert_eq!(
        b(0x6051, 0, 16, 12),
        "6051h Ah expended since last charge 1.5 Ah"
    );
    assert_eq!(
        b(0x6054, 2, 16, 14_000),
        "6054h:02 last equalization, days since 1984-01-01 14000 d"
    );
    assert_eq!(b(0x6060, 0, 32, 0xC800), "6060h battery voltage 50 V");
    assert_eq!(
        b(0x6070, 0, 16, 0x00A0),
        "6070h charge current requested 10 A"
    );
    assert_eq!(
        b(0x6070, 0, 16, 0x00FF),
        "6070h charge current requested 15.9375 A"
    );
    assert_eq!(
        b(0x6070, 0, 16, 0xFFFF),
        "6070h charge current requested: invalid (raw FFFFh)"
    );
    assert_eq!(
        b(0x6080, 0, 8, 0xFF),
        "6080h charger state of charge: invalid (raw FFh)"
    );
    assert_eq!(b(0x6081, 0, 8, 76), "6081h battery state of charge 76 %");
    assert_eq!(
        b(0x6081, 0, 8, 150),
        "6081h battery state of charge 150 % (out of range)"
    );
}

#[test]
fn ah_returned_differs_between_devices() {
    let module = one(Catalogue::BatteryModule, 0x6052, 0, 16, 0xFFFF);
    assert_eq!(
        module.to_string(),
        "6052h Ah returned during last charge 8191.875 Ah"
    );
    let charger = one(Catalogue::DeltaQCharger, 0x6052, 0, 16, 0xFFFF);
    assert_eq!(charger.value, FieldValue::NoValue);
    let charger = one(Catalogue::DeltaQCharger, 0x6052, 0, 16, 12);
    assert_eq!(
        charger.to_string(),
        "6052h Ah returned during last charge 1.5 Ah"
    );
}

#[test]
fn manufacturer_objects_belong_to_the_charger() {
    let f = one(Catalogue::BatteryModule, 0x2002, 0, 16, 0x1374);
    assert_eq!(f.value, FieldValue::Raw);
    assert_eq!(f.to_string(), "2002h unknown object: raw 1374h (16 bits)");
    // The charger also knows the CiA 418 objects.
    assert_eq!(
        one(Catalogue::DeltaQCharger, 0x6081, 0, 8, 76).to_string(),
        "6081h battery state of charge 76 %"
    );
}

#[test]
fn widths_dummies_and_unknown_subs() {
    let f = one(Catalogue::DeltaQCharger, 0x2002, 0, 8, 0x74);
    assert_eq!(f.value, FieldValue::WrongWidth { object_bits: 16 });
    assert_eq!(
        f.to_string(),
        "2002h charging current: raw 74h, mapped as 8 bits, object has 16"
    );
    let d = one(Catalogue::BatteryModule, 0x0006, 0, 16, 0xABCD);
    assert_eq!(d.value, FieldValue::Padding);
    assert_eq!(d.to_string(), "0006h padding (16 bits)");
    assert_eq!(
        one(Catalogue::DeltaQCharger, 0x2FFA, 1, 16, 0).value,
        FieldValue::Padding
    );
    assert_eq!(
        one(Catalogue::BatteryModule, 0x6020, 5, 16, 1).value,
        FieldValue::Raw
    );
    assert_eq!(
        one(Catalogue::BatteryModule, 0x6030, 4, 32, 1).value,
        FieldValue::Raw
    );
    assert_eq!(
        one(Catalogue::BatteryModule, 0x7000, 0, 1, 1).to_string(),
        "7000h unknown object: raw 1h (1 bits)"
    );
}

fn mapping(entries: &[(u16, u8, u8)]) -> PdoMapping {
    let e: Vec<MappingEntry> = entries
        .iter()
        .map(|&(i, s, b)| MappingEntry::new(i, s, b))
        .collect();
    PdoMapping::new(&e).unwrap()
}

#[test]
fn short_and_long_frames() {
    let m = mapping(&[(0x6010, 0, 16), (0x6000, 0, 8), (0x6060, 0, 32)]);
    let fields = Catalogue::BatteryModule.decode(&m, &[0x30, 0x02, 0x01, 0x00]);
    assert_eq!(fields.len(), 3);
    let s = fields.as_slice();
    assert_eq!(s[0].value.number(), Some(Fixed::new(0x230, 3)));
    assert_eq!(s[1].raw, 1);
    assert_eq!(s[2].value, FieldValue::Missing);
    assert_eq!(s[2].raw, 0);
    assert_eq!(
        s[2].to_string(),
        "6060h battery voltage: missing (past the end of the frame)"
    );
    assert_eq!(fields.unmapped_bytes(), 0);

    let m = mapping(&[(0x6001, 0, 8)]);
    let fields = Catalogue::DeltaQCharger.decode(&m, &[1, 2, 3]);
    assert_eq!(fields.unmapped_bytes(), 2);
    assert_eq!(fields.to_string(), "6001h charger status: enabled");

    let empty = Catalogue::DeltaQCharger.decode(&PdoMapping::EMPTY, &[1]);
    assert!(empty.is_empty());
    assert_eq!(empty.to_string(), "");
}

#[test]
fn the_capture_tpdo2_in_words() {
    let m = mapping(&[
        (0x2060, 0, 32),
        (0x2200, 0, 16),
        (0x6080, 0, 8),
        (0x0005, 0, 8),
    ]);
    let fields = Catalogue::DeltaQCharger.decode(&m, &[0, 0, 0, 0, 0xBA, 0x07, 0xFF, 0]);
    assert_eq!(
        format!("{fields:.2}"),
        "2060h displayed error: none; 2200h AC voltage 123.63 V; \
         6080h charger state of charge: invalid (raw FFh); 0005h padding (8 bits)"
    );
    let kinds: Vec<&str> = fields.iter().map(|f| f.value.kind()).collect();
    assert_eq!(kinds, ["error", "scaled", "invalid", "padding"]);
}

#[test]
fn catalogue_tables_are_consistent() {
    for table in [CIA418_OBJECTS, DELTAQ_OBJECTS] {
        for (i, a) in table.iter().enumerate() {
            assert!(a.first_sub <= a.last_sub, "{a:?}");
            assert!(a.bits >= 1 && a.bits <= 32, "{a:?}");
            for b in &table[i + 1..] {
                let overlap =
                    a.index == b.index && a.first_sub <= b.last_sub && b.first_sub <= a.last_sub;
                assert!(!overlap, "{a:?} overlaps {b:?}");
            }
        }
    }
    // Every CiA 418 application object 6000h-6090h is there.
    for index in [
        0x6000, 0x6001, 0x6010, 0x6020, 0x6030, 0x6031, 0x6040, 0x6041, 0x6050, 0x6051, 0x6052,
        0x6053, 0x6054, 0x6060, 0x6070, 0x6080, 0x6081, 0x6090,
    ] {
        assert!(
            CIA418_OBJECTS.iter().any(|e| e.index == index),
            "{index:04X}h"
        );
    }
    for index in [
        0x2002, 0x2006, 0x2008, 0x2060, 0x2100, 0x2101, 0x2200, 0x2241, 0x2271, 0x2276, 0x4201,
        0x2FFA, 0x6052,
    ] {
        assert!(
            DELTAQ_OBJECTS.iter().any(|e| e.index == index),
            "{index:04X}h"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { failure_persistence: None, ..ProptestConfig::default() })]

    /// Decoding is total and displays without panicking, for any mapping
    /// and any payload, in both catalogues.
    #[test]
    fn decode_is_total(
        raw_entries in proptest::collection::vec(any::<u32>(), 0..=8),
        payload in proptest::collection::vec(any::<u8>(), 0..=10),
        precision in proptest::option::of(0usize..25),
    ) {
        let Ok(m) = PdoMapping::from_u32s(&raw_entries) else { return Ok(()) };
        for cat in [Catalogue::BatteryModule, Catalogue::DeltaQCharger] {
            let fields = cat.decode(&m, &payload);
            prop_assert_eq!(fields.len(), m.len());
            let _ = match precision {
                Some(p) => format!("{fields:.p$}"),
                None => fields.to_string(),
            };
        }
    }

    /// Catalogue entries over their own widths, with realistic mappings.
    #[test]
    fn known_objects_are_total(raw in any::<u64>(), pick in 0usize..64) {
        for cat in [Catalogue::BatteryModule, Catalogue::DeltaQCharger] {
            let table = [CIA418_OBJECTS, DELTAQ_OBJECTS].concat();
            let def = &table[pick % table.len()];
            let bits = u32::from(def.bits);
            let raw = raw & (u64::MAX >> (64 - bits));
            let f = cat.interpret(MappingEntry::new(def.index, def.first_sub, def.bits), raw);
            let _ = format!("{f} {f:.2} {}", f.value);
        }
    }

    /// The exact and the rounded forms agree with f64 where f64 is exact.
    #[test]
    fn fixed_matches_f64(raw in -(1i64 << 40)..(1i64 << 40), q in 0u8..=12) {
        let v = Fixed::new(raw, q);
        let exact: f64 = v.to_string().parse().unwrap();
        prop_assert_eq!(exact, v.to_f64());
        let two: f64 = format!("{v:.2}").parse().unwrap();
        prop_assert!((two - v.to_f64()).abs() <= 0.005 + v.to_f64().abs() * 1e-15);
    }
}
