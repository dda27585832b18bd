//! The zlib inflater of the flate2 crate for BLF's compressed containers,
//! and its gzip decompressor for `.gz` input of any format (feature
//! `zlib`).

use std::prelude::rust_2021::*;

use super::{Inflate, Inflated};

/// flate2's zlib (RFC 1950) inflater, the [`Inflate`] that a reader of
/// compressed Vector BLF files passes (both programs do): each
/// `LogContainer` with compression method 2 is one zlib stream.
///
/// ```
/// use std::io::Write;
/// use canopen_codec::log::input::{Inflate, Zlib};
/// let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
/// z.write_all(b"LOBJ").unwrap();
/// let stream = z.finish().unwrap();
/// let mut out = [0u8; 16];
/// let done = Zlib::default().inflate(&stream, &mut out).unwrap();
/// assert_eq!((&out[..done.made], done.used, done.end), (&b"LOBJ"[..], stream.len(), true));
/// ```
pub struct Zlib(flate2::Decompress);

impl Default for Zlib {
    /// A zlib stream (with its RFC 1950 header), not raw deflate.
    fn default() -> Self {
        Zlib(flate2::Decompress::new(true))
    }
}

impl core::fmt::Debug for Zlib {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Zlib")
            .field("total_in", &self.0.total_in())
            .field("total_out", &self.0.total_out())
            .finish()
    }
}

impl Inflate for Zlib {
    fn reset(&mut self) {
        self.0.reset(true);
    }

    fn inflate(&mut self, input: &[u8], output: &mut [u8]) -> Result<Inflated, String> {
        let (before_in, before_out) = (self.0.total_in(), self.0.total_out());
        let status = self
            .0
            .decompress(input, output, flate2::FlushDecompress::None)
            .map_err(|e| e.to_string())?;
        let used = self.0.total_in().saturating_sub(before_in);
        let made = self.0.total_out().saturating_sub(before_out);
        Ok(Inflated {
            used: usize::try_from(used).unwrap_or(input.len()),
            made: usize::try_from(made).unwrap_or(0),
            end: status == flate2::Status::StreamEnd,
        })
    }
}

/// A gzip decompressor whose errors say they are the gzip stream's (a
/// truncated or corrupt `.gz` file).
pub(super) struct Gunzip<R>(pub(super) R);

impl<R: std::io::Read> std::io::Read for Gunzip<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        self.0
            .read(buf)
            .map_err(|e| std::io::Error::new(e.kind(), format!("gzip-compressed input: {e}")))
    }
}
