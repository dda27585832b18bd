//! The Delta-Q charger's objects as a PDO field catalogue
//! ([`DELTAQ_OBJECTS`]), the flag words of its bit-field objects, the
//! formats of 2060h and 2241h, and the charger's [`Catalogue`]
//! ([`CHARGER_CATALOGUE`]).
//!
//! Sources: Delta-Q's published object list for the IC Series (its EDS;
//! "IC Series CANopen interface specification rev 2.0" moved the object
//! descriptions there), with the 2100h scale erratum resolved as in
//! [`BatteryVoltageLegacy`](super::BatteryVoltageLegacy).
//!
//! ## Which device's meaning
//!
//! An object's meaning belongs to the device whose dictionary holds it, so
//! a catalogue is chosen per device, not per index:
//!
//! - [`BATTERY_MODULE_CATALOGUE`] knows the CiA 418 objects only. Indexes
//!   2000h-5FFFh are manufacturer-specific; on an unknown module they have
//!   no known meaning and decode as [`FieldValue::Raw`](crate::pdo::FieldValue::Raw).
//! - [`CHARGER_CATALOGUE`] knows the Delta-Q objects and the CiA 418
//!   objects the charger implements, with the charger's meaning where it
//!   differs. The one difference known is **6052h**: both scale it by
//!   0.125 Ah, but on the charger 0xFFFF is "no value" (its default), while
//!   CiA 418 has no marker and 0xFFFF reads 8191.875 Ah.
//!
//! A PDO is decoded with the catalogue of the device that owns the PDO's
//! dictionary: a charger's TPDOs *and* RPDOs (the RPDOs write into the
//! charger's dictionary) use [`CHARGER_CATALOGUE`]. Delta-Q's defaults of
//! 0xFFFF / 0xFFFF_FFFF mean "no value":
//! [`FieldValue::NoValue`](crate::pdo::FieldValue::NoValue).
//!
//! ```
//! use canopen_codec::deltaq::CHARGER_CATALOGUE;
//! use canopen_codec::pdo::{MappingEntry, PdoMapping};
//!
//! // The real capture's charger TPDO 0, remapped by its integrator
//! // (tests/data/CAPTURES.md): 2002h/16, 2101h/16, 2006h/16, 16 bits padding.
//! let mapping = PdoMapping::new(&[
//!     MappingEntry::new(0x2002, 0, 16),
//!     MappingEntry::new(0x2101, 0, 16),
//!     MappingEntry::new(0x2006, 0, 16),
//!     MappingEntry::new(0x0006, 0, 16), // UNSIGNED16 dummy entry
//! ]).unwrap();
//! let fields = CHARGER_CATALOGUE.decode(&mapping, &[0x74, 0x13, 0x45, 0x4E, 0x70, 0, 0, 0]);
//! let words: Vec<String> = fields.iter().map(|f| format!("{f:.2}")).collect();
//! assert_eq!(words, [
//!     "2002h charging current 19.45 A",
//!     "2101h battery voltage 78.27 V",
//!     "2006h extended charge status: AC present, charger enabled, override external (BMS)",
//!     "0006h padding (16 bits)",
//! ]);
//! // Without a precision the value is exact: 0x1374 / 256.
//! assert_eq!(fields.as_slice()[0].to_string(), "2002h charging current 19.453125 A");
//! ```

use core::fmt;

use crate::cia418::CIA418_OBJECTS;
use crate::od::Access::ReadWrite as Rw;
use crate::od::DataType::Unsigned8 as U8;
use crate::od::ObjectRow;
use crate::pdo::{Catalogue, FlagField, FlagWord, Unit, ValueFormat};

use super::index;
use super::DELTAQ_OBJECTS;

#[cfg(doc)]
use crate::cia418::BATTERY_MODULE_CATALOGUE;

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

/// Objects of Delta-Q's list the charger model does not serve, known to
/// the decoder: 2275h cable resistance (U8 mOhm, not PDO-mappable).
#[rustfmt::skip]
pub const DELTAQ_UNSERVED_OBJECTS: &[ObjectRow] = &[
    ObjectRow::var(index::CABLE_RESISTANCE, "Cable Resistance", U8, Rw)
        .short("cable resistance").scaled(0, Some(Unit::Milliohm)),
];

/// The Delta-Q IC Series charger: [`DELTAQ_OBJECTS`], then
/// [`DELTAQ_UNSERVED_OBJECTS`], then [`CIA418_OBJECTS`].
pub const CHARGER_CATALOGUE: Catalogue = Catalogue::new(
    "Delta-Q IC Series charger",
    &[DELTAQ_OBJECTS, DELTAQ_UNSERVED_OBJECTS, CIA418_OBJECTS],
);

#[cfg(test)]
#[path = "catalogue_tests.rs"]
mod tests;
