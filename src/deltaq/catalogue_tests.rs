//! The Delta-Q charger's catalogue, row by row, and both device catalogues
//! together: the per-device meaning of 6052h, manufacturer objects, short
//! frames, the capture's TPDO 2, and totality.

use std::string::{String, ToString};
use std::vec::Vec;

use proptest::prelude::*;

use super::*;
use crate::cia418::BATTERY_MODULE_CATALOGUE;
use crate::deltaq::*;
use crate::pdo::catalogue_test_support::{
    any_pdo, assert_decode_total, assert_short_and_long_frames, assert_table_consistent,
    assert_vectors, mapping,
};
use crate::pdo::{FieldValue, Fixed, MappingEntry, NamedField};

fn one(cat: Catalogue, index: u16, sub: u8, bits: u8, raw: u64) -> NamedField {
    cat.interpret(MappingEntry::new(index, sub, bits), raw)
}

#[test]
fn deltaq_objects_in_words() {
    assert_vectors(CHARGER_CATALOGUE, include_str!("catalogue_vectors.txt"));
}

#[test]
fn deltaq_scaled_objects() {
    let f = one(CHARGER_CATALOGUE, 0x2002, 0, 16, 0x1374);
    assert_eq!(format!("{f:.2}"), "2002h charging current 19.45 A");
    let g = one(CHARGER_CATALOGUE, 0x2101, 0, 16, 0x5200);
    assert_eq!(format!("{g:#.2}"), "2101h battery voltage 82 V");
    assert_eq!(format!("{:#.2}", g.value), "82 V");
    assert_eq!(f.value.unit(), Some(Unit::Ampere));
    assert_eq!(f.value.number(), Some(Fixed::new(0x1374, 8)));
    assert_eq!(f.value.kind(), "scaled");
}

#[test]
fn ah_returned_differs_between_devices() {
    let module = one(BATTERY_MODULE_CATALOGUE, 0x6052, 0, 16, 0xFFFF);
    assert_eq!(
        module.to_string(),
        "6052h Ah returned during last charge 8191.875 Ah"
    );
    let charger = one(CHARGER_CATALOGUE, 0x6052, 0, 16, 0xFFFF);
    assert_eq!(charger.value, FieldValue::NoValue);
}

#[test]
fn manufacturer_objects_belong_to_the_charger() {
    let f = one(BATTERY_MODULE_CATALOGUE, 0x2002, 0, 16, 0x1374);
    assert_eq!(f.value, FieldValue::Raw);
    assert_eq!(f.to_string(), "2002h unknown object: raw 1374h (16 bits)");
}

#[test]
fn widths_dummies_and_unknown_subs() {
    let f = one(CHARGER_CATALOGUE, 0x2002, 0, 8, 0x74);
    assert_eq!(f.value.kind(), "narrowed");
    assert_eq!(
        f.value.number().map(|v| v.to_string()),
        Some("0.453125".into())
    );
    let f = one(CHARGER_CATALOGUE, 0x2002, 0, 32, 0x74);
    assert_eq!(f.value, FieldValue::WrongWidth { object_bits: 16 });
    let d = one(BATTERY_MODULE_CATALOGUE, 0x0006, 0, 16, 0xABCD);
    assert_eq!(d.value, FieldValue::Padding);
    assert_eq!(d.to_string(), "0006h padding (16 bits)");
    assert_eq!(
        one(CHARGER_CATALOGUE, 0x2FFA, 1, 16, 0).value,
        FieldValue::Padding
    );
    assert_eq!(
        one(BATTERY_MODULE_CATALOGUE, 0x6020, 5, 16, 1).value,
        FieldValue::Raw
    );
    assert_eq!(
        one(BATTERY_MODULE_CATALOGUE, 0x6030, 4, 32, 1).value,
        FieldValue::Raw
    );
    assert_eq!(
        one(BATTERY_MODULE_CATALOGUE, 0x7000, 0, 1, 1).to_string(),
        "7000h unknown object: raw 1h (1 bits)"
    );
}

#[test]
fn short_and_long_frames() {
    assert_short_and_long_frames(
        (
            BATTERY_MODULE_CATALOGUE,
            [(0x6010, 0, 16), (0x6000, 0, 8), (0x6060, 0, 32)],
            "6060h battery voltage: missing (past the end of the frame)",
        ),
        (
            CHARGER_CATALOGUE,
            (0x6001, 0, 8),
            "6001h charger status: enabled",
        ),
    );
}

#[test]
fn the_capture_tpdo2_in_words() {
    let m = mapping(&[
        (0x2060, 0, 32),
        (0x2200, 0, 16),
        (0x6080, 0, 8),
        (0x0005, 0, 8),
    ]);
    let fields = CHARGER_CATALOGUE.decode(&m, &[0, 0, 0, 0, 0xBA, 0x07, 0xFF, 0]);
    assert_eq!(
        format!("{fields:.2}"),
        "2060h displayed error: none; 2200h AC voltage 123.63 V; \
         6080h charger state of charge: invalid (raw FFh); 0005h padding (8 bits)"
    );
    let kinds: Vec<&str> = fields.iter().map(|f| f.value.kind()).collect();
    assert_eq!(kinds, ["error", "scaled", "invalid", "padding"]);
}

