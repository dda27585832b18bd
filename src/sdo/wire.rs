//! SDO frames: command specifiers and their fields, CiA 301.
//!
//! Requests travel client to server (0x600 + node) and decode to
//! [`ClientCommand`]; responses travel server to client (0x580 + node) and
//! decode to [`ServerCommand`]. [`SdoRequest`] and [`SdoResponse`] pair the
//! typed command with the frame's bytes so that bytes the command leaves
//! undefined (reserved bits, padding after the n field, garbage in unused
//! expedited bytes, a DLC below 8) survive a decode/encode round trip.
//!
//! **Short frames**: a frame shorter than 8 bytes decodes when every byte its
//! command needs is present (python-canopen sends DLC 5 expedited responses);
//! otherwise it is [`DecodeError::Truncated`].
//!
//! **Block transfer sub-block segments** carry no command specifier (byte 0 is
//! a sequence number). A stateless decoder cannot tell them apart, so they
//! decode as whatever specifier their bits spell; a block-transfer state
//! machine reinterprets them through [`SdoRequest::bytes`] /
//! [`SdoResponse::bytes`].

use byteorder::{ByteOrder, LittleEndian};

use super::abort::AbortCode;
use super::data::{ExpeditedData, InitiatePayload, Segment, SegmentData};
use crate::error::DecodeError;
use crate::frame::CanFrame;

/// Block upload commands a client sends (ccs = 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ClientBlockUpload {
    /// cs = 0: initiate, with the client's CRC support, block size and
    /// protocol switch threshold.
    Initiate {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// cc: client supports CRC.
        crc: bool,
        /// Segments per block, 1..=127 (kept as received).
        blksize: u8,
        /// Protocol switch threshold (0: no switch).
        pst: u8,
    },
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

/// Block download commands a client sends (ccs = 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ClientBlockDownload {
    /// cs = 0: initiate, with CRC support and the size when indicated.
    Initiate {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// cc: client supports CRC.
        crc: bool,
        /// Total size when s = 1.
        size: Option<u32>,
    },
    /// cs = 1: end, with the unused bytes of the last segment and the CRC.
    End {
        /// n: bytes of the last segment that carry no data (0..=7).
        unused: u8,
        /// CRC-16/XMODEM of the whole value (0 when CRC is not in use).
        crc: u16,
    },
}

/// Block download responses a server sends (scs = 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServerBlockDownload {
    /// ss = 0: initiate response.
    Initiate {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// sc: server supports CRC.
        crc: bool,
        /// Segments per block.
        blksize: u8,
    },
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

/// Block upload responses a server sends (scs = 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServerBlockUpload {
    /// ss = 0: initiate response, with CRC support and size when indicated.
    Initiate {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// sc: server supports CRC.
        crc: bool,
        /// Total size when s = 1.
        size: Option<u32>,
    },
    /// ss = 1: end, with the unused bytes of the last segment and the CRC.
    End {
        /// n: bytes of the last segment that carry no data (0..=7).
        unused: u8,
        /// CRC-16/XMODEM of the whole value.
        crc: u16,
    },
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

/// The frame bytes behind a typed command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct RawSdo {
    len: u8,
    bytes: [u8; 8],
}

impl RawSdo {
    const ZERO: RawSdo = RawSdo {
        len: 8,
        bytes: [0; 8],
    };

    #[inline(always)]
    fn of_frame(frame: &CanFrame) -> Self {
        RawSdo {
            len: frame.dlc().min(8),
            bytes: frame.padded_data(),
        }
    }

    #[inline]
    fn from_slice(data: &[u8]) -> Result<Self, DecodeError> {
        if data.len() > 8 {
            return Err(DecodeError::TooLong {
                max: 8,
                got: data.len(),
            });
        }
        let mut bytes = [0u8; 8];
        crate::bytes::copy_payload(&mut bytes, data);
        Ok(RawSdo {
            len: data.len() as u8,
            bytes,
        })
    }
}

/// Reads bytes of the frame, failing with `Truncated` when `need` bytes are
/// not all present.
struct Reader<'a> {
    raw: &'a RawSdo,
}

