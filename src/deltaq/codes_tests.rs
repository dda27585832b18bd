//! Row-by-row tests of the Delta-Q alarm and fault table, and of the code
//! type's decoding, encoding and labels.
//!
//! Every expected value below is a literal copied from the alarm and fault
//! tables of "Delta-Q IC Series CANopen interface specification rev 2.0",
//! section 4.4.1 (the "Object 1003h Error Code" column; the EMCY bytes and
//! SDO wire bytes are those values laid out as section 4.4.1.1 describes:
//! EEC little-endian, error register 01h, the Delta-Q code little-endian in
//! bytes 3-4), never computed by the code under test.

use super::*;
use crate::emcy::{Emergency, ErrorCode, ErrorFieldEntry, ErrorRegister};
use crate::wire::Codec;
use DeltaQCode::{Alarm, Fault, Other};

struct Case {
    label: &'static str,
    code: DeltaQCode,
    eec: u16,
    emcy: [u8; 8],
    field: u32,
    wire: [u8; 4],
    in_1003h: bool,
}

fn check_row(c: &Case) {
    let eec = ErrorCode(c.eec);
    // Table row.
    let row = c
        .code
        .entry()
        .unwrap_or_else(|| panic!("{} not in table", c.label));
    assert_eq!(row.code, c.code, "{}", c.label);
    assert_eq!(row.label, c.label);
    assert_eq!(row.eec, eec, "{}", c.label);
    assert_eq!(row.in_1003h, c.in_1003h, "{}", c.label);
    assert!(!row.description.is_empty());
    assert_eq!(row.error_field(), c.field, "{}", c.label);
    // Label both ways.
    assert_eq!(format!("{}", c.code), c.label);
    assert_eq!(DeltaQCode::from_label(c.label), Some(c.code));
    // EMCY path.
    let e = Emergency::parse(&c.emcy).unwrap();
    assert_eq!(e.code, eec, "{}", c.label);
    assert_eq!(DeltaQCode::from_emergency(&e), c.code, "{}", c.label);
    assert_eq!(
        c.code.to_emergency(eec, ErrorRegister::GENERIC).to_bytes(),
        c.emcy,
        "{}",
        c.label
    );
    assert_eq!(row.emergency(ErrorRegister::GENERIC).to_bytes(), c.emcy);
    // 1003h / 2060h path.
    assert_eq!(DeltaQCode::from_error_field(c.field), (eec, c.code));
    assert_eq!(DeltaQCode::from_error_field_lenient(c.field), (eec, c.code));
    assert_eq!(c.code.to_error_field(eec), c.field, "{}", c.label);
    // SDO wire bytes of the 1003h value.
    assert_eq!(c.field.to_le_bytes(), c.wire, "{}", c.label);
    let entry = ErrorFieldEntry::decode(&c.wire).unwrap();
    assert_eq!(entry.code, eec);
    assert_eq!(DeltaQCode::from_error_field_entry(entry), c.code);
    assert_eq!(c.code.to_error_field_entry(eec).to_le_bytes(), c.wire);
}

macro_rules! rows {
    ($($name:ident: $label:literal, $code:expr, $eec:literal, $emcy:expr, $field:literal,
       $wire:expr, $in:literal;)*) => {
        $(
            #[test]
            fn $name() {
                check_row(&CASES[CASES.iter().position(|c| c.label == $label).unwrap()]);
            }
        )*
        const CASES: &[Case] = &[$(Case {
            label: $label,
            code: $code,
            eec: $eec,
            emcy: $emcy,
            field: $field,
            wire: $wire,
            in_1003h: $in,
        }),*];
    };
}

