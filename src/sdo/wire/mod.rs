//! The SDO wire layer, CiA 301 section 7.2.4.3 (SDO protocols): the one
//! place where the 8 data bytes of an SDO frame are read and written.
//!
//! - [`SdoFrame`] is the checked view: 1..=8 data bytes, read through
//!   accessors that cannot index out of bounds (bytes past the frame's
//!   length read as zero).
//! - [`ClientCommand`] (requests, client to server on 0x600 + node) and
//!   [`ServerCommand`] (responses, server to client on 0x580 + node), with
//!   their block families [`ClientBlockUpload`], [`ClientBlockDownload`],
//!   [`ServerBlockDownload`] and [`ServerBlockUpload`], are the typed
//!   representation: `parse(&SdoFrame)` reads one, `emit(&mut [u8; 8])`
//!   writes one and returns the length it needs, `buffer_len` is that
//!   length. Every user (client, server, observer, `Message::decode`, the
//!   decoder program, the firmware nodes) goes through them.
//! - [`needed`] is the one length rule: how many bytes each command
//!   needs, by the side that sends it.
//! - [`SdoRequest`] and [`SdoResponse`] pair a command with the frame's
//!   bytes so that bytes the command leaves undefined (reserved bits,
//!   padding after the n field, garbage in unused expedited bytes, a DLC
//!   below 8) survive a decode/encode round trip.
//!
//! **Short frames**: a frame shorter than 8 bytes decodes when every byte its
//! command needs is present (python-canopen sends DLC 5 expedited responses);
//! otherwise it is [`DecodeError::Truncated`] with the length the command
//! needs.
//!
//! **Block transfer sub-block segments** carry no command specifier (byte 0 is
//! a sequence number). A stateless decoder cannot tell them apart, so they
//! decode as whatever specifier their bits spell; a block-transfer state
//! machine reads them as [`BlockSegment`]s (see [`SdoRequest::bytes`] /
//! [`SdoResponse::bytes`] for the bytes themselves).

use byteorder::{ByteOrder, LittleEndian};

use super::data::{InitiatePayload, Segment};
use crate::abort::AbortCode;
use crate::error::DecodeError;
use crate::frame::CanFrame;
use crate::wire::Codec;

mod block;
mod request;
mod response;
pub(crate) mod view;

pub use block::{
    BlockDataCommand, BlockDataInitiate, BlockSegment, ClientBlockDownload, ServerBlockUpload,
};
pub use request::{BlockUploadInitiate, ClientBlockUpload, ClientCommand};
pub use response::{BlockDownloadAccept, ServerBlockDownload, ServerCommand};

/// Which end of an SDO channel sent a frame, or aborted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// The SDO client.
    Client,
    /// The SDO server.
    Server,
}

impl Side {
    /// The other end.
    #[must_use]
    pub const fn other(self) -> Self {
        match self {
            Side::Client => Side::Server,
            Side::Server => Side::Client,
        }
    }
}

/// The data bytes of one SDO frame, checked to be 1..=8 (CiA 301: every
/// SDO frame starts with its command byte). The bytes are held padded to
/// 8 with zeros, so every accessor reads a byte that exists; whether a
/// command has all the bytes it needs is [`needed`]'s rule, checked by
/// `parse`.
///
/// ```
/// use canopen_codec::sdo::{ClientCommand, SdoFrame};
/// let frame = SdoFrame::new_checked(&[0x40, 0x18, 0x10, 0x01]).unwrap();
/// assert_eq!((frame.specifier(), frame.index(), frame.sub()), (2, 0x1018, 1));
/// assert_eq!(
///     ClientCommand::parse(&frame),
///     Ok(ClientCommand::InitiateUpload { index: 0x1018, sub: 1 })
/// );
/// assert!(SdoFrame::new_checked(&[]).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SdoFrame {
    bytes: [u8; 8],
    len: u8,
}

impl SdoFrame {
    /// Eight zero bytes: the frame a command is emitted onto when no
    /// received frame's bytes are to be kept.
    pub(crate) const ZERO: SdoFrame = SdoFrame {
        bytes: [0; 8],
        len: 8,
    };

