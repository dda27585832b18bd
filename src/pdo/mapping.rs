//! PDO mapping entries and mappings (objects 1600h-1603h / 1A00h-1A03h),
//! CiA 301.
//!
//! A mapping entry is an Unsigned32: bits 31-16 index, bits 15-8 sub-index,
//! bits 7-0 length in bits. A mapping holds at most 8 entries and at most 64
//! bits in total; fields are packed little-endian across the whole payload,
//! in entry order, without byte alignment.

use core::fmt;

use crate::abort::AbortCode;
use crate::od::ObjectDictionary;

/// Most entries in one mapping.
pub const MAX_ENTRIES: usize = 8;
/// Most bits in one mapping (the 8-byte CAN payload).
pub const MAX_BITS: u32 = 64;

/// One mapping entry: which object goes into the PDO, and how many bits.
///
/// ```
/// use canopen_codec::pdo::MappingEntry;
/// let e = MappingEntry::from_u32(0x6010_0010);
/// assert_eq!((e.index, e.sub, e.bits), (0x6010, 0, 16));
/// assert_eq!(e.to_u32(), 0x6010_0010);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct MappingEntry {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// Length in bits (1..=64 in a valid mapping; 0 is an empty entry).
    pub bits: u8,
}

impl MappingEntry {
    /// An entry.
    #[must_use]
    pub const fn new(index: u16, sub: u8, bits: u8) -> Self {
        MappingEntry { index, sub, bits }
    }

    /// From the Unsigned32 of a mapping sub-index.
    #[must_use]
    pub const fn from_u32(raw: u32) -> Self {
        MappingEntry {
            index: (raw >> 16) as u16,
            sub: (raw >> 8) as u8,
            bits: raw as u8,
        }
    }

    /// The Unsigned32 of a mapping sub-index.
    #[must_use]
    pub const fn to_u32(self) -> u32 {
        (self.index as u32) << 16 | (self.sub as u32) << 8 | self.bits as u32
    }

    /// True for the all-zero (uninitialised) entry.
    #[must_use]
    pub const fn is_empty(self) -> bool {
        self.to_u32() == 0
    }

    /// True for a dummy entry: an index below 20h names a standard data
    /// type, whose bits are skipped (receive) or zero (transmit).
    #[must_use]
    pub const fn is_dummy(self) -> bool {
        self.index >= 0x0001 && self.index <= 0x001F
    }

    /// The width of a standard data type used as a dummy entry, if the index
    /// names one (CiA 301 table of static data types).
    #[must_use]
    pub const fn dummy_type_bits(index: u16) -> Option<u8> {
        Some(match index {
            0x0001 => 1,                    // BOOLEAN
            0x0002 | 0x0005 => 8,           // INTEGER8, UNSIGNED8
            0x0003 | 0x0006 => 16,          // INTEGER16, UNSIGNED16
            0x0010 | 0x0016 => 24,          // INTEGER24, UNSIGNED24
            0x0004 | 0x0007 | 0x0008 => 32, // INTEGER32, UNSIGNED32, REAL32
            0x0012 | 0x0018 => 40,          // INTEGER40, UNSIGNED40
            0x0013 | 0x0019 => 48,          // INTEGER48, UNSIGNED48
            0x0014 | 0x001A => 56,          // INTEGER56, UNSIGNED56
            0x0011 | 0x0015 | 0x001B => 64, // REAL64, INTEGER64, UNSIGNED64
            _ => return None,
        })
    }

    /// Checks this entry against a dictionary: the object must exist, be
    /// PDO-mappable and hold at least `bits` bits. Dummy entries must name a
    /// standard data type of exactly `bits` bits. The empty entry is
    /// [`MappingError::EmptyEntry`].
    #[inline(never)]
    pub fn check<D: ObjectDictionary + ?Sized>(self, od: &D) -> Result<(), MappingError> {
        if self.is_empty() || self.bits == 0 {
            return Err(MappingError::EmptyEntry { entry: self });
        }
        if self.is_dummy() {
            return match Self::dummy_type_bits(self.index) {
                Some(bits) if bits == self.bits => Ok(()),
                _ => Err(MappingError::NotMappable { entry: self }),
            };
        }
        let info = od.info(self.index, self.sub).map_err(|code| match code {
            AbortCode::SubIndexDoesNotExist => MappingError::SubIndexMissing { entry: self },
            AbortCode::ObjectDoesNotExist => MappingError::ObjectMissing { entry: self },
            other => MappingError::Dictionary {
                entry: self,
                code: other,
            },
        })?;
        if !info.pdo_mappable {
            return Err(MappingError::NotMappable { entry: self });
        }
        if u32::from(self.bits) > (info.len as u32).saturating_mul(8) {
            return Err(MappingError::LongerThanObject {
                entry: self,
                object_bits: (info.len as u32).saturating_mul(8),
            });
        }
        Ok(())
    }

