//! Vector BLF input: the file read in blocks through the library's
//! `trace::blf::BlfReader`, each zlib container inflated here (flate2) and
//! handed back to it, every classic CAN frame decoded like a text trace's
//! line. Memory stays bounded: one input block and one inflate block,
//! whatever the file's sizes say (the reader refuses a container that
//! inflates past its declared size as soon as it does).
//!
//! Objects are numbered from 1 in file order (containers not counted) for
//! the messages on stderr: CAN FD and error frames are reported and
//! counted, not decoded; other objects are skipped (counted at the end); a
//! malformed object is a bad object (the run goes on when its size lets
//! the reader skip it, and stops at an error of the file's structure).

use std::io::{self, Read, Write};

use canopen_codec::trace::blf::{BlfError, BlfEvent, BlfReader, Compression};
use canopen_codec::trace::candump::LogLine;
use flate2::{Decompress, FlushDecompress, Status};

use crate::decoding::Decoding;
use crate::pipeline::Outcome;

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

/// What one event does to the run; false at a fatal error.
fn event(
    e: Result<Option<BlfEvent<'_>>, BlfError>,
    count: &mut Count,
    run: &mut Decoding<'_>,
    out: &mut impl Write,
    diag: &mut impl Write,
) -> io::Result<bool> {
    match e {
        Ok(Some(BlfEvent::Frame(f))) => {
            count.objects += 1;
            let line = LogLine {
                timestamp: f.timestamp,
                interface: None,
                frame: f.frame,
            };
            run.frame(
                &format_args!("object {}", count.objects),
                &line,
                Some(f.direction),
                out,
                diag,
            )?;
        }
        Ok(Some(BlfEvent::Unsupported {
            what, object_type, ..
        })) => {
            count.objects += 1;
            run.unsupported(
                &format_args!("object {}", count.objects),
                what,
                &format_args!("object type {object_type}"),
                diag,
            );
        }
        Ok(Some(BlfEvent::Skipped { .. })) => {
            count.objects += 1;
            count.skipped += 1;
        }
        Ok(None | Some(_)) => {}
        Err(e) if e.is_fatal() => {
            let _ = writeln!(
                diag,
                "after object {}: {e}: the rest is not read",
                count.objects
            );
            run.bad += 1;
            return Ok(false);
        }
        Err(e) => {
            count.objects += 1;
            let _ = writeln!(diag, "object {}: {e}", count.objects);
            run.bad += 1;
        }
    }
    Ok(true)
}

/// The reader and the inflater of one file.
struct File {
    reader: BlfReader,
    zlib: Decompress,
    buf: Vec<u8>,
    count: Count,
}

/// Inflates one piece of a zlib container's payload into the reader;
/// false at a fatal error (of the reader or of zlib).
fn inflate(
    mut z: &[u8],
    file: &mut File,
    run: &mut Decoding<'_>,
    out: &mut impl Write,
    diag: &mut impl Write,
) -> io::Result<bool> {
    let File {
        reader,
        zlib,
        buf,
        count,
    } = file;
    loop {
        let (before_in, before_out) = (zlib.total_in(), zlib.total_out());
        let status = match zlib.decompress(z, buf, FlushDecompress::None) {
            Ok(s) => s,
            Err(e) => {
                let _ = writeln!(
                    diag,
                    "after object {}: container does not inflate ({e}): the rest is not read",
                    count.objects
                );
                run.bad += 1;
                return Ok(false);
            }
        };
        let used = usize::try_from(zlib.total_in() - before_in).unwrap_or(z.len());
        let made = usize::try_from(zlib.total_out() - before_out).unwrap_or(0);
        z = z.get(used..).unwrap_or(&[]);
        let mut inflated = buf.get(..made).unwrap_or(&[]);
        loop {
            match reader.read_inflated(&mut inflated) {
                Ok(None) => break,
                r => {
                    if !event(r, count, run, out, diag)? {
                        return Ok(false);
                    }
                }
            }
        }
        let stuck = used == 0 && made == 0;
        if status == Status::StreamEnd || stuck || (z.is_empty() && made < buf.len()) {
            return Ok(true);
        }
    }
}

/// Decodes the BLF file `input` into `out` (what is wrong on `diag`);
/// returns how it ended (bad objects, a problem open, no frame).
pub fn read(
    mut input: impl Read,
    mut run: Decoding<'_>,
    out: &mut impl Write,
    diag: &mut impl Write,
) -> io::Result<Outcome> {
    let mut file = File {
        reader: BlfReader::new(),
        zlib: Decompress::new(true),
        buf: vec![0u8; INFLATE],
        count: Count::default(),
    };
    let mut block = vec![0u8; BLOCK];
    let mut going = true;
    'file: while going {
        let n = match input.read(&mut block) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        let mut chunk = block.get(..n).unwrap_or(&[]);
        loop {
            match file.reader.read(&mut chunk) {
                Ok(None) => break,
                Ok(Some(BlfEvent::ContainerStart {
                    compression: Compression::Zlib,
                    ..
                })) => file.zlib.reset(true),
                Ok(Some(BlfEvent::Compressed(z))) => {
                    if !inflate(z, &mut file, &mut run, out, diag)? {
                        going = false;
                        break 'file;
                    }
                }
                r => {
                    if !event(r, &mut file.count, &mut run, out, diag)? {
                        going = false;
                        break 'file;
                    }
                }
            }
        }
    }
    if going {
        if let Err(e) = file.reader.finish() {
            let _ = writeln!(diag, "after object {}: {e}", file.count.objects);
            run.bad += 1;
        }
    }
    let count = file.count;
    if count.skipped > 0 {
        let _ = writeln!(
            diag,
            "canopen-decode: {} other BLF object(s) skipped (not CAN frames)",
            count.skipped
        );
    }
    let frames = run.frames;
    let (bad, open) = run.finish(out, diag)?;
    let no_frame = frames == 0;
    if no_frame {
        let _ = writeln!(
            diag,
            "canopen-decode: none of the {} object(s) is a CAN frame (read as blf)",
            count.objects
        );
    }
    Ok(Outcome {
        bad,
        open,
        no_frame,
    })
}
