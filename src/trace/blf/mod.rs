//! Vector BLF, the binary logging format of CANalyzer / CANoe (and of
//! python-can's `BLFWriter`), read from byte chunks the caller feeds:
//! sans-IO, no allocation, bounded memory (one 72-byte buffer per object
//! stream, whatever the object sizes say).
//!
//! Vector publishes no specification of the format; the layouts here are
//! those of Toby Lorenz's `vector_blf` library and python-can's `blf`
//! module, which read and write the files Vector's tools do:
//!
//! - the **file header**: `LOGG`, its size (u32, 144 in practice), the
//!   application, the file size and uncompressed size (u64), the object
//!   count (u32) and the measurement's start and end as Windows
//!   `SYSTEMTIME`s (eight u16: year, month, weekday, day, hour, minute,
//!   second, millisecond), then padding up to its size;
//! - **objects**, each `LOBJ`, header size (u16), header version (u16),
//!   object size (u32, header included), object type (u32); a version 1
//!   header goes on with flags (u32), client index (u16), object version
//!   (u16) and timestamp (u64): 32 bytes; version 2 with flags (u32),
//!   timestamp status (u8), a reserved byte, object version (u16),
//!   timestamp (u64) and original timestamp (u64): 40 bytes. The flags
//!   give the timestamp's unit: 1 = 10 us, 2 = 1 ns; it counts from the
//!   measurement's start. An object of size `s` is followed by `s % 4`
//!   padding bytes (this reader finds the next `LOBJ` within 3 bytes of
//!   the object's end, so it also reads writers that pad to 4);
//! - **`LOG_CONTAINER`** objects (type 10, base header only) hold the other
//!   objects: compression method (u16, 0 stored, 2 zlib), 6 reserved bytes,
//!   the uncompressed size (u32), 4 reserved bytes, then the payload. The
//!   objects in the payloads form one stream: one may begin in a container
//!   and end in the next;
//! - **`CAN_MESSAGE`** (1) and **`CAN_MESSAGE2`** (86): channel (u16,
//!   from 1), flags (u8: bit 0 transmitted, bit 7 remote frame), DLC (u8),
//!   identifier (u32, bit 31 set for a 29-bit one), 8 data bytes (and for
//!   `CAN_MESSAGE2` frame length and bit count after them, not needed).
//!
//! Error frames (`CAN_ERROR` 2, `CAN_ERROR_EXT` 73) and CAN FD frames
//! (`CAN_FD_MESSAGE` 100, `CAN_FD_MESSAGE_64` 101) are reported as
//! [`BlfEvent::Unsupported`]; any other object is skipped by its size
//! ([`BlfEvent::Skipped`]).
//!
//! The library inflates nothing (it has no zlib): a zlib container's
//! payload comes out as [`BlfEvent::Compressed`] pieces, which the caller
//! inflates (one zlib stream per container, begun at each
//! [`BlfEvent::ContainerStart`]) and hands back with
//! [`BlfReader::read_inflated`]; stored containers are read through. Every
//! object is parsed here, in one place, whichever way it came.
//!
//! ```
//! use canopen_codec::trace::blf::{BlfEvent, BlfReader};
//! # fn blf_file() -> Vec<u8> {
//! #     let mut f = vec![0u8; 144];
//! #     f[..4].copy_from_slice(b"LOGG");
//! #     f[4..8].copy_from_slice(&144u32.to_le_bytes());
//! #     let mut msg = Vec::new();
//! #     msg.extend_from_slice(b"LOBJ");
//! #     msg.extend_from_slice(&32u16.to_le_bytes());
//! #     msg.extend_from_slice(&1u16.to_le_bytes());
//! #     msg.extend_from_slice(&48u32.to_le_bytes());
//! #     msg.extend_from_slice(&1u32.to_le_bytes());
//! #     msg.extend_from_slice(&2u32.to_le_bytes());
//! #     msg.extend_from_slice(&[0; 4]);
//! #     msg.extend_from_slice(&1_500_000_000u64.to_le_bytes());
//! #     msg.extend_from_slice(&[1, 0, 0, 2, 0x8A, 0x01, 0, 0, 0x74, 0x13, 0, 0, 0, 0, 0, 0]);
//! #     f.extend_from_slice(b"LOBJ");
//! #     f.extend_from_slice(&16u16.to_le_bytes());
//! #     f.extend_from_slice(&1u16.to_le_bytes());
//! #     f.extend_from_slice(&(32 + msg.len() as u32).to_le_bytes());
//! #     f.extend_from_slice(&10u32.to_le_bytes());
//! #     f.extend_from_slice(&[0; 8]);
//! #     f.extend_from_slice(&(msg.len() as u32).to_le_bytes());
//! #     f.extend_from_slice(&[0; 4]);
//! #     f.extend_from_slice(&msg);
//! #     f
//! # }
//! let file: Vec<u8> = blf_file(); // a stored container with one CAN message
//! let mut reader = BlfReader::new();
//! let mut frames = Vec::new();
//! for mut chunk in file.chunks(7) {
//!     while let Some(event) = reader.read(&mut chunk).unwrap() {
//!         if let BlfEvent::Frame(f) = event {
//!             frames.push(f);
//!         }
//!     }
//! }
//! reader.finish().unwrap();
//! assert_eq!(frames[0].frame.to_string(), "18A#7413");
//! assert_eq!(frames[0].timestamp.unwrap().as_micros(), 1_500_000);
//! ```