impl Reader<'_> {
    #[inline]
    fn need(&self, need: usize) -> Result<(), DecodeError> {
        if usize::from(self.raw.len) < need {
            Err(DecodeError::Truncated {
                need,
                got: usize::from(self.raw.len),
            })
        } else {
            Ok(())
        }
    }
    #[inline]
    fn b(&self, i: usize) -> u8 {
        self.raw.bytes.get(i).copied().unwrap_or(0)
    }
    /// All 8 bytes as one little-endian word (zero past the length).
    #[inline]
    fn word(&self) -> u64 {
        u64::from_le_bytes(self.raw.bytes)
    }
    #[inline]
    fn u16(&self, i: usize) -> u16 {
        u16::from_le_bytes([self.b(i), self.b(i + 1)])
    }
    #[inline]
    fn u32(&self, i: usize) -> u32 {
        u32::from_le_bytes([self.b(i), self.b(i + 1), self.b(i + 2), self.b(i + 3)])
    }
    #[inline]
    fn multiplexer(&self) -> Result<(u16, u8), DecodeError> {
        self.need(4)?;
        Ok((self.u16(1), self.b(3)))
    }
    /// Initiate payload (shared by download request and upload response).
    #[inline]
    fn initiate_payload(&self) -> Result<InitiatePayload, DecodeError> {
        let cmd = self.b(0);
        let e = cmd & 0x02 != 0;
        let s = cmd & 0x01 != 0;
        match (e, s) {
            (true, true) => {
                let len = 4 - usize::from((cmd >> 2) & 0x03);
                self.need(4 + len)?;
                Ok(InitiatePayload::Expedited {
                    data: ExpeditedData::from_le_word(self.word() >> 32, len),
                    size_indicated: true,
                })
            }
            (true, false) => {
                self.need(4)?;
                let end = usize::from(self.raw.len).min(8);
                Ok(InitiatePayload::Expedited {
                    data: ExpeditedData::from_le_word(self.word() >> 32, end.saturating_sub(4)),
                    size_indicated: false,
                })
            }
            (false, true) => {
                self.need(8)?;
                Ok(InitiatePayload::Segmented {
                    size: Some(self.u32(4)),
                })
            }
            (false, false) => {
                self.need(4)?;
                Ok(InitiatePayload::Segmented { size: None })
            }
        }
    }
    #[inline]
    fn segment(&self) -> Result<Segment, DecodeError> {
        let cmd = self.b(0);
        let len = 7 - usize::from((cmd >> 1) & 0x07);
        self.need(1 + len)?;
        Ok(Segment {
            toggle: cmd & 0x10 != 0,
            last: cmd & 0x01 != 0,
            data: SegmentData::from_le_word(self.word() >> 8, len),
        })
    }
    #[inline]
    fn abort(&self) -> Result<(u16, u8, AbortCode), DecodeError> {
        self.need(8)?;
        Ok((self.u16(1), self.b(3), AbortCode::from(self.u32(4))))
    }
    #[inline]
    fn size_if(&self, s: bool) -> Result<Option<u32>, DecodeError> {
        if s {
            self.need(8)?;
            Ok(Some(self.u32(4)))
        } else {
            Ok(None)
        }
    }
}

/// Writes typed fields over the frame's bytes.
struct Writer {
    raw: RawSdo,
    need: usize,
}

