//! The concise DCF: a node's configuration as one byte string, the value
//! of object 1F22h (CiA 302-3 "Configuration and program download",
//! section 4 "Configuration management"; the object is listed in CiA 301
//! section 7.5 among the network-management objects 1F00h-1FFFh).
//!
//! The format: a `UNSIGNED32` number of entries, then per entry the
//! `UNSIGNED16` index, the `UNSIGNED8` sub-index, the `UNSIGNED32` size of
//! the data in bytes and the data themselves, every number little-endian as
//! everywhere in CANopen (CiA 301 section 7.1.4, "Data type encoding").
//! A configuration manager writes each entry to the node with an SDO
//! download, in the order the entries are listed (CiA 302-3 section 4: the
//! order is the file's, so an entry that must precede another, such as a
//! PDO's disable before its mapping, is written first).
//!
//! [`ConciseDcf::new_checked`] checks the whole string once; its iterator
//! then yields [`ConciseEntry`]s without any further failure.
//! [`ConciseWriter`] appends entries into a caller's buffer (no heap), and
//! [`ConciseDcf::encode_vec`] (feature `alloc`) builds a `Vec`.
//!
//! ```
//! use canopen_codec::od::{Address, ConciseDcf, ConciseEntry, ConciseWriter};
//!
//! // Heartbeat producer time 1017h = 500 ms, then 1400h sub 2 = FEh.
//! let mut buf = [0u8; 64];
//! let mut w = ConciseWriter::new(&mut buf)?;
//! w.push(ConciseEntry::new(Address::new(0x1017, 0), &500u16.to_le_bytes()))?;
//! w.push(ConciseEntry::new(Address::new(0x1400, 2), &[0xFE]))?;
//! let len = w.finish();
//! assert_eq!(len, 4 + (7 + 2) + (7 + 1));
//! assert_eq!(&buf[..4], &[2, 0, 0, 0]);
//!
//! let dcf = ConciseDcf::new_checked(&buf[..len])?;
//! assert_eq!(dcf.len(), 2);
//! let first = dcf.iter().next();
//! assert_eq!(first.map(|e| (e.addr, e.data)), Some((Address::new(0x1017, 0), &[0xF4, 0x01][..])));
//! # Ok::<(), canopen_codec::od::ConciseDcfError>(())
//! ```

use core::iter::FusedIterator;

use super::Address;

/// Bytes before the first entry: the `UNSIGNED32` entry count.
const COUNT_LEN: usize = ConciseDcf::COUNT_LEN;
/// Bytes of an entry before its data: index (2), sub-index (1), size (4).
const ENTRY_HEADER_LEN: usize = ConciseEntry::HEADER_LEN;

/// Why bytes are not a concise DCF, or why an entry does not fit one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum ConciseDcfError {
    /// Fewer than the four bytes of the entry count (reading), or a buffer
    /// too small for them (writing).
    #[error("concise DCF shorter than its 4-byte entry count ({got} bytes)")]
    NoCount {
        /// The bytes there are.
        got: usize,
    },
    /// The data end cleanly after `found` entries but the count says more.
    #[error("concise DCF announces {count} entries but holds {found}")]
    MissingEntries {
        /// The entry count the string starts with.
        count: u32,
        /// The whole entries it holds.
        found: u32,
    },
    /// Entry `entry` (from 0) starts but its 7-byte header is cut short.
    #[error("concise DCF entry {entry}: header cut after {got} of 7 bytes")]
    EntryHeaderTruncated {
        /// Which entry, from 0.
        entry: u32,
        /// The header bytes there are.
        got: usize,
    },
    /// Entry `entry` (from 0) announces more data than the string holds.
    #[error("concise DCF entry {entry}: size {size} but {remaining} bytes remain")]
    SizePastEnd {
        /// Which entry, from 0.
        entry: u32,
        /// The size the entry announces.
        size: u32,
        /// The bytes left after its header.
        remaining: usize,
    },
    /// Bytes follow the last entry the count announces.
    #[error("concise DCF: {extra} bytes after its {count} entries")]
    TrailingBytes {
        /// The entry count.
        count: u32,
        /// The bytes after the last entry.
        extra: usize,
    },
    /// Writing: the entry does not fit the rest of the caller's buffer.
    #[error("concise DCF buffer too small: need {need} bytes, have {got}")]
    BufferTooSmall {
        /// The bytes the entry needs.
        need: usize,
        /// The bytes left in the buffer.
        got: usize,
    },
    /// Writing: more than `u32::MAX` entries, or data longer than
    /// `u32::MAX` bytes: the format's fields cannot say it.
    #[error("concise DCF: entry count or data size beyond UNSIGNED32")]
    TooLarge,
}

