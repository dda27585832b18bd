//! [`WriteBuffer`]: the buffer a dictionary of small values (at most 4
//! bytes each) keeps while a download is in progress, so the value is
//! applied whole at [`finish_write`](super::ObjectDictionary::finish_write)
//! and a refused or aborted download changes nothing.

use super::{Access, ObjectInfo};
use crate::abort::AbortCode;
use crate::bytes::InlineData;

/// The bytes of one download in progress, at most 4.
///
/// ```
/// use canopen_codec::od::WriteBuffer;
/// use canopen_codec::sdo::AbortCode;
/// let mut w = WriteBuffer::new();
/// w.write(0x1017, 0, 0, &[0xE8]).unwrap();
/// w.write(0x1017, 0, 1, &[0x03]).unwrap();
/// assert_eq!(w.take(0x1017, 0), &[0xE8, 0x03]);
/// assert_eq!(w.take(0x1017, 0), &[] as &[u8], "taken once");
/// assert_eq!(w.write(0x1017, 0, 0, &[0; 5]), Err(AbortCode::DataTypeLengthTooHigh));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct WriteBuffer {
    // 8 bytes: the object, the count and the bytes, no `Option` or
    // `usize` (a buffer sits in each dictionary layer's state).
    index: u16,
    sub: u8,
    /// Bytes written, [`NONE`] when no value is in progress.
    len: u8,
    bytes: [u8; 4],
}

/// [`WriteBuffer::len`] when no value is in progress: past any length, so
/// a continuation never fits.
const NONE: u8 = u8::MAX;

impl Default for WriteBuffer {
    fn default() -> Self {
        Self::new()
    }
}

impl WriteBuffer {
    /// Empty.
    #[must_use]
    pub const fn new() -> Self {
        WriteBuffer {
            index: 0,
            sub: 0,
            len: NONE,
            bytes: [0; 4],
        }
    }

    /// Appends `data` at `offset` of the value of `index`/`sub`. Offset 0
    /// starts a new value; any other offset must continue the same object
    /// exactly where it stopped. Out of order, or more than 4 bytes in all,
    /// is 06070012h and forgets the value.
    pub fn write(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        data: &[u8],
    ) -> Result<(), AbortCode> {
        if offset == 0 {
            *self = WriteBuffer {
                index,
                sub,
                len: 0,
                bytes: [0; 4],
            };
        }
        // No value in progress: `len` is past the bytes, nothing fits.
        let len = usize::from(self.len);
        let end = len.saturating_add(data.len());
        let fits = self.index == index && self.sub == sub && offset == len;
        match self.bytes.get_mut(len..end) {
            Some(dst) if fits => {
                dst.copy_from_slice(data);
                self.len = end as u8;
                Ok(())
            }
            _ => {
                self.clear();
                Err(AbortCode::DataTypeLengthTooHigh)
            }
        }
    }

    /// How many bytes were written for `index`/`sub` (0 for another
    /// object), and forgets them; they stay in `bytes`, zero past them.
    fn take_len(&mut self, index: u16, sub: u8) -> usize {
        let len = core::mem::replace(&mut self.len, NONE);
        if self.index == index && self.sub == sub && len <= 4 {
            usize::from(len)
        } else {
            0
        }
    }

    /// The bytes written for `index`/`sub` (empty for another object), and
    /// forgets them.
    pub fn take(&mut self, index: u16, sub: u8) -> &[u8] {
        let len = self.take_len(index, sub);
        self.bytes.get(..len).unwrap_or(&[])
    }

    /// The complete value of a download of `len` bytes to an object
    /// described by `info` (the dictionary's answer for it), checked against
    /// its access (06010002h) and size rule (06070012h / 06070013h). The
    /// buffer is empty afterwards, whatever the outcome.
    pub fn finish(
        &mut self,
        info: Result<ObjectInfo, AbortCode>,
        index: u16,
        sub: u8,
        len: usize,
    ) -> Result<InlineData<4>, AbortCode> {
        let taken = self.take(index, sub);
        let value =
            InlineData::new(taken.get(..len.min(taken.len())).unwrap_or(&[])).unwrap_or_default();
        let info = info?;
        if !info.access.is_writable() {
            return Err(AbortCode::WriteOfReadOnlyObject);
        }
        info.check_download_len(value.len())?;
        Ok(value)
    }