mod objects;
#[cfg(feature = "alloc")]
pub mod write;
#[cfg(feature = "alloc")]
pub use write::{BlfWriter, Deflate};

use super::{RxTx, TraceFrame, Unsupported};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::trace::fields::{u16_at, u32_at, u64_at};
use objects::{take, Objects, Step};

/// The file header's signature.
pub const FILE_SIGNATURE: [u8; 4] = *b"LOGG";
/// Every object's signature.
pub const OBJECT_SIGNATURE: [u8; 4] = *b"LOBJ";

/// The object types this reader knows (the numbers of Vector's
/// `BL_OBJ_TYPE_*` constants).
pub mod object_type {
    /// A classic CAN frame.
    pub const CAN_MESSAGE: u32 = 1;
    /// A CAN error frame.
    pub const CAN_ERROR: u32 = 2;
    /// A container of other objects, stored or zlib-compressed.
    pub const LOG_CONTAINER: u32 = 10;
    /// A CAN error frame with its bit position and error code.
    pub const CAN_ERROR_EXT: u32 = 73;
    /// A classic CAN frame with its frame length and bit count.
    pub const CAN_MESSAGE2: u32 = 86;
    /// A CAN FD frame (up to 64 data bytes).
    pub const CAN_FD_MESSAGE: u32 = 100;
    /// A CAN FD frame with its bit timing.
    pub const CAN_FD_MESSAGE_64: u32 = 101;
}

/// The file header fields read (the header's own size field says how long
/// it is).
const FILE_HEADER_FIELDS: usize = 72;
/// `LOBJ`, header size, header version, object size, object type.
const BASE_HEADER: usize = 16;
/// The base header and the version 1 fields.
const V1_HEADER: usize = 32;
/// The base header and the version 2 fields.
const V2_HEADER: usize = 40;
/// The longest object header read (a longer one is skipped).
const MAX_HEADER: usize = 48;
/// Compression method, reserved, uncompressed size, reserved.
const CONTAINER_HEADER: usize = 16;
/// Channel, flags, DLC, identifier, 8 data bytes.
const CAN_MESSAGE_BODY: usize = 16;
/// The most of one object (or of the file header) held at once.
const BUF: usize = 72;
/// Padding after an object: at most 3 bytes.
const MAX_PADDING: u8 = 3;

/// How a container's payload is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Compression {
    /// Method 0: the objects as they are.
    Stored,
    /// Method 2: a zlib stream (RFC 1950) of the objects.
    Zlib,
}

