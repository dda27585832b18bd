//! The candump log line format (Linux can-utils), parsed and written without
//! allocation, so loggers, replayers and the example programs share one
//! implementation.
//!
//! Accepted forms (whitespace-separated fields):
//!
//! - `(1700000000.123456) can0 18A#7413454E70000000`: timestamp, interface, frame
//! - `18A#7413454E70000000`: the frame alone
//! - `701#R`, `701#R1`: remote frames (DLC 0 or the digit given)
//! - 3 hex digits mean an 11-bit identifier, 8 hex digits a 29-bit one.
//!
//! CAN FD (`ID##...`) and error frames are rejected with a typed error.

use core::fmt;

use crate::frame::{CanFrame, CanId, MAX_EXTENDED_ID, MAX_STANDARD_ID};
use crate::time::Timestamp;

/// Why a candump line did not parse.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CandumpError {
    /// The line is empty or only whitespace.
    #[error("empty line")]
    Empty,
    /// The timestamp is not `(seconds.fraction)` with at most 6 fraction digits.
    #[error("bad timestamp")]
    BadTimestamp,
    /// No `ID#DATA` field.
    #[error("no ID#DATA field")]
    MissingFrame,
    /// The identifier is not 3 or 8 hex digits, or is out of range.
    #[error("bad identifier")]
    BadId,
    /// The data is not an even number of hex digits.
    #[error("bad data bytes")]
    BadData,
    /// More than 8 data bytes (or remote DLC above 8).
    #[error("more than 8 data bytes")]
    TooLong,
    /// CAN FD frames (`ID##...`) are not classic CAN.
    #[error("CAN FD frames are not supported")]
    CanFd,
    /// Extra fields after the frame.
    #[error("unexpected text after the frame")]
    TrailingText,
}

/// One parsed log line. Borrows the interface name from the line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LogLine<'a> {
    /// The `(seconds.micros)` timestamp, if present.
    pub timestamp: Option<Timestamp>,
    /// The interface name (`can0`), if present.
    pub interface: Option<&'a str>,
    /// The frame.
    pub frame: CanFrame,
}

/// Parses one candump log line.
///
/// ```
/// use canopen_codec::candump::parse_line;
/// let l = parse_line("(1756955653.603308) can1 000#010A").unwrap();
/// assert_eq!(l.timestamp.unwrap().as_micros(), 1_756_955_653_603_308);
/// assert_eq!(l.interface, Some("can1"));
/// assert_eq!(l.frame.data(), &[0x01, 0x0A]);
/// assert!(parse_line("701#R").unwrap().frame.is_remote());
/// ```
pub fn parse_line(line: &str) -> Result<LogLine<'_>, CandumpError> {
    if let Some(parsed) = parse_usual(line) {
        return Ok(parsed);
    }
    parse_general(line)
}

/// The line candump `-L` writes, `(1700000000.123456) can0 18A#7413454E`,
/// read in one pass over its bytes; `None` for anything else (then the
/// general reader decides, so both give the same answer for every line).
fn parse_usual(line: &str) -> Option<LogLine<'_>> {
    let bytes = line.as_bytes();
    let (b'(', mut rest) = bytes.split_first().map(|(b, r)| (*b, r))? else {
        return None;
    };
    // Seconds (at most 19 digits: no overflow), '.', 1..=6 digits, ')'.
    let mut secs: u64 = 0;
    let mut n = 0;
    while let [d @ b'0'..=b'9', tail @ ..] = rest {
        if n == 19 {
            return None;
        }
        secs = secs * 10 + u64::from(d - b'0');
        rest = tail;
        n += 1;
    }
    let [b'.', tail @ ..] = rest else {
        return None;
    };
    rest = tail;
    let (mut micros, mut places) = (0u64, 0);
    while let [d @ b'0'..=b'9', tail @ ..] = rest {
        if places == 6 {
            return None;
        }
        micros = micros * 10 + u64::from(d - b'0');
        rest = tail;
        places += 1;
    }
    let [b')', b' ', tail @ ..] = rest else {
        return None;
    };
    if n == 0 || places == 0 {
        return None;
    }
    for _ in places..6 {
        micros *= 10;
    }
    let us = secs.checked_mul(1_000_000)?.checked_add(micros)?;
    // The interface: printable ASCII up to one space, no '#'.
    let iface_start = bytes.len() - tail.len();
    let iface_len = tail.iter().position(|&b| b == b' ')?;
    let iface = tail.get(..iface_len)?;
    if iface.is_empty() || !iface.iter().all(|&b| b.is_ascii_graphic() && b != b'#') {
        return None;
    }
    let frame_start = iface_start + iface_len + 1;
    let frame_text = line.get(frame_start..)?;
    if frame_text.is_empty() || !frame_text.bytes().all(|b| b.is_ascii_graphic()) {
        return None;
    }
    let frame = parse_frame(frame_text).ok()?;
    Some(LogLine {
        timestamp: Some(Timestamp::from_micros(us)),
        interface: line.get(iface_start..iface_start + iface_len),
        frame,
    })
}

