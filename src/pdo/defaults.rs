//! Default PDO sets as data: the Delta-Q charger's TPDOs 0-3 and RPDOs 0-3
//! (DIGEST section 4, "Charger default PDO mappings" and the pairing table),
//! and the battery module's CiA 418 set ([`crate::cia418::DEFAULT_PDOS`]) as
//! [`PdoMapping`]s.
//!
//! **Numbering.** PDOs count from 0 ([`PdoNumber`]), as Delta-Q does: the
//! charger's TPDO 1 (1801h / 1A01h) pairs with CiA 418's "2nd RPDO" of the
//! module. **Direction** ([`PdoDirection`]) is seen from the device that owns
//! the PDO: a charger `Transmit` PDO is one the charger sends.
//!
//! **Charger RPDO 3 is not published.** Delta-Q's documents give the
//! charger's RPDO 3 (1403h / 1603h) a COB-ID and a pairing (the module's TPDO
//! 3, "not expected from the module") but no mapping; its row here has
//! `entries: None` and [`charger_default_mapping`] returns `None` for it.
//!
//! ```
//! use canopen_codec::cia418::PdoDirection;
//! use canopen_codec::pdo::{charger_default_mapping, MappingEntry};
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

use crate::cia418::{PdoDirection, DEFAULT_PDOS};
use crate::cob_id::{classify_standard, CobKind, NodeId, PdoNumber};

use super::catalogue::Catalogue;
use super::mapping::{MappingEntry, PdoMapping};

/// One default PDO of the Delta-Q charger (DIGEST section 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ChargerDefaultPdo {
    /// Transmit (the charger sends it) or receive (the charger consumes it).
    pub direction: PdoDirection,
    /// PDO number, counted from 0.
    pub number: PdoNumber,
    /// Communication parameter index (1400h + n or 1800h + n).
    pub communication_index: u16,
    /// Mapping parameter index (1600h + n or 1A00h + n).
    pub mapping_index: u16,
    /// Default COB-ID without the node id (0x180/0x280/0x380/0x480 for
    /// TPDOs, 0x200/0x300/0x400/0x500 for RPDOs); see
    /// [`ChargerDefaultPdo::cob_id`].
    pub cob_id_base: u16,
    /// Transmit period in ms (200 for TPDO 0..2, 1000 for TPDO 3); `None`
    /// for receive PDOs.
    pub period_ms: Option<u16>,
    /// Default mapping entries, sub 1 first; `None` where the mapping is not
    /// published (RPDO 3).
    pub entries: Option<&'static [MappingEntry]>,
    /// The battery module's PDO this one pairs with, seen from the module
    /// (the charger's TPDO n pairs with the module's RPDO n and vice versa).
    pub paired_direction: PdoDirection,
    /// The paired module PDO's communication parameter index.
    pub paired_communication_index: u16,
}

impl ChargerDefaultPdo {
    /// The default 11-bit COB-ID for a charger with id `node`
    /// (`0x18A` for TPDO 0 of node 10).
    #[must_use]
    pub const fn cob_id(&self, node: NodeId) -> u16 {
        self.cob_id_base + node.raw() as u16
    }

    /// The default mapping, `None` where it is not published.
    #[must_use]
    pub fn mapping(&self) -> Option<PdoMapping> {
        self.entries.and_then(|e| PdoMapping::new(e).ok())
    }
}

const fn e(index: u16, bits: u8) -> MappingEntry {
    MappingEntry::new(index, 0, bits)
}

/// The Delta-Q charger's default PDOs: TPDO 0..3, then RPDO 0..3 (DIGEST
/// section 4).
pub const CHARGER_DEFAULT_PDOS: [ChargerDefaultPdo; 8] = [
    ChargerDefaultPdo {
        direction: PdoDirection::Transmit,
        number: PdoNumber::P0,
        communication_index: 0x1800,
        mapping_index: 0x1A00,
        cob_id_base: 0x180,
        period_ms: Some(200),
        entries: Some(&[e(0x6001, 8)]),
        paired_direction: PdoDirection::Receive,
        paired_communication_index: 0x1400,
    },
    ChargerDefaultPdo {
        direction: PdoDirection::Transmit,
        number: PdoNumber::P1,
        communication_index: 0x1801,
        mapping_index: 0x1A01,
        cob_id_base: 0x280,
        period_ms: Some(200),
        entries: Some(&[e(0x6001, 8), e(0x6052, 16)]),
        paired_direction: PdoDirection::Receive,
        paired_communication_index: 0x1401,
    },
    ChargerDefaultPdo {
        direction: PdoDirection::Transmit,
        number: PdoNumber::P2,
        communication_index: 0x1802,
        mapping_index: 0x1A02,
        cob_id_base: 0x380,
        period_ms: Some(200),
        entries: Some(&[e(0x6001, 8), e(0x6052, 16), e(0x6080, 8)]),
        paired_direction: PdoDirection::Receive,
        paired_communication_index: 0x1402,
    },
    ChargerDefaultPdo {
        direction: PdoDirection::Transmit,
        number: PdoNumber::P3,
        communication_index: 0x1803,
        mapping_index: 0x1A03,
        cob_id_base: 0x480,
        period_ms: Some(1000),
        entries: Some(&[e(0x2002, 16), e(0x2100, 16), e(0x2006, 16)]),
        paired_direction: PdoDirection::Receive,
        paired_communication_index: 0x1403,
    },
    ChargerDefaultPdo {
        direction: PdoDirection::Receive,
        number: PdoNumber::P0,
        communication_index: 0x1400,
        mapping_index: 0x1600,
        cob_id_base: 0x200,
        period_ms: None,
        entries: Some(&[e(0x6010, 16), e(0x6000, 8)]),
        paired_direction: PdoDirection::Transmit,
        paired_communication_index: 0x1800,
    },
    ChargerDefaultPdo {
        direction: PdoDirection::Receive,
        number: PdoNumber::P1,
        communication_index: 0x1401,
        mapping_index: 0x1601,
        cob_id_base: 0x300,
        period_ms: None,
        entries: Some(&[e(0x6010, 16), e(0x6000, 8), e(0x6060, 32)]),
        paired_direction: PdoDirection::Transmit,
        paired_communication_index: 0x1801,
    },
    ChargerDefaultPdo {
        direction: PdoDirection::Receive,
        number: PdoNumber::P2,
        communication_index: 0x1402,
        mapping_index: 0x1602,
        cob_id_base: 0x400,
        period_ms: None,
        entries: Some(&[e(0x6070, 16), e(0x6081, 8)]),
        paired_direction: PdoDirection::Transmit,
        paired_communication_index: 0x1802,
    },
    ChargerDefaultPdo {
        direction: PdoDirection::Receive,
        number: PdoNumber::P3,
        communication_index: 0x1403,
        mapping_index: 0x1603,
        cob_id_base: 0x500,
        period_ms: None,
        // Not published by Delta-Q: no entries rather than a guess.
        entries: None,
        paired_direction: PdoDirection::Transmit,
        paired_communication_index: 0x1803,
    },
];

