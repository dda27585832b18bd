//! Bit-exact PDO packing and unpacking, CiA 301.
//!
//! The mapped fields sit in entry order, little-endian across the whole
//! payload: entry 0 starts at bit 0 of byte 0, each next entry at the bit
//! after the previous one, with no byte alignment; a field of `n` bits holds
//! the low `n` bits of its value, least significant bit first. The payload
//! is [`PdoMapping::byte_len`] bytes; bits past [`PdoMapping::total_bits`]
//! are zero on transmit.
//!
//! Receiving ([`PdoMapping::unpack`]): a payload shorter than the mapping is
//! not processed ([`UnpackError::TooShort`], EMCY 8210h); a longer one is
//! decoded and flagged ([`Unpacked::longer_than_mapping`], EMCY 8220h may be
//! raised). Decoding never fails otherwise: every bit pattern is a value.
//!
//! ```
//! use canopen_codec::pdo::{FieldKind, MappingEntry, PdoMapping, Value};
//!
//! // Vector P1: INTEGER16, UNSIGNED8 in 4 bits, INTEGER8 in 4 bits,
//! // INTEGER32, two BOOLEANs (58 bits).
//! let m = PdoMapping::new(&[
//!     MappingEntry::new(0x2000, 1, 16),
//!     MappingEntry::new(0x2000, 2, 4),
//!     MappingEntry::new(0x2000, 3, 4),
//!     MappingEntry::new(0x2000, 4, 32),
//!     MappingEntry::new(0x2000, 5, 1),
//!     MappingEntry::new(0x2000, 6, 1),
//! ])?;
//! let values = [
//!     Value::Signed(-3),
//!     Value::Unsigned(0xF),
//!     Value::Signed(-2),
//!     Value::Signed(0x0102_0304),
//!     Value::Boolean(false),
//!     Value::Boolean(true),
//! ];
//! let payload = m.pack(&values)?;
//! assert_eq!(payload.as_slice(), [0xFD, 0xFF, 0xEF, 0x04, 0x03, 0x02, 0x01, 0x02]);
//!
//! let u = m.unpack(payload.as_slice())?;
//! assert_eq!(u.signed(0), Some(-3));
//! assert_eq!(u.raw(1), Some(0xF));
//! assert_eq!(u.value(2, FieldKind::Signed), Ok(Value::Signed(-2)));
//! assert_eq!(u.boolean(5), Some(true));
//! assert!(!u.longer_than_mapping());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use core::fmt;

use crate::bytes::{copy_payload, Payload};
use crate::emcy::ErrorCode;

use super::mapping::{sign_extend, MappingEntry, PdoMapping, MAX_ENTRIES};

/// How to read a mapped field (a mapping carries widths, not types).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum FieldKind {
    /// UNSIGNEDn: the bits as they are.
    Unsigned,
    /// INTEGERn: two's complement, sign-extended from the field's width.
    Signed,
    /// BOOLEAN: zero is false, anything else true.
    Boolean,
    /// REAL32: IEEE 754 single; only a 32-bit field.
    Real32,
    /// REAL64: IEEE 754 double; only a 64-bit field.
    Real64,
}

impl FieldKind {
    /// True when a field of `bits` bits can hold this kind: any width for
    /// the integers and BOOLEAN, exactly 32 for REAL32 and 64 for REAL64.
    #[inline]
    #[must_use]
    pub const fn fits_width(self, bits: u8) -> bool {
        match self {
            FieldKind::Unsigned | FieldKind::Signed | FieldKind::Boolean => true,
            FieldKind::Real32 => bits == 32,
            FieldKind::Real64 => bits == 64,
        }
    }
}

impl fmt::Display for FieldKind {
    /// The CiA 301 data type family: `UNSIGNED`, `INTEGER`, `BOOLEAN`,
    /// `REAL32`, `REAL64`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FieldKind::Unsigned => "UNSIGNED",
            FieldKind::Signed => "INTEGER",
            FieldKind::Boolean => "BOOLEAN",
            FieldKind::Real32 => "REAL32",
            FieldKind::Real64 => "REAL64",
        })
    }
}

