//! Lines of a trace, read in large blocks: one `read` per block, one UTF-8
//! check per block (not per line), and each line handed out where it lies
//! in the block, never copied. `BufRead::read_line` checks and copies every
//! line on its own, which was a sixth of the program's time.
//!
//! A line that is not UTF-8 is handed out as [`Piece::NotUtf8`] (the
//! program reports it and goes on, where `read_line` would end the run),
//! and a line longer than [`MAX_LINE`] as [`Piece::TooLong`] (its bytes are
//! skipped up to the next line), so memory stays bounded on any input.

use std::io::{self, Read};
use std::prelude::rust_2021::*;
use std::vec;

/// The longest line read (no trace format comes near it).
pub const MAX_LINE: usize = 64 * 1024;
/// The block size.
const BLOCK: usize = 256 * 1024;

/// Finds the first `\n` in a slice: the line splitter's search. The
/// default is [`newline`]; a program may pass a faster one (the programs
/// pass the memchr crate's, which this crate does not depend on).
pub type FindNewline = fn(&[u8]) -> Option<usize>;

/// The default [`FindNewline`]: `<[u8]>::iter().position`.
pub fn newline(bytes: &[u8]) -> Option<usize> {
    bytes.iter().position(|&b| b == b'\n')
}

/// One line of the input, without its line ending (`\n` or `\r\n`).
#[derive(Debug, PartialEq, Eq)]
pub enum Piece<'a> {
    /// A line of text.
    Line(&'a str),
    /// A line that is not UTF-8.
    NotUtf8,
    /// A line longer than [`MAX_LINE`] (its bytes skipped).
    TooLong,
}

/// Reads blocks of lines from `R`.
pub struct LineReader<R> {
    input: R,
    buf: Vec<u8>,
    /// `buf[start..end]` is read and not handed out yet.
    start: usize,
    end: usize,
    eof: bool,
    /// Skipping the rest of a line longer than [`MAX_LINE`].
    skipping: bool,
    /// `buf[start..scanned]` has no line ending (so a line that comes in
    /// small reads is searched once, not once per read).
    scanned: usize,
    /// The search for a line's end.
    find: FindNewline,
}

impl<R: Read> LineReader<R> {
    /// A reader of `input`'s lines.
    pub fn new(input: R) -> Self {
        LineReader::with_search(input, newline)
    }

    /// A reader of `input`'s lines that finds each line's end with `find`.
    pub fn with_search(input: R, find: FindNewline) -> Self {
        LineReader {
            find,
            input,
            buf: vec![0; BLOCK + MAX_LINE],
            start: 0,
            end: 0,
            eof: false,
            skipping: false,
            scanned: 0,
        }
    }

    /// The next block of whole lines; `None` at the end of the input.
    pub fn next_block(&mut self) -> io::Result<Option<Block<'_>>> {
        loop {
            let pending = self.buf.get(self.start..self.end).unwrap_or(&[]);
            if self.skipping {
                match pending.iter().position(|&b| b == b'\n') {
                    Some(i) => {
                        self.start += i + 1;
                        self.skipping = false;
                        continue;
                    }
                    None if self.eof => {
                        self.skipping = false;
                        self.start = self.end;
                        return Ok(None);
                    }
                    None => self.start = self.end,
                }
            } else {
                let from_scan = self.scanned.max(self.start);
                let new = self.buf.get(from_scan..self.end).unwrap_or(&[]);
                if let Some(last) = new.iter().rposition(|&b| b == b'\n') {
                    let (from, to) = (self.start, from_scan + last + 1);
                    self.start = to;
                    return Ok(Some(Block::new(
                        self.buf.get(from..to).unwrap_or(&[]),
                        self.find,
                    )));
                }
                self.scanned = self.end;
                if self.eof {
                    if pending.is_empty() {
                        return Ok(None);
                    }
                    // The last line has no line ending.
                    let (from, to) = (self.start, self.end);
                    self.start = to;
                    return Ok(Some(Block::new(
                        self.buf.get(from..to).unwrap_or(&[]),
                        self.find,
                    )));
                }
                if pending.len() > MAX_LINE {
                    self.start = self.end;
                    self.skipping = true;
                    return Ok(Some(Block::too_long()));
                }
            }
            self.fill()?;
        }
    }

    /// Moves what is pending to the front and reads once after it.
    fn fill(&mut self) -> io::Result<()> {
        self.buf.copy_within(self.start..self.end, 0);
        self.end -= self.start;
        self.scanned = self.scanned.saturating_sub(self.start);
        self.start = 0;
        let free = self.buf.get_mut(self.end..).unwrap_or(&mut []);
        match super::read_some(&mut self.input, free)? {
            0 => self.eof = true,
            n => self.end += n,
        }
        Ok(())
    }
}

/// Whole lines of the input, handed out one by one.
pub struct Block<'a> {
    /// Checked text not handed out yet.
    text: &'a str,
    /// Bytes not checked yet.
    rest: &'a [u8],
    too_long: bool,
    find: FindNewline,
}

impl<'a> Block<'a> {
    fn new(bytes: &'a [u8], find: FindNewline) -> Self {
        Block {
            text: "",
            rest: bytes,
            too_long: false,
            find,
        }
    }