rows! {
    e_0_0_1: "E-0-0-1", Alarm(1), 0x9000, [0x00, 0x90, 0x01, 0x01, 0x80, 0x00, 0x00, 0x00], 0x0180_9000, [0x00, 0x90, 0x80, 0x01], true;
    e_0_0_2: "E-0-0-2", Alarm(2), 0x9000, [0x00, 0x90, 0x01, 0x02, 0x80, 0x00, 0x00, 0x00], 0x0280_9000, [0x00, 0x90, 0x80, 0x02], true;
    e_0_0_3: "E-0-0-3", Alarm(3), 0x9000, [0x00, 0x90, 0x01, 0x03, 0x80, 0x00, 0x00, 0x00], 0x0380_9000, [0x00, 0x90, 0x80, 0x03], true;
    e_0_0_4: "E-0-0-4", Alarm(4), 0x9000, [0x00, 0x90, 0x01, 0x04, 0x80, 0x00, 0x00, 0x00], 0x0480_9000, [0x00, 0x90, 0x80, 0x04], true;
    e_0_0_7: "E-0-0-7", Alarm(7), 0x9000, [0x00, 0x90, 0x01, 0x07, 0x80, 0x00, 0x00, 0x00], 0x0780_9000, [0x00, 0x90, 0x80, 0x07], true;
    e_0_0_8: "E-0-0-8", Alarm(8), 0x9000, [0x00, 0x90, 0x01, 0x08, 0x80, 0x00, 0x00, 0x00], 0x0880_9000, [0x00, 0x90, 0x80, 0x08], true;
    e_0_1_2: "E-0-1-2", Alarm(12), 0x9000, [0x00, 0x90, 0x01, 0x0C, 0x80, 0x00, 0x00, 0x00], 0x0C80_9000, [0x00, 0x90, 0x80, 0x0C], true;
    e_0_1_3: "E-0-1-3", Alarm(13), 0x9000, [0x00, 0x90, 0x01, 0x0D, 0x80, 0x00, 0x00, 0x00], 0x0D80_9000, [0x00, 0x90, 0x80, 0x0D], true;
    e_0_1_4: "E-0-1-4", Alarm(14), 0x1000, [0x00, 0x10, 0x01, 0x0E, 0x80, 0x00, 0x00, 0x00], 0x0E80_1000, [0x00, 0x10, 0x80, 0x0E], true;
    e_0_1_5: "E-0-1-5", Alarm(15), 0x1000, [0x00, 0x10, 0x01, 0x0F, 0x80, 0x00, 0x00, 0x00], 0x0F80_1000, [0x00, 0x10, 0x80, 0x0F], true;
    e_0_1_6: "E-0-1-6", Alarm(16), 0x0000, [0x00, 0x00, 0x01, 0x10, 0x80, 0x00, 0x00, 0x00], 0x1080_0000, [0x00, 0x00, 0x80, 0x10], false;
    e_0_1_7: "E-0-1-7", Alarm(17), 0x0000, [0x00, 0x00, 0x01, 0x11, 0x80, 0x00, 0x00, 0x00], 0x1180_0000, [0x00, 0x00, 0x80, 0x11], false;
    e_0_1_8: "E-0-1-8", Alarm(18), 0x0000, [0x00, 0x00, 0x01, 0x12, 0x80, 0x00, 0x00, 0x00], 0x1280_0000, [0x00, 0x00, 0x80, 0x12], false;
    e_0_1_9: "E-0-1-9", Alarm(19), 0x0000, [0x00, 0x00, 0x01, 0x13, 0x80, 0x00, 0x00, 0x00], 0x1380_0000, [0x00, 0x00, 0x80, 0x13], false;
    e_0_2_0: "E-0-2-0", Alarm(20), 0x1000, [0x00, 0x10, 0x01, 0x14, 0x80, 0x00, 0x00, 0x00], 0x1480_1000, [0x00, 0x10, 0x80, 0x14], true;
    e_0_2_1: "E-0-2-1", Alarm(21), 0x9000, [0x00, 0x90, 0x01, 0x15, 0x80, 0x00, 0x00, 0x00], 0x1580_9000, [0x00, 0x90, 0x80, 0x15], true;
    e_0_2_2: "E-0-2-2", Alarm(22), 0x9000, [0x00, 0x90, 0x01, 0x16, 0x80, 0x00, 0x00, 0x00], 0x1680_9000, [0x00, 0x90, 0x80, 0x16], true;
    e_0_2_3: "E-0-2-3", Alarm(23), 0x9000, [0x00, 0x90, 0x01, 0x17, 0x80, 0x00, 0x00, 0x00], 0x1780_9000, [0x00, 0x90, 0x80, 0x17], true;
    e_0_2_4: "E-0-2-4", Alarm(24), 0x1000, [0x00, 0x10, 0x01, 0x18, 0x80, 0x00, 0x00, 0x00], 0x1880_1000, [0x00, 0x10, 0x80, 0x18], true;
    e_0_2_5: "E-0-2-5", Alarm(25), 0x9000, [0x00, 0x90, 0x01, 0x19, 0x80, 0x00, 0x00, 0x00], 0x1980_9000, [0x00, 0x90, 0x80, 0x19], true;
    e_0_2_6: "E-0-2-6", Alarm(26), 0x0000, [0x00, 0x00, 0x01, 0x1A, 0x80, 0x00, 0x00, 0x00], 0x1A80_0000, [0x00, 0x00, 0x80, 0x1A], false;
    e_0_2_7: "E-0-2-7", Alarm(27), 0x0000, [0x00, 0x00, 0x01, 0x1B, 0x80, 0x00, 0x00, 0x00], 0x1B80_0000, [0x00, 0x00, 0x80, 0x1B], false;
    e_0_2_8: "E-0-2-8", Alarm(28), 0x1000, [0x00, 0x10, 0x01, 0x1C, 0x80, 0x00, 0x00, 0x00], 0x1C80_1000, [0x00, 0x10, 0x80, 0x1C], true;
    e_0_2_9: "E-0-2-9", Alarm(29), 0x9000, [0x00, 0x90, 0x01, 0x1D, 0x80, 0x00, 0x00, 0x00], 0x1D80_9000, [0x00, 0x90, 0x80, 0x1D], true;
    e_0_3_0: "E-0-3-0", Alarm(30), 0x8130, [0x30, 0x81, 0x01, 0x1E, 0x80, 0x00, 0x00, 0x00], 0x1E80_8130, [0x30, 0x81, 0x80, 0x1E], true;
    e_0_3_1: "E-0-3-1", Alarm(31), 0x1000, [0x00, 0x10, 0x01, 0x1F, 0x80, 0x00, 0x00, 0x00], 0x1F80_1000, [0x00, 0x10, 0x80, 0x1F], true;
    e_0_3_2: "E-0-3-2", Alarm(32), 0x8130, [0x30, 0x81, 0x01, 0x20, 0x80, 0x00, 0x00, 0x00], 0x2080_8130, [0x30, 0x81, 0x80, 0x20], true;
    e_0_3_3: "E-0-3-3", Alarm(33), 0x1000, [0x00, 0x10, 0x01, 0x21, 0x80, 0x00, 0x00, 0x00], 0x2180_1000, [0x00, 0x10, 0x80, 0x21], true;
    e_0_3_4: "E-0-3-4", Alarm(34), 0x1000, [0x00, 0x10, 0x01, 0x22, 0x80, 0x00, 0x00, 0x00], 0x2280_1000, [0x00, 0x10, 0x80, 0x22], true;
    e_0_3_5: "E-0-3-5", Alarm(35), 0x1000, [0x00, 0x10, 0x01, 0x23, 0x80, 0x00, 0x00, 0x00], 0x2380_1000, [0x00, 0x10, 0x80, 0x23], true;
    e_0_3_6: "E-0-3-6", Alarm(36), 0x9000, [0x00, 0x90, 0x01, 0x24, 0x80, 0x00, 0x00, 0x00], 0x2480_9000, [0x00, 0x90, 0x80, 0x24], true;
    e_0_3_7: "E-0-3-7", Alarm(37), 0x6000, [0x00, 0x60, 0x01, 0x25, 0x80, 0x00, 0x00, 0x00], 0x2580_6000, [0x00, 0x60, 0x80, 0x25], true;
    e_0_3_8: "E-0-3-8", Alarm(38), 0x9000, [0x00, 0x90, 0x01, 0x26, 0x80, 0x00, 0x00, 0x00], 0x2680_9000, [0x00, 0x90, 0x80, 0x26], true;
    e_0_3_9: "E-0-3-9", Alarm(39), 0x1000, [0x00, 0x10, 0x01, 0x27, 0x80, 0x00, 0x00, 0x00], 0x2780_1000, [0x00, 0x10, 0x80, 0x27], true;
    e_0_4_0: "E-0-4-0", Alarm(40), 0x1000, [0x00, 0x10, 0x01, 0x28, 0x80, 0x00, 0x00, 0x00], 0x2880_1000, [0x00, 0x10, 0x80, 0x28], true;
    e_0_4_1: "E-0-4-1", Alarm(41), 0x6000, [0x00, 0x60, 0x01, 0x29, 0x80, 0x00, 0x00, 0x00], 0x2980_6000, [0x00, 0x60, 0x80, 0x29], true;
    e_0_4_2: "E-0-4-2", Alarm(42), 0x6000, [0x00, 0x60, 0x01, 0x2A, 0x80, 0x00, 0x00, 0x00], 0x2A80_6000, [0x00, 0x60, 0x80, 0x2A], true;
    e_0_4_3: "E-0-4-3", Alarm(43), 0x9000, [0x00, 0x90, 0x01, 0x2B, 0x80, 0x00, 0x00, 0x00], 0x2B80_9000, [0x00, 0x90, 0x80, 0x2B], true;
    e_0_4_4: "E-0-4-4", Alarm(44), 0x9000, [0x00, 0x90, 0x01, 0x2C, 0x80, 0x00, 0x00, 0x00], 0x2C80_9000, [0x00, 0x90, 0x80, 0x2C], true;
    e_0_4_5: "E-0-4-5", Alarm(45), 0x9000, [0x00, 0x90, 0x01, 0x2D, 0x80, 0x00, 0x00, 0x00], 0x2D80_9000, [0x00, 0x90, 0x80, 0x2D], true;
    e_0_4_6: "E-0-4-6", Alarm(46), 0x8210, [0x10, 0x82, 0x01, 0x2E, 0x80, 0x00, 0x00, 0x00], 0x2E80_8210, [0x10, 0x82, 0x80, 0x2E], true;
    f_0_0_1: "F-0-0-1", Fault(1), 0x5000, [0x00, 0x50, 0x01, 0x01, 0xC0, 0x00, 0x00, 0x00], 0x01C0_5000, [0x00, 0x50, 0xC0, 0x01], true;
    f_0_0_2: "F-0-0-2", Fault(2), 0x5000, [0x00, 0x50, 0x01, 0x02, 0xC0, 0x00, 0x00, 0x00], 0x02C0_5000, [0x00, 0x50, 0xC0, 0x02], true;
    f_0_0_3: "F-0-0-3", Fault(3), 0x5000, [0x00, 0x50, 0x01, 0x03, 0xC0, 0x00, 0x00, 0x00], 0x03C0_5000, [0x00, 0x50, 0xC0, 0x03], true;
    f_0_0_4: "F-0-0-4", Fault(4), 0x5000, [0x00, 0x50, 0x01, 0x04, 0xC0, 0x00, 0x00, 0x00], 0x04C0_5000, [0x00, 0x50, 0xC0, 0x04], true;
    f_0_0_5: "F-0-0-5", Fault(5), 0x5000, [0x00, 0x50, 0x01, 0x05, 0xC0, 0x00, 0x00, 0x00], 0x05C0_5000, [0x00, 0x50, 0xC0, 0x05], true;
    f_0_0_6: "F-0-0-6", Fault(6), 0x5000, [0x00, 0x50, 0x01, 0x06, 0xC0, 0x00, 0x00, 0x00], 0x06C0_5000, [0x00, 0x50, 0xC0, 0x06], true;
}

