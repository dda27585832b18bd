//! The object-dictionary seam: what the SDO server (and PDO mapping) need to
//! know about an object, and byte access at an offset.
//!
//! The crate never owns application data. A device implements
//! [`ObjectDictionary`] over its own storage; the SDO server asks it for an
//! object's [`ObjectInfo`] and reads or writes bytes at an offset. Failures
//! are [`AbortCode`]s, which the server sends to the client unchanged.
//!
//! ## Write protocol
//!
//! A download of `n` bytes calls [`ObjectDictionary::write`] one or more
//! times with increasing offsets (once per segment, once for an expedited
//! transfer), then [`ObjectDictionary::finish_write`] with the total length.
//! If the transfer is aborted after some writes,
//! [`ObjectDictionary::abort_write`] is called instead of `finish_write`. An
//! implementation that must apply values atomically buffers until
//! `finish_write`; a simple one writes through and ignores the two hooks.

use crate::abort::AbortCode;

mod address;
pub mod comm;
mod concise;
mod fixed;
#[cfg(test)]
pub(crate) mod fixture;
pub mod index;
#[cfg(feature = "alloc")]
mod memory;
mod reading;
mod row;
mod table;
mod types;
mod write_buffer;
pub use address::Address;
pub use concise::{ConciseDcf, ConciseDcfError, ConciseEntries, ConciseEntry, ConciseWriter};
pub use fixed::{FixedDictionary, FixedEntry, FixedObject, FixedObjects};
#[cfg(feature = "alloc")]
pub use memory::MemoryDictionary;
pub use reading::{FlagField, FlagWord, Interpretation, Marker, Unit, ValueFormat};
pub use row::{Compound, ObjectRow};
pub use types::{DataType, ObjectType};
pub use write_buffer::WriteBuffer;

/// Access rights of an object, CiA 301.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Access {
    /// `ro`: readable; writes abort with 06010002h.
    ReadOnly,
    /// `wo`: writable; reads abort with 06010001h.
    WriteOnly,
    /// `rw`: readable and writable.
    ReadWrite,
    /// `const`: readable, never writable (06010002h).
    Const,
}

impl Access {
    /// True if an SDO upload may read it.
    #[must_use]
    pub const fn is_readable(self) -> bool {
        !matches!(self, Access::WriteOnly)
    }

    /// True if an SDO download may write it.
    #[must_use]
    pub const fn is_writable(self) -> bool {
        matches!(self, Access::WriteOnly | Access::ReadWrite)
    }
}

/// How long a download to the object may be.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SizeRule {
    /// Exactly this many bytes (numbers, records of fixed size).
    Fixed(usize),
    /// Anything from 0 up to `max` bytes (strings, domains).
    Variable {
        /// The largest accepted length.
        max: usize,
    },
}

/// What the dictionary says about one sub-object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ObjectInfo {
    /// Access rights.
    pub access: Access,
    /// Length of the current value in bytes (what an upload returns).
    pub len: usize,
    /// What a download may write.
    pub size: SizeRule,
    /// True if the object may be mapped into a PDO.
    pub pdo_mappable: bool,
}

impl ObjectInfo {
    /// A fixed-size object of `len` bytes.
    #[must_use]
    pub const fn fixed(access: Access, len: usize) -> Self {
        ObjectInfo {
            access,
            len,
            size: SizeRule::Fixed(len),
            pdo_mappable: false,
        }
    }

    /// The same, PDO-mappable.
    #[must_use]
    pub const fn mappable(mut self) -> Self {
        self.pdo_mappable = true;
        self
    }

    /// Checks a download of `len` bytes against the size rule: too long is
    /// 06070012h, too short for a fixed-size object 06070013h.
    pub const fn check_download_len(&self, len: usize) -> Result<(), AbortCode> {
        match self.size {
            SizeRule::Fixed(n) if len > n => Err(AbortCode::DataTypeLengthTooHigh),
            SizeRule::Fixed(n) if len < n => Err(AbortCode::DataTypeLengthTooLow),
            SizeRule::Variable { max } if len > max => Err(AbortCode::DataTypeLengthTooHigh),
            _ => Ok(()),
        }
    }
}

