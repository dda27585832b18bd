//! PDO communication parameters (objects 1400h-1403h / 1800h-1803h), CiA 301.
//!
//! | sub | name | type |
//! |---|---|---|
//! | 0 | highest sub-index | U8 (5 here; read-only) |
//! | 1 | COB-ID | U32: bit 31 not valid, bit 30 no RTR, bit 29 29-bit frame, 28-0 id |
//! | 2 | transmission type | U8 |
//! | 3 | inhibit time | U16, 100 µs units (TPDO) |
//! | 4 | reserved / compatibility entry | U8 |
//! | 5 | event timer | U16, ms |

use core::fmt;

use crate::abort::AbortCode;
use crate::cob_id::PdoNumber;
use crate::frame::CanId;
use crate::od::index::{RPDO_COMMUNICATION, TPDO_COMMUNICATION};

/// Direction of a PDO, seen from the device that holds it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PdoDirection {
    /// Receive PDO: consumed (comm. 1400h + n, mapping 1600h + n).
    Receive,
    /// Transmit PDO: produced (comm. 1800h + n, mapping 1A00h + n).
    Transmit,
}

impl PdoDirection {
    /// The communication parameter index of PDO `n`.
    #[must_use]
    pub const fn comm_index(self, n: PdoNumber) -> u16 {
        match self {
            PdoDirection::Receive => RPDO_COMMUNICATION + n.raw() as u16,
            PdoDirection::Transmit => TPDO_COMMUNICATION + n.raw() as u16,
        }
    }

    /// The mapping parameter index of PDO `n`.
    #[must_use]
    pub const fn mapping_index(self, n: PdoNumber) -> u16 {
        self.comm_index(n) + 0x200
    }

    /// Which PDO an index 1400h-1403h / 1600h-1603h / 1800h-1803h /
    /// 1A00h-1A03h belongs to, and whether it is the mapping object.
    #[must_use]
    pub const fn from_index(index: u16) -> Option<(PdoDirection, PdoNumber, bool)> {
        // A mask and two compares.
        let base = index & !0x0203;
        let dir = if base == RPDO_COMMUNICATION {
            PdoDirection::Receive
        } else if base == TPDO_COMMUNICATION {
            PdoDirection::Transmit
        } else {
            return None;
        };
        match PdoNumber::new((index & 3) as u8) {
            Some(n) => Some((dir, n, index & 0x0200 != 0)),
            None => None,
        }
    }
}

/// Whether `index` is a PDO object, 1400h-1403h / 1600h-1603h /
/// 1800h-1803h / 1A00h-1A03h (`PdoDirection::from_index(index).is_some()`,
/// without working out which).
#[inline]
pub(crate) const fn is_pdo_index(index: u16) -> bool {
    let base = index & !0x0203;
    base == RPDO_COMMUNICATION || base == TPDO_COMMUNICATION
}

/// A PDO COB-ID entry (sub-index 1): the identifier plus three flags.
/// Every u32 is accepted and kept bit for bit.
///
/// ```
/// use canopen_codec::pdo::PdoCobId;
/// use canopen_codec::CanId;
/// let c = PdoCobId::from_u32(0x8000_0181); // CiA 418 1st TPDO default: not valid
/// assert!(!c.is_valid());
/// assert_eq!(c.can_id(), Some(CanId::Standard(0x181)));
/// assert_eq!(c.with_valid(true).to_u32(), 0x0000_0181);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct PdoCobId(u32);

impl PdoCobId {
    /// Bit 31: the PDO does not exist / is not valid.
    pub const NOT_VALID: u32 = 1 << 31;
    /// Bit 30: no RTR allowed on this PDO.
    pub const NO_RTR: u32 = 1 << 30;
    /// Bit 29: 29-bit identifier.
    pub const EXTENDED: u32 = 1 << 29;

    /// From the Unsigned32.
    #[must_use]
    pub const fn from_u32(raw: u32) -> Self {
        PdoCobId(raw)
    }

    /// A valid COB-ID on an 11-bit identifier, RTR allowed.
    #[must_use]
    pub const fn standard(id: u16) -> Self {
        PdoCobId((id & 0x7FF) as u32)
    }

    /// The Unsigned32.
    #[must_use]
    pub const fn to_u32(self) -> u32 {
        self.0
    }