    /// The complete value of a download of `len` bytes to a fixed-size
    /// object of `size` bytes with `access` (what the dictionary says of
    /// it), checked against that access (06010002h) and size (06070012h /
    /// 06070013h): the value as a little-endian word, the bytes past it
    /// zero. The buffer is empty afterwards, whatever the outcome.
    ///
    /// ```
    /// use canopen_codec::od::{Access, WriteBuffer};
    /// use canopen_codec::sdo::AbortCode;
    /// let mut w = WriteBuffer::new();
    /// w.write(0x1017, 0, 0, &[0xE8, 0x03]).unwrap();
    /// assert_eq!(w.downloaded_value(Access::ReadWrite, 2, 0x1017, 0, 2), Ok(1000));
    /// w.write(0x1017, 0, 0, &[0xE8]).unwrap();
    /// assert_eq!(
    ///     w.downloaded_value(Access::ReadWrite, 2, 0x1017, 0, 1),
    ///     Err(AbortCode::DataTypeLengthTooLow)
    /// );
    /// w.write(0x6001, 0, 0, &[7]).unwrap();
    /// assert_eq!(
    ///     w.downloaded_value(Access::ReadOnly, 1, 0x6001, 0, 1),
    ///     Err(AbortCode::WriteOfReadOnlyObject)
    /// );
    /// ```
    pub fn downloaded_value(
        &mut self,
        access: Access,
        size: usize,
        index: u16,
        sub: u8,
        len: usize,
    ) -> Result<u32, AbortCode> {
        let n = len.min(self.take_len(index, sub));
        if !access.is_writable() {
            return Err(AbortCode::WriteOfReadOnlyObject);
        }
        if n > size {
            return Err(AbortCode::DataTypeLengthTooHigh);
        }
        if n < size {
            return Err(AbortCode::DataTypeLengthTooLow);
        }
        // The bytes past `len` were zeroed when the value started; a
        // declared length shorter than what was written cuts the rest.
        let mask = u32::MAX.checked_shr(32 - 8 * n as u32).unwrap_or(0);
        Ok(u32::from_le_bytes(self.bytes) & mask)
    }

    /// `found`, what the dictionary says of the object a write goes to,
    /// or its refusal with the buffered bytes dropped: a refused write
    /// leaves nothing behind.
    pub fn unless_refused<T>(&mut self, found: Result<T, AbortCode>) -> Result<T, AbortCode> {
        if found.is_err() {
            self.clear();
        }
        found
    }