#[test]
fn table_is_exactly_the_specification_rows() {
    assert_eq!(ALARMS_AND_FAULTS.len(), 47);
    assert_eq!(CASES.len(), 47);
    assert_eq!(
        ALARMS_AND_FAULTS.iter().filter(|e| e.is_alarm()).count(),
        41
    );
    assert_eq!(ALARMS_AND_FAULTS.iter().filter(|e| e.is_fault()).count(), 6);
    for row in ALARMS_AND_FAULTS {
        assert!(
            CASES.iter().any(|c| c.code == row.code),
            "{} has no test row",
            row.label
        );
        assert_eq!(
            ALARMS_AND_FAULTS
                .iter()
                .filter(|r| r.code == row.code)
                .count(),
            1,
            "{} listed twice",
            row.label
        );
        assert_eq!(format!("{}", row.code), row.label);
    }
    // The table is in code order.
    assert!(ALARMS_AND_FAULTS
        .windows(2)
        .all(|w| w[0].code.raw() < w[1].code.raw()));
    // Exactly the six `*` rows are 2060h-only, all with EEC 0000h.
    let starred: std::vec::Vec<&str> = ALARMS_AND_FAULTS
        .iter()
        .filter(|e| !e.in_1003h)
        .map(|e| e.label)
        .collect();
    assert_eq!(
        starred,
        ["E-0-1-6", "E-0-1-7", "E-0-1-8", "E-0-1-9", "E-0-2-6", "E-0-2-7"]
    );
    assert!(ALARMS_AND_FAULTS
        .iter()
        .all(|e| e.in_1003h != (e.eec == ErrorCode::NO_ERROR)));
}

