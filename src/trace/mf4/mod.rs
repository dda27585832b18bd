//! ASAM MDF 4 bus logging (`.mf4`), as python-can's `MF4Writer` (through
//! asammdf), CANedge loggers and Vector's tools write it: the CAN frames
//! of a file's bus-logging channel groups, in time order.
//!
//! The layouts are those of ASAM MDF 4.1/4.2 (section 5, the block types)
//! and its associated standard for bus logging (CAN, section 7.1):
//!
//! - the **`##ID` block** (64 bytes at offset 0): `MDF     `, the version
//!   text, the program, and the version number (u16 at byte 28, 400 and
//!   above here); the **`##HD` block** at byte 64 links the first data
//!   group and gives the start time (ns since 1970, u64);
//! - **`##DG`** data groups (a chain), each with its record id size (0
//!   sorted: one channel group; 1, 2, 4 or 8 unsorted: each record begins
//!   with the id of its channel group) and a link to its data; **`##CG`**
//!   channel groups (record id, data and invalidation bytes per record;
//!   flag bit 0 a variable-length signal data group, whose records are a
//!   u32 length and that many bytes); **`##CN`** channels with their
//!   `##TX` names, place in the record and `##CC` conversion; a
//!   variable-length `DataBytes` (channel type 1) reads its values from a
//!   **`##SD`** chain (read forward) or from the variable-length channel
//!   group its `cn_data` links (the value just before the record);
//! - the data: **`##DT`** (records), **`##DZ`** (a `##DT` compressed
//!   with deflate, or transposed then deflated), **`##DL`** lists of them
//!   and **`##HL`** header lists (module `data`).
//!
//! A CAN bus-logging channel group is told by its composed channel
//! `CAN_DataFrame`, `CAN_RemoteFrame` or `CAN_ErrorFrame` (module `layout`
//! for its members). Data frames become [`Mf4Frame`]s; error frames,
//! CAN FD frames (EDL set, or more than 8 data bytes) and other CAN events
//! are [`Mf4Event::Unsupported`]. Other channel groups (signals) are
//! skipped. Several data groups (python-can writes one per event type)
//! are merged by time, as python-can's `MF4Reader` does.
//!
//! **Why a reader of its own**: the Rust crates that read MDF 4 (mdf4-rs,
//! about 12 000 lines with serde and a DBC crate by default, reading only
//! with std) are neither small nor fuzzed against hostile files, and none
//! reads through this crate's
//! [`Inflate`](crate::trace::inflate::Inflate) seam; bus logging needs a small
//! part of the standard, read here in one place.
//!
//! **How it reads**: MDF 4 links point anywhere in the file, so the reader
//! reads it through a [`Source`] of random access: the file in memory
//! (`&[u8]`) or, with feature `std`, a file that seeks ([`SeekSource`],
//! which the programs use for a file on disk), so memory stays constant in
//! the file's size. The blocks that describe the groups and channels are
//! read once when the reader is made (each at most [`MAX_BLOCK`]); then
//! each data group's data blocks are read in order, a `##DL` list followed
//! as its blocks are reached: a `##DT` in windows of 1 MiB, a `##DZ`
//! inflated one at a time (whole, at most 64 MiB), and the data groups
//! together hold at most [`MAX_HELD`]. Every link and size is checked: a
//! block past the end, a length below its links, a chain that loops (each
//! chain may visit at most one block per 24 bytes of the file) are typed
//! errors, never a panic or an endless loop. Needs feature `alloc`.
//!
//! ```no_run
//! use canopen_codec::trace::mf4::{Mf4Event, Mf4Reader};
//! use canopen_codec::trace::inflate::NoInflate;
//! let file = std::fs::File::open("capture.mf4")?;
//! // In place: the file's data blocks are read as they are reached.
//! let mut reader = Mf4Reader::new(canopen_codec::trace::mf4::SeekSource::new(file)?)?;
//! // NoInflate reads uncompressed files; pass a zlib inflater for ##DZ.
//! while let Some(event) = reader.next(&mut NoInflate)? {
//!     if let Mf4Event::Frame(f) = event {
//!         println!("{:?} {}", f.timestamp, f.frame);
//!     }
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod blocks;
mod data;
mod layout;
mod read;
#[cfg(feature = "std")]
mod seek;

