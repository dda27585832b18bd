//! The blocks of an MDF 4 file as checked views over the file's bytes
//! (ASAM MDF 4.1/4.2, section 5 "Block types"): every block is its
//! 24-byte header (`##XX` identifier, 4 reserved bytes, length u64, link
//! count u64), its links (u64 file offsets, 0 for none) and its data; the
//! accessors read fields at the offsets the standard gives and cannot
//! index out of bounds (a field past the block's end reads as 0).
//!
//! The file is read through a [`Source`] (random access: the links point
//! anywhere in it): the blocks that describe (header, groups, channels,
//! texts, conversions, lists) are read whole, at most [`MAX_BLOCK`] bytes
//! each; the data blocks (`##DT`, `##SD`, `##DZ`) only by their header
//! ([`head`]), their data read in pieces by the data stream.

use alloc::vec;
use alloc::vec::Vec;

use super::Mf4Error;
use crate::trace::fields::u64_at;

/// The header every block but `##ID` begins with.
pub(super) const HEADER: u64 = 24;
/// The longest block read whole (any but a data block): 16 MiB.
pub const MAX_BLOCK: u64 = 16 << 20;

/// Random access to an MDF 4 file's bytes: the file in memory (`&[u8]`,
/// `&Vec<u8>`) or, with feature `std`, a file that can seek
/// ([`SeekSource`](super::SeekSource)).
pub trait Source {
    /// The file's length in bytes.
    fn size(&self) -> u64;
    /// Fills `buf` with the file's bytes from byte `at`: an error when
    /// they lie past its end ([`Mf4Error::PastEnd`]) or cannot be read
    /// ([`Mf4Error::Read`]).
    fn read_at(&mut self, at: u64, buf: &mut [u8]) -> Result<(), Mf4Error>;
}

impl<T: AsRef<[u8]> + ?Sized> Source for &T {
    fn size(&self) -> u64 {
        self.as_ref().len() as u64
    }

    fn read_at(&mut self, at: u64, buf: &mut [u8]) -> Result<(), Mf4Error> {
        let from = self
            .as_ref()
            .get(usize::try_from(at).unwrap_or(usize::MAX)..)
            .and_then(|rest| rest.get(..buf.len()))
            .ok_or(Mf4Error::PastEnd { at })?;
        buf.copy_from_slice(from);
        Ok(())
    }
}

impl<S: Source + ?Sized> Source for &mut S {
    fn size(&self) -> u64 {
        (**self).size()
    }

    fn read_at(&mut self, at: u64, buf: &mut [u8]) -> Result<(), Mf4Error> {
        (**self).read_at(at, buf)
    }
}

/// A block's header, checked: where its links and data lie in the file.
#[derive(Debug, Clone, Copy)]
pub(super) struct Head {
    /// Its offset in the file.
    pub(super) at: u64,
    /// Its identifier (`##DT`, ...).
    pub(super) id: [u8; 4],
    /// Its links: this many.
    pub(super) links: u64,
    /// Where its data section begins.
    pub(super) data: u64,
    /// Where it ends.
    pub(super) end: u64,
}

/// The header of the block at `at`, checked: the block lies inside the
/// file, its length holds its header and links, and its identifier is one
/// of `ids`.
pub(super) fn head(src: &mut dyn Source, at: u64, ids: &[[u8; 4]]) -> Result<Head, Mf4Error> {
    let mut h = [0u8; HEADER as usize];
    match src.read_at(at, &mut h[..8]) {
        Err(Mf4Error::PastEnd { .. }) => return Err(Mf4Error::PastEnd { at }),
        r => r?,
    }
    let [a, b, c, d, ..] = h;
    let id = [a, b, c, d];
    if !ids.contains(&id) {
        return Err(Mf4Error::UnexpectedBlock { at, found: id });
    }
    match src.read_at(at.saturating_add(8), &mut h[8..]) {
        Err(Mf4Error::PastEnd { .. }) => return Err(Mf4Error::PastEnd { at }),
        r => r?,
    }
    let length = u64_at(&h, 8);
    let links = u64_at(&h, 16);
    let data = links
        .checked_mul(8)
        .and_then(|l| l.checked_add(HEADER))
        .filter(|&end| end <= length)
        .ok_or(Mf4Error::BlockLength { at, length })?;
    let end = at
        .checked_add(length)
        .filter(|&end| end <= src.size())
        .ok_or(Mf4Error::PastEnd { at })?;
    Ok(Head {
        at,
        id,
        links,
        // data <= length: no overflow past `end`.
        data: at.saturating_add(data),
        end,
    })
}

