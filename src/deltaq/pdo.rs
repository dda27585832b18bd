//! The Delta-Q charger's default PDO set as data, in the CiA 301 row type
//! [`DefaultPdo`], and which default mapping a COB-ID carries on a bus of
//! the charger and a CiA 418 battery module.
//!
//! Sources: "Delta-Q IC Series CANopen interface specification rev 2.0",
//! section 4.3.2 (default COB-IDs: TPDO n at 180h/280h/380h/480h + node,
//! RPDO n at 200h/300h/400h/500h + node), section 4.5.5 (the pairing of the
//! charger's PDOs with the module's, and the transmit periods: 200 ms for
//! TPDO 0-2, 1000 ms for TPDO 3), section 4.6.1 (TPDO 3 carries 2002h,
//! 2100h, 2006h); the mappings of TPDO 0-2 and RPDO 0-2 are Delta-Q's
//! published EDS defaults, which mirror the CiA 418 module's PDOs, and the
//! EDS gives every PDO transmission type 255 (FFh).
//!
//! **Numbering.** PDOs count from 0 ([`PdoNumber`]), as Delta-Q does: the
//! charger's TPDO 1 (1801h / 1A01h) pairs with CiA 418's "2nd RPDO" of the
//! module. **Direction** ([`PdoDirection`]) is seen from the charger: a
//! `Transmit` PDO is one the charger sends.
//!
//! **Charger RPDO 3 is not published.** Delta-Q's documents give the
//! charger's RPDO 3 (1403h / 1603h) a COB-ID and a pairing (the module's TPDO
//! 3, "not expected from the module") but no mapping; its row here has no
//! entries and [`charger_default_mapping`] returns `None` for it.
//!
//! ```
//! use canopen_codec::deltaq::charger_default_mapping;
//! use canopen_codec::pdo::{MappingEntry, PdoDirection};
//! use canopen_codec::PdoNumber;
//!
//! let tpdo3 = charger_default_mapping(PdoDirection::Transmit, PdoNumber::P3).unwrap();
//! assert_eq!(tpdo3.entries(), &[
//!     MappingEntry::new(0x2002, 0, 16),
//!     MappingEntry::new(0x2100, 0, 16),
//!     MappingEntry::new(0x2006, 0, 16),
//! ]);
//! assert_eq!(charger_default_mapping(PdoDirection::Receive, PdoNumber::P3), None);
//! ```

use crate::cia418::{
    battery_default_mapping, BATTERY_MODULE_CATALOGUE, RPDO_1ST_ENTRIES, RPDO_2ND_ENTRIES,
    RPDO_3RD_ENTRIES, TPDO_1ST_ENTRIES, TPDO_2ND_ENTRIES, TPDO_3RD_ENTRIES,
};
use crate::cob_id::{classify_standard, CobKind, NodeId, PdoNumber};
use crate::od::index::{RPDO_COMMUNICATION, TPDO_COMMUNICATION};
use crate::pdo::{find_default, Catalogue, DefaultPdo, PdoDirection, PdoMapping};

use super::{index, CHARGER_CATALOGUE};

use PdoDirection::{Receive, Transmit};

/// The Delta-Q charger's default PDOs: TPDO 0..3, then RPDO 0..3. TPDOs
/// send every 200 ms (TPDO 3 every 1000 ms); RPDOs have no timer. TPDO 0-2
/// and RPDO 0-2 carry the mappings of the battery module's PDOs they pair
/// with (section 4.5.5; [`paired_module_pdo`]): TPDO n the module's RPDO n
/// (6001h, then 6052h, then 6080h added), RPDO n the module's TPDO n
/// (6010h and 6000h, then 6060h added; 6070h with 6081h); TPDO 3 carries
/// 2002h, 2100h, 2006h; RPDO 3 has no published mapping.
pub const CHARGER_DEFAULT_PDOS: [DefaultPdo; 8] = [
    DefaultPdo::asynchronous(Transmit, PdoNumber::P0, 0x180, 200, RPDO_1ST_ENTRIES),
    DefaultPdo::asynchronous(Transmit, PdoNumber::P1, 0x280, 200, RPDO_2ND_ENTRIES),
    DefaultPdo::asynchronous(Transmit, PdoNumber::P2, 0x380, 200, RPDO_3RD_ENTRIES),
    DefaultPdo::asynchronous(
        Transmit,
        PdoNumber::P3,
        0x480,
        1000,
        &[
            (index::CHARGING_CURRENT, 0, 16),
            (index::BATTERY_VOLTAGE_LEGACY, 0, 16),
            (index::EXTENDED_CHARGE_STATUS, 0, 16),
        ],
    ),
    DefaultPdo::asynchronous(Receive, PdoNumber::P0, 0x200, 0, TPDO_1ST_ENTRIES),
    DefaultPdo::asynchronous(Receive, PdoNumber::P1, 0x300, 0, TPDO_2ND_ENTRIES),
    DefaultPdo::asynchronous(Receive, PdoNumber::P2, 0x400, 0, TPDO_3RD_ENTRIES),
    // Not published by Delta-Q: no entries rather than a guess.
    DefaultPdo::asynchronous(Receive, PdoNumber::P3, 0x500, 0, &[]),
];