impl Writer {
    #[inline]
    fn new(raw: RawSdo) -> Self {
        Writer { raw, need: 1 }
    }
    /// Sets the bits of byte 0 selected by `mask` to `value`.
    #[inline]
    fn cmd(&mut self, mask: u8, value: u8) {
        if let Some(b) = self.raw.bytes.get_mut(0) {
            *b = (*b & !mask) | (value & mask);
        }
    }
    #[inline]
    fn put(&mut self, at: usize, src: &[u8]) {
        if let Some(dst) = self.raw.bytes.get_mut(at..) {
            crate::bytes::copy_payload(dst, src);
        }
        self.need = self.need.max(at + src.len());
    }
    #[inline]
    fn multiplexer(&mut self, index: u16, sub: u8) {
        let [lo, hi] = index.to_le_bytes();
        self.put(1, &[lo, hi, sub]);
    }
    #[inline]
    fn initiate_payload(&mut self, specifier: u8, payload: &InitiatePayload) {
        match payload {
            InitiatePayload::Expedited {
                data,
                size_indicated: true,
            } => {
                let n = (4 - data.len().min(4)) as u8;
                self.cmd(0xEF, specifier << 5 | n << 2 | 0x03);
                self.need = self.need.max(4);
                self.put(4, data.as_slice());
            }
            InitiatePayload::Expedited {
                data,
                size_indicated: false,
            } => {
                self.cmd(0xE3, specifier << 5 | 0x02);
                self.need = self.need.max(4);
                self.put(4, data.as_slice());
            }
            InitiatePayload::Segmented { size: Some(size) } => {
                self.cmd(0xE3, specifier << 5 | 0x01);
                self.put(4, &size.to_le_bytes());
            }
            InitiatePayload::Segmented { size: None } => {
                self.cmd(0xE3, specifier << 5);
                self.need = self.need.max(4);
            }
        }
    }
    #[inline]
    fn segment(&mut self, specifier: u8, seg: &Segment) {
        let n = (7 - seg.data.len().min(7)) as u8;
        self.cmd(
            0xFF,
            specifier << 5 | u8::from(seg.toggle) << 4 | n << 1 | u8::from(seg.last),
        );
        self.put(1, seg.data.as_slice());
    }
    #[inline]
    fn abort(&mut self, index: u16, sub: u8, code: AbortCode) {
        self.cmd(0xE0, 0x80);
        self.multiplexer(index, sub);
        self.put(4, &code.to_u32().to_le_bytes());
    }
    #[inline]
    fn finish(mut self) -> ([u8; 8], usize) {
        let len = usize::from(self.raw.len).max(self.need).min(8);
        for b in self.raw.bytes.iter_mut().skip(len) {
            *b = 0;
        }
        (self.raw.bytes, len)
    }
}

