//! The blocks of an MDF 4 file as checked views over the file's bytes
//! (ASAM MDF 4.1/4.2, section 5 "Block types"): every block is its
//! 24-byte header (`##XX` identifier, 4 reserved bytes, length u64, link
//! count u64), its links (u64 file offsets, 0 for none) and its data; the
//! accessors read fields at the offsets the standard gives and cannot
//! index out of bounds (a field past the block's end reads as 0).

use super::Mf4Error;
use crate::trace::fields::u64_at;

/// The header every block but `##ID` begins with.
pub(super) const HEADER: u64 = 24;

/// One block: its place, links and data, borrowed from the file.
#[derive(Debug, Clone, Copy)]
pub(super) struct Block<'a> {
    /// Its offset in the file.
    pub(super) at: u64,
    /// Its identifier (`##DT`, ...).
    pub(super) id: [u8; 4],
    links: &'a [u8],
    /// The data section (after the links).
    pub(super) data: &'a [u8],
}

/// The block at `at`, checked: it lies inside the file, its length holds
/// its header and links, and its identifier is one of `ids`.
pub(super) fn block<'a>(file: &'a [u8], at: u64, ids: &[[u8; 4]]) -> Result<Block<'a>, Mf4Error> {
    let start = usize::try_from(at).map_err(|_| Mf4Error::PastEnd { at })?;
    let Some(&[a, b, c, d, _, _, _, _, ref rest @ ..]) = file.get(start..) else {
        return Err(Mf4Error::PastEnd { at });
    };
    let id = [a, b, c, d];
    if !ids.contains(&id) {
        return Err(Mf4Error::UnexpectedBlock { at, found: id });
    }
    let length = u64_at(rest, 0);
    let links = u64_at(rest, 8);
    if rest.len() < 16 {
        return Err(Mf4Error::PastEnd { at });
    }
    let links_end = links
        .checked_mul(8)
        .and_then(|l| l.checked_add(HEADER))
        .filter(|&end| end <= length)
        .ok_or(Mf4Error::BlockLength { at, length })?;
    let end = usize::try_from(length)
        .ok()
        .and_then(|l| start.checked_add(l))
        .filter(|&end| end <= file.len())
        .ok_or(Mf4Error::PastEnd { at })?;
    let whole = file.get(start..end).ok_or(Mf4Error::PastEnd { at })?;
    // links_end <= length, which fits the file: the casts and slices hold.
    let links_end = usize::try_from(links_end).map_err(|_| Mf4Error::PastEnd { at })?;
    Ok(Block {
        at,
        id,
        links: whole.get(24..links_end).unwrap_or(&[]),
        data: whole.get(links_end..).unwrap_or(&[]),
    })
}

impl<'a> Block<'a> {
    /// Link `i` (0 when the block has fewer links).
    pub(super) fn link(&self, i: usize) -> u64 {
        i.checked_mul(8).map_or(0, |at| u64_at(self.links, at))
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
        u64_at(self.data, at)
    }

    /// The data section's little-endian f64 at `at`.
    pub(super) fn f64(&self, at: usize) -> f64 {
        f64::from_bits(self.u64(at))
    }

    /// The data section from `at` on.
    pub(super) fn data_from(&self, at: usize) -> &'a [u8] {
        self.data.get(at..).unwrap_or(&[])
    }
}

/// The text of a `##TX` block (UTF-8 up to its first NUL); `None` for no
/// link, another block or text that is not UTF-8.
pub(super) fn text(file: &[u8], at: u64) -> Option<&str> {
    if at == 0 {
        return None;
    }
    let b = block(file, at, &[*b"##TX"]).ok()?;
    let end = b.data.iter().position(|&c| c == 0).unwrap_or(b.data.len());
    core::str::from_utf8(b.data.get(..end)?).ok()
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
