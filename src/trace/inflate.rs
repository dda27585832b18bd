//! The zlib (RFC 1950) inflater seam of the binary trace readers: Vector
//! BLF's compressed containers and MDF 4's `##DZ` blocks are zlib streams,
//! and this crate's core has no zlib of its own. The caller passes an
//! [`Inflate`] (with feature `zlib` the crate has flate2's, which the
//! programs pass).

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
