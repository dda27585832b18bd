//! The CiA 418 catalogue, row by row: every application object 6000h-6090h
//! in words (CiA 418 v1.0.1, 7.3.1-7.3.18), and the status flag words
//! against the status types.

use std::string::ToString;

use super::*;
use crate::pdo::catalogue_test_support::{assert_table_consistent, assert_vectors};
use crate::pdo::{FieldValue, MappingEntry, NamedField};

fn one(index: u16, sub: u8, bits: u8, raw: u64) -> NamedField {
    BATTERY_MODULE_CATALOGUE.interpret(MappingEntry::new(index, sub, bits), raw)
}

#[test]
fn cia418_objects() {
    assert_vectors(
        BATTERY_MODULE_CATALOGUE,
        include_str!("catalogue_vectors.txt"),
    );
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
    /// (object, bit 0 as the status type reads it, its words set and clear)
    type Status = (u16, fn(u8) -> bool, &'static str, &'static str);
    let objects: [Status; 3] = [
        (
            0x6000,
            |b| BatteryStatus::from_bits_retain(b).contains(BatteryStatus::READY_TO_CHARGE),
            "ready to charge",
            "not ready to charge",
        ),
        (
            0x6001,
            |b| ChargerStatus::from_bits_retain(b).contains(ChargerStatus::ENABLED),
            "enabled",
            "not enabled",
        ),
        (
            0x6090,
            |b| WaterLevelStatus::from_bits_retain(b).is_full(),
            "full",
            "low",
        ),
    ];
    for byte in 0..=255u8 {
        let rest = byte & !0x01;
        for (index, bit0, set, clear) in objects {
            let words = if bit0(byte) { set } else { clear };
            let want = if rest == 0 {
                words.to_string()
            } else {
                format!("{words}, other bits {rest:02X}h")
            };
            let got = one(index, 0, 8, u64::from(byte)).value.to_string();
            assert_eq!(got, want, "{index:04X}h {byte:02X}h");
        }
    }
}
