//! The zlib (RFC 1950) inflater seam of the binary trace readers: Vector
//! BLF's compressed containers and MDF 4's `##DZ` blocks are zlib streams,
//! and this crate's core has no zlib of its own. The caller passes an
//! [`Inflate`] (with feature `zlib` the crate has flate2's, [`Zlib`],
//! which the programs pass).

use alloc::string::{String, ToString};

/// A zlib (RFC 1950) inflater for the compressed parts of a binary trace
/// (one BLF container, one MDF 4 `##DZ` block: one stream each). A caller
/// that reads compressed files passes one (`Zlib`, flate2's, which the
/// programs pass); [`NoInflate`] reads the uncompressed parts and reports
/// the first compressed one.
pub trait Inflate {
    /// Starts a new zlib stream (one per container or block).
    fn reset(&mut self);
    /// Inflates from `input` into `output`, as much as fits: what was used
    /// and made, or the stream's error in words.
    fn inflate(&mut self, input: &[u8], output: &mut [u8]) -> Result<Inflated, String>;
}

/// What one [`Inflate::inflate`] call did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Inflated {
    /// Bytes of the input used.
    pub used: usize,
    /// Bytes written to the output.
    pub made: usize,
    /// The zlib stream ended.
    pub end: bool,
}

/// No inflater: every compressed part is an error (and the rest of the
/// file is not read).
#[derive(Clone, Copy, Debug, Default)]
pub struct NoInflate;

impl Inflate for NoInflate {
    fn reset(&mut self) {}

    fn inflate(&mut self, _: &[u8], _: &mut [u8]) -> Result<Inflated, String> {
        Err("no zlib inflater given".to_string())
    }
}

/// flate2's zlib (RFC 1950) inflater, the [`Inflate`] that a reader of
/// compressed Vector BLF or MDF 4 files passes (the programs do, and so
/// do this crate's own tests): each BLF `LogContainer` with compression
/// method 2, each MDF 4 `##DZ` block, is one zlib stream.
///
/// ```
/// use std::io::Write;
/// use canopen_codec::trace::inflate::{Inflate, Zlib};
/// let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
/// z.write_all(b"LOBJ").unwrap();
/// let stream = z.finish().unwrap();
/// let mut out = [0u8; 16];
/// let done = Zlib::default().inflate(&stream, &mut out).unwrap();
/// assert_eq!((&out[..done.made], done.used, done.end), (&b"LOBJ"[..], stream.len(), true));
/// ```
#[cfg(any(test, feature = "zlib"))]
pub struct Zlib(flate2::Decompress);

#[cfg(any(test, feature = "zlib"))]
impl Default for Zlib {
    /// A zlib stream (with its RFC 1950 header), not raw deflate.
    fn default() -> Self {
        Zlib(flate2::Decompress::new(true))
    }
}

#[cfg(any(test, feature = "zlib"))]
impl core::fmt::Debug for Zlib {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Zlib")
            .field("total_in", &self.0.total_in())
            .field("total_out", &self.0.total_out())
            .finish()
    }
}

#[cfg(any(test, feature = "zlib"))]
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