/// The F-0-0-6 erratum ("Delta-Q IC Series CANopen interface
/// specification rev 2.0", section 4.4.1: the printed 1003h value has its
/// words swapped) and the lenient reading, which fixes only values of that
/// shape; encoding always gives the correct layout.
#[test]
fn error_field_erratum_and_the_lenient_reading() {
    type Reading = (ErrorCode, DeltaQCode);
    // (1003h value, its strict reading where named, its lenient reading;
    // `None` for the lenient: the strict one)
    let cases: [(u32, Option<Reading>, Option<Reading>); 10] = [
        // The correct 1003h value of F-0-0-6.
        (
            0x06C0_5000,
            Some((ErrorCode::DEVICE_HARDWARE, Fault(6))),
            None,
        ),
        // The document's printed value: strictly EEC 06C0h with code 0050h
        // (not a Delta-Q code); the lenient reading recognises it.
        (
            0x5000_06C0,
            Some((ErrorCode(0x06C0), Other(0x0050))),
            Some((ErrorCode::DEVICE_HARDWARE, Fault(6))),
        ),
        // Word-swapped E-0-3-2 (EEC 8130h) is fixed too.
        (0x8130_2080, None, Some((ErrorCode::HEARTBEAT, Alarm(32)))),
        // Swapped, a table code, but the EEC does not match: strict.
        (0x9000_06C0, None, None),
        // Swapped reading not in the table: strict.
        (0x5000_63C0, Some((ErrorCode(0x63C0), Other(0x0050))), None),
        // Empty and foreign entries stay as they are.
        (0, None, None),
        (0xFFFF_FFFF, None, None),
        (0x0000_8130, None, None),
        (0x1234_5678, None, None),
        (0x0580_9000, None, None),
    ];
    for (field, strict, lenient) in cases {
        let read = DeltaQCode::from_error_field(field);
        if let Some(want) = strict {
            assert_eq!(read, want, "{field:#010x}");
        }
        let want = lenient.unwrap_or(read);
        assert_eq!(
            DeltaQCode::from_error_field_lenient(field),
            want,
            "{field:#010x}"
        );
    }
    assert_eq!(
        Fault(6).to_error_field(ErrorCode::DEVICE_HARDWARE),
        0x06C0_5000
    );
}

