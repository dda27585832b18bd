//! The one codec shape every CANopen payload shares (smoltcp's `wire`
//! layer, rustls' `Codec` trait).
//!
//! Each protocol has one wire module, the only place its data bytes are
//! read and written:
//!
//! | protocol | checked view | representation ([`Codec`]) | module |
//! |---|---|---|---|
//! | NMT module control | [`NmtFrame`](crate::nmt::NmtFrame) | [`NmtCommand`](crate::nmt::NmtCommand) | [`nmt`](crate::nmt) |
//! | heartbeat, boot-up, node-guarding reply | [`HeartbeatFrame`](crate::nmt::HeartbeatFrame) | [`Heartbeat`](crate::nmt::Heartbeat) | [`nmt`](crate::nmt) |
//! | EMCY | [`EmcyFrame`](crate::emcy::EmcyFrame) | [`Emergency`](crate::emcy::Emergency) | [`emcy`](crate::emcy) |
//! | SYNC | [`SyncFrame`](crate::sync::SyncFrame) | [`SyncMessage`](crate::sync::SyncMessage) | [`sync`](crate::sync) |
//! | TIME | [`TimeFrame`](crate::time::TimeFrame) | [`TimeOfDay`](crate::time::TimeOfDay) | [`time`](crate::time) |
//! | LSS (CiA 305) | [`LssFrame`](crate::lss::LssFrame) | [`LssRequest`](crate::lss::LssRequest), [`LssResponse`](crate::lss::LssResponse) | [`lss`](crate::lss) |
//! | PDO | [`PdoFrame`](crate::pdo::PdoFrame) | [`Payload`](crate::bytes::Payload) | [`pdo`](crate::pdo) |
//! | SDO | [`SdoFrame`](crate::sdo::SdoFrame) | [`SdoRequest`](crate::sdo::SdoRequest), [`SdoResponse`](crate::sdo::SdoResponse) | [`sdo`](crate::sdo) |
//!
//! The checked view (`new_checked(&[u8]) -> Result`) is where a frame's
//! length is checked once; its accessors read fields without indexing.
//! The representation is the typed value: [`Codec::parse`] reads it from a
//! frame's data bytes through the view, [`Codec::emit`] writes it into a
//! caller's 8-byte buffer and returns [`Codec::buffer_len`]. Every frame
//! that parses emits back to the identical bytes (unknown bits and
//! reserved values are kept). [`Message`](crate::Message) is the enum of
//! these representations: one decode and one encode path over all of them.
//!
//! ```
//! use canopen_codec::emcy::{Emergency, ErrorCode};
//! use canopen_codec::wire::Codec;
//! let bytes = [0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0];
//! let emcy = Emergency::parse(&bytes).unwrap();
//! assert_eq!(emcy.code, ErrorCode::HEARTBEAT);
//! let mut buf = [0; 8];
//! assert_eq!(emcy.emit(&mut buf), emcy.buffer_len());
//! assert_eq!(buf, bytes);
//! ```

use crate::error::{exact_len, DecodeError};
use crate::frame::{CanFrame, CanId};

/// A typed CANopen payload: read from a frame's data bytes, written into
/// a caller's 8-byte buffer, the same way for every protocol.
pub trait Codec: Sized {
    /// Reads the data bytes of one frame (0..=8 of them). Total: any
    /// input gives a value or a [`DecodeError`] naming the length it
    /// needed, never a panic.
    fn parse(data: &[u8]) -> Result<Self, DecodeError>;

    /// Writes the data bytes into `buf` from byte 0 and returns how many
    /// ([`Codec::buffer_len`]). Bytes of `buf` past that length are not
    /// part of the frame.
    fn emit(&self, buf: &mut [u8; 8]) -> usize;

    /// The number of data bytes [`Codec::emit`] writes (0..=8).
    fn buffer_len(&self) -> usize;

    /// [`Codec::parse`] of a data frame's bytes; a remote frame is
    /// [`DecodeError::UnexpectedRemote`] (CANopen's remote frames carry
    /// no data to parse).
    #[inline]
    fn parse_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
        if frame.is_remote() {
            return Err(DecodeError::UnexpectedRemote);
        }
        Self::parse(frame.data())
    }

    /// The data frame on `id` that carries this value.
    #[must_use]
    #[inline]
    fn to_frame_on(&self, id: CanId) -> CanFrame {
        let mut buf = [0u8; 8];
        let len = self.emit(&mut buf);
        CanFrame::from_parts(id, buf, len.min(8) as u8)
    }
}

/// The view of a fixed-length payload: `data` as exactly `N` bytes, or
/// the `Truncated` / `TooLong` error naming `N` (the length check every
/// fixed-length checked view makes once).
#[inline]
pub(crate) fn fixed<const N: usize>(data: &[u8]) -> Result<&[u8; N], DecodeError> {
    exact_len(data, N)?;
    <&[u8; N]>::try_from(data).map_err(|_| DecodeError::Truncated {
        need: N,
        got: data.len(),
    })
}

/// Writes `src` at the start of `buf` (at most 8 bytes); returns the
/// length written.
#[inline]
pub(crate) fn put(buf: &mut [u8; 8], src: &[u8]) -> usize {
    crate::bytes::copy_payload(buf, src);
    src.len().min(8)
}

/// For the crate's tests: `emit(parse(x)) == x` for every `x` that parses,
/// with `buffer_len` the emitted length.
#[cfg(test)]
pub(crate) fn assert_round_trip<T: Codec + core::fmt::Debug>(data: &[u8]) -> Option<T> {
    let value = T::parse(data).ok()?;
    let mut buf = [0xA5u8; 8];
    let len = value.emit(&mut buf);
    assert_eq!(len, value.buffer_len(), "{value:?}");
    assert_eq!(buf.get(..len), Some(data), "{value:?}");
    Some(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_checks_the_length_once() {
        assert_eq!(fixed::<2>(&[1, 2]), Ok(&[1, 2]));
        assert_eq!(
            fixed::<2>(&[1]),
            Err(DecodeError::Truncated { need: 2, got: 1 })
        );
        assert_eq!(
            fixed::<2>(&[1, 2, 3]),
            Err(DecodeError::TooLong { max: 2, got: 3 })
        );
        assert_eq!(fixed::<0>(&[]), Ok(&[]));
    }

    #[test]
    fn put_copies_at_most_eight_bytes() {
        let mut buf = [9; 8];
        assert_eq!(put(&mut buf, &[1, 2]), 2);
        assert_eq!(buf, [1, 2, 9, 9, 9, 9, 9, 9]);
        assert_eq!(put(&mut buf, &[7; 12]), 8);
        assert_eq!(buf, [7; 8]);
    }
}