/// One entry of a concise DCF: the object to write and the bytes an SDO
/// download writes to it (CiA 302-3 section 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ConciseEntry<'a> {
    /// The object written.
    pub addr: Address,
    /// Its value, encoded as the object's data type (little-endian).
    pub data: &'a [u8],
}

impl<'a> ConciseEntry<'a> {
    /// Bytes of an entry before its data: index (2), sub-index (1), size (4).
    pub const HEADER_LEN: usize = 7;

    /// The entry writing `data` to `addr`.
    #[must_use]
    pub const fn new(addr: Address, data: &'a [u8]) -> Self {
        ConciseEntry { addr, data }
    }

    /// The bytes this entry takes in a concise DCF: its 7-byte header and
    /// its data.
    #[must_use]
    pub const fn buffer_len(&self) -> usize {
        ENTRY_HEADER_LEN.saturating_add(self.data.len())
    }

    /// Writes the entry (header, then data) at the start of `out` and
    /// returns the bytes written.
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, ConciseDcfError> {
        let size = u32::try_from(self.data.len()).map_err(|_| ConciseDcfError::TooLarge)?;
        let need = self.buffer_len();
        let got = out.len();
        let Some((header, rest)) = out.split_first_chunk_mut::<ENTRY_HEADER_LEN>() else {
            return Err(ConciseDcfError::BufferTooSmall { need, got });
        };
        let Some(body) = rest.get_mut(..self.data.len()) else {
            return Err(ConciseDcfError::BufferTooSmall { need, got });
        };
        let [i0, i1] = self.addr.index.to_le_bytes();
        let [s0, s1, s2, s3] = size.to_le_bytes();
        *header = [i0, i1, self.addr.sub, s0, s1, s2, s3];
        body.copy_from_slice(self.data);
        Ok(need)
    }
}

/// A checked concise DCF: the count matches the entries, every entry's data
/// lies within the bytes and nothing follows the last one. Iterating it
/// cannot fail.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ConciseDcf<'a> {
    count: u32,
    entries: &'a [u8],
}

impl<'a> ConciseDcf<'a> {
    /// Bytes before the first entry: the `UNSIGNED32` entry count.
    pub const COUNT_LEN: usize = 4;

    /// Checks `bytes` as a whole concise DCF (the value of 1F22h for one
    /// node, CiA 302-3 section 4). Total on any input; the work is linear
    /// in `bytes.len()` whatever the count claims.
    pub fn new_checked(bytes: &'a [u8]) -> Result<Self, ConciseDcfError> {
        let Some((count, entries)) = bytes.split_first_chunk::<COUNT_LEN>() else {
            return Err(ConciseDcfError::NoCount { got: bytes.len() });
        };
        let count = u32::from_le_bytes(*count);
        let mut rest = entries;
        let mut found = 0u32;
        while found < count {
            match split_entry(rest) {
                Ok((_, tail)) => rest = tail,
                Err(Cut::End) => return Err(ConciseDcfError::MissingEntries { count, found }),
                Err(Cut::Header(got)) => {
                    return Err(ConciseDcfError::EntryHeaderTruncated { entry: found, got })
                }
                Err(Cut::Data { size, remaining }) => {
                    return Err(ConciseDcfError::SizePastEnd {
                        entry: found,
                        size,
                        remaining,
                    })
                }
            }
            found = found.saturating_add(1);
        }
        if !rest.is_empty() {
            return Err(ConciseDcfError::TrailingBytes {
                count,
                extra: rest.len(),
            });
        }
        Ok(ConciseDcf { count, entries })
    }

    /// The number of entries.
    #[must_use]
    pub const fn len(&self) -> u32 {
        self.count
    }

    /// True if it configures nothing (a count of 0).
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The bytes of the whole concise DCF, count included.
    #[must_use]
    pub fn buffer_len(&self) -> usize {
        COUNT_LEN.saturating_add(self.entries.len())
    }

    /// The entries in their order.
    #[must_use]
    pub fn iter(&self) -> ConciseEntries<'a> {
        ConciseEntries {
            left: self.count,
            rest: self.entries,
        }
    }

    /// Writes `entries` as a concise DCF into `out` and returns its length
    /// (the no-heap way to build one from a list; [`ConciseWriter`] appends
    /// one at a time).
    pub fn encode<'e, I>(entries: I, out: &mut [u8]) -> Result<usize, ConciseDcfError>
    where
        I: IntoIterator<Item = ConciseEntry<'e>>,
    {
        let mut w = ConciseWriter::new(out)?;
        for e in entries {
            w.push(e)?;
        }
        Ok(w.finish())
    }

    /// Builds the concise DCF of `entries` in a `Vec`.
    #[cfg(feature = "alloc")]
    pub fn encode_vec<'e, I>(entries: I) -> Result<alloc::vec::Vec<u8>, ConciseDcfError>
    where
        I: IntoIterator<Item = ConciseEntry<'e>>,
    {
        let mut out = alloc::vec![0u8; COUNT_LEN];
        let mut count = 0u32;
        for e in entries {
            count = count.checked_add(1).ok_or(ConciseDcfError::TooLarge)?;
            let start = out.len();
            out.resize(start.saturating_add(e.buffer_len()), 0);
            e.emit(out.get_mut(start..).unwrap_or_default())?;
        }
        if let Some(head) = out.first_chunk_mut::<COUNT_LEN>() {
            *head = count.to_le_bytes();
        }
        Ok(out)
    }
}