/// What the file header says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FileHeader {
    /// The header's size in bytes.
    pub header_size: u32,
    /// The writing application's ID (python-can writes 5).
    pub application_id: u8,
    /// The file's size as the writer recorded it.
    pub file_size: u64,
    /// The size of the objects uncompressed, as the writer recorded it.
    pub uncompressed_size: u64,
    /// The number of objects (not counting containers), as recorded.
    pub object_count: u32,
    /// The measurement's start as UNIX time (its `SYSTEMTIME` read as UTC,
    /// as python-can does), when the header has a valid one.
    pub start: Option<Timestamp>,
}

/// A classic CAN frame of a BLF file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlfFrame {
    /// The measurement's start plus the object's timestamp, to the nearest
    /// microsecond (UNIX time when the header has a start, time since the
    /// start otherwise); `None`
    /// when the object's flags name neither unit.
    pub timestamp: Option<Timestamp>,
    /// The channel, as the file numbers it (from 1).
    pub channel: u16,
    /// Flags bit 0: transmitted by the logging node.
    pub direction: RxTx,
    /// The frame (a DLC above 8 carries 8 data bytes).
    pub frame: CanFrame,
}

impl BlfFrame {
    /// The frame as the line formats give theirs (no channel name).
    #[must_use]
    pub const fn trace_frame(&self) -> TraceFrame<'static> {
        TraceFrame {
            timestamp: self.timestamp,
            channel: None,
            direction: Some(self.direction),
            frame: self.frame,
        }
    }
}

/// What the reader found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum BlfEvent<'a> {
    /// The file header (first, once).
    Header(FileHeader),
    /// A container begins: for [`Compression::Zlib`] begin a new zlib
    /// stream; its inflated size must be `uncompressed_size`.
    ContainerStart {
        /// How its payload is stored.
        compression: Compression,
        /// The size of its payload uncompressed.
        uncompressed_size: u32,
    },
    /// A piece of a zlib container's payload (borrowed from the input):
    /// inflate it and hand what comes out to [`BlfReader::read_inflated`]
    /// before the next [`BlfReader::read`].
    Compressed(&'a [u8]),
    /// A classic CAN frame.
    Frame(BlfFrame),
    /// An object read but not decoded: CAN FD or error frames.
    Unsupported {
        /// What it is.
        what: Unsupported,
        /// Its object type.
        object_type: u32,
        /// Its time, as a frame's.
        timestamp: Option<Timestamp>,
    },
    /// Any other object (or an object header version other than 1 and 2),
    /// skipped by its size.
    Skipped {
        /// Its object type.
        object_type: u32,
    },
}

