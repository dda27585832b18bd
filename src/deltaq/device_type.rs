//! The battery module's device type (1000h) as the Delta-Q charger reads it
//! ("Delta-Q IC Series CANopen interface specification rev 2.0", section
//! 4.5.5): the charger reads 1000h of the module by SDO, bits 0-15 must be
//! 418, and bits 16-21 say which PDOs the module supports. Delta-Q numbers
//! PDOs from 0, so its "RPDO 1" is CiA 418's "2nd RPDO"; bits 20 and 21 are
//! reserved in CiA 418 and Delta-Q's own.
//!
//! | bit | CiA 418 name | Delta-Q name | here |
//! |---|---|---|---|
//! | 16 | 2nd RPDO | RPDO 1 supported | [`RPDO_1`] = [`DeviceType::RPDO_2ND`] |
//! | 17 | 3rd RPDO | RPDO 2 supported | [`RPDO_2`] = [`DeviceType::RPDO_3RD`] |
//! | 18 | 2nd TPDO | TPDO 1 supported | [`TPDO_1`] = [`DeviceType::TPDO_2ND`] |
//! | 19 | 3rd TPDO | TPDO 2 supported | [`TPDO_2`] = [`DeviceType::TPDO_3RD`] |
//! | 20 | reserved | RPDO 3 supported: the charger sends its TPDO 3 | [`RPDO_3`] |
//! | 21 | reserved | deprecated | [`DEPRECATED`] |
//! | 22-31 | reserved | 0 | |
//!
//! ```
//! use canopen_codec::cia418::DeviceType;
//! use canopen_codec::deltaq::device_type;
//! use canopen_codec::PdoNumber;
//! let dt = DeviceType::cia418(device_type::RPDO_3);
//! assert!(device_type::module_rpdos(dt).contains(PdoNumber::P3));
//! assert!(!dt.rpdos().contains(PdoNumber::P3)); // reserved in CiA 418
//! assert!(device_type::wants_charger_tpdo3(dt));
//! ```

use crate::cia418::{DeviceType, PdoSet};
use crate::cob_id::PdoNumber;

/// Bit 16, Delta-Q "RPDO 1 supported" (CiA 418's 2nd RPDO).
pub const RPDO_1: u32 = DeviceType::RPDO_2ND;
/// Bit 17, Delta-Q "RPDO 2 supported" (CiA 418's 3rd RPDO).
pub const RPDO_2: u32 = DeviceType::RPDO_3RD;
/// Bit 18, Delta-Q "TPDO 1 supported" (CiA 418's 2nd TPDO).
pub const TPDO_1: u32 = DeviceType::TPDO_2ND;
/// Bit 19, Delta-Q "TPDO 2 supported" (CiA 418's 3rd TPDO).
pub const TPDO_2: u32 = DeviceType::TPDO_3RD;
/// Bit 20, Delta-Q "RPDO 3 supported" (reserved in CiA 418): the module
/// receives the charger's manufacturer TPDO 3, which the charger sends only
/// when this bit asks for it.
pub const RPDO_3: u32 = 1 << 20;
/// Bit 21, Delta-Q "deprecated" (reserved in CiA 418).
pub const DEPRECATED: u32 = 1 << 21;

/// The module's receive PDOs as the charger reads them: CiA 418's
/// ([`DeviceType::rpdos`]) plus `P3` for bit 20.
#[must_use]
pub const fn module_rpdos(dt: DeviceType) -> PdoSet {
    let s = dt.rpdos();
    if dt.has(RPDO_3) {
        s.with(PdoNumber::P3)
    } else {
        s
    }
}

/// Bit 20: the module wants the charger's manufacturer TPDO 3.
#[must_use]
pub const fn wants_charger_tpdo3(dt: DeviceType) -> bool {
    dt.has(RPDO_3)
}

/// Bit 21 (deprecated) is set.
#[must_use]
pub const fn deprecated(dt: DeviceType) -> bool {
    dt.has(DEPRECATED)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_table() {
        // Section 4.5.5, the device-type table, with CiA 418's numbering.
        assert_eq!(RPDO_1, 0x0001_0000);
        assert_eq!(RPDO_2, 0x0002_0000);
        assert_eq!(TPDO_1, 0x0004_0000);
        assert_eq!(TPDO_2, 0x0008_0000);
        assert_eq!(RPDO_3, 0x0010_0000);
        assert_eq!(DEPRECATED, 0x0020_0000);
        assert_eq!(RPDO_3 | DEPRECATED, 0x0030_0000);
        assert_eq!(RPDO_3 & !DeviceType::CIA418_RESERVED, 0);
    }

    #[test]
    fn every_pdo_bit() {
        let dt = DeviceType::decode(&[0xA2, 0x01, 0x3F, 0x00]).unwrap();
        assert_eq!(module_rpdos(dt).len(), 4);
        assert_eq!(dt.tpdos().len(), 3);
        assert!(wants_charger_tpdo3(dt));
        assert!(deprecated(dt));
        assert_eq!(dt.cia418_reserved_bits(), RPDO_3 | DEPRECATED);
    }

    #[test]
    fn one_bit_at_a_time() {
        let none = DeviceType::cia418(0);
        assert_eq!(module_rpdos(none), PdoSet::EMPTY.with(PdoNumber::P0));
        assert!(!wants_charger_tpdo3(none) && !deprecated(none));
        for (bit, pdo) in [
            (RPDO_1, PdoNumber::P1),
            (RPDO_2, PdoNumber::P2),
            (RPDO_3, PdoNumber::P3),
        ] {
            let set = module_rpdos(DeviceType::cia418(bit));
            assert_eq!(set, PdoSet::EMPTY.with(PdoNumber::P0).with(pdo));
        }
        let dep = DeviceType::cia418(DEPRECATED);
        assert!(deprecated(dep) && !wants_charger_tpdo3(dep));
        assert_eq!(module_rpdos(dep).len(), 1);
    }
}
