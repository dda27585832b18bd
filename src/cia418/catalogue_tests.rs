//! The CiA 418 catalogue, row by row: every application object 6000h-6090h
//! in words (CiA 418 v1.0.1, 7.3.1-7.3.18), and the status flag words
//! against the status types.

use std::string::{String, ToString};

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