/// A typed value of one mapped field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// UNSIGNEDn; must fit in the field's bits.
    Unsigned(u64),
    /// INTEGERn; must fit in the field's bits as two's complement (-8..=7
    /// in 4 bits).
    Signed(i64),
    /// BOOLEAN; packs as 1 or 0 (in a field of any width).
    Boolean(bool),
    /// REAL32; only in a 32-bit field.
    Real32(f32),
    /// REAL64; only in a 64-bit field.
    Real64(f64),
}

impl Value {
    /// The kind of this value.
    #[inline]
    #[must_use]
    pub const fn kind(self) -> FieldKind {
        match self {
            Value::Unsigned(_) => FieldKind::Unsigned,
            Value::Signed(_) => FieldKind::Signed,
            Value::Boolean(_) => FieldKind::Boolean,
            Value::Real32(_) => FieldKind::Real32,
            Value::Real64(_) => FieldKind::Real64,
        }
    }

    /// The field bits of this value in a field of `bits` (1..=64) bits;
    /// `entry` names the field in the error.
    #[inline]
    fn to_raw(self, entry: usize, bits: u8) -> Result<u64, PackError> {
        let mask = low_mask(bits);
        let too_wide = PackError::ValueTooWide { entry, bits };
        match self {
            Value::Unsigned(v) if v & !mask == 0 => Ok(v),
            Value::Signed(v) if sign_extend(v as u64 & mask, u32::from(bits)) == v => {
                Ok(v as u64 & mask)
            }
            Value::Unsigned(_) | Value::Signed(_) => Err(too_wide),
            // A valid mapping has no 0-bit field: 1 always fits.
            Value::Boolean(b) => Ok(u64::from(b)),
            Value::Real32(f) if bits == 32 => Ok(u64::from(f.to_bits())),
            Value::Real64(f) if bits == 64 => Ok(f.to_bits()),
            Value::Real32(_) | Value::Real64(_) => Err(PackError::KindWidth {
                entry,
                kind: self.kind(),
                bits,
            }),
        }
    }
}

/// The low `bits` bits set (all 64 for 64 or more).
#[inline]
const fn low_mask(bits: u8) -> u64 {
    if bits >= 64 {
        u64::MAX
    } else {
        (1u64 << bits) - 1
    }
}

/// Why values did not pack. The `entry` is the position in the mapping
/// (0-based; sub-index `entry + 1` of the mapping object).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum PackError {
    /// Not one value per mapping entry.
    #[error("{values} values for a mapping of {entries} entries")]
    CountMismatch {
        /// Entries in the mapping.
        entries: usize,
        /// Values given.
        values: usize,
    },
    /// The value does not fit its field: an unsigned value of more than
    /// `bits` bits, or a signed one outside the `bits`-bit two's complement
    /// range.
    #[error("value of entry {entry} does not fit in {bits} bits")]
    ValueTooWide {
        /// Position of the entry.
        entry: usize,
        /// The field's width.
        bits: u8,
    },
    /// A REAL32 outside a 32-bit field or a REAL64 outside a 64-bit one.
    #[error("{kind} value for entry {entry} of {bits} bits")]
    KindWidth {
        /// Position of the entry.
        entry: usize,
        /// The value's kind.
        kind: FieldKind,
        /// The field's width.
        bits: u8,
    },
}

/// Why a received PDO was not processed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum UnpackError {
    /// The payload is shorter than the mapping: CiA 301 says the PDO is not
    /// processed ([`UnpackError::emcy_code`] 8210h).
    #[error("PDO of {got} bytes, the mapping needs {need}")]
    TooShort {
        /// Bytes the mapping needs ([`PdoMapping::byte_len`]).
        need: usize,
        /// Bytes received.
        got: usize,
    },
}

