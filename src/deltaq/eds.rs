//! The Delta-Q IC Series charger described as an EDS (CiA 306): the names
//! and types of its table ([`DELTAQ_OBJECTS`]: the Delta-Q names of its
//! manufacturer objects, the CiA 418 names of the shared ones, ours for the
//! charge control), the CiA 301 names of the communication objects, and
//! the charger's own dictionary.

use crate::eds::{DeviceHeader, Eds};

use super::{Charger, DELTAQ_OBJECTS};

/// The EDS (CiA 306, "Electronic data sheet specification for CANopen") of
/// `charger` as it is configured now: every object of its SDO dictionary
/// (`dictionary()`: the PDO objects, the CiA 301 communication
/// objects with 1016h, the CiA 418 objects it shares with the module and
/// the Delta-Q objects) with its access, PDO-mappable flag and current
/// value as `DefaultValue`, named and typed by CiA 301
/// ([`COMM_OBJECTS`](crate::od::comm::COMM_OBJECTS)) and the charger's table
/// ([`DELTAQ_OBJECTS`]: CiA 418 v1.0.1, Delta-Q, ours for the charge
/// control); `[DeviceInfo]` from 1008h and 1018h (see [`Eds::describe_profile`]).
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
#[must_use]
pub fn charger_eds(charger: &Charger) -> Eds {
    let mut od = charger.dictionary().clone();
    Eds::describe_profile(
        &mut od,
        DELTAQ_OBJECTS,
        &DeviceHeader {
            file_name: "charger.eds",
            description: "Delta-Q IC Series charger (canopen-codec)",
            vendor_name: Some("Delta-Q Technologies"),
        },
    )
}