impl ClientCommand {
    /// The command of a frame, as `SdoRequest::decode_frame` decodes it
    /// (the general decoder alone, without the frame's bytes kept).
    #[cfg(any(test, feature = "sdo-block"))]
    #[inline(always)]
    pub(crate) fn of_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
        Self::decode_raw(&RawSdo::of_frame(frame))
    }

    #[inline(always)]
    fn decode_raw(raw: &RawSdo) -> Result<Self, DecodeError> {
        let r = Reader { raw };
        r.need(1)?;
        let cmd = r.b(0);
        Ok(match cmd >> 5 {
            0 => ClientCommand::DownloadSegment(r.segment()?),
            1 => {
                let (index, sub) = r.multiplexer()?;
                ClientCommand::InitiateDownload {
                    index,
                    sub,
                    payload: r.initiate_payload()?,
                }
            }
            2 => {
                let (index, sub) = r.multiplexer()?;
                ClientCommand::InitiateUpload { index, sub }
            }
            3 => ClientCommand::UploadSegment {
                toggle: cmd & 0x10 != 0,
            },
            4 => {
                let (index, sub, code) = r.abort()?;
                ClientCommand::Abort { index, sub, code }
            }
            5 => ClientCommand::BlockUpload(match cmd & 0x03 {
                0 => {
                    r.need(6)?;
                    ClientBlockUpload::Initiate {
                        index: r.u16(1),
                        sub: r.b(3),
                        crc: cmd & 0x04 != 0,
                        blksize: r.b(4),
                        pst: r.b(5),
                    }
                }
                1 => ClientBlockUpload::End,
                2 => {
                    r.need(3)?;
                    ClientBlockUpload::Ack {
                        ackseq: r.b(1),
                        blksize: r.b(2),
                    }
                }
                _ => ClientBlockUpload::Start,
            }),
            6 => ClientCommand::BlockDownload(if cmd & 0x01 == 0 {
                let (index, sub) = r.multiplexer()?;
                ClientBlockDownload::Initiate {
                    index,
                    sub,
                    crc: cmd & 0x04 != 0,
                    size: r.size_if(cmd & 0x02 != 0)?,
                }
            } else {
                r.need(3)?;
                ClientBlockDownload::End {
                    unused: (cmd >> 2) & 0x07,
                    crc: r.u16(1),
                }
            }),
            _ => ClientCommand::Unknown(cmd),
        })
    }

    #[inline]
    fn encode_onto(&self, raw: RawSdo) -> ([u8; 8], usize) {
        let mut w = Writer::new(raw);
        match self {
            ClientCommand::DownloadSegment(seg) => w.segment(0, seg),
            ClientCommand::InitiateDownload {
                index,
                sub,
                payload,
            } => {
                w.multiplexer(*index, *sub);
                w.initiate_payload(1, payload);
            }
            ClientCommand::InitiateUpload { index, sub } => {
                w.cmd(0xE0, 0x40);
                w.multiplexer(*index, *sub);
            }
            ClientCommand::UploadSegment { toggle } => {
                w.cmd(0xF0, 0x60 | u8::from(*toggle) << 4);
            }
            ClientCommand::Abort { index, sub, code } => w.abort(*index, *sub, *code),
            ClientCommand::BlockUpload(b) => match b {
                ClientBlockUpload::Initiate {
                    index,
                    sub,
                    crc,
                    blksize,
                    pst,
                } => {
                    w.cmd(0xE7, 0xA0 | u8::from(*crc) << 2);
                    w.multiplexer(*index, *sub);
                    w.put(4, &[*blksize, *pst]);
                }
                ClientBlockUpload::End => w.cmd(0xE3, 0xA1),
                ClientBlockUpload::Ack { ackseq, blksize } => {
                    w.cmd(0xE3, 0xA2);
                    w.put(1, &[*ackseq, *blksize]);
                }
                ClientBlockUpload::Start => w.cmd(0xE3, 0xA3),
            },
            ClientCommand::BlockDownload(b) => match b {
                ClientBlockDownload::Initiate {
                    index,
                    sub,
                    crc,
                    size,
                } => {
                    w.cmd(
                        0xE7,
                        0xC0 | u8::from(*crc) << 2 | u8::from(size.is_some()) << 1,
                    );
                    w.multiplexer(*index, *sub);
                    if let Some(size) = size {
                        w.put(4, &size.to_le_bytes());
                    }
                }
                ClientBlockDownload::End { unused, crc } => {
                    w.cmd(0xFD, 0xC1 | (unused & 0x07) << 2);
                    w.put(1, &crc.to_le_bytes());
                }
            },
            ClientCommand::Unknown(b) => w.cmd(0xFF, *b),
        }
        w.finish()
    }
}

