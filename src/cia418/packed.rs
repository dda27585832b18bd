//! Packed strings: 6030h battery serial number, 6031h battery ID, 6040h
//! vehicle serial number, 6041h vehicle ID (CiA 418 sections 7.3.5-7.3.8).
//!
//! Each object is an ARRAY of Unsigned32; sub-index 0 holds the number of
//! elements, sub-indexes 1.. hold ISO 646 7-bit characters, four per
//! element, the first character in the least significant byte, zero padded.
//!
//! # Rules this crate applies
//!
//! - **Characters**: any byte `0x01..=0x7F` (ISO 646 is 7-bit; control
//!   characters are not filtered). NUL (0x00) is the padding character.
//! - **Encoding** rejects a NUL inside the string ([`PackedStringError::Nul`])
//!   because it could not be told from padding, any byte `>= 0x80`
//!   ([`PackedStringError::NonAscii`]) and strings longer than the object's
//!   maximum in bytes ([`PackedStringError::TooLong`]; checked first).
//! - **The empty string** encodes to one element of value 0 (sub 0 = 1,
//!   sub 1 = 0): every object needs at least one element.
//! - **Decoding** reads the bytes of elements `1..=count` in order; the text
//!   ends at the first NUL. Every byte after that NUL must be NUL too
//!   ([`PackedStringError::DataAfterNul`]), bytes before it must be 7-bit, and
//!   the text may not exceed the object's maximum (6030h: 10 characters in 3
//!   elements, so bytes 11 and 12 must be padding). Trailing all-zero elements
//!   are accepted (a module may report a fixed element count) and kept, so
//!   [`PackedString::encode_with_count`] rebuilds exactly what was decoded.

use core::fmt;

use super::{BATTERY_ID, BATTERY_SERIAL_NUMBER, VEHICLE_ID, VEHICLE_SERIAL_NUMBER};

/// The four packed-string objects and their limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PackedStringObject {
    /// 6030h: max 10 characters, 1..=3 elements.
    BatterySerialNumber,
    /// 6031h: max 20 characters, 1..=5 elements.
    BatteryId,
    /// 6040h: max 20 characters, 1..=5 elements.
    VehicleSerialNumber,
    /// 6041h: max 20 characters, 1..=5 elements.
    VehicleId,
}

impl PackedStringObject {
    /// All four objects.
    pub const ALL: [PackedStringObject; 4] = [
        Self::BatterySerialNumber,
        Self::BatteryId,
        Self::VehicleSerialNumber,
        Self::VehicleId,
    ];

    /// The object for an index, `None` if it is not a packed-string object.
    #[must_use]
    pub const fn from_index(index: u16) -> Option<Self> {
        match index {
            BATTERY_SERIAL_NUMBER => Some(Self::BatterySerialNumber),
            BATTERY_ID => Some(Self::BatteryId),
            VEHICLE_SERIAL_NUMBER => Some(Self::VehicleSerialNumber),
            VEHICLE_ID => Some(Self::VehicleId),
            _ => None,
        }
    }

    /// The object index.
    #[must_use]
    pub const fn index(self) -> u16 {
        match self {
            Self::BatterySerialNumber => BATTERY_SERIAL_NUMBER,
            Self::BatteryId => BATTERY_ID,
            Self::VehicleSerialNumber => VEHICLE_SERIAL_NUMBER,
            Self::VehicleId => VEHICLE_ID,
        }
    }

    /// Maximum number of characters.
    #[must_use]
    pub const fn max_chars(self) -> usize {
        match self {
            Self::BatterySerialNumber => 10,
            _ => 20,
        }
    }

    /// Maximum number of elements (the largest valid sub-index 0 value).
    #[must_use]
    pub const fn max_elements(self) -> u8 {
        match self {
            Self::BatterySerialNumber => 3,
            _ => 5,
        }
    }
}

