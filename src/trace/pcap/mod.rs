//! pcap and pcapng capture files of a SocketCAN interface (what Wireshark,
//! dumpcap and tcpdump write when they capture `can0`), read from byte
//! chunks the caller feeds: sans-IO, no allocation, bounded memory (one
//! 96-byte buffer and a table of [`MAX_INTERFACES`] interfaces, whatever
//! the lengths in the file say).
//!
//! The layouts are those of the IETF drafts "PCAP Capture File Format"
//! (draft-ietf-opsawg-pcap) and "PCAP Now Generic (pcapng) Capture File
//! Format" (draft-ietf-opsawg-pcapng), and of the tcpdump.org link-layer
//! header type registry for `LINKTYPE_CAN_SOCKETCAN`:
//!
//! - **pcap** (section 4 of the first): a 24-byte file header whose magic
//!   number `A1B2C3D4h` (microsecond times) or `A1B23C4Dh` (nanosecond
//!   times), written in the writer's byte order, gives the byte order of
//!   every field; its link type (low 16 bits of the last field) is that of
//!   every packet. Each packet record: seconds, micro- or nanoseconds,
//!   captured length, original length (u32 each), then the captured bytes.
//! - **pcapng** (section 4 of the second): blocks of type (u32), total
//!   length (u32, a multiple of 4, at least 12), body, and the total
//!   length again. A Section Header Block (type `0A0D0D0Ah`) begins each
//!   section; its byte-order magic `1A2B3C4Dh` gives the byte order of the
//!   section's blocks. Interface Description Blocks (type 1) number the
//!   section's interfaces from 0, each with its link type and options, of
//!   which `if_tsresol` (9: the time unit, 10^-n s, or 2^-n s when its top
//!   bit is set; microseconds when absent) and `if_tsoffset` (14: seconds
//!   added to every time) are honoured. Enhanced Packet Blocks (6:
//!   interface, 64-bit time, captured and original length, data), Simple
//!   Packet Blocks (3: interface 0, no time) and the obsolete Packet Block
//!   (2) carry the packets; every other block is skipped by its length. A
//!   new section forgets the interfaces of the last.
//! - **`LINKTYPE_CAN_SOCKETCAN`** (227): the Linux `struct can_frame` /
//!   `struct canfd_frame` with the CAN identifier and flags word in
//!   **network byte order** (big-endian, whatever the file's byte order:
//!   the capture library swaps it from the host's), bit 31 set for a
//!   29-bit identifier, bit 30 a remote frame, bit 29 an error frame; then
//!   the payload length (u8), the FD flags (u8; bit 2 `CANFD_FDF` marks a
//!   CAN FD frame, which older writers leave clear: a 72-byte packet or a
//!   payload over 8 bytes is CAN FD too), two reserved bytes and the
//!   payload. A CAN XL frame (bit 7 of the fifth byte, `CANXL_XLF`) has
//!   another layout.
//!
//! Classic CAN frames are [`PcapEvent::Frame`]s. CAN FD, CAN XL and error
//! frames, and every packet of another link type, are
//! [`PcapEvent::Unsupported`] (one per packet, never silently nothing). A
//! malformed packet is a [`PcapError`] the reader goes on after
//! ([`PcapError::is_fatal`] false); an error of the file's structure ends
//! the read.
//!
//! ```
//! use canopen_codec::trace::pcap::{PcapEvent, PcapReader};
//! let mut file = Vec::new();
//! // A little-endian pcap header: microseconds, link type 227.
//! file.extend_from_slice(&0xA1B2_C3D4u32.to_le_bytes());
//! file.extend_from_slice(&[2, 0, 4, 0]);
//! file.extend_from_slice(&[0; 8]);
//! file.extend_from_slice(&65_535u32.to_le_bytes());
//! file.extend_from_slice(&227u32.to_le_bytes());
//! // One packet at 1.5 s: 18A#7413.
//! file.extend_from_slice(&1u32.to_le_bytes());
//! file.extend_from_slice(&500_000u32.to_le_bytes());
//! file.extend_from_slice(&16u32.to_le_bytes());
//! file.extend_from_slice(&16u32.to_le_bytes());
//! file.extend_from_slice(&[0, 0, 0x01, 0x8A, 2, 0, 0, 0, 0x74, 0x13, 0, 0, 0, 0, 0, 0]);
//! let mut reader = PcapReader::new();
//! let mut frames = Vec::new();
//! for mut chunk in file.chunks(5) {
//!     while let Some(event) = reader.read(&mut chunk).unwrap() {
//!         if let PcapEvent::Frame(f) = event {
//!             frames.push(f);
//!         }
//!     }
//! }
//! reader.finish().unwrap();
//! assert_eq!(frames[0].frame.to_string(), "18A#7413");
//! assert_eq!(frames[0].timestamp.unwrap().as_micros(), 1_500_000);
//! ```