use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::trace::{RxTx, TraceFrame, Unsupported};

pub use blocks::{Source, MAX_BLOCK};
pub use read::{Mf4Reader, MAX_HELD};
#[cfg(feature = "std")]
pub use seek::SeekSource;

/// The file identification's first 8 bytes.
pub const FILE_MAGIC: [u8; 8] = *b"MDF     ";

/// What the file's `##ID` and `##HD` blocks say.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mf4Header {
    /// The version number (410 for 4.10).
    pub version: u16,
    /// The writing program's 8 characters (`amdf8.8.` for asammdf).
    pub program: [u8; 8],
    /// The start time (`hd_start_time_ns`) to the nearest microsecond,
    /// when not 0.
    pub start: Option<Timestamp>,
}

/// A classic CAN frame of an MF4 file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mf4Frame {
    /// The start time plus the record's time, to the nearest microsecond
    /// (UNIX time when the header has a start); `None` when the group has
    /// no time channel or the time is not a number.
    pub timestamp: Option<Timestamp>,
    /// `BusChannel`, when the group has it.
    pub channel: Option<u64>,
    /// `Dir` (0 Rx, 1 Tx), when the group has it.
    pub direction: Option<RxTx>,
    /// The frame.
    pub frame: CanFrame,
}

impl Mf4Frame {
    /// The frame as the line formats give theirs (no channel name).
    #[must_use]
    pub const fn trace_frame(&self) -> TraceFrame<'static> {
        TraceFrame {
            timestamp: self.timestamp,
            channel: None,
            direction: self.direction,
            frame: self.frame,
        }
    }
}

/// What the reader found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Mf4Event {
    /// A classic CAN frame (data or remote).
    Frame(Mf4Frame),
    /// A record read but not decoded: CAN FD, error or other CAN events.
    Unsupported {
        /// What it is.
        what: Unsupported,
        /// Its time, as a frame's.
        timestamp: Option<Timestamp>,
    },
}

