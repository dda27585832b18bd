//! The default PDO set of a CiA 418 battery module (CiA 418 v1.0.1,
//! 6.2.3-6.2.8: the 1st-3rd RPDO and TPDO), as data in the CiA 301 row type
//! [`DefaultPdo`].
//!
//! All six PDOs are asynchronous (transmission type 255). RPDO COB-IDs
//! default to `0x200/0x300/0x400 + node`; the profile allows bit 30 ("no RTR")
//! to be set as well (`4000 0200h + node`), and this table gives the form
//! without it. TPDO COB-IDs default to "not valid" (bit 31 set): the module's
//! application enables them.

use crate::cob_id::PdoNumber;

use super::{
    DeviceType, AH_RETURNED_DURING_LAST_CHARGE, BATTERY_STATE_OF_CHARGE, BATTERY_STATUS,
    BATTERY_VOLTAGE, CHARGER_STATE_OF_CHARGE, CHARGER_STATUS, CHARGE_CURRENT_REQUESTED,
    TEMPERATURE,
};

pub use crate::pdo::{DefaultPdo, PdoDirection};

use crate::pdo::{default_mapping, PdoMapping};

use PdoDirection::{Receive, Transmit};

/// The 1st RPDO's mapping (CiA 418 v1.0.1, 6.2.3): the charger's 6001h.
/// A Delta-Q charger's TPDO 0 carries the same (it pairs with this PDO).
pub const RPDO_1ST_ENTRIES: &[(u16, u8, u8)] = &[(CHARGER_STATUS, 0, 8)];
/// The 2nd RPDO's mapping (CiA 418 v1.0.1, 6.2.4): 6001h, 6052h.
pub const RPDO_2ND_ENTRIES: &[(u16, u8, u8)] = &[
    (CHARGER_STATUS, 0, 8),
    (AH_RETURNED_DURING_LAST_CHARGE, 0, 16),
];
/// The 3rd RPDO's mapping (CiA 418 v1.0.1, 6.2.5): 6001h, 6052h, 6080h.
pub const RPDO_3RD_ENTRIES: &[(u16, u8, u8)] = &[
    (CHARGER_STATUS, 0, 8),
    (AH_RETURNED_DURING_LAST_CHARGE, 0, 16),
    (CHARGER_STATE_OF_CHARGE, 0, 8),
];
/// The 1st TPDO's mapping (CiA 418 v1.0.1, 6.2.6): 6010h, 6000h. A
/// Delta-Q charger's RPDO 0 takes the same (it pairs with this PDO).
pub const TPDO_1ST_ENTRIES: &[(u16, u8, u8)] = &[(TEMPERATURE, 0, 16), (BATTERY_STATUS, 0, 8)];
/// The 2nd TPDO's mapping (CiA 418 v1.0.1, 6.2.7): 6010h, 6000h, 6060h.
pub const TPDO_2ND_ENTRIES: &[(u16, u8, u8)] = &[
    (TEMPERATURE, 0, 16),
    (BATTERY_STATUS, 0, 8),
    (BATTERY_VOLTAGE, 0, 32),
];
/// The 3rd TPDO's mapping (CiA 418 v1.0.1, 6.2.8): 6070h, 6081h.
pub const TPDO_3RD_ENTRIES: &[(u16, u8, u8)] = &[
    (CHARGE_CURRENT_REQUESTED, 0, 16),
    (BATTERY_STATE_OF_CHARGE, 0, 8),
];

/// The CiA 418 default PDOs: 1st, 2nd, 3rd RPDO, then 1st, 2nd, 3rd TPDO
/// (CiA 418 v1.0.1, 6.2.3-6.2.8). The 1st RPDO and TPDO are mandatory, the
/// others exist when device-type bits 16-19 say so; the RPDOs carry the
/// charger's 6001h (+ 6052h, + 6080h), the TPDOs the module's 6010h and
/// 6000h (+ 6060h), and 6070h with 6081h. The profile prints the 1st TPDO's
/// default COB-ID as `80000 0180h`, read as 8000_0180h + node (not valid).
///
/// ```
/// use canopen_codec::cia418::{DEFAULT_PDOS, DeviceType};
/// use canopen_codec::NodeId;
/// let first_tpdo = &DEFAULT_PDOS[3];
/// assert_eq!(first_tpdo.communication_index, 0x1800);
/// assert_eq!(first_tpdo.cob_id(NodeId::new(1).unwrap()), 0x8000_0181);
/// assert_eq!(first_tpdo.entries, &[(0x6010, 0, 16), (0x6000, 0, 8)]);
/// assert!(first_tpdo.is_present(DeviceType::cia418(0)));
/// ```
pub const DEFAULT_PDOS: [DefaultPdo; 6] = [
    DefaultPdo::asynchronous(Receive, PdoNumber::P0, 0x200, 0, RPDO_1ST_ENTRIES),
    DefaultPdo::asynchronous(Receive, PdoNumber::P1, 0x300, 0, RPDO_2ND_ENTRIES)
        .when_device_type(DeviceType::RPDO_2ND),
    DefaultPdo::asynchronous(Receive, PdoNumber::P2, 0x400, 0, RPDO_3RD_ENTRIES)
        .when_device_type(DeviceType::RPDO_3RD),
    DefaultPdo::asynchronous(Transmit, PdoNumber::P0, 0x8000_0180, 200, TPDO_1ST_ENTRIES),
    DefaultPdo::asynchronous(Transmit, PdoNumber::P1, 0x8000_0280, 200, TPDO_2ND_ENTRIES)
        .when_device_type(DeviceType::TPDO_2ND),
    DefaultPdo::asynchronous(Transmit, PdoNumber::P2, 0x8000_0380, 200, TPDO_3RD_ENTRIES)
        .when_device_type(DeviceType::TPDO_3RD),
];

/// The CiA 418 battery module's default mapping of one of its PDOs (from
/// [`DEFAULT_PDOS`]); `None` for PDO 3, which CiA 418 does not define.
///
/// ```
/// use canopen_codec::cia418::{battery_default_mapping, PdoDirection};
/// use canopen_codec::pdo::MappingEntry;
/// use canopen_codec::PdoNumber;
/// let m = battery_default_mapping(PdoDirection::Transmit, PdoNumber::P0).unwrap();
/// assert_eq!(m.entries(), &[MappingEntry::new(0x6010, 0, 16), MappingEntry::new(0x6000, 0, 8)]);
/// ```
#[must_use]
pub fn battery_default_mapping(direction: PdoDirection, number: PdoNumber) -> Option<PdoMapping> {
    default_mapping(&DEFAULT_PDOS, direction, number)
}
