//! Tests of the Delta-Q manufacturer object values.

use super::*;
use crate::deltaq::{index, timeouts};
use crate::emcy::ErrorCode;

/// The capture's charger TPDO 0 `18A#7413454E70000000` and TPDO 2
/// `38A#00000000BA07FF00` (the worked example of tests/data/CAPTURES.md).
#[test]
fn capture_worked_example() {
    assert_eq!(
        ChargingCurrent::decode(&[0x74, 0x13]),
        Ok(ChargingCurrent::from_raw(0x1374))
    );
    let i = ChargingCurrent::from_raw(0x1374).unwrap();
    assert_eq!(i.raw(), 0x1374);
    assert_eq!(i.as_f64(), 19.453125);
    assert_eq!(i.as_f32(), 19.453125f32);
    assert_eq!(i.milliamps(), 19_453);
    assert_eq!(format!("{i}"), "19.453125 A");
    let v = BatteryVoltage::decode(&[0x45, 0x4E]).unwrap().unwrap();
    assert_eq!(v.raw(), 0x4E45);
    assert_eq!(v.millivolts(), 78_270); // 78.26953125 V
    let s = ExtendedChargeStatus::decode(&[0x70, 0x00]).unwrap();
    assert_eq!(s.to_u16(), 0x0070);
    // 2060h: nothing displayed.
    let e = DisplayedError::decode(&[0x00, 0x00, 0x00, 0x00]).unwrap();
    assert!(e.is_none());
    assert_eq!(e, DisplayedError::NONE);
    assert_eq!(e.entry(), None);
    // 2200h: 0x07BA / 16 = 123.625 V.
    let ac = AcVoltage::decode(&[0xBA, 0x07]).unwrap().unwrap();
    assert_eq!(ac.millivolts(), 123_625);
    assert_eq!(ac.as_f64(), 123.625);
    assert_eq!(format!("{ac}"), "123.625 V");
}

/// A 2006h value by its fields.
const fn status(
    charge_type: ChargeType,
    indication: ChargeIndication,
    override_source: OverrideSource,
    flags: u8,
) -> ExtendedChargeStatus {
    ExtendedChargeStatus {
        charge_type,
        indication,
        override_source,
        flags: ChargeStatusFlags::from_bits_retain(flags),
    }
}

use ChargeStatusFlags as F;

/// 2006h words and their fields; unknown values are kept.
#[rustfmt::skip]
const EXTENDED_CHARGE_STATUS: &[(u16, ExtendedChargeStatus)] = &[
    (0x0070, status(ChargeType::None, ChargeIndication::Inactive, OverrideSource::External,
        F::AC_PRESENT.bits() | F::CHARGER_ENABLED.bits())),
    (0x1423, status(ChargeType::Normal, ChargeIndication::Complete, OverrideSource::Internal,
        F::CHARGER_ENABLED.bits() | F::ALARM_ACTIVE.bits() | F::FAULT_ACTIVE.bits())),
    (0x271C, status(ChargeType::Maintenance, ChargeIndication::PowerSupplyMode, OverrideSource::Internal,
        F::AC_PRESENT.bits() | F::DERATING.bits() | F::HW_SHUTDOWN.bits())),
    (0xF8C0, status(ChargeType::Other(15), ChargeIndication::Other(8), OverrideSource::Other(3), 0)),
];

#[test]
fn extended_charge_status_fields() {
    for &(raw, want) in EXTENDED_CHARGE_STATUS {
        let s = ExtendedChargeStatus::from_u16(raw);
        assert_eq!(s, want, "{raw:04X}h");
        assert_eq!(s.to_u16(), raw, "{raw:04X}h");
        assert_eq!(s.encode(), raw.to_le_bytes(), "{raw:04X}h");
    }
    // Indications 1..=7 by name.
    let names = [
        ChargeIndication::Below80,
        ChargeIndication::Above80,
        ChargeIndication::Finishing,
        ChargeIndication::Complete,
        ChargeIndication::Resting,
        ChargeIndication::Equalize,
        ChargeIndication::PowerSupplyMode,
    ];
    for (i, ind) in (1u16..).zip(names) {
        assert_eq!(ExtendedChargeStatus::from_u16(i << 8).indication, ind);
    }
    // Out-of-range hand-built Other values are masked on encode.
    let s = ExtendedChargeStatus {
        charge_type: ChargeType::Other(0x13),
        indication: ChargeIndication::Other(0x1F),
        override_source: OverrideSource::Other(6),
        flags: ChargeStatusFlags::from_bits_retain(0xC1),
    };
    assert_eq!(s.to_u16(), 0x3F81);
}