/// Why an MF4 file cannot be read. [`is_fatal`](Self::is_fatal) says
/// whether reading can go on (one record was not decoded).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Mf4Error {
    /// The file does not begin with `MDF     `.
    #[error("not an MDF file (no \"MDF     \" identification)")]
    NotMf4,
    /// An MDF file of a version below 4.00.
    #[error("MDF version {version} is not MDF 4")]
    Version {
        /// The version number (330 for 3.30).
        version: u16,
    },
    /// A block (or its data) lies past the file's end.
    #[error("the block at byte {at} lies past the end of the file")]
    PastEnd {
        /// The block's offset.
        at: u64,
    },
    /// A link leads to a block of another type than the link's.
    #[error("the block at byte {at} is {}, not the one its link names", core::str::from_utf8(found).unwrap_or("not a block"))]
    UnexpectedBlock {
        /// The block's offset.
        at: u64,
        /// Its first 4 bytes.
        found: [u8; 4],
    },
    /// A block's length is below its header and links.
    #[error("the block at byte {at} has length {length}, below its header and links")]
    BlockLength {
        /// The block's offset.
        at: u64,
        /// Its length.
        length: u64,
    },
    /// A block other than a data block is longer than
    /// [`MAX_BLOCK`] (16 MiB): it is not read.
    #[error("the block at byte {at} is {length} bytes long, over the 16 MiB this reader takes")]
    BlockTooLong {
        /// The block's offset.
        at: u64,
        /// Its length.
        length: u64,
    },
    /// The file could not be read at a place (an I/O error of a
    /// [`SeekSource`]: it keeps the error).
    #[error("the file could not be read at byte {at}")]
    Read {
        /// The place.
        at: u64,
    },
    /// A chain of links visits more blocks than the file can hold: it
    /// loops.
    #[error("the {what} links loop")]
    LinkCycle {
        /// Which chain.
        what: &'static str,
    },
    /// A data group's record id size is not 0, 1, 2, 4 or 8.
    #[error("the data group at byte {at} has record id size {size}")]
    RecordIdSize {
        /// The data group's offset.
        at: u64,
        /// The size.
        size: u8,
    },
    /// A sorted data group (record id size 0) with several channel groups.
    #[error("the sorted data group at byte {at} has several channel groups")]
    SortedGroups {
        /// The data group's offset.
        at: u64,
    },
    /// An unsorted record's id names no channel group of its data group.
    #[error("record id {record_id} names no channel group")]
    UnknownRecordId {
        /// The record id.
        record_id: u64,
    },
    /// A channel group's records are larger than this reader takes.
    #[error("records of {size} bytes are over the 1 MiB this reader takes")]
    RecordTooLarge {
        /// The record size (data and invalidation bytes).
        size: u64,
    },
    /// The data ends inside a record.
    #[error("the data ends inside a record ({left} of {need} bytes)")]
    RecordPastEnd {
        /// The bytes wanted.
        need: usize,
        /// The bytes left.
        left: usize,
    },
    /// A `##DZ` block's original length is over the 64 MiB inflated.
    #[error("the compressed block at byte {at} inflates to {size} bytes, over 64 MiB")]
    BlockTooLarge {
        /// The block's offset.
        at: u64,
        /// Its original length.
        size: u64,
    },
    /// The data groups' streams hold more than [`MAX_HELD`] bytes at once
    /// (one data block each).
    #[error("the data groups hold {held} bytes at once, over the 256 MiB this reader holds")]
    TooMuchHeld {
        /// The bytes held.
        held: u64,
    },
    /// A `##DZ` block that does not inflate (or no inflater given).
    #[error("the compressed block at byte {at} does not inflate")]
    Inflate {
        /// The block's offset.
        at: u64,
    },
    /// A `##DZ` block inflates to another length than it declares.
    #[error("the compressed block at byte {at} inflates to {inflated} bytes, not the {declared} it declares")]
    InflatedSize {
        /// The block's offset.
        at: u64,
        /// The original length it declares.
        declared: u64,
        /// What it inflated to.
        inflated: u64,
    },
    /// A `##DZ` block's zip type is neither 0 (deflate) nor 1 (transposed).
    #[error("the compressed block at byte {at} has unknown zip type {zip_type}")]
    UnknownZip {
        /// The block's offset.
        at: u64,
        /// The zip type.
        zip_type: u8,
    },
    /// The time channel's conversion is neither identity nor linear.
    #[error("the time conversion at byte {at} is of type {conversion}, not linear")]
    TimeConversion {
        /// The conversion's offset.
        at: u64,
        /// Its type.
        conversion: u8,
    },
    /// The time channel is neither an unsigned integer nor a float.
    #[error("the time channel at byte {at} has data type {data_type}")]
    TimeType {
        /// The channel's offset.
        at: u64,
        /// Its data type.
        data_type: u8,
    },
    /// A bus-logging record lacks a field it needs (or it lies past the
    /// record's end).
    #[error("the record has no {field}")]
    MissingField {
        /// The field's name (`ID`).
        field: &'static str,
    },
    /// An 11-bit identifier above 7FFh.
    #[error("identifier {raw:X}h is not an 11-bit identifier")]
    BadId {
        /// The identifier field.
        raw: u32,
    },
    /// A data frame's length is past its data bytes field.
    #[error("data length {length} is past the record's data bytes")]
    DataPastField {
        /// The length.
        length: u64,
    },
    /// A record's variable-length `DataBytes` offset names no value of
    /// its signal data.
    #[error("no variable-length DataBytes value at offset {offset}")]
    SignalOffset {
        /// The offset.
        offset: u64,
    },
    /// A remote frame's DLC above 8.
    #[error("remote frame DLC {dlc} is above 8")]
    BadDlc {
        /// The DLC.
        dlc: u64,
    },
}

impl Mf4Error {
    /// False when the error was about one record, which was skipped:
    /// reading can go on. After a fatal error the reader gives it again on
    /// every call.
    #[must_use]
    pub const fn is_fatal(&self) -> bool {
        !matches!(
            self,
            Mf4Error::MissingField { .. }
                | Mf4Error::BadId { .. }
                | Mf4Error::DataPastField { .. }
                | Mf4Error::BadDlc { .. }
                | Mf4Error::SignalOffset { .. }
        )
    }
}

#[cfg(test)]
mod tests;