/// The charger's default PDO row for a direction and number.
#[must_use]
pub fn charger_default_pdo(direction: PdoDirection, number: PdoNumber) -> &'static DefaultPdo {
    // The table has a row for every direction and number 0..=3; fall back
    // to the first row rather than index.
    find_default(&CHARGER_DEFAULT_PDOS, direction, number).unwrap_or(&CHARGER_DEFAULT_PDOS[0])
}

/// The Delta-Q charger's default mapping of one of its PDOs; `None` for RPDO
/// 3, whose mapping is not published.
#[must_use]
pub fn charger_default_mapping(direction: PdoDirection, number: PdoNumber) -> Option<PdoMapping> {
    charger_default_pdo(direction, number).mapping()
}

/// The battery module's PDO a charger PDO pairs with ("Delta-Q IC Series
/// CANopen interface specification rev 2.0", section 4.5.5): the charger's
/// TPDO n with the module's RPDO n (1400h + n), its RPDO n with the
/// module's TPDO n (1800h + n). Returns the module PDO's direction (seen
/// from the module) and communication parameter index.
#[must_use]
pub const fn paired_module_pdo(charger_pdo: &DefaultPdo) -> (PdoDirection, u16) {
    let n = charger_pdo.number.raw() as u16;
    match charger_pdo.direction {
        Transmit => (Receive, RPDO_COMMUNICATION + n),
        Receive => (Transmit, TPDO_COMMUNICATION + n),
    }
}

/// Which default mapping an 11-bit COB-ID carries, given which node is the
/// charger and which the battery module: a PDO identifier of the charger
/// node gets the charger's default (decoded with [`CHARGER_CATALOGUE`]),
/// one of the battery node the CiA 418 default
/// ([`BATTERY_MODULE_CATALOGUE`]). `None` for any other identifier and
/// where no default mapping exists (charger RPDO 3, PDO 3 of the module).
///
/// This follows the predefined connection set; a charger that copied the
/// module's COB-IDs (CiA 419 configuration) uses other identifiers, for which
/// the caller passes the mapping explicitly.
///
/// ```
/// use canopen_codec::deltaq::{default_mapping_for_cob_id, CHARGER_CATALOGUE};
/// use canopen_codec::pdo::MappingEntry;
/// use canopen_codec::NodeId;
/// let (charger, battery) = (NodeId::new(10).unwrap(), NodeId::new(1).unwrap());
/// let (cat, m) = default_mapping_for_cob_id(0x20A, charger, battery).unwrap();
/// assert_eq!(cat, CHARGER_CATALOGUE);
/// assert_eq!(m.entries(), &[MappingEntry::new(0x6010, 0, 16), MappingEntry::new(0x6000, 0, 8)]);
/// assert_eq!(default_mapping_for_cob_id(0x18B, charger, battery), None);
/// ```
#[must_use]
pub fn default_mapping_for_cob_id(
    cob_id: u16,
    charger: NodeId,
    battery: NodeId,
) -> Option<(Catalogue, PdoMapping)> {
    let (direction, number, node) = match classify_standard(cob_id) {
        CobKind::Tpdo(n, node) => (Transmit, n, node),
        CobKind::Rpdo(n, node) => (Receive, n, node),
        _ => return None,
    };
    if node == charger {
        charger_default_mapping(direction, number).map(|m| (CHARGER_CATALOGUE, m))
    } else if node == battery {
        battery_default_mapping(direction, number).map(|m| (BATTERY_MODULE_CATALOGUE, m))
    } else {
        None
    }
}

#[cfg(test)]
#[path = "pdo_tests.rs"]
mod tests;