    /// The view of `data`: [`DecodeError::TooLong`] above 8 bytes,
    /// [`DecodeError::Truncated`] when empty.
    pub fn new_checked(data: &[u8]) -> Result<Self, DecodeError> {
        if data.len() > 8 {
            return Err(DecodeError::TooLong {
                max: 8,
                got: data.len(),
            });
        }
        let mut bytes = [0u8; 8];
        crate::bytes::copy_payload(&mut bytes, data);
        Self::padded(bytes, data.len() as u8)
    }

    /// The view of a CAN frame's data (its zero-padded buffer, no copy
    /// loop): [`DecodeError::Truncated`] for DLC 0.
    #[inline(always)]
    pub fn of_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
        Self::padded(frame.padded_data(), frame.dlc().min(8))
    }

    #[inline(always)]
    fn padded(bytes: [u8; 8], len: u8) -> Result<Self, DecodeError> {
        if len == 0 {
            return Err(DecodeError::Truncated { need: 1, got: 0 });
        }
        Ok(SdoFrame { bytes, len })
    }

    /// The number of data bytes (1..=8).
    #[must_use]
    #[inline]
    pub const fn len(&self) -> usize {
        self.len as usize
    }

    /// Never true: a checked frame has its command byte.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The data bytes.
    #[must_use]
    pub fn as_bytes(&self) -> &[u8] {
        self.bytes.get(..self.len()).unwrap_or(&[])
    }

    /// Byte 0, the command byte.
    #[must_use]
    #[inline]
    pub const fn command(&self) -> u8 {
        let [b0, ..] = self.bytes;
        b0
    }

    /// The command specifier: bits 7..=5 of byte 0 (ccs of a request, scs
    /// of a response).
    #[must_use]
    #[inline]
    pub const fn specifier(&self) -> u8 {
        self.command() >> 5
    }

    /// Byte `i` (0..=7), zero past the frame's length and past byte 7.
    #[must_use]
    #[inline]
    pub const fn byte(&self, i: usize) -> u8 {
        if i < 8 {
            self.bytes[i]
        } else {
            0
        }
    }

    /// The multiplexer's index: bytes 1..=2, little-endian.
    #[must_use]
    #[inline]
    pub const fn index(&self) -> u16 {
        let [_, lo, hi, ..] = self.bytes;
        u16::from_le_bytes([lo, hi])
    }

    /// The multiplexer's sub-index: byte 3.
    #[must_use]
    #[inline]
    pub const fn sub(&self) -> u8 {
        let [_, _, _, sub, ..] = self.bytes;
        sub
    }

    /// The CRC of a block end frame: bytes 1..=2, little-endian (where
    /// other commands have the index).
    #[must_use]
    #[inline]
    pub const fn block_crc(&self) -> u16 {
        self.index()
    }

    /// Bytes 4..=7 as a little-endian `u32` (an abort code, an indicated
    /// size, expedited data).
    #[must_use]
    #[inline]
    pub const fn u32_at_4(&self) -> u32 {
        let [.., a, b, c, d] = self.bytes;
        u32::from_le_bytes([a, b, c, d])
    }

    /// `len` data bytes from byte `at` (at most `N`; zero past the
    /// frame's length).
    #[inline(always)]
    fn data_at<const N: usize>(&self, at: u32, len: usize) -> crate::bytes::InlineData<N> {
        let tail = u64::from_le_bytes(self.bytes)
            .checked_shr(8 * at)
            .unwrap_or(0);
        crate::bytes::InlineData::from_le_word(tail, len)
    }

    /// `Ok` when the frame has `need` bytes, else the `Truncated` error.
    #[inline]
    pub fn check_len(&self, need: usize) -> Result<(), DecodeError> {
        if self.len() < need {
            Err(DecodeError::Truncated {
                need,
                got: self.len(),
            })
        } else {
            Ok(())
        }
    }

    /// The t bit (bit 4 of byte 0) of a segment, a segment request or a
    /// segment acknowledgement.
    #[inline]
    const fn toggle(&self) -> bool {
        self.command() & 0x10 != 0
    }

    /// The cc / sc bit (bit 2 of byte 0) of a block initiate: its sender
    /// supports CRC.
    #[inline]
    const fn crc_supported(&self) -> bool {
        self.command() & 0x04 != 0
    }

    /// The abort code of an abort frame (bytes 4..=7).
    #[inline]
    fn abort_code(&self) -> AbortCode {
        AbortCode::from(self.u32_at_4())
    }

    /// True when the frame is a segment (specifier 0, with its data) or
    /// the toggle-only command of specifier `toggle_only` that answers
    /// one (the upload segment request, 3, or the download segment
    /// acknowledgement, 1): the frames that make nearly every step of a
    /// segmented transfer.
    #[inline(always)]
    fn is_segment_or(&self, toggle_only: u8) -> bool {
        match self.specifier() {
            0 => self.len() > segment_data_len(self.command()),
            s => s == toggle_only,
        }
    }

    /// A segment (request ccs = 0, response scs = 0): toggle bit 4, c bit 0,
    /// 7 - n data bytes after byte 0 (n in bits 3..=1).
    #[inline]
    fn segment(&self) -> Segment {
        let b0 = self.command();
        Segment {
            toggle: self.toggle(),
            last: b0 & 0x01 != 0,
            data: self.data_at(1, segment_data_len(b0)),
        }
    }

    /// The payload of an initiate (download request, upload response):
    /// e (bit 1) and s (bit 0) choose expedited data or the segmented size.
    #[inline]
    fn initiate_payload(&self) -> InitiatePayload {
        let b0 = self.command();
        let size_indicated = b0 & 0x01 != 0;
        if b0 & 0x02 != 0 {
            // Without the size: every data byte the frame carried.
            let len = if size_indicated {
                expedited_len(b0)
            } else {
                self.len().saturating_sub(4)
            };
            InitiatePayload::Expedited {
                data: self.data_at(4, len),
                size_indicated,
            }
        } else {
            InitiatePayload::Segmented {
                size: if size_indicated {
                    Some(self.u32_at_4())
                } else {
                    None
                },
            }
        }
    }
}