mod reader;
mod socketcan;

pub use reader::PcapReader;

use super::{TraceFrame, Unsupported};
use crate::clock::Timestamp;
use crate::frame::CanFrame;

/// `LINKTYPE_CAN_SOCKETCAN`: Linux SocketCAN frames (tcpdump.org's
/// link-layer header type registry).
pub const LINKTYPE_CAN_SOCKETCAN: u16 = 227;
/// The most interfaces of one pcapng section this reader keeps (a packet
/// of a later one is a [`PcapError::TooManyInterfaces`]).
pub const MAX_INTERFACES: usize = 64;
/// The longest packet record of a pcap file this reader accepts (262144
/// bytes, Wireshark's limit for ordinary link types): a longer one is
/// taken for a corrupt length.
pub const MAX_RECORD: u32 = 262_144;
/// The longest pcapng block this reader accepts (16 MiB): a longer one is
/// taken for a corrupt length.
pub const MAX_BLOCK: u32 = 16 * 1024 * 1024;

/// A Section Header Block's type, the first bytes of a pcapng file.
const SHB: u32 = 0x0A0D_0D0A;
/// A Section Header Block's byte-order magic.
const BYTE_ORDER_MAGIC: u32 = 0x1A2B_3C4D;
/// Block types (pcapng section 4).
const IDB: u32 = 1;
const PB: u32 = 2;
const SPB: u32 = 3;
const EPB: u32 = 6;
/// pcap magic numbers (microsecond and nanosecond times).
const PCAP_MICROS: u32 = 0xA1B2_C3D4;
const PCAP_NANOS: u32 = 0xA1B2_3C4D;

/// The two file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Flavor {
    /// pcap (the libpcap format), with micro- or nanosecond times.
    Pcap {
        /// Times in nanoseconds (magic `A1B23C4Dh`).
        nanos: bool,
    },
    /// pcapng.
    PcapNg,
}

impl Flavor {
    /// The format whose magic number `head` (a file's first four bytes or
    /// more) begins with, in either byte order.
    ///
    /// ```
    /// use canopen_codec::trace::pcap::Flavor;
    /// assert_eq!(Flavor::detect(&[0x0A, 0x0D, 0x0D, 0x0A]), Some(Flavor::PcapNg));
    /// assert_eq!(Flavor::detect(&[0xA1, 0xB2, 0x3C, 0x4D]), Some(Flavor::Pcap { nanos: true }));
    /// assert_eq!(Flavor::detect(&[0xD4, 0xC3, 0xB2, 0xA1]), Some(Flavor::Pcap { nanos: false }));
    /// assert_eq!(Flavor::detect(b"LOGG"), None);
    /// ```
    #[must_use]
    pub fn detect(head: &[u8]) -> Option<Flavor> {
        let magic: [u8; 4] = head.get(..4)?.try_into().ok()?;
        let (be, le) = (u32::from_be_bytes(magic), u32::from_le_bytes(magic));
        if be == SHB {
            Some(Flavor::PcapNg)
        } else if be == PCAP_MICROS || le == PCAP_MICROS {
            Some(Flavor::Pcap { nanos: false })
        } else if be == PCAP_NANOS || le == PCAP_NANOS {
            Some(Flavor::Pcap { nanos: true })
        } else {
            None
        }
    }
}

/// A classic CAN frame of a capture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PcapFrame {
    /// UNIX time to the nearest microsecond (`None` for a Simple Packet
    /// Block, which has none, or a time past the range of [`Timestamp`]).
    pub timestamp: Option<Timestamp>,
    /// The interface (pcapng: its number in the section; pcap: 0).
    pub interface: u32,
    /// The frame.
    pub frame: CanFrame,
}

impl PcapFrame {
    /// The frame as the line formats give theirs (no channel name, no
    /// direction).
    #[must_use]
    pub const fn trace_frame(&self) -> TraceFrame<'static> {
        TraceFrame {
            timestamp: self.timestamp,
            channel: None,
            direction: None,
            frame: self.frame,
        }
    }
}

