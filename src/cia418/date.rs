//! 6054h date of last equalization (CiA 418 section 7.3.13): sub 1 minutes
//! since midnight, sub 2 days since 1984-01-01, both Unsigned16, and its
//! conversion to and from a proleptic Gregorian calendar date.
//!
//! The calendar arithmetic is Howard Hinnant's `days_from_civil` /
//! `civil_from_days` (public domain), in integers, no time zone: the object
//! carries no zone, so neither does [`CalendarDateTime`].

use crate::bytes::InlineData;

use super::{read_u16, read_u8, ObjectError, DATE_OF_LAST_EQUALIZATION};

/// Why a date did not convert.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum DateError {
    /// Year outside what 6054h can carry.
    #[error("year {got} outside {min}..={max}")]
    YearOutOfRange {
        /// 1984.
        min: u16,
        /// The last year 6054h reaches.
        max: u16,
        /// Year given.
        got: u16,
    },
    /// The date lies after the last day 6054h can carry (day 65535).
    #[error("date after the last day 6054h can carry")]
    AfterLastDay,
    /// Month outside 1..=12.
    #[error("month {got} outside 1..=12")]
    MonthOutOfRange {
        /// Month given.
        got: u8,
    },
    /// Day outside 1..=days in the month.
    #[error("day {got} outside 1..={max}")]
    DayOutOfRange {
        /// Days in the month.
        max: u8,
        /// Day given.
        got: u8,
    },
    /// Hour outside 0..=23.
    #[error("hour {got} outside 0..=23")]
    HourOutOfRange {
        /// Hour given.
        got: u8,
    },
    /// Minute outside 0..=59.
    #[error("minute {got} outside 0..=59")]
    MinuteOutOfRange {
        /// Minute given.
        got: u8,
    },
    /// Sub 1 (minutes since midnight) outside 0..=1439.
    #[error("minutes since midnight {got} outside 0..=1439")]
    MinutesSinceMidnightOutOfRange {
        /// Value of sub 1.
        got: u16,
    },
}

/// Days from 1970-01-01 to `y-m-d` (Hinnant's `days_from_civil`). Callers
/// pass a validated date with a positive year.
const fn days_from_civil(y: i32, m: u32, d: u32) -> i32 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = if y >= 0 { y } else { y - 399 } / 400;
    let yoe = (y - era * 400) as u32; // 0..=399
    let mp = if m > 2 { m - 3 } else { m + 9 }; // March = 0
    let doy = (153 * mp + 2) / 5 + d - 1; // 0..=365
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy; // 0..=146096
    era * 146_097 + doe as i32 - 719_468
}

/// `(year, month, day)` of a day count from 1970-01-01 (Hinnant's
/// `civil_from_days`).
const fn civil_from_days(z: i32) -> (i32, u32, u32) {
    let z = z + 719_468;
    let era = if z >= 0 { z } else { z - 146_096 } / 146_097;
    let doe = (z - era * 146_097) as u32; // 0..=146096
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365; // 0..=399
    let y = yoe as i32 + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100); // 0..=365
    let mp = (5 * doy + 2) / 153; // 0..=11
    let d = doy - (153 * mp + 2) / 5 + 1; // 1..=31
    let m = if mp < 10 { mp + 3 } else { mp - 9 }; // 1..=12
    (if m <= 2 { y + 1 } else { y }, m, d)
}

const fn is_leap(year: u16) -> bool {
    (year.is_multiple_of(4) && !year.is_multiple_of(100)) || year.is_multiple_of(400)
}