/// The Delta-Q table (CiA 418's is checked in its own module): no
/// overlapping rows, every width a CiA 301 basic type's, every Delta-Q
/// object there.
#[test]
fn catalogue_tables_are_consistent() {
    assert_table_consistent(
        DELTAQ_OBJECTS,
        &[
            0x2002, 0x2006, 0x2008, 0x2060, 0x2100, 0x2101, 0x2200, 0x2241, 0x2271, 0x2276, 0x4201,
            0x2FFA, 0x6052,
        ],
    );
}

/// The 2006h flag word says what [`ExtendedChargeStatus`] decodes, for
/// every 16-bit value; 2008h and 4201h likewise for every byte.
#[test]
fn flag_words_agree_with_the_typed_values() {
    use super::super::ExtendedChargeStatus;
    for raw in 0..=u16::MAX {
        let s = ExtendedChargeStatus::from_u16(raw);
        let mut want: Vec<String> = Vec::new();
        for (flag, name) in [
            (ChargeStatusFlags::FAULT_ACTIVE, "fault active"),
            (ChargeStatusFlags::ALARM_ACTIVE, "alarm active"),
            (ChargeStatusFlags::HW_SHUTDOWN, "hardware shutdown"),
            (ChargeStatusFlags::DERATING, "de-rating"),
            (ChargeStatusFlags::AC_PRESENT, "AC present"),
            (ChargeStatusFlags::CHARGER_ENABLED, "charger enabled"),
        ] {
            if s.flags.contains(flag) {
                want.push(name.into());
            }
        }
        want.push(match s.override_source {
            OverrideSource::Internal => "override internal".into(),
            OverrideSource::External => "override external (BMS)".into(),
            OverrideSource::Other(v) => format!("override source {v}"),
        });
        match s.indication {
            ChargeIndication::Inactive => {}
            ChargeIndication::Below80 => want.push("below 80 %".into()),
            ChargeIndication::Above80 => want.push("above 80 %".into()),
            ChargeIndication::Finishing => want.push("finishing".into()),
            ChargeIndication::Complete => want.push("complete".into()),
            ChargeIndication::Resting => want.push("resting".into()),
            ChargeIndication::Equalize => want.push("equalize".into()),
            ChargeIndication::PowerSupplyMode => want.push("power-supply mode".into()),
            ChargeIndication::Other(v) => want.push(format!("indication {v}")),
        }
        match s.charge_type {
            ChargeType::None => {}
            ChargeType::Normal => want.push("normal charge".into()),
            ChargeType::Maintenance => want.push("maintenance charge".into()),
            ChargeType::Other(v) => want.push(format!("charge type {v}")),
        }
        let got = one(CHARGER_CATALOGUE, 0x2006, 0, 16, u64::from(raw));
        assert_eq!(got.value.to_string(), want.join(", "), "{raw:04X}h");
    }
    // The flag bytes: (object, its named bits).
    let flag_bytes: [(u16, &[(u8, &str)]); 2] = [
        (
            0x2008,
            &[
                (DerateReasons::AC_VOLTAGE.bits(), "AC voltage"),
                (DerateReasons::BATTERY_VOLTAGE.bits(), "battery voltage"),
                (DerateReasons::TEMPERATURE.bits(), "temperature"),
                (DerateReasons::AC_CURRENT_LIMIT.bits(), "AC current limit"),
            ],
        ),
        (
            0x4201,
            &[
                (ExternalOverride::EQUALIZE.bits(), "equalize"),
                (ExternalOverride::MAINTENANCE.bits(), "maintenance"),
            ],
        ),
    ];
    for byte in 0..=255u8 {
        for (index, names) in flag_bytes {
            let mut known = 0;
            let mut want: Vec<String> = Vec::new();
            for &(bit, name) in names {
                known |= bit;
                if byte & bit != 0 {
                    want.push(name.into());
                }
            }
            if byte & !known != 0 {
                want.push(format!("other bits {:02X}h", byte & !known));
            }
            let want = if want.is_empty() {
                "none".into()
            } else {
                want.join(", ")
            };
            let got = one(CHARGER_CATALOGUE, index, 0, 8, u64::from(byte));
            assert_eq!(got.value.to_string(), want, "{index:04X}h {byte:02X}h");
        }
    }
}

proptest! {
    #![proptest_config(crate::testing::proptest_config("tests/proptest-regressions/src-deltaq-catalogue_tests.txt"))]

    /// Decoding is total and displays without panicking, for any mapping
    /// and any payload, in both catalogues.
    #[test]
    fn decode_is_total((raw_entries, payload, precision) in any_pdo()) {
        assert_decode_total(
            &[BATTERY_MODULE_CATALOGUE, CHARGER_CATALOGUE],
            &raw_entries,
            &payload,
            precision,
        )?;
    }

    /// Catalogue entries over their own widths, with realistic mappings.
    #[test]
    fn known_objects_are_total(raw in any::<u64>(), pick in 0usize..64) {
        for cat in [BATTERY_MODULE_CATALOGUE, CHARGER_CATALOGUE] {
            let table = [CIA418_OBJECTS, DELTAQ_OBJECTS].concat();
            let def = &table[pick % table.len()];
            let bits = u32::from(def.bits());
            let raw = raw & (u64::MAX >> (64 - bits));
            let f = cat.interpret(MappingEntry::new(def.address.index, def.address.sub, def.bits()), raw);
            let _ = format!("{f} {f:.2} {}", f.value);
        }
    }

}