/// Data bytes of a segment with command byte `b0`: 7 - n.
#[inline]
const fn segment_data_len(b0: u8) -> usize {
    7 - ((b0 >> 1) & 0x07) as usize
}

/// Data bytes of an expedited initiate with the size indicated: 4 - n
/// (n in bits 3..=2).
#[inline]
const fn expedited_len(b0: u8) -> usize {
    4 - ((b0 >> 2) & 0x03) as usize
}

/// The bytes an initiate (download request, upload response) needs: the
/// multiplexer and, expedited with the size indicated, its 4 - n data
/// bytes; segmented with the size indicated, the whole frame.
#[inline]
const fn initiate_needs(b0: u8) -> usize {
    match b0 & 0x03 {
        0x03 => 4 + expedited_len(b0),
        0x01 => 8,
        _ => 4,
    }
}

/// The one length rule of SDO frames (CiA 301 section 7.2.4.3): the bytes
/// the command of byte 0 `b0` needs, sent by `from`. A shorter frame does
/// not decode ([`DecodeError::Truncated`]).
///
/// | specifier | request (client) | response (server) |
/// |---|---|---|
/// | 0 | segment: 1 + 7 - n | segment: 1 + 7 - n |
/// | 1 | initiate download: see below | segment acknowledged: 1 |
/// | 2 | initiate upload: 4 | initiate upload: see below |
/// | 3 | upload segment request: 1 | initiate download: 4 |
/// | 4 | abort: 8 | abort: 8 |
/// | 5 | block upload: initiate 6, ack 3, start / end 1 | block download: initiate 5, ack 3, end 1 |
/// | 6 | block download: initiate 4 (8 with the size), end 3 | block upload: the same |
/// | 7 | 1 | 1 |
///
/// An initiate needs the multiplexer (4 bytes), expedited with the size
/// indicated its 4 - n data bytes too, segmented with the size all 8.
#[must_use]
#[inline]
pub const fn needed(from: Side, b0: u8) -> usize {
    match (from, b0 >> 5) {
        (_, 0) => 1 + segment_data_len(b0),
        (Side::Client, 1) | (Side::Server, 2) => initiate_needs(b0),
        (Side::Client, 2) | (Side::Server, 3) => 4,
        (_, 4) => 8,
        (_, 5) => match (from, b0 & 0x03) {
            (Side::Client, 0) => 6,
            (Side::Server, 0) => 5,
            (_, 2) => 3,
            _ => 1,
        },
        (_, 6) => match b0 & 0x03 {
            0x02 => 8,
            0x00 => 4,
            _ => 3,
        },
        _ => 1,
    }
}

