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
//! CAN FD frames (`ID##FDATA`: one hex digit of FD flags, then the data)
//! are recognised and refused with [`CandumpError::CanFd`] (a malformed one
//! with the error of its malformed part), and error frames (an 8-digit
//! identifier with SocketCAN's `CAN_ERR_FLAG`, 2000 0000h, as candump
//! writes them: `20000004#0004000000000000`) with
//! [`CandumpError::ErrorFrame`]; [`parse_on_bus`] reads both for the bus
//! load.

use core::fmt;

use crate::clock::Timestamp;
use crate::frame::{CanFrame, CanId, MAX_EXTENDED_ID, MAX_STANDARD_ID};
use crate::trace::{FdFrame, OnBus};

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
    /// An error frame (SocketCAN's `CAN_ERR_FLAG` in the identifier).
    #[error("error frame")]
    ErrorFrame,
}

/// SocketCAN's `CAN_ERR_FLAG` (linux/can.h): the frame is an error frame.
const CAN_ERR_FLAG: u32 = 0x2000_0000;

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
/// use canopen_codec::trace::candump::parse_line;
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
    let [b'(', rest @ ..] = bytes else {
        return None;
    };
    let (us, tail) = usual_time(rest)?;
    // The interface: printable ASCII up to one space, no '#'.
    let iface_start = bytes.len() - tail.len();
    let iface_len = tail.iter().position(|&b| b == b' ')?;
    let iface = tail.get(..iface_len)?;
    if iface.is_empty() || !iface.iter().all(|&b| b.is_ascii_graphic() && b != b'#') {
        return None;
    }
    let frame_text = tail.get(iface_len + 1..)?;
    let frame = match usual_frame(frame_text) {
        Some(frame) => frame,
        None => {
            if frame_text.is_empty() || !frame_text.iter().all(u8::is_ascii_graphic) {
                return None;
            }
            parse_frame(line.get(iface_start + iface_len + 1..)?).ok()?
        }
    };
    Some(LogLine {
        timestamp: Some(Timestamp::from_micros(us)),
        interface: line.get(iface_start..iface_start + iface_len),
        frame,
    })
}

/// `secs.micros) ` after the `(`: the time in microseconds and the text
/// after the space. candump's own shape (10 digits, 6 digits) is read
/// eight digits at a time; any other is read digit by digit.
fn usual_time(rest: &[u8]) -> Option<(u64, &[u8])> {
    if let Some((&[a, b, s @ .., b'.', m0, m1, m2, m3, m4, m5, b')', b' '], tail)) =
        rest.split_first_chunk::<19>()
    {
        if let (Some(lead), Some(secs), Some(micros)) = (
            two_digits(a, b),
            eight_digits(s),
            eight_digits([b'0', b'0', m0, m1, m2, m3, m4, m5]),
        ) {
            // At most 9 999 999 999 999 999: no overflow.
            return Some(((lead * 100_000_000 + secs) * 1_000_000 + micros, tail));
        }
    }
    // Seconds (at most 19 digits: no overflow), '.', 1..=6 digits, ')'.
    let (secs, n, rest) = leading_digits(rest, 19)?;
    let [b'.', rest @ ..] = rest else {
        return None;
    };
    let (mut micros, places, rest) = leading_digits(rest, 6)?;
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
    Some((us, tail))
}

/// The ASCII digits at the start of `rest` as a number, how many there
/// are and what follows them; `None` for more than `max` (at most 19, so
/// the number cannot overflow).
fn leading_digits(rest: &[u8], max: usize) -> Option<(u64, usize, &[u8])> {
    let (mut value, mut n, mut rest) = (0u64, 0, rest);
    while let [d @ b'0'..=b'9', tail @ ..] = rest {
        if n == max {
            return None;
        }
        value = value * 10 + u64::from(d - b'0');
        rest = tail;
        n += 1;
    }
    Some((value, n, rest))
}

/// Two ASCII digits as a number.
fn two_digits(a: u8, b: u8) -> Option<u64> {
    let (a, b) = (a.wrapping_sub(b'0'), b.wrapping_sub(b'0'));
    (a < 10 && b < 10).then(|| u64::from(a * 10 + b))
}

