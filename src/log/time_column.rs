//! The time column, `1756955653.612992`, written by hand: it is on every
//! line, and a log's seconds change once a second while its lines come by
//! the thousand, so the seconds (with their padding and the dot) are kept
//! from the previous line and only the six digits of microseconds are new.

use std::fmt::Write;
use std::prelude::rust_2021::*;

use crate::Timestamp;

/// `"000102...9899"`: the two digits of every number below 100.
const PAIRS: &str = {
    const BYTES: [u8; 200] = {
        let mut b = [0u8; 200];
        let mut i = 0;
        while i < 100 {
            b[2 * i] = b'0' + (i / 10) as u8;
            b[2 * i + 1] = b'0' + (i % 10) as u8;
            i += 1;
        }
        b
    };
    match std::str::from_utf8(&BYTES) {
        Ok(s) => s,
        Err(_) => core::panic!("digits are ASCII"),
    }
};

/// Writes `secs.micros` (6 digits of micros) with the seconds right-aligned
/// in `width` columns (more when they need more), as `Timestamp`'s
/// `Display` writes it when `width` is 0.
pub struct TimeColumn {
    width: usize,
    /// The seconds `head` holds.
    secs: Option<u64>,
    /// The seconds, padded, and the dot.
    head: String,
}

impl TimeColumn {
    /// A column `width` wide before the dot (0: no padding).
    pub fn new(width: usize) -> Self {
        TimeColumn {
            width,
            secs: None,
            head: String::new(),
        }
    }

    /// Appends `t` to `out`.
    pub fn write(&mut self, out: &mut String, t: Timestamp) {
        let us = t.as_micros();
        let (secs, micros) = (us / 1_000_000, us % 1_000_000);
        if self.secs != Some(secs) {
            self.head.clear();
            let _ = write!(self.head, "{secs:>0$}.", self.width);
            self.secs = Some(secs);
        }
        out.push_str(&self.head);
        // Three pairs of digits from one table (constant divisors: no
        // division).
        let m = micros as usize;
        for pair in [m / 10_000, m / 100 % 100, m % 100] {
            let at = 2 * pair;
            out.push_str(PAIRS.get(at..at + 2).unwrap_or("00"));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The column equals `Timestamp`'s `Display` (padded by `format!`) for
    /// times in and out of order, whatever came before.
    #[test]
    fn the_column_is_the_timestamps_display() {
        let times = [
            0,
            1,
            999_999,
            1_000_000,
            1_756_955_653_612_992,
            1_756_955_653_000_007,
            1_756_955_654_100_000,
            1_756_955_653_612_992,
            u64::MAX,
            12_345_678,
        ];
        for width in [0, 10] {
            let mut column = TimeColumn::new(width);
            for us in times {
                let t = Timestamp::from_micros(us);
                let mut out = String::from("x");
                column.write(&mut out, t);
                assert_eq!(
                    out,
                    format!("x{:>w$}", t.to_string(), w = width + 7),
                    "{us}"
                );
            }
        }
    }
}
