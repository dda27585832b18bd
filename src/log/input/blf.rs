//! Vector BLF input: the file read in blocks through
//! [`crate::trace::blf::BlfReader`], each zlib container inflated by the
//! caller's [`Inflate`] and handed back to it, every classic CAN frame an
//! item like a text trace's line. Memory stays bounded: one input block and one inflate block,
//! whatever the file's sizes say (the reader refuses a container that
//! inflates past its declared size as soon as it does).
//!
//! Objects are numbered from 1 in file order (containers not counted):
//! CAN FD and error frames are unsupported items; other objects are
//! skipped (counted); a malformed object is a bad item (the read goes on
//! when its size lets the reader skip it, and stops at an error of the
//! file's structure).

use std::io::{self, Read};
use std::prelude::rust_2021::*;
use std::vec;

use crate::trace::blf::{BlfError, BlfEvent, BlfReader, Compression};

pub use crate::trace::inflate::{Inflate, Inflated, NoInflate};

use super::{read_some, At, Bad, Counted, Detail, Item, Kind};

/// The input block.
const BLOCK: usize = 256 * 1024;
/// The inflate block.
const INFLATE: usize = 64 * 1024;

/// The objects of a file, by what became of them.
#[derive(Default)]
struct Count {
    /// Objects seen (the number of the last one).
    objects: u64,
    skipped: u64,
}

/// Hands one event on; false at a fatal error.
fn event<F: FnMut(Item<'_>) -> io::Result<()>>(
    e: Result<Option<BlfEvent<'_>>, BlfError>,
    count: &mut Count,
    each: &mut Counted<'_, F>,
) -> io::Result<bool> {
    match e {
        Ok(Some(BlfEvent::Frame(f))) => {
            count.objects += 1;
            each.give(Item::Frame {
                at: At::Object(count.objects),
                frame: f.trace_frame(),
            })?;
        }
        Ok(Some(BlfEvent::Unsupported {
            what,
            object_type,
            timestamp,
        })) => {
            count.objects += 1;
            each.give(Item::Unsupported {
                at: At::Object(count.objects),
                what,
                detail: Detail::ObjectType(object_type),
                timestamp,
                on_bus: None,
            })?;
        }
        Ok(Some(BlfEvent::Skipped { .. })) => {
            count.objects += 1;
            count.skipped += 1;
        }
        Ok(None | Some(_)) => {}
        Err(e) if e.is_fatal() => {
            each.give(Item::Bad {
                at: At::AfterObject(count.objects),
                why: Bad::Structure(e),
            })?;
            return Ok(false);
        }
        Err(e) => {
            count.objects += 1;
            each.give(Item::Bad {
                at: At::Object(count.objects),
                why: Bad::Object(e),
            })?;
        }
    }
    Ok(true)
}

/// The reader and the inflater of one file.
struct File<'z> {
    reader: BlfReader,
    zlib: &'z mut dyn Inflate,
    buf: Vec<u8>,
    count: Count,
}

/// Inflates one piece of a zlib container's payload into the reader;
/// false at a fatal error (of the reader or of zlib).
fn inflate<F: FnMut(Item<'_>) -> io::Result<()>>(
    mut z: &[u8],
    file: &mut File<'_>,
    each: &mut Counted<'_, F>,
) -> io::Result<bool> {
    let File {
        reader,
        zlib,
        buf,
        count,
    } = file;
    loop {
        let Inflated { used, made, end } = match zlib.inflate(z, buf) {
            Ok(s) => s,
            Err(e) => {
                each.give(Item::Bad {
                    at: At::AfterObject(count.objects),
                    why: Bad::Inflate(e),
                })?;
                return Ok(false);
            }
        };
        let made = made.min(buf.len());
        z = z.get(used..).unwrap_or(&[]);
        let mut inflated = buf.get(..made).unwrap_or(&[]);
        loop {
            match reader.read_inflated(&mut inflated) {
                Ok(None) => break,
                r => {
                    if !event(r, count, each)? {
                        return Ok(false);
                    }
                }
            }
        }
        let stuck = used == 0 && made == 0;
        if end || stuck || (z.is_empty() && made < buf.len()) {
            return Ok(true);
        }
    }
}

/// Reads the BLF file `input`, handing each item to `each`.
pub(super) fn read<F: FnMut(Item<'_>) -> io::Result<()>>(
    mut input: impl Read,
    zlib: &mut dyn Inflate,
    each: &mut Counted<'_, F>,
) -> io::Result<Kind> {
    let mut file = File {
        reader: BlfReader::new(),
        zlib,
        buf: vec![0u8; INFLATE],
        count: Count::default(),
    };
    let mut block = vec![0u8; BLOCK];
    let mut going = true;
    'file: while going {
        let n = read_some(&mut input, &mut block)?;
        if n == 0 {
            break;
        }
        let mut chunk = block.get(..n).unwrap_or(&[]);
        loop {
            match file.reader.read(&mut chunk) {
                Ok(None) => break,
                Ok(Some(BlfEvent::ContainerStart {
                    compression: Compression::Zlib,
                    ..
                })) => file.zlib.reset(),
                Ok(Some(BlfEvent::Compressed(z))) => {
                    if !inflate(z, &mut file, each)? {
                        going = false;
                        break 'file;
                    }
                }
                r => {
                    if !event(r, &mut file.count, each)? {
                        going = false;
                        break 'file;
                    }
                }
            }
        }
    }
    if going {
        if let Err(e) = file.reader.finish() {
            each.give(Item::Bad {
                at: At::AfterObject(file.count.objects),
                why: Bad::End(e),
            })?;
        }
    }
    Ok(Kind::Binary {
        binary: super::Binary::Blf,
        objects: file.count.objects,
        skipped: file.count.skipped,
    })
}
