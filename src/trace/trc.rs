//! PCAN-View `.trc` files (PEAK-System's trace format), versions 1.0 to
//! 1.3 and 2.0 to 2.1. Header and comment lines start with `;`; the
//! `;$FILEVERSION=x.y` line tells the version (1.0 when absent, as PEAK's
//! PCAN-View and python-can read such a file; a header-less line with an
//! `Rx`/`Tx` column is read as the 1.1 line it is), the
//! `;$STARTTIME=` line the start as days since 1899-12-30 (fractional), and
//! in 2.x `;$COLUMNS=` the column order. Message lines:
//!
//! ```text
//!      1)      1841  0300  8  00 00 00 00 00 00 00 00                 1.0
//!      1)      1841.6  Rx         0300  8  00 00 00 00 00 00 00 00    1.1
//!      1)      1841.600 1  Rx         0300  8  00 ...                 1.2
//!      1)      1841.600 1  Rx         0300 -  8  00 ...               1.3
//!      1      1059.900 DT     0300 Rx 7  00 00 00 00 04 00 00         2.0
//!      1      1059.900 DT 1      0300 Rx -  7  00 00 00 00 04 00 00   2.1
//! ```
//!
//! Columns of 2.x: `N` number, `O` offset in ms, `T` type (`DT` data, `RR`
//! remote request, `FD`/`FB`/`FE`/`BI` CAN FD, `ER` error frame, `ST`,
//! `EC`, `EV` events), `B` bus, `I` identifier (hex; 8 digits: 29-bit),
//! `d` Rx/Tx, `R` reserved, `L` length, `D` data. In 1.x a remote frame has
//! `RTR` in place of its data; type `Error` / `Warng` lines are bus events.

use super::fields::{can_id, dec_u32, decimal_scaled, frame, hex_u32};
use super::{Record, RxTx, State, TraceError, TraceFrame, Unsupported};
use crate::clock::Timestamp;

/// Days from 1899-12-30 (the `$STARTTIME` epoch) to 1970-01-01.
const UNIX_EPOCH_DAY: u64 = 25_569;
const DAY_US: u64 = 86_400_000_000;

/// True when the line looks like a 1.x message line (`N)` first).
pub(super) fn looks_like_frame(line: &str) -> bool {
    line.split_whitespace()
        .next()
        .and_then(|n| n.strip_suffix(')'))
        .is_some_and(|n| dec_u32(n).is_some())
}

pub(super) fn parse<'a>(line: &'a str, state: &mut State) -> Result<Record<'a>, TraceError> {
    let t = line.trim();
    if let Some(header) = t.strip_prefix(';') {
        header_line(header.trim(), state);
        return Ok(Record::Meta);
    }
    let offset_to_time = |state: &State, o: &str| -> Result<Timestamp, TraceError> {
        let us = decimal_scaled(o, 3).ok_or(TraceError::BadTimestamp)?;
        Ok(Timestamp::from_micros(
            state.trc_start_us.map_or(us, |s| s.saturating_add(us)),
        ))
    };
    if state.trc_version.0 >= 2 {
        return parse_v2(t, state, offset_to_time);
    }
    let mut tokens = t.split_whitespace();
    let number = tokens.next().ok_or(TraceError::MissingField)?;
    if number.strip_suffix(')').and_then(dec_u32).is_none() {
        return Err(TraceError::MissingField);
    }
    let timestamp = offset_to_time(state, tokens.next().ok_or(TraceError::MissingField)?)?;
    let mut minor = state.trc_version.1;
    // A 1.1 line (a direction or a bus-event type after the time) in a
    // file that does not say its version.
    if minor == 0
        && matches!(
            t.split_whitespace().nth(2),
            Some("Rx" | "Tx" | "Warng" | "Error")
        )
    {
        minor = 1;
    }
    let mut channel = None;
    if minor >= 2 {
        channel = tokens.next();
    }
    let mut direction = None;
    if minor >= 1 {
        direction = match tokens.next().ok_or(TraceError::MissingField)? {
            "Rx" => Some(RxTx::Rx),
            "Tx" => Some(RxTx::Tx),
            "Error" => return Ok(Record::Unsupported(Unsupported::ErrorFrame)),
            _ => return Ok(Record::Unsupported(Unsupported::Event)),
        };
    }
    let id_text = tokens.next().ok_or(TraceError::MissingField)?;
    if minor >= 3 {
        let _reserved = tokens.next();
    }
    let dlc = tokens
        .next()
        .and_then(dec_u32)
        .and_then(|d| u8::try_from(d).ok())
        .ok_or(TraceError::BadDlc)?;
    let raw = hex_u32(id_text).ok_or(TraceError::BadId)?;
    let id = can_id(raw, id_text.len() > 4)?;
    let mut data = tokens.peekable();
    let remote = data.peek() == Some(&"RTR");
    let frame = frame(id, dlc, remote, data.take(8))?;
    Ok(Record::Frame(TraceFrame {
        timestamp: Some(timestamp),
        channel,
        direction,
        frame,
    }))
}

