//! A small in-memory object dictionary (`alloc` feature), for tests,
//! simulators and desktop tools. Downloads are applied atomically: bytes are
//! buffered and committed by `finish_write`.

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use super::{Access, ObjectDictionary, ObjectInfo, SizeRule};
use crate::abort::AbortCode;

#[derive(Debug, Clone, PartialEq, Eq)]
struct Entry {
    access: Access,
    size: SizeRule,
    mappable: bool,
    value: Vec<u8>,
}

/// A `BTreeMap`-backed dictionary of byte values.
///
/// ```
/// use canopen_codec::od::{Access, MemoryDictionary, ObjectDictionary};
/// let mut od = MemoryDictionary::new();
/// od.insert(0x1017, 0, Access::ReadWrite, &[0xE8, 0x03]);
/// od.insert_variable(0x1008, 0, Access::Const, b"charger", 32);
/// assert_eq!(od.get(0x1017, 0), Some(&[0xE8, 0x03][..]));
/// assert_eq!(od.info(0x1008, 0).unwrap().len, 7);
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MemoryDictionary {
    entries: BTreeMap<(u16, u8), Entry>,
    pending: Option<((u16, u8), Vec<u8>)>,
}

impl MemoryDictionary {
    /// An empty dictionary.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or replaces) a fixed-size object holding `value`.
    pub fn insert(&mut self, index: u16, sub: u8, access: Access, value: &[u8]) -> &mut Self {
        self.put(index, sub, access, SizeRule::Fixed(value.len()), value)
    }

    /// Adds (or replaces) a variable-size object (string, domain) of at most `max` bytes.
    pub fn insert_variable(
        &mut self,
        index: u16,
        sub: u8,
        access: Access,
        value: &[u8],
        max: usize,
    ) -> &mut Self {
        self.put(index, sub, access, SizeRule::Variable { max }, value)
    }

    fn put(
        &mut self,
        index: u16,
        sub: u8,
        access: Access,
        size: SizeRule,
        value: &[u8],
    ) -> &mut Self {
        self.entries.insert(
            (index, sub),
            Entry {
                access,
                size,
                mappable: false,
                value: value.to_vec(),
            },
        );
        self
    }

    /// Marks an existing object PDO-mappable.
    pub fn set_mappable(&mut self, index: u16, sub: u8, mappable: bool) -> &mut Self {
        if let Some(e) = self.entries.get_mut(&(index, sub)) {
            e.mappable = mappable;
        }
        self
    }

    /// The number of objects (index and sub-index pairs) it holds.
    #[must_use]
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when it holds no object.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The current value.
    #[must_use]
    pub fn get(&self, index: u16, sub: u8) -> Option<&[u8]> {
        self.entries.get(&(index, sub)).map(|e| e.value.as_slice())
    }

    /// Replaces the value of an existing object (the application's side;
    /// no access or size check). Returns false if the object does not exist.
    pub fn set(&mut self, index: u16, sub: u8, value: &[u8]) -> bool {
        match self.entries.get_mut(&(index, sub)) {
            Some(e) => {
                e.value = value.to_vec();
                true
            }
            None => false,
        }
    }

    fn entry(&self, index: u16, sub: u8) -> Result<&Entry, AbortCode> {
        if let Some(e) = self.entries.get(&(index, sub)) {
            return Ok(e);
        }
        let object_exists = self
            .entries
            .range((index, 0)..=(index, u8::MAX))
            .next()
            .is_some();
        Err(if object_exists {
            AbortCode::SubIndexDoesNotExist
        } else {
            AbortCode::ObjectDoesNotExist
        })
    }
}

impl ObjectDictionary for MemoryDictionary {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        let e = self.entry(index, sub)?;
        Ok(ObjectInfo {
            access: e.access,
            len: e.value.len(),
            size: e.size,
            pdo_mappable: e.mappable,
        })
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let e = self.entry(index, sub)?;
        Ok(super::read_at(&e.value, offset, buf))
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        self.entry(index, sub)?;
        let key = (index, sub);
        let buf = match &mut self.pending {
            Some((k, buf)) if *k == key => buf,
            _ => {
                self.pending = Some((key, Vec::new()));
                match &mut self.pending {
                    Some((_, buf)) => buf,
                    None => return Err(AbortCode::GeneralError),
                }
            }
        };
        if offset != buf.len() {
            return Err(AbortCode::GeneralError);
        }
        buf.extend_from_slice(data);
        Ok(())
    }

    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        let value = match self.pending.take() {
            Some((k, buf)) if k == (index, sub) => buf,
            _ => Vec::new(),
        };
        if value.len() != len {
            return Err(AbortCode::GeneralError);
        }
        match self.entries.get_mut(&(index, sub)) {
            Some(e) => {
                e.value = value;
                Ok(())
            }
            None => Err(AbortCode::ObjectDoesNotExist),
        }
    }

    fn abort_write(&mut self, index: u16, sub: u8) {
        if matches!(&self.pending, Some((k, _)) if *k == (index, sub)) {
            self.pending = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_object_vs_sub() {
        let mut od = MemoryDictionary::new();
        assert!(od.is_empty());
        od.insert(0x1018, 1, Access::ReadOnly, &[4, 0, 0, 0]);
        assert_eq!(od.len(), 1);
        assert_eq!(od.info(0x1018, 2), Err(AbortCode::SubIndexDoesNotExist));
        assert_eq!(od.info(0x1019, 0), Err(AbortCode::ObjectDoesNotExist));
    }

    #[test]
    fn writes_are_atomic() {
        let mut od = MemoryDictionary::new();
        od.insert_variable(0x2000, 0, Access::ReadWrite, b"old", 20);
        od.write(0x2000, 0, 0, b"new ").unwrap();
        od.write(0x2000, 0, 4, b"value").unwrap();
        assert_eq!(od.get(0x2000, 0), Some(&b"old"[..]));
        od.abort_write(0x2000, 0);
        assert_eq!(od.get(0x2000, 0), Some(&b"old"[..]));
        od.write(0x2000, 0, 0, b"new").unwrap();
        od.finish_write(0x2000, 0, 3).unwrap();
        assert_eq!(od.get(0x2000, 0), Some(&b"new"[..]));
        let mut buf = [0u8; 2];
        assert_eq!(od.read(0x2000, 0, 1, &mut buf), Ok(2));
        assert_eq!(&buf, b"ew");
        assert_eq!(od.read(0x2000, 0, 9, &mut buf), Ok(0));
    }
}
