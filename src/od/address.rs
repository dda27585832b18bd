//! The address of one object-dictionary entry: an index and a sub-index
//! (CiA 301, "object dictionary"). SDO, PDO mapping entries, EDS sections
//! and the decoder's names all speak of entries by this pair.

use core::fmt;

/// One entry of an object dictionary: the 16-bit index and the 8-bit
/// sub-index. It is what an SDO request's multiplexer (bytes 1-3), a PDO
/// mapping entry's upper 24 bits and an EDS section name (`[1017]`,
/// `[1018sub2]`) name.
///
/// It displays as the CiA 301 documents write it, `1018h sub 2`; `{:#}`
/// gives the compact form tools print, `1018h:02`.
///
/// ```
/// use canopen_codec::od::Address;
///
/// let serial = Address::new(0x1018, 4);
/// assert_eq!(serial.to_string(), "1018h sub 4");
/// assert_eq!(format!("{serial:#}"), "1018h:04");
/// assert_eq!(Address::from_multiplexer([0x18, 0x10, 0x04]), serial);
/// assert_eq!(serial.multiplexer(), [0x18, 0x10, 0x04]);
/// assert_eq!(Address::index(0x1017), Address::new(0x1017, 0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Address {
    /// The object's index (0000h-FFFFh).
    pub index: u16,
    /// The sub-index within the object (0 for a variable).
    pub sub: u8,
}

impl Address {
    /// The entry `index`, sub-index `sub`.
    #[must_use]
    pub const fn new(index: u16, sub: u8) -> Self {
        Address { index, sub }
    }

    /// Sub-index 0 of `index`: a variable, or the entry count of an array
    /// or record.
    #[must_use]
    pub const fn index(index: u16) -> Self {
        Address { index, sub: 0 }
    }

    /// The same object at sub-index `sub`.
    #[must_use]
    pub const fn with_sub(self, sub: u8) -> Self {
        Address {
            index: self.index,
            sub,
        }
    }

    /// The SDO multiplexer bytes: the index little-endian, then the sub-index.
    #[must_use]
    pub const fn multiplexer(self) -> [u8; 3] {
        let [lo, hi] = self.index.to_le_bytes();
        [lo, hi, self.sub]
    }

    /// The entry an SDO multiplexer names.
    #[must_use]
    pub const fn from_multiplexer(bytes: [u8; 3]) -> Self {
        Address {
            index: u16::from_le_bytes([bytes[0], bytes[1]]),
            sub: bytes[2],
        }
    }
}

impl From<(u16, u8)> for Address {
    fn from((index, sub): (u16, u8)) -> Self {
        Address { index, sub }
    }
}

impl From<Address> for (u16, u8) {
    fn from(a: Address) -> Self {
        (a.index, a.sub)
    }
}

impl fmt::Display for Address {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if f.alternate() {
            write!(f, "{:04X}h:{:02X}", self.index, self.sub)
        } else {
            write!(f, "{:04X}h sub {}", self.index, self.sub)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multiplexer_round_trips_every_sub_of_an_index() {
        for sub in 0..=u8::MAX {
            let a = Address::new(0xA5C3, sub);
            assert_eq!(a.multiplexer(), [0xC3, 0xA5, sub]);
            assert_eq!(Address::from_multiplexer(a.multiplexer()), a);
        }
    }

    #[test]
    fn orders_by_index_then_sub() {
        assert!(Address::new(0x1017, 0xFF) < Address::new(0x1018, 0));
        assert!(Address::new(0x1018, 1) < Address::new(0x1018, 2));
        let pair: (u16, u8) = Address::new(0x6052, 0).into();
        assert_eq!(pair, (0x6052, 0));
    }
}
