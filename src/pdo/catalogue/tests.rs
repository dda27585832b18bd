//! Catalogue mechanism: exact numbers, markers, flag words, profile
//! formats, widths, dummies, short frames and totality, on a small table of
//! its own (the profiles' tables are tested in their modules).

use std::string::ToString;

use proptest::prelude::*;

use super::test_support::{
    any_pdo, assert_decode_total, assert_short_and_long_frames, assert_vectors,
};
use super::*;
use crate::od::DataType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use crate::od::{Access, Address, DataType};

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

const WORD: FlagWord = FlagWord {
    fields: &[
        FlagField::Bit {
            mask: 0x01,
            set: "on",
            clear: Some("off"),
        },
        FlagField::Bit {
            mask: 0x02,
            set: "hot",
            clear: None,
        },
        FlagField::Choice {
            mask: 0x0C,
            values: &[(0, None), (1, Some("mode one"))],
            unknown: "mode",
        },
        FlagField::OtherBits { mask: 0xFF },
    ],
    when_empty: None,
};

const QUIET: FlagWord = FlagWord {
    fields: &[
        FlagField::Bit {
            mask: 0x01,
            set: "alarm",
            clear: None,
        },
        FlagField::OtherBits { mask: 0x0F },
    ],
    when_empty: Some("none"),
};

fn has_value(raw: u64) -> bool {
    raw != 0xFF
}

fn write_code(raw: u64, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    write!(f, "code {raw}")
}

const CODE: ValueFormat = ValueFormat {
    kind: "code",
    has_value,
    write: write_code,
};

/// A read-only VAR of the tables below.
const fn row(index: u16, name: &'static str, data_type: DataType) -> ObjectRow {
    ObjectRow::var(index, name, data_type, Access::ReadOnly)
}

#[rustfmt::skip]
const TABLE: &[ObjectRow] = &[
    row(0x2000, "current", U16).scaled(8, Some(Unit::Ampere))
        .marked(Marker::NoValue(0xFFFF), None),
    row(0x2001, "level", U8).scaled(0, Some(Unit::Percent))
        .marked(Marker::Invalid(0xFF), Some(100)),
    row(0x2002, "temperature", DataType::Integer16).scaled(3, Some(Unit::DegreeCelsius)),
    row(0x2003, "status", U8).reading(Interpretation::Flags(&WORD)),
    row(0x2004, "code", U8).reading(Interpretation::Formatted(&CODE)),
    ObjectRow::new(Address::new(0x2005, 1), "name", U32, Access::ReadOnly).through(2)
        .reading(Interpretation::Chars),
    ObjectRow::new(Address::new(0x2006, 1), "filler", U8, Access::ReadOnly)
        .reading(Interpretation::Padding),
    row(0x2007, "alarms", U8).reading(Interpretation::Flags(&QUIET)),
];
#[rustfmt::skip]
const SECOND: &[ObjectRow] = &[
    row(0x2000, "shadowed", U16),
    row(0x3000, "counter", U32),
];
const CAT: Catalogue = Catalogue::new("test device", &[TABLE, SECOND]);

fn one(index: u16, sub: u8, bits: u8, raw: u64) -> NamedField {
    CAT.interpret(MappingEntry::new(index, sub, bits), raw)
}

#[test]
fn lookup_first_table_first() {
    assert_eq!(CAT.name(), "test device");
    assert_eq!(CAT.tables().len(), 2);
    assert_eq!(CAT.lookup(0x2000, 0).unwrap().name, "current");
    assert_eq!(CAT.lookup(0x3000, 0).unwrap().name, "counter");
    assert_eq!(CAT.lookup(0x2005, 2).unwrap().name, "name");
    assert!(CAT.lookup(0x2005, 3).is_none());
    assert!(CAT.lookup(0x4000, 0).is_none());
    assert!(Catalogue::new("empty", &[]).lookup(0x2000, 0).is_none());
}

#[test]
fn rows_in_words() {
    assert_vectors(CAT, include_str!("vectors.txt"));
}

#[test]
fn scaled_markers_and_ranges() {
    assert_eq!(
        format!("{:.2}", one(0x2000, 0, 16, 0x1374)),
        "2000h current 19.45 A"
    );
    assert_eq!(one(0x2000, 0, 16, 0xFFFF).value, FieldValue::NoValue);
    assert_eq!(one(0x2001, 0, 8, 150).value.kind(), "out_of_range");
    let f = one(0x2000, 0, 16, 0x1374);
    assert_eq!(f.value.unit(), Some(Unit::Ampere));
    assert_eq!(f.value.number(), Some(Fixed::new(0x1374, 8)));
    assert_eq!(f.value.kind(), "scaled");
}

#[test]
fn flag_words() {
    let FieldValue::Flags(flags) = one(0x2003, 0, 8, 0x03).value else {
        panic!("not flags")
    };
    assert_eq!(flags.raw(), 0x03);
    assert!(flags.contains(0x02) && !flags.contains(0x04));
    assert_eq!(flags.word(), &WORD);
    assert_eq!(WORD.known_bits(), 0x0F);
    assert_eq!(flags.to_string(), "on, hot");
}

#[test]
fn profile_formats() {
    let f = one(0x2004, 0, 8, 12);
    assert_eq!(f.value.kind(), "code");
    assert_eq!(
        f.value,
        FieldValue::Formatted(Formatted {
            format: &CODE,
            raw: 12
        })
    );
    assert_eq!(one(0x2004, 0, 8, 0xFF).value, FieldValue::NoValue);
}

#[test]
fn widths_dummies_and_unknown_objects() {
    // Fewer bits than the object: read leniently (python-canopen maps an
    // UNSIGNED8 as 4 bits and reads 15, an INTEGER8 as 4 bits and -2).
    assert_eq!(
        one(0x2000, 0, 8, 0x74).value,
        FieldValue::Narrowed {
            value: Fixed::new(0x74, 8),
            unit: Some(Unit::Ampere),
            object_bits: 16
        }
    );
    assert_eq!(one(0x2000, 0, 8, 0x74).value.kind(), "narrowed");
    assert_eq!(
        one(0x2002, 0, 4, 0xE).value.number(),
        Some(Fixed::new(-2, 3))
    );
    // More bits than the object, or a bit field cut short: not read.
    assert_eq!(
        one(0x2001, 0, 16, 0x74).value,
        FieldValue::WrongWidth { object_bits: 8 }
    );
    assert_eq!(
        one(0x2003, 0, 4, 1).value,
        FieldValue::WrongWidth { object_bits: 8 }
    );
    assert_eq!(one(0x0006, 0, 16, 0xABCD).value, FieldValue::Padding);
    assert_eq!(one(0x7000, 0, 1, 1).value, FieldValue::Raw);
}

#[test]
fn short_and_long_frames() {
    assert_short_and_long_frames(
        (
            CAT,
            [(0x2002, 0, 16), (0x2003, 0, 8), (0x3000, 0, 32)],
            "3000h counter: missing (past the end of the frame)",
        ),
        (CAT, (0x2001, 0, 8), "2001h level 1 %"),
    );
}

proptest! {
    #![proptest_config(crate::testing::proptest_config("tests/proptest-regressions/src-pdo-catalogue-tests.txt"))]

    /// Decoding is total and displays without panicking, for any mapping
    /// and any payload.
    #[test]
    fn decode_is_total((raw_entries, payload, precision) in any_pdo()) {
        assert_decode_total(&[CAT], &raw_entries, &payload, precision)?;
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
