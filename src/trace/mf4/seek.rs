//! An MDF 4 file read in place: a [`Source`] over a file that can seek,
//! read through a window of [`WINDOW`] bytes, so that the blocks read one
//! after the other (a data group's data) cost one read per window and no
//! seek.

use std::io::{self, Read, Seek, SeekFrom};
use std::vec::Vec;

use super::blocks::Source;
use super::Mf4Error;

/// The window read at once.
pub const WINDOW: usize = 64 * 1024;

/// A file that can seek (`std::fs::File`, `io::Cursor`) as an MDF 4
/// [`Source`]: the bytes asked for come from a window of 64 KiB
/// read ahead (a larger piece is read straight into its buffer). An I/O
/// error is [`Mf4Error::Read`] for the reader and is kept here
/// ([`SeekSource::take_error`]).
#[derive(Debug)]
pub struct SeekSource<R> {
    inner: R,
    size: u64,
    /// Where the inner reader is.
    pos: u64,
    window: Vec<u8>,
    /// Where the window begins in the file.
    window_at: u64,
    error: Option<io::Error>,
}

impl<R: Read + Seek> SeekSource<R> {
    /// The file `inner` (its length taken by seeking to its end).
    ///
    /// # Errors
    ///
    /// The seek's error.
    pub fn new(mut inner: R) -> io::Result<Self> {
        let size = inner.seek(SeekFrom::End(0))?;
        Ok(SeekSource {
            inner,
            size,
            pos: size,
            window: Vec::new(),
            window_at: 0,
            error: None,
        })
    }

    /// The I/O error behind the last [`Mf4Error::Read`], once.
    pub fn take_error(&mut self) -> Option<io::Error> {
        self.error.take()
    }

    /// Reads `buf.len()` bytes at `at` from the inner reader.
    fn fill(&mut self, at: u64, buf: &mut [u8]) -> io::Result<()> {
        if self.pos != at {
            self.inner.seek(SeekFrom::Start(at))?;
            self.pos = at;
        }
        self.inner.read_exact(buf)?;
        self.pos = at.saturating_add(buf.len() as u64);
        Ok(())
    }
}

impl<R: Read + Seek> Source for SeekSource<R> {
    fn size(&self) -> u64 {
        self.size
    }

    fn read_at(&mut self, at: u64, buf: &mut [u8]) -> Result<(), Mf4Error> {
        let len = buf.len() as u64;
        if at.checked_add(len).is_none_or(|end| end > self.size) {
            return Err(Mf4Error::PastEnd { at });
        }
        let fail = |s: &mut Self, e| {
            s.error = Some(e);
            s.window.clear();
            // Unknown: the next read seeks.
            s.pos = u64::MAX;
            Err(Mf4Error::Read { at })
        };
        if buf.len() >= WINDOW {
            return self.fill(at, buf).or_else(|e| fail(self, e));
        }
        let inside = at
            .checked_sub(self.window_at)
            .and_then(|from| usize::try_from(from).ok())
            .and_then(|from| self.window.get(from..from.checked_add(buf.len())?));
        if let Some(bytes) = inside {
            buf.copy_from_slice(bytes);
            return Ok(());
        }
        // at + len <= size; the window ends at the file's end at the latest.
        let n = (self.size - at).min(WINDOW as u64) as usize;
        let mut window = core::mem::take(&mut self.window);
        window.resize(n, 0);
        if let Err(e) = self.fill(at, &mut window) {
            return fail(self, e);
        }
        self.window = window;
        self.window_at = at;
        match self.window.get(..buf.len()) {
            Some(bytes) => {
                buf.copy_from_slice(bytes);
                Ok(())
            }
            None => Err(Mf4Error::PastEnd { at }),
        }
    }
}