    /// True when bit 31 is clear: the PDO is in use.
    #[must_use]
    pub const fn is_valid(self) -> bool {
        self.0 & Self::NOT_VALID == 0
    }

    /// True when bit 30 is clear: remote requests are allowed.
    #[must_use]
    pub const fn rtr_allowed(self) -> bool {
        self.0 & Self::NO_RTR == 0
    }

    /// True when bit 29 is set: a 29-bit identifier.
    #[must_use]
    pub const fn is_extended(self) -> bool {
        self.0 & Self::EXTENDED != 0
    }

    /// The identifier bits (28-0; only 10-0 for an 11-bit identifier).
    #[must_use]
    pub const fn id_bits(self) -> u32 {
        if self.is_extended() {
            self.0 & 0x1FFF_FFFF
        } else {
            self.0 & 0x7FF
        }
    }

    /// The CAN identifier. `None` when an 11-bit COB-ID has bits set in
    /// 28-11 (not a representable identifier).
    #[must_use]
    pub const fn can_id(self) -> Option<CanId> {
        crate::cob_id::can_id_of_cob_word(self.0)
    }

    /// The same COB-ID with bit 31 set (`valid == false`) or cleared.
    #[must_use]
    pub const fn with_valid(self, valid: bool) -> Self {
        if valid {
            PdoCobId(self.0 & !Self::NOT_VALID)
        } else {
            PdoCobId(self.0 | Self::NOT_VALID)
        }
    }

    /// True when both name the same identifier and frame format (the flags
    /// 31 and 30 aside).
    #[must_use]
    pub const fn same_identifier(self, other: PdoCobId) -> bool {
        self.0 & !(Self::NOT_VALID | Self::NO_RTR) == other.0 & !(Self::NOT_VALID | Self::NO_RTR)
    }
}

impl fmt::Display for PdoCobId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:08X}h", self.0)?;
        if !self.is_valid() {
            f.write_str(" (not valid)")?;
        }
        Ok(())
    }
}

/// Why a transmission type was refused (SDO abort 06090030h).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum TransmissionTypeError {
    /// 241..=251: reserved by CiA 301.
    #[error("transmission type {0} is reserved")]
    Reserved(u8),
    /// 252 / 253: RTR-only types, which this crate (like the Delta-Q charger)
    /// does not support.
    #[error("transmission type {0} (RTR only) is not supported")]
    RtrOnly(u8),
}

impl From<TransmissionTypeError> for AbortCode {
    fn from(_: TransmissionTypeError) -> Self {
        AbortCode::InvalidValue
    }
}

/// PDO transmission type (sub-index 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TransmissionType {
    /// 0: synchronous, acyclic (sent at the SYNC after an event).
    SynchronousAcyclic,
    /// 1..=240: synchronous, every n-th SYNC.
    SynchronousCyclic(u8),
    /// 254: event-driven, manufacturer-specific.
    EventManufacturer,
    /// 255: event-driven, device-profile-specific (CiA 418's default).
    EventProfile,
}

impl TransmissionType {
    /// From the U8; reserved and RTR-only values are errors (06090030h).
    pub const fn from_u8(raw: u8) -> Result<Self, TransmissionTypeError> {
        match raw {
            0 => Ok(TransmissionType::SynchronousAcyclic),
            1..=240 => Ok(TransmissionType::SynchronousCyclic(raw)),
            241..=251 => Err(TransmissionTypeError::Reserved(raw)),
            252 | 253 => Err(TransmissionTypeError::RtrOnly(raw)),
            254 => Ok(TransmissionType::EventManufacturer),
            255 => Ok(TransmissionType::EventProfile),
        }
    }

    /// The U8.
    #[must_use]
    pub const fn to_u8(self) -> u8 {
        match self {
            TransmissionType::SynchronousAcyclic => 0,
            TransmissionType::SynchronousCyclic(n) => n,
            TransmissionType::EventManufacturer => 254,
            TransmissionType::EventProfile => 255,
        }
    }

    /// True for 254/255: sent on events and the event timer.
    #[must_use]
    pub const fn is_event_driven(self) -> bool {
        matches!(
            self,
            TransmissionType::EventManufacturer | TransmissionType::EventProfile
        )
    }
}

