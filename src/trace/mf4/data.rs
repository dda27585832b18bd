//! The bytes of one data group's records as one stream (ASAM MDF 4.1,
//! sections 5.21 to 5.26): the data group's link names a `##DT` block
//! (records), a `##DZ` block (a `##DT` compressed with deflate, or
//! transposed then deflated), a `##DL` list of such blocks (its own
//! `dl_dl_next` chain) or a `##HL` header list of a `##DL`. A record may
//! span two blocks of a list.
//!
//! Memory stays bounded by one block: a `##DT` is copied in windows of at
//! most [`WINDOW`] bytes; a `##DZ` is inflated whole (its original length
//! must be at most [`MAX_INFLATED`]); the bytes of a record begun in one
//! block wait for the next.

use alloc::vec;
use alloc::vec::Vec;

use super::blocks::{block, head, id, Head, Source, HEADER};
use super::Mf4Error;
use crate::trace::fields::{u32_at, u64_at};
use crate::trace::inflate::Inflate;

/// The most of a `##DT` block copied at once.
pub const WINDOW: usize = 1 << 20;
/// The largest original length of a `##DZ` block inflated (writers keep
/// them to a few MiB: asammdf to 4 MiB).
pub const MAX_INFLATED: u64 = 64 << 20;
/// The piece read or inflated at a time.
const PIECE: usize = 64 * 1024;

/// Where the stream is in its chain of blocks.
#[derive(Debug, Clone)]
enum Chain {
    /// No more blocks.
    Done,
    /// One block (the data group's own link), not yet read.
    One(u64),
    /// A `##DL` block's data links, the index of the next one, and the
    /// next `##DL` of the chain (0: none).
    List {
        links: Vec<u64>,
        next: usize,
        next_list: u64,
    },
}

/// One data group's records as a stream of bytes.
#[derive(Debug)]
pub(super) struct Stream {
    chain: Chain,
    /// The `##DT` being copied in windows: where its data not yet copied
    /// begins and where it ends.
    dt: (u64, u64),
    /// The bytes read ahead: `buf[pos..end]` not yet taken (the buffer
    /// keeps its length, so that it is not filled again before each
    /// read).
    buf: Vec<u8>,
    pos: usize,
    end: usize,
    /// A transposed `##DZ` block inflated, before it is turned back into
    /// records (kept for the next one).
    spare: Vec<u8>,
    /// Blocks of the chain left to visit (against link cycles).
    hops: u64,
    /// The uncompressed block type: `##DT` (records) or `##SD` (signal
    /// data: a u32 length and that many bytes, per value).
    leaf: [u8; 4],
}

impl Stream {
    /// The stream of the data group whose data link is `data` (0: no
    /// records), in a file of `size` bytes.
    pub(super) fn new(size: u64, data: u64) -> Self {
        Self::of(size, data, id::DT)
    }

    /// The stream of a variable-length channel's signal data (its
    /// `cn_data` link: `##SD`, a `##DZ` of one, or a list of them).
    pub(super) fn signal(size: u64, data: u64) -> Self {
        Self::of(size, data, id::SD)
    }

    fn of(size: u64, data: u64, leaf: [u8; 4]) -> Self {
        Stream {
            chain: if data == 0 {
                Chain::Done
            } else {
                Chain::One(data)
            },
            dt: (0, 0),
            buf: Vec::new(),
            pos: 0,
            end: 0,
            spare: Vec::new(),
            hops: size / HEADER + 1,
            leaf,
        }
    }

    /// The bytes it holds (its buffer, as long as the most read ahead or
    /// inflated at once, and the room kept for a transposed block).
    pub(super) fn held(&self) -> usize {
        self.buf.len().saturating_add(self.spare.len())
    }

    /// The next `n` bytes; `None` at the end of the data (an error when
    /// it ends inside them).
    pub(super) fn take(
        &mut self,
        n: usize,
        src: &mut dyn Source,
        zlib: &mut dyn Inflate,
    ) -> Result<Option<&[u8]>, Mf4Error> {
        while self.end.saturating_sub(self.pos) < n {
            if !self.more(src, zlib)? {
                let left = self.end.saturating_sub(self.pos);
                if left == 0 {
                    return Ok(None);
                }
                return Err(Mf4Error::RecordPastEnd { need: n, left });
            }
        }
        let start = self.pos;
        self.pos = start.saturating_add(n);
        Ok(self.buf.get(start..self.pos))
    }

