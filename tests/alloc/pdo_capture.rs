//! The real Delta-Q ICL1500 capture's PDOs decoded with the mapping
//! tests/data/CAPTURES.md gives (the captures are read from the shared data
//! folder beside the checkout: `common::captures`), through
//! the public API only. Expected numbers are worked out by hand from the
//! bytes (little-endian, fields packed in mapping order).

use crate::common;

use canopen_codec::cia418::{BatteryStatus, BATTERY_MODULE_CATALOGUE, BATTERY_STATUS_FLAGS};
use canopen_codec::deltaq::{
    ChargeIndication, ChargeStatusFlags, ChargeType, DisplayedError, ExtendedChargeStatus,
    ExternalOverride, OverrideSource, CHARGER_CATALOGUE, DISPLAYED_ERROR_FORMAT,
    EXTENDED_CHARGE_STATUS_FLAGS, EXTERNAL_OVERRIDE_FLAGS,
};
use canopen_codec::pdo::{
    FieldValue, Fixed, Flags, Formatted, MappingEntry, NamedField, NamedFields, PdoMapping, Unit,
};
use canopen_codec::trace::candump::parse_line;
use canopen_codec::{CanFrame, Message};

/// tests/data/CAPTURES.md: (COB-ID, entries as (index, sub, bits)). The
/// README's unnamed padding is mapped with CiA 301 dummy entries (0005h
/// UNSIGNED8, 0006h UNSIGNED16); where it names 2FFAh:01 that is used.
/// (index, sub-index, bits).
type Entry = (u16, u8, u8);

const CAPTURE_MAPPING: &[(u16, &[Entry])] = &[
    (
        0x18A,
        &[
            (0x2002, 0, 16),
            (0x2101, 0, 16),
            (0x2006, 0, 16),
            (0x0006, 0, 16),
        ],
    ),
    (
        0x38A,
        &[
            (0x2060, 0, 32),
            (0x2200, 0, 16),
            (0x6080, 0, 8),
            (0x0005, 0, 8),
        ],
    ),
    (
        0x20A,
        &[
            (0x2FFA, 1, 8),
            (0x6081, 0, 8),
            (0x4201, 0, 8),
            (0x2276, 0, 16),
            (0x6070, 0, 16),
            (0x6000, 0, 8),
        ],
    ),
    (
        0x30A,
        &[
            (0x2FFA, 1, 8),
            (0x2FFA, 1, 8),
            (0x2002, 0, 16),
            (0x2101, 0, 16),
            (0x6010, 0, 16),
        ],
    ),
];

fn mapping_of(cob_id: u16) -> Option<PdoMapping> {
    let (_, entries) = CAPTURE_MAPPING.iter().find(|(id, _)| *id == cob_id)?;
    let e: Vec<MappingEntry> = entries
        .iter()
        .map(|&(i, s, b)| MappingEntry::new(i, s, b))
        .collect();
    Some(PdoMapping::new(&e).unwrap())
}

/// Decodes one capture line (`ID#DATA`) with the capture mapping; the
/// frames all belong to the charger (node 0x0A), so its catalogue applies.
fn decode(line: &str) -> NamedFields {
    let parsed = parse_line(line).unwrap();
    let frame: CanFrame = parsed.frame;
    let payload = match Message::decode(&frame).unwrap() {
        Message::Tpdo { payload, .. } | Message::Rpdo { payload, .. } => payload,
        other => panic!("not a PDO: {other:?}"),
    };
    let id = match frame.id() {
        canopen_codec::CanId::Standard(id) => id,
        other => panic!("{other:?}"),
    };
    let m = mapping_of(id).unwrap();
    let fields = CHARGER_CATALOGUE.decode(&m, payload.as_slice());
    assert_eq!(fields.unmapped_bytes(), 0);
    fields
}

fn scaled(raw: i64, q: u8, unit: Unit) -> FieldValue {
    FieldValue::Scaled {
        value: Fixed::new(raw, q),
        unit: Some(unit),
    }
}

fn check(fields: &NamedFields, want: &[(u16, u8, &str, u64, FieldValue)]) {
    let got: Vec<(u16, u8, &str, u64, FieldValue)> = fields
        .iter()
        .map(|f: &NamedField| (f.entry.index, f.entry.sub, f.name, f.raw, f.value))
        .collect();
    assert_eq!(got, want);
}