    /// [`check`](Self::check) as the abort code an SDO server answers with
    /// (`check(od).map_err(MappingError::abort_code)`), without building
    /// the [`MappingError`]: the device's mapping writes.
    #[inline(never)]
    pub(crate) fn check_abort<D: ObjectDictionary + ?Sized>(self, od: &D) -> Result<(), AbortCode> {
        if self.is_empty() || self.bits == 0 {
            return Err(AbortCode::InvalidValue);
        }
        let fits = if self.is_dummy() {
            Self::dummy_type_bits(self.index) == Some(self.bits)
        } else {
            // The dictionary's codes are the answer as they are.
            let info = od.info(self.index, self.sub)?;
            info.pdo_mappable && u32::from(self.bits) <= (info.len as u32).saturating_mul(8)
        };
        if fits {
            Ok(())
        } else {
            Err(AbortCode::ObjectCannotBeMapped)
        }
    }
}

impl fmt::Display for MappingEntry {
    /// `6010h:00/16`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:04X}h:{:02X}/{}", self.index, self.sub, self.bits)
    }
}

/// Why a mapping is not valid. Converts to the CiA 301 abort code an SDO
/// server answers with ([`MappingError::abort_code`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum MappingError {
    /// More than 8 entries (06040042h).
    #[error("{got} mapping entries, at most 8")]
    TooManyEntries {
        /// Entries asked for.
        got: usize,
    },
    /// More than 64 bits in total (06040042h).
    #[error("mapping of {got} bits, at most 64")]
    TooManyBits {
        /// Total bits.
        got: u32,
    },
    /// A counted entry is zero / has no bits (06090030h: the value written
    /// to sub-index 0 is invalid given the entries).
    #[error("mapping entry {entry} is empty")]
    EmptyEntry {
        /// The entry.
        entry: MappingEntry,
    },
    /// The object may not be mapped, or a dummy entry names no standard
    /// type of that width (06040041h).
    #[error("object {entry} cannot be mapped")]
    NotMappable {
        /// The entry.
        entry: MappingEntry,
    },
    /// The entry maps more bits than the object holds (06040041h).
    #[error("entry {entry} maps more than the object's {object_bits} bits")]
    LongerThanObject {
        /// The entry.
        entry: MappingEntry,
        /// The object's size in bits.
        object_bits: u32,
    },
    /// The object does not exist (06020000h).
    #[error("object {entry} does not exist")]
    ObjectMissing {
        /// The entry.
        entry: MappingEntry,
    },
    /// The sub-index does not exist (06090011h).
    #[error("sub-index of {entry} does not exist")]
    SubIndexMissing {
        /// The entry.
        entry: MappingEntry,
    },
    /// The dictionary refused to describe the object with another code.
    #[error("object {entry}: {code}")]
    Dictionary {
        /// The entry.
        entry: MappingEntry,
        /// The dictionary's code.
        code: AbortCode,
    },
}

impl MappingError {
    /// The SDO abort code for this error.
    #[must_use]
    pub const fn abort_code(self) -> AbortCode {
        match self {
            MappingError::TooManyEntries { .. } | MappingError::TooManyBits { .. } => {
                AbortCode::PdoLengthExceeded
            }
            MappingError::EmptyEntry { .. } => AbortCode::InvalidValue,
            MappingError::NotMappable { .. } | MappingError::LongerThanObject { .. } => {
                AbortCode::ObjectCannotBeMapped
            }
            MappingError::ObjectMissing { .. } => AbortCode::ObjectDoesNotExist,
            MappingError::SubIndexMissing { .. } => AbortCode::SubIndexDoesNotExist,
            MappingError::Dictionary { code, .. } => code,
        }
    }
}

impl From<MappingError> for AbortCode {
    fn from(e: MappingError) -> Self {
        e.abort_code()
    }
}

/// A PDO mapping: up to 8 non-empty entries, at most 64 bits in total.
/// Built and validated without allocation.
///
/// ```
/// use canopen_codec::pdo::{MappingEntry, PdoMapping};
/// // Delta-Q charger TPDO 3: 2002h/16, 2100h/16, 2006h/16.
/// let m = PdoMapping::new(&[
///     MappingEntry::new(0x2002, 0, 16),
///     MappingEntry::new(0x2100, 0, 16),
///     MappingEntry::new(0x2006, 0, 16),
/// ]).unwrap();
/// assert_eq!(m.total_bits(), 48);
/// assert_eq!(m.byte_len(), 6);
/// assert_eq!(m.offsets().collect::<Vec<_>>(), [0, 16, 32]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct PdoMapping {
    entries: [MappingEntry; MAX_ENTRIES],
    count: u8,
}

impl PdoMapping {
    /// The empty mapping (a PDO with no data).
    pub const EMPTY: PdoMapping = PdoMapping {
        entries: [MappingEntry {
            index: 0,
            sub: 0,
            bits: 0,
        }; MAX_ENTRIES],
        count: 0,
    };