/// Eight ASCII digits, most significant first, as a number (all eight
/// checked and combined in a few word operations); `None` unless every
/// byte is a digit.
fn eight_digits(digits: [u8; 8]) -> Option<u64> {
    const ONES: u64 = 0x0101_0101_0101_0101;
    // Each byte minus '0'. A byte below '0' borrows, but it then has its
    // high nibble set itself, so the check below still refuses it.
    let d = u64::from_le_bytes(digits).wrapping_sub(0x30 * ONES);
    // A byte is a digit when it and it plus 6 both stay below 10h.
    if (d | d.wrapping_add(6 * ONES)) & (0xF0 * ONES) != 0 {
        return None;
    }
    // Pairs, then fours, then all eight (the first byte is the most
    // significant digit).
    let d = (d * 10 + (d >> 8)) & 0x00FF_00FF_00FF_00FF;
    let d = (d * 100 + (d >> 16)) & 0x0000_FFFF_0000_FFFF;
    Some((d * 10_000 + (d >> 32)) & 0xFFFF_FFFF)
}

/// Hex digit values by byte (`0xFF`: not a hex digit).
const HEX: [u8; 256] = {
    let mut table = [0xFF; 256];
    let mut b = 0;
    while b < 256 {
        table[b] = match b as u8 {
            d @ b'0'..=b'9' => d - b'0',
            d @ b'a'..=b'f' => d - b'a' + 10,
            d @ b'A'..=b'F' => d - b'A' + 10,
            _ => 0xFF,
        };
        b += 1;
    }
    table
};

/// The usual frame field, an 11-bit identifier in 3 hex digits and up to 8
/// data bytes (`18A#7413454E`); `None` for anything else (then
/// [`parse_frame`] decides).
fn usual_frame(text: &[u8]) -> Option<CanFrame> {
    let &[h0, h1, h2, b'#', ref data @ ..] = text else {
        return None;
    };
    let (h0, h1, h2) = (
        HEX[usize::from(h0)],
        HEX[usize::from(h1)],
        HEX[usize::from(h2)],
    );
    if (h0 | h1 | h2) > 0xF || data.len() % 2 != 0 || data.len() > 16 {
        return None;
    }
    let id = u16::from(h0) << 8 | u16::from(h1) << 4 | u16::from(h2);
    if id > MAX_STANDARD_ID {
        return None;
    }
    let mut buf = [0u8; 8];
    for (dst, pair) in buf.iter_mut().zip(data.chunks_exact(2)) {
        let [hi, lo] = *pair else {
            return None;
        };
        let (hi, lo) = (HEX[usize::from(hi)], HEX[usize::from(lo)]);
        if (hi | lo) > 0xF {
            return None;
        }
        *dst = hi << 4 | lo;
    }
    Some(CanFrame::from_parts(
        CanId::Standard(id),
        buf,
        (data.len() / 2) as u8,
    ))
}

/// Any line: whitespace-separated fields.
fn parse_general(line: &str) -> Result<LogLine<'_>, CandumpError> {
    let (timestamp, interface, field, trailing) = split_fields(line)?;
    let frame = parse_frame(field)?;
    if trailing {
        return Err(CandumpError::TrailingText);
    }
    Ok(LogLine {
        timestamp,
        interface,
        frame,
    })
}

/// A line's time, interface and frame field, and whether text follows it.
type Fields<'a> = (Option<Timestamp>, Option<&'a str>, &'a str, bool);

/// The fields of a line: `(time) interface frame`, either of the first two
/// left out.
fn split_fields(line: &str) -> Result<Fields<'_>, CandumpError> {
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
    Ok((timestamp, interface, field, fields.next().is_some()))
}