impl ServerCommand {
    /// The command of a frame, as `SdoResponse::decode_frame` decodes it
    /// (the general decoder alone, without the frame's bytes kept): the
    /// client's, with segmented transfer.
    #[cfg(any(test, feature = "sdo-client-segmented"))]
    #[inline(always)]
    pub(crate) fn of_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
        Self::decode_raw(&RawSdo::of_frame(frame))
    }

    #[inline(always)]
    fn decode_raw(raw: &RawSdo) -> Result<Self, DecodeError> {
        let r = Reader { raw };
        r.need(1)?;
        let cmd = r.b(0);
        Ok(match cmd >> 5 {
            0 => ServerCommand::UploadSegment(r.segment()?),
            1 => ServerCommand::DownloadSegment {
                toggle: cmd & 0x10 != 0,
            },
            2 => {
                let (index, sub) = r.multiplexer()?;
                ServerCommand::InitiateUpload {
                    index,
                    sub,
                    payload: r.initiate_payload()?,
                }
            }
            3 => {
                let (index, sub) = r.multiplexer()?;
                ServerCommand::InitiateDownload { index, sub }
            }
            4 => {
                let (index, sub, code) = r.abort()?;
                ServerCommand::Abort { index, sub, code }
            }
            5 => match cmd & 0x03 {
                0 => {
                    r.need(5)?;
                    ServerCommand::BlockDownload(ServerBlockDownload::Initiate {
                        index: r.u16(1),
                        sub: r.b(3),
                        crc: cmd & 0x04 != 0,
                        blksize: r.b(4),
                    })
                }
                1 => ServerCommand::BlockDownload(ServerBlockDownload::End),
                2 => {
                    r.need(3)?;
                    ServerCommand::BlockDownload(ServerBlockDownload::Ack {
                        ackseq: r.b(1),
                        blksize: r.b(2),
                    })
                }
                _ => ServerCommand::Unknown(cmd),
            },
            6 => ServerCommand::BlockUpload(if cmd & 0x01 == 0 {
                let (index, sub) = r.multiplexer()?;
                ServerBlockUpload::Initiate {
                    index,
                    sub,
                    crc: cmd & 0x04 != 0,
                    size: r.size_if(cmd & 0x02 != 0)?,
                }
            } else {
                r.need(3)?;
                ServerBlockUpload::End {
                    unused: (cmd >> 2) & 0x07,
                    crc: r.u16(1),
                }
            }),
            _ => ServerCommand::Unknown(cmd),
        })
    }

    #[inline]
    fn encode_onto(&self, raw: RawSdo) -> ([u8; 8], usize) {
        let mut w = Writer::new(raw);
        match self {
            ServerCommand::UploadSegment(seg) => w.segment(0, seg),
            ServerCommand::DownloadSegment { toggle } => {
                w.cmd(0xF0, 0x20 | u8::from(*toggle) << 4);
            }
            ServerCommand::InitiateUpload {
                index,
                sub,
                payload,
            } => {
                w.multiplexer(*index, *sub);
                w.initiate_payload(2, payload);
            }
            ServerCommand::InitiateDownload { index, sub } => {
                w.cmd(0xE0, 0x60);
                w.multiplexer(*index, *sub);
            }
            ServerCommand::Abort { index, sub, code } => w.abort(*index, *sub, *code),
            ServerCommand::BlockDownload(b) => match b {
                ServerBlockDownload::Initiate {
                    index,
                    sub,
                    crc,
                    blksize,
                } => {
                    w.cmd(0xE7, 0xA0 | u8::from(*crc) << 2);
                    w.multiplexer(*index, *sub);
                    w.put(4, &[*blksize]);
                }
                ServerBlockDownload::End => w.cmd(0xE3, 0xA1),
                ServerBlockDownload::Ack { ackseq, blksize } => {
                    w.cmd(0xE3, 0xA2);
                    w.put(1, &[*ackseq, *blksize]);
                }
            },
            ServerCommand::BlockUpload(b) => match b {
                ServerBlockUpload::Initiate {
                    index,
                    sub,
                    crc,
                    size,
                } => {
                    w.cmd(
                        0xE7,
                        0xC0 | u8::from(*crc) << 2 | u8::from(size.is_some()) << 1,
                    );
                    w.multiplexer(*index, *sub);
                    if let Some(size) = size {
                        w.put(4, &size.to_le_bytes());
                    }
                }
                ServerBlockUpload::End { unused, crc } => {
                    w.cmd(0xFD, 0xC1 | (unused & 0x07) << 2);
                    w.put(1, &crc.to_le_bytes());
                }
            },
            ServerCommand::Unknown(b) => w.cmd(0xFF, *b),
        }
        w.finish()
    }
}

