//! CiA 418 battery-module profile: objects, statuses, units, packed strings.
//!
//! Everything here follows CiA 418 v1.0.1 ("Device profile for battery
//! modules"): 6.2 for the communication objects (device type, error
//! register, default PDOs), 7.2 and 7.3 for the application objects. Delta-Q's
//! readings of the module's objects live in the `deltaq` module.
//!
//! - [`BATTERY_STATUS`] and friends: the index of every application object.
//! - [`BatteryStatus`], [`ChargerStatus`], [`WaterLevelStatus`]: status bytes
//!   as bitflags that keep unknown bits.
//! - [`Temperature`], [`AmpHours`], [`EighthAmpHours`], [`BatteryVoltage`],
//!   [`ChargeCurrentRequested`], [`StateOfCharge`]: scaled quantities with
//!   exact integer conversions.
//! - [`BatteryParameters`] (6020h) and [`BatteryType`] (`cccc wxyz`), with
//!   names for the types ([`BATTERY_TYPE_NAMES`]: `flooded`, `agm`, `li-ion`, ...).
//! - [`PackedString`] (6030h, 6031h, 6040h, 6041h): strings packed four
//!   characters per Unsigned32.
//! - [`EqualizationDate`] (6054h) and [`CalendarDateTime`].
//! - [`DeviceType`] (1000h) and the default PDO set [`DEFAULT_PDOS`]
//!   ([`battery_default_mapping`]).
//! - [`BATTERY_MODULE_CATALOGUE`], [`CIA418_OBJECTS`]: the application
//!   objects for decoding PDO fields in words.
//! - [`BatteryModule`]: a whole CiA 418 node (object dictionary
//!   [`BatteryObjects`], SDO server, default PDOs, heartbeat, EMCY, NMT
//!   slave) as a sans-IO state machine.
//!
//! Every value object has `decode(&[u8])` for the little-endian bytes an SDO
//! upload (or a PDO slice) carries and `encode()` for the bytes to send.
//! Decoding is total: a wrong length is a [`DecodeError`], any value of the
//! right length decodes.
//!
//! **PDO numbering**: as everywhere in this crate, PDOs count from 0
//! ([`PdoNumber`](crate::PdoNumber)); CiA 418's "1st TPDO" is `PdoNumber::P0`,
//! its "2nd RPDO" is `PdoNumber::P1` (Delta-Q's "RPDO 1").

mod battery;
mod battery_names;
pub(crate) mod catalogue;
mod date;
mod device_type;
#[cfg(feature = "alloc")]
mod eds;
mod module;
mod objects;
mod packed;
mod pdo;
mod status;
mod units;

#[cfg(test)]
mod battery_tests;
#[cfg(test)]
mod packed_tests;
#[cfg(test)]
mod tests;

pub use crate::device::Identity;
/// The CiA 301 indexes a CiA 418 module serves, re-exported from
/// [`od::index`](crate::od::index) (defined there only).
pub use crate::od::index::{
    DEVICE_TYPE, ERROR_REGISTER, IDENTITY, MANUFACTURER_DEVICE_NAME, PRODUCER_HEARTBEAT_TIME,
    SDO_SERVER_PARAMETER,
};
pub use battery::{
    BatteryParameterValue, BatteryParameters, BatteryType, Chemistry, Gravity, LeadAcid,
    MaintenanceFree, NickelCadmiumCell, NickelCadmiumPlate, ObjectError, Plate, SilverOxide,
};
pub use battery_names::NAMES as BATTERY_TYPE_NAMES;
pub use catalogue::{
    BATTERY_MODULE_CATALOGUE, BATTERY_STATUS_FLAGS, BATTERY_TYPE_FORMAT, CHARGER_STATUS_FLAGS,
    CIA418_OBJECTS, WATER_LEVEL_STATUS_FLAGS,
};
pub use date::{CalendarDateTime, DateError, EqualizationDate};
pub use device_type::{DeviceType, PdoSet};
#[cfg(feature = "alloc")]
pub use eds::battery_module_eds;
pub use module::{
    BatteryEvent, BatteryModule, BatteryModuleConfig, BatteryModuleDevice, BatteryModulePowerOn,
    BatteryModuleProfile,
};
pub use objects::{
    BatteryDictionary, BatteryObjects, BatteryPowerOnValues, BATTERY_OBJECT_INDEXES,
    BATTERY_PARAMETERS_RESTORED,
};
pub use packed::{PackedString, PackedStringError, PackedStringObject, PackedText};
pub use pdo::{
    battery_default_mapping, DefaultPdo, PdoDirection, DEFAULT_PDOS, RPDO_1ST_ENTRIES,
    RPDO_2ND_ENTRIES, RPDO_3RD_ENTRIES, TPDO_1ST_ENTRIES, TPDO_2ND_ENTRIES, TPDO_3RD_ENTRIES,
};
pub use status::{BatteryStatus, ChargerStatus, WaterLevelStatus};
pub use units::{
    AmpHours, BatteryVoltage, ChargeCurrentRequested, EighthAmpHours, SocReading, StateOfCharge,
    Temperature,
};

use crate::error::{exact_len, DecodeError};

// ---------------------------------------------------------------------------
// Objects CiA 418 defines beyond CiA 301. CiA 418 v1.0.1, 6.2.1: in 1000h
// device type bits 0-15 are 418 and bits 16-19 flag the optional PDOs (see
// [`DeviceType`]); 6.2.2: in 1001h error register the device-profile bit
// (bit 5) flags a temperature sensor fault.
// ---------------------------------------------------------------------------