#[test]
fn extended_charge_status_round_trip_every_u16() {
    for raw in 0..=u16::MAX {
        let s = ExtendedChargeStatus::from_u16(raw);
        assert_eq!(s.to_u16(), raw);
        assert_eq!(u16::from(ExtendedChargeStatus::from(raw)), raw);
        assert_eq!(ExtendedChargeStatus::decode(&raw.to_le_bytes()), Ok(s));
        assert_eq!(s.encode(), raw.to_le_bytes());
    }
}

macro_rules! u16_scaled_round_trip {
    ($t:ty, $milli:ident, $from_milli:ident, $exact_milli:literal) => {
        for raw in 0..=u16::MAX {
            let v = <$t>::from_raw(raw);
            assert_eq!(<$t>::encode_raw(v), raw);
            assert_eq!(<$t>::decode(&raw.to_le_bytes()), Ok(v));
            assert_eq!(<$t>::encode(v), raw.to_le_bytes());
            let Some(v) = v else {
                assert_eq!(raw, 0xFFFF);
                continue;
            };
            assert_eq!(v.raw(), raw);
            let step = 1u64 << <$t>::FRAC_BITS;
            // Milli-units within half a milli-unit of the exact value.
            let m = u64::from(v.$milli());
            let err = (m * step).abs_diff(u64::from(raw) * 1000);
            assert!(2 * err <= step, "{} {raw}", stringify!($t));
            if $exact_milli {
                assert_eq!(<$t>::$from_milli(v.$milli()), Some(v));
            }
            assert_eq!(v.as_f64() * step as f64, f64::from(raw));
            assert_eq!(f64::from(v.as_f32()), v.as_f64());
        }
    };
}

#[test]
fn scaled_u16_round_trip_every_value() {
    u16_scaled_round_trip!(ChargingCurrent, milliamps, from_milliamps, true);
    u16_scaled_round_trip!(BatteryVoltageLegacy, millivolts, from_millivolts, false);
    u16_scaled_round_trip!(BatteryVoltage, millivolts, from_millivolts, true);
    u16_scaled_round_trip!(AcVoltage, millivolts, from_millivolts, true);
    u16_scaled_round_trip!(VoltageRequest16, millivolts, from_millivolts, true);
    u16_scaled_round_trip!(ChargerAhReturned, milliamp_hours, from_milliamp_hours, true);
}

#[test]
fn sentinels_are_no_value() {
    assert_eq!(ChargingCurrent::from_raw(0xFFFF), None);
    assert_eq!(ChargingCurrent::decode(&[0xFF, 0xFF]), Ok(None));
    assert_eq!(ChargingCurrent::encode(None), [0xFF, 0xFF]);
    assert_eq!(BatteryVoltageLegacy::decode(&[0xFF, 0xFF]), Ok(None));
    assert_eq!(BatteryVoltage::decode(&[0xFF, 0xFF]), Ok(None));
    assert_eq!(AcVoltage::decode(&[0xFF, 0xFF]), Ok(None));
    assert_eq!(VoltageRequest16::decode(&[0xFF, 0xFF]), Ok(None));
    assert_eq!(VoltageRequest16::encode(None), [0xFF, 0xFF]);
    assert_eq!(ChargerAhReturned::decode(&[0xFF, 0xFF]), Ok(None));
    assert_eq!(ChargerAhReturned::encode_raw(None), 0xFFFF);
    assert_eq!(VoltageRequest::from_raw(0xFFFF_FFFF), None);
    assert_eq!(VoltageRequest::decode(&[0xFF; 4]), Ok(None));
    assert_eq!(VoltageRequest::encode(None), [0xFF; 4]);
    assert_eq!(VoltageRequest::encode_raw(None), 0xFFFF_FFFF);
    assert_eq!(AlgorithmRequest::from_u32(0xFFFF_FFFF), None);
    assert_eq!(AlgorithmRequest::decode(&[0xFF; 4]), Ok(None));
    assert_eq!(AlgorithmRequest::encode(None), [0xFF; 4]);
    assert_eq!(AlgorithmRequest::encode_raw(None), 0xFFFF_FFFF);
    // One below the sentinel is a real value.
    assert_eq!(
        ChargingCurrent::from_raw(0xFFFE),
        Some(ChargingCurrent::MAX)
    );
    assert_eq!(ChargingCurrent::MAX.milliamps(), 255_992);
    assert_eq!(
        VoltageRequest::from_raw(0xFFFF_FFFE),
        Some(VoltageRequest::MAX)
    );
    assert_eq!(VoltageRequest::MAX.millivolts(), 4_194_303_998);
    // 6052h default 0xFFFF; 8 Ah = 64 steps, exact.
    assert_eq!(
        ChargerAhReturned::from_raw(64).unwrap().milliamp_hours(),
        8_000
    );
    assert_eq!(
        ChargerAhReturned::from_milliamp_hours(8_125).map(ChargerAhReturned::raw),
        Some(65)
    );
}

