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

/// The rule every dictionary keeps for a download broken off (CiA 301
/// 7.2.4.3.12: an SDO abort ends the transfer; a value is stored whole
/// when its download completes): the first byte of the `len`-byte object
/// `index`/`sub` written, then the download aborted; completing it
/// afterwards finds no bytes held (06070013h), and the object reads what
/// it read before.
pub(crate) fn assert_aborted_write_changes_nothing(
    od: &mut impl ObjectDictionary,
    index: u16,
    sub: u8,
    len: usize,
) {
    let mut before = [0u8; 4];
    let n = od.read(index, sub, 0, &mut before).unwrap();
    let [first, ..] = before;
    od.write(index, sub, 0, &[!first]).unwrap();
    od.abort_write(index, sub);
    assert_eq!(
        od.finish_write(index, sub, len),
        Err(AbortCode::DataTypeLengthTooLow),
        "{index:04X}h:{sub}"
    );
    let mut after = [0u8; 4];
    assert_eq!(od.read(index, sub, 0, &mut after), Ok(n));
    assert_eq!(after, before, "{index:04X}h:{sub} unchanged");
}
