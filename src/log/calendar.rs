//! CiA 301 dates and times as UTC calendar dates and clock times: the TIME
//! object's TIME_OF_DAY (CiA 301, section 7.1.6.5: milliseconds after
//! midnight and days since 1984-01-01) and the objects that count the same
//! way (1020h, 1F52h-1F54h). Proleptic Gregorian calendar, no leap seconds
//! (CiA 301 counts whole days).

use std::prelude::rust_2021::*;

/// Days from 1970-01-01 to 1984-01-01, the CiA 301 epoch.
const EPOCH_1984: i64 = 5113;

/// The civil date of `days` after 1970-01-01 (year, month 1..=12, day
/// 1..=31), by H. Hinnant's days-from-civil inverse.
fn civil(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// `2025-09-05` for `days` since 1984-01-01.
pub fn date(days: u64) -> String {
    // A U32 object holds at most 2^32 - 1 days: far inside i64.
    let days = i64::try_from(days).unwrap_or(i64::MAX / 2);
    let (y, m, d) = civil(EPOCH_1984.saturating_add(days));
    format!("{y:04}-{m:02}-{d:02}")
}

/// `14:07:33.612` for `ms` after midnight; a value of a day or more (not a
/// time of day) keeps counting hours past 24 so nothing is hidden.
pub fn time_of_day(ms: u64) -> String {
    let (h, rest) = (ms / 3_600_000, ms % 3_600_000);
    let (m, rest) = (rest / 60_000, rest % 60_000);
    format!("{h:02}:{m:02}:{:02}.{:03}", rest / 1000, rest % 1000)
}

/// `2025-09-05T14:07:33.612Z`: the instant a TIME_OF_DAY names.
pub fn utc(days: u16, ms: u32) -> String {
    format!("{}T{}Z", date(u64::from(days)), time_of_day(u64::from(ms)))
}

/// The UTC instant a TIME frame names (`2025-08-31T14:07:33.612Z`), or
/// `None` when its milliseconds are not within a day.
pub fn time_frame(t: &crate::time::TimeOfDay) -> Option<String> {
    (t.millis < 86_400_000).then(|| utc(t.days, t.millis))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_from_the_1984_epoch() {
        assert_eq!(date(0), "1984-01-01");
        assert_eq!(date(59), "1984-02-29"); // 1984 is a leap year
        assert_eq!(date(60), "1984-03-01");
        assert_eq!(date(366), "1985-01-01");
        // 2000-01-01 is 16 years on, 4 of them (1984, 88, 92, 96) leap.
        assert_eq!(date(16 * 365 + 4), "2000-01-01");
        assert_eq!(date(u64::from(u16::MAX)), "2163-06-06");
    }

    #[test]
    fn times_of_day() {
        assert_eq!(time_of_day(0), "00:00:00.000");
        assert_eq!(time_of_day(86_399_999), "23:59:59.999");
        assert_eq!(time_of_day(50_853_612), "14:07:33.612");
        assert_eq!(utc(15_218, 50_853_612), "2025-08-31T14:07:33.612Z");
    }
}
