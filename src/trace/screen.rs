//! candump screen output (can-utils `candump` without `-L`):
//!
//! ```text
//!   can0  18A   [8]  74 13 45 4E 70 00 00 00
//!   can0  701   [1]  remote request
//! (1700000000.123456)  can0  18A   [8]  74 13 45 4E 70 00 00 00      -t a
//! (000.000211)  can0  18A   [8]  74 13 45 4E 70 00 00 00             -t d, -t z
//! (2025-09-04 03:14:13.603308)  can0  18A   [8]  74 13 ...           -t A
//!   can0  RX - -  18A   [8]  74 13 ...                               -x
//!   can0  20000004   [8]  00 04 00 00 00 00 00 00   ERRORFRAME        -e
//!   can0  123  [12]  00 11 22 ...                                    CAN FD
//! ```
//!
//! A 3-digit identifier is 11-bit, an 8-digit one 29-bit. candump prints a
//! classic length as `[n]` and a CAN FD length with two digits (`[08]`,
//! `[12]`). Text after the data bytes (`-a`'s ASCII column) is ignored.

use super::fields::{can_id, dec_u32, decimal_scaled, frame, hex_u32};
use super::{Record, RxTx, State, TraceError, TraceFrame, Unsupported};
use crate::clock::Timestamp;

/// True when the line has the `[n]` length field of screen output.
pub(super) fn looks_like_frame(line: &str) -> bool {
    line.split_whitespace().any(|t| length_field(t).is_some())
}

/// `[n]` (classic, `Some((n, false))`) or `[nn]` (CAN FD, `Some((n, true))`).
fn length_field(t: &str) -> Option<(u32, bool)> {
    let digits = t.strip_prefix('[')?.strip_suffix(']')?;
    Some((dec_u32(digits)?, digits.len() > 1))
}

pub(super) fn parse<'a>(line: &'a str, state: &mut State) -> Result<Record<'a>, TraceError> {
    let t = line.trim();
    let (timestamp, rest) = match t.strip_prefix('(') {
        Some(after) => {
            let (ts, rest) = after.split_once(')').ok_or(TraceError::BadTimestamp)?;
            (Some(time(ts.trim(), state)?), rest)
        }
        None => (None, t),
    };
    if rest.contains("ERRORFRAME") {
        return Ok(Record::Unsupported(Unsupported::ErrorFrame));
    }
    let mut tokens = rest.split_whitespace();
    let channel = tokens.next().ok_or(TraceError::MissingField)?;
    let mut direction = None;
    let mut id_text = tokens.next().ok_or(TraceError::MissingField)?;
    if let Some(d) = match id_text {
        "RX" => Some(RxTx::Rx),
        "TX" => Some(RxTx::Tx),
        _ => None,
    } {
        direction = Some(d);
        // `-x` flag columns ("-", "B", "E", "I" ...) up to the identifier.
        id_text = tokens
            .by_ref()
            .find(|t| t.len() >= 3)
            .ok_or(TraceError::MissingField)?;
    }
    let len_text = tokens.next().ok_or(TraceError::MissingField)?;
    let (len, fd) = length_field(len_text).ok_or(TraceError::BadDlc)?;
    if fd {
        return Ok(Record::Unsupported(Unsupported::CanFd));
    }
    let raw = hex_u32(id_text).ok_or(TraceError::BadId)?;
    let id = can_id(raw, id_text.len() > 3)?;
    let dlc = u8::try_from(len).map_err(|_| TraceError::BadDlc)?;
    let mut data = tokens.peekable();
    let remote = data.peek() == Some(&"remote");
    let frame = frame(id, dlc, remote, data.take(usize::from(dlc)))?;
    Ok(Record::Frame(TraceFrame {
        timestamp,
        channel: Some(channel),
        direction,
        frame,
    }))
}

/// `seconds.micros`, or `YYYY-MM-DD HH:MM:SS.micros` (`-t A`, UTC).
fn time(ts: &str, state: &mut State) -> Result<Timestamp, TraceError> {
    if let Some((date, clock)) = ts.split_once(' ') {
        return civil_micros(date, clock)
            .map(Timestamp::from_micros)
            .ok_or(TraceError::BadTimestamp);
    }
    let us = decimal_scaled(ts, 6).ok_or(TraceError::BadTimestamp)?;
    if state.screen_delta {
        state.screen_clock_us = state.screen_clock_us.saturating_add(us);
        return Ok(Timestamp::from_micros(state.screen_clock_us));
    }
    Ok(Timestamp::from_micros(us))
}

/// UNIX microseconds of a UTC civil date and time (proleptic Gregorian).
fn civil_micros(date: &str, clock: &str) -> Option<u64> {
    let mut d = date.split('-');
    let (y, m, day) = (d.next()?, d.next()?, d.next()?);
    if d.next().is_some() {
        return None;
    }
    let (y, m, day) = (dec_u32(y)?, dec_u32(m)?, dec_u32(day)?);
    if !(1970..=9999).contains(&y) || !(1..=12).contains(&m) || !(1..=31).contains(&day) {
        return None;
    }
    let mut c = clock.split(':');
    let (h, min, sec) = (c.next()?, c.next()?, c.next()?);
    if c.next().is_some() {
        return None;
    }
    let (h, min) = (dec_u32(h)?, dec_u32(min)?);
    let sec_us = decimal_scaled(sec, 6)?;
    if h > 23 || min > 59 || sec_us >= 61_000_000 {
        return None;
    }
    // Days from 1970-01-01 (H. Hinnant's days_from_civil), all non-negative
    // for years from 1970.
    let y = i64::from(if m <= 2 { y - 1 } else { y });
    let era = y / 400;
    let yoe = y - era * 400;
    let mp = i64::from((m + 9) % 12);
    let doy = (153 * mp + 2) / 5 + i64::from(day) - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    let days = era * 146_097 + doe - 719_468;
    let secs = u64::try_from(days).ok()? * 86_400 + u64::from(h) * 3600 + u64::from(min) * 60;
    Some(secs * 1_000_000 + sec_us)
}
