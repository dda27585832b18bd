//! Vector ASC logs (CANalyzer / CANoe and python-can's `ASCWriter`):
//!
//! ```text
//! date Tue Dec 01 09:11:16.935 2026
//! base hex  timestamps absolute
//! internal events logged
//! Begin Triggerblock Thu Sep 04 03:14:13.603 2025
//!  0.000000 Start of measurement
//!    1.234567 1  18A             Rx   d 8 74 13 45 4E 70 00 00 00
//!    1.244251 1  70A             Rx   r 1
//!    1.331259 1  18DAF110x       Rx   d 2 01 02
//!    1.400000 1  ErrorFrame
//!    1.500000 CANFD   1 Rx 18A  ...
//! End TriggerBlock
//! ```
//!
//! The time is seconds since the start of the measurement, or with
//! `timestamps relative` in the `base` line since the line before; the
//! channel is a number; an identifier ending in `x` is 29-bit; `base dec`
//! means identifiers in decimal. `d` is a data frame (length, then the
//! bytes), `r` a remote frame (length optional). A classic frame's length
//! 9 to 15 means 8 data bytes (CiA / ISO 11898-1: a DLC above 8 carries
//! 8). Text after the data (the `Length = .. BitCount = .. ID = ..`
//! trailer CANalyzer and CANoe write) is ignored. `Start of measurement`,
//! `Log trigger event`, `Statistic:`, `Status:`, `ErrorFrame`, `CANFD` and
//! system-variable (`SV:`) lines are events, not frames; any other line
//! with a time that is not a frame is an error. `ErrorFrame` and `CANFD`
//! lines give the bus load their time and an FD frame's identifier, flags
//! and data ([`Record::OnBus`]).

use super::fields::{can_id, dec_u32, decimal_scaled, frame, hex_u32};
use super::{FdFrame, OnBus, Record, RxTx, State, TraceError, TraceFrame, Unsupported};
use crate::clock::Timestamp;

/// The frame of a `CANFD` line after its time and `CANFD`: channel,
/// direction, identifier (`x` after a 29-bit one), an optional symbolic
/// name, BRS and ESI (0 or 1), the DLC (hex), the data length (decimal)
/// and the data bytes, as CANoe and python-can's `ASCWriter` write it
/// (`1 Rx 123  1 0 9 12 00 01 ... 0B`); the trailer after the data
/// (duration, length, flags, CRC, bit timings) is not read.
fn fd_frame<'a>(mut tokens: impl Iterator<Item = &'a str>, state: &State) -> Option<FdFrame> {
    let (_channel, _direction, id_text) = (tokens.next()?, tokens.next()?, tokens.next()?);
    let id = frame_id(id_text, state).ok()?;
    let flag = |t: &str| match t {
        "0" => Some(false),
        "1" => Some(true),
        _ => None,
    };
    let mut tokens = tokens.peekable();
    // A symbolic name before the flags.
    if tokens.peek().copied().and_then(flag).is_none() {
        tokens.next();
    }
    let brs = flag(tokens.next()?)?;
    let esi = flag(tokens.next()?)?;
    let _dlc = hex_u32(tokens.next()?)?;
    let len = usize::try_from(dec_u32(tokens.next()?)?).ok()?;
    let mut data = [0u8; 64];
    for byte in data.get_mut(..len)? {
        *byte = u8::try_from(hex_u32(tokens.next()?)?).ok()?;
    }
    FdFrame::new(id, data.get(..len)?, brs, esi)
}

/// An identifier field: hex (decimal after `base dec`), `x` after a
/// 29-bit one.
fn frame_id(id_text: &str, state: &State) -> Result<crate::frame::CanId, TraceError> {
    let (digits, extended) = match id_text.strip_suffix(['x', 'X']) {
        Some(d) => (d, true),
        None => (id_text, false),
    };
    let raw = if state.asc_decimal {
        dec_u32(digits)
    } else {
        hex_u32(digits)
    }
    .ok_or(TraceError::BadId)?;
    can_id(raw, extended)
}