/// A line whose frame is a CAN FD frame (`123##1` and its data) or an error
/// frame (`20000004#...`), with its time: what the bus load counts of it.
/// A classic frame is [`CandumpError::MissingFrame`].
pub fn parse_on_bus(line: &str) -> Result<(Option<Timestamp>, OnBus), CandumpError> {
    let (timestamp, _, field, trailing) = split_fields(line)?;
    if trailing {
        return Err(CandumpError::TrailingText);
    }
    let (id, data) = field.split_once('#').ok_or(CandumpError::MissingFrame)?;
    match (parse_id(id), data.strip_prefix('#')) {
        (Err(CandumpError::ErrorFrame), _) => Ok((timestamp, OnBus::ErrorFrame)),
        (Ok(id), Some(fd)) => {
            fd_frame(fd)?;
            let (flags, data) = fd.split_at_checked(1).ok_or(CandumpError::BadData)?;
            let flags = flags.bytes().next().and_then(hex_digit).unwrap_or(0);
            let mut buf = [0u8; 64];
            let mut len = 0;
            for (dst, pair) in buf.iter_mut().zip(data.as_bytes().chunks_exact(2)) {
                let [hi, lo] = *pair else {
                    return Err(CandumpError::BadData);
                };
                *dst = hex_digit(hi).ok_or(CandumpError::BadData)? << 4
                    | hex_digit(lo).ok_or(CandumpError::BadData)?;
                len += 1;
            }
            let data = buf.get(..len).unwrap_or(&[]);
            FdFrame::new(id, data, flags & 1 != 0, flags & 2 != 0)
                .map(|f| (timestamp, OnBus::Fd(f)))
                .ok_or(CandumpError::TooLong)
        }
        (Err(e), _) => Err(e),
        (Ok(_), None) => Err(CandumpError::MissingFrame),
    }
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
    let id = parse_id(id)?;
    if let Some(fd) = data.strip_prefix('#') {
        return Err(fd_frame(fd).err().unwrap_or(CandumpError::CanFd));
    }
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

/// The identifier field: 3 hex digits for an 11-bit identifier, 8 for a
/// 29-bit one; [`CandumpError::ErrorFrame`] for 8 digits with
/// `CAN_ERR_FLAG` set.
fn parse_id(id: &str) -> Result<CanId, CandumpError> {
    let raw = id
        .bytes()
        .try_fold(0u32, |acc, b| Some(acc << 4 | u32::from(hex_digit(b)?)))
        .ok_or(CandumpError::BadId)?;
    match id.len() {
        3 if raw <= u32::from(MAX_STANDARD_ID) => Ok(CanId::Standard(raw as u16)),
        8 if raw <= MAX_EXTENDED_ID => Ok(CanId::Extended(raw)),
        8 if raw & !MAX_EXTENDED_ID == CAN_ERR_FLAG => Err(CandumpError::ErrorFrame),
        _ => Err(CandumpError::BadId),
    }
}

/// Checks the part of a CAN FD field after `ID##`: one hex digit of FD
/// flags (bit 0 bit-rate switch, bit 1 error state indicator), then the
/// data in hex pairs, of a CAN FD length (0..=8, 12, 16, 20, 24, 32, 48, 64
/// bytes, ISO 11898-1); the error of the malformed part otherwise.
fn fd_frame(fd: &str) -> Result<(), CandumpError> {
    let Some((&flags, data)) = fd.as_bytes().split_first() else {
        return Err(CandumpError::BadData);
    };
    if hex_digit(flags).is_none()
        || data.len() % 2 != 0
        || !data.iter().all(|&b| hex_digit(b).is_some())
    {
        return Err(CandumpError::BadData);
    }
    match data.len() / 2 {
        0..=8 | 12 | 16 | 20 | 24 | 32 | 48 | 64 => Ok(()),
        _ => Err(CandumpError::TooLong),
    }
}

/// Writes a frame as a candump log line: `(secs.micros) iface ID#DATA`.
///
/// ```
/// use canopen_codec::trace::candump::LogLineDisplay;
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
                "(1.000001) can0 123##1112233",
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

    /// The word-at-a-time digit reader equals reading digit by digit, for
    /// every byte at every place.
    #[test]
    fn eight_digits_is_digit_by_digit() {
        let naive = |d: [u8; 8]| {
            d.iter().try_fold(0u64, |acc, &b| {
                b.is_ascii_digit().then(|| acc * 10 + u64::from(b - b'0'))
            })
        };
        for base in [*b"12345678", *b"00000000", *b"99999999", *b"90817263"] {
            assert_eq!(eight_digits(base), naive(base));
            for place in 0..8 {
                for byte in 0..=255u8 {
                    let mut d = base;
                    d[place] = byte;
                    assert_eq!(eight_digits(d), naive(d), "{d:?}");
                }
            }
        }
        for a in 0..=255u8 {
            for b in 0..=255u8 {
                let d = [a, b, b'0', b'1', b'2', b'3', b'4', b'5'];
                assert_eq!(eight_digits(d), naive(d), "{d:?}");
                assert_eq!(
                    two_digits(a, b),
                    naive([b'0', b'0', b'0', b'0', b'0', b'0', a, b])
                );
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(crate::testing::proptest_config("tests/proptest-regressions/src-trace-candump.txt"))]
        /// Lines near the usual shape read the same by the fast reader and
        /// by the general one.
        #[test]
        fn usual_shapes_read_as_the_general_reader_reads_them(
            line in "\\([0-9]{0,12}\\.?[0-9]{0,7}\\)? ?[a-z0-9#]{0,5} [0-9A-Fa-fxR#]{0,20}"
        ) {
            let general = parse_general(&line);
            if let Some(u) = parse_usual(&line) {
                proptest::prop_assert_eq!(Ok(u), general);
            }
            proptest::prop_assert_eq!(parse_line(&line), general);
        }

        /// candump's own shape, with any hex digits and lengths: the fast
        /// reader takes every well-formed one and agrees on all.
        #[test]
        fn candump_shape_reads_as_the_general_reader_reads_it(
            line in "\\([0-9]{10}\\.[0-9]{6}\\) can[0-9] [0-9A-Fa-f]{3}#[0-9A-Fa-f]{0,18}"
        ) {
            let general = parse_general(&line);
            let usual = parse_usual(&line);
            proptest::prop_assert_eq!(usual.is_some(), general.is_ok());
            if let Some(u) = usual {
                proptest::prop_assert_eq!(Ok(u), general);
            }
        }
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
            ("20000000#05", ErrorFrame),
            ("40000000#05", BadId),
            ("1FFFFFFF##05", BadData),
            ("701#0", BadData),
            ("701#ZZ", BadData),
            ("701#R12", BadData),
            ("701#R9", TooLong),
            ("701#000102030405060708", TooLong),
            ("701##0112", BadData),
            ("701##", BadData),
            ("701##G11", BadData),
            ("701##1ZZ", BadData),
            ("701##0112233445566778899", TooLong),
            ("7011##011", BadId),
            ("701#05 extra", TrailingText),
        ] {
            assert_eq!(parse_line(line), Err(err), "{line:?}");
        }
    }

    #[test]
    fn fd_and_error_frames_for_the_bus_load() {
        use std::string::ToString;
        let t = Some(Timestamp::from_micros(1_500_000));
        let fd = |text: &str| match parse_on_bus(text) {
            Ok((time, OnBus::Fd(f))) => (time, f),
            other => panic!("{text}: {other:?}"),
        };
        let (time, f) = fd("(1.5) can0 123##1AABB");
        assert_eq!(
            (time, f.id(), f.data(), f.brs(), f.esi()),
            (t, CanId::Standard(0x123), &[0xAA, 0xBB][..], true, false)
        );
        let (_, f) = fd("1FFFFFFF##2");
        assert_eq!(
            (f.id(), f.dlc(), f.brs(), f.esi()),
            (CanId::Extended(0x1FFF_FFFF), 0, false, true)
        );
        let twelve = "00".repeat(12);
        let (_, f) = fd(&format!("123##3{twelve}"));
        assert_eq!((f.dlc(), f.data().len()), (9, 12));
        assert_eq!(f.to_string(), format!("123##3{twelve}"));
        assert_eq!(
            parse_on_bus("(1.5) can0 20000004#0004000000000000"),
            Ok((t, OnBus::ErrorFrame))
        );
        assert_eq!(
            parse_on_bus("(1.5) can0 123#00"),
            Err(CandumpError::MissingFrame)
        );
        assert_eq!(
            parse_on_bus("123##1001122334455667788"),
            Err(CandumpError::TooLong)
        );
        assert_eq!(parse_on_bus("123##Z"), Err(CandumpError::BadData));
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