/// Writes the bits of byte 0 selected by `mask` (the others keep what
/// `buf` holds: reserved bits of a decoded frame survive).
#[inline]
fn put_command(buf: &mut [u8; 8], mask: u8, value: u8) {
    let [b0, ..] = buf;
    *b0 = (*b0 & !mask) | (value & mask);
}

/// Writes the multiplexer (bytes 1..=3).
#[inline]
fn put_mux(buf: &mut [u8; 8], index: u16, sub: u8) {
    let [_, lo, hi, s, ..] = buf;
    [*lo, *hi] = index.to_le_bytes();
    *s = sub;
}

/// Writes bytes 4..=7, little-endian.
#[inline]
fn put_u32(buf: &mut [u8; 8], value: u32) {
    let [.., a, b, c, d] = buf;
    [*a, *b, *c, *d] = value.to_le_bytes();
}

/// Writes `src` from byte `at` (as far as the frame reaches).
#[inline]
fn put_data(buf: &mut [u8; 8], at: usize, src: &[u8]) {
    if let Some(dst) = buf.get_mut(at..) {
        crate::bytes::copy_payload(dst, src);
    }
}

/// Emits an initiate of command specifier `specifier` (1 download
/// request, 2 upload response); returns the length it needs.
#[inline]
fn emit_initiate(
    buf: &mut [u8; 8],
    specifier: u8,
    index: u16,
    sub: u8,
    payload: &InitiatePayload,
) -> usize {
    put_mux(buf, index, sub);
    match payload {
        InitiatePayload::Expedited {
            data,
            size_indicated,
        } => {
            // e = 1; with the size indicated (s = 1), n = 4 - length in
            // bits 3..=2; without it, those bits are left as they are.
            let n = (4 - data.len().min(4)) as u8;
            let (mask, value) = if *size_indicated {
                (0xEF, n << 2 | 0x03)
            } else {
                (0xE3, 0x02)
            };
            put_command(buf, mask, specifier << 5 | value);
            put_data(buf, 4, data.as_slice());
            4 + data.len()
        }
        InitiatePayload::Segmented { size } => {
            put_command(buf, 0xE3, specifier << 5 | u8::from(size.is_some()));
            match size {
                Some(size) => {
                    put_u32(buf, *size);
                    8
                }
                None => 4,
            }
        }
    }
}

/// Emits a segment of command specifier `specifier` (0 both ways).
#[inline]
fn emit_segment(buf: &mut [u8; 8], specifier: u8, seg: &Segment) -> usize {
    let n = (7 - seg.data.len().min(7)) as u8;
    put_command(
        buf,
        0xFF,
        specifier << 5 | u8::from(seg.toggle) << 4 | n << 1 | u8::from(seg.last),
    );
    put_data(buf, 1, seg.data.as_slice());
    1 + seg.data.len()
}

/// Emits an abort (specifier 4 both ways).
#[inline]
fn emit_abort(buf: &mut [u8; 8], index: u16, sub: u8, code: AbortCode) -> usize {
    put_command(buf, 0xE0, 0x80);
    put_mux(buf, index, sub);
    put_u32(buf, code.to_u32());
    8
}

/// Emits a block acknowledgement (specifier 5, cs/ss = 2): the last
/// sequence number received in order and the next block size.
#[inline]
fn emit_block_ack(buf: &mut [u8; 8], ackseq: u8, blksize: u8) -> usize {
    put_command(buf, 0xE3, 0xA2);
    put_data(buf, 1, &[ackseq, blksize]);
    3
}

