//! python-can CSV logs (`can.CSVWriter`):
//!
//! ```text
//! timestamp,arbitration_id,extended,remote,error,dlc,data
//! 1756955653.603308,0x18a,0,0,0,8,dBNFTnAAAAA=
//! 1756955653.612992,0x70a,0,1,0,1,
//! ```
//!
//! `timestamp` is UNIX seconds; `arbitration_id` hex with `0x` (decimal
//! accepted); `extended`, `remote`, `error` are 0/1; `data` is the bytes in
//! standard base64 (RFC 4648, with padding), as python-can writes them.
//! The base64 decoder is written here (a dozen lines): the library takes no
//! dependency for it.

use super::fields::{can_id, dec_u32, decimal_scaled, frame, hex_u32};
use super::{Record, TraceError, TraceFrame, Unsupported};
use crate::clock::Timestamp;
use crate::frame::CanFrame;

pub(super) fn parse(line: &str) -> Result<Record<'_>, TraceError> {
    let t = line.trim();
    if t.starts_with("timestamp,") {
        return Ok(Record::Meta);
    }
    let mut f = t.split(',');
    let mut next = || f.next().map(str::trim).ok_or(TraceError::MissingField);
    let (ts, id, ext, rtr, err, dlc, data) = (
        next()?,
        next()?,
        next()?,
        next()?,
        next()?,
        next()?,
        next()?,
    );
    if next().is_ok() {
        return Err(TraceError::MissingField);
    }
    let us = decimal_scaled(ts, 6).ok_or(TraceError::BadTimestamp)?;
    let flag = |s: &str| match s {
        "0" | "False" | "false" => Ok(false),
        "1" | "True" | "true" => Ok(true),
        _ => Err(TraceError::MissingField),
    };
    if flag(err)? {
        return Ok(Record::Unsupported(Unsupported::ErrorFrame));
    }
    let raw = match id.strip_prefix("0x").or_else(|| id.strip_prefix("0X")) {
        Some(h) => hex_u32(h),
        None => dec_u32(id),
    }
    .ok_or(TraceError::BadId)?;
    let id = can_id(raw, flag(ext)?)?;
    let dlc = dec_u32(dlc)
        .and_then(|d| u8::try_from(d).ok())
        .ok_or(TraceError::BadDlc)?;
    let remote = flag(rtr)?;
    let frame = if remote {
        frame(id, dlc, true, core::iter::empty())?
    } else {
        let mut bytes = [0u8; 8];
        let n = base64(data, &mut bytes).ok_or(TraceError::BadData)?;
        if n != usize::from(dlc) {
            return Err(if dlc > 8 {
                TraceError::CanFd
            } else {
                TraceError::BadDlc
            });
        }
        CanFrame::new(id, bytes.get(..n).unwrap_or(&[])).map_err(|_| TraceError::BadData)?
    };
    Ok(Record::Frame(TraceFrame {
        timestamp: Some(Timestamp::from_micros(us)),
        channel: None,
        direction: None,
        frame,
    }))
}

/// Decodes standard base64 into `out`; the number of bytes, or `None` for
/// bad characters, bad padding or more bytes than `out` holds.
fn base64(s: &str, out: &mut [u8]) -> Option<usize> {
    let value = |c: u8| -> Option<u32> {
        Some(u32::from(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        }))
    };
    let bytes = s.as_bytes();
    if !bytes.len().is_multiple_of(4) {
        return None;
    }
    let mut n = 0usize;
    let groups = bytes.len() / 4;
    for (g, quad) in bytes.chunks_exact(4).enumerate() {
        let last = g + 1 == groups;
        let pad = quad.iter().rev().take_while(|c| **c == b'=').count();
        if pad > 2 || (pad > 0 && !last) {
            return None;
        }
        let mut acc = 0u32;
        for &c in quad.get(..4 - pad)? {
            acc = acc << 6 | value(c)?;
        }
        acc <<= 6 * pad as u32;
        for byte in acc.to_be_bytes().get(1..4 - pad)? {
            *out.get_mut(n)? = *byte;
            n += 1;
        }
    }
    Some(n)
}

#[cfg(test)]
mod tests {
    use super::base64;

    #[test]
    fn base64_vectors() {
        // RFC 4648, section 10.
        for (text, want) in [
            ("", &b""[..]),
            ("Zg==", b"f"),
            ("Zm8=", b"fo"),
            ("Zm9v", b"foo"),
            ("Zm9vYg==", b"foob"),
            ("Zm9vYmE=", b"fooba"),
            ("Zm9vYmFy", b"foobar"),
            ("dBNFTnAAAAA=", &[0x74, 0x13, 0x45, 0x4E, 0x70, 0, 0, 0]),
        ] {
            let mut out = [0u8; 8];
            let n = base64(text, &mut out).unwrap();
            assert_eq!(&out[..n], want, "{text}");
        }
        let mut out = [0u8; 8];
        for bad in ["Zg=", "Z===", "Zg==Zg==", "Zm9v!A==", "AAAAAAAAAAAA"] {
            assert_eq!(base64(bad, &mut out), None, "{bad}");
        }
    }
}