const fn days_in_month(year: u16, month: u8) -> u8 {
    match month {
        2 if is_leap(year) => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// 1984-01-01 as days from 1970-01-01.
const EPOCH: i32 = days_from_civil(1984, 1, 1);

/// A minute-resolution calendar date and time, proleptic Gregorian, no time
/// zone, always inside what 6054h can carry (1984-01-01 00:00 to the end of
/// day 65535, which is [`CalendarDateTime::LAST_YEAR`]-06-06).
///
/// ```
/// use canopen_codec::cia418::{CalendarDateTime, EqualizationDate};
/// let when = CalendarDateTime::new(2024, 2, 29, 13, 45).unwrap();
/// let eq = EqualizationDate::from(when);
/// assert_eq!(eq.minutes, 13 * 60 + 45);
/// assert_eq!(eq.days, 14_669);
/// assert_eq!(eq.to_calendar(), Ok(when));
/// assert!(CalendarDateTime::new(2023, 2, 29, 0, 0).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CalendarDateTime {
    year: u16,
    month: u8,
    day: u8,
    hour: u8,
    minute: u8,
}

impl CalendarDateTime {
    /// 1984, the first year.
    pub const FIRST_YEAR: u16 = 1984;
    /// The last year 6054h reaches (day 65535 is in it).
    pub const LAST_YEAR: u16 = civil_from_days(EPOCH + u16::MAX as i32).0 as u16;

    /// Validates and builds a date and time.
    pub const fn new(
        year: u16,
        month: u8,
        day: u8,
        hour: u8,
        minute: u8,
    ) -> Result<Self, DateError> {
        if year < Self::FIRST_YEAR || year > Self::LAST_YEAR {
            return Err(DateError::YearOutOfRange {
                min: Self::FIRST_YEAR,
                max: Self::LAST_YEAR,
                got: year,
            });
        }
        if month < 1 || month > 12 {
            return Err(DateError::MonthOutOfRange { got: month });
        }
        let max = days_in_month(year, month);
        if day < 1 || day > max {
            return Err(DateError::DayOutOfRange { max, got: day });
        }
        if hour > 23 {
            return Err(DateError::HourOutOfRange { got: hour });
        }
        if minute > 59 {
            return Err(DateError::MinuteOutOfRange { got: minute });
        }
        let days = days_from_civil(year as i32, month as u32, day as u32) - EPOCH;
        if days > u16::MAX as i32 {
            return Err(DateError::AfterLastDay);
        }
        Ok(CalendarDateTime {
            year,
            month,
            day,
            hour,
            minute,
        })
    }

    /// Year.
    #[must_use]
    pub const fn year(&self) -> u16 {
        self.year
    }

    /// Month, 1..=12.
    #[must_use]
    pub const fn month(&self) -> u8 {
        self.month
    }

    /// Day of the month, 1..=31.
    #[must_use]
    pub const fn day(&self) -> u8 {
        self.day
    }

    /// Hour, 0..=23.
    #[must_use]
    pub const fn hour(&self) -> u8 {
        self.hour
    }

    /// Minute, 0..=59.
    #[must_use]
    pub const fn minute(&self) -> u8 {
        self.minute
    }
}

/// 6054h date of last equalization (CiA 418 section 7.3.13): the raw
/// sub-index values. Any pair of `u16` is kept; [`EqualizationDate::to_calendar`]
/// rejects a minute count of a day of 1440 or more.
///
/// ```
/// use canopen_codec::cia418::EqualizationDate;
/// let mut eq = EqualizationDate::default();
/// eq.decode_sub(1, &[0x3C, 0x00]).unwrap(); // 60 minutes: 01:00
/// eq.decode_sub(2, &[0x01, 0x00]).unwrap(); // day 1: 1984-01-02
/// let c = eq.to_calendar().unwrap();
/// assert_eq!((c.year(), c.month(), c.day(), c.hour(), c.minute()), (1984, 1, 2, 1, 0));
/// assert_eq!(eq.encode_sub(2).unwrap().as_slice(), &[0x01, 0x00]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct EqualizationDate {
    /// Sub 1: minutes since midnight (0..=1439 when valid).
    pub minutes: u16,
    /// Sub 2: days since 1984-01-01.
    pub days: u16,
}

impl EqualizationDate {
    /// Value of sub 0, the number of elements.
    pub const NUMBER_OF_ELEMENTS: u8 = 2;
    /// Sub-index of the minutes since midnight.
    pub const SUB_MINUTES: u8 = 1;
    /// Sub-index of the days since 1984-01-01.
    pub const SUB_DAYS: u8 = 2;

    /// The calendar date and time; fails only for `minutes >= 1440`.
    pub const fn to_calendar(self) -> Result<CalendarDateTime, DateError> {
        if self.minutes >= 1440 {
            return Err(DateError::MinutesSinceMidnightOutOfRange { got: self.minutes });
        }
        let (y, m, d) = civil_from_days(EPOCH + self.days as i32);
        Ok(CalendarDateTime {
            year: y as u16,
            month: m as u8,
            day: d as u8,
            hour: (self.minutes / 60) as u8,
            minute: (self.minutes % 60) as u8,
        })
    }

    /// Converts a (valid by construction) calendar date and time.
    #[must_use]
    pub const fn from_date_time(c: CalendarDateTime) -> Self {
        let days = days_from_civil(c.year as i32, c.month as u32, c.day as u32) - EPOCH;
        EqualizationDate {
            minutes: c.hour as u16 * 60 + c.minute as u16,
            days: days as u16,
        }
    }

    /// The little-endian bytes of sub-index `sub` (0: 1 byte, the element
    /// count 2; 1 and 2: 2 bytes); `None` for any other sub-index.
    #[must_use]
    pub fn encode_sub(&self, sub: u8) -> Option<InlineData<2>> {
        match sub {
            0 => InlineData::new(&[Self::NUMBER_OF_ELEMENTS]),
            Self::SUB_MINUTES => InlineData::new(&self.minutes.to_le_bytes()),
            Self::SUB_DAYS => InlineData::new(&self.days.to_le_bytes()),
            _ => None,
        }
    }

    /// Decodes the bytes of sub-index `sub` and stores the value. Sub 0 is
    /// read-only: its byte is checked for length and otherwise ignored.
    pub fn decode_sub(&mut self, sub: u8, data: &[u8]) -> Result<(), ObjectError> {
        match sub {
            0 => {
                read_u8(data)?;
            }
            Self::SUB_MINUTES => self.minutes = read_u16(data)?,
            Self::SUB_DAYS => self.days = read_u16(data)?,
            _ => {
                return Err(ObjectError::NoSuchSubIndex {
                    index: DATE_OF_LAST_EQUALIZATION,
                    sub,
                })
            }
        }
        Ok(())
    }
}