    /// Skips `n` bytes (a record not read), piece by piece.
    pub(super) fn skip(
        &mut self,
        mut n: u64,
        src: &mut dyn Source,
        zlib: &mut dyn Inflate,
    ) -> Result<(), Mf4Error> {
        loop {
            let have = self.end.saturating_sub(self.pos) as u64;
            if have >= n {
                self.pos = self.pos.saturating_add(n as usize);
                return Ok(());
            }
            n -= have;
            self.pos = self.end;
            if !self.more(src, zlib)? {
                return Err(Mf4Error::RecordPastEnd {
                    need: usize::try_from(n).unwrap_or(usize::MAX),
                    left: 0,
                });
            }
        }
    }

    /// Appends the next piece of data to the buffer (what is read
    /// dropped first); false at the end of the chain.
    fn more(&mut self, src: &mut dyn Source, zlib: &mut dyn Inflate) -> Result<bool, Mf4Error> {
        let (pos, end) = (self.pos.min(self.end), self.end);
        if end <= self.buf.len() {
            self.buf.copy_within(pos..end, 0);
        }
        (self.pos, self.end) = (0, end - pos);
        loop {
            let (from, to) = self.dt;
            if from < to {
                // At most WINDOW: the cast holds.
                let n = (to - from).min(WINDOW as u64) as usize;
                let filled = self.end.saturating_add(n);
                if self.buf.len() < filled {
                    self.buf.resize(filled, 0);
                }
                if let Some(window) = self.buf.get_mut(self.end..filled) {
                    src.read_at(from, window)?;
                }
                self.end = filled;
                self.dt = (from.saturating_add(n as u64), to);
                return Ok(true);
            }
            let Some(at) = self.next_block(src)? else {
                return Ok(false);
            };
            let h = head(src, at, &[self.leaf, id::DZ])?;
            if h.id == self.leaf {
                self.dt = (h.data, h.end);
            } else {
                let out = (&mut self.buf, self.end);
                let made = inflate_dz(src, &h, self.leaf, out, &mut self.spare, zlib)?;
                self.end = self.end.saturating_add(made);
                if made > 0 {
                    return Ok(true);
                }
            }
        }
    }

    /// The offset of the chain's next data block.
    fn next_block(&mut self, src: &mut dyn Source) -> Result<Option<u64>, Mf4Error> {
        loop {
            self.hops = self
                .hops
                .checked_sub(1)
                .ok_or(Mf4Error::LinkCycle { what: "data list" })?;
            let list_at = match &mut self.chain {
                Chain::Done => return Ok(None),
                Chain::One(at) => {
                    let at = *at;
                    let h = head(src, at, &[self.leaf, id::DZ, id::DL, id::HL])?;
                    if h.id == id::HL {
                        block(src, at, &[id::HL])?.link(0)
                    } else if h.id == id::DL {
                        at
                    } else {
                        self.chain = Chain::Done;
                        return Ok(Some(at));
                    }
                }
                Chain::List {
                    links,
                    next,
                    next_list,
                } => {
                    if let Some(&data) = links.get(*next) {
                        *next += 1;
                        if data != 0 {
                            return Ok(Some(data));
                        }
                        continue;
                    }
                    *next_list
                }
            };
            self.chain = if list_at == 0 {
                Chain::Done
            } else {
                let dl = block(src, list_at, &[id::DL])?;
                // dl_dl_next, then dl_count data links.
                let count = (dl.u32(4) as usize).min(dl.link_count().saturating_sub(1));
                Chain::List {
                    links: (1..=count).map(|i| dl.link(i)).collect(),
                    next: 0,
                    next_list: dl.link(0),
                }
            };
        }
    }
}

