//! The CiA 418 battery module described as an EDS (CiA 306): the object
//! names and data types of CiA 418 v1.0.1 (its table, [`CIA418_OBJECTS`])
//! and the module's own dictionary.

use crate::eds::{DeviceHeader, Eds};

use super::{BatteryModule, CIA418_OBJECTS};

/// The EDS (CiA 306, "Electronic data sheet specification for CANopen") of
/// `module` as it is configured now: every object of its SDO dictionary
/// (`dictionary()`: the PDO objects, the CiA 301
/// communication objects, the CiA 418 application objects) with its
/// access, PDO-mappable flag and current value as `DefaultValue`, named
/// and typed by CiA 301 ([`COMM_OBJECTS`](crate::od::comm::COMM_OBJECTS)) and CiA 418 v1.0.1
/// ([`CIA418_OBJECTS`]); `[DeviceInfo]` from 1008h and 1018h
/// (see [`Eds::describe_profile`]).
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
    Eds::describe_profile(
        &mut od,
        CIA418_OBJECTS,
        &DeviceHeader {
            file_name: "battery_module.eds",
            description: "CiA 418 battery module (canopen-codec)",
            vendor_name: None,
        },
    )
}
