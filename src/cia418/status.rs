//! Status bytes: 6000h battery status, 6001h charger status, 6090h water
//! level status (CiA 418 sections 7.3.1, 7.3.2, 7.3.18).
//!
//! The bit tables of 6000h and 6001h (CiA 418 v1.0.1, 7.3.1 and 7.3.2) are
//! not public in full. Only the bits known are named: 6000h bit 0 "battery
//! ready to be charged", 6001h bit 0 "charger enabled" (as Delta-Q's object
//! list also reads them); every other bit is kept (`from_bits_retain`) so a
//! round trip is exact.

use crate::error::DecodeError;

use super::read_u8;

bitflags::bitflags! {
    /// 6000h battery status (CiA 418 section 7.3.1), written by the battery
    /// module (or, on the Delta-Q charger, by the BMS). Unknown bits are kept.
    ///
    /// ```
    /// use canopen_codec::cia418::BatteryStatus;
    /// let s = BatteryStatus::decode(&[0x01]).unwrap();
    /// assert!(s.contains(BatteryStatus::READY_TO_CHARGE));
    /// let odd = BatteryStatus::decode(&[0x81]).unwrap();
    /// assert_eq!(odd.encode(), [0x81]); // unknown bit 7 kept
    /// ```
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
    pub struct BatteryStatus: u8 {
        /// Bit 0: the battery is ready to be charged (1) or not (0).
        const READY_TO_CHARGE = 0x01;
    }
}

bitflags::bitflags! {
    /// 6001h charger status (CiA 418 section 7.3.2), written by the charger
    /// into the battery module. Unknown bits are kept.
    ///
    /// ```
    /// use canopen_codec::cia418::ChargerStatus;
    /// let s = ChargerStatus::decode(&[0x01]).unwrap();
    /// assert!(s.contains(ChargerStatus::ENABLED));
    /// assert_eq!(s.encode(), [0x01]);
    /// ```
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
    pub struct ChargerStatus: u8 {
        /// Bit 0: the charger is enabled / able to charge (Delta-Q's object
        /// list; mirrored in Delta-Q 2006h bit 5).
        const ENABLED = 0x01;
    }
}

bitflags::bitflags! {
    /// 6090h water level status (CiA 418 section 7.3.18): bit 0 is 0 for
    /// "low" (water needed) and 1 for "full". Other bits are kept.
    ///
    /// ```
    /// use canopen_codec::cia418::WaterLevelStatus;
    /// assert!(WaterLevelStatus::decode(&[0x00]).unwrap().is_low());
    /// assert!(WaterLevelStatus::decode(&[0x01]).unwrap().is_full());
    /// ```
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
    pub struct WaterLevelStatus: u8 {
        /// Bit 0: water level full (1) or low (0).
        const FULL = 0x01;
    }
}

macro_rules! status_codec {
    ($ty:ident) => {
        impl $ty {
            /// Decodes the 1-byte object value; every byte is accepted and
            /// unknown bits are kept.
            pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
                read_u8(data).map(Self::from_bits_retain)
            }

            /// The 1-byte object value, unknown bits included.
            #[must_use]
            pub const fn encode(self) -> [u8; 1] {
                [self.bits()]
            }
        }

        impl From<u8> for $ty {
            fn from(raw: u8) -> Self {
                Self::from_bits_retain(raw)
            }
        }

        impl From<$ty> for u8 {
            fn from(s: $ty) -> u8 {
                s.bits()
            }
        }
    };
}

status_codec!(BatteryStatus);
status_codec!(ChargerStatus);
status_codec!(WaterLevelStatus);

impl WaterLevelStatus {
    /// Bit 0 set: the water level is full.
    #[must_use]
    pub const fn is_full(self) -> bool {
        self.contains(Self::FULL)
    }

    /// Bit 0 clear: the water level is low (water must be added).
    #[must_use]
    pub const fn is_low(self) -> bool {
        !self.is_full()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn battery_status_bytes() {
        assert_eq!(BatteryStatus::decode(&[0x00]), Ok(BatteryStatus::empty()));
        assert_eq!(
            BatteryStatus::decode(&[0x01]),
            Ok(BatteryStatus::READY_TO_CHARGE)
        );
        assert_eq!(BatteryStatus::READY_TO_CHARGE.encode(), [0x01]);
        for raw in 0..=u8::MAX {
            assert_eq!(BatteryStatus::decode(&[raw]).unwrap().encode(), [raw]);
            assert_eq!(ChargerStatus::decode(&[raw]).unwrap().encode(), [raw]);
            assert_eq!(WaterLevelStatus::decode(&[raw]).unwrap().encode(), [raw]);
            assert_eq!(u8::from(BatteryStatus::from(raw)), raw);
        }
    }

    #[test]
    fn charger_status_bytes() {
        assert_eq!(ChargerStatus::decode(&[0x01]), Ok(ChargerStatus::ENABLED));
        let s = ChargerStatus::decode(&[0xFE]).unwrap();
        assert!(!s.contains(ChargerStatus::ENABLED));
        assert_eq!(s.bits(), 0xFE);
    }

    #[test]
    fn water_level_bytes() {
        assert!(WaterLevelStatus::decode(&[0x00]).unwrap().is_low());
        assert!(WaterLevelStatus::decode(&[0x01]).unwrap().is_full());
        assert!(WaterLevelStatus::decode(&[0x02]).unwrap().is_low());
        assert_eq!(WaterLevelStatus::FULL.encode(), [0x01]);
    }

    #[test]
    fn status_lengths() {
        crate::error::assert_exact_length(BatteryStatus::decode, 1);
        crate::error::assert_exact_length(ChargerStatus::decode, 1);
    }
}