/// One block read whole: its links and data.
#[derive(Debug, Clone)]
pub(super) struct Block {
    links: Vec<u8>,
    /// The data section (after the links).
    pub(super) data: Vec<u8>,
}

/// The block at `at`, read whole and checked as [`head`] checks it; a
/// block over [`MAX_BLOCK`] bytes is an error.
pub(super) fn block(src: &mut dyn Source, at: u64, ids: &[[u8; 4]]) -> Result<Block, Mf4Error> {
    let h = head(src, at, ids)?;
    let length = h.end.saturating_sub(at);
    if length > MAX_BLOCK {
        return Err(Mf4Error::BlockTooLong { at, length });
    }
    // At most MAX_BLOCK bytes: the casts hold.
    let mut links = vec![0u8; (h.links.saturating_mul(8)) as usize];
    let mut data = vec![0u8; h.end.saturating_sub(h.data) as usize];
    src.read_at(at.saturating_add(HEADER), &mut links)?;
    src.read_at(h.data, &mut data)?;
    Ok(Block { links, data })
}

impl Block {
    /// Link `i` (0 when the block has fewer links).
    pub(super) fn link(&self, i: usize) -> u64 {
        i.checked_mul(8).map_or(0, |at| u64_at(&self.links, at))
    }

    /// The number of links.
    pub(super) fn link_count(&self) -> usize {
        self.links.len() / 8
    }

    /// The data section's byte `at` (0 past its end).
    pub(super) fn u8(&self, at: usize) -> u8 {
        self.data.get(at).copied().unwrap_or(0)
    }

    /// The data section's little-endian u16 at `at`.
    pub(super) fn u16(&self, at: usize) -> u16 {
        u16::from_le_bytes([self.u8(at), self.u8(at.saturating_add(1))])
    }

    /// The data section's little-endian u32 at `at`.
    pub(super) fn u32(&self, at: usize) -> u32 {
        u32::from(self.u16(at)) | u32::from(self.u16(at.saturating_add(2))) << 16
    }

    /// The data section's little-endian u64 at `at`.
    pub(super) fn u64(&self, at: usize) -> u64 {
        u64_at(&self.data, at)
    }

    /// The data section's little-endian f64 at `at`.
    pub(super) fn f64(&self, at: usize) -> f64 {
        f64::from_bits(self.u64(at))
    }
}

/// The text of a `##TX` block (UTF-8 up to its first NUL); `None` for no
/// link, another block or text that is not UTF-8.
pub(super) fn text(src: &mut dyn Source, at: u64) -> Option<alloc::string::String> {
    if at == 0 {
        return None;
    }
    let mut b = block(src, at, &[*b"##TX"]).ok()?;
    let end = b.data.iter().position(|&c| c == 0).unwrap_or(b.data.len());
    b.data.truncate(end);
    alloc::string::String::from_utf8(b.data).ok()
}

/// Block identifiers.
pub(super) mod id {
    /// The header block.
    pub const HD: [u8; 4] = *b"##HD";
    /// A data group.
    pub const DG: [u8; 4] = *b"##DG";
    /// A channel group.
    pub const CG: [u8; 4] = *b"##CG";
    /// A channel.
    pub const CN: [u8; 4] = *b"##CN";
    /// A conversion.
    pub const CC: [u8; 4] = *b"##CC";
    /// Data (records).
    pub const DT: [u8; 4] = *b"##DT";
    /// Signal data (variable-length values).
    pub const SD: [u8; 4] = *b"##SD";
    /// Compressed data.
    pub const DZ: [u8; 4] = *b"##DZ";
    /// A data list.
    pub const DL: [u8; 4] = *b"##DL";
    /// A header list (of compressed data lists).
    pub const HL: [u8; 4] = *b"##HL";
}
