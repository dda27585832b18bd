//! 1000h device type of a CiA 418 battery module (CiA 418 v1.0.1, 6.2.1):
//! bits 0-15 the device profile number (418), bits 16-19 the optional PDOs,
//! bits 20-31 reserved (0).
//!
//! | bit | CiA 418 name | this crate |
//! |---|---|---|
//! | 16 | 2nd RPDO | [`DeviceType::RPDO_2ND`], RPDO `P1` |
//! | 17 | 3rd RPDO | [`DeviceType::RPDO_3RD`], RPDO `P2` |
//! | 18 | 2nd TPDO | [`DeviceType::TPDO_2ND`], TPDO `P1` |
//! | 19 | 3rd TPDO | [`DeviceType::TPDO_3RD`], TPDO `P2` |
//! | 20-31 | reserved | [`DeviceType::CIA418_RESERVED`] |
//!
//! The 1st RPDO and 1st TPDO (`P0`) are mandatory and always present. All
//! 32 bits are kept, so a round trip is exact (a vendor that gives reserved
//! bits a meaning reads them in its own profile module).

use crate::cob_id::PdoNumber;
use crate::error::DecodeError;

use super::read_u32;

/// A set of PDO numbers `0..=3` (one bit each).
///
/// ```
/// use canopen_codec::cia418::PdoSet;
/// use canopen_codec::PdoNumber;
/// let s = PdoSet::EMPTY.with(PdoNumber::P0).with(PdoNumber::P2);
/// assert!(s.contains(PdoNumber::P2) && !s.contains(PdoNumber::P1));
/// assert_eq!(s.iter().map(PdoNumber::raw).collect::<Vec<_>>(), [0, 2]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct PdoSet(u8);

impl PdoSet {
    /// No PDO.
    pub const EMPTY: PdoSet = PdoSet(0);

    /// This set plus `pdo`.
    #[must_use]
    pub const fn with(self, pdo: PdoNumber) -> Self {
        PdoSet(self.0 | 1 << (pdo.raw() & 3))
    }

    /// True if `pdo` is in the set.
    #[must_use]
    pub const fn contains(self, pdo: PdoNumber) -> bool {
        self.0 & 1 << (pdo.raw() & 3) != 0
    }

    /// Number of PDOs in the set.
    #[must_use]
    pub const fn len(self) -> usize {
        self.0.count_ones() as usize
    }

    /// True for the empty set.
    #[must_use]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The PDOs in ascending order.
    pub fn iter(self) -> impl Iterator<Item = PdoNumber> {
        (0..4u8)
            .filter_map(PdoNumber::new)
            .filter(move |&p| self.contains(p))
    }
}

/// Device type, object 1000h, of a CiA 418 battery module. Keeps all 32 bits.
///
/// ```
/// use canopen_codec::cia418::DeviceType;
/// use canopen_codec::PdoNumber;
/// // 418 with the 2nd RPDO (bit 16) and the 3rd TPDO (bit 19): 0x0009_01A2.
/// let dt = DeviceType::decode(&[0xA2, 0x01, 0x09, 0x00]).unwrap();
/// assert!(dt.is_cia418());
/// assert!(dt.rpdos().contains(PdoNumber::P1));
/// assert!(dt.tpdos().contains(PdoNumber::P2));
/// assert!(!dt.tpdos().contains(PdoNumber::P1));
/// assert_eq!(dt.encode(), [0xA2, 0x01, 0x09, 0x00]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DeviceType(u32);

impl DeviceType {
    /// Device profile number of CiA 418 (bits 0-15).
    pub const PROFILE_NUMBER: u16 = 418;

    /// Bit 16: CiA 418 "2nd RPDO" (RPDO `P1`).
    pub const RPDO_2ND: u32 = 1 << 16;
    /// Bit 17: CiA 418 "3rd RPDO" (RPDO `P2`).
    pub const RPDO_3RD: u32 = 1 << 17;
    /// Bit 18: CiA 418 "2nd TPDO" (TPDO `P1`).
    pub const TPDO_2ND: u32 = 1 << 18;
    /// Bit 19: CiA 418 "3rd TPDO" (TPDO `P2`).
    pub const TPDO_3RD: u32 = 1 << 19;

    /// Bits 20-31, reserved by CiA 418 (shall read 0).
    pub const CIA418_RESERVED: u32 = 0xFFF0_0000;

    /// Wraps any raw value.
    #[must_use]
    pub const fn from_raw(raw: u32) -> Self {
        DeviceType(raw)
    }

    /// A CiA 418 device type (profile 418) with the given optional bits
    /// (any of the bit constants above, or-ed; other bits are kept as given).
    #[must_use]
    pub const fn cia418(optional_bits: u32) -> Self {
        DeviceType(optional_bits & 0xFFFF_0000 | Self::PROFILE_NUMBER as u32)
    }

    /// The raw Unsigned32.
    #[must_use]
    pub const fn raw(self) -> u32 {
        self.0
    }

    /// Bits 0-15: the device profile number.
    #[must_use]
    pub const fn profile_number(self) -> u16 {
        self.0 as u16
    }

    /// Bits 16-31: the additional information.
    #[must_use]
    pub const fn additional_info(self) -> u16 {
        (self.0 >> 16) as u16
    }

    /// True if bits 0-15 are 418.
    #[must_use]
    pub const fn is_cia418(self) -> bool {
        self.profile_number() == Self::PROFILE_NUMBER
    }

