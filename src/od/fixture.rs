//! A dictionary for the crate's own tests: one mappable, writable object,
//! 2000h sub-index 0, of `LEN` bytes (1..=4), its value a little-endian
//! word; every other object does not exist (06020000h), every other
//! sub-index of 2000h neither (06090011h).

use super::{read_at, Access, ObjectDictionary, ObjectInfo};
use crate::abort::AbortCode;

/// The one object's value; a write stores the bytes written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Word<const LEN: usize>(pub u32);

impl<const LEN: usize> ObjectDictionary for Word<LEN> {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        match (index, sub) {
            (0x2000, 0) => Ok(ObjectInfo::fixed(Access::ReadWrite, LEN).mappable()),
            (0x2000, _) => Err(AbortCode::SubIndexDoesNotExist),
            _ => Err(AbortCode::ObjectDoesNotExist),
        }
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        self.info(index, sub)?;
        let bytes = self.0.to_le_bytes();
        Ok(read_at(bytes.get(..LEN).unwrap_or(&bytes), offset, buf))
    }

    fn write(&mut self, index: u16, sub: u8, _: usize, data: &[u8]) -> Result<(), AbortCode> {
        self.info(index, sub)?;
        let mut bytes = [0u8; 4];
        crate::bytes::copy_payload(&mut bytes, data);
        self.0 = u32::from_le_bytes(bytes);
        Ok(())
    }
}