/// Any line: whitespace-separated fields.
fn parse_general(line: &str) -> Result<LogLine<'_>, CandumpError> {
    let mut fields = line.split_ascii_whitespace();
    let mut field = fields.next().ok_or(CandumpError::Empty)?;
    let mut timestamp = None;
    let mut interface = None;
    if field.starts_with('(') {
        timestamp = Some(parse_timestamp(field)?);
        field = fields.next().ok_or(CandumpError::MissingFrame)?;
        if !field.contains('#') {
            interface = Some(field);
            field = fields.next().ok_or(CandumpError::MissingFrame)?;
        }
    } else if !field.contains('#') {
        interface = Some(field);
        field = fields.next().ok_or(CandumpError::MissingFrame)?;
    }
    let frame = parse_frame(field)?;
    if fields.next().is_some() {
        return Err(CandumpError::TrailingText);
    }
    Ok(LogLine {
        timestamp,
        interface,
        frame,
    })
}

fn parse_timestamp(field: &str) -> Result<Timestamp, CandumpError> {
    let inner = field
        .strip_prefix('(')
        .and_then(|f| f.strip_suffix(')'))
        .ok_or(CandumpError::BadTimestamp)?;
    let (secs, frac) = inner.split_once('.').unwrap_or((inner, ""));
    if secs.is_empty() || frac.len() > 6 {
        return Err(CandumpError::BadTimestamp);
    }
    let secs = parse_dec(secs).ok_or(CandumpError::BadTimestamp)?;
    let mut micros = if frac.is_empty() {
        0
    } else {
        parse_dec(frac).ok_or(CandumpError::BadTimestamp)?
    };
    for _ in frac.len()..6 {
        micros *= 10;
    }
    secs.checked_mul(1_000_000)
        .and_then(|us| us.checked_add(micros))
        .map(Timestamp::from_micros)
        .ok_or(CandumpError::BadTimestamp)
}

fn parse_dec(s: &str) -> Option<u64> {
    if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    s.bytes().try_fold(0u64, |acc, b| {
        acc.checked_mul(10)?.checked_add(u64::from(b - b'0'))
    })
}

fn hex_digit(b: u8) -> Option<u8> {
    match b {
        b'0'..=b'9' => Some(b - b'0'),
        b'a'..=b'f' => Some(b - b'a' + 10),
        b'A'..=b'F' => Some(b - b'A' + 10),
        _ => None,
    }
}

/// Parses the `ID#DATA` / `ID#R[dlc]` field alone.
pub fn parse_frame(field: &str) -> Result<CanFrame, CandumpError> {
    let (id, data) = field.split_once('#').ok_or(CandumpError::MissingFrame)?;
    if data.starts_with('#') {
        return Err(CandumpError::CanFd);
    }
    let raw = id
        .bytes()
        .try_fold(0u32, |acc, b| Some(acc << 4 | u32::from(hex_digit(b)?)))
        .ok_or(CandumpError::BadId)?;
    let id = match id.len() {
        3 if raw <= u32::from(MAX_STANDARD_ID) => CanId::Standard(raw as u16),
        8 if raw <= MAX_EXTENDED_ID => CanId::Extended(raw),
        _ => return Err(CandumpError::BadId),
    };
    if let Some(dlc) = data.strip_prefix('R').or_else(|| data.strip_prefix('r')) {
        let dlc = match dlc.as_bytes() {
            [] => 0,
            [d] => hex_digit(*d)
                .filter(|d| *d <= 9)
                .ok_or(CandumpError::BadData)?,
            _ => return Err(CandumpError::BadData),
        };
        return CanFrame::remote(id, dlc).map_err(|_| CandumpError::TooLong);
    }
    let digits = data.as_bytes();
    if digits.len() % 2 != 0 {
        return Err(CandumpError::BadData);
    }
    if digits.len() > 16 {
        return Err(CandumpError::TooLong);
    }
    let mut buf = [0u8; 8];
    for (dst, pair) in buf.iter_mut().zip(digits.chunks_exact(2)) {
        let [hi, lo] = *pair else {
            return Err(CandumpError::BadData);
        };
        *dst = hex_digit(hi).ok_or(CandumpError::BadData)? << 4
            | hex_digit(lo).ok_or(CandumpError::BadData)?;
    }
    let len = digits.len() / 2;
    CanFrame::new(id, buf.get(..len).unwrap_or(&[])).map_err(|_| CandumpError::TooLong)
}

/// Writes a frame as a candump log line: `(secs.micros) iface ID#DATA`.
///
/// ```
/// use canopen_codec::candump::LogLineDisplay;
/// use canopen_codec::{CanFrame, Timestamp};
/// let f = CanFrame::standard(0x70A, &[0x05]).unwrap();
/// let line = LogLineDisplay { timestamp: Timestamp::from_micros(1_500_000), interface: "can0", frame: &f };
/// assert_eq!(line.to_string(), "(1.500000) can0 70A#05");
/// ```
#[derive(Debug, Clone, Copy)]
pub struct LogLineDisplay<'a> {
    /// When the frame was seen or sent.
    pub timestamp: Timestamp,
    /// Interface name.
    pub interface: &'a str,
    /// The frame.
    pub frame: &'a CanFrame,
}