    /// True if every bit of `mask` is set.
    #[must_use]
    pub const fn has(self, mask: u32) -> bool {
        self.0 & mask == mask
    }

    /// Bits CiA 418 reserves (20-31) that are set; 0 on a conforming module
    /// (a vendor's own use of them shows up here too).
    #[must_use]
    pub const fn cia418_reserved_bits(self) -> u32 {
        self.0 & Self::CIA418_RESERVED
    }

    /// The battery module's receive PDOs: `P0` always (mandatory), `P1` for
    /// bit 16, `P2` for bit 17.
    #[must_use]
    pub const fn rpdos(self) -> PdoSet {
        self.pdos(Self::RPDO_2ND, Self::RPDO_3RD)
    }

    /// The battery module's transmit PDOs: `P0` always (mandatory), `P1` for
    /// bit 18, `P2` for bit 19.
    #[must_use]
    pub const fn tpdos(self) -> PdoSet {
        self.pdos(Self::TPDO_2ND, Self::TPDO_3RD)
    }

    /// `P0` (mandatory), `P1` if the bit `second` is set, `P2` if `third` is.
    const fn pdos(self, second: u32, third: u32) -> PdoSet {
        let mut s = PdoSet::EMPTY.with(PdoNumber::P0);
        if self.has(second) {
            s = s.with(PdoNumber::P1);
        }
        if self.has(third) {
            s = s.with(PdoNumber::P2);
        }
        s
    }

    /// Decodes the 4 little-endian bytes of 1000h (any value).
    pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
        read_u32(data).map(DeviceType)
    }

    /// The 4 little-endian bytes of 1000h.
    #[must_use]
    pub const fn encode(self) -> [u8; 4] {
        self.0.to_le_bytes()
    }
}

crate::bytes::raw_word!(DeviceType: u32, DeviceType, |d: DeviceType| d.0);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_table() {
        // CiA 418 v1.0.1, 6.2.1: the optional-PDO bits of 1000h.
        assert_eq!(DeviceType::RPDO_2ND, 0x0001_0000);
        assert_eq!(DeviceType::RPDO_3RD, 0x0002_0000);
        assert_eq!(DeviceType::TPDO_2ND, 0x0004_0000);
        assert_eq!(DeviceType::TPDO_3RD, 0x0008_0000);
        assert_eq!(DeviceType::CIA418_RESERVED, 0xFFF0_0000);
    }

    #[test]
    fn bare_418() {
        let dt = DeviceType::decode(&[0xA2, 0x01, 0x00, 0x00]).unwrap();
        assert_eq!(dt.profile_number(), 418);
        assert!(dt.is_cia418());
        assert_eq!(dt.additional_info(), 0);
        assert_eq!(dt.rpdos(), PdoSet::EMPTY.with(PdoNumber::P0));
        assert_eq!(dt.tpdos(), PdoSet::EMPTY.with(PdoNumber::P0));
        assert_eq!(DeviceType::cia418(0), dt);
    }

    #[test]
    fn every_pdo_bit() {
        let dt = DeviceType::decode(&[0xA2, 0x01, 0x3F, 0x00]).unwrap();
        assert_eq!(dt.raw(), 0x003F_01A2);
        assert_eq!(dt.rpdos().len(), 3);
        assert_eq!(dt.tpdos().len(), 3);
        assert!(!dt.rpdos().contains(PdoNumber::P3));
        assert!(!dt.tpdos().contains(PdoNumber::P3));
        assert_eq!(dt.cia418_reserved_bits(), 0x0030_0000);
        assert_eq!(dt.encode(), [0xA2, 0x01, 0x3F, 0x00]);
    }

    #[test]
    fn one_bit_at_a_time() {
        let rows: [(u32, Option<PdoNumber>, Option<PdoNumber>); 4] = [
            (DeviceType::RPDO_2ND, Some(PdoNumber::P1), None),
            (DeviceType::RPDO_3RD, Some(PdoNumber::P2), None),
            (DeviceType::TPDO_2ND, None, Some(PdoNumber::P1)),
            (DeviceType::TPDO_3RD, None, Some(PdoNumber::P2)),
        ];
        for (bit, rpdo, tpdo) in rows {
            let dt = DeviceType::cia418(bit);
            assert_eq!(dt.rpdos().len(), 1 + usize::from(rpdo.is_some()));
            assert_eq!(dt.tpdos().len(), 1 + usize::from(tpdo.is_some()));
            if let Some(p) = rpdo {
                assert!(dt.rpdos().contains(p));
            }
            if let Some(p) = tpdo {
                assert!(dt.tpdos().contains(p));
            }
            assert_eq!(dt.cia418_reserved_bits(), 0);
        }
    }

    #[test]
    fn other_profiles_and_reserved_bits_kept() {
        let dt = DeviceType::from_raw(0xFFC0_0193); // 403 + reserved bits
        assert!(!dt.is_cia418());
        assert_eq!(dt.cia418_reserved_bits(), 0xFFC0_0000);
        assert_eq!(DeviceType::decode(&dt.encode()), Ok(dt));
        assert_eq!(u32::from(DeviceType::from(0xDEAD_BEEF)), 0xDEAD_BEEF);
        assert!(DeviceType::decode(&[1, 2, 3]).is_err());
    }
}