#[test]
fn from_milli_rounds_and_rejects_overflow() {
    // 19.45 A -> 4979.2 steps -> 4979.
    assert_eq!(
        ChargingCurrent::from_milliamps(19_450).map(|v| v.raw()),
        Some(4979)
    );
    assert_eq!(
        ChargingCurrent::from_milliamps(0),
        Some(ChargingCurrent::ZERO)
    );
    // 255.992 A is the largest value; 255.996 A would round onto the sentinel.
    assert_eq!(
        ChargingCurrent::from_milliamps(255_992),
        Some(ChargingCurrent::MAX)
    );
    assert_eq!(ChargingCurrent::from_milliamps(255_996), None);
    assert_eq!(ChargingCurrent::from_milliamps(u32::MAX), None);
    // 2100h: 48 V = 49152 steps of 1/1024 V.
    let v = BatteryVoltageLegacy::from_millivolts(48_000).unwrap();
    assert_eq!(v.raw(), 49_152);
    assert_eq!(v.as_f64(), 48.0);
    assert_eq!(BatteryVoltageLegacy::from_millivolts(64_000), None);
    // 2271h: 54.6 V -> 55910.4 -> 55910.
    let r = VoltageRequest::from_millivolts(54_600).unwrap();
    assert_eq!(r.raw(), 55_910);
    assert_eq!(r.millivolts(), 54_600);
    assert_eq!(VoltageRequest::encode(Some(r)), [0x66, 0xDA, 0x00, 0x00]);
    assert!(VoltageRequest::from_millivolts(u32::MAX).is_none());
    // 2276h: 54.6 V -> 13977.6 -> 13978 (0x369A).
    let r = VoltageRequest16::from_millivolts(54_600).unwrap();
    assert_eq!(VoltageRequest16::encode(Some(r)), [0x9A, 0x36]);
}

#[test]
fn voltage_request_u32_round_trips() {
    let mut raw: u32 = 0xDEAD_BEEF;
    for _ in 0..100_000 {
        raw = raw.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let v = VoltageRequest::from_raw(raw);
        assert_eq!(VoltageRequest::encode_raw(v), raw);
        assert_eq!(VoltageRequest::decode(&raw.to_le_bytes()), Ok(v));
        if let Some(v) = v {
            let err = (u64::from(v.millivolts()) * 1024).abs_diff(u64::from(raw) * 1000);
            assert!(err <= 512);
            assert_eq!(v.as_f64() * 1024.0, f64::from(raw));
        }
    }
}

#[test]
fn algorithm_request() {
    let r = AlgorithmRequest::from_u32(0x8000_000B).unwrap();
    assert_eq!(
        r,
        AlgorithmRequest {
            algorithm: 11,
            variant: 0,
            reserved: 0,
            revert_after_ac_loss: false,
            store_permanently: true,
        }
    );
    assert_eq!(AlgorithmRequest::encode(Some(r)), [0x0B, 0x00, 0x00, 0x80]);
    assert_eq!(
        AlgorithmRequest::decode(&[0x0B, 0x00, 0x00, 0x80]),
        Ok(Some(r))
    );
    let r = AlgorithmRequest::from_u32(0x7F03_0102).unwrap();
    assert_eq!(r.algorithm, 0x0102);
    assert_eq!(r.variant, 3);
    assert_eq!(r.reserved, 0x3F);
    assert!(r.revert_after_ac_loss);
    assert!(!r.store_permanently);
    assert_eq!(r.to_u32(), 0x7F03_0102);
    // Every field at its maximum is the sentinel.
    let all = AlgorithmRequest {
        algorithm: 0xFFFF,
        variant: 0xFF,
        reserved: 0x3F,
        revert_after_ac_loss: true,
        store_permanently: true,
    };
    assert_eq!(all.to_u32(), AlgorithmRequest::NO_VALUE);
    // Reserved bits beyond 6 are masked on encode.
    let r = AlgorithmRequest {
        reserved: 0xFF,
        ..AlgorithmRequest::new(1)
    };
    assert_eq!(r.to_u32(), 0x3F00_0001);
    let mut raw: u32 = 1;
    for _ in 0..100_000 {
        raw = raw.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        assert_eq!(
            AlgorithmRequest::encode_raw(AlgorithmRequest::from_u32(raw)),
            raw
        );
    }
}

