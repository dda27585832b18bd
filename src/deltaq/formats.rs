//! The flag words of the Delta-Q charger's bit-field objects and the
//! formats of 2060h and 2241h (Delta-Q IC Series CANopen interface
//! specification, the object descriptions of its EDS), which the rows of
//! [`DELTAQ_OBJECTS`](super::DELTAQ_OBJECTS) read their values with.

use core::fmt;

use crate::pdo::{FlagField, FlagWord, ValueFormat};

use super::{
    AlgorithmRequest, ChargeIndication, ChargeStatusFlags, ChargeType, DerateReasons,
    DisplayedError, ExternalOverride, OverrideSource,
};

const fn bit(mask: u8, set: &'static str) -> FlagField {
    FlagField::Bit {
        mask: mask as u64,
        set,
        clear: None,
    }
}

const fn value(v: u8, words: Option<&'static str>) -> (u64, Option<&'static str>) {
    (v as u64, words)
}

/// 2006h extended charge status (U16): bits 0-5 the flags fault active,
/// alarm active, hardware shutdown, de-rating, AC present, charger enabled;
/// bits 6-7 the override source (0 internal, 1 external / BMS); bits 8-11
/// the charge indication (0 inactive, 1 below 80 %, 2 above 80 %,
/// 3 finishing, 4 complete, 5 resting, 6 equalize, 7 power-supply mode);
/// bits 12-15 the charge type (0 none, 1 normal, 2 maintenance). See
/// [`ExtendedChargeStatus`](super::ExtendedChargeStatus).
pub const EXTENDED_CHARGE_STATUS_FLAGS: FlagWord = FlagWord {
    fields: &[
        bit(ChargeStatusFlags::FAULT_ACTIVE.bits(), "fault active"),
        bit(ChargeStatusFlags::ALARM_ACTIVE.bits(), "alarm active"),
        bit(ChargeStatusFlags::HW_SHUTDOWN.bits(), "hardware shutdown"),
        bit(ChargeStatusFlags::DERATING.bits(), "de-rating"),
        bit(ChargeStatusFlags::AC_PRESENT.bits(), "AC present"),
        bit(ChargeStatusFlags::CHARGER_ENABLED.bits(), "charger enabled"),
        FlagField::OtherBits { mask: 0x3F },
        FlagField::Choice {
            mask: 0x00C0,
            values: &[
                value(OverrideSource::Internal.bits(), Some("override internal")),
                value(
                    OverrideSource::External.bits(),
                    Some("override external (BMS)"),
                ),
            ],
            unknown: "override source",
        },
        FlagField::Choice {
            mask: 0x0F00,
            values: &[
                value(ChargeIndication::Inactive.bits(), None),
                value(ChargeIndication::Below80.bits(), Some("below 80 %")),
                value(ChargeIndication::Above80.bits(), Some("above 80 %")),
                value(ChargeIndication::Finishing.bits(), Some("finishing")),
                value(ChargeIndication::Complete.bits(), Some("complete")),
                value(ChargeIndication::Resting.bits(), Some("resting")),
                value(ChargeIndication::Equalize.bits(), Some("equalize")),
                value(
                    ChargeIndication::PowerSupplyMode.bits(),
                    Some("power-supply mode"),
                ),
            ],
            unknown: "indication",
        },
        FlagField::Choice {
            mask: 0xF000,
            values: &[
                value(ChargeType::None.bits(), None),
                value(ChargeType::Normal.bits(), Some("normal charge")),
                value(ChargeType::Maintenance.bits(), Some("maintenance charge")),
            ],
            unknown: "charge type",
        },
    ],
    when_empty: None,
};

/// 2008h derate reasons (U8): bit 0 AC voltage, 1 battery voltage,
/// 2 temperature, 3 AC current limit; `none` when no bit is set.
pub const DERATE_REASONS_FLAGS: FlagWord = FlagWord {
    fields: &[
        bit(DerateReasons::AC_VOLTAGE.bits(), "AC voltage"),
        bit(DerateReasons::BATTERY_VOLTAGE.bits(), "battery voltage"),
        bit(DerateReasons::TEMPERATURE.bits(), "temperature"),
        bit(DerateReasons::AC_CURRENT_LIMIT.bits(), "AC current limit"),
        FlagField::OtherBits { mask: 0xFF },
    ],
    when_empty: Some("none"),
};

/// 4201h external override (U8): bit 0 equalize, bit 1 maintenance; `none`
/// when no bit is set.
pub const EXTERNAL_OVERRIDE_FLAGS: FlagWord = FlagWord {
    fields: &[
        bit(ExternalOverride::EQUALIZE.bits(), "equalize"),
        bit(ExternalOverride::MAINTENANCE.bits(), "maintenance"),
        FlagField::OtherBits { mask: 0xFF },
    ],
    when_empty: Some("none"),
};

fn always(_: u64) -> bool {
    true
}

fn write_displayed_error(raw: u64, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    let e = DisplayedError::from_u32(raw as u32);
    if e.is_none() {
        return f.write_str("none");
    }
    write!(f, "{}", e.code)?;
    if let Some(d) = e.code.description() {
        write!(f, " {d}")?;
    }
    write!(f, " (EEC {:04X}h)", e.eec.raw())
}

/// 2060h current displayed error / fault (U32, laid out as a 1003h entry:
/// EEC in the low word, the Delta-Q code byte-swapped in the high word):
/// `E-0-3-2 heartbeat lost (EEC 8130h)`, or `none` for 0; kind `error`.
/// See [`DisplayedError`].
pub const DISPLAYED_ERROR_FORMAT: ValueFormat = ValueFormat {
    kind: "error",
    has_value: always,
    write: write_displayed_error,
};

fn algorithm_has_value(raw: u64) -> bool {
    AlgorithmRequest::from_u32(raw as u32).is_some()
}

fn write_algorithm(raw: u64, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    let Some(r) = AlgorithmRequest::from_u32(raw as u32) else {
        return f.write_str("no value");
    };
    write!(f, "algorithm {} variant {}", r.algorithm, r.variant)?;
    if r.revert_after_ac_loss {
        f.write_str(", revert after AC loss")?;
    }
    if r.store_permanently {
        f.write_str(", store permanently")?;
    }
    Ok(())
}

/// 2241h active algorithm request (U32): bits 0-15 the algorithm id, 16-23
/// the variant, bit 30 revert to the permanent algorithm after AC loss,
/// bit 31 store permanently; 0xFFFF_FFFF is no value. Written as
/// `algorithm 11 variant 0, store permanently`; kind `algorithm`. See
/// [`AlgorithmRequest`].
pub const ALGORITHM_REQUEST_FORMAT: ValueFormat = ValueFormat {
    kind: "algorithm",
    has_value: algorithm_has_value,
    write: write_algorithm,
};