impl UnpackError {
    /// The EMCY error code a device reports: 8210h "PDO not processed due
    /// to length error".
    #[inline]
    #[must_use]
    pub const fn emcy_code(self) -> ErrorCode {
        match self {
            UnpackError::TooShort { .. } => ErrorCode::PDO_LENGTH,
        }
    }
}

/// Why a field could not be read as asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum FieldError {
    /// No entry at this position.
    #[error("no entry {entry} in a mapping of {count} entries")]
    NoSuchEntry {
        /// Position asked for.
        entry: usize,
        /// Entries in the mapping.
        count: usize,
    },
    /// REAL32 asked of a field that is not 32 bits, or REAL64 of one that
    /// is not 64.
    #[error("entry {entry} of {bits} bits cannot be read as {kind}")]
    KindWidth {
        /// Position of the entry.
        entry: usize,
        /// The kind asked for.
        kind: FieldKind,
        /// The field's width.
        bits: u8,
    },
}

/// A decoded PDO: the raw bits of every mapped field, with typed views.
///
/// Holds no copy of the payload and allocates nothing: `[u64; 8]` and the
/// borrowed mapping. Positions are 0-based entry numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Unpacked<'m> {
    mapping: &'m PdoMapping,
    raws: [u64; MAX_ENTRIES],
    longer: bool,
}

impl<'m> Unpacked<'m> {
    /// The mapping this payload was decoded with.
    #[inline]
    #[must_use]
    pub const fn mapping(&self) -> &'m PdoMapping {
        self.mapping
    }

    /// Number of fields (the mapping's entries).
    #[inline]
    #[must_use]
    pub const fn len(&self) -> usize {
        self.mapping.len()
    }

    /// True when the mapping is empty.
    #[inline]
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.mapping.is_empty()
    }

    /// The raw field bits, one per entry, zero-extended to `u64`. Dummy
    /// entries keep the bits received, so [`PdoMapping::pack_raw`] of these
    /// gives the payload back.
    #[inline]
    #[must_use]
    pub fn raws(&self) -> &[u64] {
        self.raws.get(..self.len()).unwrap_or(&[])
    }

    /// The raw bits of field `i`, zero-extended.
    #[inline]
    #[must_use]
    pub fn raw(&self, i: usize) -> Option<u64> {
        self.raws().get(i).copied()
    }

    /// Field `i` as UNSIGNEDn (the same as [`Self::raw`]).
    #[inline]
    #[must_use]
    pub fn unsigned(&self, i: usize) -> Option<u64> {
        self.raw(i)
    }

    /// Field `i` as INTEGERn: sign-extended from the entry's width.
    #[inline]
    #[must_use]
    pub fn signed(&self, i: usize) -> Option<i64> {
        let raw = self.raw(i)?;
        let bits = self.mapping.entries().get(i)?.bits;
        Some(sign_extend(raw, u32::from(bits)))
    }

    /// Field `i` as BOOLEAN: true when any bit is set.
    #[inline]
    #[must_use]
    pub fn boolean(&self, i: usize) -> Option<bool> {
        Some(self.raw(i)? != 0)
    }

    /// Field `i` read as `kind`.
    #[inline]
    pub fn value(&self, i: usize, kind: FieldKind) -> Result<Value, FieldError> {
        let (Some(entry), Some(&raw)) = (self.mapping.entries().get(i), self.raws.get(i)) else {
            return Err(FieldError::NoSuchEntry {
                entry: i,
                count: self.len(),
            });
        };
        if !kind.fits_width(entry.bits) {
            return Err(FieldError::KindWidth {
                entry: i,
                kind,
                bits: entry.bits,
            });
        }
        Ok(match kind {
            FieldKind::Unsigned => Value::Unsigned(raw),
            FieldKind::Signed => Value::Signed(sign_extend(raw, u32::from(entry.bits))),
            FieldKind::Boolean => Value::Boolean(raw != 0),
            FieldKind::Real32 => Value::Real32(f32::from_bits(raw as u32)),
            FieldKind::Real64 => Value::Real64(f64::from_bits(raw)),
        })
    }

    /// Each entry with its raw field bits, in mapping order.
    #[inline]
    pub fn iter(&self) -> impl Iterator<Item = (MappingEntry, u64)> + '_ {
        self.mapping
            .entries()
            .iter()
            .copied()
            .zip(self.raws().iter().copied())
    }

    /// True when the payload was longer than the mapping needs (decoded
    /// anyway; the extra bytes are ignored).
    #[inline]
    #[must_use]
    pub const fn longer_than_mapping(&self) -> bool {
        self.longer
    }

    /// The EMCY error code a device may raise for this PDO: 8220h "PDO
    /// length exceeded" when it was longer than the mapping, else `None`.
    #[inline]
    #[must_use]
    pub const fn emcy_code(&self) -> Option<ErrorCode> {
        if self.longer {
            Some(ErrorCode::PDO_LENGTH_EXCEEDED)
        } else {
            None
        }
    }
}

