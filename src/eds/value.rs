//! Numbers and values of an EDS: integers in decimal or `0x` hex (leading
//! zeros allowed, a leading minus sign allowed), `$NODEID` sums, and the
//! encoding of a `DefaultValue` into the bytes an SDO upload returns.
//!
//! CiA 306 ("Electronic data sheet specification for CANopen", section 4.6
//! "Object descriptions") lets a value be an expression `$NODEID+<number>`
//! so that one file serves every node id; real files also write the term
//! last (`0x180+$NODEID`), in any case and with spaces (`$NodeID + 0x200`),
//! and all of them are read here. CiA 306 reads a leading `0` as octal, but
//! the tools that write zero-padded numbers (`0010`) mean decimal, and
//! python-canopen and CANopenNode read them so: so do we.

use alloc::vec::Vec;

use super::DataType;

/// Why a value could not be read or encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum ValueError {
    /// The text is not a number (nor a `$NODEID` sum).
    #[error("not a number")]
    NotANumber,
    /// The value uses `$NODEID` but no node id was given.
    #[error("$NODEID used without a node id")]
    NoNodeId,
    /// The number does not fit the data type.
    #[error("value out of range for the data type")]
    OutOfRange,
    /// The data type has no known encoding (an unknown DEFTYPE or DEFSTRUCT).
    #[error("no encoding for data type {0:#06x}")]
    UnsupportedType(u16),
}

/// Reads an integer: decimal (leading zeros allowed) or `0x`/`0X` hex, with
/// an optional sign; spaces around it are ignored. `None` if it is not one
/// or does not fit an `i128`. The sign may also follow the `0x` (`0x-5`),
/// as python-canopen's DCF writer puts it.
///
/// ```
/// use canopen_codec::eds::parse_int;
/// assert_eq!(parse_int("0x180"), Some(0x180));
/// assert_eq!(parse_int(" 0010 "), Some(10));
/// assert_eq!(parse_int("-100"), Some(-100));
/// assert_eq!(parse_int("0x"), None);
/// ```
#[must_use]
pub fn parse_int(s: &str) -> Option<i128> {
    let s = s.trim();
    let (negative, s) = match s.as_bytes() {
        [b'-', ..] => (true, s.get(1..)?),
        [b'+', ..] => (false, s.get(1..)?),
        _ => (false, s),
    };
    let (negative, digits, radix) = match s.as_bytes() {
        // `0x-5`: python-canopen's DCF writer spells a negative number so.
        [b'0', b'x' | b'X', b'-', ..] if !negative => (true, s.get(3..)?, 16),
        [b'0', b'x' | b'X', ..] => (negative, s.get(2..)?, 16),
        _ => (negative, s, 10),
    };
    if digits.is_empty() {
        return None;
    }
    let mut n: i128 = 0;
    for c in digits.chars() {
        let d = c.to_digit(radix)?;
        n = n
            .checked_mul(i128::from(radix))?
            .checked_add(i128::from(d))?;
    }
    Some(if negative { -n } else { n })
}

/// True if `term` (spaces around it ignored) is `$NODEID` in any case.
fn is_node_id(term: &str) -> bool {
    term.trim().eq_ignore_ascii_case("$NODEID")
}

/// True if the text uses `$NODEID` anywhere.
#[must_use]
pub fn uses_node_id(s: &str) -> bool {
    s.split('+').any(is_node_id)
}

/// Evaluates a number or a `$NODEID` sum (`$NODEID+0x180`, `0x180+$NODEID`,
/// `$NodeID + 512`) for `node`.
///
/// ```
/// use canopen_codec::eds::eval_int;
/// assert_eq!(eval_int("$NODEID+0x180", Some(10)), Ok(0x18A));
/// assert_eq!(eval_int("1280 + $nodeid", Some(10)), Ok(1290));
/// assert!(eval_int("$NODEID+1", None).is_err());
/// ```
pub fn eval_int(s: &str, node: Option<u8>) -> Result<i128, ValueError> {
    let mut sum: i128 = 0;
    for term in s.split('+') {
        let n = if is_node_id(term) {
            i128::from(node.ok_or(ValueError::NoNodeId)?)
        } else {
            parse_int(term).ok_or(ValueError::NotANumber)?
        };
        sum = sum.checked_add(n).ok_or(ValueError::OutOfRange)?;
    }
    // "-5" splits into one term; "+5" into an empty one and fails above.
    Ok(sum)
}

/// Reads hex bytes, spaces allowed between them (`"01 02 ab"`, `"0102AB"`).
fn parse_hex_bytes(s: &str) -> Option<Vec<u8>> {
    let digits: Vec<u32> = s
        .chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| c.to_digit(16))
        .collect::<Option<_>>()?;
    let pairs = digits.chunks_exact(2);
    if !pairs.remainder().is_empty() {
        return None;
    }
    // Each pair is two hex digits, so the value is at most 0xFF.
    pairs
        .map(|p| match p {
            [hi, lo] => u8::try_from(hi * 16 + lo).ok(),
            _ => None,
        })
        .collect()
}

