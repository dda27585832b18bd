//! The CiA 418 catalogue, row by row: every application object 6000h-6090h
//! in words (CiA 418 v1.0.1, 7.3.1-7.3.18), and the status flag words
//! against the status types.

use std::string::{String, ToString};

use super::*;
use crate::pdo::catalogue_test_support::{assert_table_consistent, assert_words, WordsCase};
use crate::pdo::{FieldValue, MappingEntry, NamedField};

fn one(index: u16, sub: u8, bits: u8, raw: u64) -> NamedField {
    BATTERY_MODULE_CATALOGUE.interpret(MappingEntry::new(index, sub, bits), raw)
}

/// Every CiA 418 object in words: `(mapping entry, raw, words)`.
const CASES: &[WordsCase] = &[
    (0x6000_0008, 1, "6000h battery status: ready to charge"),
    (
        0x6000_0008,
        0x80,
        "6000h battery status: not ready to charge, other bits 80h",
    ),
    (0x6001_0008, 1, "6001h charger status: enabled"),
    (0x6001_0008, 0, "6001h charger status: not enabled"),
    (0x6090_0008, 1, "6090h water level status: full"),
    (0x6090_0008, 0, "6090h water level status: low"),
    (0x6010_0010, 0x0230, "6010h temperature 70 degC"),
    (0x6010_0010, 0xFEC0, "6010h temperature -40 degC"),
    (0x6010_0010, 0xFFFF, "6010h temperature -0.125 degC"),
    (0x6020_0108, 0x10, "6020h:01 battery type: lead acid (10h)"),
    (0x6020_0210, 400, "6020h:02 Ah capacity 400 Ah"),
    (0x6020_0410, 24, "6020h:04 number of cells 24"),
    (
        0x6030_0120,
        0x5454_4142,
        "6030h:01 battery serial number: \"BATT\"",
    ),
    (
        0x6030_0220,
        0x0059_5245,
        "6030h:02 battery serial number: \"ERY\"",
    ),
    (
        0x6031_0520,
        0x2201_5C41,
        "6031h:05 battery ID: \"A\\x5C\\x01\\x22\"",
    ),
    (
        0x6050_0020,
        10_000,
        "6050h cumulative total Ah charge 10000 Ah",
    ),
    (
        0x6051_0010,
        12,
        "6051h Ah expended since last charge 1.5 Ah",
    ),
    (
        0x6052_0010,
        0xFFFF,
        "6052h Ah returned during last charge 8191.875 Ah",
    ),
    (
        0x6054_0210,
        14_000,
        "6054h:02 last equalization, days since 1984-01-01 14000 d",
    ),
    (0x6060_0020, 0xC800, "6060h battery voltage 50 V"),
    (0x6070_0010, 0x00A0, "6070h charge current requested 10 A"),
    (
        0x6070_0010,
        0x00FF,
        "6070h charge current requested 15.9375 A",
    ),
    (
        0x6070_0010,
        0xFFFF,
        "6070h charge current requested: invalid (raw FFFFh)",
    ),
    (
        0x6080_0008,
        0xFF,
        "6080h charger state of charge: invalid (raw FFh)",
    ),
    (0x6081_0008, 76, "6081h battery state of charge 76 %"),
    (
        0x6081_0008,
        150,
        "6081h battery state of charge 150 % (out of range)",
    ),
];

#[test]
fn cia418_objects() {
    assert_words(BATTERY_MODULE_CATALOGUE, CASES);
}

#[test]
fn manufacturer_objects_are_unknown_on_a_module() {
    let f = one(0x2002, 0, 16, 0x1374);
    assert_eq!(f.value, FieldValue::Raw);
    assert_eq!(f.to_string(), "2002h unknown object: raw 1374h (16 bits)");
    assert_eq!(one(0x6020, 5, 16, 1).value, FieldValue::Raw);
    assert_eq!(one(0x6030, 4, 32, 1).value, FieldValue::Raw);
    assert_eq!(one(0x6020, 1, 8, 0x10).value.kind(), "battery_type");
}

#[test]
fn table_is_consistent_and_complete() {
    // Every CiA 418 application object 6000h-6090h is there.
    assert_table_consistent(
        CIA418_OBJECTS,
        &[
            0x6000, 0x6001, 0x6010, 0x6020, 0x6030, 0x6031, 0x6040, 0x6041, 0x6050, 0x6051, 0x6052,
            0x6053, 0x6054, 0x6060, 0x6070, 0x6080, 0x6081, 0x6090,
        ],
    );
}

/// The status bytes in words, as the status types read them, for every
/// byte.
#[test]
fn status_words_agree_with_the_status_types() {
    for byte in 0..=255u8 {
        let rest = byte & !0x01;
        let other = |s: &str| -> String {
            if rest == 0 {
                s.to_string()
            } else {
                format!("{s}, other bits {rest:02X}h")
            }
        };
        let b = BatteryStatus::from_bits_retain(byte);
        let want = other(if b.contains(BatteryStatus::READY_TO_CHARGE) {
            "ready to charge"
        } else {
            "not ready to charge"
        });
        assert_eq!(one(0x6000, 0, 8, u64::from(byte)).value.to_string(), want);
        let c = ChargerStatus::from_bits_retain(byte);
        let want = other(if c.contains(ChargerStatus::ENABLED) {
            "enabled"
        } else {
            "not enabled"
        });
        assert_eq!(one(0x6001, 0, 8, u64::from(byte)).value.to_string(), want);
        let w = WaterLevelStatus::from_bits_retain(byte);
        let want = other(if w.is_full() { "full" } else { "low" });
        assert_eq!(one(0x6090, 0, 8, u64::from(byte)).value.to_string(), want);
    }
}