impl PdoMapping {
    /// Packs one typed value per entry into the PDO payload
    /// ([`Self::byte_len`] bytes, unused bits zero). A dummy entry's value is
    /// ignored (its kind and width are not checked) and its bits are zero.
    ///
    /// ```
    /// use canopen_codec::pdo::{MappingEntry, PackError, PdoMapping, Value};
    /// let m = PdoMapping::new(&[MappingEntry::new(0x2000, 1, 4), MappingEntry::new(0x0005, 0, 8)])?;
    /// let p = m.pack(&[Value::Signed(-8), Value::Unsigned(0xFF)])?;
    /// assert_eq!(p.as_slice(), [0x08, 0x00]);
    /// assert_eq!(
    ///     m.pack(&[Value::Signed(8), Value::Unsigned(0)]),
    ///     Err(PackError::ValueTooWide { entry: 0, bits: 4 })
    /// );
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn pack(&self, values: &[Value]) -> Result<Payload, PackError> {
        self.pack_fields(values, |i, e, v| {
            if e.is_dummy() {
                Ok(0)
            } else {
                v.to_raw(i, e.bits)
            }
        })
    }

    /// Packs one raw field value per entry, verbatim (dummy entries
    /// included, so `pack_raw(unpack(p).raws())` gives back `p`'s first
    /// [`Self::byte_len`] bytes with the bits past [`Self::total_bits`]
    /// zero). Each value must fit in its entry's bits, as an unsigned
    /// number (a signed value is passed as its low bits).
    #[inline]
    pub fn pack_raw(&self, raws: &[u64]) -> Result<Payload, PackError> {
        self.pack_fields(raws, |i, e, &raw| {
            if raw & !low_mask(e.bits) == 0 {
                Ok(raw)
            } else {
                Err(PackError::ValueTooWide {
                    entry: i,
                    bits: e.bits,
                })
            }
        })
    }

    /// One item per entry, each made the entry's raw field by `field`
    /// (given the entry's position) and placed at its bit offset.
    #[inline]
    fn pack_fields<T>(
        &self,
        items: &[T],
        field: impl Fn(usize, &MappingEntry, &T) -> Result<u64, PackError>,
    ) -> Result<Payload, PackError> {
        let entries = self.entries();
        if items.len() != entries.len() {
            return Err(PackError::CountMismatch {
                entries: entries.len(),
                values: items.len(),
            });
        }
        let mut word = 0u64;
        let mut at = 0u32;
        for (i, (e, item)) in entries.iter().zip(items).enumerate() {
            word |= field(i, e, item)?.checked_shl(at).unwrap_or(0);
            at += u32::from(e.bits);
        }
        Ok(payload(word, at))
    }