/// Encodes a value given as text (`DefaultValue`, `ParameterValue`) into
/// the little-endian bytes of `data_type` (CiA 301, section 7.1 "Data type
/// definitions"), resolving `$NODEID` with `node`.
///
/// Integers take the type's size in two's complement; a hex pattern that
/// fills the type (`0xFFFFFFFF` for an INTEGER32) is read as its bits. An
/// empty value is zero (an empty string for the variable-size types).
/// VISIBLE_STRING is the text's bytes; UNICODE_STRING is UTF-16LE;
/// OCTET_STRING and DOMAIN are hex bytes (`"01 02"`), or the text's bytes
/// when the text is not hex.
///
/// ```
/// use canopen_codec::eds::{encode_value, DataType};
/// assert_eq!(encode_value(DataType::Unsigned32, "$NODEID+0x180", Some(10)).unwrap(), [0x8A, 1, 0, 0]);
/// assert_eq!(encode_value(DataType::Integer16, "-2", None).unwrap(), [0xFE, 0xFF]);
/// assert_eq!(encode_value(DataType::Unsigned8, "", None).unwrap(), [0]);
/// ```
pub fn encode_value(
    data_type: DataType,
    text: &str,
    node: Option<u8>,
) -> Result<Vec<u8>, ValueError> {
    let text = text.trim();
    match data_type {
        DataType::VisibleString => return Ok(text.as_bytes().to_vec()),
        DataType::UnicodeString => {
            return Ok(text.encode_utf16().flat_map(u16::to_le_bytes).collect());
        }
        DataType::OctetString | DataType::Domain => {
            return Ok(parse_hex_bytes(text).unwrap_or_else(|| text.as_bytes().to_vec()));
        }
        _ => {}
    }
    let size = data_type
        .fixed_size()
        .ok_or(ValueError::UnsupportedType(u16::from(data_type)))?;
    if text.is_empty() {
        return Ok(alloc::vec![0; size]);
    }
    let bits: u64 = match data_type {
        DataType::Real32 if parse_int(text).is_none() => {
            let f: f32 = text.parse().map_err(|_| ValueError::NotANumber)?;
            u64::from(f.to_bits())
        }
        DataType::Real64 if parse_int(text).is_none() => {
            let f: f64 = text.parse().map_err(|_| ValueError::NotANumber)?;
            f.to_bits()
        }
        _ => {
            let n = eval_int(text, node)?;
            let width =
                u32::try_from(size.saturating_mul(8)).map_err(|_| ValueError::OutOfRange)?;
            let unsigned_max = 1i128 << width; // width <= 64
            let min = if data_type.is_signed() {
                -(unsigned_max >> 1)
            } else {
                0
            };
            if n < min || n >= unsigned_max {
                return Err(ValueError::OutOfRange);
            }
            // Two's complement of a value within 64 bits.
            n.rem_euclid(unsigned_max) as u64
        }
    };
    Ok(bits.to_le_bytes().get(..size).unwrap_or(&[]).to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers() {
        assert_eq!(parse_int("0X1f"), Some(31));
        assert_eq!(parse_int("007"), Some(7));
        assert_eq!(parse_int("-0x10"), Some(-16));
        assert_eq!(parse_int("0x-10"), Some(-16));
        assert_eq!(parse_int("-0x-10"), None);
        assert_eq!(parse_int("0x-"), None);
        assert_eq!(parse_int(""), None);
        assert_eq!(parse_int("-"), None);
        assert_eq!(parse_int("12a"), None);
        assert_eq!(parse_int("0xFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFF"), None);
    }

    #[test]
    fn node_id_sums() {
        assert_eq!(eval_int("$NODEID+0x180", Some(10)), Ok(0x18A));
        assert_eq!(eval_int("0x180+$NODEID", Some(10)), Ok(0x18A));
        assert_eq!(eval_int("$NodeID + 0x200", Some(10)), Ok(0x20A));
        assert_eq!(eval_int("$nodeid", Some(3)), Ok(3));
        assert_eq!(eval_int("$NODEID+", Some(3)), Err(ValueError::NotANumber));
        assert_eq!(eval_int("$NODEID+1", None), Err(ValueError::NoNodeId));
        assert!(uses_node_id("0x80 + $NodeId"));
        assert!(!uses_node_id("0x80"));
    }

    #[test]
    fn encodings() {
        let enc = |t, s| encode_value(t, s, Some(10));
        assert_eq!(
            enc(DataType::Integer32, "0xFFFFFFFF"),
            Ok(alloc::vec![0xFF; 4])
        );
        assert_eq!(
            enc(DataType::Integer32, "0x1FFFFFFFF"),
            Err(ValueError::OutOfRange)
        );
        assert_eq!(enc(DataType::Integer8, "-129"), Err(ValueError::OutOfRange));
        assert_eq!(enc(DataType::Unsigned8, "-1"), Err(ValueError::OutOfRange));
        assert_eq!(
            enc(DataType::Unsigned24, "0x123456"),
            Ok(alloc::vec![0x56, 0x34, 0x12])
        );
        assert_eq!(
            enc(DataType::Unsigned64, "0xFFFFFFFFFFFFFFFF"),
            Ok(alloc::vec![0xFF; 8])
        );
        assert_eq!(
            enc(DataType::Real32, "5.2"),
            Ok(5.2f32.to_le_bytes().to_vec())
        );
        assert_eq!(enc(DataType::Real64, "1"), Ok(1u64.to_le_bytes().to_vec()));
        assert_eq!(enc(DataType::VisibleString, "IC650"), Ok(b"IC650".to_vec()));
        assert_eq!(enc(DataType::UnicodeString, "A"), Ok(alloc::vec![0x41, 0]));
        assert_eq!(
            enc(DataType::OctetString, "01 02 aB"),
            Ok(alloc::vec![1, 2, 0xAB])
        );
        assert_eq!(enc(DataType::Domain, "xyz"), Ok(b"xyz".to_vec()));
        assert_eq!(enc(DataType::Domain, ""), Ok(alloc::vec![]));
        assert_eq!(enc(DataType::Unsigned16, ""), Ok(alloc::vec![0, 0]));
        assert_eq!(
            enc(DataType::Other(0x40), "1"),
            Err(ValueError::UnsupportedType(0x40))
        );
        assert_eq!(enc(DataType::Real32, "abc"), Err(ValueError::NotANumber));
    }
}