#[test]
fn charger_tpdo0_worked_example() {
    // 74 13 | 45 4E | 70 00 | 00 00
    let f = decode("18A#7413454E70000000");
    check(
        &f,
        &[
            // 0x1374 / 256 = 19.453125 A
            (
                0x2002,
                0,
                "charging current",
                0x1374,
                scaled(0x1374, 8, Unit::Ampere),
            ),
            // 0x4E45 / 256 = 78.26953125 V
            (
                0x2101,
                0,
                "battery voltage",
                0x4E45,
                scaled(0x4E45, 8, Unit::Volt),
            ),
            (
                0x2006,
                0,
                "extended charge status",
                0x0070,
                FieldValue::Flags(Flags::new(
                    &EXTENDED_CHARGE_STATUS_FLAGS,
                    u64::from(
                        ExtendedChargeStatus {
                            charge_type: ChargeType::None,
                            indication: ChargeIndication::Inactive,
                            override_source: OverrideSource::External,
                            flags: ChargeStatusFlags::AC_PRESENT
                                | ChargeStatusFlags::CHARGER_ENABLED,
                        }
                        .to_u16(),
                    ),
                )),
            ),
            (0x0006, 0, "padding", 0, FieldValue::Padding),
        ],
    );
    let s = f.as_slice();
    assert_eq!(s[0].value.number().unwrap().to_f64(), 19.453125);
    assert_eq!(s[1].value.number().unwrap().to_f64(), 78.26953125);
    assert_eq!(
        format!("{f:.2}"),
        "2002h charging current 19.45 A; 2101h battery voltage 78.27 V; \
         2006h extended charge status: AC present, charger enabled, override external (BMS); \
         0006h padding (16 bits)"
    );
}

#[test]
fn charger_tpdo2_worked_example() {
    // 00 00 00 00 | BA 07 | FF | 00
    let f = decode("38A#00000000BA07FF00");
    check(
        &f,
        &[
            (
                0x2060,
                0,
                "displayed error",
                0,
                FieldValue::Formatted(Formatted {
                    format: &DISPLAYED_ERROR_FORMAT,
                    raw: u64::from(DisplayedError::NONE.to_u32()),
                }),
            ),
            // 0x07BA / 16 = 123.625 V
            (
                0x2200,
                0,
                "AC voltage",
                0x07BA,
                scaled(0x07BA, 4, Unit::Volt),
            ),
            (
                0x6080,
                0,
                "charger state of charge",
                0xFF,
                FieldValue::Invalid,
            ),
            (0x0005, 0, "padding", 0, FieldValue::Padding),
        ],
    );
    assert_eq!(f.as_slice()[1].value.number().unwrap().to_f64(), 123.625);
    assert_eq!(
        format!("{f:.1}"),
        "2060h displayed error: none; 2200h AC voltage 123.6 V; \
         6080h charger state of charge: invalid (raw FFh); 0005h padding (8 bits)"
    );
}

#[test]
fn charger_rpdo0_from_the_bms() {
    // 00 | 4C | 01 | 00 52 | A0 00 | 01
    let f = decode("20A#004C010052A00001");
    check(
        &f,
        &[
            (0x2FFA, 1, "padding", 0, FieldValue::Padding),
            // 0x4C = 76 %
            (
                0x6081,
                0,
                "battery state of charge",
                76,
                scaled(76, 0, Unit::Percent),
            ),
            (
                0x4201,
                0,
                "external override",
                1,
                FieldValue::Flags(Flags::new(
                    &EXTERNAL_OVERRIDE_FLAGS,
                    u64::from(ExternalOverride::EQUALIZE.bits()),
                )),
            ),
            // 0x5200 / 256 = 82 V
            (
                0x2276,
                0,
                "voltage request",
                0x5200,
                scaled(0x5200, 8, Unit::Volt),
            ),
            // 0x00A0 / 16 = 10 A
            (
                0x6070,
                0,
                "charge current requested",
                0xA0,
                scaled(0xA0, 4, Unit::Ampere),
            ),
            (
                0x6000,
                0,
                "battery status",
                1,
                FieldValue::Flags(Flags::new(
                    &BATTERY_STATUS_FLAGS,
                    u64::from(BatteryStatus::READY_TO_CHARGE.bits()),
                )),
            ),
        ],
    );
    assert_eq!(
        format!("{f:.2}"),
        "2FFAh:01 padding (8 bits); 6081h battery state of charge 76.00 %; \
         4201h external override: equalize; 2276h voltage request 82.00 V; \
         6070h charge current requested 10.00 A; 6000h battery status: ready to charge"
    );
}