/// What the reader found: one event per packet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum PcapEvent {
    /// A classic CAN frame.
    Frame(PcapFrame),
    /// A packet read but not decoded: CAN FD, CAN XL or error frames
    /// ([`Unsupported::CanFd`], [`Unsupported::CanXl`],
    /// [`Unsupported::ErrorFrame`]), or a packet of another link type
    /// ([`Unsupported::LinkType`]).
    Unsupported {
        /// What it is.
        what: Unsupported,
        /// Its interface's link type.
        link_type: u16,
        /// Its time, as a frame's.
        timestamp: Option<Timestamp>,
        /// What the bus load counts of a CAN FD frame (its identifier,
        /// flags and data) or an error frame; `None` for anything else.
        on_bus: Option<crate::trace::OnBus>,
    },
}

/// Why a capture cannot be read. [`is_fatal`](Self::is_fatal) says
/// whether reading can go on (a malformed packet is skipped by its
/// length).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PcapError {
    /// The file begins with neither a pcap magic number nor a Section
    /// Header Block.
    #[error("not a pcap or pcapng file (no magic number)")]
    NotPcap,
    /// A format version this reader does not know (pcap 2.x, pcapng 1.x).
    #[error("version {major}.{minor} is not pcap 2.x or pcapng 1.x")]
    Version {
        /// The major version.
        major: u16,
        /// The minor version.
        minor: u16,
    },
    /// A Section Header Block whose byte-order magic is neither order of
    /// `1A2B3C4Dh`.
    #[error("section header at byte {offset} has no byte-order magic")]
    ByteOrder {
        /// Bytes into the file.
        offset: u64,
    },
    /// A pcapng block length below 12 bytes, not a multiple of 4, or past
    /// [`MAX_BLOCK`].
    #[error("block at byte {offset} has length {length}")]
    BlockLength {
        /// Bytes into the file.
        offset: u64,
        /// Its length.
        length: u32,
    },
    /// A block's trailing length differs from its leading one.
    #[error("block at byte {offset}: trailing length {trailing} is not its length {length}")]
    TrailingLength {
        /// Bytes into the file of the block's start.
        offset: u64,
        /// The leading length.
        length: u32,
        /// The trailing length.
        trailing: u32,
    },
    /// A block shorter than its fixed fields, or an option of an Interface
    /// Description Block that runs past its block.
    #[error("block of type {block_type} at byte {offset} is too short for its fields")]
    BlockTooShort {
        /// The block's type.
        block_type: u32,
        /// Bytes into the file of the block's start.
        offset: u64,
    },
    /// A pcap packet record longer than [`MAX_RECORD`].
    #[error("packet record of {length} bytes is past {MAX_RECORD}: a corrupt length")]
    RecordLength {
        /// Its captured length.
        length: u32,
    },
    /// A packet block whose captured length runs past its block.
    #[error("captured length {captured} runs past its block")]
    CapturedPastBlock {
        /// The captured length.
        captured: u32,
    },
    /// A packet of an interface no Interface Description Block of the
    /// section described.
    #[error("interface {interface} is not described in its section")]
    UnknownInterface {
        /// The interface number.
        interface: u32,
    },
    /// A packet of an interface past the [`MAX_INTERFACES`] kept.
    #[error("interface {interface} is past the {MAX_INTERFACES} this reader keeps")]
    TooManyInterfaces {
        /// The interface number.
        interface: u32,
    },
    /// A SocketCAN packet shorter than its header, or than the payload
    /// length it gives.
    #[error("SocketCAN packet of {captured} bytes is too short for its header and payload")]
    SocketCanTooShort {
        /// The captured length.
        captured: u32,
    },
    /// A classic frame with an 11-bit identifier above 7FFh.
    #[error("identifier {raw:X}h is not an 11-bit identifier")]
    BadId {
        /// The identifier bits.
        raw: u32,
    },
    /// A classic frame with a payload length above 8.
    #[error("payload length {length} of a classic frame is above 8")]
    PayloadLength {
        /// The length.
        length: u8,
    },
    /// The file ends inside its header, a block or a record.
    #[error("the file ends inside {0}")]
    Truncated(&'static str),
}

impl PcapError {
    /// True when the rest of the file cannot be read: an error of the
    /// file's structure (a malformed packet is skipped by its length).
    #[must_use]
    pub const fn is_fatal(&self) -> bool {
        !matches!(
            self,
            PcapError::CapturedPastBlock { .. }
                | PcapError::UnknownInterface { .. }
                | PcapError::TooManyInterfaces { .. }
                | PcapError::SocketCanTooShort { .. }
                | PcapError::BadId { .. }
                | PcapError::PayloadLength { .. }
        )
    }
}

#[cfg(test)]
mod tests;