macro_rules! sdo_frame {
    ($(#[$doc:meta])* $name:ident, $cmd:ty) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub struct $name {
            /// The typed command.
            pub command: $cmd,
            raw: RawSdo,
        }

        impl $name {
            /// A frame carrying `command`, with reserved bytes zero and DLC 8.
            #[must_use]
            #[inline]
            pub const fn new(command: $cmd) -> Self {
                $name {
                    command,
                    raw: RawSdo::ZERO,
                }
            }

            /// Decodes an SDO frame's data (0..=8 bytes).
            pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
                let raw = RawSdo::from_slice(data)?;
                Ok($name {
                    command: <$cmd>::decode_raw(&raw)?,
                    raw,
                })
            }

            /// Decodes a frame's data straight from its 8-byte buffer (no copy).
            #[inline]
            pub fn decode_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
                Self::decode_frame_fast(frame)
            }

            /// [`Self::decode_frame`], always inlined: `Message::decode`
            /// builds its result in place through it.
            #[inline(always)]
            pub(crate) fn decode_frame_inline(frame: &CanFrame) -> Result<Self, DecodeError> {
                let raw = RawSdo::of_frame(frame);
                Ok($name {
                    command: <$cmd>::decode_raw(&raw)?,
                    raw,
                })
            }

            /// The data bytes and length. Bytes the command does not define
            /// come from the decoded frame (zero for [`Self::new`]); the length
            /// is the decoded frame's, raised to what the command needs.
            #[must_use]
            #[inline]
            pub fn encode(&self) -> ([u8; 8], usize) {
                self.command.encode_onto(self.raw)
            }

            /// The frame's bytes as decoded (for reinterpreting block
            /// sub-block segments); for [`Self::new`], 8 zero bytes.
            #[must_use]
            pub fn bytes(&self) -> &[u8] {
                self.raw.bytes.get(..usize::from(self.raw.len)).unwrap_or(&[])
            }
        }

        impl From<$cmd> for $name {
            fn from(command: $cmd) -> Self {
                Self::new(command)
            }
        }
    };
}

sdo_frame!(
    /// A client-to-server SDO frame (0x600 + node).
    ///
    /// ```
    /// use canopen_codec::sdo::{ClientCommand, SdoRequest};
    /// // [V1] upload 1018h sub 1.
    /// let req = SdoRequest::decode(&[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]).unwrap();
    /// assert_eq!(req.command, ClientCommand::InitiateUpload { index: 0x1018, sub: 1 });
    /// assert_eq!(SdoRequest::new(req.command).encode(), ([0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0], 8));
    /// ```
    SdoRequest,
    ClientCommand
);

sdo_frame!(
    /// A server-to-client SDO frame (0x580 + node).
    ///
    /// ```
    /// use canopen_codec::sdo::{InitiatePayload, SdoResponse, ServerCommand};
    /// // [V1b] python-canopen's DLC 5 expedited response: 1 byte, FEh.
    /// let resp = SdoResponse::decode(&[0x4F, 0x00, 0x14, 0x02, 0xFE]).unwrap();
    /// let ServerCommand::InitiateUpload { index, sub, payload } = resp.command else { panic!() };
    /// assert_eq!((index, sub), (0x1400, 2));
    /// let InitiatePayload::Expedited { data, size_indicated } = payload else { panic!() };
    /// assert_eq!((data.as_slice(), size_indicated), (&[0xFE][..], true));
    /// assert_eq!(resp.encode(), ([0x4F, 0x00, 0x14, 0x02, 0xFE, 0, 0, 0], 5));
    /// ```
    SdoResponse,
    ServerCommand
);

// The segment commands alone, for `Message::decode`'s out-of-line hot
// arms: the same checks and result as `decode_frame` for a frame whose
// byte 0 has that command specifier. Check and build are apart (the check
// returns only a length; the build cannot fail), so the caller stores the
// whole message straight instead of moving a `Result` through the stack.
impl SdoResponse {
    /// The check of `decode_frame` for scs = 0: the segment's length.
    #[inline(always)]
    pub(crate) fn check_upload_segment(frame: &CanFrame) -> Result<usize, DecodeError> {
        segment_len(&RawSdo::of_frame(frame))
    }

    /// `decode_frame` for scs = 0, after [`Self::check_upload_segment`].
    #[inline(always)]
    pub(crate) fn upload_segment(frame: &CanFrame, len: usize) -> Self {
        let raw = RawSdo::of_frame(frame);
        SdoResponse {
            command: ServerCommand::UploadSegment(segment_of(&raw, len)),
            raw,
        }
    }
}

impl SdoResponse {
    /// `decode_frame`: the segment command by its own straight path, the
    /// rest by the general decoder (the client's per-frame decode).
    #[inline]
    fn decode_frame_fast(frame: &CanFrame) -> Result<Self, DecodeError> {
        let [b0, ..] = frame.padded_data();
        if b0 >> 5 == 0 {
            let len = Self::check_upload_segment(frame)?;
            Ok(Self::upload_segment(frame, len))
        } else {
            Self::decode_frame_inline(frame)
        }
    }
}