#[test]
fn displayed_error() {
    let e = DisplayedError::decode(&[0x30, 0x81, 0x80, 0x20]).unwrap();
    assert_eq!(e.eec, ErrorCode::HEARTBEAT);
    assert_eq!(e.code, DeltaQCode::Alarm(32));
    assert_eq!(e.entry().map(|r| r.label), Some("E-0-3-2"));
    assert!(!e.is_none());
    assert_eq!(e.encode(), [0x30, 0x81, 0x80, 0x20]);
    // A 2060h-only alarm (EEC 0000h, `*` in the table) is not "none".
    let e = DisplayedError::from_u32(0x1080_0000);
    assert_eq!(e.code, DeltaQCode::Alarm(16));
    assert!(!e.is_none());
    assert_eq!(e.entry().map(|r| r.in_1003h), Some(false));
    let mut raw: u32 = 7;
    for _ in 0..100_000 {
        raw = raw.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        assert_eq!(DisplayedError::from_u32(raw).to_u32(), raw);
    }
}

#[test]
fn bitflag_objects_keep_every_bit() {
    for raw in 0..=u8::MAX {
        assert_eq!(DerateReasons::from_bits_retain(raw).bits(), raw);
        assert_eq!(ExternalOverride::from_bits_retain(raw).bits(), raw);
    }
    assert_eq!(DerateReasons::all().bits(), 0x0F);
    assert_eq!(
        DerateReasons::from_bits_retain(0x05),
        DerateReasons::AC_VOLTAGE | DerateReasons::TEMPERATURE
    );
    assert_eq!(
        DerateReasons::BATTERY_VOLTAGE | DerateReasons::AC_CURRENT_LIMIT,
        DerateReasons::from_bits_retain(0x0A)
    );
    assert_eq!(ExternalOverride::EQUALIZE.bits(), 0x01);
    assert_eq!(ExternalOverride::MAINTENANCE.bits(), 0x02);
}

#[test]
fn wrong_lengths_are_errors() {
    crate::error::assert_exact_length(ChargingCurrent::decode, 2);
    crate::error::assert_exact_length(BatteryVoltage::decode, 2);
    crate::error::assert_exact_length(VoltageRequest::decode, 4);
    crate::error::assert_exact_length(ExtendedChargeStatus::decode, 2);
    crate::error::assert_exact_length(DisplayedError::decode, 4);
    crate::error::assert_exact_length(AlgorithmRequest::decode, 4);
}

#[test]
fn index_and_timeout_constants() {
    assert_eq!(
        [
            index::CHARGING_CURRENT,
            index::EXTENDED_CHARGE_STATUS,
            index::DERATE_REASONS,
            index::DISPLAYED_ERROR,
            index::BATTERY_VOLTAGE_LEGACY,
            index::BATTERY_VOLTAGE,
            index::AC_VOLTAGE,
            index::ALGORITHM_REQUEST,
            index::VOLTAGE_REQUEST,
            index::CABLE_RESISTANCE,
            index::VOLTAGE_REQUEST_16,
            index::CUMULATIVE_COUNTERS,
            index::CHARGE_HISTORY_INDEX,
            index::CHARGE_HISTORY_RECORDS,
            index::PADDING,
            index::RESET_REQUEST,
            index::EXTERNAL_OVERRIDE,
            index::AH_RETURNED,
        ],
        [
            0x2002, 0x2006, 0x2008, 0x2060, 0x2100, 0x2101, 0x2200, 0x2241, 0x2271, 0x2275, 0x2276,
            0x2500, 0x2E00, 0x2E01, 0x2FFA, 0x4000, 0x4201, 0x6052,
        ]
    );
    assert_eq!(index::CUMULATIVE_COUNTERS_LAST_SUB, 0x12);
    assert_eq!(
        [
            timeouts::BOOT_UP_MS,
            timeouts::NMT_MS,
            timeouts::SDO_MS,
            timeouts::STORE_RESTORE_MS,
            timeouts::HEARTBEAT_PRODUCER_MS,
            timeouts::HEARTBEAT_CONSUMER_MS,
            timeouts::CHARGER_TPDO_0_2_PERIOD_MS,
            timeouts::CHARGER_TPDO_3_PERIOD_MS,
            timeouts::BATTERY_TPDO_EVENT_TIMER_MS,
        ],
        [5000, 2000, 2000, 2000, 1000, 2000, 200, 1000, 200]
    );
}
