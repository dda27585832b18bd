//! Moving PDO data between a payload and an object dictionary: building a
//! TPDO's payload from the mapped objects' current values, and writing a
//! received RPDO's fields into the mapped objects.

use super::mapping::{extract_bits, MappingEntry, PdoMapping};
use crate::abort::AbortCode;
use crate::bytes::Payload;
use crate::emcy::ErrorCode;
use crate::od::ObjectDictionary;

/// Why a received RPDO was not (fully) processed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum RpdoError {
    /// The payload is shorter than the mapping: not processed (EMCY 8210h).
    #[error("RPDO of {got} bytes is shorter than its {need}-byte mapping")]
    TooShort {
        /// Bytes the mapping needs.
        need: usize,
        /// Bytes received.
        got: usize,
    },
    /// The dictionary refused a mapped object's value.
    #[error("RPDO field {index:04X}h:{sub:02X} refused: {code}")]
    Refused {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// The dictionary's code.
        code: AbortCode,
    },
}

impl RpdoError {
    /// The EMCY code a device raises for this error (8210h for a short PDO;
    /// none for a refused value).
    #[must_use]
    pub const fn emcy_code(&self) -> Option<ErrorCode> {
        match self {
            RpdoError::TooShort { .. } => Some(ErrorCode::PDO_LENGTH),
            RpdoError::Refused { .. } => None,
        }
    }
}

/// Builds a TPDO payload from the mapped objects' current values (each
/// object read little-endian, its low `bits` bits packed). Dummy entries
/// give zero bits.
pub fn read_mapped<D: ObjectDictionary + ?Sized>(
    mapping: &PdoMapping,
    od: &mut D,
) -> Result<Payload, AbortCode> {
    let (word, len) = read_entries(mapping.entries(), od)?;
    Ok(Payload::from_le_word(word, usize::from(len)))
}

/// [`read_mapped`] over the entries of a valid mapping: the payload as a
/// little-endian word and its length in bytes.
pub(crate) fn read_entries<D: ObjectDictionary + ?Sized>(
    entries: &[MappingEntry],
    od: &mut D,
) -> Result<(u64, u8), AbortCode> {
    let mut payload = 0u64;
    let mut offset = 0u32;
    for entry in entries {
        let bits = u32::from(entry.bits);
        if !entry.is_dummy() && offset < 64 {
            let mut buf = [0u8; 8];
            let n = od.read(
                entry.index,
                entry.sub,
                0,
                buf.get_mut(..field_len(bits)).unwrap_or(&mut []),
            )?;
            // The low `bits` bits of what the dictionary gave (`n` bytes);
            // the fields do not overlap, so an or places each.
            let keep = bits.min(8 * n.min(8) as u32);
            let mask = if keep >= 64 {
                u64::MAX
            } else {
                (1 << keep) - 1
            };
            payload |= (u64::from_le_bytes(buf) & mask) << offset;
        }
        offset += bits;
    }
    Ok((payload, field_len(offset) as u8))
}

/// The bytes `bits` take, rounded up (at most 8 in a valid mapping; a
/// longer slice request is refused by `get`).
#[inline]
fn field_len(bits: u32) -> usize {
    // Not div_ceil: its overflow-safe form costs 48 bytes on Cortex-M,
    // and `bits` (a sum of at most eight u8 widths) is far from overflow.
    (bits as usize + 7) >> 3
}

/// Writes a received RPDO's fields into the mapped objects. A payload
/// shorter than the mapping is refused whole ([`RpdoError::TooShort`],
/// EMCY 8210h); a longer one is processed and `Ok(true)` says so (CiA 301
/// allows EMCY 8220h). Dummy entries are skipped. Each field is written as
/// `ceil(bits / 8)` little-endian bytes.
pub fn write_mapped<D: ObjectDictionary + ?Sized>(
    mapping: &PdoMapping,
    payload: &[u8],
    od: &mut D,
) -> Result<bool, RpdoError> {
    write_entries(mapping.entries(), payload, od)
}

/// Whether the mapped objects already hold the fields of `payload`: each
/// one reads back as the bits [`write_entries`] would write, so writing
/// it would change no value (the device core reads its TPDOs' objects
/// again after an RPDO only when one did not). A payload shorter than the
/// mapping, or an object that cannot be read, is `false`.
#[cfg(feature = "alloc")]
pub(crate) fn holds_entries<D: ObjectDictionary + ?Sized>(
    entries: &[MappingEntry],
    payload: &[u8],
    od: &mut D,
) -> bool {
    // The bits the fields take (dummies and what follows the mapping are
    // no value), compared with what `read_entries` makes of the objects.
    let mut fields = 0u64;
    let mut offset = 0u32;
    for entry in entries {
        let bits = u32::from(entry.bits);
        if !entry.is_dummy() && offset < 64 {
            let ones = if bits >= 64 {
                u64::MAX
            } else {
                (1 << bits) - 1
            };
            fields |= ones << offset;
        }
        offset += bits;
    }
    if payload.len() < field_len(offset) {
        return false;
    }
    let mut word = [0u8; 8];
    crate::bytes::copy_payload(&mut word, payload);
    read_entries(entries, od).is_ok_and(|(held, _)| held == u64::from_le_bytes(word) & fields)
}