impl SdoRequest {
    /// `decode_frame`: the segment commands by their own straight paths,
    /// the rest by the general decoder (the server's per-frame decode).
    #[inline]
    fn decode_frame_fast(frame: &CanFrame) -> Result<Self, DecodeError> {
        let [b0, ..] = frame.padded_data();
        match b0 >> 5 {
            0 => {
                let len = Self::check_download_segment(frame)?;
                Ok(Self::download_segment(frame, len))
            }
            3 => {
                Self::check_upload_segment(frame)?;
                Ok(Self::upload_segment(frame))
            }
            _ => Self::decode_frame_inline(frame),
        }
    }

    /// The check of `decode_frame` for ccs = 0: the segment's length.
    #[inline(always)]
    pub(crate) fn check_download_segment(frame: &CanFrame) -> Result<usize, DecodeError> {
        segment_len(&RawSdo::of_frame(frame))
    }

    /// `decode_frame` for ccs = 0, after [`Self::check_download_segment`].
    #[inline(always)]
    pub(crate) fn download_segment(frame: &CanFrame, len: usize) -> Self {
        let raw = RawSdo::of_frame(frame);
        SdoRequest {
            command: ClientCommand::DownloadSegment(segment_of(&raw, len)),
            raw,
        }
    }

    /// The check of `decode_frame` for ccs = 3 (upload segment request).
    #[inline(always)]
    pub(crate) fn check_upload_segment(frame: &CanFrame) -> Result<(), DecodeError> {
        if frame.dlc() == 0 {
            return Err(truncated(1, 0));
        }
        Ok(())
    }

    /// `decode_frame` for ccs = 3, after [`Self::check_upload_segment`].
    #[inline(always)]
    pub(crate) fn upload_segment(frame: &CanFrame) -> Self {
        let raw = RawSdo::of_frame(frame);
        let [cmd, ..] = raw.bytes;
        SdoRequest {
            command: ClientCommand::UploadSegment {
                toggle: cmd & 0x10 != 0,
            },
            raw,
        }
    }
}

#[inline(always)]
fn truncated(need: usize, got: u8) -> DecodeError {
    DecodeError::Truncated {
        need,
        got: usize::from(got),
    }
}

/// `need(1)` then `Reader::segment`'s check: the segment's data length.
#[inline(always)]
fn segment_len(raw: &RawSdo) -> Result<usize, DecodeError> {
    let [cmd, ..] = raw.bytes;
    if raw.len == 0 {
        return Err(truncated(1, 0));
    }
    let len = 7 - usize::from((cmd >> 1) & 0x07);
    if usize::from(raw.len) < 1 + len {
        return Err(truncated(1 + len, raw.len));
    }
    Ok(len)
}

/// The segment of a checked frame (`len` from [`segment_len`]): built in
/// one straight line, no intermediate `Result` assembled on the stack.
#[inline(always)]
fn segment_of(raw: &RawSdo, len: usize) -> Segment {
    let [cmd, ..] = raw.bytes;
    Segment {
        toggle: cmd & 0x10 != 0,
        last: cmd & 0x01 != 0,
        data: SegmentData::from_le_word(u64::from_le_bytes(raw.bytes) >> 8, len),
    }
}

/// The segment of a frame checked by `check_download_segment` or
/// `check_upload_segment` (`len` is what that returned): the client's
/// upload segment (the server reads its download segments from the frame).
#[cfg(feature = "sdo-client-segmented")]
#[inline(always)]
pub(crate) fn segment_of_frame(frame: &CanFrame, len: usize) -> Segment {
    segment_of(&RawSdo::of_frame(frame), len)
}

/// Reads the little-endian u32 abort code of an abort frame, if present.
#[must_use]
pub fn abort_code_of(data: &[u8]) -> Option<AbortCode> {
    let bytes = data.get(4..8)?;
    Some(AbortCode::from(LittleEndian::read_u32(bytes)))
}

#[cfg(test)]
#[path = "wire_tests.rs"]
mod tests;