impl From<CalendarDateTime> for EqualizationDate {
    fn from(c: CalendarDateTime) -> Self {
        Self::from_date_time(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::DecodeError;

    fn cal(y: u16, mo: u8, d: u8, h: u8, mi: u8) -> CalendarDateTime {
        CalendarDateTime::new(y, mo, d, h, mi).unwrap()
    }

    #[test]
    fn epoch_and_known_days() {
        assert_eq!(EPOCH, 5113);
        let eq = EqualizationDate::from(cal(1984, 1, 1, 0, 0));
        assert_eq!((eq.minutes, eq.days), (0, 0));
        // 1984 is a leap year: 366 days to 1985-01-01.
        assert_eq!(EqualizationDate::from(cal(1985, 1, 1, 0, 0)).days, 366);
        assert_eq!(EqualizationDate::from(cal(2000, 3, 1, 0, 0)).days, 5904);
        assert_eq!(
            EqualizationDate::from(cal(2024, 2, 29, 23, 59)).minutes,
            1439
        );
        assert_eq!(CalendarDateTime::LAST_YEAR, 2163);
        let last = EqualizationDate {
            minutes: 1439,
            days: u16::MAX,
        }
        .to_calendar()
        .unwrap();
        assert_eq!(last, cal(2163, 6, 6, 23, 59));
        assert_eq!(
            CalendarDateTime::new(2163, 6, 7, 0, 0),
            Err(DateError::AfterLastDay)
        );
    }

    #[test]
    fn every_day_round_trips() {
        let mut prev: Option<CalendarDateTime> = None;
        for days in 0..=u16::MAX {
            let eq = EqualizationDate { minutes: 0, days };
            let c = eq.to_calendar().unwrap();
            assert_eq!(
                CalendarDateTime::new(c.year(), c.month(), c.day(), 0, 0),
                Ok(c)
            );
            assert_eq!(EqualizationDate::from(c), eq);
            if let Some(p) = prev {
                assert!(p < c);
            }
            prev = Some(c);
        }
    }

    /// `(year, month, day, hour, minute)` and what `new` says of it.
    type DateCase = ((u16, u8, u8, u8, u8), Result<(), DateError>);

    const CASES: &[DateCase] = &[
        (
            (1983, 12, 31, 0, 0),
            Err(DateError::YearOutOfRange {
                min: 1984,
                max: 2163,
                got: 1983,
            }),
        ),
        (
            (2000, 13, 1, 0, 0),
            Err(DateError::MonthOutOfRange { got: 13 }),
        ),
        (
            (2000, 0, 1, 0, 0),
            Err(DateError::MonthOutOfRange { got: 0 }),
        ),
        (
            (2100, 2, 29, 0, 0),
            Err(DateError::DayOutOfRange { max: 28, got: 29 }),
        ),
        ((2000, 2, 29, 0, 0), Ok(())),
        (
            (2001, 4, 31, 0, 0),
            Err(DateError::DayOutOfRange { max: 30, got: 31 }),
        ),
        (
            (2001, 4, 0, 0, 0),
            Err(DateError::DayOutOfRange { max: 30, got: 0 }),
        ),
        (
            (2001, 4, 1, 24, 0),
            Err(DateError::HourOutOfRange { got: 24 }),
        ),
        (
            (2001, 4, 1, 0, 60),
            Err(DateError::MinuteOutOfRange { got: 60 }),
        ),
    ];

    #[test]
    fn validation() {
        for &((year, month, day, hour, minute), want) in CASES {
            let got = CalendarDateTime::new(year, month, day, hour, minute);
            assert_eq!(
                got.map(|_| ()),
                want,
                "{year}-{month}-{day} {hour}:{minute}"
            );
        }
        assert_eq!(
            EqualizationDate {
                minutes: 1440,
                days: 0
            }
            .to_calendar(),
            Err(DateError::MinutesSinceMidnightOutOfRange { got: 1440 })
        );
    }

    #[test]
    fn sub_index_bytes() {
        let mut eq = EqualizationDate::default();
        eq.decode_sub(1, &[0x9F, 0x05]).unwrap();
        eq.decode_sub(2, &[0x4D, 0x39]).unwrap();
        assert_eq!(eq.minutes, 1439);
        assert_eq!(eq.days, 0x394D);
        assert_eq!(eq.encode_sub(0).unwrap().as_slice(), &[2]);
        assert_eq!(eq.encode_sub(1).unwrap().as_slice(), &[0x9F, 0x05]);
        assert_eq!(eq.encode_sub(2).unwrap().as_slice(), &[0x4D, 0x39]);
        assert!(eq.encode_sub(3).is_none());
        assert_eq!(eq.decode_sub(0, &[2]), Ok(()));
        assert_eq!(
            eq.decode_sub(3, &[0, 0]),
            Err(ObjectError::NoSuchSubIndex {
                index: 0x6054,
                sub: 3
            })
        );
        assert_eq!(
            eq.decode_sub(1, &[0]),
            Err(ObjectError::Decode(DecodeError::Truncated {
                need: 2,
                got: 1
            }))
        );
    }
}
