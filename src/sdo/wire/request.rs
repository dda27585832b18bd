//! Requests, client to server (CiA 301 section 7.2.4.3, SDO protocols):
//! [`ClientCommand`] and its block families, read from and written to the
//! frame in one place.

use super::{
    emit_abort, emit_block_ack, emit_initiate, emit_segment, needed, put_command, put_data,
    put_mux, BlockDataCommand, ClientBlockDownload, SdoFrame, Side,
};
use crate::abort::AbortCode;
use crate::error::DecodeError;
use crate::sdo::data::{InitiatePayload, Segment};

/// The client's initiate of a block upload (CiA 301 section 7.2.4.3,
/// initiate SDO block upload request): the object, the client's CRC
/// support, the block size it asks for and its protocol switch threshold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BlockUploadInitiate {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// cc: client supports CRC.
    pub crc: bool,
    /// Segments per block, 1..=127 (kept as received).
    pub blksize: u8,
    /// Protocol switch threshold (0: no switch).
    pub pst: u8,
}

/// Block upload commands a client sends (ccs = 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ClientBlockUpload {
    /// cs = 0: initiate, with the client's CRC support, block size and
    /// protocol switch threshold.
    Initiate(BlockUploadInitiate),
    /// cs = 3: start the upload.
    Start,
    /// cs = 2: acknowledge a sub-block.
    Ack {
        /// Last sequence number received correctly.
        ackseq: u8,
        /// Size of the next block.
        blksize: u8,
    },
    /// cs = 1: end of the transfer acknowledged.
    End,
}

/// A client-to-server SDO command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ClientCommand {
    /// ccs = 0: a download segment.
    DownloadSegment(Segment),
    /// ccs = 1: initiate a download (write) of `index`/`sub`.
    InitiateDownload {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Expedited data or the segmented size.
        payload: InitiatePayload,
    },
    /// ccs = 2: initiate an upload (read) of `index`/`sub`.
    InitiateUpload {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
    },
    /// ccs = 3: request the next upload segment.
    UploadSegment {
        /// The t bit.
        toggle: bool,
    },
    /// ccs = 4: abort the transfer.
    Abort {
        /// Object index of the transfer.
        index: u16,
        /// Sub-index of the transfer.
        sub: u8,
        /// Why.
        code: AbortCode,
    },
    /// ccs = 5: block upload.
    BlockUpload(ClientBlockUpload),
    /// ccs = 6: block download.
    BlockDownload(ClientBlockDownload),
    /// ccs = 7 (not defined by CiA 301): byte 0 as received. A server answers
    /// it with abort 05040001h.
    Unknown(u8),
}

impl ClientCommand {
    /// [`parse`](Self::parse) of the two commands that make nearly every
    /// request of a segmented transfer (a download segment, an upload
    /// segment request), recognised without the other commands' rules:
    /// any other frame is [`parse`](Self::parse)'s. Both agree on every
    /// frame (the wire layer's tests).
    #[inline(always)]
    pub(crate) fn is_segment(frame: &SdoFrame) -> bool {
        frame.is_segment_or(3)
    }

    /// The command of a frame [`is_segment`](Self::is_segment) accepts
    /// (what [`parse`](Self::parse) gives for it).
    #[inline(always)]
    pub(crate) fn parse_segment(frame: &SdoFrame) -> Self {
        if frame.specifier() == 0 {
            ClientCommand::DownloadSegment(frame.segment())
        } else {
            ClientCommand::UploadSegment {
                toggle: frame.toggle(),
            }
        }
    }

    /// Reads the request in `frame`: [`DecodeError::Truncated`] when the
    /// frame is shorter than its command needs ([`needed`]); every byte 0
    /// decodes (ccs = 7 as [`ClientCommand::Unknown`]).
    #[inline]
    pub fn parse(frame: &SdoFrame) -> Result<Self, DecodeError> {
        let b0 = frame.command();
        frame.check_len(needed(Side::Client, b0))?;
        let (index, sub) = (frame.index(), frame.sub());
        let crc = frame.crc_supported();
        Ok(match b0 >> 5 {
            0 => ClientCommand::DownloadSegment(frame.segment()),
            1 => ClientCommand::InitiateDownload {
                index,
                sub,
                payload: frame.initiate_payload(),
            },
            2 => ClientCommand::InitiateUpload { index, sub },
            3 => ClientCommand::UploadSegment {
                toggle: frame.toggle(),
            },
            4 => ClientCommand::Abort {
                index,
                sub,
                code: frame.abort_code(),
            },
            5 => ClientCommand::BlockUpload(match b0 & 0x03 {
                0 => ClientBlockUpload::Initiate(BlockUploadInitiate {
                    index,
                    sub,
                    crc,
                    blksize: frame.byte(4),
                    pst: frame.byte(5),
                }),
                1 => ClientBlockUpload::End,
                2 => ClientBlockUpload::Ack {
                    ackseq: frame.byte(1),
                    blksize: frame.byte(2),
                },
                _ => ClientBlockUpload::Start,
            }),
            6 => ClientCommand::BlockDownload(BlockDataCommand::parse(frame)),
            _ => ClientCommand::Unknown(b0),
        })
    }

    /// Writes the request into `buf` and returns the bytes it needs. Bits
    /// and bytes the command leaves undefined keep what `buf` holds (zero
    /// for a fresh buffer; a decoded frame's reserved bits survive).
    #[inline]
    pub fn emit(&self, buf: &mut [u8; 8]) -> usize {
        match self {
            ClientCommand::DownloadSegment(seg) => emit_segment(buf, 0, seg),
            ClientCommand::InitiateDownload {
                index,
                sub,
                payload,
            } => emit_initiate(buf, 1, *index, *sub, payload),
            ClientCommand::InitiateUpload { index, sub } => {
                put_command(buf, 0xE0, 0x40);
                put_mux(buf, *index, *sub);
                4
            }
            ClientCommand::UploadSegment { toggle } => {
                put_command(buf, 0xF0, 0x60 | u8::from(*toggle) << 4);
                1
            }
            ClientCommand::Abort { index, sub, code } => emit_abort(buf, *index, *sub, *code),
            ClientCommand::BlockUpload(b) => match b {
                ClientBlockUpload::Initiate(i) => {
                    put_command(buf, 0xE7, 0xA0 | u8::from(i.crc) << 2);
                    put_mux(buf, i.index, i.sub);
                    put_data(buf, 4, &[i.blksize, i.pst]);
                    6
                }
                ClientBlockUpload::End => {
                    put_command(buf, 0xE3, 0xA1);
                    1
                }
                ClientBlockUpload::Ack { ackseq, blksize } => {
                    emit_block_ack(buf, *ackseq, *blksize)
                }
                ClientBlockUpload::Start => {
                    put_command(buf, 0xE3, 0xA3);
                    1
                }
            },
            ClientCommand::BlockDownload(b) => b.emit(buf),
            ClientCommand::Unknown(b) => {
                put_command(buf, 0xFF, *b);
                1
            }
        }
    }

    /// The bytes the request needs (what [`Self::emit`] returns).
    #[must_use]
    pub fn buffer_len(&self) -> usize {
        self.emit(&mut [0; 8])
    }

    /// The request as the 8 bytes a machine sends (DLC 8, every byte the
    /// command leaves undefined zero).
    #[must_use]
    #[inline]
    pub fn to_bytes(&self) -> [u8; 8] {
        let mut buf = [0u8; 8];
        self.emit(&mut buf);
        buf
    }
}