/// Why a BLF file cannot be read. [`is_fatal`](Self::is_fatal) says
/// whether reading can go on (the object was skipped by its size).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BlfError {
    /// The file does not begin with `LOGG`.
    #[error("not a BLF file (no LOGG signature)")]
    NotBlf,
    /// The file header's size is below the fields it must hold.
    #[error("file header size {header_size} is below 72 bytes")]
    FileHeaderSize {
        /// The size the header gives.
        header_size: u32,
    },
    /// No `LOBJ` where an object must begin.
    #[error("no object signature at byte {offset} of the {}", if *in_container { "container payloads" } else { "file" })]
    BadSignature {
        /// Bytes into the file, or into the container payloads' stream.
        offset: u64,
        /// In the container payloads' stream.
        in_container: bool,
    },
    /// An object's size is below its header's size (or the base header's).
    #[error("object size {object_size} is below its header size {header_size}")]
    ObjectSmallerThanHeader {
        /// The object's size.
        object_size: u32,
        /// Its header's size.
        header_size: u16,
    },
    /// An object header's size does not fit its version.
    #[error("object header size {header_size} does not fit header version {version}")]
    HeaderSize {
        /// The header's size.
        header_size: u16,
        /// The header's version.
        version: u16,
    },
    /// An object is shorter than its type's fields.
    #[error("object of type {object_type} is {object_size} bytes, too short for its fields")]
    ObjectTooShort {
        /// Its type.
        object_type: u32,
        /// Its size.
        object_size: u32,
    },
    /// A CAN message with an 11-bit identifier above 7FFh.
    #[error("identifier {raw:X}h is not an 11-bit identifier")]
    BadId {
        /// The identifier field.
        raw: u32,
    },
    /// A container is shorter than its own header.
    #[error("container of {object_size} bytes is shorter than its header")]
    ContainerTooShort {
        /// The container's size.
        object_size: u32,
    },
    /// A container's header size is below 16 or above 48 bytes.
    #[error("container header size {header_size} is not 16 to 48 bytes")]
    ContainerHeaderSize {
        /// The header's size.
        header_size: u16,
    },
    /// A container's compression method is neither 0 nor 2.
    #[error("unknown container compression method {method}")]
    UnknownCompression {
        /// The method.
        method: u16,
    },
    /// A stored container's payload is not its declared uncompressed size.
    #[error("stored container of {payload} bytes declares {declared}")]
    StoredSizeMismatch {
        /// The payload's size.
        payload: u32,
        /// The uncompressed size it declares.
        declared: u32,
    },
    /// A zlib container inflates to a size other than the one it declares.
    #[error("container inflates to {inflated} bytes, not the {declared} it declares")]
    InflatedSizeMismatch {
        /// The uncompressed size it declares.
        declared: u32,
        /// What was inflated (so far, when more than declared).
        inflated: u64,
    },
    /// Inflated bytes handed in with no zlib container open.
    #[error("inflated bytes with no compressed container open")]
    NotInflating,
    /// The input ends inside the file header, an object or a container.
    #[error("the file ends inside {0}")]
    Truncated(&'static str),
}

impl BlfError {
    /// False when the error was about one object, which was skipped by
    /// its size: reading can go on. After a fatal error the reader gives it
    /// again on every call.
    #[must_use]
    pub const fn is_fatal(&self) -> bool {
        !matches!(
            self,
            BlfError::HeaderSize { .. } | BlfError::ObjectTooShort { .. } | BlfError::BadId { .. }
        )
    }
}

/// Where the reader is in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// The file header's fields.
    FileHeader,
    /// The rest of the file header, skipped.
    HeaderRest { left: u32 },
    /// The objects.
    Objects,
}

/// Reads a BLF file from the chunks the caller feeds. See the
/// [module docs](self).
///
/// Call [`read`](Self::read) with each chunk of the file until it returns
/// `None` (the chunk is used up), handing the inflated bytes of every
/// [`BlfEvent::Compressed`] piece to [`read_inflated`](Self::read_inflated)
/// until that returns `None`; at the end of the file call
/// [`finish`](Self::finish).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlfReader {
    phase: Phase,
    start: Option<Timestamp>,
    top: Objects,
    inner: Objects,
    /// The open zlib container: declared and inflated sizes.
    inflating: Option<(u32, u64)>,
    failed: Option<BlfError>,
}

impl Default for BlfReader {
    fn default() -> Self {
        Self::new()
    }
}

impl BlfReader {
    /// A reader at the start of a file.
    #[must_use]
    pub const fn new() -> Self {
        BlfReader {
            phase: Phase::FileHeader,
            start: None,
            top: Objects::new(true),
            inner: Objects::new(false),
            inflating: None,
            failed: None,
        }
    }

    /// True when `bytes` (the start of a file) begin with `LOGG`.
    #[must_use]
    pub fn detect(bytes: &[u8]) -> bool {
        bytes.starts_with(&FILE_SIGNATURE)
    }

    /// `read`, unless a fatal error came before (then that error again);
    /// a fatal error `read` meets is kept for every later call
    /// ([`BlfError::is_fatal`]).
    fn unless_failed<T>(
        &mut self,
        read: impl FnOnce(&mut Self) -> Result<T, BlfError>,
    ) -> Result<T, BlfError> {
        if let Some(e) = self.failed {
            return Err(e);
        }
        let r = read(self);
        if let Err(e) = r {
            if e.is_fatal() {
                self.failed = Some(e);
            }
        }
        r
    }

