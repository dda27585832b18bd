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
    buf: Vec<u8>,
    pos: usize,
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
            hops: size / HEADER + 1,
            leaf,
        }
    }

    /// The bytes it holds (read ahead, inflated).
    pub(super) fn held(&self) -> usize {
        self.buf.len()
    }

    /// The next `n` bytes; `None` at the end of the data (an error when
    /// it ends inside them).
    pub(super) fn take(
        &mut self,
        n: usize,
        src: &mut dyn Source,
        zlib: &mut dyn Inflate,
    ) -> Result<Option<&[u8]>, Mf4Error> {
        while self.buf.len().saturating_sub(self.pos) < n {
            if !self.more(src, zlib)? {
                let left = self.buf.len().saturating_sub(self.pos);
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
            let have = self.buf.len().saturating_sub(self.pos) as u64;
            if have >= n {
                self.pos = self.pos.saturating_add(n as usize);
                return Ok(());
            }
            n -= have;
            self.pos = self.buf.len();
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
        self.buf.drain(..self.pos.min(self.buf.len()));
        self.pos = 0;
        loop {
            let (from, end) = self.dt;
            if from < end {
                // At most WINDOW: the cast holds.
                let n = (end - from).min(WINDOW as u64) as usize;
                let old = self.buf.len();
                self.buf.resize(old.saturating_add(n), 0);
                if let Some(to) = self.buf.get_mut(old..) {
                    src.read_at(from, to)?;
                }
                self.dt = (from.saturating_add(n as u64), end);
                return Ok(true);
            }
            let Some(at) = self.next_block(src)? else {
                return Ok(false);
            };
            let h = head(src, at, &[self.leaf, id::DZ])?;
            if h.id == self.leaf {
                self.dt = (h.data, h.end);
            } else {
                let before = self.buf.len();
                inflate_dz(src, &h, self.leaf, &mut self.buf, zlib)?;
                if self.buf.len() > before {
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

/// Inflates the `##DZ` block `b` (of a `leaf`: `##DT` or `##SD`) onto `out`: deflate (zip
/// type 0) or transposed deflate (1: the records' bytes stored column by
/// column, `dz_zip_parameter` columns; the bytes past the last whole row
/// as they are), ASAM MDF 4.1 section 5.26.
pub(super) fn inflate_dz(
    src: &mut dyn Source,
    b: &Head,
    leaf: [u8; 4],
    out: &mut Vec<u8>,
    zlib: &mut dyn Inflate,
) -> Result<(), Mf4Error> {
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
    let from = b.data.saturating_add(24);
    let compressed_end = from
        .checked_add(compressed_len)
        .filter(|&end| end <= b.end)
        .ok_or(Mf4Error::PastEnd { at })?;
    // Inflated in pieces, so a block that declares much and holds little
    // costs what it holds (declared <= MAX_INFLATED fits usize).
    let size = declared as usize;
    let mut raw = Vec::new();
    let mut piece = vec![0u8; PIECE.min(size.max(1))];
    // The compressed bytes, read a piece at a time: `input[used..have]`
    // not yet inflated, `next` the file's next compressed byte.
    let mut input = vec![0u8; PIECE];
    let (mut used, mut have, mut next) = (0usize, 0usize, from);
    zlib.reset();
    loop {
        if used == have && next < compressed_end {
            // At most PIECE: the cast holds.
            have = (compressed_end - next).min(PIECE as u64) as usize;
            used = 0;
            let to = input.get_mut(..have).unwrap_or(&mut []);
            src.read_at(next, to)?;
            next = next.saturating_add(have as u64);
        }
        let pending = input.get(used..have).unwrap_or(&[]);
        let r = zlib
            .inflate(pending, &mut piece)
            .map_err(|_| Mf4Error::Inflate { at })?;
        used = used.saturating_add(r.used).min(have);
        raw.extend_from_slice(piece.get(..r.made).unwrap_or(&piece));
        if raw.len() > size {
            return Err(Mf4Error::InflatedSize {
                at,
                declared,
                inflated: raw.len() as u64,
            });
        }
        if r.end || (r.used == 0 && r.made == 0) {
            break;
        }
    }
    let made = raw.len();
    if made != size {
        return Err(Mf4Error::InflatedSize {
            at,
            declared,
            inflated: made as u64,
        });
    }
    match zip {
        0 => out.extend_from_slice(&raw),
        1 if columns > 0 => {
            let rows = size / columns;
            let whole = rows * columns;
            out.reserve(size);
            for r in 0..rows {
                for c in 0..columns {
                    out.push(raw.get(c * rows + r).copied().unwrap_or(0));
                }
            }
            out.extend_from_slice(raw.get(whole..).unwrap_or(&[]));
        }
        1 => out.extend_from_slice(&raw),
        zip_type => return Err(Mf4Error::UnknownZip { at, zip_type }),
    }
    Ok(())
}