    /// Decodes a received PDO payload into the raw bits of every field
    /// (CiA 301: shorter than [`Self::byte_len`] is not processed, EMCY
    /// 8210h; longer is processed and flagged, EMCY 8220h).
    ///
    /// ```
    /// use canopen_codec::emcy::ErrorCode;
    /// use canopen_codec::pdo::{MappingEntry, PdoMapping, UnpackError};
    /// let m = PdoMapping::new(&[MappingEntry::new(0x2002, 0, 16)])?;
    /// let e = m.unpack(&[0x74]).unwrap_err();
    /// assert_eq!(e, UnpackError::TooShort { need: 2, got: 1 });
    /// assert_eq!(e.emcy_code(), ErrorCode::PDO_LENGTH);
    /// let u = m.unpack(&[0x74, 0x13, 0x00])?;
    /// assert_eq!(u.raw(0), Some(0x1374));
    /// assert_eq!(u.emcy_code(), Some(ErrorCode::PDO_LENGTH_EXCEEDED));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn unpack(&self, payload: &[u8]) -> Result<Unpacked<'_>, UnpackError> {
        // One short copy into a zero-padded word; each field is then the low
        // bits of what is left, shifted out in turn (the same bits as
        // `extract_bits(payload, offset, bits)`, without recomputing the
        // offset). The walk also gives the length needed: `byte_len()`
        // without a second pass over the entries.
        //
        // The walk is straight-line code over a fixed number of slots, four
        // (most PDOs map at most four objects) or all eight: a mapping's
        // slots past its count are empty (0 bits: a zero field, nothing
        // shifted, no length), so walking them changes nothing.
        let word = le_word(payload);
        let mut raws = [0u64; MAX_ENTRIES];
        let at = if self.len() <= 4 {
            walk(word, raws.iter_mut().take(4), self.slots())
        } else {
            walk(word, raws.iter_mut(), self.slots())
        };
        let need = at.div_ceil(8) as usize;
        if payload.len() < need {
            return Err(UnpackError::TooShort {
                need,
                got: payload.len(),
            });
        }
        Ok(Unpacked {
            mapping: self,
            raws,
            longer: payload.len() > need,
        })
    }
}

/// Splits `word` into the fields of `slots`, one per slot of `raws` (as
/// many as `raws` yields), from bit 0 up; returns the bits taken.
#[inline(always)]
fn walk<'r>(
    word: u64,
    raws: impl Iterator<Item = &'r mut u64>,
    slots: &[MappingEntry; MAX_ENTRIES],
) -> u32 {
    let mut rest = word;
    let mut at = 0u32;
    for (raw, e) in raws.zip(slots) {
        *raw = rest & low_mask(e.bits);
        rest = rest.checked_shr(u32::from(e.bits)).unwrap_or(0);
        at += u32::from(e.bits);
    }
    at
}

/// The first 8 bytes of `payload` as a little-endian word, zero past its
/// end, without a byte-wise copy: 4..=8 bytes (every PDO worth unpacking)
/// are two overlapping loads.
#[inline]
fn le_word(payload: &[u8]) -> u64 {
    match *payload {
        [a, b, c, d, e, f, g, h, ..] => u64::from_le_bytes([a, b, c, d, e, f, g, h]),
        [a, b, c, d, ..] => {
            let n = payload.len();
            let lo = u32::from_le_bytes([a, b, c, d]);
            let hi = match payload.get(n.saturating_sub(4)..) {
                Some(&[e, f, g, h]) => u32::from_le_bytes([e, f, g, h]),
                _ => 0,
            };
            // Bytes n-4..n at their place; the overlap repeats bytes of `lo`.
            u64::from(lo) | u64::from(hi) << (8 * (n - 4))
        }
        _ => {
            let mut word = [0u8; 8];
            copy_payload(&mut word, payload);
            u64::from_le_bytes(word)
        }
    }
}

/// The payload of `bits` packed bits (at most 64: the mapping's invariant).
#[inline]
fn payload(word: u64, bits: u32) -> Payload {
    let word = word.to_le_bytes();
    let len = (bits.div_ceil(8) as usize).min(word.len());
    Payload::new(word.get(..len).unwrap_or(&word)).unwrap_or_default()
}

#[cfg(test)]
#[path = "pack_tests.rs"]
mod tests;
