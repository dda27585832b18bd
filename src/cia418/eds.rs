//! The CiA 418 battery module described as an EDS (CiA 306): the object
//! names and data types of CiA 418 v1.0.1 and the module's own dictionary.

use crate::eds::DataType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use crate::eds::{
    sub, DataType, DeviceHeader, Eds, ObjectDescription, ObjectNames, ObjectType, SubDescription,
};
use crate::od::comm::COMM_OBJECTS;

use super::BatteryModule;

/// A packed string (CiA 418 v1.0.1, 7.3.5-7.3.8): an ARRAY of up to five
/// Unsigned32, four characters each.
const fn packed(index: u16, name: &'static str) -> ObjectDescription {
    ObjectDescription::with_subs(index, index, name, ObjectType::Array, PACKED_SUBS)
}

const PACKED_SUBS: &[SubDescription] = &[
    sub(0, 0, "Highest sub-index supported", U8),
    sub(1, 5, "Packed characters", U32),
];

/// The CiA 418 application objects 6000h-6090h with their names and data
/// types from CiA 418 v1.0.1 ("Device profile for battery modules",
/// section 7.3 "Detailed object specifications", 7.3.1 battery status to
/// 7.3.18 water level status). The Delta-Q charger, which shares these
/// objects, uses the same table.
pub const CIA418_OBJECT_DESCRIPTIONS: &[ObjectDescription] = &[
    ObjectDescription::var(0x6000, "Battery status", U8),
    ObjectDescription::var(0x6001, "Charger status", U8),
    ObjectDescription::var(0x6010, "Temperature", DataType::Integer16),
    ObjectDescription::with_subs(
        0x6020,
        0x6020,
        "Battery parameters",
        ObjectType::Record,
        &[
            sub(0, 0, "Highest sub-index supported", U8),
            sub(1, 1, "Battery type", U8),
            sub(2, 2, "Ah capacity", U16),
            sub(3, 3, "Maximum charge current", U16),
            sub(4, 4, "Number of cells", U16),
        ],
    ),
    packed(0x6030, "Battery serial number"),
    packed(0x6031, "Battery ID"),
    packed(0x6040, "Vehicle serial number"),
    packed(0x6041, "Vehicle ID"),
    ObjectDescription::var(0x6050, "Cumulative total Ah charge", U32),
    ObjectDescription::var(0x6051, "Ah expended since last charge", U16),
    ObjectDescription::var(0x6052, "Ah returned during last charge", U16),
    ObjectDescription::var(0x6053, "Ah since last equalization", U16),
    ObjectDescription::with_subs(
        0x6054,
        0x6054,
        "Date of last equalization",
        ObjectType::Record,
        &[
            sub(0, 0, "Number of elements", U8),
            sub(1, 1, "Minutes since midnight", U16),
            sub(2, 2, "Days since 1984-01-01", U16),
        ],
    ),
    ObjectDescription::var(0x6060, "Battery voltage", U32),
    ObjectDescription::var(0x6070, "Charge current requested", U16),
    ObjectDescription::var(0x6080, "Charger state of charge", U8),
    ObjectDescription::var(0x6081, "Battery state of charge", U8),
    ObjectDescription::var(0x6090, "Water level status", U8),
];

/// The EDS (CiA 306, "Electronic data sheet specification for CANopen") of
/// `module` as it is configured now: every object of its SDO dictionary
/// (`dictionary()`: the PDO objects, the CiA 301
/// communication objects, the CiA 418 application objects) with its
/// access, PDO-mappable flag and current value as `DefaultValue`, named
/// and typed by CiA 301 ([`COMM_OBJECTS`]) and CiA 418 v1.0.1
/// ([`CIA418_OBJECT_DESCRIPTIONS`]); `[DeviceInfo]` from 1008h and 1018h
/// (see [`Eds::describe`]).
///
/// ```
/// use canopen_codec::cia418::{battery_module_eds, BatteryModule, BatteryModuleConfig};
/// use canopen_codec::eds::{parse, write, DataType};
/// let module = BatteryModule::new(BatteryModuleConfig::default());
/// let text = write(&battery_module_eds(&module));
/// let eds = parse(&text).unwrap();
/// assert_eq!(eds.name(0x6010, 0), Some("Temperature"));
/// assert_eq!(eds.entry(0x6010, 0).unwrap().data_type, Some(DataType::Integer16));
/// assert_eq!(eds.entry(0x1000, 0).unwrap().default_value.as_deref(), Some("418"));
/// ```
#[must_use]
pub fn battery_module_eds(module: &BatteryModule) -> Eds {
    let mut od = module.dictionary().clone();
    Eds::describe(
        &mut od,
        &[
            ObjectNames::Rows(COMM_OBJECTS),
            ObjectNames::Descriptions(CIA418_OBJECT_DESCRIPTIONS),
        ],
        &DeviceHeader {
            file_name: "battery_module.eds",
            description: "CiA 418 battery module (canopen-codec)",
            vendor_name: None,
        },
    )
}
