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

use super::blocks::{block, id, Block, HEADER};
use super::Mf4Error;
use crate::trace::inflate::Inflate;

/// The most of a `##DT` block copied at once.
pub const WINDOW: usize = 1 << 20;
/// The largest original length of a `##DZ` block inflated (writers keep
/// them to a few MiB: asammdf to 4 MiB).
pub const MAX_INFLATED: u64 = 64 << 20;
/// The piece inflated at a time.
const PIECE: usize = 64 * 1024;

/// Where the stream is in its chain of blocks.
#[derive(Debug, Clone, Copy)]
enum Chain {
    /// No more blocks.
    Done,
    /// One block (the data group's own link), not yet read.
    One(u64),
    /// A `##DL` block and the index of its next data link.
    List { at: u64, next: usize },
}

/// One data group's records as a stream of bytes.
#[derive(Debug)]
pub(super) struct Stream<'a> {
    file: &'a [u8],
    chain: Chain,
    /// The `##DT` being copied in windows: its data not yet copied.
    dt: &'a [u8],
    buf: Vec<u8>,
    pos: usize,
    /// Blocks of the chain left to visit (against link cycles).
    hops: u64,
    /// The uncompressed block type: `##DT` (records) or `##SD` (signal
    /// data: a u32 length and that many bytes, per value).
    leaf: [u8; 4],
}

impl<'a> Stream<'a> {
    /// The stream of the data group whose data link is `data` (0: no
    /// records).
    pub(super) fn new(file: &'a [u8], data: u64) -> Self {
        Self::of(file, data, id::DT)
    }

    /// The stream of a variable-length channel's signal data (its
    /// `cn_data` link: `##SD`, a `##DZ` of one, or a list of them).
    pub(super) fn signal(file: &'a [u8], data: u64) -> Self {
        Self::of(file, data, id::SD)
    }

    fn of(file: &'a [u8], data: u64, leaf: [u8; 4]) -> Self {
        Stream {
            file,
            chain: if data == 0 {
                Chain::Done
            } else {
                Chain::One(data)
            },
            dt: &[],
            buf: Vec::new(),
            pos: 0,
            hops: file.len() as u64 / HEADER + 1,
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
        zlib: &mut dyn Inflate,
    ) -> Result<Option<&[u8]>, Mf4Error> {
        while self.buf.len().saturating_sub(self.pos) < n {
            if !self.more(zlib)? {
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
    pub(super) fn skip(&mut self, mut n: u64, zlib: &mut dyn Inflate) -> Result<(), Mf4Error> {
        loop {
            let have = self.buf.len().saturating_sub(self.pos) as u64;
            if have >= n {
                self.pos = self.pos.saturating_add(n as usize);
                return Ok(());
            }
            n -= have;
            self.pos = self.buf.len();
            if !self.more(zlib)? {
                return Err(Mf4Error::RecordPastEnd {
                    need: usize::try_from(n).unwrap_or(usize::MAX),
                    left: 0,
                });
            }
        }
    }

    /// Appends the next piece of data to the buffer (what is read
    /// dropped first); false at the end of the chain.
    fn more(&mut self, zlib: &mut dyn Inflate) -> Result<bool, Mf4Error> {
        self.buf.drain(..self.pos.min(self.buf.len()));
        self.pos = 0;
        loop {
            if !self.dt.is_empty() {
                let (piece, rest) = self.dt.split_at(self.dt.len().min(WINDOW));
                self.buf.extend_from_slice(piece);
                self.dt = rest;
                return Ok(true);
            }
            let Some(at) = self.next_block()? else {
                return Ok(false);
            };
            let b = block(self.file, at, &[self.leaf, id::DZ])?;
            if b.id == self.leaf {
                self.dt = b.data;
            } else {
                let before = self.buf.len();
                inflate_dz(&b, self.leaf, &mut self.buf, zlib)?;
                if self.buf.len() > before {
                    return Ok(true);
                }
            }
        }
    }

    /// The offset of the chain's next data block.
    fn next_block(&mut self) -> Result<Option<u64>, Mf4Error> {
        loop {
            self.hops = self
                .hops
                .checked_sub(1)
                .ok_or(Mf4Error::LinkCycle { what: "data list" })?;
            match self.chain {
                Chain::Done => return Ok(None),
                Chain::One(at) => {
                    let b = block(self.file, at, &[self.leaf, id::DZ, id::DL, id::HL])?;
                    self.chain = if b.id == id::HL {
                        match b.link(0) {
                            0 => Chain::Done,
                            dl => Chain::List { at: dl, next: 0 },
                        }
                    } else if b.id == id::DL {
                        Chain::List { at, next: 0 }
                    } else {
                        self.chain = Chain::Done;
                        return Ok(Some(at));
                    };
                }
                Chain::List { at, next } => {
                    let dl = block(self.file, at, &[id::DL])?;
                    // dl_dl_next, then dl_count data links.
                    let count = (dl.u32(4) as usize).min(dl.link_count().saturating_sub(1));
                    if next < count {
                        self.chain = Chain::List { at, next: next + 1 };
                        match dl.link(next + 1) {
                            0 => {}
                            data => return Ok(Some(data)),
                        }
                    } else {
                        self.chain = match dl.link(0) {
                            0 => Chain::Done,
                            next_dl => Chain::List {
                                at: next_dl,
                                next: 0,
                            },
                        };
                    }
                }
            }
        }
    }
}

/// Inflates the `##DZ` block `b` (of a `leaf`: `##DT` or `##SD`) onto `out`: deflate (zip
/// type 0) or transposed deflate (1: the records' bytes stored column by
/// column, `dz_zip_parameter` columns; the bytes past the last whole row
/// as they are), ASAM MDF 4.1 section 5.26.
pub(super) fn inflate_dz(
    b: &Block<'_>,
    leaf: [u8; 4],
    out: &mut Vec<u8>,
    zlib: &mut dyn Inflate,
) -> Result<(), Mf4Error> {
    let at = b.at;
    let original = [b.u8(0), b.u8(1)];
    if original != [leaf[2], leaf[3]] {
        return Err(Mf4Error::UnexpectedBlock {
            at,
            found: [b'#', b'#', original[0], original[1]],
        });
    }
    let zip = b.u8(2);
    let columns = b.u32(4) as usize;
    let declared = b.u64(8);
    let compressed_len = b.u64(16);
    if declared > MAX_INFLATED {
        return Err(Mf4Error::BlockTooLarge { at, size: declared });
    }
    let compressed = b.data_from(24);
    let compressed = usize::try_from(compressed_len)
        .ok()
        .and_then(|n| compressed.get(..n))
        .ok_or(Mf4Error::PastEnd { at })?;
    // Inflated in pieces, so a block that declares much and holds little
    // costs what it holds (declared <= MAX_INFLATED fits usize).
    let size = declared as usize;
    let mut raw = Vec::new();
    let mut piece = vec![0u8; PIECE.min(size.max(1))];
    zlib.reset();
    let mut used = 0usize;
    loop {
        let input = compressed.get(used..).unwrap_or(&[]);
        let r = zlib
            .inflate(input, &mut piece)
            .map_err(|_| Mf4Error::Inflate { at })?;
        used = used.saturating_add(r.used).min(compressed.len());
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