/// Two EMCY frames of the real startup capture (tests/data/CAPTURES.md).
#[test]
fn capture_emcy_frames() {
    // 08A#3081012080000000: E-0-3-2 heartbeat lost.
    let e = Emergency::parse(&[0x30, 0x81, 0x01, 0x20, 0x80, 0x00, 0x00, 0x00]).unwrap();
    assert_eq!(e.code, ErrorCode::HEARTBEAT);
    let c = DeltaQCode::from_emergency(&e);
    assert_eq!(c, Alarm(32));
    assert_eq!(c, DeltaQCode::HEARTBEAT_LOST);
    assert_eq!(format!("{c}"), "E-0-3-2");
    assert_eq!(c.description(), Some("heartbeat lost"));
    assert_eq!(c.to_emergency(e.code, e.register), e);
    // 08A#3081011E80000000: E-0-3-0 battery module communication error.
    let e = Emergency::parse(&[0x30, 0x81, 0x01, 0x1E, 0x80, 0x00, 0x00, 0x00]).unwrap();
    let c = DeltaQCode::from_emergency(&e);
    assert_eq!(c, Alarm(30));
    assert_eq!(c, DeltaQCode::BATTERY_MODULE_COMMUNICATION);
    assert_eq!(format!("{c}"), "E-0-3-0");
    // 08A#0000000000000000: error reset, no Delta-Q code.
    let e = Emergency::parse(&[0; 8]).unwrap();
    assert!(e.is_reset());
    let c = DeltaQCode::from_emergency(&e);
    assert_eq!(c, Other(0));
    assert_eq!(c, DeltaQCode::NONE);
    assert_eq!(c, DeltaQCode::default());
    assert_eq!(c.entry(), None);
    assert_eq!(format!("{c}"), "0x0000");
    assert_eq!(
        c.to_emergency(ErrorCode::NO_ERROR, ErrorRegister::empty()),
        e
    );
}

#[test]
fn capture_2060h_no_error() {
    // 38A#00000000BA07FF00: 2060h = 0, no error displayed.
    assert_eq!(
        DeltaQCode::from_error_field(0),
        (ErrorCode::NO_ERROR, DeltaQCode::NONE)
    );
}

#[test]
fn emcy_ignores_manufacturer_bytes_2_to_4() {
    let e = Emergency::parse(&[0x00, 0x50, 0x81, 0x06, 0xC0, 0xAA, 0xBB, 0xCC]).unwrap();
    assert_eq!(DeltaQCode::from_emergency(&e), Fault(6));
}

