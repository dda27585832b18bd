//! Exact binary fixed-point numbers with an exact decimal `Display`.

use core::fmt;

/// An exact binary fixed-point number: `raw / 2^frac_bits`.
///
/// ```
/// use canopen_codec::pdo::Fixed;
/// let v = Fixed::new(0x07BA, 4); // 1978 / 16
/// assert_eq!(v.to_string(), "123.625");
/// assert_eq!(format!("{v:.2}"), "123.63");
/// assert_eq!(format!("{:.2}", Fixed::new(82 * 256, 8)), "82.00");
/// assert_eq!(format!("{:#.2}", Fixed::new(82 * 256, 8)), "82"); // at most 2 places
/// assert_eq!(format!("{:.1}", Fixed::new(-3, 3)), "-0.4");
/// assert_eq!(v.to_f64(), 123.625);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fixed {
    raw: i64,
    frac_bits: u8,
}

impl Fixed {
    /// Most fractional bits (larger values are clamped to it).
    pub const MAX_FRAC_BITS: u8 = 32;

    /// `raw / 2^frac_bits`; `frac_bits` above 32 is taken as 32.
    #[must_use]
    pub const fn new(raw: i64, frac_bits: u8) -> Self {
        let frac_bits = if frac_bits > Self::MAX_FRAC_BITS {
            Self::MAX_FRAC_BITS
        } else {
            frac_bits
        };
        Fixed { raw, frac_bits }
    }

    /// The integer numerator.
    #[must_use]
    pub const fn raw(self) -> i64 {
        self.raw
    }

    /// The number of fractional bits.
    #[must_use]
    pub const fn frac_bits(self) -> u8 {
        self.frac_bits
    }

    /// The value as `f64` (exact while `|raw| < 2^53`).
    #[must_use]
    pub fn to_f64(self) -> f64 {
        self.raw as f64 / (1u64 << self.frac_bits) as f64
    }
}

impl fmt::Display for Fixed {
    /// Exact decimal digits, or rounded (halves away from zero) to the
    /// formatter's precision (at most 18 places); with `#` as well
    /// (`{:#.2}`), trailing zeros after rounding are dropped: at most that
    /// many places.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let q = u32::from(self.frac_bits.min(Self::MAX_FRAC_BITS));
        let magnitude = u128::from(self.raw.unsigned_abs());
        let negative = self.raw < 0;
        match f.precision() {
            None => {
                let int = magnitude >> q;
                let frac = magnitude & ((1u128 << q) - 1);
                if negative {
                    f.write_str("-")?;
                }
                write!(f, "{int}")?;
                if frac != 0 {
                    // frac / 2^q = frac * 5^q / 10^q: exactly q digits.
                    let mut digits = frac * 5u128.pow(q);
                    let mut width = q as usize;
                    while digits.is_multiple_of(10) && width > 1 {
                        digits /= 10;
                        width -= 1;
                    }
                    write!(f, ".{digits:0width$}")?;
                }
                Ok(())
            }
            Some(places) => {
                let places = places.min(18);
                let scale = 10u128.pow(places as u32);
                let half = if q == 0 { 0 } else { 1u128 << (q - 1) };
                let rounded = (magnitude * scale + half) >> q;
                if negative && rounded != 0 {
                    f.write_str("-")?;
                }
                write!(f, "{}", rounded / scale)?;
                let (mut frac, mut places) = (rounded % scale, places);
                if f.alternate() {
                    // `{:#.2}`: at most 2 places, trailing zeros dropped.
                    while places > 0 && frac % 10 == 0 {
                        frac /= 10;
                        places -= 1;
                    }
                }
                if places > 0 {
                    write!(f, ".{frac:0places$}")?;
                }
                Ok(())
            }
        }
    }
}
