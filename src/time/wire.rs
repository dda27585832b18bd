//! The TIME wire layer, CiA 301 section 7.2.6.3 (TIME protocol): the one
//! place where the bytes of a TIME frame are read and written. Its
//! TIME_OF_DAY value is 6 bytes: bits 0..=27
//! milliseconds after midnight, bits 28..=31 reserved, then a u16 of days
//! since 1984-01-01, all little-endian.

use crate::wire::{fixed_view, parse_through_view, Codec};

/// Milliseconds in a day.
pub const MS_PER_DAY: u32 = 86_400_000;

fixed_view! {
    /// The checked view of a TIME frame's data: exactly 6 bytes.
    ///
    /// ```
    /// use canopen_codec::time::TimeFrame;
    /// let f = TimeFrame::new_checked(&[0x00, 0x2E, 0x93, 0xF2, 0x02, 0x00]).unwrap();
    /// assert_eq!((f.millis(), f.reserved(), f.days()), (12 * 3_600_000, 0xF, 2));
    /// assert!(TimeFrame::new_checked(&[0; 5]).is_err());
    /// ```
    TimeFrame, 6
}

impl TimeFrame {
    /// Bytes 0..=3, little-endian: milliseconds and the reserved bits.
    #[must_use]
    #[inline]
    pub const fn word(&self) -> u32 {
        let [a, b, c, d, ..] = self.bytes;
        u32::from_le_bytes([a, b, c, d])
    }

    /// Bits 0..=27: milliseconds after midnight.
    #[must_use]
    #[inline]
    pub const fn millis(&self) -> u32 {
        self.word() & 0x0FFF_FFFF
    }

    /// Bits 28..=31: reserved (normally 0).
    #[must_use]
    #[inline]
    pub const fn reserved(&self) -> u8 {
        (self.word() >> 28) as u8
    }

    /// Bytes 4..=5, little-endian: days since 1984-01-01.
    #[must_use]
    #[inline]
    pub const fn days(&self) -> u16 {
        let [.., e, f] = self.bytes;
        u16::from_le_bytes([e, f])
    }
}

/// A TIME_OF_DAY value. The 4 reserved bits are kept so frames round-trip.
///
/// ```
/// use canopen_codec::time::TimeOfDay;
/// use canopen_codec::wire::Codec;
/// // 12:00:00.000 on 1984-01-03 (day 2).
/// let t = TimeOfDay::new(12 * 3_600_000, 2).unwrap();
/// let mut buf = [0; 8];
/// assert_eq!(t.emit(&mut buf), 6);
/// assert_eq!(buf[..6], [0x00, 0x2E, 0x93, 0x02, 0x02, 0x00]);
/// assert_eq!(TimeOfDay::parse(&buf[..6]).unwrap(), t);
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
    /// The data length of a TIME frame.
    pub const LEN: usize = 6;

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

    /// The value a checked frame carries.
    #[must_use]
    #[inline]
    pub const fn from_view(frame: &TimeFrame) -> Self {
        TimeOfDay {
            millis: frame.millis(),
            days: frame.days(),
            reserved: frame.reserved(),
        }
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

impl Codec for TimeOfDay {
    parse_through_view!(TimeFrame);

    #[inline]
    fn emit(&self, buf: &mut [u8; 8]) -> usize {
        let word = (self.millis & 0x0FFF_FFFF) | (u32::from(self.reserved & 0x0F) << 28);
        let [a, b, c, d, e, f, ..] = buf;
        [*a, *b, *c, *d] = word.to_le_bytes();
        [*e, *f] = self.days.to_le_bytes();
        Self::LEN
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::DecodeError;
    use crate::wire::assert_round_trip;

    #[test]
    fn keeps_reserved_bits_and_rejects_lengths() {
        let raw = [0xFF, 0xFF, 0xFF, 0xFF, 0x34, 0x12];
        let t = assert_round_trip::<TimeOfDay>(&raw).unwrap();
        assert_eq!(t.millis, 0x0FFF_FFFF);
        assert_eq!(t.reserved, 0xF);
        assert_eq!(t.days, 0x1234);
        assert_eq!(
            TimeOfDay::parse(&raw[..5]),
            Err(DecodeError::Truncated { need: 6, got: 5 })
        );
        crate::error::assert_exact_length(TimeOfDay::parse, 6);
        crate::error::assert_exact_length(TimeFrame::new_checked, 6);
        assert!(TimeOfDay::new(MS_PER_DAY, 0).is_none());
    }

    #[test]
    fn emit_writes_six_bytes() {
        let t = TimeOfDay {
            millis: 0x0123_4567,
            days: 0xBEEF,
            reserved: 0x5,
        };
        let mut buf = [0xAA; 8];
        assert_eq!(t.emit(&mut buf), 6);
        assert_eq!(buf, [0x67, 0x45, 0x23, 0x51, 0xEF, 0xBE, 0xAA, 0xAA]);
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