/// Inflates the `##DZ` block `b` (of a `leaf`: `##DT` or `##SD`) into
/// `out.0` from byte `out.1` on, and says how many bytes it made: deflate
/// (zip type 0) or transposed deflate (1: the records' bytes stored column
/// by column, `dz_zip_parameter` columns; the bytes past the last whole
/// row as they are), ASAM MDF 4.1 section 5.26. A transposed block is
/// inflated into `spare` (kept for the next block), then turned back into
/// records. The buffers grow when the block needs it, never shrink.
pub(super) fn inflate_dz(
    src: &mut dyn Source,
    b: &Head,
    leaf: [u8; 4],
    (out, base): (&mut Vec<u8>, usize),
    spare: &mut Vec<u8>,
    zlib: &mut dyn Inflate,
) -> Result<usize, Mf4Error> {
    let at = b.at;
    // dz_org_block_type (2), dz_zip_type, reserved, dz_zip_parameter (u32),
    // dz_org_data_length (u64), dz_data_length (u64).
    let mut fixed = [0u8; 24];
    if b.end.saturating_sub(b.data) < 24 {
        return Err(Mf4Error::PastEnd { at });
    }
    src.read_at(b.data, &mut fixed)?;
    let original = [fixed[0], fixed[1]];
    if original != [leaf[2], leaf[3]] {
        return Err(Mf4Error::UnexpectedBlock {
            at,
            found: [b'#', b'#', original[0], original[1]],
        });
    }
    let zip = fixed[2];
    let columns = u32_at(&fixed, 4) as usize;
    let declared = u64_at(&fixed, 8);
    let compressed_len = u64_at(&fixed, 16);
    if declared > MAX_INFLATED {
        return Err(Mf4Error::BlockTooLarge { at, size: declared });
    }
    if zip > 1 {
        return Err(Mf4Error::UnknownZip { at, zip_type: zip });
    }
    let from = b.data.saturating_add(24);
    let compressed = from
        .checked_add(compressed_len)
        .filter(|&end| end <= b.end)
        .map(|end| (from, end))
        .ok_or(Mf4Error::PastEnd { at })?;
    // declared <= MAX_INFLATED fits usize.
    let size = declared as usize;
    if zip == 0 || columns == 0 {
        inflate(src, at, compressed, size, (out, base), zlib)?;
        return Ok(size);
    }
    inflate(src, at, compressed, size, (spare, 0), zlib)?;
    let end = base.saturating_add(size);
    if out.len() < end {
        out.resize(end, 0);
    }
    let raw = spare.get(..size).unwrap_or(&[]);
    untranspose(raw, columns, out.get_mut(base..end).unwrap_or(&mut []));
    Ok(size)
}

/// Inflates the zlib stream at `compressed` (its first byte and its end
/// in the file) of the block at `at` into `out.0` from byte `out.1` on:
/// exactly `size` bytes, or the error. The buffer grows as the bytes are
/// made (doubling from [`PIECE`]), so a block that declares much and
/// holds little costs what it holds.
fn inflate(
    src: &mut dyn Source,
    at: u64,
    (mut next, end): (u64, u64),
    size: usize,
    (out, base): (&mut Vec<u8>, usize),
    zlib: &mut dyn Inflate,
) -> Result<(), Mf4Error> {
    let before = out.len();
    // One byte of room past `size`, so that a stream inflating to more is
    // seen.
    let limit = base.saturating_add(size).saturating_add(1);
    let mut made = base;
    // The compressed bytes, read a piece at a time: `input[used..have]`
    // not yet inflated, `next` the file's next compressed byte.
    let mut input = vec![0u8; end.saturating_sub(next).min(PIECE as u64) as usize];
    let (mut used, mut have) = (0usize, 0usize);
    zlib.reset();
    let result = loop {
        if used == have && next < end {
            // At most PIECE: the cast holds.
            have = (end - next).min(PIECE as u64) as usize;
            used = 0;
            let to = input.get_mut(..have).unwrap_or(&mut []);
            if let Err(e) = src.read_at(next, to) {
                break Err(Some(e));
            }
            next = next.saturating_add(have as u64);
        }
        if made >= out.len() {
            let grown = made.saturating_add(PIECE.max(made - base)).min(limit);
            out.resize(grown, 0);
        }
        let pending = input.get(used..have).unwrap_or(&[]);
        let room = out.get_mut(made..).unwrap_or(&mut []);
        let Ok(r) = zlib.inflate(pending, room) else {
            break Err(Some(Mf4Error::Inflate { at }));
        };
        used = used.saturating_add(r.used).min(have);
        made = made.saturating_add(r.made).min(out.len());
        if made - base > size {
            break Err(None);
        }
        if r.end || (r.used == 0 && r.made == 0) {
            break Ok(());
        }
    };
    // What grew past the bytes made (the byte of room) goes.
    out.truncate(before.max(made));
    let inflated = made - base;
    match result {
        Ok(()) if inflated == size => Ok(()),
        Err(Some(e)) => Err(e),
        _ => Err(Mf4Error::InflatedSize {
            at,
            declared: size as u64,
            inflated: inflated as u64,
        }),
    }
}

/// Rows turned back at a time: their records (a few KiB) stay in the
/// first-level cache while eight columns at a time are read along.
const TILE: usize = 256;