/// The charger's default PDO row for a direction and number.
#[must_use]
pub fn charger_default_pdo(
    direction: PdoDirection,
    number: PdoNumber,
) -> &'static ChargerDefaultPdo {
    let row = match direction {
        PdoDirection::Transmit => 0,
        PdoDirection::Receive => 4,
    } + usize::from(number.raw() & 3);
    // The table has 8 rows and `row` is below 8; fall back to the first row
    // rather than index.
    CHARGER_DEFAULT_PDOS
        .get(row)
        .unwrap_or(&CHARGER_DEFAULT_PDOS[0])
}

/// The Delta-Q charger's default mapping of one of its PDOs; `None` for RPDO
/// 3, whose mapping is not published.
#[must_use]
pub fn charger_default_mapping(direction: PdoDirection, number: PdoNumber) -> Option<PdoMapping> {
    charger_default_pdo(direction, number).mapping()
}

/// The CiA 418 battery module's default mapping of one of its PDOs (from
/// [`DEFAULT_PDOS`]); `None` for PDO 3, which CiA 418 does not define.
///
/// ```
/// use canopen_codec::cia418::PdoDirection;
/// use canopen_codec::pdo::{battery_default_mapping, MappingEntry};
/// use canopen_codec::PdoNumber;
/// let m = battery_default_mapping(PdoDirection::Transmit, PdoNumber::P0).unwrap();
/// assert_eq!(m.entries(), &[MappingEntry::new(0x6010, 0, 16), MappingEntry::new(0x6000, 0, 8)]);
/// ```
#[must_use]
pub fn battery_default_mapping(direction: PdoDirection, number: PdoNumber) -> Option<PdoMapping> {
    let pdo = DEFAULT_PDOS
        .iter()
        .find(|p| p.direction == direction && p.number == number)?;
    let mut entries = [MappingEntry::default(); super::MAX_ENTRIES];
    for (slot, &(index, sub, bits)) in entries.iter_mut().zip(pdo.entries) {
        *slot = MappingEntry::new(index, sub, bits);
    }
    PdoMapping::new(entries.get(..pdo.entries.len())?).ok()
}

/// Which default mapping an 11-bit COB-ID carries, given which node is the
/// charger and which the battery module: a PDO identifier of the charger
/// node gets the charger's default (decoded with
/// [`Catalogue::DeltaQCharger`]), one of the battery node the CiA 418
/// default ([`Catalogue::BatteryModule`]). `None` for any other identifier
/// and where no default mapping exists (charger RPDO 3, PDO 3 of the module).
///
/// This follows the predefined connection set; a charger that copied the
/// module's COB-IDs (CiA 419 configuration) uses other identifiers, for which
/// the caller passes the mapping explicitly.
///
/// ```
/// use canopen_codec::pdo::{default_mapping_for_cob_id, Catalogue, MappingEntry};
/// use canopen_codec::NodeId;
/// let (charger, battery) = (NodeId::new(10).unwrap(), NodeId::new(1).unwrap());
/// let (cat, m) = default_mapping_for_cob_id(0x20A, charger, battery).unwrap();
/// assert_eq!(cat, Catalogue::DeltaQCharger);
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
        CobKind::Tpdo(n, node) => (PdoDirection::Transmit, n, node),
        CobKind::Rpdo(n, node) => (PdoDirection::Receive, n, node),
        _ => return None,
    };
    if node == charger {
        charger_default_mapping(direction, number).map(|m| (Catalogue::DeltaQCharger, m))
    } else if node == battery {
        battery_default_mapping(direction, number).map(|m| (Catalogue::BatteryModule, m))
    } else {
        None
    }
}

#[cfg(test)]
#[path = "defaults_tests.rs"]
mod tests;