impl fmt::Display for LogLineDisplay<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}) {} {}", self.timestamp, self.interface, self.frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-pass reader of the usual line gives what the general reader
    /// gives, for the usual line and every near miss of it.
    #[test]
    fn the_usual_line_reads_as_the_general_reader_reads_it() {
        use std::string::{String, ToString};
        use std::vec::Vec;
        let base = "(1756955653.612992) can0 18A#7413454E70000000";
        let mut lines: Vec<String> = std::vec![base.to_string()];
        let alphabet = [
            ' ', '\t', '(', ')', '.', '#', '0', '9', 'A', 'f', 'R', 'x', '\u{e9}',
        ];
        for i in 0..=base.len() {
            for c in alphabet {
                let mut replaced = base.to_string();
                if i < base.len() && base.is_char_boundary(i) && base.is_char_boundary(i + 1) {
                    replaced.replace_range(i..i + 1, c.encode_utf8(&mut [0; 4]));
                    lines.push(replaced);
                }
                let mut inserted = base.to_string();
                inserted.insert(i, c);
                lines.push(inserted);
            }
            lines.push(base[..i].to_string());
            lines.push(base[i..].to_string());
        }
        lines.extend(
            [
                "(1.5) c 123#",
                "(1.) can0 123#00",
                "(.5) can0 123#00",
                "(18446744073709.551615) can0 123#00",
                "(18446744073710.000000) can0 123#00",
                "(99999999999999999999.1) can0 123#00",
                "(1.1234567) can0 123#00",
                "(1.000001) can0 12345678#0011",
                "(1.000001) can0 123#R",
                "(1.000001) can0 123#R8",
                "(1.000001) can0 123##01",
                "(1.000001)  can0 123#00",
                "(1.000001) can0  123#00",
                "(1.000001) can0 123#00 ",
                "(1.000001) can0 123#00 x",
            ]
            .map(str::to_string),
        );
        for line in &lines {
            let usual = parse_usual(line);
            let general = parse_general(line);
            if let Some(u) = usual {
                assert_eq!(Ok(u), general, "{line:?}");
            }
            assert_eq!(parse_line(line), general, "{line:?}");
        }
        assert!(parse_usual(base).is_some());
    }

    #[test]
    fn forms() {
        let l = parse_line("(1757032311.207551) can1 70A#7F").unwrap();
        assert_eq!(
            l.timestamp,
            Some(Timestamp::from_micros(1_757_032_311_207_551))
        );
        assert_eq!(l.frame, CanFrame::standard(0x70A, &[0x7F]).unwrap());
        let l = parse_line("  18A#7413454E70000000 ").unwrap();
        assert_eq!((l.timestamp, l.interface), (None, None));
        assert_eq!(l.frame.dlc(), 8);
        let l = parse_line("vcan0 12345678#").unwrap();
        assert_eq!(l.interface, Some("vcan0"));
        assert_eq!(l.frame.id(), CanId::Extended(0x1234_5678));
        assert_eq!(l.frame.dlc(), 0);
        assert_eq!(parse_line("(1.5) 701#R1").unwrap().frame.dlc(), 1);
        assert_eq!(
            parse_line("(1.5) 701#R1").unwrap().timestamp,
            Some(Timestamp::from_micros(1_500_000))
        );
        assert_eq!(
            parse_line("(2) 080#").unwrap().timestamp,
            Some(Timestamp::from_millis(2000))
        );
    }

    #[test]
    fn errors() {
        use CandumpError::*;
        for (line, err) in [
            ("", Empty),
            ("   ", Empty),
            ("(1.5", BadTimestamp),
            ("(1.1234567) can0 701#05", BadTimestamp),
            ("(x) can0 701#05", BadTimestamp),
            ("(99999999999999999999.0) can0 701#05", BadTimestamp),
            ("(1.0) can0", MissingFrame),
            ("can0", MissingFrame),
            ("7011#05", BadId),
            ("800#05", BadId),
            ("G01#05", BadId),
            ("20000000#05", BadId),
            ("701#0", BadData),
            ("701#ZZ", BadData),
            ("701#R12", BadData),
            ("701#R9", TooLong),
            ("701#000102030405060708", TooLong),
            ("701##0112", CanFd),
            ("701#05 extra", TrailingText),
        ] {
            assert_eq!(parse_line(line), Err(err), "{line:?}");
        }
    }

    #[test]
    fn display_parses_back() {
        let f = CanFrame::standard(0x08A, &[0x30, 0x81, 1, 0x20, 0x80, 0, 0, 0]).unwrap();
        let t = Timestamp::from_micros(1_756_955_653_612_992);
        let s = format!(
            "{}",
            LogLineDisplay {
                timestamp: t,
                interface: "can1",
                frame: &f
            }
        );
        assert_eq!(s, "(1756955653.612992) can1 08A#3081012080000000");
        let back = parse_line(&s).unwrap();
        assert_eq!((back.timestamp, back.frame), (Some(t), f));
    }
}