/// Turns the bytes of a transposed block back into records (ASAM MDF 4.1
/// section 5.26): `raw` holds `rows = raw.len() / columns` bytes of each
/// column in turn (column `c` of row `r` at `c * rows + r`), then the
/// bytes past the last whole row as they are; `out`, as long as `raw`,
/// gets the rows one after the other, then those bytes. [`TILE`] rows at
/// a time, eight columns by eight rows as one 8 x 8 byte transposition
/// (eight columns read in order, which the processor reads ahead).
fn untranspose(raw: &[u8], columns: usize, out: &mut [u8]) {
    if columns == 0 || columns > raw.len() {
        // No whole row: the bytes as they are.
        if out.len() == raw.len() {
            out.copy_from_slice(raw);
        }
        return;
    }
    let rows = raw.len() / columns;
    // Inside raw: no product or sum below overflows.
    let whole = rows * columns;
    if let (Some(to), Some(from)) = (out.get_mut(whole..), raw.get(whole..)) {
        if to.len() == from.len() {
            to.copy_from_slice(from);
        }
    }
    let body = out.get_mut(..whole).unwrap_or(&mut []);
    // The columns turned back eight at a time.
    let wide = columns - columns % 8;
    for (t, tile) in body.chunks_mut(TILE * columns).enumerate() {
        let r0 = t * TILE;
        for c in (0..wide).step_by(8) {
            for (g, block) in tile.chunks_exact_mut(8 * columns).enumerate() {
                let r = r0 + 8 * g;
                let mut w = [0u64; 8];
                for (i, w) in w.iter_mut().enumerate() {
                    let at = (c + i) * rows + r;
                    *w = raw
                        .get(at..at + 8)
                        .and_then(|b| b.first_chunk())
                        .map_or(0, |b| u64::from_le_bytes(*b));
                }
                for (row, w) in block.chunks_exact_mut(columns).zip(transpose8(w)) {
                    if let Some(to) = row.get_mut(c..c + 8) {
                        to.copy_from_slice(&w.to_le_bytes());
                    }
                }
            }
        }
        // The other columns, and every column of the rows past the last
        // eight, byte by byte.
        let eights = tile.len() / columns / 8 * 8;
        for (k, row) in tile.chunks_exact_mut(columns).enumerate() {
            let from = if k < eights { wide } else { 0 };
            for (c, to) in row.iter_mut().enumerate().skip(from) {
                *to = raw.get(c * rows + r0 + k).copied().unwrap_or(0);
            }
        }
    }
}

/// Transposes the 8 x 8 bytes of `w` (byte `j` of word `i` to byte `i`
/// of word `j`): the 4 x 4 blocks off the diagonal swapped, then the
/// 2 x 2 blocks in each of them, then the bytes.
fn transpose8(w: [u64; 8]) -> [u64; 8] {
    /// Swaps, between each word `i` without bit `apart` and word
    /// `i | apart`, the bytes of the first above `shift` in `mask` with
    /// those of the second in `mask`.
    #[inline(always)]
    fn swap(w: [u64; 8], apart: usize, shift: u32, mask: u64) -> [u64; 8] {
        let mut out = w;
        for (i, o) in out.iter_mut().enumerate() {
            let other = w.get(i ^ apart).copied().unwrap_or(0);
            *o = if i & apart == 0 {
                *o ^ ((((*o >> shift) ^ other) & mask) << shift)
            } else {
                *o ^ (((other >> shift) ^ *o) & mask)
            };
        }
        out
    }
    let w = swap(w, 4, 32, 0x0000_0000_FFFF_FFFF);
    let w = swap(w, 2, 16, 0x0000_FFFF_0000_FFFF);
    swap(w, 1, 8, 0x00FF_00FF_00FF_00FF)
}

#[cfg(test)]
mod tests {
    use super::untranspose;
    use alloc::vec::Vec;

    /// Column `c` of row `r` at `c * rows + r`, the tail as it is: what a
    /// writer stores (ASAM MDF 4.1 section 5.26), written the plain way.
    fn transposed(records: &[u8], columns: usize) -> Vec<u8> {
        let rows = records.len() / columns;
        let mut t = Vec::new();
        for c in 0..columns {
            for r in 0..rows {
                t.push(records[r * columns + c]);
            }
        }
        t.extend_from_slice(&records[rows * columns..]);
        t
    }

    #[test]
    fn transposed_blocks_of_any_shape_turn_back_into_their_records() {
        // Byte values that differ between neighbours and repeat rarely.
        let records: Vec<u8> = (0..1000u32).map(|i| (i * 7 + i / 251) as u8).collect();
        for columns in 1..=27 {
            for len in (0..200).chain([999, 1000]) {
                let records = &records[..len];
                let raw = transposed(records, columns);
                let mut out = vec![0xAA; len];
                untranspose(&raw, columns, &mut out);
                assert_eq!(out, records, "{columns} columns, {len} bytes");
            }
        }
    }
}