    /// Forgets the value in progress (an aborted download).
    pub fn clear(&mut self) {
        *self = Self::new();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_order_and_limits() {
        let mut w = WriteBuffer::new();
        assert_eq!(w.write(1, 0, 0, &[1, 2]), Ok(()));
        assert_eq!(w.write(1, 0, 2, &[3, 4]), Ok(()));
        assert_eq!(w.take(1, 0), &[1, 2, 3, 4]);
        // Another object's continuation, a gap, an overlap, too long.
        for (index, offset, data) in [(2u16, 1usize, &[9u8][..]), (1, 3, &[9]), (1, 0, &[0; 5])] {
            let _ = w.write(1, 0, 0, &[7]);
            assert_eq!(
                w.write(index, 0, offset, data),
                Err(AbortCode::DataTypeLengthTooHigh)
            );
            assert_eq!(w.take(1, 0), &[] as &[u8], "forgotten");
        }
        assert_eq!(w.write(1, 0, 0, &[7]), Ok(()));
        assert_eq!(w.take(2, 0), &[] as &[u8], "another object's take");
        assert_eq!(
            w.write(1, 0, usize::MAX, &[1]),
            Err(AbortCode::DataTypeLengthTooHigh)
        );
        assert_eq!(w.write(1, 0, 0, &[]), Ok(()));
        assert_eq!(w.take(1, 0), &[] as &[u8]);
        w.write(1, 0, 0, &[5]).unwrap();
        w.clear();
        assert_eq!(w.take(1, 0), &[] as &[u8]);
    }

    /// A refusal of the object drops the buffered bytes; an answer keeps them.
    #[test]
    fn refused_objects_leave_nothing_behind() {
        let mut w = WriteBuffer::new();
        w.write(1, 0, 0, &[5, 6]).unwrap();
        assert_eq!(w.unless_refused(Ok(3)), Ok(3));
        assert_eq!(w.take(1, 0), &[5, 6]);
        let refused: Result<u8, _> = Err(AbortCode::ObjectDoesNotExist);
        assert_eq!(w.unless_refused(refused), refused);
        assert_eq!(w.take(1, 0), &[] as &[u8]);
    }

    #[test]
    fn checked_writes() {
        use crate::od::Access;
        let rw = ObjectInfo::fixed(Access::ReadWrite, 2);
        let ro = ObjectInfo::fixed(Access::ReadOnly, 2);
        let mut w = WriteBuffer::new();
        w.write(1, 0, 0, &[1, 2]).unwrap();
        assert_eq!(w.finish(Ok(rw), 1, 0, 2).unwrap().as_slice(), &[1, 2]);
        w.write(1, 0, 0, &[1]).unwrap();
        assert_eq!(
            w.finish(Ok(rw), 1, 0, 1),
            Err(AbortCode::DataTypeLengthTooLow)
        );
        w.write(1, 0, 0, &[1, 2]).unwrap();
        assert_eq!(
            w.finish(Ok(ro), 1, 0, 2),
            Err(AbortCode::WriteOfReadOnlyObject)
        );
        w.write(1, 0, 0, &[1, 2]).unwrap();
        assert_eq!(
            w.finish(Err(AbortCode::ObjectDoesNotExist), 1, 0, 2),
            Err(AbortCode::ObjectDoesNotExist)
        );
        // The declared length cuts what was written.
        w.write(1, 0, 0, &[1, 2]).unwrap();
        assert_eq!(
            w.finish(Ok(rw), 1, 0, 1),
            Err(AbortCode::DataTypeLengthTooLow)
        );
        assert_eq!(w.take(1, 0), &[] as &[u8], "always empty afterwards");
    }

    #[test]
    fn word_of_a_fixed_size_value() {
        use crate::od::Access::{ReadOnly, ReadWrite};
        let mut w = WriteBuffer::new();
        for (data, size, len, want) in [
            (&[1u8, 2, 3, 4][..], 4usize, 4usize, Ok(0x0403_0201)),
            (&[0xFF][..], 1, 1, Ok(0xFF)),
            (&[1, 2][..], 2, 2, Ok(0x0201)),
            // The declared length cuts what was written.
            (&[1, 2, 3][..], 2, 2, Ok(0x0201)),
            (&[1, 2, 3][..], 2, 3, Err(AbortCode::DataTypeLengthTooHigh)),
            (&[1][..], 2, 1, Err(AbortCode::DataTypeLengthTooLow)),
            (&[][..], 1, 0, Err(AbortCode::DataTypeLengthTooLow)),
        ] {
            w.write(1, 0, 0, data).unwrap();
            assert_eq!(
                w.downloaded_value(ReadWrite, size, 1, 0, len),
                want,
                "{data:?}"
            );
            assert_eq!(w.take(1, 0), &[] as &[u8], "always empty afterwards");
        }
        // A shorter value after a longer one: no old bytes past it.
        w.write(1, 0, 0, &[9, 9, 9, 9]).unwrap();
        w.write(1, 0, 0, &[7]).unwrap();
        assert_eq!(w.downloaded_value(ReadWrite, 1, 1, 0, 1), Ok(7));
        w.write(1, 0, 0, &[1, 2]).unwrap();
        assert_eq!(
            w.downloaded_value(ReadOnly, 2, 1, 0, 2),
            Err(AbortCode::WriteOfReadOnlyObject)
        );
        // Another object's bytes are not this one's value.
        w.write(2, 0, 0, &[1, 2]).unwrap();
        assert_eq!(
            w.downloaded_value(ReadWrite, 2, 1, 0, 2),
            Err(AbortCode::DataTypeLengthTooLow)
        );
        assert_eq!(core::mem::size_of::<WriteBuffer>(), 8);
    }
}
