//! The Delta-Q IC Series charger described as an EDS (CiA 306): the
//! Delta-Q names of its manufacturer objects, the CiA 418 and CiA 301
//! names of the others, and the charger's own dictionary.

use crate::eds::DataType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};
use crate::eds::{sub, ObjectDescription, ObjectType};
#[cfg(feature = "heartbeat-consumer")]
use crate::{
    cia418::CIA418_OBJECT_DESCRIPTIONS,
    eds::{DeviceHeader, Eds, ObjectNames},
    od::comm::COMM_OBJECTS,
};

use super::index;
#[cfg(feature = "heartbeat-consumer")]
use super::Charger;

/// The Delta-Q manufacturer objects the charger serves (2002h, 2006h,
/// 2008h, 2060h, 2100h, 2101h, 2200h, 2241h, 2271h, 2276h, 2FFAh, 4201h) with the
/// names and data types of the Delta-Q IC Series CANopen interface
/// specification rev 2.0 (section 5, "Object dictionary"), spelled as
/// Delta-Q's own EDS spells them.
pub const DELTAQ_OBJECT_DESCRIPTIONS: &[ObjectDescription] = &[
    ObjectDescription::var(index::CHARGING_CURRENT, "Charging Current", U16),
    ObjectDescription::var(index::EXTENDED_CHARGE_STATUS, "Extended Charge Status", U16),
    ObjectDescription::var(index::DERATE_REASONS, "Derate Reasons", U8),
    ObjectDescription::var(index::DISPLAYED_ERROR, "Current Displayed Error/Fault", U32),
    ObjectDescription::var(index::BATTERY_VOLTAGE_LEGACY, "Battery Voltage UINT16", U16),
    ObjectDescription::var(index::BATTERY_VOLTAGE, "Battery Voltage Q8.8", U16),
    ObjectDescription::var(index::AC_VOLTAGE, "AC Voltage", U16),
    ObjectDescription::var(index::ALGORITHM_REQUEST, "Active Algorithm Request", U32),
    ObjectDescription::var(index::VOLTAGE_REQUEST, "Voltage Request", U32),
    ObjectDescription::var(index::VOLTAGE_REQUEST_16, "Voltage Request U16 Q8", U16),
    ObjectDescription::with_subs(
        index::PADDING,
        index::PADDING,
        "Zero-Filling",
        ObjectType::Array,
        &[
            sub(0, 0, "NrOfEntries", U8),
            sub(1, 1, "ZeroRxFilling", U8),
            sub(2, 2, "ZeroTxFilling", U8),
        ],
    ),
    ObjectDescription::var(index::EXTERNAL_OVERRIDE, "External Override", U8),
];

/// The charge control's two objects the Delta-Q documents do not name
/// (ours: [`AH_TARGET`](super::charge::AH_TARGET) 2250h and
/// [`ELAPSED_TIME`](super::charge::ELAPSED_TIME) 2251h).
pub const CHARGE_CONTROL_OBJECT_DESCRIPTIONS: &[ObjectDescription] = &[
    ObjectDescription::var(super::charge::AH_TARGET, "Ah Target", U16),
    ObjectDescription::var(
        super::charge::ELAPSED_TIME,
        "Charge Cycle Elapsed Time",
        U32,
    ),
];

/// The EDS (CiA 306, "Electronic data sheet specification for CANopen") of
/// `charger` as it is configured now: every object of its SDO dictionary
/// (`dictionary()`: the PDO objects, the CiA 301 communication
/// objects with 1016h, the CiA 418 objects it shares with the module and
/// the Delta-Q objects) with its access, PDO-mappable flag and current
/// value as `DefaultValue`, named and typed by CiA 301
/// ([`COMM_OBJECTS`]), CiA 418 v1.0.1
/// ([`CIA418_OBJECT_DESCRIPTIONS`]) and Delta-Q
/// ([`DELTAQ_OBJECT_DESCRIPTIONS`]) and ours for the charge control
/// ([`CHARGE_CONTROL_OBJECT_DESCRIPTIONS`]); `[DeviceInfo]` from 1008h and 1018h
/// (see [`Eds::describe`]).
///
/// ```
/// use canopen_codec::deltaq::{charger_eds, Charger, ChargerConfig};
/// use canopen_codec::eds::{parse, write};
/// use canopen_codec::NodeId;
/// let config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::MIN);
/// let eds = parse(&write(&charger_eds(&Charger::new(config)))).unwrap();
/// assert_eq!(eds.name(0x2002, 0), Some("Charging Current"));
/// assert!(eds.objects.contains_key(&0x1016));
/// ```
#[cfg(feature = "heartbeat-consumer")]
#[must_use]
pub fn charger_eds(charger: &Charger) -> Eds {
    let mut od = charger.dictionary().clone();
    Eds::describe(
        &mut od,
        &[
            ObjectNames::Rows(COMM_OBJECTS),
            ObjectNames::Descriptions(CIA418_OBJECT_DESCRIPTIONS),
            ObjectNames::Descriptions(DELTAQ_OBJECT_DESCRIPTIONS),
            ObjectNames::Descriptions(CHARGE_CONTROL_OBJECT_DESCRIPTIONS),
        ],
        &DeviceHeader {
            file_name: "charger.eds",
            description: "Delta-Q IC Series charger (canopen-codec)",
            vendor_name: Some("Delta-Q Technologies"),
        },
    )
}