/// The communication parameters of one PDO.
///
/// ```
/// use canopen_codec::pdo::{PdoCobId, PdoCommParams, TransmissionType};
/// let p = PdoCommParams::event_driven(PdoCobId::standard(0x18A), 200);
/// assert_eq!(p.encode_sub(1).unwrap().as_slice(), &[0x8A, 0x01, 0x00, 0x00]);
/// assert_eq!(p.event_timer_ms, 200);
/// assert_eq!(p.transmission_type, TransmissionType::EventProfile);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PdoCommParams {
    /// Sub 1.
    pub cob_id: PdoCobId,
    /// Sub 2.
    pub transmission_type: TransmissionType,
    /// Sub 3: minimum time between two transmissions, in 100 µs units.
    pub inhibit_time_100us: u16,
    /// Sub 4: compatibility entry (kept as written).
    pub reserved: u8,
    /// Sub 5: event timer in ms (0 = off).
    pub event_timer_ms: u16,
}

/// The bytes of one communication parameter sub-index (1, 2 or 4 bytes).
pub type SubValue = crate::bytes::InlineData<4>;

impl PdoCommParams {
    /// Highest sub-index (sub 0).
    pub const HIGHEST_SUB: u8 = 5;

    /// Event-driven (type 255), no inhibit time, with this event timer.
    #[must_use]
    pub const fn event_driven(cob_id: PdoCobId, event_timer_ms: u16) -> Self {
        PdoCommParams {
            cob_id,
            transmission_type: TransmissionType::EventProfile,
            inhibit_time_100us: 0,
            reserved: 0,
            event_timer_ms,
        }
    }

    /// The inhibit time in microseconds.
    #[must_use]
    pub const fn inhibit_time_us(&self) -> u64 {
        self.inhibit_time_100us as u64 * 100
    }

    /// The little-endian bytes of sub-index `sub` (0..=5), `None` beyond.
    #[must_use]
    pub fn encode_sub(&self, sub: u8) -> Option<SubValue> {
        let (word, len) = self.sub_word(sub)?;
        Some(SubValue::from_le_word(u64::from(word), len))
    }

    /// Sub-index `sub` (0..=5) as an unsigned value and its size in bytes.
    pub(crate) fn sub_word(&self, sub: u8) -> Option<(u32, usize)> {
        let word = match sub {
            0 => u32::from(Self::HIGHEST_SUB),
            1 => self.cob_id.to_u32(),
            2 => u32::from(self.transmission_type.to_u8()),
            3 => u32::from(self.inhibit_time_100us),
            4 => u32::from(self.reserved),
            5 => u32::from(self.event_timer_ms),
            _ => return None,
        };
        Some((word, Self::sub_len(sub)?))
    }

    /// The size in bytes of sub-index `sub`.
    #[must_use]
    pub const fn sub_len(sub: u8) -> Option<usize> {
        match sub {
            0 | 2 | 4 => Some(1),
            1 => Some(4),
            3 | 5 => Some(2),
            _ => None,
        }
    }

    /// Sets sub-index `sub` from its little-endian bytes, without the
    /// "while valid" rules of the reconfiguration procedure: wrong
    /// lengths are 06070012h/06070013h, an unknown sub-index 06090011h, sub
    /// 0 06010002h (read-only), a bad transmission type 06090030h.
    pub fn decode_sub(&mut self, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let len = Self::sub_len(sub).ok_or(AbortCode::SubIndexDoesNotExist)?;
        let word = le_word(data, len)?;
        // Each value is `len` bytes wide: the casts below keep all of it.
        match sub {
            1 => self.cob_id = PdoCobId::from_u32(word),
            2 => self.transmission_type = TransmissionType::from_u8(word as u8)?,
            3 => self.inhibit_time_100us = word as u16,
            4 => self.reserved = word as u8,
            5 => self.event_timer_ms = word as u16,
            _ => return Err(AbortCode::WriteOfReadOnlyObject),
        }
        Ok(())
    }
}

