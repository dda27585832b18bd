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

use crate::cia418::catalogue::{A, AH, V};
use core::fmt;

use crate::cia418::{
    AH_RETURNED_DURING_LAST_CHARGE, BATTERY_STATE_OF_CHARGE, BATTERY_STATUS, BATTERY_VOLTAGE,
    CHARGER_STATE_OF_CHARGE, CHARGER_STATUS, CHARGE_CURRENT_REQUESTED, CIA418_OBJECTS, TEMPERATURE,
};
use crate::od::Access::{self, Const, ReadOnly as Ro, ReadWrite as Rw};
use crate::od::DataType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use crate::od::{Address, ObjectRow, ObjectType};
use crate::pdo::{Catalogue, FlagField, FlagWord, Interpretation, Marker, Unit, ValueFormat};

use super::charge::{AH_TARGET, ELAPSED_TIME};
use super::index;

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

const NO_16: Marker = Marker::NoValue(0xFFFF);
const NO_32: Marker = Marker::NoValue(0xFFFF_FFFF);

/// The charger's row of a CiA 418 object it shares with the battery
/// module (CiA 419 uses them for the values the two exchange): the CiA 418
/// names, type and reading ([`CIA418_OBJECTS`]) with the charger's access,
/// PDO-mappable. A row of the charger's table whose object CiA 418 lacks
/// would have an empty name (a test checks every row has one).
const fn shared(index: u16, access: Access) -> ObjectRow {
    let mut rows = CIA418_OBJECTS;
    while let [row, rest @ ..] = rows {
        if row.address.index == index && row.address.sub == 0 {
            let mut row = *row;
            row.access = access;
            row.mappable = true;
            return row;
        }
        rows = rest;
    }
    ObjectRow::var(index, "", U8, access)
}

/// The Delta-Q IC Series charger's objects, the area's one table: the
/// CiA 418 objects it shares with the battery module (with the charger's
/// access and its reading of 6052h: Q3 Ah like CiA 418, but 0xFFFF is "no
/// value"), the Delta-Q manufacturer objects of the IC Series CANopen
/// interface specification rev 2.0 (section 5, "Object dictionary", names
/// as Delta-Q's own EDS spells them), the 2FFAh padding objects its PDO
/// mappings use, and the charge control's two objects the Delta-Q
/// documents do not name (ours: 2250h Ah target, 2251h elapsed time; see
/// [`charge`](super::charge)). Every entry is PDO-mappable but 2FFAh sub
/// 0; 0xFFFF (0xFFFF_FFFF for 32 bits) is "no value". The charger's
/// dictionary ([`ChargerObjects`](super::ChargerObjects)), its EDS and
/// [`CHARGER_CATALOGUE`] are derived from it.
#[rustfmt::skip]
pub const DELTAQ_OBJECTS: &[ObjectRow] = &[
    shared(BATTERY_STATUS, Rw),
    shared(CHARGER_STATUS, Ro),
    shared(TEMPERATURE, Rw),
    shared(AH_RETURNED_DURING_LAST_CHARGE, Rw).default(0xFFFF).marked(NO_16, None),
    shared(BATTERY_VOLTAGE, Rw),
    shared(CHARGE_CURRENT_REQUESTED, Rw).default(0xFFFF),
    shared(CHARGER_STATE_OF_CHARGE, Ro).default(0xFF),
    shared(BATTERY_STATE_OF_CHARGE, Rw).default(0xFF),
    ObjectRow::var(index::CHARGING_CURRENT, "Charging Current", U16, Rw).mappable()
        .short("charging current").scaled(8, A).marked(NO_16, None),
    ObjectRow::var(index::EXTENDED_CHARGE_STATUS, "Extended Charge Status", U16, Ro).mappable()
        .short("extended charge status")
        .reading(Interpretation::Flags(&EXTENDED_CHARGE_STATUS_FLAGS)),
    ObjectRow::var(index::DERATE_REASONS, "Derate Reasons", U8, Ro).mappable()
        .short("derate reasons").reading(Interpretation::Flags(&DERATE_REASONS_FLAGS)),
    ObjectRow::var(index::DISPLAYED_ERROR, "Current Displayed Error/Fault", U32, Ro).mappable()
        .short("displayed error").reading(Interpretation::Formatted(&DISPLAYED_ERROR_FORMAT)),
    ObjectRow::var(index::BATTERY_VOLTAGE_LEGACY, "Battery Voltage UINT16", U16, Ro).mappable()
        .short("battery voltage (legacy)").default(0xFFFF).scaled(10, V).marked(NO_16, None),
    ObjectRow::var(index::BATTERY_VOLTAGE, "Battery Voltage Q8.8", U16, Rw).mappable()
        .short("battery voltage").default(0xFFFF).scaled(8, V).marked(NO_16, None),
    ObjectRow::var(index::AC_VOLTAGE, "AC Voltage", U16, Ro).mappable()
        .short("AC voltage").default(0xFFFF).scaled(4, V).marked(NO_16, None),
    ObjectRow::var(index::ALGORITHM_REQUEST, "Active Algorithm Request", U32, Rw).mappable()
        .short("algorithm request").default(0xFFFF_FFFF)
        .reading(Interpretation::Formatted(&ALGORITHM_REQUEST_FORMAT)),
    ObjectRow::var(index::VOLTAGE_REQUEST, "Voltage Request", U32, Rw).mappable()
        .short("voltage request").default(0xFFFF_FFFF).scaled(10, V).marked(NO_32, None),
    ObjectRow::var(index::VOLTAGE_REQUEST_16, "Voltage Request U16 Q8", U16, Rw).mappable()
        .short("voltage request").default(0xFFFF).scaled(8, V).marked(NO_16, None),
    ObjectRow::var(index::PADDING, "NrOfEntries", U8, Const).heads("Zero-Filling", ObjectType::Array)
        .short("padding: highest sub-index").default(2),
    ObjectRow::new(Address::new(index::PADDING, 1), "ZeroRxFilling", U8, Rw).mappable()
        .short("padding").reading(Interpretation::Padding),
    ObjectRow::new(Address::new(index::PADDING, 2), "ZeroTxFilling", U8, Rw).mappable()
        .short("padding").reading(Interpretation::Padding),
    ObjectRow::var(index::EXTERNAL_OVERRIDE, "External Override", U8, Rw).mappable()
        .short("external override").reading(Interpretation::Flags(&EXTERNAL_OVERRIDE_FLAGS)),
    ObjectRow::var(AH_TARGET, "Ah Target", U16, Rw).mappable()
        .short("Ah target").default(0xFFFF).scaled(3, AH).marked(NO_16, None),
    ObjectRow::var(ELAPSED_TIME, "Charge Cycle Elapsed Time", U32, Ro).mappable()
        .short("charge cycle elapsed time"),
];

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
