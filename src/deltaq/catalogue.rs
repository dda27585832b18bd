//! The Delta-Q charger's [`Catalogue`] ([`CHARGER_CATALOGUE`]): its
//! objects ([`DELTAQ_OBJECTS`], their flag words and formats in
//! `formats.rs`), the ones it does not serve, and CiA 418's.
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

use crate::cia418::CIA418_OBJECTS;
use crate::od::Access::ReadWrite as Rw;
use crate::od::DataType::Unsigned8 as U8;
use crate::od::ObjectRow;
use crate::pdo::{Catalogue, Unit};

use super::index;
use super::DELTAQ_OBJECTS;

#[cfg(doc)]
use crate::cia418::BATTERY_MODULE_CATALOGUE;

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