/// Why a string did not pack or packed words did not decode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum PackedStringError {
    /// More characters than the object allows (counted in bytes).
    #[error("string too long: at most {max} characters, got {got}")]
    TooLong {
        /// The object's maximum.
        max: usize,
        /// Characters (bytes) present.
        got: usize,
    },
    /// A byte outside 7-bit ISO 646.
    #[error("byte {byte:#04x} at position {position} is not a 7-bit character")]
    NonAscii {
        /// Zero-based position of the byte in the string.
        position: usize,
        /// The byte.
        byte: u8,
    },
    /// A NUL inside a string to encode (NUL is the padding character).
    #[error("NUL at position {position}: NUL is the padding character")]
    Nul {
        /// Zero-based position of the NUL.
        position: usize,
    },
    /// A non-NUL byte after the first NUL (padding) in decoded words.
    #[error("byte {byte:#04x} at position {position} follows the NUL padding")]
    DataAfterNul {
        /// Zero-based position of the byte in the packed bytes.
        position: usize,
        /// The byte.
        byte: u8,
    },
    /// Number of elements (sub-index 0) outside what the object allows, or
    /// too small for the string.
    #[error("element count {got} outside {min}..={max}")]
    BadCount {
        /// Smallest allowed count.
        min: u8,
        /// Largest allowed count.
        max: u8,
        /// Count given.
        got: u8,
    },
    /// Fewer words given than the element count says.
    #[error("missing elements: need {need} words, got {got}")]
    MissingWords {
        /// Words the count asks for.
        need: usize,
        /// Words given.
        got: usize,
    },
}

/// The longest text of any packed-string object (20 characters).
const TEXT_CAPACITY: usize = 20;

/// Decoded text of a packed string: up to 20 7-bit characters, inline.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct PackedText {
    len: u8,
    bytes: [u8; TEXT_CAPACITY],
}

impl PackedText {
    /// The text.
    #[must_use]
    pub fn as_str(&self) -> &str {
        // Only 7-bit bytes are ever stored, so this never fails.
        core::str::from_utf8(self.as_bytes()).unwrap_or("")
    }

    /// The text's bytes.
    #[must_use]
    pub fn as_bytes(&self) -> &[u8] {
        self.bytes.get(..usize::from(self.len)).unwrap_or(&[])
    }

    /// Number of characters.
    #[must_use]
    pub const fn len(&self) -> usize {
        self.len as usize
    }

    /// True for the empty string.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl fmt::Debug for PackedText {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_str(), f)
    }
}

impl fmt::Display for PackedText {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The largest element count of any packed-string object.
const MAX_WORDS: usize = 5;

/// A valid packed string of one object: the element count (sub-index 0) and
/// the elements (sub-indexes 1..=count), no allocation. See the module docs
/// for the rules.
///
/// ```
/// use canopen_codec::cia418::{PackedString, PackedStringObject};
/// let p = PackedString::encode(PackedStringObject::BatterySerialNumber, "BATTERY").unwrap();
/// assert_eq!(p.count(), 2);
/// assert_eq!(p.words(), &[0x5454_4142, 0x0059_5245]);
/// assert_eq!(p.word(1), Some(0x5454_4142));
///
/// let back = PackedString::decode(PackedStringObject::BatterySerialNumber, 2, p.words()).unwrap();
/// assert_eq!(back.text().as_str(), "BATTERY");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PackedString {
    object: PackedStringObject,
    count: u8,
    words: [u32; MAX_WORDS],
}

impl PackedString {
    /// Packs `text` into the fewest elements (at least one).
    pub fn encode(object: PackedStringObject, text: &str) -> Result<Self, PackedStringError> {
        let count = words_needed(text.len());
        Self::encode_with_count(object, text, u8::try_from(count).unwrap_or(u8::MAX))
    }

    /// Packs `text` into exactly `count` elements, padding with zero
    /// elements. `count` must lie between the elements `text` needs (at least
    /// 1) and the object's maximum, else [`PackedStringError::BadCount`].
    pub fn encode_with_count(
        object: PackedStringObject,
        text: &str,
        count: u8,
    ) -> Result<Self, PackedStringError> {
        let bytes = text.as_bytes();
        let max = object.max_chars();
        if bytes.len() > max {
            return Err(PackedStringError::TooLong {
                max,
                got: bytes.len(),
            });
        }
        for (position, &byte) in bytes.iter().enumerate() {
            if byte == 0 {
                return Err(PackedStringError::Nul { position });
            }
            if byte >= 0x80 {
                return Err(PackedStringError::NonAscii { position, byte });
            }
        }
        // At most 5 for a string within the maximum.
        let min = u8::try_from(words_needed(bytes.len())).unwrap_or(u8::MAX);
        let max_elements = object.max_elements();
        if count < min || count > max_elements {
            return Err(PackedStringError::BadCount {
                min,
                max: max_elements,
                got: count,
            });
        }
        let mut words = [0u32; MAX_WORDS];
        for (word, chunk) in words.iter_mut().zip(bytes.chunks(4)) {
            let mut le = [0u8; 4];
            for (dst, &src) in le.iter_mut().zip(chunk) {
                *dst = src;
            }
            *word = u32::from_le_bytes(le);
        }
        Ok(PackedString {
            object,
            count,
            words,
        })
    }