    /// Builds a mapping; checks the count, the total length and that no
    /// entry is empty. (Object checks need a dictionary: [`Self::check`].)
    pub fn new(entries: &[MappingEntry]) -> Result<Self, MappingError> {
        if entries.len() > MAX_ENTRIES {
            return Err(MappingError::TooManyEntries { got: entries.len() });
        }
        let mut m = PdoMapping::EMPTY;
        let mut total = 0u32;
        for (slot, e) in m.entries.iter_mut().zip(entries) {
            if e.bits == 0 {
                return Err(MappingError::EmptyEntry { entry: *e });
            }
            total += u32::from(e.bits);
            *slot = *e;
        }
        if total > MAX_BITS {
            return Err(MappingError::TooManyBits { got: total });
        }
        m.count = entries.len() as u8;
        Ok(m)
    }

    /// From the Unsigned32 values of sub-indexes 1..=count.
    pub fn from_u32s(raw: &[u32]) -> Result<Self, MappingError> {
        if raw.len() > MAX_ENTRIES {
            return Err(MappingError::TooManyEntries { got: raw.len() });
        }
        let mut entries = [MappingEntry::default(); MAX_ENTRIES];
        for (e, r) in entries.iter_mut().zip(raw) {
            *e = MappingEntry::from_u32(*r);
        }
        Self::new(entries.get(..raw.len()).unwrap_or(&[]))
    }

    /// Checks every entry against a dictionary ([`MappingEntry::check`]).
    pub fn check<D: ObjectDictionary + ?Sized>(&self, od: &D) -> Result<(), MappingError> {
        self.entries().iter().try_for_each(|e| e.check(od))
    }

    /// The entries.
    #[must_use]
    pub fn entries(&self) -> &[MappingEntry] {
        self.entries.get(..usize::from(self.count)).unwrap_or(&[])
    }

    /// All eight entry slots: the entries, then empty ones (0 bits), which
    /// every constructor leaves past the count.
    #[inline]
    pub(crate) const fn slots(&self) -> &[MappingEntry; MAX_ENTRIES] {
        &self.entries
    }

    /// Number of entries (sub-index 0).
    #[must_use]
    pub const fn len(&self) -> usize {
        self.count as usize
    }

    /// True when nothing is mapped.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Total length in bits.
    #[must_use]
    pub fn total_bits(&self) -> u32 {
        self.entries().iter().map(|e| u32::from(e.bits)).sum()
    }

    /// Payload length in bytes the mapping needs (bits rounded up).
    #[must_use]
    pub fn byte_len(&self) -> usize {
        self.total_bits().div_ceil(8) as usize
    }

    /// The bit offset of each entry in the payload.
    pub fn offsets(&self) -> impl Iterator<Item = u32> + '_ {
        self.entries().iter().scan(0u32, |at, e| {
            let here = *at;
            *at += u32::from(e.bits);
            Some(here)
        })
    }
}

/// Reads `bits` (1..=64) bits at bit `offset` of a little-endian payload.
/// Bits past the payload read as zero; `bits` above 64 is treated as 64.
///
/// ```
/// use canopen_codec::pdo::extract_bits;
/// let p = [0xE3, 0x4F];
/// assert_eq!(extract_bits(&p, 0, 4), 0x3);
/// assert_eq!(extract_bits(&p, 4, 8), 0xFE);
/// ```
#[inline]
#[must_use]
pub fn extract_bits(payload: &[u8], offset: u32, bits: u32) -> u64 {
    let mut word = [0u8; 8];
    crate::bytes::copy_payload(&mut word, payload);
    let all = u64::from_le_bytes(word);
    let bits = bits.min(64);
    if offset >= 64 || bits == 0 {
        return 0;
    }
    let shifted = all >> offset;
    if bits == 64 {
        shifted
    } else {
        shifted & ((1u64 << bits) - 1)
    }
}

/// Writes the low `bits` bits of `value` at bit `offset` of an 8-byte
/// little-endian payload; other bits are kept. Bits past 64 are dropped.
#[inline]
pub fn insert_bits(payload: &mut [u8; 8], offset: u32, bits: u32, value: u64) {
    let bits = bits.min(64);
    if offset >= 64 || bits == 0 {
        return;
    }
    let low = if bits == 64 {
        u64::MAX
    } else {
        (1u64 << bits) - 1
    };
    let mask = low << offset;
    let all = u64::from_le_bytes(*payload);
    let merged = (all & !mask) | ((value << offset) & mask);
    *payload = merged.to_le_bytes();
}

/// Sign-extends the low `bits` bits of `raw` (two's complement).
///
/// ```
/// use canopen_codec::pdo::sign_extend;
/// assert_eq!(sign_extend(0x8, 4), -8);
/// assert_eq!(sign_extend(0x7, 4), 7);
/// assert_eq!(sign_extend(1 << 63, 64), i64::MIN);
/// ```
#[inline]
#[must_use]
pub const fn sign_extend(raw: u64, bits: u32) -> i64 {
    if bits == 0 || bits >= 64 {
        return raw as i64;
    }
    let shift = 64 - bits;
    ((raw << shift) as i64) >> shift
}

#[cfg(test)]
#[path = "mapping_tests.rs"]
mod tests;