    /// The next event from the file's bytes `input` (advanced past what is
    /// read); `None` when `input` is used up.
    pub fn read<'i>(&mut self, input: &mut &'i [u8]) -> Result<Option<BlfEvent<'i>>, BlfError> {
        self.unless_failed(|reader| reader.read_file(input))
    }

    fn read_file<'i>(&mut self, input: &mut &'i [u8]) -> Result<Option<BlfEvent<'i>>, BlfError> {
        loop {
            match self.phase {
                Phase::FileHeader => {
                    if !self.top.fill(input, FILE_HEADER_FIELDS) {
                        if self.top.buf.get(..self.top.have.min(4))
                            != FILE_SIGNATURE.get(..self.top.have.min(4))
                        {
                            return Err(BlfError::NotBlf);
                        }
                        return Ok(None);
                    }
                    let header = self.file_header()?;
                    self.top.have = 0;
                    self.start = header.start;
                    self.phase = Phase::HeaderRest {
                        left: header.header_size - FILE_HEADER_FIELDS as u32,
                    };
                    return Ok(Some(BlfEvent::Header(header)));
                }
                Phase::HeaderRest { left } => {
                    if left == 0 {
                        self.phase = Phase::Objects;
                        continue;
                    }
                    if input.is_empty() {
                        return Ok(None);
                    }
                    let n = take(input, left as usize).len();
                    self.top.offset += n as u64;
                    self.phase = Phase::HeaderRest {
                        left: left - n as u32,
                    };
                }
                Phase::Objects => {
                    let Step::Payload {
                        left,
                        compression,
                        declared,
                    } = self.top.step
                    else {
                        let event = self.top.next(input, self.start)?;
                        if let Some(BlfEvent::ContainerStart {
                            compression: Compression::Zlib,
                            uncompressed_size,
                        }) = event
                        {
                            self.inflating = Some((uncompressed_size, 0));
                        }
                        return Ok(event);
                    };
                    if left == 0 {
                        self.close_container()?;
                        continue;
                    }
                    if input.is_empty() {
                        return Ok(None);
                    }
                    let chunk = input.get(..left as usize).unwrap_or(input);
                    let used = match compression {
                        Compression::Zlib => {
                            *input = input.get(chunk.len()..).unwrap_or(&[]);
                            self.top.offset += chunk.len() as u64;
                            self.top.step = Step::Payload {
                                left: left - chunk.len() as u32,
                                compression,
                                declared,
                            };
                            return Ok(Some(BlfEvent::Compressed(chunk)));
                        }
                        Compression::Stored => {
                            let mut rest = chunk;
                            let r = self.inner.next(&mut rest, self.start);
                            let used = chunk.len() - rest.len();
                            *input = input.get(used..).unwrap_or(&[]);
                            self.top.offset += used as u64;
                            self.top.step = Step::Payload {
                                left: left - used as u32,
                                compression,
                                declared,
                            };
                            if let Some(event) = r? {
                                return Ok(Some(event));
                            }
                            used
                        }
                    };
                    if used == 0 && !input.is_empty() {
                        // Unreachable: the stream takes bytes until it has
                        // an event; stop rather than spin.
                        return Ok(None);
                    }
                }
            }
        }
    }

    /// The end of the top level's container: a zlib one must have
    /// inflated to its declared size.
    fn close_container(&mut self) -> Result<(), BlfError> {
        self.top.step = Step::Signature { slack: 0 };
        self.top.have = 0;
        if let Some((declared, inflated)) = self.inflating.take() {
            if inflated != u64::from(declared) {
                return Err(BlfError::InflatedSizeMismatch { declared, inflated });
            }
        }
        Ok(())
    }

    fn file_header(&self) -> Result<FileHeader, BlfError> {
        let b = &self.top.buf;
        if b.get(..4) != Some(&FILE_SIGNATURE[..]) {
            return Err(BlfError::NotBlf);
        }
        let header_size = u32_at(b, 4);
        if (header_size as usize) < FILE_HEADER_FIELDS {
            return Err(BlfError::FileHeaderSize { header_size });
        }
        let t = |i: usize| u16_at(b, 40 + 2 * i);
        Ok(FileHeader {
            header_size,
            application_id: b.get(8).copied().unwrap_or(0),
            file_size: u64_at(b, 16),
            uncompressed_size: u64_at(b, 24),
            object_count: u32_at(b, 32),
            start: system_time([t(0), t(1), t(3), t(4), t(5), t(6), t(7)]),
        })
    }

    /// The next event from the inflated bytes of the open zlib container
    /// (`inflated` advanced past what is read); `None` when they are used
    /// up.
    pub fn read_inflated(
        &mut self,
        inflated: &mut &[u8],
    ) -> Result<Option<BlfEvent<'static>>, BlfError> {
        self.unless_failed(|reader| reader.inflated(inflated))
    }

    fn inflated(&mut self, input: &mut &[u8]) -> Result<Option<BlfEvent<'static>>, BlfError> {
        if input.is_empty() {
            return Ok(None);
        }
        let zlib_open = matches!(
            self.top.step,
            Step::Payload {
                compression: Compression::Zlib,
                ..
            }
        );
        let Some((declared, inflated)) = self.inflating.filter(|_| zlib_open) else {
            return Err(BlfError::NotInflating);
        };
        let offered = inflated + input.len() as u64;
        if offered > u64::from(declared) {
            return Err(BlfError::InflatedSizeMismatch {
                declared,
                inflated: offered,
            });
        }
        let before = input.len();
        let r = self.inner.next(input, self.start);
        self.inflating = Some((declared, inflated + (before - input.len()) as u64));
        r
    }

    /// At the end of the file: an error when it ends inside the file
    /// header, an object or a container (padding at the end is fine).
    pub fn finish(&mut self) -> Result<(), BlfError> {
        if let Some(e) = self.failed {
            return Err(e);
        }
        match self.phase {
            Phase::FileHeader if self.top.have == 0 => return Err(BlfError::NotBlf),
            Phase::FileHeader | Phase::HeaderRest { .. } => {
                return Err(BlfError::Truncated("the file header"))
            }
            Phase::Objects => {}
        }
        if let Step::Payload { left: 0, .. } = self.top.step {
            self.close_container()?;
        }
        if matches!(self.top.step, Step::Payload { .. }) {
            return Err(BlfError::Truncated("a container"));
        }
        if !self.top.between_objects() || !self.inner.between_objects() {
            return Err(BlfError::Truncated("an object"));
        }
        Ok(())
    }
}

/// A `SYSTEMTIME` (year, month, day, hour, minute, second, millisecond;
/// the weekday left out) read as UTC, as UNIX time; `None` unless valid
/// (python-can writes zeros when it has no start).
fn system_time([year, month, day, hour, minute, second, ms]: [u16; 7]) -> Option<Timestamp> {
    if !(1970..=9999).contains(&year)
        || !(1..=12).contains(&month)
        || !(1..=31).contains(&day)
        || hour > 23
        || minute > 59
        || second > 59
        || ms > 999
    {
        return None;
    }
    // Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's
    // days_from_civil).
    let (y, m, d) = (i64::from(year), i64::from(month), i64::from(day));
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let doy = (153 * ((m + 9) % 12) + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    let days = era * 146_097 + doe - 719_468;
    let secs = days * 86_400 + i64::from(hour) * 3600 + i64::from(minute) * 60 + i64::from(second);
    let us = u64::try_from(secs).ok()?.checked_mul(1_000_000)?;
    Some(Timestamp::from_micros(us + u64::from(ms) * 1000))
}

#[cfg(test)]
mod tests;