macro_rules! sdo_frame {
    ($(#[$doc:meta])* $name:ident, $cmd:ty) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub struct $name {
            /// The typed command.
            pub command: $cmd,
            frame: SdoFrame,
        }

        impl $name {
            /// A frame carrying `command`, with reserved bytes zero and DLC 8.
            #[must_use]
            #[inline]
            pub const fn new(command: $cmd) -> Self {
                $name {
                    command,
                    frame: SdoFrame::ZERO,
                }
            }

            /// Decodes a frame's data straight from its 8-byte buffer (no
            /// copy); the segments of a transfer first, the rest by
            /// [`from_view`](Self::from_view).
            #[inline(always)]
            pub fn decode_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
                let frame = SdoFrame::of_frame(frame)?;
                if <$cmd>::is_segment(&frame) {
                    return Ok(Self::segment(frame));
                }
                Self::from_view(frame)
            }

            /// True when `frame` is one of a transfer's segments (what
            /// [`segment`](Self::segment) reads).
            #[inline(always)]
            pub(crate) fn is_segment(frame: &SdoFrame) -> bool {
                <$cmd>::is_segment(frame)
            }

            /// A frame [`is_segment`](Self::is_segment) accepts, read as
            /// [`from_view`](Self::from_view) reads it.
            #[inline(always)]
            pub(crate) fn segment(frame: SdoFrame) -> Self {
                $name {
                    command: <$cmd>::parse_segment(&frame),
                    frame,
                }
            }

            /// The command of the checked `frame`, with its bytes kept.
            #[inline]
            pub fn from_view(frame: SdoFrame) -> Result<Self, DecodeError> {
                Ok($name {
                    command: <$cmd>::parse(&frame)?,
                    frame,
                })
            }

            /// The data bytes and length. Bytes the command does not define
            /// come from the decoded frame (zero for [`Self::new`]); the length
            /// is the decoded frame's, raised to what the command needs.
            #[must_use]
            #[inline]
            pub fn encode(&self) -> ([u8; 8], usize) {
                let mut bytes = self.frame.bytes;
                let need = self.command.emit(&mut bytes);
                let len = self.frame.len().max(need).min(8);
                for b in bytes.iter_mut().skip(len) {
                    *b = 0;
                }
                (bytes, len)
            }

            /// The frame's bytes as decoded (for reinterpreting block
            /// sub-block segments); for [`Self::new`], 8 zero bytes.
            #[must_use]
            pub fn bytes(&self) -> &[u8] {
                self.frame.as_bytes()
            }
        }

        impl Codec for $name {
            /// Reads an SDO frame's data (0..=8 bytes).
            #[inline]
            fn parse(data: &[u8]) -> Result<Self, DecodeError> {
                Self::from_view(SdoFrame::new_checked(data)?)
            }

            /// [`decode_frame`](Self::decode_frame): no copy on the hot path.
            #[inline]
            fn parse_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
                if frame.is_remote() {
                    return Err(DecodeError::UnexpectedRemote);
                }
                Self::decode_frame(frame)
            }

            /// [`encode`](Self::encode)'s bytes.
            #[inline]
            fn emit(&self, buf: &mut [u8; 8]) -> usize {
                let (bytes, len) = self.encode();
                *buf = bytes;
                len
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
    /// use canopen_codec::wire::Codec;
    /// // [V1] upload 1018h sub 1.
    /// let req = SdoRequest::parse(&[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]).unwrap();
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
    /// use canopen_codec::wire::Codec;
    /// // [V1b] python-canopen's DLC 5 expedited response: 1 byte, FEh.
    /// let resp = SdoResponse::parse(&[0x4F, 0x00, 0x14, 0x02, 0xFE]).unwrap();
    /// let ServerCommand::InitiateUpload { index, sub, payload } = resp.command else { panic!() };
    /// assert_eq!((index, sub), (0x1400, 2));
    /// let InitiatePayload::Expedited { data, size_indicated } = payload else { panic!() };
    /// assert_eq!((data.as_slice(), size_indicated), (&[0xFE][..], true));
    /// assert_eq!(resp.encode(), ([0x4F, 0x00, 0x14, 0x02, 0xFE, 0, 0, 0], 5));
    /// ```
    SdoResponse,
    ServerCommand
);

/// Reads the little-endian u32 abort code of an abort frame, if present.
#[must_use]
pub fn abort_code_of(data: &[u8]) -> Option<AbortCode> {
    let bytes = data.get(4..8)?;
    Some(AbortCode::from(LittleEndian::read_u32(bytes)))
}

#[cfg(test)]
mod tests;
