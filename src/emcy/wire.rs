//! The EMCY wire layer, CiA 301 section 7.2.7.3 (Emergency object
//! protocol): the one place where the bytes of an emergency frame
//! (80h + node) are read and written.
//!
//! Frame layout, 8 bytes: bytes 0..=1 the emergency error code
//! ([`ErrorCode`], little-endian), byte 2 the error register (1001h,
//! [`ErrorRegister`]), bytes 3..=7 the manufacturer-specific error field.
//! Every 8-byte frame parses (any code, every register bit kept) and emits
//! back to itself.

use crate::cob_id::{NodeId, EMCY_BASE};
use crate::error::DecodeError;
use crate::frame::{CanFrame, CanId};
use crate::wire::{fixed_view, parse_through_view, Codec};

use super::{ErrorCode, ErrorRegister};

fixed_view! {
    /// The checked view of an EMCY frame's data: exactly 8 bytes.
    ///
    /// ```
    /// use canopen_codec::emcy::EmcyFrame;
    /// let f = EmcyFrame::new_checked(&[0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0]).unwrap();
    /// assert_eq!((f.code(), f.register()), (0x8130, 0x01));
    /// assert_eq!(f.manufacturer(), [0x20, 0x80, 0, 0, 0]);
    /// assert!(EmcyFrame::new_checked(&[0x30, 0x81, 0x01]).is_err());
    /// ```
    EmcyFrame, 8
}

impl EmcyFrame {
    /// The view of a data frame's bytes straight from its padded buffer
    /// (the hot path: no slice), the same checks as
    /// [`new_checked`](Self::new_checked); a remote frame is
    /// [`DecodeError::UnexpectedRemote`].
    #[inline]
    pub fn of_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
        if frame.is_remote() {
            return Err(DecodeError::UnexpectedRemote);
        }
        match usize::from(frame.dlc()) {
            Emergency::LEN => Ok(EmcyFrame {
                bytes: frame.padded_data(),
            }),
            got => Err(DecodeError::Truncated {
                need: Emergency::LEN,
                got,
            }),
        }
    }

    /// Bytes 0..=1, little-endian: the emergency error code.
    #[must_use]
    #[inline]
    pub const fn code(&self) -> u16 {
        let [c0, c1, ..] = self.bytes;
        u16::from_le_bytes([c0, c1])
    }

    /// Byte 2: the error register.
    #[must_use]
    #[inline]
    pub const fn register(&self) -> u8 {
        let [_, _, reg, ..] = self.bytes;
        reg
    }

    /// Bytes 3..=7: the manufacturer-specific error field.
    #[must_use]
    #[inline]
    pub const fn manufacturer(&self) -> [u8; 5] {
        let [_, _, _, m0, m1, m2, m3, m4] = self.bytes;
        [m0, m1, m2, m3, m4]
    }
}

/// One emergency message: code, error register, 5 manufacturer bytes.
///
/// ```
/// use canopen_codec::emcy::{Emergency, ErrorCode, ErrorRegister};
/// use canopen_codec::wire::Codec;
/// // The real charger's "heartbeat lost" EMCY (08A#3081012080000000).
/// let bytes = [0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0];
/// let e = Emergency::parse(&bytes).unwrap();
/// assert_eq!(e.code, ErrorCode::HEARTBEAT);
/// assert_eq!(e.register, ErrorRegister::GENERIC);
/// assert_eq!(e.manufacturer, [0x20, 0x80, 0, 0, 0]);
/// let mut buf = [0; 8];
/// assert_eq!(e.emit(&mut buf), 8);
/// assert_eq!(buf, bytes);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Emergency {
    /// Emergency error code.
    pub code: ErrorCode,
    /// Error register (1001h) at the time of the event.
    pub register: ErrorRegister,
    /// Manufacturer-specific error field (bytes 3-7).
    pub manufacturer: [u8; 5],
}

impl Emergency {
    /// Length of an EMCY frame's data.
    pub const LEN: usize = 8;

    /// The emergency a checked frame carries.
    #[must_use]
    #[inline]
    pub const fn from_view(frame: &EmcyFrame) -> Self {
        Emergency {
            code: ErrorCode(frame.code()),
            register: ErrorRegister::from_bits_retain(frame.register()),
            manufacturer: frame.manufacturer(),
        }
    }

