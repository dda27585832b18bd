//! What CiA 419 (battery charger device profile) itself defines and the
//! crate uses: the charger's device type and the pairing of the charger's
//! PDOs with the battery module's (CiA 419, 7.2: the charger reads the
//! module's COB-IDs by SDO and gives its own paired PDO the same
//! identifier). The Delta-Q IC Series charger built on it is
//! [`crate::deltaq::Charger`].

use crate::cob_id::PdoNumber;
use crate::od::index::{RPDO_COMMUNICATION, TPDO_COMMUNICATION};
use crate::pdo::{Catalogue, PdoDirection};

/// A CiA 419 battery charger's application objects for naming PDO fields
/// and SDO values: the objects 6000h-6090h the charger shares with the
/// battery module (CiA 419 uses the CiA 418 objects for the values the two
/// exchange: battery status, charger status, temperature, battery voltage,
/// charge current requested, states of charge). No manufacturer objects:
/// those need the manufacturer's evidence (see
/// [`crate::deltaq::CHARGER_CATALOGUE`]).
pub const CHARGER_CATALOGUE: Catalogue =
    Catalogue::new("CiA 419 battery charger", &[crate::cia418::CIA418_OBJECTS]);

/// CiA 419 device type (1000h): profile 419 (01A3h), no additional bits.
pub const CHARGER_DEVICE_TYPE: u32 = 419;

/// One PDO pairing of CiA 419, 7.2: the battery module's PDO whose
/// communication parameter is at `module_comm_index` carries the same
/// COB-ID as the charger's PDO `charger_pdo` in direction
/// `charger_direction`. The pair is in use when the module's device type
/// (1000h) has `device_type_bit` set (0: always).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PdoPair {
    /// The module's communication parameter index (1400h + n or 1800h + n).
    pub module_comm_index: u16,
    /// The charger's direction (transmit pairs with a module RPDO).
    pub charger_direction: PdoDirection,
    /// The charger's PDO number.
    pub charger_pdo: PdoNumber,
    /// The device-type bit of the module that declares the pair (0: always).
    pub device_type_bit: u32,
}

const fn pair(index: u16, dir: PdoDirection, pdo: PdoNumber, bit: u32) -> PdoPair {
    PdoPair {
        module_comm_index: index,
        charger_direction: dir,
        charger_pdo: pdo,
        device_type_bit: bit,
    }
}

/// The pairs CiA 419 and CiA 418 define, in the order a charger reads them:
/// charger TPDO 0 / RPDO 0 always (module RPDO 0 at 1400h, TPDO 0 at
/// 1800h); TPDO 1 / 2 when device-type bits 16 / 17 say the module has
/// RPDO 1 / 2; RPDO 1 / 2 when bits 18 / 19 say it has TPDO 1 / 2
/// (CiA 418 v1.0.1, 6.2.1).
pub const PDO_PAIRS: [PdoPair; 6] = [
    pair(RPDO_COMMUNICATION, PdoDirection::Transmit, PdoNumber::P0, 0),
    pair(TPDO_COMMUNICATION, PdoDirection::Receive, PdoNumber::P0, 0),
    pair(
        RPDO_COMMUNICATION + 1,
        PdoDirection::Transmit,
        PdoNumber::P1,
        1 << 16,
    ),
    pair(
        RPDO_COMMUNICATION + 2,
        PdoDirection::Transmit,
        PdoNumber::P2,
        1 << 17,
    ),
    pair(
        TPDO_COMMUNICATION + 1,
        PdoDirection::Receive,
        PdoNumber::P1,
        1 << 18,
    ),
    pair(
        TPDO_COMMUNICATION + 2,
        PdoDirection::Receive,
        PdoNumber::P2,
        1 << 19,
    ),
];

impl PdoPair {
    /// True when a module with device type `device_type` has this pair.
    #[must_use]
    pub const fn is_declared(&self, device_type: u32) -> bool {
        self.device_type_bit == 0 || device_type & self.device_type_bit != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_row_by_row() {
        use PdoDirection::{Receive as R, Transmit as T};
        let (p0, p1, p2) = (PdoNumber::P0, PdoNumber::P1, PdoNumber::P2);
        let want = [
            (0x1400, T, p0, None),
            (0x1800, R, p0, None),
            (0x1401, T, p1, Some(16)),
            (0x1402, T, p2, Some(17)),
            (0x1801, R, p1, Some(18)),
            (0x1802, R, p2, Some(19)),
        ];
        for (p, (index, dir, n, bit)) in PDO_PAIRS.iter().zip(want) {
            assert_eq!(
                (p.module_comm_index, p.charger_direction, p.charger_pdo),
                (index, dir, n)
            );
            assert!(p.is_declared(0x0F_0000 | 418));
            match bit {
                None => assert!(p.is_declared(418)),
                Some(b) => {
                    assert!(!p.is_declared(418 | 0xFFF0_0000));
                    assert!(p.is_declared(418 | 1 << b));
                }
            }
        }
    }
}
