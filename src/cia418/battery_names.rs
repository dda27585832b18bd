//! Names for battery types (6020h sub 1, CiA 418 v1.0.1 appendix A), as
//! people and scenario files write them: `flooded`, `agm`, `gel`,
//! `li-ion`, `nicd`, `nimh`, ... One table ([`NAMES`], re-exported as
//! `BATTERY_TYPE_NAMES`) gives every name its
//! byte `cccc wxyz`; [`BatteryType::from_name`] and [`BatteryType::name`]
//! read it both ways, and [`Chemistry::from_name`] takes the chemistry
//! nibble of the named type.
//!
//! The names are ours (CiA 418 names the bits, not the batteries): the
//! usual trade names where there is one (AGM, gel, NiCd, NiMH, Li-ion),
//! otherwise the chemistry's element symbols. A name without a variant
//! names the variant whose bits are all zero (`flooded`: normal gravity,
//! flat plates; `nicd`: vented, pocket plates).

use super::{BatteryType, Chemistry};

/// Every battery type with a name: the name, then the 6020h sub 1 byte.
/// The first name of a byte is its own ([`BatteryType::name`]); the long
/// chemistry names at the end are aliases that only
/// [`BatteryType::from_name`] reads.
pub const NAMES: [(&str, u8); 28] = [
    // 0001 lead acid: w 0 flooded (y gravity, z plate), w 1 maintenance free (yz).
    ("flooded", 0x10),
    ("flooded-tubular", 0x11),
    ("flooded-high-gravity", 0x12),
    ("flooded-high-gravity-tubular", 0x13),
    ("agm", 0x18),
    ("gel", 0x19),
    ("lead-acid-hybrid", 0x1A),
    // 0010 nickel cadmium: w 0 vented / 1 sealed, z 0 pocket / 1 sintered.
    ("nicd", 0x20),
    ("nicd-sintered", 0x21),
    ("nicd-sealed", 0x28),
    ("nicd-sealed-sintered", 0x29),
    ("nizn", 0x30),
    ("nife", 0x50),
    // 0110 silver oxide: yz the couple.
    ("agzn", 0x60),
    ("agcd", 0x61),
    ("agfe", 0x62),
    ("nih2", 0x70),
    ("nimh", 0x80),
    ("alkaline", 0x90),
    ("li-ion", 0xA0),
    ("znbr", 0xB0),
    ("metal-air", 0xC0),
    ("li-fes", 0xD0),
    ("sodium-beta", 0xE0),
    // Aliases.
    ("lead-acid", 0x10),
    ("lithium-ion", 0xA0),
    ("nickel-cadmium", 0x20),
    ("nickel-metal-hydride", 0x80),
];

impl BatteryType {
    /// The battery type named `name` in [`NAMES`] (ASCII case ignored), or
    /// `None` for a name the table does not have.
    ///
    /// ```
    /// use canopen_codec::cia418::{BatteryType, Chemistry, LeadAcid, MaintenanceFree};
    /// let agm = BatteryType::from_name("AGM").unwrap();
    /// assert_eq!(u8::from(agm), 0x18);
    /// assert_eq!(agm.chemistry(), Chemistry::LeadAcid);
    /// assert_eq!(agm.name(), Some("agm"));
    /// assert_eq!(BatteryType::from_name("li-ion").map(u8::from), Some(0xA0));
    /// assert_eq!(BatteryType::from_name("lipo"), None);
    /// ```
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, raw)| Self::from_u8(raw))
    }

    /// This type's name in [`NAMES`] (`None` for a byte without one: a
    /// reserved bit set, or an unlisted chemistry).
    #[must_use]
    pub fn name(self) -> Option<&'static str> {
        let raw = self.to_u8();
        NAMES.iter().find(|(_, b)| *b == raw).map(|&(n, _)| n)
    }
}

impl Chemistry {
    /// The chemistry of the battery type named `name` in [`NAMES`]
    /// (`"agm"`, `"flooded"` and `"lead-acid"` are all lead acid).
    ///
    /// ```
    /// use canopen_codec::cia418::Chemistry;
    /// assert_eq!(Chemistry::from_name("li-ion"), Some(Chemistry::LithiumIon));
    /// assert_eq!(Chemistry::from_name("gel"), Some(Chemistry::LeadAcid));
    /// assert_eq!(Chemistry::from_name("NiCd"), Some(Chemistry::NickelCadmium));
    /// assert_eq!(Chemistry::from_name(""), None);
    /// ```
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        BatteryType::from_name(name).map(BatteryType::chemistry)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cia418::{Gravity, LeadAcid, MaintenanceFree, NickelCadmiumCell, Plate};

    #[test]
    fn every_name_is_one_byte_and_every_own_name_reads_back() {
        for (i, &(name, raw)) in NAMES.iter().enumerate() {
            let t = BatteryType::from_name(name).unwrap();
            assert_eq!(t.to_u8(), raw, "{name}");
            // The byte decodes to a known chemistry with no reserved bit.
            assert!(!matches!(t.chemistry(), Chemistry::Unknown(_)), "{name}");
            // A name is unique; the byte's own name is its first.
            assert_eq!(NAMES.iter().filter(|(n, _)| *n == name).count(), 1);
            let first = NAMES.iter().position(|(_, b)| *b == raw).unwrap();
            let own = NAMES.get(first).map(|(n, _)| *n);
            assert_eq!(t.name(), own, "{name}");
            assert_eq!(t.name() == Some(name), first == i, "{name}");
        }
    }

    #[test]
    fn names_mean_the_appendix_a_bits() {
        assert_eq!(
            BatteryType::from_name("flooded"),
            Some(BatteryType::LeadAcid {
                kind: LeadAcid::Flooded {
                    gravity: Gravity::Normal,
                    plate: Plate::Flat
                },
                reserved: 0
            })
        );
        assert_eq!(
            BatteryType::from_name("Gel"),
            Some(BatteryType::LeadAcid {
                kind: LeadAcid::MaintenanceFree(MaintenanceFree::Gel),
                reserved: 0
            })
        );
        assert!(matches!(
            BatteryType::from_name("nicd-sealed"),
            Some(BatteryType::NickelCadmium {
                cell: NickelCadmiumCell::Sealed,
                ..
            })
        ));
        assert_eq!(
            Chemistry::from_name("nimh"),
            Some(Chemistry::NickelMetalHydride)
        );
        assert_eq!(Chemistry::from_name("lead-acid"), Some(Chemistry::LeadAcid));
        assert_eq!(BatteryType::from_name("li ion"), None);
        // A reserved bit set, or an unlisted chemistry: no name.
        assert_eq!(BatteryType::from_u8(0x14).name(), None);
        assert_eq!(BatteryType::from_u8(0x40).name(), None);
    }
}
