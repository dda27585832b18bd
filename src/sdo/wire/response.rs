//! Responses, server to client (CiA 301 section 7.2.4.3, SDO protocols):
//! [`ServerCommand`] and its block families, read from and written to the
//! frame in one place.

use super::{
    emit_abort, emit_block_ack, emit_initiate, emit_segment, needed, put_command, put_data,
    put_mux, BlockDataCommand, SdoFrame, ServerBlockUpload, Side,
};
use crate::abort::AbortCode;
use crate::error::DecodeError;
use crate::sdo::data::{InitiatePayload, Segment};

/// The server's answer to a block download initiate (CiA 301 section
/// 7.2.4.3, initiate SDO block download response): the object, the
/// server's CRC support and the block size it asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BlockDownloadAccept {
    // `crc` last: the enum tags around it then take its niche in a layout
    // that keeps the firmware's response parsing as small as before
    // (examples/firmware/size.sh).
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// Segments per block.
    pub blksize: u8,
    /// sc: server supports CRC.
    pub crc: bool,
}

/// Block download responses a server sends (scs = 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServerBlockDownload {
    /// ss = 0: initiate response.
    Initiate(BlockDownloadAccept),
    /// ss = 2: sub-block acknowledged.
    Ack {
        /// Last sequence number received correctly.
        ackseq: u8,
        /// Size of the next block.
        blksize: u8,
    },
    /// ss = 1: end acknowledged.
    End,
}

/// A server-to-client SDO command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServerCommand {
    /// scs = 0: an upload segment.
    UploadSegment(Segment),
    /// scs = 1: a download segment acknowledged.
    DownloadSegment {
        /// The t bit (echoes the segment's).
        toggle: bool,
    },
    /// scs = 2: the upload is initiated, with expedited data or the size.
    InitiateUpload {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Expedited data or the segmented size.
        payload: InitiatePayload,
    },
    /// scs = 3: the download is initiated (or, expedited, done).
    InitiateDownload {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
    },
    /// scs = 4: abort the transfer.
    Abort {
        /// Object index of the transfer.
        index: u16,
        /// Sub-index of the transfer.
        sub: u8,
        /// Why.
        code: AbortCode,
    },
    /// scs = 5: block download response.
    BlockDownload(ServerBlockDownload),
    /// scs = 6: block upload response.
    BlockUpload(ServerBlockUpload),
    /// scs = 7, or scs = 5 with ss = 3 (not defined by CiA 301): byte 0 as
    /// received.
    Unknown(u8),
}

impl ServerCommand {
    /// [`parse`](Self::parse) of the two commands that make nearly every
    /// response of a segmented transfer (an upload segment, a download
    /// segment acknowledgement), recognised without the other commands'
    /// rules: any other frame is [`parse`](Self::parse)'s. Both agree on
    /// every frame (the wire layer's tests).
    #[inline(always)]
    pub(crate) fn is_segment(frame: &SdoFrame) -> bool {
        frame.is_segment_or(1)
    }

    /// The command of a frame [`is_segment`](Self::is_segment) accepts
    /// (what [`parse`](Self::parse) gives for it).
    #[inline(always)]
    pub(crate) fn parse_segment(frame: &SdoFrame) -> Self {
        if frame.specifier() == 0 {
            ServerCommand::UploadSegment(frame.segment())
        } else {
            ServerCommand::DownloadSegment {
                toggle: frame.toggle(),
            }
        }
    }

    /// Reads the response in `frame`: [`DecodeError::Truncated`] when the
    /// frame is shorter than its command needs ([`needed`]); every byte 0
    /// decodes (scs = 7, and scs = 5 with ss = 3, as
    /// [`ServerCommand::Unknown`]).
    #[inline]
    pub fn parse(frame: &SdoFrame) -> Result<Self, DecodeError> {
        let b0 = frame.command();
        frame.check_len(needed(Side::Server, b0))?;
        let (index, sub) = (frame.index(), frame.sub());
        let crc = frame.crc_supported();
        Ok(match b0 >> 5 {
            0 => ServerCommand::UploadSegment(frame.segment()),
            1 => ServerCommand::DownloadSegment {
                toggle: frame.toggle(),
            },
            2 => ServerCommand::InitiateUpload {
                index,
                sub,
                payload: frame.initiate_payload(),
            },
            3 => ServerCommand::InitiateDownload { index, sub },
            4 => ServerCommand::Abort {
                index,
                sub,
                code: frame.abort_code(),
            },
            5 => match b0 & 0x03 {
                0 => ServerCommand::BlockDownload(ServerBlockDownload::Initiate(
                    BlockDownloadAccept {
                        index,
                        sub,
                        crc,
                        blksize: frame.byte(4),
                    },
                )),
                1 => ServerCommand::BlockDownload(ServerBlockDownload::End),
                2 => ServerCommand::BlockDownload(ServerBlockDownload::Ack {
                    ackseq: frame.byte(1),
                    blksize: frame.byte(2),
                }),
                _ => ServerCommand::Unknown(b0),
            },
            6 => ServerCommand::BlockUpload(BlockDataCommand::parse(frame)),
            _ => ServerCommand::Unknown(b0),
        })
    }

    /// Writes the response into `buf` and returns the bytes it needs. Bits
    /// and bytes the command leaves undefined keep what `buf` holds (zero
    /// for a fresh buffer; a decoded frame's reserved bits survive).
    /// Inlined: where the command is known, only its own fields are
    /// written.
    #[inline(always)]
    pub fn emit(&self, buf: &mut [u8; 8]) -> usize {
        match self {
            ServerCommand::UploadSegment(seg) => emit_segment(buf, 0, seg),
            ServerCommand::DownloadSegment { toggle } => {
                put_command(buf, 0xF0, 0x20 | u8::from(*toggle) << 4);
                1
            }
            ServerCommand::InitiateUpload {
                index,
                sub,
                payload,
            } => emit_initiate(buf, 2, *index, *sub, payload),
            ServerCommand::InitiateDownload { index, sub } => {
                put_command(buf, 0xE0, 0x60);
                put_mux(buf, *index, *sub);
                4
            }
            ServerCommand::Abort { index, sub, code } => emit_abort(buf, *index, *sub, *code),
            ServerCommand::BlockDownload(b) => match b {
                ServerBlockDownload::Initiate(a) => {
                    put_command(buf, 0xE7, 0xA0 | u8::from(a.crc) << 2);
                    put_mux(buf, a.index, a.sub);
                    put_data(buf, 4, &[a.blksize]);
                    5
                }
                ServerBlockDownload::End => {
                    put_command(buf, 0xE3, 0xA1);
                    1
                }
                ServerBlockDownload::Ack { ackseq, blksize } => {
                    emit_block_ack(buf, *ackseq, *blksize)
                }
            },
            ServerCommand::BlockUpload(b) => b.emit(buf),
            ServerCommand::Unknown(b) => {
                put_command(buf, 0xFF, *b);
                1
            }
        }
    }

    /// The bytes the response needs (what [`Self::emit`] returns).
    #[must_use]
    pub fn buffer_len(&self) -> usize {
        self.emit(&mut [0; 8])
    }

    /// The response as the 8 bytes a machine sends (DLC 8, every byte the
    /// command leaves undefined zero).
    #[must_use]
    #[inline(always)]
    pub fn to_bytes(&self) -> [u8; 8] {
        let mut buf = [0u8; 8];
        self.emit(&mut buf);
        buf
    }
}