fn parse_v2<'a>(
    t: &'a str,
    state: &State,
    offset_to_time: impl Fn(&State, &str) -> Result<Timestamp, TraceError>,
) -> Result<Record<'a>, TraceError> {
    let default: &[u8] = if state.trc_version.1 >= 1 {
        b"NOTBIdRLD"
    } else {
        b"NOTIdLD"
    };
    let set = state
        .trc_columns
        .iter()
        .position(|c| *c == 0)
        .unwrap_or(state.trc_columns.len());
    let columns = match state.trc_columns.get(..set) {
        Some(c) if !c.is_empty() => c,
        _ => default,
    };
    let mut tokens = t.split_whitespace();
    let (mut timestamp, mut channel, mut direction) = (None, None, None);
    let (mut kind, mut id_text, mut len) = ("DT", None, None);
    for column in columns {
        if *column == b'D' {
            break;
        }
        let value = tokens.next().ok_or(TraceError::MissingField)?;
        match column {
            b'O' => timestamp = Some(offset_to_time(state, value)?),
            b'T' => kind = value,
            b'B' => channel = Some(value),
            b'I' => id_text = Some(value),
            b'd' => {
                direction = match value {
                    "Rx" => Some(RxTx::Rx),
                    "Tx" => Some(RxTx::Tx),
                    _ => None,
                }
            }
            b'L' | b'l' => len = Some(value),
            _ => {}
        }
        // Event lines have fewer columns: decided once the type is known.
        if *column == b'T' && !matches!(kind, "DT" | "RR") {
            return Ok(Record::Unsupported(match kind {
                "FD" | "FB" | "FE" | "BI" => Unsupported::CanFd,
                "ER" => Unsupported::ErrorFrame,
                _ => Unsupported::Event,
            }));
        }
    }
    let id_text = id_text.ok_or(TraceError::MissingField)?;
    let raw = hex_u32(id_text).ok_or(TraceError::BadId)?;
    let id = can_id(raw, id_text.len() > 4)?;
    let dlc = len
        .and_then(dec_u32)
        .and_then(|d| u8::try_from(d).ok())
        .ok_or(TraceError::BadDlc)?;
    let remote = kind == "RR";
    let frame = frame(id, dlc, remote, tokens.take(8))?;
    Ok(Record::Frame(TraceFrame {
        timestamp,
        channel,
        direction,
        frame,
    }))
}

/// `$FILEVERSION=`, `$STARTTIME=`, `$COLUMNS=`; other comments are ignored.
fn header_line(h: &str, state: &mut State) {
    let Some((key, value)) = h.split_once('=') else {
        return;
    };
    let value = value.trim();
    match key.trim() {
        "$FILEVERSION" => {
            if let Some((major, minor)) = value.split_once('.') {
                if let (Some(a), Some(b)) = (dec_u32(major), dec_u32(minor)) {
                    state.trc_version = (
                        u8::try_from(a).unwrap_or(u8::MAX),
                        u8::try_from(b).unwrap_or(u8::MAX),
                    );
                }
            }
        }
        "$STARTTIME" => {
            state.trc_start_us = start_time(value);
        }
        "$COLUMNS" => {
            let mut columns = [0u8; 12];
            for (slot, c) in
                columns
                    .iter_mut()
                    .zip(value.split(',').filter_map(|c| match c.trim().as_bytes() {
                        [b] => Some(*b),
                        _ => None,
                    }))
            {
                *slot = c;
            }
            state.trc_columns = columns;
        }
        _ => {}
    }
}

/// Days since 1899-12-30 (fractional) as UNIX microseconds, to the nearest
/// microsecond; `None` before 1970.
fn start_time(value: &str) -> Option<u64> {
    let (int, frac) = value.split_once('.').unwrap_or((value, ""));
    let days = u64::from(dec_u32(int)?);
    let days = days.checked_sub(UNIX_EPOCH_DAY)?;
    let mut us = days.checked_mul(DAY_US)?;
    // The fraction of a day, to the microsecond (at most 12 digits used).
    let digits = frac.get(..frac.len().min(12)).unwrap_or("");
    if !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let num = digits
        .bytes()
        .fold(0u128, |a, b| a * 10 + u128::from(b - b'0'));
    let den = 10u128.pow(u32::try_from(digits.len()).unwrap_or(0));
    // To the nearest microsecond: a writer's start time in whole
    // microseconds comes back as a float of days a fraction of a
    // microsecond off either way (python-can's 45904.13487411408 is
    // ...123456.512 us for ...123457), which truncation would lose.
    let fraction_us = (num * u128::from(DAY_US) + den / 2) / den;
    us = us.checked_add(u64::try_from(fraction_us).ok()?)?;
    Some(us)
}