/// Copies the bytes of `value` from `offset` into `buf` and returns how
/// many: what [`ObjectDictionary::read`] does for a value held in memory
/// (an offset at or past the end copies nothing).
///
/// ```
/// let mut buf = [0u8; 3];
/// assert_eq!(canopen_codec::od::read_at(b"battery", 5, &mut buf), 2);
/// assert_eq!(&buf[..2], b"ry");
/// assert_eq!(canopen_codec::od::read_at(b"battery", usize::MAX, &mut buf), 0);
/// ```
#[inline(never)]
pub fn read_at(value: &[u8], offset: usize, buf: &mut [u8]) -> usize {
    let src = value.get(offset..).unwrap_or(&[]);
    let n = src.len().min(buf.len());
    // SDO reads are 1..=7 bytes: a fixed-length copy, not a memcpy call.
    crate::bytes::copy_payload(buf, src);
    n
}

/// An object dictionary the SDO server serves. Implemented by the
/// application over its own storage.
pub trait ObjectDictionary {
    /// Describes `index`/`sub`, or fails with 06020000h (no object) /
    /// 06090011h (no sub-index) or any other code.
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode>;

    /// Copies bytes of the value starting at `offset` into `buf`; returns how
    /// many were copied (fewer than `buf.len()` only at the end of the value).
    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode>;

    /// Writes `data` at `offset` of the value being downloaded.
    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode>;

    /// The download is complete with `len` bytes in total. Validation that
    /// needs the whole value (ranges, PDO mapping rules) belongs here.
    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        let _ = (index, sub, len);
        Ok(())
    }

    /// The download was aborted after some [`write`](Self::write) calls.
    fn abort_write(&mut self, index: u16, sub: u8) {
        let _ = (index, sub);
    }
}

impl<T: ObjectDictionary + ?Sized> ObjectDictionary for &mut T {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        (**self).info(index, sub)
    }
    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        (**self).read(index, sub, offset, buf)
    }
    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        (**self).write(index, sub, offset, data)
    }
    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        (**self).finish_write(index, sub, len)
    }
    fn abort_write(&mut self, index: u16, sub: u8) {
        (**self).abort_write(index, sub)
    }
}

/// `Deref`/`DerefMut` of a dictionary layered over the application's
/// objects (its field `$field`): the application reads and updates its
/// own values through the layer, which serves some objects itself
/// ([`FixedDictionary`] over its fixed objects, the device's program
/// download objects over the application's dictionary).
macro_rules! layered_over {
    ($layer:ident<$inner:ident>, $field:ident) => {
        impl<$inner> core::ops::Deref for $layer<$inner> {
            type Target = $inner;

            fn deref(&self) -> &$inner {
                &self.$field
            }
        }

        impl<$inner> core::ops::DerefMut for $layer<$inner> {
            fn deref_mut(&mut self) -> &mut $inner {
                &mut self.$field
            }
        }
    };
}
pub(crate) use layered_over;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn access_rules() {
        assert!(Access::ReadOnly.is_readable() && !Access::ReadOnly.is_writable());
        assert!(!Access::WriteOnly.is_readable() && Access::WriteOnly.is_writable());
        assert!(Access::ReadWrite.is_readable() && Access::ReadWrite.is_writable());
        assert!(Access::Const.is_readable() && !Access::Const.is_writable());
    }

    #[test]
    fn download_length_rules() {
        let u16_obj = ObjectInfo::fixed(Access::ReadWrite, 2);
        assert_eq!(u16_obj.check_download_len(2), Ok(()));
        assert_eq!(
            u16_obj.check_download_len(3),
            Err(AbortCode::DataTypeLengthTooHigh)
        );
        assert_eq!(
            u16_obj.check_download_len(1),
            Err(AbortCode::DataTypeLengthTooLow)
        );
        let s = ObjectInfo {
            size: SizeRule::Variable { max: 10 },
            ..u16_obj
        };
        assert_eq!(s.check_download_len(0), Ok(()));
        assert_eq!(s.check_download_len(10), Ok(()));
        assert_eq!(
            s.check_download_len(11),
            Err(AbortCode::DataTypeLengthTooHigh)
        );
    }
}
