//! Emergency (EMCY) objects, CiA 301.
//!
//! Frame layout (`0x80 + node`, 8 bytes): bytes 0-1 emergency error code
//! ([`ErrorCode`], little-endian), byte 2 the error register (1001h,
//! [`ErrorRegister`]), bytes 3-7 manufacturer-specific. A code whose high
//! byte is zero means "error reset / no error".
//!
//! Object 1003h (pre-defined error field) keeps a history of Unsigned32
//! entries: low word = error code, high word = manufacturer information
//! ([`ErrorFieldEntry`]).
//!
//! The frame is read and written in one place, the EMCY wire layer
//! ([`EmcyFrame`] / [`Emergency`], the crate's [`Codec`](crate::wire::Codec)
//! shape).

mod codes;
mod wire;

pub use codes::{Document, ErrorClass, NamedCode, NAMED_CODES};
pub use wire::{EmcyFrame, Emergency};

use core::fmt;

use byteorder::{ByteOrder, LittleEndian};

use crate::error::{exact_len, DecodeError};

/// A 16-bit emergency error code (EEC). Any value is accepted; see
/// [`ErrorCode::class`] and [`ErrorCode::name`] for its meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct ErrorCode(pub u16);

impl ErrorCode {
    /// 0000h: error reset or no error.
    pub const NO_ERROR: ErrorCode = ErrorCode(0x0000);
    /// 1000h: generic error.
    pub const GENERIC: ErrorCode = ErrorCode(0x1000);
    /// 5000h: CANopen device hardware.
    pub const DEVICE_HARDWARE: ErrorCode = ErrorCode(0x5000);
    /// 5010h: temperature sensor fault (CiA 418).
    pub const TEMPERATURE_SENSOR_FAULT: ErrorCode = ErrorCode(0x5010);
    /// 6000h: CANopen device software.
    pub const DEVICE_SOFTWARE: ErrorCode = ErrorCode(0x6000);
    /// 8130h: life guard error or heartbeat error.
    pub const HEARTBEAT: ErrorCode = ErrorCode(0x8130);
    /// 8210h: PDO not processed due to length error.
    pub const PDO_LENGTH: ErrorCode = ErrorCode(0x8210);
    /// 8220h: PDO length exceeded.
    pub const PDO_LENGTH_EXCEEDED: ErrorCode = ErrorCode(0x8220);
    /// 9000h: external error.
    pub const EXTERNAL: ErrorCode = ErrorCode(0x9000);

    /// The raw value.
    #[must_use]
    pub const fn raw(self) -> u16 {
        self.0
    }

    /// True for "error reset / no error" (high byte zero, as python-canopen
    /// and CiA 301's 00xxh class have it).
    #[must_use]
    pub const fn is_reset(self) -> bool {
        self.0 & 0xFF00 == 0
    }
}

crate::bytes::raw_word!(ErrorCode: u16, ErrorCode, |c: ErrorCode| c.0);

impl fmt::Display for ErrorCode {
    /// `8130h life guard error or heartbeat error`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:04X}h {}", self.0, self.name())
    }
}

bitflags::bitflags! {
    /// Error register, object 1001h (also byte 2 of every EMCY frame).
    /// Unknown bits are kept (`from_bits_retain`), never dropped.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
    pub struct ErrorRegister: u8 {
        /// Bit 0: generic error (set whenever any error is present).
        const GENERIC = 0x01;
        /// Bit 1: current.
        const CURRENT = 0x02;
        /// Bit 2: voltage.
        const VOLTAGE = 0x04;
        /// Bit 3: temperature.
        const TEMPERATURE = 0x08;
        /// Bit 4: communication error (overrun, error state).
        const COMMUNICATION = 0x10;
        /// Bit 5: device-profile specific (CiA 418: temperature sensor fault).
        const DEVICE_PROFILE = 0x20;
        /// Bit 6: reserved (always 0 per CiA 301; kept if set).
        const RESERVED = 0x40;
        /// Bit 7: manufacturer-specific.
        const MANUFACTURER = 0x80;
    }
}

/// One entry of object 1003h (pre-defined error field), an Unsigned32:
/// bits 0-15 the error code, bits 16-31 manufacturer-specific information.
///
/// ```
/// use canopen_codec::emcy::{ErrorCode, ErrorFieldEntry};
/// let e = ErrorFieldEntry::from_u32(0x0180_9000);
/// assert_eq!(e.code, ErrorCode::EXTERNAL);
/// assert_eq!(e.info, 0x0180);
/// assert_eq!(e.to_u32(), 0x0180_9000);
/// // On the wire (SDO, little-endian):
/// assert_eq!(e.to_le_bytes(), [0x00, 0x90, 0x80, 0x01]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ErrorFieldEntry {
    /// Low word: the emergency error code.
    pub code: ErrorCode,
    /// High word: manufacturer-specific additional information.
    pub info: u16,
}

impl ErrorFieldEntry {
    /// Splits the Unsigned32 value.
    #[must_use]
    pub const fn from_u32(raw: u32) -> Self {
        ErrorFieldEntry {
            code: ErrorCode(raw as u16),
            info: (raw >> 16) as u16,
        }
    }

    /// The Unsigned32 value.
    #[must_use]
    pub const fn to_u32(self) -> u32 {
        (self.info as u32) << 16 | self.code.0 as u32
    }

    /// Decodes the 4 little-endian bytes an SDO upload of 1003h sub n carries.
    #[inline]
    pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
        exact_len(data, 4)?;
        Ok(Self::from_u32(LittleEndian::read_u32(data)))
    }

    /// The 4 little-endian bytes of the value.
    #[must_use]
    pub const fn to_le_bytes(self) -> [u8; 4] {
        self.to_u32().to_le_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrong_lengths_are_errors() {
        crate::error::assert_exact_length(ErrorFieldEntry::decode, 4);
    }

    #[test]
    fn error_field_entry_round_trip() {
        let e = ErrorFieldEntry::decode(&[0x30, 0x81, 0x80, 0x20]).unwrap();
        assert_eq!(e.code, ErrorCode::HEARTBEAT);
        assert_eq!(e.info, 0x2080);
        assert_eq!(e.to_u32(), 0x2080_8130);
    }
}
