//! The CiA 418 application objects 6000h-6090h as a PDO field catalogue
//! ([`CIA418_OBJECTS`], CiA 418 v1.0.1, 7.3.1-7.3.18), the flag words of its
//! status bytes, and the battery module's [`Catalogue`]
//! ([`BATTERY_MODULE_CATALOGUE`]).
//!
//! - **Markers.** CiA 418 marks invalid readings: 6070h 0xFFFF, 6080h and
//!   6081h 0xFF ([`FieldValue::Invalid`](crate::pdo::FieldValue::Invalid)).
//!   For 6070h the profile says "FFh" of a 16-bit object; 0xFFFF is taken as
//!   the marker (0x00FF is a valid 15.9375 A request).
//! - **6010h temperature** is CiA 418's Integer16 at 0.125 degC per bit, no
//!   offset (7.3.3).
//! - Indexes 2000h-5FFFh are manufacturer-specific: on a module of unknown
//!   make they have no known meaning and decode as
//!   [`FieldValue::Raw`](crate::pdo::FieldValue::Raw).
//!
//! ```
//! use canopen_codec::cia418::BATTERY_MODULE_CATALOGUE;
//! use canopen_codec::pdo::{MappingEntry, PdoMapping};
//!
//! // The module's 1st TPDO (CiA 418 v1.0.1, 6.2.4.3): 6010h/16, 6000h/8.
//! let m = PdoMapping::new(&[MappingEntry::new(0x6010, 0, 16), MappingEntry::new(0x6000, 0, 8)]).unwrap();
//! let fields = BATTERY_MODULE_CATALOGUE.decode(&m, &[0x30, 0x02, 0x01]);
//! assert_eq!(fields.to_string(), "6010h temperature 70 degC; 6000h battery status: ready to charge");
//! ```

use core::fmt;

use crate::pdo::{
    Catalogue, CatalogueEntry, FlagField, FlagWord, Interpretation, Marker, Unit, ValueFormat,
};

use super::{BatteryStatus, BatteryType, ChargerStatus, WaterLevelStatus};

/// 6000h battery status (CiA 418 v1.0.1, 7.3.1): bit 0 set means the
/// battery is ready to be charged; the other bits are kept as
/// `other bits XXh`.
pub const BATTERY_STATUS_FLAGS: FlagWord = FlagWord {
    fields: &[
        FlagField::Bit {
            mask: BatteryStatus::READY_TO_CHARGE.bits() as u64,
            set: "ready to charge",
            clear: Some("not ready to charge"),
        },
        FlagField::OtherBits { mask: 0xFF },
    ],
    when_empty: None,
};

/// 6001h charger status (CiA 418 v1.0.1, 7.3.2): bit 0 set means the
/// charger is enabled (able to charge).
pub const CHARGER_STATUS_FLAGS: FlagWord = FlagWord {
    fields: &[
        FlagField::Bit {
            mask: ChargerStatus::ENABLED.bits() as u64,
            set: "enabled",
            clear: Some("not enabled"),
        },
        FlagField::OtherBits { mask: 0xFF },
    ],
    when_empty: None,
};

/// 6090h water level status (CiA 418 v1.0.1, 7.3.18): bit 0 is 1 for full,
/// 0 for low.
pub const WATER_LEVEL_STATUS_FLAGS: FlagWord = FlagWord {
    fields: &[
        FlagField::Bit {
            mask: WaterLevelStatus::FULL.bits() as u64,
            set: "full",
            clear: Some("low"),
        },
        FlagField::OtherBits { mask: 0xFF },
    ],
    when_empty: None,
};

fn battery_type_has_value(_: u64) -> bool {
    true
}

fn write_battery_type(raw: u64, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    let t = BatteryType::from_u8(raw as u8);
    write!(f, "{} ({:02X}h)", t.chemistry(), t.to_u8())
}

/// 6020h sub 1 battery type (CiA 418 v1.0.1, 7.3.4): the chemistry in the
/// high nibble (`cccc wxyz`), written as `lead acid (10h)`; kind
/// `battery_type`.
pub const BATTERY_TYPE_FORMAT: ValueFormat = ValueFormat {
    kind: "battery_type",
    has_value: battery_type_has_value,
    write: write_battery_type,
};

