//! ASAM MDF 4 bus-logging input: a file that seeks read in place
//! ([`SeekSource`]: its data blocks as they are reached, memory constant in
//! the file's size); any other input (a pipe, a gzip-compressed file) read
//! into memory when it is at most [`IN_MEMORY`] bytes long, else copied to
//! a temporary file first and read in place from there (module `spill`:
//! its blocks link to anywhere in it, the describing ones after the data
//! in the files python-can and asammdf write); then read through
//! [`crate::trace::mf4::Mf4Reader`] record by record, each `##DZ` block
//! inflated by the caller's [`Inflate`]; every classic CAN frame an item
//! like a text trace's line, in time order. Besides the file, memory stays
//! bounded by one data block per data group.
//!
//! Records of the bus-logging channel groups are numbered from 1 in the
//! order read: CAN FD, error frames and other CAN events are unsupported
//! items; a malformed record is a bad item (the read goes on); an error of
//! the file's structure (a block past the end, links that loop, a block
//! that does not inflate) ends the read.

use std::io::{self, Read, Seek};
use std::path::Path;
use std::prelude::rust_2021::*;

use crate::trace::mf4::{Mf4Error, Mf4Event, Mf4Reader, SeekSource, Source};

use super::spill::Spill;
use super::{At, Bad, Binary, Counted, Item, Kind};
use crate::trace::inflate::Inflate;

/// The longest MF4 read from input that cannot seek held in memory: a
/// longer one is copied to a temporary file (1 MiB, the order of the
/// reader's own windows).
pub(super) const IN_MEMORY: usize = 1 << 20;

/// Reads the MF4 file `input` (in memory, or spilled to a temporary file
/// of the system's temporary folder), handing each item to `each`.
pub(super) fn read<F: FnMut(Item<'_>) -> io::Result<()>>(
    input: impl Read,
    zlib: &mut dyn Inflate,
    each: &mut Counted<'_, F>,
) -> io::Result<Kind> {
    read_spilling(input, IN_MEMORY, &std::env::temp_dir(), zlib, each)
}

/// [`read`] with the most held in memory and the temporary folder given.
pub(super) fn read_spilling<F: FnMut(Item<'_>) -> io::Result<()>>(
    mut input: impl Read,
    in_memory: usize,
    dir: &Path,
    zlib: &mut dyn Inflate,
    each: &mut Counted<'_, F>,
) -> io::Result<Kind> {
    let mut first = Vec::new();
    let limit = u64::try_from(in_memory).map_or(u64::MAX, |n| n.saturating_add(1));
    (&mut input).take(limit).read_to_end(&mut first)?;
    if first.len() <= in_memory {
        return items(&first, zlib, each);
    }
    let mut spill = Spill::copy(dir, &first, &mut input)?;
    drop(first);
    read_in_place(spill.file()?, zlib, each)
}

/// Reads the MF4 file `file` in place, handing each item to `each`; an
/// error reading the file is returned.
pub(super) fn read_in_place<F: FnMut(Item<'_>) -> io::Result<()>>(
    file: impl Read + Seek,
    zlib: &mut dyn Inflate,
    each: &mut Counted<'_, F>,
) -> io::Result<Kind> {
    let mut src = SeekSource::new(file)?;
    let kind = items(&mut src, zlib, each);
    match src.take_error() {
        Some(e) => Err(e),
        None => kind,
    }
}

/// The items of the MF4 file `src`: an error reading it ends the read
/// (the caller returns the I/O error).
fn items<S: Source, F: FnMut(Item<'_>) -> io::Result<()>>(
    src: S,
    zlib: &mut dyn Inflate,
    each: &mut Counted<'_, F>,
) -> io::Result<Kind> {
    let mut records = 0u64;
    let kind = |records| Kind::Binary {
        binary: Binary::Mf4,
        objects: records,
        skipped: 0,
    };
    let read_error = |e| io::Error::other(format!("{e}"));
    let mut reader = match Mf4Reader::new(src) {
        Ok(r) => r,
        Err(e @ Mf4Error::Read { .. }) => return Err(read_error(e)),
        Err(e) => {
            each.give(Item::Bad {
                at: At::AfterRecord(0),
                why: Bad::Mf4Structure(e),
            })?;
            return Ok(kind(0));
        }
    };
    loop {
        match reader.next(zlib) {
            Ok(None) => break,
            Ok(Some(Mf4Event::Frame(f))) => {
                records += 1;
                each.give(Item::Frame {
                    at: At::Record(records),
                    frame: f.trace_frame(),
                })?;
            }
            Ok(Some(Mf4Event::Unsupported { what, timestamp })) => {
                records += 1;
                each.give(Item::Unsupported {
                    at: At::Record(records),
                    what,
                    detail: super::Detail::Record,
                    timestamp,
                    on_bus: None,
                })?;
            }
            Err(e @ Mf4Error::Read { .. }) => return Err(read_error(e)),
            Err(e) if e.is_fatal() => {
                each.give(Item::Bad {
                    at: At::AfterRecord(records),
                    why: Bad::Mf4Structure(e),
                })?;
                break;
            }
            Err(e) => {
                records += 1;
                each.give(Item::Bad {
                    at: At::Record(records),
                    why: Bad::Mf4Record(e),
                })?;
            }
        }
    }
    Ok(kind(records))
}
