//! Small total helpers the trace formats share: hex identifiers and bytes,
//! decimal times in seconds or milliseconds, without floats or allocation.

use super::TraceError;
use crate::frame::{CanFrame, CanId, MAX_EXTENDED_ID, MAX_STANDARD_ID};

/// The `N` bytes of a binary trace's fixed-width field at `at`, zeros
/// when the field is not all in `bytes` (the readers check an object's,
/// a block's or a record's length before they read its fields, so zeros
/// come only from a length they have already refused).
pub(super) fn field<const N: usize>(bytes: &[u8], at: usize) -> [u8; N] {
    at.checked_add(N)
        .and_then(|end| bytes.get(at..end))
        .and_then(|s| <[u8; N]>::try_from(s).ok())
        .unwrap_or([0; N])
}

/// The little-endian `u16` at `at` (0 past the end): Vector BLF and
/// ASAM MDF 4 store every number little-endian.
pub(super) fn u16_at(bytes: &[u8], at: usize) -> u16 {
    u16::from_le_bytes(field(bytes, at))
}

/// The little-endian `u32` at `at` (0 past the end).
pub(super) fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(field(bytes, at))
}

/// The little-endian `u64` at `at` (0 past the end).
pub(super) fn u64_at(bytes: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(field(bytes, at))
}

/// A hex digit's value.
pub(super) const fn hex_digit(b: u8) -> Option<u8> {
    match b {
        b'0'..=b'9' => Some(b - b'0'),
        b'a'..=b'f' => Some(b - b'a' + 10),
        b'A'..=b'F' => Some(b - b'A' + 10),
        _ => None,
    }
}

/// A hex number of 1..=8 digits.
pub(super) fn hex_u32(s: &str) -> Option<u32> {
    if s.is_empty() || s.len() > 8 {
        return None;
    }
    s.bytes()
        .try_fold(0u32, |acc, b| Some(acc << 4 | u32::from(hex_digit(b)?)))
}

/// A decimal number of 1..=9 digits.
pub(super) fn dec_u32(s: &str) -> Option<u32> {
    if s.is_empty() || s.len() > 9 {
        return None;
    }
    s.bytes().try_fold(0u32, |acc, b| {
        b.is_ascii_digit().then(|| acc * 10 + u32::from(b - b'0'))
    })
}

/// One data byte: exactly 2 hex digits.
pub(super) fn hex_byte(s: &str) -> Option<u8> {
    match *s.as_bytes() {
        [h, l] => Some(hex_digit(h)? << 4 | hex_digit(l)?),
        _ => None,
    }
}

/// An identifier: standard when it fits 11 bits and `extended` is not
/// forced, else extended (29 bits).
pub(super) fn can_id(raw: u32, extended: bool) -> Result<CanId, TraceError> {
    if !extended && raw <= u32::from(MAX_STANDARD_ID) {
        Ok(CanId::Standard(raw as u16))
    } else if raw <= MAX_EXTENDED_ID {
        Ok(CanId::Extended(raw))
    } else {
        Err(TraceError::BadId)
    }
}

/// A data frame from space-separated hex bytes, or a remote frame of `dlc`
/// (which carries no data: `bytes` is not read).
pub(super) fn frame<'a>(
    id: CanId,
    dlc: u8,
    remote: bool,
    bytes: impl Iterator<Item = &'a str>,
) -> Result<CanFrame, TraceError> {
    if dlc > 8 {
        return Err(TraceError::CanFd);
    }
    if remote {
        return CanFrame::remote(id, dlc).map_err(|_| TraceError::BadDlc);
    }
    let mut data = [0u8; 8];
    let mut n = 0usize;
    for b in bytes {
        let slot = data.get_mut(n).ok_or(TraceError::BadData)?;
        *slot = hex_byte(b).ok_or(TraceError::BadData)?;
        n += 1;
    }
    if n != usize::from(dlc) {
        return Err(TraceError::BadDlc);
    }
    CanFrame::new(id, data.get(..n).unwrap_or(&[])).map_err(|_| TraceError::BadData)
}

/// A non-negative decimal `int[.frac]` scaled by 10^`exp` (6: seconds to
/// microseconds, 3: milliseconds to microseconds). Extra fraction digits
/// are truncated; too large saturates.
pub(super) fn decimal_scaled(s: &str, exp: u32) -> Option<u64> {
    let (int, frac) = match s.split_once('.') {
        Some((i, f)) => (i, f),
        None => (s, ""),
    };
    if int.is_empty() && frac.is_empty() {
        return None;
    }
    if !int.bytes().all(|b| b.is_ascii_digit()) || !frac.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let scale = 10u64.pow(exp);
    let mut value = int.bytes().fold(0u64, |acc, b| {
        acc.saturating_mul(10).saturating_add(u64::from(b - b'0'))
    });
    value = value.saturating_mul(scale);
    let mut unit = scale;
    for b in frac.bytes() {
        unit /= 10;
        if unit == 0 {
            break;
        }
        value = value.saturating_add(u64::from(b - b'0') * unit);
    }
    Some(value)
}
