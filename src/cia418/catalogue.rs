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

use crate::od::Access::{ReadOnly as Ro, ReadWrite as Rw};
use crate::od::DataType::{
    Integer16 as I16, Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8,
};
use crate::od::{Address, ObjectRow, ObjectType};
use crate::pdo::{Catalogue, FlagField, FlagWord, Interpretation, Marker, Unit, ValueFormat};

use super::{BatteryStatus, BatteryType, ChargerStatus, WaterLevelStatus};
use super::{
    AH_EXPENDED_SINCE_LAST_CHARGE, AH_RETURNED_DURING_LAST_CHARGE, AH_SINCE_LAST_EQUALIZATION,
    BATTERY_ID, BATTERY_PARAMETERS, BATTERY_SERIAL_NUMBER, BATTERY_STATE_OF_CHARGE, BATTERY_STATUS,
    BATTERY_VOLTAGE, CHARGER_STATE_OF_CHARGE, CHARGER_STATUS, CHARGE_CURRENT_REQUESTED,
    CUMULATIVE_TOTAL_AH_CHARGE, DATE_OF_LAST_EQUALIZATION, TEMPERATURE, VEHICLE_ID,
    VEHICLE_SERIAL_NUMBER, WATER_LEVEL_STATUS,
};

/// A CiA 418 status byte of one defined bit (CiA 418 v1.0.1, sections
/// 7.3.1, 7.3.2 and 7.3.18): `set` or `clear` for the bit `flag`, the
/// other bits kept as `other bits XXh`.
macro_rules! one_bit_status {
    ($flag:expr, $set:literal, $clear:literal) => {
        FlagWord {
            fields: &[
                FlagField::Bit {
                    mask: $flag.bits() as u64,
                    set: $set,
                    clear: Some($clear),
                },
                FlagField::OtherBits { mask: 0xFF },
            ],
            when_empty: None,
        }
    };
}

/// 6000h battery status (CiA 418 v1.0.1, 7.3.1): bit 0 set means the
/// battery is ready to be charged; the other bits are kept as
/// `other bits XXh`.
pub const BATTERY_STATUS_FLAGS: FlagWord = one_bit_status!(
    BatteryStatus::READY_TO_CHARGE,
    "ready to charge",
    "not ready to charge"
);

/// 6001h charger status (CiA 418 v1.0.1, 7.3.2): bit 0 set means the
/// charger is enabled (able to charge).
pub const CHARGER_STATUS_FLAGS: FlagWord =
    one_bit_status!(ChargerStatus::ENABLED, "enabled", "not enabled");

/// 6090h water level status (CiA 418 v1.0.1, 7.3.18): bit 0 is 1 for full,
/// 0 for low.
pub const WATER_LEVEL_STATUS_FLAGS: FlagWord =
    one_bit_status!(WaterLevelStatus::FULL, "full", "low");

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