/// True when the line is an ASC frame line.
pub(super) fn looks_like_frame(line: &str) -> bool {
    let mut t = line.split_whitespace();
    let (Some(time), Some(ch), Some(_id), Some(dir), Some(kind)) =
        (t.next(), t.next(), t.next(), t.next(), t.next())
    else {
        return false;
    };
    time.contains('.')
        && decimal_scaled(time, 6).is_some()
        && dec_u32(ch).is_some()
        && matches!(dir, "Rx" | "Tx")
        && matches!(kind, "d" | "r")
}

pub(super) fn parse<'a>(line: &'a str, state: &mut State) -> Result<Record<'a>, TraceError> {
    let t = line.trim();
    let mut tokens = t.split_whitespace();
    let Some(first) = tokens.next() else {
        return Ok(Record::Meta);
    };
    let Some(us) = decimal_scaled(first, 6).filter(|_| first.contains('.')) else {
        // Header lines: `date`, `base`, `internal events logged`, `//`,
        // `Begin Triggerblock`, `End TriggerBlock`.
        if first == "base" {
            state.asc_decimal = tokens.next() == Some("dec");
            if tokens.next() == Some("timestamps") {
                state.asc_relative = tokens.next() == Some("relative");
                state.asc_clock_us = 0;
            }
        }
        return Ok(Record::Meta);
    };
    let us = if state.asc_relative {
        state.asc_clock_us = state.asc_clock_us.saturating_add(us);
        state.asc_clock_us
    } else {
        us
    };
    let second = tokens.next().ok_or(TraceError::MissingField)?;
    if second.eq_ignore_ascii_case("CANFD") {
        // A line whose frame does not read is still a CAN FD frame,
        // counted beside the bus load.
        return Ok(
            fd_frame(tokens, state).map_or(Record::Unsupported(Unsupported::CanFd), |f| {
                Record::OnBus {
                    timestamp: Some(Timestamp::from_micros(us)),
                    what: OnBus::Fd(f),
                }
            }),
        );
    }
    if dec_u32(second).is_none() {
        // `Start of measurement`, `Log trigger event`, system variables.
        return match second {
            "Start" | "Log" | "SV:" | "Statistic:" | "Status:" => {
                Ok(Record::Unsupported(Unsupported::Event))
            }
            _ => Err(TraceError::MissingField),
        };
    }
    let channel = second;
    let id_text = tokens.next().ok_or(TraceError::MissingField)?;
    if id_text.eq_ignore_ascii_case("ErrorFrame") {
        return Ok(Record::OnBus {
            timestamp: Some(Timestamp::from_micros(us)),
            what: OnBus::ErrorFrame,
        });
    }
    if matches!(id_text, "Statistic:" | "Status:" | "SV:") {
        return Ok(Record::Unsupported(Unsupported::Event));
    }
    let direction = match tokens.next() {
        Some("Rx") => RxTx::Rx,
        Some("Tx") => RxTx::Tx,
        _ => return Err(TraceError::MissingField),
    };
    let id = frame_id(id_text, state)?;
    let remote = match tokens.next() {
        Some("d") => false,
        Some("r") => true,
        _ => return Err(TraceError::MissingField),
    };
    let mut tokens = tokens.peekable();
    let dlc = match tokens.peek().map(|d| dec_u32(d)) {
        Some(Some(d)) => {
            tokens.next();
            // A classic frame's DLC 9-15 carries 8 bytes.
            match d {
                0..=8 => d as u8,
                9..=15 => 8,
                _ => return Err(TraceError::BadDlc),
            }
        }
        // `r` alone, or followed by the trailer: no length given.
        _ if remote => 0,
        _ => return Err(TraceError::BadDlc),
    };
    let frame = frame(id, dlc, remote, tokens.take(usize::from(dlc)))?;
    Ok(Record::Frame(TraceFrame {
        timestamp: Some(Timestamp::from_micros(us)),
        channel: Some(channel),
        direction: Some(direction),
        frame,
    }))
}