/// [`write_mapped`] over the entries of a valid mapping.
pub(crate) fn write_entries<D: ObjectDictionary + ?Sized>(
    entries: &[MappingEntry],
    payload: &[u8],
    od: &mut D,
) -> Result<bool, RpdoError> {
    let total: u32 = entries.iter().map(|e| u32::from(e.bits)).sum();
    let need = field_len(total);
    if payload.len() < need {
        return Err(RpdoError::TooShort {
            need,
            got: payload.len(),
        });
    }
    let mut offset = 0u32;
    for entry in entries {
        let bits = u32::from(entry.bits);
        let at = offset;
        offset += bits;
        if entry.is_dummy() {
            continue;
        }
        let value = extract_bits(payload, at, bits);
        let len = field_len(bits);
        let bytes = value.to_le_bytes();
        let data = bytes.get(..len).unwrap_or(&[]);
        let written = od
            .write(entry.index, entry.sub, 0, data)
            .and_then(|()| od.finish_write(entry.index, entry.sub, len));
        if let Err(code) = written {
            return Err(RpdoError::Refused {
                index: entry.index,
                sub: entry.sub,
                code,
            });
        }
    }
    Ok(payload.len() > need)
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    use super::*;
    use crate::od::{Access, MemoryDictionary};
    use crate::pdo::catalogue_test_support::mapping as entries;

    fn od() -> MemoryDictionary {
        let mut od = MemoryDictionary::new();
        od.insert(0x6010, 0, Access::ReadOnly, &(-80i16).to_le_bytes());
        od.insert(0x6000, 0, Access::ReadOnly, &[0x01]);
        od.insert(0x6060, 0, Access::ReadOnly, &(51_200u32).to_le_bytes());
        od.insert(0x6001, 0, Access::ReadWrite, &[0]);
        od.insert(0x6052, 0, Access::ReadWrite, &[0, 0]);
        od.insert(0x6080, 0, Access::ReadWrite, &[0xFF]);
        od
    }

    #[test]
    fn tpdo_payload_from_objects() {
        let m = entries(&[(0x6010, 0, 16), (0x6000, 0, 8), (0x6060, 0, 32)]);
        let p = read_mapped(&m, &mut od()).unwrap();
        assert_eq!(p.as_slice(), &[0xB0, 0xFF, 0x01, 0x00, 0xC8, 0x00, 0x00]);
        // A dummy entry is zero; a missing object is the dictionary's code.
        let m = entries(&[(0x0005, 0, 8), (0x6000, 0, 8)]);
        assert_eq!(
            read_mapped(&m, &mut od()).unwrap().as_slice(),
            &[0x00, 0x01]
        );
        let m = PdoMapping::new(&[MappingEntry::new(0x6099, 0, 8)]).unwrap();
        assert_eq!(
            read_mapped(&m, &mut od()),
            Err(AbortCode::ObjectDoesNotExist)
        );
    }

    #[test]
    fn rpdo_fields_into_objects() {
        // CiA 418 3rd RPDO: 6001h/8, 6052h/16, 6080h/8.
        let m = entries(&[(0x6001, 0, 8), (0x6052, 0, 16), (0x6080, 0, 8)]);
        let mut od = od();
        assert_eq!(
            write_mapped(&m, &[0x01, 0x34, 0x12, 0x50], &mut od),
            Ok(false)
        );
        assert_eq!(od.get(0x6001, 0), Some(&[0x01][..]));
        assert_eq!(od.get(0x6052, 0), Some(&[0x34, 0x12][..]));
        assert_eq!(od.get(0x6080, 0), Some(&[0x50][..]));
        assert_eq!(
            write_mapped(&m, &[0x00, 0x00, 0x00, 0x10, 0xEE], &mut od),
            Ok(true)
        );
        let short = write_mapped(&m, &[0x01, 0x34, 0x12], &mut od);
        assert_eq!(short, Err(RpdoError::TooShort { need: 4, got: 3 }));
        assert_eq!(short.unwrap_err().emcy_code(), Some(ErrorCode::PDO_LENGTH));
        assert_eq!(
            od.get(0x6080, 0),
            Some(&[0x10][..]),
            "a short RPDO changes nothing"
        );
        let m = PdoMapping::new(&[MappingEntry::new(0x6099, 0, 8)]).unwrap();
        assert!(matches!(
            write_mapped(&m, &[1], &mut od),
            Err(RpdoError::Refused {
                index: 0x6099,
                code: AbortCode::ObjectDoesNotExist,
                ..
            })
        ));
    }

    #[test]
    fn rpdo_fields_already_held() {
        // 6001h/8, a dummy byte, 6052h/16: what `od()` holds is 00, 0000.
        let m = entries(&[(0x6001, 0, 8), (0x0005, 0, 8), (0x6052, 0, 16)]);
        let mut od = od();
        // The dummy's byte, and bytes past the mapping, are no value.
        assert!(holds_entries(m.entries(), &[0, 0xAA, 0, 0, 0xBB], &mut od));
        assert!(!holds_entries(m.entries(), &[0, 0, 0, 1], &mut od));
        assert!(!holds_entries(m.entries(), &[1, 0, 0, 0], &mut od));
        assert!(!holds_entries(m.entries(), &[0, 0, 0], &mut od), "short");
        write_mapped(&m, &[0x01, 0, 0x34, 0x12], &mut od).unwrap();
        assert!(holds_entries(m.entries(), &[0x01, 0, 0x34, 0x12], &mut od));
        // An object that cannot be read holds nothing.
        let m = entries(&[(0x6099, 0, 8)]);
        assert!(!holds_entries(m.entries(), &[0], &mut od));
    }
}
