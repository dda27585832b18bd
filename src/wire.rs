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

    /// The number of data bytes [`Codec::emit`] writes (0..=8): by
    /// default, what `emit` returns into a scratch buffer, so the length
    /// is stated once, in `emit`.
    #[inline]
    fn buffer_len(&self) -> usize {
        self.emit(&mut [0u8; 8])
    }

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

/// [`Codec::parse`] through a checked view: `$view::new_checked(data)`,
/// then the representation's `from_view`. With `of_frame`, also
/// [`Codec::parse_frame`] through `$view::of_frame`, which reads a data
/// frame's bytes without a slice (the decode hot path).
macro_rules! parse_through_view {
    ($view:ident) => {
        #[inline]
        fn parse(data: &[u8]) -> Result<Self, $crate::error::DecodeError> {
            $view::new_checked(data).map(|f| Self::from_view(&f))
        }
    };
    ($view:ident, of_frame) => {
        $crate::wire::parse_through_view!($view);

        #[inline]
        fn parse_frame(
            frame: &$crate::frame::CanFrame,
        ) -> Result<Self, $crate::error::DecodeError> {
            $view::of_frame(frame).map(|f| Self::from_view(&f))
        }
    };
}
pub(crate) use parse_through_view;

/// A checked view over a fixed-length payload (the EMCY, NMT module-control
/// and TIME frames of CiA 301 section 7.2: their data has one length, no
/// more, no less): the view type, holding a copy of the `$len` bytes, and
/// its `new_checked`, which makes the one length check ([`fixed`]). The
/// type's own accessors follow in its module.
macro_rules! fixed_view {
    ($(#[$meta:meta])* $name:ident, $len:literal) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub struct $name {
            bytes: [u8; $len],
        }

        impl $name {
            #[doc = concat!(
                "The view of `data`: [`DecodeError::Truncated`](crate::error::DecodeError::Truncated) below ",
                stringify!($len),
                " bytes, [`DecodeError::TooLong`](crate::error::DecodeError::TooLong) above."
            )]
            #[inline]
            pub fn new_checked(data: &[u8]) -> Result<Self, $crate::error::DecodeError> {
                Ok($name {
                    bytes: *$crate::wire::fixed::<$len>(data)?,
                })
            }
        }
    };
}
pub(crate) use fixed_view;

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

    /// `emit(parse(x)) == x` for one representation, on `data`; the frame
    /// fast path (`parse_frame`) agrees with `parse` of the frame's bytes.
    fn check<T: Codec + core::fmt::Debug + PartialEq>(
        data: &[u8],
    ) -> Result<(), proptest::test_runner::TestCaseError> {
        if let Ok(value) = T::parse(data) {
            let mut buf = [0xA5u8; 8];
            let len = value.emit(&mut buf);
            proptest::prop_assert_eq!(len, value.buffer_len(), "{:?}", value);
            proptest::prop_assert_eq!(buf.get(..len), Some(data), "{:?}", value);
        }
        let frame = CanFrame::new(CanId::Standard(0x123), data).expect("0..=8 bytes");
        proptest::prop_assert_eq!(T::parse_frame(&frame), T::parse(data));
        let remote = CanFrame::remote(CanId::Standard(0x123), frame.dlc()).expect("DLC 0..=8");
        proptest::prop_assert_eq!(
            T::parse_frame(&remote).err(),
            Some(DecodeError::UnexpectedRemote)
        );
        Ok(())
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 4096,
        ..crate::testing::proptest_config("tests/proptest-regressions/src-wire.txt")
    })]

        /// Every representation emits back exactly the bytes it parsed
        /// from, for every payload of 0..=8 bytes that parses, and reads a
        /// frame as it reads the frame's bytes. Byte 0 is often a command
        /// byte some protocol lists and the others often zero, so the
        /// typed LSS services and SDO commands come up, not only `Other`.
        #[test]
        fn every_frame_that_parses_emits_back_to_itself(
            first in proptest::prop_oneof![
                proptest::prelude::any::<u8>(),
                proptest::sample::select(&[
                    0x01u8, 0x02, 0x04, 0x05, 0x11, 0x13, 0x15, 0x17, 0x40, 0x43, 0x44, 0x46,
                    0x4B, 0x4C, 0x4F, 0x50, 0x51, 0x5A, 0x5E, 0x7F, 0x80, 0x81, 0x82, 0x85,
                ][..]),
            ],
            rest in proptest::collection::vec(
                proptest::prop_oneof![proptest::strategy::Just(0u8), proptest::prelude::any::<u8>()],
                0..=7,
            ),
            empty in proptest::bool::weighted(0.05),
        ) {
            let mut data = std::vec![first];
            data.extend(rest);
            if empty {
                data.clear();
            }
            let data = data.as_slice();
            check::<crate::nmt::NmtCommand>(data)?;
            check::<crate::nmt::Heartbeat>(data)?;
            check::<crate::emcy::Emergency>(data)?;
            check::<crate::sync::SyncMessage>(data)?;
            check::<crate::time::TimeOfDay>(data)?;
            check::<crate::lss::LssRequest>(data)?;
            check::<crate::lss::LssResponse>(data)?;
            check::<crate::bytes::Payload>(data)?;
            check::<crate::sdo::SdoRequest>(data)?;
            check::<crate::sdo::SdoResponse>(data)?;
        }
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
