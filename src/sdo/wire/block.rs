//! The frames of a block transfer that are the same both ways (CiA 301
//! section 7.2.4.3, SDO block download and SDO block upload): what the side
//! sending the data says around it ([`BlockDataCommand`], specifier 6 from
//! either end) and the sub-block segments ([`BlockSegment`]).

use super::{put_command, put_data, put_mux, put_u32, SdoFrame};
use crate::sdo::data::SegmentData;

/// What the side that sends a block transfer's data says before and after
/// it: the client of a block download (ccs = 6) and the server of a block
/// upload (scs = 6) send the same two frames, bit for bit (CiA 301 section
/// 7.2.4.3, initiate and end of SDO block download / upload).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BlockDataCommand {
    /// cs / ss = 0: initiate, with CRC support and the size when indicated.
    Initiate(BlockDataInitiate),
    /// cs / ss = 1: end, with the unused bytes of the last segment and the
    /// CRC.
    End {
        /// n: bytes of the last segment that carry no data (0..=7).
        unused: u8,
        /// CRC-16/XMODEM of the whole value (0 when CRC is not in use).
        crc: u16,
    },
}

/// The initiate frame of the side that sends a block transfer's data (CiA
/// 301 section 7.2.4.3, initiate SDO block download request, initiate SDO
/// block upload response): the object, the sender's CRC support and the
/// size when indicated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BlockDataInitiate {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// cc / sc: the sender supports CRC.
    pub crc: bool,
    /// Total size when s = 1.
    pub size: Option<u32>,
}

/// Block download commands a client sends (ccs = 6).
pub type ClientBlockDownload = BlockDataCommand;

/// Block upload responses a server sends (scs = 6).
pub type ServerBlockUpload = BlockDataCommand;

impl BlockDataCommand {
    /// Reads a specifier-6 frame (its length checked by the caller against
    /// [`needed`](super::needed)): bit 0 tells the initiate from the end;
    /// the initiate's s bit (bit 1) says whether bytes 4..=7 hold the size,
    /// the end's n (bits 4..=2) and CRC (bytes 1..=2) follow.
    #[inline]
    pub(super) fn parse(frame: &SdoFrame) -> Self {
        let b0 = frame.command();
        if b0 & 0x01 == 0 {
            BlockDataCommand::Initiate(BlockDataInitiate {
                index: frame.index(),
                sub: frame.sub(),
                crc: frame.crc_supported(),
                size: if b0 & 0x02 != 0 {
                    Some(frame.u32_at_4())
                } else {
                    None
                },
            })
        } else {
            BlockDataCommand::End {
                unused: (b0 >> 2) & 0x07,
                crc: frame.block_crc(),
            }
        }
    }

    /// Writes the frame into `buf`; returns the bytes it needs.
    #[inline]
    pub(super) fn emit(&self, buf: &mut [u8; 8]) -> usize {
        match *self {
            BlockDataCommand::Initiate(i) => {
                put_command(
                    buf,
                    0xE7,
                    0xC0 | u8::from(i.crc) << 2 | u8::from(i.size.is_some()) << 1,
                );
                put_mux(buf, i.index, i.sub);
                match i.size {
                    Some(size) => {
                        put_u32(buf, size);
                        8
                    }
                    None => 4,
                }
            }
            BlockDataCommand::End { unused, crc } => {
                put_command(buf, 0xFD, 0xC1 | (unused & 0x07) << 2);
                put_data(buf, 1, &crc.to_le_bytes());
                3
            }
        }
    }
}

/// One segment of a block transfer's sub-block (CiA 301 section 7.2.4.3,
/// SDO block download / upload): no command specifier, byte 0 is the
/// sequence number (bits 6..=0) and the c bit (bit 7, no more segments),
/// bytes 1..=7 the data. Its data length is not in the frame: every
/// segment carries 7 bytes, the last one's unused bytes are in the end
/// frame, so `data` holds every byte after byte 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BlockSegment {
    /// Sequence number in the sub-block (1..=127 on a valid frame).
    pub seqno: u8,
    /// The c bit: the last segment of the value.
    pub last: bool,
    /// The bytes after byte 0 (0..=7; 7 in a complete segment).
    pub data: SegmentData,
}

impl BlockSegment {
    /// Reads a sub-block segment (every checked frame is one).
    #[must_use]
    #[inline]
    pub fn parse(frame: &SdoFrame) -> Self {
        let b0 = frame.command();
        BlockSegment {
            seqno: b0 & 0x7F,
            last: b0 & 0x80 != 0,
            data: frame.data_at(1, frame.len().saturating_sub(1)),
        }
    }

    /// Writes the segment into `buf`; returns its length (1 + data).
    #[inline]
    pub fn emit(&self, buf: &mut [u8; 8]) -> usize {
        put_command(buf, 0xFF, (self.seqno & 0x7F) | u8::from(self.last) << 7);
        put_data(buf, 1, self.data.as_slice());
        self.buffer_len()
    }

    /// The bytes the segment takes: byte 0 and its data.
    #[must_use]
    pub const fn buffer_len(&self) -> usize {
        1 + self.data.len()
    }
}