/// The CiA 418 application objects 6000h-6090h, the area's one table
/// (CiA 418 v1.0.1, "Device profile for battery modules", section 7.3
/// "Detailed object specifications", 7.3.1 battery status to 7.3.18 water
/// level status): for each entry its name and data type as the profile
/// (and so an EDS) gives them, access, PDO mapping and power-on value as
/// the battery module serves them ([`BatteryObjects`](super::BatteryObjects)),
/// and the decoder's name, scale and unit. 6051h-6053h are 0.125 Ah per
/// bit, 6060h 1/1024 V, 6070h 1/16 A; 6080h and 6081h are 0..100 % with
/// 0xFF invalid. The charger (CiA 419, Delta-Q) shares these objects.
#[rustfmt::skip]
pub const CIA418_OBJECTS: &[ObjectRow] = &[
    ObjectRow::var(BATTERY_STATUS, "Battery status", U8, Ro).short("battery status").mappable()
        .reading(Interpretation::Flags(&BATTERY_STATUS_FLAGS)),
    ObjectRow::var(CHARGER_STATUS, "Charger status", U8, Rw).short("charger status").mappable()
        .reading(Interpretation::Flags(&CHARGER_STATUS_FLAGS)),
    ObjectRow::var(TEMPERATURE, "Temperature", I16, Ro).short("temperature").mappable()
        .scaled(3, Some(Unit::DegreeCelsius)),
    ObjectRow::var(BATTERY_PARAMETERS, "Highest sub-index supported", U8, Ro)
        .heads("Battery parameters", ObjectType::Record)
        .short("battery parameters: highest sub-index").default(4),
    ObjectRow::new(Address::new(BATTERY_PARAMETERS, 1), "Battery type", U8, Ro).short("battery type")
        .reading(Interpretation::Formatted(&BATTERY_TYPE_FORMAT)),
    ObjectRow::new(Address::new(BATTERY_PARAMETERS, 2), "Ah capacity", U16, Ro).scaled(0, AH),
    ObjectRow::new(Address::new(BATTERY_PARAMETERS, 3), "Maximum charge current", U16, Ro)
        .short("maximum charge current").scaled(0, A),
    ObjectRow::new(Address::new(BATTERY_PARAMETERS, 4), "Number of cells", U16, Ro)
        .short("number of cells"),
    packed_count(BATTERY_SERIAL_NUMBER, "Battery serial number", "battery serial number: elements"),
    packed(BATTERY_SERIAL_NUMBER, "battery serial number", 3),
    packed_count(BATTERY_ID, "Battery ID", "battery ID: elements"),
    packed(BATTERY_ID, "battery ID", 5),
    packed_count(VEHICLE_SERIAL_NUMBER, "Vehicle serial number", "vehicle serial number: elements"),
    packed(VEHICLE_SERIAL_NUMBER, "vehicle serial number", 5),
    packed_count(VEHICLE_ID, "Vehicle ID", "vehicle ID: elements"),
    packed(VEHICLE_ID, "vehicle ID", 5),
    ObjectRow::var(CUMULATIVE_TOTAL_AH_CHARGE, "Cumulative total Ah charge", U32, Ro)
        .short("cumulative total Ah charge").scaled(0, AH),
    ObjectRow::var(AH_EXPENDED_SINCE_LAST_CHARGE, "Ah expended since last charge", U16, Ro)
        .scaled(3, AH),
    ObjectRow::var(AH_RETURNED_DURING_LAST_CHARGE, "Ah returned during last charge", U16, Rw)
        .mappable().scaled(3, AH),
    ObjectRow::var(AH_SINCE_LAST_EQUALIZATION, "Ah since last equalization", U16, Rw)
        .scaled(3, AH),
    ObjectRow::var(DATE_OF_LAST_EQUALIZATION, "Number of elements", U8, Ro)
        .heads("Date of last equalization", ObjectType::Record)
        .short("date of last equalization: elements").default(2),
    ObjectRow::new(Address::new(DATE_OF_LAST_EQUALIZATION, 1), "Minutes since midnight", U16, Rw)
        .short("last equalization, minutes since midnight").scaled(0, Some(Unit::Minute)),
    ObjectRow::new(Address::new(DATE_OF_LAST_EQUALIZATION, 2), "Days since 1984-01-01", U16, Rw)
        .short("last equalization, days since 1984-01-01").scaled(0, Some(Unit::Day)),
    ObjectRow::var(BATTERY_VOLTAGE, "Battery voltage", U32, Ro).short("battery voltage").mappable()
        .scaled(10, V),
    ObjectRow::var(CHARGE_CURRENT_REQUESTED, "Charge current requested", U16, Ro)
        .short("charge current requested").mappable().default(0xFFFF)
        .scaled(4, A).marked(Marker::Invalid(0xFFFF), None),
    ObjectRow::var(CHARGER_STATE_OF_CHARGE, "Charger state of charge", U8, Rw)
        .short("charger state of charge").mappable().default(0xFF)
        .scaled(0, PCT).marked(Marker::Invalid(0xFF), Some(100)),
    ObjectRow::var(BATTERY_STATE_OF_CHARGE, "Battery state of charge", U8, Ro)
        .short("battery state of charge").mappable().default(0xFF)
        .scaled(0, PCT).marked(Marker::Invalid(0xFF), Some(100)),
    ObjectRow::var(WATER_LEVEL_STATUS, "Water level status", U8, Ro).short("water level status")
        .reading(Interpretation::Flags(&WATER_LEVEL_STATUS_FLAGS)),
];

/// Sub-index 0 of a packed string (CiA 418 v1.0.1, 7.3.5-7.3.8): the
/// element count of the ARRAY `name`, one element when empty.
const fn packed_count(index: u16, name: &'static str, short: &'static str) -> ObjectRow {
    ObjectRow::var(index, "Highest sub-index supported", U8, Ro)
        .heads(name, ObjectType::Array)
        .short(short)
        .default(1)
}

/// Sub-indexes 1..=`last` of a packed string: Unsigned32 elements of four
/// ISO 646 characters each.
const fn packed(index: u16, short: &'static str, last: u8) -> ObjectRow {
    ObjectRow::new(Address::new(index, 1), "Packed characters", U32, Ro)
        .through(last)
        .short(short)
        .reading(Interpretation::Chars)
}

/// A CiA 418 battery module: [`CIA418_OBJECTS`] only.
pub const BATTERY_MODULE_CATALOGUE: Catalogue =
    Catalogue::new("CiA 418 battery module", &[CIA418_OBJECTS]);

#[cfg(test)]
#[path = "catalogue_tests.rs"]
mod tests;