#[test]
fn charger_rpdo1_from_the_bms() {
    // 00 | 00 | 00 00 | 00 4E | 30 02
    let f = decode("30A#00000000004E3002");
    let temperature = (
        0x6010,
        0,
        "temperature",
        0x0230,
        scaled(0x230, 3, Unit::DegreeCelsius),
    );
    check(
        &f,
        &[
            (0x2FFA, 1, "padding", 0, FieldValue::Padding),
            (0x2FFA, 1, "padding", 0, FieldValue::Padding),
            (0x2002, 0, "charging current", 0, scaled(0, 8, Unit::Ampere)),
            // 0x4E00 / 256 = 78 V
            (
                0x2101,
                0,
                "battery voltage",
                0x4E00,
                scaled(0x4E00, 8, Unit::Volt),
            ),
            // 0x0230 = 560 * 0.125 = 70 degC per CiA 418 (the integrator's
            // DBC would subtract 40: 30 degC).
            temperature,
        ],
    );
    assert_eq!(f.as_slice()[4].value.number().unwrap().to_f64(), 70.0);

    // 00 | 00 | 00 0A | 00 52 | 30 02
    let f = decode("30A#0000000A00523002");
    check(
        &f,
        &[
            (0x2FFA, 1, "padding", 0, FieldValue::Padding),
            (0x2FFA, 1, "padding", 0, FieldValue::Padding),
            // 0x0A00 / 256 = 10 A
            (
                0x2002,
                0,
                "charging current",
                0x0A00,
                scaled(0x0A00, 8, Unit::Ampere),
            ),
            // 0x5200 / 256 = 82 V
            (
                0x2101,
                0,
                "battery voltage",
                0x5200,
                scaled(0x5200, 8, Unit::Volt),
            ),
            temperature,
        ],
    );
    assert_eq!(
        f.to_string(),
        "2FFAh:01 padding (8 bits); 2FFAh:01 padding (8 bits); 2002h charging current 10 A; \
         2101h battery voltage 82 V; 6010h temperature 70 degC"
    );
}

/// Every mapped PDO of both captures decodes fully (no missing, unknown or
/// wrongly sized field), and the charging log's current sits near 19.5 A.
#[test]
fn whole_captures_decode() {
    let (Some(startup), Some(charging)) = (
        common::captures::text(common::captures::STARTUP),
        common::captures::text(common::captures::CHARGING),
    ) else {
        return;
    };
    for (log, min_frames) in [(startup.as_str(), 500), (charging.as_str(), 300)] {
        let mut decoded = 0;
        for line in log.lines() {
            let parsed = parse_line(line).unwrap();
            let canopen_codec::CanId::Standard(id) = parsed.frame.id() else {
                continue;
            };
            if mapping_of(id).is_none() {
                continue;
            }
            let f = decode(line);
            for field in &f {
                assert!(
                    !matches!(
                        field.value,
                        FieldValue::Missing | FieldValue::Raw | FieldValue::WrongWidth { .. }
                    ),
                    "{line}: {field}"
                );
            }
            if id == 0x18A {
                let amps = f.as_slice()[0].value.number().unwrap().to_f64();
                assert!((0.0..=20.0).contains(&amps), "{line}: {amps}");
            }
            decoded += 1;
        }
        assert!(decoded >= min_frames, "{decoded}");
    }
    let amps: Vec<f64> = charging
        .lines()
        .filter(|l| l.contains(" 18A#"))
        .map(|l| decode(l).as_slice()[0].value.number().unwrap().to_f64())
        .collect();
    let mean = amps.iter().sum::<f64>() / amps.len() as f64;
    assert!((19.0..20.0).contains(&mean), "{mean}");
}

// ---------------------------------------------------------------------------
// No allocation: decoding and formatting fields never touch the heap.
// ---------------------------------------------------------------------------

use std::hint::black_box;

use crate::counting::allocations;

/// A `fmt::Write` that discards.
struct Sink;
impl std::fmt::Write for Sink {
    fn write_str(&mut self, _: &str) -> std::fmt::Result {
        Ok(())
    }
}

#[test]
fn decoding_and_display_do_not_allocate() {
    use std::fmt::Write as _;
    let frames: Vec<(PdoMapping, [u8; 8])> = [
        (0x18A, [0x74, 0x13, 0x45, 0x4E, 0x70, 0, 0, 0]),
        (0x38A, [0, 0, 0, 0, 0xBA, 0x07, 0xFF, 0]),
        (0x20A, [0, 0x4C, 0x01, 0, 0x52, 0xA0, 0, 0x01]),
        (0x30A, [0, 0, 0, 0x0A, 0, 0x52, 0x30, 0x02]),
    ]
    .into_iter()
    .map(|(id, data)| (mapping_of(id).unwrap(), data))
    .collect();
    let before = allocations();
    for (m, data) in &frames {
        for cat in [CHARGER_CATALOGUE, BATTERY_MODULE_CATALOGUE] {
            let fields = black_box(cat.decode(black_box(m), black_box(data)));
            write!(Sink, "{fields} {fields:.2} {fields:#.2}").unwrap();
            for f in &fields {
                write!(Sink, "{} {}", f.value, f.value.kind()).unwrap();
            }
        }
    }
    assert_eq!(allocations(), before);
}