/// The value of exactly `len` (at most 4) little-endian bytes: a longer
/// `data` is 06070012h, a shorter one 06070013h.
pub(crate) fn le_word(data: &[u8], len: usize) -> Result<u32, AbortCode> {
    if data.len() > len {
        return Err(AbortCode::DataTypeLengthTooHigh);
    }
    if data.len() < len {
        return Err(AbortCode::DataTypeLengthTooLow);
    }
    Ok(data
        .iter()
        .rev()
        .fold(0u32, |word, &b| word << 8 | u32::from(b)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn direction_indexes() {
        use PdoDirection::*;
        assert_eq!(Receive.comm_index(PdoNumber::P0), 0x1400);
        assert_eq!(Receive.mapping_index(PdoNumber::P3), 0x1603);
        assert_eq!(Transmit.comm_index(PdoNumber::P2), 0x1802);
        assert_eq!(Transmit.mapping_index(PdoNumber::P1), 0x1A01);
        for index in 0..=0xFFFFu16 {
            assert_eq!(
                is_pdo_index(index),
                PdoDirection::from_index(index).is_some()
            );
            match PdoDirection::from_index(index) {
                Some((d, n, m)) => {
                    let back = if m {
                        d.mapping_index(n)
                    } else {
                        d.comm_index(n)
                    };
                    assert_eq!(back, index);
                }
                None => assert!(
                    !matches!(index, 0x1400..=0x1403 | 0x1600..=0x1603 | 0x1800..=0x1803 | 0x1A00..=0x1A03),
                    "{index:04X}"
                ),
            }
        }
    }

    #[test]
    fn cob_id_flags() {
        let c = PdoCobId::from_u32(0xC000_0281);
        assert!(!c.is_valid() && !c.rtr_allowed() && !c.is_extended());
        assert_eq!(c.can_id(), Some(CanId::Standard(0x281)));
        assert_eq!(c.with_valid(true).to_u32(), 0x4000_0281);
        let e = PdoCobId::from_u32(0x2000_0000 | 0x18FF_0001);
        assert!(e.is_extended() && e.is_valid());
        assert_eq!(e.can_id(), Some(CanId::Extended(0x18FF_0001)));
        assert_eq!(PdoCobId::from_u32(0x0000_0801).can_id(), None);
        assert!(PdoCobId::from_u32(0x8000_0181).same_identifier(PdoCobId::standard(0x181)));
        assert!(!PdoCobId::standard(0x182).same_identifier(PdoCobId::standard(0x181)));
        assert_eq!(
            format!("{}", PdoCobId::from_u32(0x8000_0181)),
            "80000181h (not valid)"
        );
    }

    #[test]
    fn transmission_types() {
        for raw in 0..=255u8 {
            match TransmissionType::from_u8(raw) {
                Ok(t) => assert_eq!(t.to_u8(), raw),
                Err(e) => {
                    assert!((241..=253).contains(&raw));
                    assert_eq!(AbortCode::from(e), AbortCode::InvalidValue);
                }
            }
        }
        assert!(TransmissionType::EventProfile.is_event_driven());
        assert!(!TransmissionType::SynchronousCyclic(1).is_event_driven());
    }

    #[test]
    fn sub_indexes() {
        let mut p = PdoCommParams::event_driven(PdoCobId::from_u32(0x8000_0181), 200);
        assert_eq!(p.encode_sub(0).unwrap().as_slice(), &[5]);
        assert_eq!(p.encode_sub(1).unwrap().as_slice(), &[0x81, 0x01, 0, 0x80]);
        assert_eq!(p.encode_sub(2).unwrap().as_slice(), &[255]);
        assert_eq!(p.encode_sub(5).unwrap().as_slice(), &[200, 0]);
        assert_eq!(p.encode_sub(6), None);
        p.decode_sub(3, &[10, 0]).unwrap();
        assert_eq!(p.inhibit_time_us(), 1000);
        p.decode_sub(1, &[0x81, 0x01, 0, 0]).unwrap();
        assert!(p.cob_id.is_valid());
        p.decode_sub(4, &[7]).unwrap();
        assert_eq!(p.reserved, 7);
        p.decode_sub(5, &[0xE8, 0x03]).unwrap();
        assert_eq!(p.event_timer_ms, 1000);
        assert_eq!(p.decode_sub(2, &[250]), Err(AbortCode::InvalidValue));
        assert_eq!(p.decode_sub(2, &[1]), Ok(()));
        assert_eq!(p.decode_sub(0, &[5]), Err(AbortCode::WriteOfReadOnlyObject));
        assert_eq!(
            p.decode_sub(1, &[1, 2]),
            Err(AbortCode::DataTypeLengthTooLow)
        );
        assert_eq!(
            p.decode_sub(5, &[1, 2, 3]),
            Err(AbortCode::DataTypeLengthTooHigh)
        );
        assert_eq!(p.decode_sub(6, &[1]), Err(AbortCode::SubIndexDoesNotExist));
    }
}