impl<'a> IntoIterator for &ConciseDcf<'a> {
    type Item = ConciseEntry<'a>;
    type IntoIter = ConciseEntries<'a>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<'a> IntoIterator for ConciseDcf<'a> {
    type Item = ConciseEntry<'a>;
    type IntoIter = ConciseEntries<'a>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

/// The entries of a [`ConciseDcf`], in their order.
#[derive(Debug, Clone)]
pub struct ConciseEntries<'a> {
    left: u32,
    rest: &'a [u8],
}

impl<'a> Iterator for ConciseEntries<'a> {
    type Item = ConciseEntry<'a>;

    fn next(&mut self) -> Option<ConciseEntry<'a>> {
        if self.left == 0 {
            return None;
        }
        // Checked by `new_checked`: a cut here cannot happen, and ends the
        // iteration if it did.
        let (entry, tail) = split_entry(self.rest).ok()?;
        self.rest = tail;
        self.left = self.left.saturating_sub(1);
        Some(entry)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = usize::try_from(self.left).unwrap_or(usize::MAX);
        (n, Some(n))
    }
}

impl ExactSizeIterator for ConciseEntries<'_> {}
impl FusedIterator for ConciseEntries<'_> {}

/// Where an entry is cut short.
enum Cut {
    /// No byte of it at all.
    End,
    /// Within its header: the bytes there are.
    Header(usize),
    /// Within its data.
    Data { size: u32, remaining: usize },
}

/// Splits the first entry off `bytes`.
fn split_entry(bytes: &[u8]) -> Result<(ConciseEntry<'_>, &[u8]), Cut> {
    let Some(([i0, i1, sub, s0, s1, s2, s3], rest)) = bytes.split_first_chunk::<ENTRY_HEADER_LEN>()
    else {
        return Err(if bytes.is_empty() {
            Cut::End
        } else {
            Cut::Header(bytes.len())
        });
    };
    let size = u32::from_le_bytes([*s0, *s1, *s2, *s3]);
    let remaining = rest.len();
    let Some((data, tail)) = usize::try_from(size)
        .ok()
        .and_then(|n| rest.split_at_checked(n))
    else {
        return Err(Cut::Data { size, remaining });
    };
    let addr = Address::new(u16::from_le_bytes([*i0, *i1]), *sub);
    Ok((ConciseEntry { addr, data }, tail))
}

/// Appends entries to a concise DCF in a caller's buffer; [`finish`]
/// writes the count and returns the length.
///
/// [`finish`]: ConciseWriter::finish
#[derive(Debug)]
pub struct ConciseWriter<'b> {
    buf: &'b mut [u8],
    len: usize,
    count: u32,
}

impl<'b> ConciseWriter<'b> {
    /// A writer over `buf`, which must hold at least the 4-byte count.
    pub fn new(buf: &'b mut [u8]) -> Result<Self, ConciseDcfError> {
        if buf.len() < COUNT_LEN {
            return Err(ConciseDcfError::NoCount { got: buf.len() });
        }
        Ok(ConciseWriter {
            buf,
            len: COUNT_LEN,
            count: 0,
        })
    }

    /// Appends one entry; on an error nothing is appended.
    pub fn push(&mut self, entry: ConciseEntry<'_>) -> Result<(), ConciseDcfError> {
        let count = self.count.checked_add(1).ok_or(ConciseDcfError::TooLarge)?;
        let out = self.buf.get_mut(self.len..).unwrap_or_default();
        let n = entry.emit(out)?;
        self.len = self.len.saturating_add(n);
        self.count = count;
        Ok(())
    }

    /// The entries appended so far.
    #[must_use]
    pub const fn count(&self) -> u32 {
        self.count
    }

    /// Writes the entry count and returns the length of the concise DCF at
    /// the start of the buffer.
    pub fn finish(self) -> usize {
        if let Some(head) = self.buf.first_chunk_mut::<COUNT_LEN>() {
            *head = self.count.to_le_bytes();
        }
        self.len
    }
}

#[cfg(test)]
#[path = "concise_tests.rs"]
mod tests;