    /// The 8 data bytes.
    #[must_use]
    #[inline]
    pub const fn to_bytes(&self) -> [u8; 8] {
        let [c0, c1] = self.code.0.to_le_bytes();
        let [m0, m1, m2, m3, m4] = self.manufacturer;
        [c0, c1, self.register.bits(), m0, m1, m2, m3, m4]
    }

    /// True for an "error reset / no error" message.
    #[must_use]
    pub const fn is_reset(&self) -> bool {
        self.code.is_reset()
    }

    /// The frame on 80h + `node` (the predefined EMCY identifier, CiA 301
    /// section 7.3.3 "Pre-defined connection set") that carries this
    /// emergency.
    #[must_use]
    #[inline]
    pub fn to_frame(&self, node: NodeId) -> CanFrame {
        self.to_frame_on(CanId::Standard(EMCY_BASE + u16::from(node.raw())))
    }
}

impl Codec for Emergency {
    parse_through_view!(EmcyFrame, of_frame);

    #[inline]
    fn emit(&self, buf: &mut [u8; 8]) -> usize {
        *buf = self.to_bytes();
        Self::LEN
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::assert_round_trip;
    use std::string::ToString;

    #[test]
    fn public_vectors_e1_e2_e3() {
        // [E1] python-canopen producer frames.
        let e = Emergency {
            code: ErrorCode(0x2001),
            register: ErrorRegister::CURRENT,
            manufacturer: [0x2A, 0, 0, 0, 0],
        };
        let mut buf = [0xEE; 8];
        assert_eq!(e.emit(&mut buf), 8);
        assert_eq!(buf, [0x01, 0x20, 0x02, 0x2A, 0, 0, 0, 0]);
        let reset = Emergency::parse(&[0x00, 0x00, 0x03, 0xAA, 0xBB, 0, 0, 0]).unwrap();
        assert!(reset.is_reset());
        assert_eq!(
            reset.register,
            ErrorRegister::GENERIC | ErrorRegister::CURRENT
        );
        // [E2] consumer frames.
        let e = Emergency::parse(&[0x10, 0x90, 0x01, 0x04, 0x03, 0x02, 0x01, 0x00]).unwrap();
        assert_eq!(e.code, ErrorCode(0x9010));
        assert_eq!(e.manufacturer, [4, 3, 2, 1, 0]);
        assert!(Emergency::parse(&[0x99, 0, 1, 0, 0, 0, 0, 0])
            .unwrap()
            .is_reset());
        // [E3] CANopenNode heartbeat consumer EMCY.
        let e = Emergency::parse(&[0x30, 0x81, 0x10, 0x1B, 0x01, 0, 0, 0]).unwrap();
        assert_eq!(e.code, ErrorCode::HEARTBEAT);
        assert_eq!(e.register, ErrorRegister::COMMUNICATION);
    }

    #[test]
    fn wrong_lengths_are_errors() {
        crate::error::assert_exact_length(Emergency::parse, 8);
        crate::error::assert_exact_length(EmcyFrame::new_checked, 8);
    }

    #[test]
    fn register_keeps_unknown_bits() {
        let bytes = [0, 0x10, 0xFF, 1, 2, 3, 4, 5];
        let e = assert_round_trip::<Emergency>(&bytes).unwrap();
        assert_eq!(e.register.bits(), 0xFF);
    }

    #[test]
    fn of_a_frame_agrees_with_parse_of_its_bytes() {
        let bytes = [0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 7];
        for len in 0..=8usize {
            let frame = CanFrame::standard(0x08A, &bytes[..len]).unwrap();
            assert_eq!(
                Emergency::parse_frame(&frame),
                Emergency::parse(&bytes[..len])
            );
        }
        let e = Emergency::parse(&bytes).unwrap();
        assert_eq!(
            e.to_frame(NodeId::new(10).unwrap()).to_string(),
            "08A#3081012080000007"
        );
        let remote = CanFrame::remote(CanId::Standard(0x08A), 8).unwrap();
        assert_eq!(
            Emergency::parse_frame(&remote),
            Err(DecodeError::UnexpectedRemote)
        );
    }
}