    fn too_long() -> Self {
        Block {
            text: "",
            rest: &[],
            too_long: true,
            find: newline,
        }
    }
}

impl<'a> Iterator for Block<'a> {
    type Item = Piece<'a>;

    fn next(&mut self) -> Option<Piece<'a>> {
        if self.too_long {
            self.too_long = false;
            return Some(Piece::TooLong);
        }
        if self.text.is_empty() {
            if self.rest.is_empty() {
                return None;
            }
            match std::str::from_utf8(self.rest) {
                Ok(text) => {
                    self.text = text;
                    self.rest = &[];
                }
                Err(e) => {
                    let good = self.rest.get(..e.valid_up_to()).unwrap_or(&[]);
                    match good.iter().rposition(|&b| b == b'\n') {
                        // The lines before the bad one.
                        Some(i) => {
                            let (lines, rest) = self.rest.split_at(i + 1);
                            self.text = std::str::from_utf8(lines).unwrap_or("");
                            self.rest = rest;
                        }
                        // The bad line itself.
                        None => {
                            let end = self.rest.iter().position(|&b| b == b'\n');
                            self.rest = end.and_then(|i| self.rest.get(i + 1..)).unwrap_or(&[]);
                            return Some(Piece::NotUtf8);
                        }
                    }
                }
            }
        }
        let (line, text) = match (self.find)(self.text.as_bytes()) {
            Some(i) => (
                self.text.get(..i).unwrap_or(""),
                self.text.get(i + 1..).unwrap_or(""),
            ),
            None => (self.text, ""),
        };
        self.text = text;
        if line.len() > MAX_LINE {
            return Some(Piece::TooLong);
        }
        Some(Piece::Line(line.strip_suffix('\r').unwrap_or(line)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reads `input` in reads of at most `chunk` bytes.
    struct Trickle<'a> {
        input: &'a [u8],
        chunk: usize,
    }

    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = self.chunk.min(buf.len()).min(self.input.len());
            let (head, tail) = self.input.split_at(n);
            buf.get_mut(..n).unwrap_or(&mut []).copy_from_slice(head);
            self.input = tail;
            Ok(n)
        }
    }

    fn pieces(input: &[u8], chunk: usize) -> Vec<String> {
        pieces_with(input, chunk, newline)
    }

    fn pieces_with(input: &[u8], chunk: usize, find: FindNewline) -> Vec<String> {
        let mut r = LineReader::with_search(Trickle { input, chunk }, find);
        let mut out = Vec::new();
        while let Some(block) = r.next_block().unwrap() {
            for p in block {
                out.push(match p {
                    Piece::Line(l) => l.to_string(),
                    Piece::NotUtf8 => "<not utf-8>".to_string(),
                    Piece::TooLong => "<too long>".to_string(),
                });
            }
        }
        out
    }

    /// What `BufRead::lines` would give, with the bad lines named.
    fn expected(input: &[u8]) -> Vec<String> {
        let mut lines: Vec<&[u8]> = input.split(|&b| b == b'\n').collect();
        if input.ends_with(b"\n") || input.is_empty() {
            lines.pop();
        }
        lines
            .into_iter()
            .map(|l| {
                if l.len() > MAX_LINE {
                    return "<too long>".to_string();
                }
                match std::str::from_utf8(l) {
                    Ok(s) => s.strip_suffix('\r').unwrap_or(s).to_string(),
                    Err(_) => "<not utf-8>".to_string(),
                }
            })
            .collect()
    }

    #[test]
    fn lines_come_out_as_they_went_in_whatever_the_reads() {
        let mut long = vec![b'x'; MAX_LINE + 10];
        long.push(b'\n');
        let inputs: Vec<Vec<u8>> = vec![
            b"".to_vec(),
            b"\n".to_vec(),
            b"a".to_vec(),
            b"a\nb".to_vec(),
            b"a\r\nb\r\n\r\n".to_vec(),
            b"one\n\xFF\xFEtwo\nthree\n".to_vec(),
            b"\xC3\n\xC3\xA9\n".to_vec(),
            [b"before\n".as_slice(), &long, b"after\n"].concat(),
            [b"before\n".as_slice(), &long[..MAX_LINE + 5]].concat(),
            "(1.0) can0 18A#00\n".repeat(20_000).into_bytes(),
        ];
        for input in &inputs {
            for chunk in [1, 7, 4096, usize::MAX] {
                assert_eq!(pieces(input, chunk), expected(input), "chunk {chunk}");
            }
        }
    }

    static SEARCHES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

    /// A search of its own, counting its calls.
    fn counted(bytes: &[u8]) -> Option<usize> {
        SEARCHES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        bytes
            .iter()
            .enumerate()
            .find(|(_, b)| **b == b'\n')
            .map(|(i, _)| i)
    }

    #[test]
    fn the_callers_search_splits_the_lines() {
        let input = b"one\r\ntwo\n\xFF\nthree";
        assert_eq!(pieces_with(input, 2, counted), expected(input));
        assert!(SEARCHES.load(std::sync::atomic::Ordering::Relaxed) >= 3);
    }
}