#[test]
fn from_raw_raw_round_trip_every_u16() {
    for raw in 0..=u16::MAX {
        let c = DeltaQCode::from_raw(raw);
        assert_eq!(c.raw(), raw);
        assert_eq!(c.canonical(), c);
        assert_eq!(u16::from(DeltaQCode::from(raw)), raw);
        match raw >> 8 {
            0x80 => assert_eq!(c, Alarm(raw as u8)),
            0xC0 => assert_eq!(c, Fault(raw as u8)),
            _ => assert_eq!(c, Other(raw)),
        }
        assert_eq!(c.is_alarm(), raw >> 8 == 0x80);
        assert_eq!(c.is_fault(), raw >> 8 == 0xC0);
        // EMCY and 1003h round trips for every code.
        let eec = ErrorCode(raw.rotate_left(3));
        let e = c.to_emergency(eec, ErrorRegister::GENERIC);
        assert_eq!(DeltaQCode::from_emergency(&e), c);
        assert_eq!(
            DeltaQCode::from_error_field(c.to_error_field(eec)),
            (eec, c)
        );
    }
}

#[test]
fn from_error_field_round_trips_sampled_u32() {
    let mut v: u32 = 0x1234_5678;
    for _ in 0..100_000 {
        v = v.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let (eec, code) = DeltaQCode::from_error_field(v);
        assert_eq!(code.to_error_field(eec), v);
    }
    for v in [0, u32::MAX, 0x8000_0000, 0x0000_FFFF] {
        let (eec, code) = DeltaQCode::from_error_field(v);
        assert_eq!(code.to_error_field(eec), v);
    }
}

#[test]
fn display_texts() {
    assert_eq!(format!("{}", Alarm(32)), "E-0-3-2");
    assert_eq!(format!("{}", Fault(6)), "F-0-0-6");
    assert_eq!(format!("{}", Alarm(0)), "E-0-0-0");
    // Not in the table but in the numbering: still a label.
    assert_eq!(format!("{}", Alarm(5)), "E-0-0-5");
    assert_eq!(Alarm(5).entry(), None);
    assert_eq!(format!("{}", Fault(99)), "F-0-9-9");
    // Numbers above 99 and Other: raw hex.
    assert_eq!(format!("{}", Alarm(100)), "0x8064");
    assert_eq!(format!("{}", Fault(255)), "0xC0FF");
    assert_eq!(format!("{}", Other(0x1234)), "0x1234");
    assert_eq!(format!("{}", Other(0xABCD)), "0xABCD");
    assert_eq!(format!("{}", Other(0)), "0x0000");
    // A hand-built non-canonical Other displays as its canonical form.
    assert_eq!(format!("{}", Other(0x8020)), "E-0-3-2");
    assert_eq!(Other(0x8020).canonical(), Alarm(32));
    assert_eq!(Other(0x8020).entry(), Alarm(32).entry());
}

#[test]
fn label_parts_and_constructors() {
    assert_eq!(Alarm(32).label_parts(), Some(('E', 3, 2)));
    assert_eq!(Fault(6).label_parts(), Some(('F', 0, 6)));
    assert_eq!(Alarm(100).label_parts(), None);
    assert_eq!(Other(7).label_parts(), None);
    assert_eq!(DeltaQCode::alarm(3, 2), Some(Alarm(32)));
    assert_eq!(DeltaQCode::fault(0, 6), Some(Fault(6)));
    assert_eq!(DeltaQCode::alarm(10, 0), None);
    assert_eq!(DeltaQCode::fault(0, 10), None);
    assert_eq!(DeltaQCode::from_label("E-0-4-6"), Some(Alarm(46)));
    assert_eq!(DeltaQCode::from_label("F-0-0-6"), Some(Fault(6)));
    for bad in [
        "", "E", "E-0-3-", "E-1-3-2", "e-0-3-2", "X-0-3-2", "E-0-A-2", "E-0-3-2 ", "E_0_3_2",
        "0x8020", "E-0-3-:", "E-0-/-2",
    ] {
        assert_eq!(DeltaQCode::from_label(bad), None, "{bad:?}");
    }
}

#[test]
fn display_round_trips_through_from_label() {
    for n in 0..=99u8 {
        for c in [Alarm(n), Fault(n)] {
            let text = format!("{c}");
            assert_eq!(DeltaQCode::from_label(&text), Some(c));
        }
    }
}