/// 0080h: index of the `BatteryPar` record data type (CiA 418 section 7.2.1),
/// the type of object 6020h.
pub const BATTERY_PAR_DATA_TYPE: u16 = 0x0080;

// ---------------------------------------------------------------------------
// Application objects (CiA 418 v1.0.1, 7.3.1-7.3.18).
// ---------------------------------------------------------------------------

/// 6000h battery status, U8 ro (CiA 418 section 7.3.1). See [`BatteryStatus`].
pub const BATTERY_STATUS: u16 = 0x6000;
/// 6001h charger status, U8 rw (CiA 418 section 7.3.2). See [`ChargerStatus`].
pub const CHARGER_STATUS: u16 = 0x6001;
/// 6010h temperature, I16 ro, 0.125 degC/bit (CiA 418 section 7.3.3). See
/// [`Temperature`].
pub const TEMPERATURE: u16 = 0x6010;
/// 6020h battery parameters, RECORD `BatteryPar` ro (CiA 418 section 7.3.4).
/// See [`BatteryParameters`].
pub const BATTERY_PARAMETERS: u16 = 0x6020;
/// 6030h battery serial number, ARRAY U32 packed string, max 10 characters
/// (CiA 418 section 7.3.5). See [`PackedString`].
pub const BATTERY_SERIAL_NUMBER: u16 = 0x6030;
/// 6031h battery ID, ARRAY U32 packed string, max 20 characters (CiA 418
/// section 7.3.6).
pub const BATTERY_ID: u16 = 0x6031;
/// 6040h vehicle serial number, ARRAY U32 packed string, max 20 characters
/// (CiA 418 section 7.3.7).
pub const VEHICLE_SERIAL_NUMBER: u16 = 0x6040;
/// 6041h vehicle ID, ARRAY U32 packed string, max 20 characters (CiA 418
/// section 7.3.8).
pub const VEHICLE_ID: u16 = 0x6041;
/// 6050h cumulative total Ah charge, U32 ro, 1 Ah/bit (CiA 418 section
/// 7.3.9). See [`AmpHours`].
pub const CUMULATIVE_TOTAL_AH_CHARGE: u16 = 0x6050;
/// 6051h Ah expended since last charge, U16 ro, 0.125 Ah/bit (CiA 418
/// section 7.3.10). See [`EighthAmpHours`].
pub const AH_EXPENDED_SINCE_LAST_CHARGE: u16 = 0x6051;
/// 6052h Ah returned during last charge, U16 rw, 0.125 Ah/bit (CiA 418
/// section 7.3.11). See [`EighthAmpHours`].
pub const AH_RETURNED_DURING_LAST_CHARGE: u16 = 0x6052;
/// 6053h Ah since last equalization, U16 rw, 0.125 Ah/bit (CiA 418 section
/// 7.3.12). See [`EighthAmpHours`].
pub const AH_SINCE_LAST_EQUALIZATION: u16 = 0x6053;
/// 6054h date of last equalization, ARRAY U16 rw (CiA 418 section 7.3.13).
/// See [`EqualizationDate`].
pub const DATE_OF_LAST_EQUALIZATION: u16 = 0x6054;
/// 6060h battery voltage, U32 ro, 1/1024 V/bit (CiA 418 section 7.3.14). See
/// [`BatteryVoltage`].
pub const BATTERY_VOLTAGE: u16 = 0x6060;
/// 6070h charge current requested, U16 ro, 1/16 A/bit (CiA 418 section
/// 7.3.15). See [`ChargeCurrentRequested`].
pub const CHARGE_CURRENT_REQUESTED: u16 = 0x6070;
/// 6080h charger state of charge, U8 rw, 1 %/bit (CiA 418 section 7.3.16).
/// See [`StateOfCharge`].
pub const CHARGER_STATE_OF_CHARGE: u16 = 0x6080;
/// 6081h battery state of charge, U8 ro, 1 %/bit (CiA 418 section 7.3.17).
/// See [`StateOfCharge`].
pub const BATTERY_STATE_OF_CHARGE: u16 = 0x6081;
/// 6090h water level status, U8 ro (CiA 418 section 7.3.18). See
/// [`WaterLevelStatus`].
pub const WATER_LEVEL_STATUS: u16 = 0x6090;

// ---------------------------------------------------------------------------
// Little-endian helpers shared by the codecs (whole arrays, no indexing).
// ---------------------------------------------------------------------------

/// The bytes of a value of exactly `N` bytes.
fn exact<const N: usize>(data: &[u8]) -> Result<[u8; N], DecodeError> {
    exact_len(data, N)?;
    <[u8; N]>::try_from(data).map_err(|_| DecodeError::Truncated {
        need: N,
        got: data.len(),
    })
}

pub(crate) fn read_u8(data: &[u8]) -> Result<u8, DecodeError> {
    exact(data).map(u8::from_le_bytes)
}

pub(crate) fn read_u16(data: &[u8]) -> Result<u16, DecodeError> {
    exact(data).map(u16::from_le_bytes)
}

pub(crate) fn read_u32(data: &[u8]) -> Result<u32, DecodeError> {
    exact(data).map(u32::from_le_bytes)
}
