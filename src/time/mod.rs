//! TIME (identifier 0x100), CiA 301: a TIME_OF_DAY value, 6 bytes:
//! bits 0-27 milliseconds after midnight, bits 28-31 reserved, then a u16 of
//! days since 1984-01-01. The TIME producer and consumer follow 1012h
//! COB-ID TIME ([`TimeCobId`], [`TimeProducer`], [`TimeConsumer`]).

use byteorder::{ByteOrder, LittleEndian};

use crate::error::{exact_len, DecodeError};

/// Milliseconds in a day.
pub const MS_PER_DAY: u32 = 86_400_000;

/// A TIME_OF_DAY value. The 4 reserved bits are kept so frames round-trip.
///
/// ```
/// use canopen_codec::time::TimeOfDay;
/// // 12:00:00.000 on 1984-01-03 (day 2).
/// let t = TimeOfDay::new(12 * 3_600_000, 2).unwrap();
/// let bytes = t.encode();
/// assert_eq!(bytes, [0x00, 0x2E, 0x93, 0x02, 0x02, 0x00]);
/// assert_eq!(TimeOfDay::decode(&bytes).unwrap(), t);
/// assert_eq!(t.unix_millis(), 441_979_200_000);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct TimeOfDay {
    /// Milliseconds after midnight (28 bits; a valid time is below 86 400 000).
    pub millis: u32,
    /// Days since 1984-01-01.
    pub days: u16,
    /// The 4 reserved bits (28-31 of the first word), normally 0.
    pub reserved: u8,
}

/// Unix time (ms) of 1984-01-01T00:00:00Z.
const EPOCH_1984_UNIX_MS: u64 = 441_763_200_000;

impl TimeOfDay {
    /// Builds a value; `None` if `millis` is not within a day.
    #[must_use]
    pub const fn new(millis: u32, days: u16) -> Option<Self> {
        if millis < MS_PER_DAY {
            Some(TimeOfDay {
                millis,
                days,
                reserved: 0,
            })
        } else {
            None
        }
    }

    /// Decodes the 6 data bytes.
    #[inline]
    pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
        exact_len(data, 6)?;
        let word = LittleEndian::read_u32(data.get(0..4).unwrap_or(&[0; 4]));
        let days = LittleEndian::read_u16(data.get(4..6).unwrap_or(&[0; 2]));
        Ok(TimeOfDay {
            millis: word & 0x0FFF_FFFF,
            days,
            reserved: (word >> 28) as u8,
        })
    }

    /// The 6 data bytes.
    #[must_use]
    #[inline]
    pub fn encode(&self) -> [u8; 6] {
        let word = (self.millis & 0x0FFF_FFFF) | (u32::from(self.reserved & 0x0F) << 28);
        let [a, b, c, d] = word.to_le_bytes();
        let [e, f] = self.days.to_le_bytes();
        [a, b, c, d, e, f]
    }

    /// Milliseconds since the Unix epoch (no leap seconds, as CiA 301).
    #[must_use]
    pub const fn unix_millis(&self) -> u64 {
        EPOCH_1984_UNIX_MS + self.days as u64 * MS_PER_DAY as u64 + self.millis as u64
    }

    /// From Unix milliseconds; `None` before 1984 or after day 65535.
    #[must_use]
    pub fn from_unix_millis(ms: u64) -> Option<Self> {
        let since = ms.checked_sub(EPOCH_1984_UNIX_MS)?;
        let days = u16::try_from(since / u64::from(MS_PER_DAY)).ok()?;
        let millis = (since % u64::from(MS_PER_DAY)) as u32;
        Self::new(millis, days)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_reserved_bits_and_rejects_lengths() {
        let raw = [0xFF, 0xFF, 0xFF, 0xFF, 0x34, 0x12];
        let t = TimeOfDay::decode(&raw).unwrap();
        assert_eq!(t.millis, 0x0FFF_FFFF);
        assert_eq!(t.reserved, 0xF);
        assert_eq!(t.days, 0x1234);
        assert_eq!(t.encode(), raw);
        assert_eq!(
            TimeOfDay::decode(&raw[..5]),
            Err(DecodeError::Truncated { need: 6, got: 5 })
        );
        assert!(TimeOfDay::new(MS_PER_DAY, 0).is_none());
    }

    #[test]
    fn unix_conversion() {
        // 2026-11-22T00:00:00Z = 1795305600 s; days since 1984 = 15666.
        let t = TimeOfDay::from_unix_millis(1_795_305_600_000 + 1).unwrap();
        assert_eq!(t.days, 15666);
        assert_eq!(t.millis, 1);
        assert_eq!(t.unix_millis(), 1_795_305_600_001);
        assert_eq!(TimeOfDay::from_unix_millis(0), None);
    }
}

mod consumer;
mod producer;
pub use consumer::{TimeConsumer, TimeEvent};
pub use producer::{TimeCobId, TimeProducer};
