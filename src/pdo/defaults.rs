//! Default PDO sets as data: one row type, [`DefaultPdo`], for any device
//! profile's table of default PDOs (communication parameters 1400h + n /
//! 1800h + n and mappings 1600h + n / 1A00h + n, CiA 301), and lookups over
//! such a table.
//!
//! The tables themselves belong to the profiles that define them (the
//! CiA 418 battery module's set and the Delta-Q charger's set live in those
//! profile modules).
//!
//! **Numbering.** PDOs count from 0 ([`PdoNumber`]): a profile's "1st TPDO"
//! is `PdoNumber::P0`. **Direction** ([`PdoDirection`]) is seen from the
//! device that owns the PDO: a `Transmit` PDO is one the device sends.
//!
//! ```
//! use canopen_codec::pdo::{default_mapping, find_default, DefaultPdo, MappingEntry, PdoDirection};
//! use canopen_codec::{NodeId, PdoNumber};
//!
//! const TABLE: [DefaultPdo; 1] = [DefaultPdo {
//!     direction: PdoDirection::Transmit,
//!     number: PdoNumber::P0,
//!     communication_index: 0x1800,
//!     mapping_index: 0x1A00,
//!     cob_id_base: 0x180,
//!     transmission_type: 255,
//!     event_timer_ms: 100,
//!     entries: &[(0x6000, 0, 8)],
//!     enabled_by: None,
//! }];
//! let row = find_default(&TABLE, PdoDirection::Transmit, PdoNumber::P0).unwrap();
//! assert_eq!(row.cob_id(NodeId::new(5).unwrap()), 0x185);
//! let m = default_mapping(&TABLE, PdoDirection::Transmit, PdoNumber::P0).unwrap();
//! assert_eq!(m.entries(), &[MappingEntry::new(0x6000, 0, 8)]);
//! assert_eq!(default_mapping(&TABLE, PdoDirection::Receive, PdoNumber::P0), None);
//! ```

use crate::cob_id::{NodeId, PdoNumber};

use super::comm::PdoDirection;
use super::mapping::{MappingEntry, PdoMapping, MAX_ENTRIES};

/// One default PDO of a device profile: its parameters as the profile
/// gives them for a device that has not been configured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DefaultPdo {
    /// Receive or transmit, seen from the device that owns the PDO.
    pub direction: PdoDirection,
    /// PDO number, counted from 0.
    pub number: PdoNumber,
    /// Communication parameter index (1400h + n or 1800h + n).
    pub communication_index: u16,
    /// Mapping parameter index (1600h + n or 1A00h + n).
    pub mapping_index: u16,
    /// Default COB-ID (communication parameter sub 1) without the node id,
    /// flags included (bit 31 set: not valid); see [`DefaultPdo::cob_id`].
    pub cob_id_base: u32,
    /// Transmission type (sub 2; 255: asynchronous, event-driven).
    pub transmission_type: u8,
    /// Default event timer (sub 5) in ms; 0 is off.
    pub event_timer_ms: u16,
    /// Default mapping entries as (index, sub-index, length in bits), sub 1
    /// first. Empty where the profile publishes no default mapping for the
    /// PDO (a default PDO with nothing mapped carries nothing, so the empty
    /// list is never a real default); [`DefaultPdo::mapping`] is `None`
    /// then.
    pub entries: &'static [(u16, u8, u8)],
    /// The device-type (1000h) bits that must all be set for the PDO to
    /// exist; `None` for a PDO every device has.
    pub enabled_by: Option<u32>,
}

impl DefaultPdo {
    /// An asynchronous, event-driven default PDO (transmission type 255,
    /// CiA 301 section 7.5.2.35): PDO `number` of `direction` at its
    /// communication and mapping parameters (1400h/1800h + n,
    /// 1600h/1A00h + n), present on every device (see
    /// [`when_device_type`](Self::when_device_type)).
    #[must_use]
    pub const fn asynchronous(
        direction: PdoDirection,
        number: PdoNumber,
        cob_id_base: u32,
        event_timer_ms: u16,
        entries: &'static [(u16, u8, u8)],
    ) -> Self {
        DefaultPdo {
            direction,
            number,
            communication_index: direction.comm_index(number),
            mapping_index: direction.mapping_index(number),
            cob_id_base,
            transmission_type: 255,
            event_timer_ms,
            entries,
            enabled_by: None,
        }
    }

    /// This PDO present only on a device whose device type (1000h) has all
    /// of `bits` set.
    #[must_use]
    pub const fn when_device_type(mut self, bits: u32) -> Self {
        self.enabled_by = Some(bits);
        self
    }

    /// The default COB-ID (communication parameter sub 1) for a device with
    /// id `node`, flags included.
    #[must_use]
    pub const fn cob_id(&self, node: NodeId) -> u32 {
        self.cob_id_base.wrapping_add(node.raw() as u32)
    }

    /// True if a device whose device type (1000h) is `device_type` has this
    /// PDO.
    #[must_use]
    pub fn is_present(&self, device_type: impl Into<u32>) -> bool {
        match self.enabled_by {
            None => true,
            Some(bits) => device_type.into() & bits == bits,
        }
    }

    /// The mapping entries as CiA 301 Unsigned32 values (index << 16 | sub
    /// << 8 | bits), sub 1 first.
    pub fn mapping_values(&self) -> impl Iterator<Item = u32> + '_ {
        self.entries
            .iter()
            .map(|&(index, sub, bits)| MappingEntry::new(index, sub, bits).to_u32())
    }

    /// Total mapped length in bits.
    #[must_use]
    pub fn total_bits(&self) -> u32 {
        self.entries
            .iter()
            .map(|&(_, _, bits)| u32::from(bits))
            .sum()
    }

    /// The default mapping; `None` where none is published (no entries) or
    /// the entries do not form a valid mapping.
    #[must_use]
    pub fn mapping(&self) -> Option<PdoMapping> {
        if self.entries.is_empty() {
            return None;
        }
        let mut entries = [MappingEntry::default(); MAX_ENTRIES];
        for (slot, &(index, sub, bits)) in entries.iter_mut().zip(self.entries) {
            *slot = MappingEntry::new(index, sub, bits);
        }
        PdoMapping::new(entries.get(..self.entries.len())?).ok()
    }
}

/// The row of `table` for a direction and number, if the table has one.
#[must_use]
pub fn find_default(
    table: &[DefaultPdo],
    direction: PdoDirection,
    number: PdoNumber,
) -> Option<&DefaultPdo> {
    table
        .iter()
        .find(|p| p.direction == direction && p.number == number)
}

/// The default mapping of one PDO of `table`; `None` where the table has no
/// such PDO or publishes no mapping for it.
#[must_use]
pub fn default_mapping(
    table: &[DefaultPdo],
    direction: PdoDirection,
    number: PdoNumber,
) -> Option<PdoMapping> {
    find_default(table, direction, number)?.mapping()
}

#[cfg(test)]
#[path = "defaults_tests.rs"]
mod tests;