    /// Decodes the element count (sub-index 0) and the elements
    /// (`words[0]` = sub-index 1). `count` must lie in
    /// `1..=object.max_elements()`; `words` must hold at least `count` words
    /// (words past `count` are ignored, so a fixed `[u32; 5]` buffer works).
    pub fn decode(
        object: PackedStringObject,
        count: u8,
        words: &[u32],
    ) -> Result<Self, PackedStringError> {
        let max_elements = object.max_elements();
        if count < 1 || count > max_elements {
            return Err(PackedStringError::BadCount {
                min: 1,
                max: max_elements,
                got: count,
            });
        }
        let n = usize::from(count);
        let Some(given) = words.get(..n) else {
            return Err(PackedStringError::MissingWords {
                need: n,
                got: words.len(),
            });
        };
        let mut kept = [0u32; MAX_WORDS];
        for (dst, &src) in kept.iter_mut().zip(given) {
            *dst = src;
        }
        let packed = PackedString {
            object,
            count,
            words: kept,
        };
        packed.validate()?;
        Ok(packed)
    }

    /// Checks the packed bytes against the decoding rules.
    fn validate(&self) -> Result<(), PackedStringError> {
        let max = self.object.max_chars();
        let mut text_len = None;
        for (position, byte) in self.bytes().enumerate() {
            match (text_len, byte) {
                (None, 0) => text_len = Some(position),
                (None, b) if b >= 0x80 => {
                    return Err(PackedStringError::NonAscii { position, byte: b })
                }
                (None, _) if position >= max => {
                    return Err(PackedStringError::TooLong {
                        max,
                        got: self.raw_text_len(),
                    })
                }
                (None, _) | (Some(_), 0) => {}
                (Some(_), b) => return Err(PackedStringError::DataAfterNul { position, byte: b }),
            }
        }
        Ok(())
    }

    /// Length up to the first NUL (or of all bytes), for error reports.
    fn raw_text_len(&self) -> usize {
        self.bytes().take_while(|&b| b != 0).count()
    }

    /// The packed bytes of elements `1..=count`, in order.
    fn bytes(&self) -> impl Iterator<Item = u8> + '_ {
        self.words().iter().flat_map(|w| w.to_le_bytes())
    }

    /// The object this string belongs to.
    #[must_use]
    pub const fn object(&self) -> PackedStringObject {
        self.object
    }

    /// The element count, the value of sub-index 0.
    #[must_use]
    pub const fn count(&self) -> u8 {
        self.count
    }

    /// The elements, sub-indexes `1..=count` (`words()[0]` is sub-index 1).
    #[must_use]
    pub fn words(&self) -> &[u32] {
        self.words
            .get(..usize::from(self.count))
            .unwrap_or(&self.words)
    }

    /// The value of sub-index `sub` (`1..=count`) as the Unsigned32 element;
    /// `None` otherwise (sub-index 0 is [`PackedString::count`]). On the wire
    /// it is `word.to_le_bytes()`.
    #[must_use]
    pub fn word(&self, sub: u8) -> Option<u32> {
        let i = usize::from(sub).checked_sub(1)?;
        self.words().get(i).copied()
    }

    /// The text (up to the first NUL).
    #[must_use]
    pub fn text(&self) -> PackedText {
        let mut out = PackedText::default();
        for (dst, b) in out
            .bytes
            .iter_mut()
            .zip(self.bytes().take_while(|&b| b != 0))
        {
            *dst = b;
            out.len += 1;
        }
        out
    }
}

/// Elements needed for `len` characters: at least one.
const fn words_needed(len: usize) -> usize {
    if len == 0 {
        1
    } else {
        len.div_ceil(4)
    }
}
