//! flate2's gzip decompressor for `.gz` input of any format (feature
//! `zlib`); its zlib inflater for BLF's compressed containers is
//! [`crate::trace::inflate::Zlib`].

use std::prelude::rust_2021::*;

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
