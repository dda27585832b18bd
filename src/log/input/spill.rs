//! An anonymous temporary file for an MF4 that cannot be read in place
//! (from a pipe, or gzip-compressed): ASAM MDF 4 blocks link to anywhere
//! in the file (ASAM MDF 4.1, section 4 "Block structure"), and the
//! writers the decoder meets put the describing blocks after the data
//! (python-can's `MF4Writer` and asammdf write `##HD`, then the `##DT` or
//! `##DZ` data, then the `##DG`/`##CG`/`##CN` blocks the `##HD` links
//! forward to), so the data cannot be read before the end of the input
//! is. The input is copied to a file of the system's temporary folder
//! (`std::env::temp_dir`, `TMPDIR` on Unix) named after the process, read
//! in place from there like a file given by its path. On Unix its name
//! is removed as soon as it is open (the open file stays readable and
//! its space is freed when it is closed, even when the program is
//! killed); elsewhere the file is removed when the reading ends.

use std::fs::{File, OpenOptions};
use std::io::{self, Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::prelude::rust_2021::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Spills made by this process so far: each has a name of its own.
static MADE: AtomicUsize = AtomicUsize::new(0);

/// Names tried before giving up (a name left by an earlier process of
/// the same id is skipped).
const TRIES: usize = 16;

/// A temporary copy of an input: its name removed at once on Unix, the
/// file removed on drop elsewhere.
#[derive(Debug)]
pub(super) struct Spill {
    /// The file (taken on drop, to close it before it is removed).
    file: Option<File>,
    path: PathBuf,
}

impl Spill {
    /// Copies `input` to a new file in `dir`, `first` (bytes read from
    /// the input already) then the rest, and returns it positioned at
    /// its start. An error writing the file says what it was for.
    pub(super) fn copy(dir: &Path, first: &[u8], input: &mut impl Read) -> io::Result<Spill> {
        let mut spill = Spill::create(dir)?;
        let path = spill.path.clone();
        let file = spill
            .file
            .as_mut()
            .ok_or_else(|| cannot(&path, io::Error::other("closed")))?;
        file.write_all(first).map_err(|e| cannot(&path, e))?;
        let mut buf = vec![0u8; 64 * 1024];
        loop {
            let n = super::read_some(input, &mut buf)?;
            let Some(piece) = buf.get(..n).filter(|p| !p.is_empty()) else {
                break;
            };
            file.write_all(piece).map_err(|e| cannot(&path, e))?;
        }
        file.rewind().map_err(|e| cannot(&path, e))?;
        Ok(spill)
    }

    /// A new, empty file in `dir`.
    fn create(dir: &Path) -> io::Result<Spill> {
        let mut last = None;
        for _ in 0..TRIES {
            let n = MADE.fetch_add(1, Ordering::Relaxed);
            let path = dir.join(format!("canopen-codec-{}-{n}.mf4", std::process::id()));
            match OpenOptions::new()
                .read(true)
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(file) => {
                    // Unix keeps an open file whose name is gone: nothing
                    // is left behind whatever ends the program.
                    #[cfg(unix)]
                    let _ = std::fs::remove_file(&path);
                    return Ok(Spill {
                        file: Some(file),
                        path,
                    });
                }
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = Some((path, e)),
                Err(e) => return Err(cannot(&path, e)),
            }
        }
        let (path, e) = last.unwrap_or_else(|| (dir.to_path_buf(), io::Error::other("no name")));
        Err(cannot(&path, e))
    }

    /// The file, to be read in place.
    pub(super) fn file(&mut self) -> io::Result<&mut File> {
        let path = &self.path;
        self.file
            .as_mut()
            .ok_or_else(|| cannot(path, io::Error::other("closed")))
    }
}

impl Drop for Spill {
    fn drop(&mut self) {
        drop(self.file.take());
        // Nothing to do when it cannot be removed (or is gone already, on
        // Unix): it is in the temporary folder, and its name says which
        // program left it.
        let _ = std::fs::remove_file(&self.path);
    }
}

/// An error making or writing the temporary file at `path`, in words the
/// user can act on.
fn cannot(path: &Path, e: io::Error) -> io::Error {
    io::Error::new(
        e.kind(),
        format!(
            "an MF4 read from a pipe or gzip-compressed is copied to a temporary file \
             (its blocks link to anywhere in it), and {} cannot be written: {e} \
             (set TMPDIR to a writable folder, or give the uncompressed file's path)",
            path.display()
        ),
    )
}