/// The units of the catalogue rows, short (the Delta-Q catalogue uses them too).
pub(crate) const A: Option<Unit> = Some(Unit::Ampere);
pub(crate) const V: Option<Unit> = Some(Unit::Volt);
pub(crate) const AH: Option<Unit> = Some(Unit::AmpereHour);
const PCT: Option<Unit> = Some(Unit::Percent);

/// The CiA 418 application objects 6000h-6090h (CiA 418 v1.0.1, 7.3.1-7.3.18):
/// name, size and scale of each. 6051h-6053h are 0.125 Ah per bit, 6060h
/// 1/1024 V, 6070h 1/16 A; 6080h and 6081h are 0..100 % with 0xFF invalid.
#[rustfmt::skip]
pub const CIA418_OBJECTS: &[CatalogueEntry] = &[
    CatalogueEntry::new(0x6000, "battery status", 8, Interpretation::Flags(&BATTERY_STATUS_FLAGS)),
    CatalogueEntry::new(0x6001, "charger status", 8, Interpretation::Flags(&CHARGER_STATUS_FLAGS)),
    CatalogueEntry::new(
        0x6010,
        "temperature",
        16,
        Interpretation::Signed {
            frac_bits: 3,
            unit: Some(Unit::DegreeCelsius),
        },
    ),
    CatalogueEntry::scaled(0x6020, "battery parameters: highest sub-index", 8, 0, None),
    CatalogueEntry::new(0x6020, "battery type", 8, Interpretation::Formatted(&BATTERY_TYPE_FORMAT))
    .subs(1, 1),
    CatalogueEntry::scaled(0x6020, "Ah capacity", 16, 0, AH).subs(2, 2),
    CatalogueEntry::scaled(0x6020, "maximum charge current", 16, 0, A).subs(3, 3),
    CatalogueEntry::scaled(0x6020, "number of cells", 16, 0, None).subs(4, 4),
    CatalogueEntry::scaled(0x6030, "battery serial number: elements", 8, 0, None),
    CatalogueEntry::new(0x6030, "battery serial number", 32, Interpretation::Chars).subs(1, 3),
    CatalogueEntry::scaled(0x6031, "battery ID: elements", 8, 0, None),
    CatalogueEntry::new(0x6031, "battery ID", 32, Interpretation::Chars).subs(1, 5),
    CatalogueEntry::scaled(0x6040, "vehicle serial number: elements", 8, 0, None),
    CatalogueEntry::new(0x6040, "vehicle serial number", 32, Interpretation::Chars).subs(1, 5),
    CatalogueEntry::scaled(0x6041, "vehicle ID: elements", 8, 0, None),
    CatalogueEntry::new(0x6041, "vehicle ID", 32, Interpretation::Chars).subs(1, 5),
    CatalogueEntry::scaled(0x6050, "cumulative total Ah charge", 32, 0, AH),
    CatalogueEntry::scaled(0x6051, "Ah expended since last charge", 16, 3, AH),
    CatalogueEntry::scaled(0x6052, "Ah returned during last charge", 16, 3, AH),
    CatalogueEntry::scaled(0x6053, "Ah since last equalization", 16, 3, AH),
    CatalogueEntry::scaled(0x6054, "date of last equalization: elements", 8, 0, None),
    CatalogueEntry::scaled(0x6054, "last equalization, minutes since midnight", 16, 0, Some(Unit::Minute))
    .subs(1, 1),
    CatalogueEntry::scaled(0x6054, "last equalization, days since 1984-01-01", 16, 0, Some(Unit::Day))
    .subs(2, 2),
    CatalogueEntry::scaled(0x6060, "battery voltage", 32, 10, V),
    CatalogueEntry::scaled(0x6070, "charge current requested", 16, 4, A)
        .marked(Marker::Invalid(0xFFFF), None),
    CatalogueEntry::scaled(0x6080, "charger state of charge", 8, 0, PCT)
        .marked(Marker::Invalid(0xFF), Some(100)),
    CatalogueEntry::scaled(0x6081, "battery state of charge", 8, 0, PCT)
        .marked(Marker::Invalid(0xFF), Some(100)),
    CatalogueEntry::new(0x6090, "water level status", 8, Interpretation::Flags(&WATER_LEVEL_STATUS_FLAGS)),
];

/// A CiA 418 battery module: [`CIA418_OBJECTS`] only.
pub const BATTERY_MODULE_CATALOGUE: Catalogue =
    Catalogue::new("CiA 418 battery module", &[CIA418_OBJECTS]);

#[cfg(test)]
#[path = "catalogue_tests.rs"]
mod tests;
