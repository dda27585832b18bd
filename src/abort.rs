//! SDO abort codes, CiA 301 section 7.2.4.3.17: all 31 codes CiA 301
//! defines, with the meanings the open implementations (python-canopen,
//! CANopenNode, Lely) agree on.
//!
//! A leaf at the base of the crate: the object dictionary ([`crate::od`])
//! refuses an access with one of these codes and the SDO layer
//! ([`crate::sdo`], which re-exports them) carries it on the wire, so both
//! import it from here and neither climbs to the other.

use core::fmt;

/// An SDO abort code. Unlisted values are kept in [`AbortCode::Other`], so
/// conversion from and to `u32` is lossless.
///
/// ```
/// use canopen_codec::sdo::AbortCode;
/// assert_eq!(AbortCode::from(0x0503_0000), AbortCode::ToggleBitNotAlternated);
/// assert_eq!(u32::from(AbortCode::SdoProtocolTimedOut), 0x0504_0000);
/// assert_eq!(AbortCode::from(0x1234_5678), AbortCode::Other(0x1234_5678));
/// assert_eq!(AbortCode::SubIndexDoesNotExist.description(), "Sub-index does not exist");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[non_exhaustive]
pub enum AbortCode {
    /// 05030000h: Toggle bit not alternated.
    ToggleBitNotAlternated,
    /// 05040000h: SDO protocol timed out.
    SdoProtocolTimedOut,
    /// 05040001h: Client/server command specifier not valid or unknown.
    InvalidCommandSpecifier,
    /// 05040002h: Invalid block size (block mode only).
    InvalidBlockSize,
    /// 05040003h: Invalid sequence number (block mode only).
    InvalidSequenceNumber,
    /// 05040004h: CRC error (block mode only).
    CrcError,
    /// 05040005h: Out of memory.
    OutOfMemory,
    /// 06010000h: Unsupported access to an object.
    UnsupportedAccess,
    /// 06010001h: Attempt to read a write only object.
    ReadOfWriteOnlyObject,
    /// 06010002h: Attempt to write a read only object.
    WriteOfReadOnlyObject,
    /// 06020000h: Object does not exist in the object dictionary.
    ObjectDoesNotExist,
    /// 06040041h: Object cannot be mapped to the PDO.
    ObjectCannotBeMapped,
    /// 06040042h: The number and length of the objects to be mapped would exceed the PDO length.
    PdoLengthExceeded,
    /// 06040043h: General parameter incompatibility reason.
    GeneralParameterIncompatibility,
    /// 06040047h: General internal incompatibility in the device.
    GeneralInternalIncompatibility,
    /// 06060000h: Access failed due to a hardware error.
    HardwareError,
    /// 06070010h: Data type does not match, length of service parameter does not match.
    DataTypeLengthMismatch,
    /// 06070012h: Data type does not match, length of service parameter too high.
    DataTypeLengthTooHigh,
    /// 06070013h: Data type does not match, length of service parameter too low.
    DataTypeLengthTooLow,
    /// 06090011h: Sub-index does not exist.
    SubIndexDoesNotExist,
    /// 06090030h: Invalid value for parameter (download only).
    InvalidValue,
    /// 06090031h: Value of parameter written too high (download only).
    ValueTooHigh,
    /// 06090032h: Value of parameter written too low (download only).
    ValueTooLow,
    /// 06090036h: Maximum value is less than minimum value.
    MaxLessThanMin,
    /// 060A0023h: Resource not available: SDO connection.
    ResourceNotAvailable,
    /// 08000000h: General error.
    GeneralError,
    /// 08000020h: Data cannot be transferred or stored to the application.
    DataCannotBeStored,
    /// 08000021h: Data cannot be transferred or stored to the application because of local control.
    DataCannotBeStoredLocalControl,
    /// 08000022h: Data cannot be transferred or stored to the application because of the present device state.
    DataCannotBeStoredDeviceState,
    /// 08000023h: Object dictionary dynamic generation fails or no object dictionary is present.
    ObjectDictionaryGenerationFailed,
    /// 08000024h: No data available.
    NoDataAvailable,
    /// Any code CiA 301 does not list (kept as received).
    Other(u32),
}

/// Every named abort code, in numeric order.
pub const ALL_ABORT_CODES: [AbortCode; 31] = [
    AbortCode::ToggleBitNotAlternated,
    AbortCode::SdoProtocolTimedOut,
    AbortCode::InvalidCommandSpecifier,
    AbortCode::InvalidBlockSize,
    AbortCode::InvalidSequenceNumber,
    AbortCode::CrcError,
    AbortCode::OutOfMemory,
    AbortCode::UnsupportedAccess,
    AbortCode::ReadOfWriteOnlyObject,
    AbortCode::WriteOfReadOnlyObject,
    AbortCode::ObjectDoesNotExist,
    AbortCode::ObjectCannotBeMapped,
    AbortCode::PdoLengthExceeded,
    AbortCode::GeneralParameterIncompatibility,
    AbortCode::GeneralInternalIncompatibility,
    AbortCode::HardwareError,
    AbortCode::DataTypeLengthMismatch,
    AbortCode::DataTypeLengthTooHigh,
    AbortCode::DataTypeLengthTooLow,
    AbortCode::SubIndexDoesNotExist,
    AbortCode::InvalidValue,
    AbortCode::ValueTooHigh,
    AbortCode::ValueTooLow,
    AbortCode::MaxLessThanMin,
    AbortCode::ResourceNotAvailable,
    AbortCode::GeneralError,
    AbortCode::DataCannotBeStored,
    AbortCode::DataCannotBeStoredLocalControl,
    AbortCode::DataCannotBeStoredDeviceState,
    AbortCode::ObjectDictionaryGenerationFailed,
    AbortCode::NoDataAvailable,
];

/// The values of [`ALL_ABORT_CODES`], in the same (ascending) order: the
/// one table both conversions use (`to_u32` by the code's place, `from_u32`
/// by binary search), in flash.
const ABORT_VALUES: [u32; 31] = [
    0x05030000, // ToggleBitNotAlternated
    0x05040000, // SdoProtocolTimedOut
    0x05040001, // InvalidCommandSpecifier
    0x05040002, // InvalidBlockSize
    0x05040003, // InvalidSequenceNumber
    0x05040004, // CrcError
    0x05040005, // OutOfMemory
    0x06010000, // UnsupportedAccess
    0x06010001, // ReadOfWriteOnlyObject
    0x06010002, // WriteOfReadOnlyObject
    0x06020000, // ObjectDoesNotExist
    0x06040041, // ObjectCannotBeMapped
    0x06040042, // PdoLengthExceeded
    0x06040043, // GeneralParameterIncompatibility
    0x06040047, // GeneralInternalIncompatibility
    0x06060000, // HardwareError
    0x06070010, // DataTypeLengthMismatch
    0x06070012, // DataTypeLengthTooHigh
    0x06070013, // DataTypeLengthTooLow
    0x06090011, // SubIndexDoesNotExist
    0x06090030, // InvalidValue
    0x06090031, // ValueTooHigh
    0x06090032, // ValueTooLow
    0x06090036, // MaxLessThanMin
    0x060A0023, // ResourceNotAvailable
    0x08000000, // GeneralError
    0x08000020, // DataCannotBeStored
    0x08000021, // DataCannotBeStoredLocalControl
    0x08000022, // DataCannotBeStoredDeviceState
    0x08000023, // ObjectDictionaryGenerationFailed
    0x08000024, // NoDataAvailable
];

impl AbortCode {
    /// The 32-bit value as sent on the wire (little-endian in bytes 4-7).
    #[must_use]
    pub const fn to_u32(self) -> u32 {
        match self {
            AbortCode::Other(raw) => raw,
            // A load from the table, not a decision tree at every use.
            named => ABORT_VALUES[named.position()],
        }
    }

    /// The place of a named code in [`ALL_ABORT_CODES`] (the variants are
    /// declared in that order, so this compiles to the discriminant);
    /// `Other` gives 0 (not used: `to_u32` reads its value).
    const fn position(self) -> usize {
        match self {
            AbortCode::ToggleBitNotAlternated => 0,
            AbortCode::SdoProtocolTimedOut => 1,
            AbortCode::InvalidCommandSpecifier => 2,
            AbortCode::InvalidBlockSize => 3,
            AbortCode::InvalidSequenceNumber => 4,
            AbortCode::CrcError => 5,
            AbortCode::OutOfMemory => 6,
            AbortCode::UnsupportedAccess => 7,
            AbortCode::ReadOfWriteOnlyObject => 8,
            AbortCode::WriteOfReadOnlyObject => 9,
            AbortCode::ObjectDoesNotExist => 10,
            AbortCode::ObjectCannotBeMapped => 11,
            AbortCode::PdoLengthExceeded => 12,
            AbortCode::GeneralParameterIncompatibility => 13,
            AbortCode::GeneralInternalIncompatibility => 14,
            AbortCode::HardwareError => 15,
            AbortCode::DataTypeLengthMismatch => 16,
            AbortCode::DataTypeLengthTooHigh => 17,
            AbortCode::DataTypeLengthTooLow => 18,
            AbortCode::SubIndexDoesNotExist => 19,
            AbortCode::InvalidValue => 20,
            AbortCode::ValueTooHigh => 21,
            AbortCode::ValueTooLow => 22,
            AbortCode::MaxLessThanMin => 23,
            AbortCode::ResourceNotAvailable => 24,
            AbortCode::GeneralError => 25,
            AbortCode::DataCannotBeStored => 26,
            AbortCode::DataCannotBeStoredLocalControl => 27,
            AbortCode::DataCannotBeStoredDeviceState => 28,
            AbortCode::ObjectDictionaryGenerationFailed => 29,
            AbortCode::NoDataAvailable => 30,
            AbortCode::Other(_) => 0,
        }
    }

    /// From the 32-bit value; unlisted values become [`AbortCode::Other`].
    #[must_use]
    pub const fn from_u32(raw: u32) -> Self {
        // A binary search of the sorted values: a few compares and one
        // table, where a 31-arm match is a decision tree at every use.
        let (mut lo, mut hi) = (0, ABORT_VALUES.len());
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            let value = ABORT_VALUES[mid];
            if value == raw {
                return Self::named(mid);
            }
            if value < raw {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        AbortCode::Other(raw)
    }

    /// The named code at `i` of [`ALL_ABORT_CODES`] (the variants are
    /// declared in that order, so this compiles to the index itself).
    const fn named(i: usize) -> Self {
        match i {
            0 => AbortCode::ToggleBitNotAlternated,
            1 => AbortCode::SdoProtocolTimedOut,
            2 => AbortCode::InvalidCommandSpecifier,
            3 => AbortCode::InvalidBlockSize,
            4 => AbortCode::InvalidSequenceNumber,
            5 => AbortCode::CrcError,
            6 => AbortCode::OutOfMemory,
            7 => AbortCode::UnsupportedAccess,
            8 => AbortCode::ReadOfWriteOnlyObject,
            9 => AbortCode::WriteOfReadOnlyObject,
            10 => AbortCode::ObjectDoesNotExist,
            11 => AbortCode::ObjectCannotBeMapped,
            12 => AbortCode::PdoLengthExceeded,
            13 => AbortCode::GeneralParameterIncompatibility,
            14 => AbortCode::GeneralInternalIncompatibility,
            15 => AbortCode::HardwareError,
            16 => AbortCode::DataTypeLengthMismatch,
            17 => AbortCode::DataTypeLengthTooHigh,
            18 => AbortCode::DataTypeLengthTooLow,
            19 => AbortCode::SubIndexDoesNotExist,
            20 => AbortCode::InvalidValue,
            21 => AbortCode::ValueTooHigh,
            22 => AbortCode::ValueTooLow,
            23 => AbortCode::MaxLessThanMin,
            24 => AbortCode::ResourceNotAvailable,
            25 => AbortCode::GeneralError,
            26 => AbortCode::DataCannotBeStored,
            27 => AbortCode::DataCannotBeStoredLocalControl,
            28 => AbortCode::DataCannotBeStoredDeviceState,
            29 => AbortCode::ObjectDictionaryGenerationFailed,
            30 => AbortCode::NoDataAvailable,
            // Not reached: from_u32 passes an index of ABORT_VALUES.
            _ => AbortCode::Other(0),
        }
    }

    /// CiA 301's description of the code.
    #[must_use]
    pub const fn description(self) -> &'static str {
        match self {
            AbortCode::ToggleBitNotAlternated => "Toggle bit not alternated",
            AbortCode::SdoProtocolTimedOut => "SDO protocol timed out",
            AbortCode::InvalidCommandSpecifier => "Client/server command specifier not valid or unknown",
            AbortCode::InvalidBlockSize => "Invalid block size (block mode only)",
            AbortCode::InvalidSequenceNumber => "Invalid sequence number (block mode only)",
            AbortCode::CrcError => "CRC error (block mode only)",
            AbortCode::OutOfMemory => "Out of memory",
            AbortCode::UnsupportedAccess => "Unsupported access to an object",
            AbortCode::ReadOfWriteOnlyObject => "Attempt to read a write only object",
            AbortCode::WriteOfReadOnlyObject => "Attempt to write a read only object",
            AbortCode::ObjectDoesNotExist => "Object does not exist in the object dictionary",
            AbortCode::ObjectCannotBeMapped => "Object cannot be mapped to the PDO",
            AbortCode::PdoLengthExceeded => "The number and length of the objects to be mapped would exceed the PDO length",
            AbortCode::GeneralParameterIncompatibility => "General parameter incompatibility reason",
            AbortCode::GeneralInternalIncompatibility => "General internal incompatibility in the device",
            AbortCode::HardwareError => "Access failed due to a hardware error",
            AbortCode::DataTypeLengthMismatch => "Data type does not match, length of service parameter does not match",
            AbortCode::DataTypeLengthTooHigh => "Data type does not match, length of service parameter too high",
            AbortCode::DataTypeLengthTooLow => "Data type does not match, length of service parameter too low",
            AbortCode::SubIndexDoesNotExist => "Sub-index does not exist",
            AbortCode::InvalidValue => "Invalid value for parameter (download only)",
            AbortCode::ValueTooHigh => "Value of parameter written too high (download only)",
            AbortCode::ValueTooLow => "Value of parameter written too low (download only)",
            AbortCode::MaxLessThanMin => "Maximum value is less than minimum value",
            AbortCode::ResourceNotAvailable => "Resource not available: SDO connection",
            AbortCode::GeneralError => "General error",
            AbortCode::DataCannotBeStored => "Data cannot be transferred or stored to the application",
            AbortCode::DataCannotBeStoredLocalControl => "Data cannot be transferred or stored to the application because of local control",
            AbortCode::DataCannotBeStoredDeviceState => "Data cannot be transferred or stored to the application because of the present device state",
            AbortCode::ObjectDictionaryGenerationFailed => "Object dictionary dynamic generation fails or no object dictionary is present",
            AbortCode::NoDataAvailable => "No data available",
            AbortCode::Other(_) => "Unknown abort code",
        }
    }
}

crate::bytes::raw_word!(AbortCode: u32, AbortCode::from_u32, AbortCode::to_u32);

impl fmt::Display for AbortCode {
    /// `05040000h SDO protocol timed out`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:08X}h {}", self.to_u32(), self.description())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every row of sdo_abort_codes.tsv: value, variant, description.
    #[test]
    fn every_row() {
        let rows: [(u32, AbortCode, &str); 31] = [
            (0x05030000, AbortCode::ToggleBitNotAlternated, "Toggle bit not alternated"),
            (0x05040000, AbortCode::SdoProtocolTimedOut, "SDO protocol timed out"),
            (0x05040001, AbortCode::InvalidCommandSpecifier, "Client/server command specifier not valid or unknown"),
            (0x05040002, AbortCode::InvalidBlockSize, "Invalid block size (block mode only)"),
            (0x05040003, AbortCode::InvalidSequenceNumber, "Invalid sequence number (block mode only)"),
            (0x05040004, AbortCode::CrcError, "CRC error (block mode only)"),
            (0x05040005, AbortCode::OutOfMemory, "Out of memory"),
            (0x06010000, AbortCode::UnsupportedAccess, "Unsupported access to an object"),
            (0x06010001, AbortCode::ReadOfWriteOnlyObject, "Attempt to read a write only object"),
            (0x06010002, AbortCode::WriteOfReadOnlyObject, "Attempt to write a read only object"),
            (0x06020000, AbortCode::ObjectDoesNotExist, "Object does not exist in the object dictionary"),
            (0x06040041, AbortCode::ObjectCannotBeMapped, "Object cannot be mapped to the PDO"),
            (0x06040042, AbortCode::PdoLengthExceeded, "The number and length of the objects to be mapped would exceed the PDO length"),
            (0x06040043, AbortCode::GeneralParameterIncompatibility, "General parameter incompatibility reason"),
            (0x06040047, AbortCode::GeneralInternalIncompatibility, "General internal incompatibility in the device"),
            (0x06060000, AbortCode::HardwareError, "Access failed due to a hardware error"),
            (0x06070010, AbortCode::DataTypeLengthMismatch, "Data type does not match, length of service parameter does not match"),
            (0x06070012, AbortCode::DataTypeLengthTooHigh, "Data type does not match, length of service parameter too high"),
            (0x06070013, AbortCode::DataTypeLengthTooLow, "Data type does not match, length of service parameter too low"),
            (0x06090011, AbortCode::SubIndexDoesNotExist, "Sub-index does not exist"),
            (0x06090030, AbortCode::InvalidValue, "Invalid value for parameter (download only)"),
            (0x06090031, AbortCode::ValueTooHigh, "Value of parameter written too high (download only)"),
            (0x06090032, AbortCode::ValueTooLow, "Value of parameter written too low (download only)"),
            (0x06090036, AbortCode::MaxLessThanMin, "Maximum value is less than minimum value"),
            (0x060A0023, AbortCode::ResourceNotAvailable, "Resource not available: SDO connection"),
            (0x08000000, AbortCode::GeneralError, "General error"),
            (0x08000020, AbortCode::DataCannotBeStored, "Data cannot be transferred or stored to the application"),
            (0x08000021, AbortCode::DataCannotBeStoredLocalControl, "Data cannot be transferred or stored to the application because of local control"),
            (0x08000022, AbortCode::DataCannotBeStoredDeviceState, "Data cannot be transferred or stored to the application because of the present device state"),
            (0x08000023, AbortCode::ObjectDictionaryGenerationFailed, "Object dictionary dynamic generation fails or no object dictionary is present"),
            (0x08000024, AbortCode::NoDataAvailable, "No data available"),
        ];
        for (raw, code, text) in rows {
            assert_eq!(AbortCode::from(raw), code);
            assert_eq!(u32::from(code), raw);
            assert_eq!(code.description(), text);
        }
        for (i, c) in ALL_ABORT_CODES.iter().enumerate() {
            assert_eq!(*c, rows[i].1);
        }
    }

    #[test]
    fn values_ascend_and_neighbours_are_other() {
        // The binary search in from_u32 relies on the order.
        assert!(ABORT_VALUES.windows(2).all(|w| w[0] < w[1]));
        for (i, code) in ALL_ABORT_CODES.iter().enumerate() {
            assert_eq!(AbortCode::named(i), *code);
            assert_eq!(code.position(), i);
        }
        for raw in ABORT_VALUES {
            for n in [raw.wrapping_sub(1), raw.wrapping_add(1)] {
                let listed = ABORT_VALUES.contains(&n);
                assert_eq!(
                    AbortCode::from(n) == AbortCode::Other(n),
                    !listed,
                    "{n:08X}"
                );
                assert_eq!(AbortCode::from(n).to_u32(), n);
            }
        }
    }

    #[test]
    fn other_is_lossless() {
        for raw in [0u32, 1, 0x0503_0001, 0xFFFF_FFFF] {
            assert_eq!(AbortCode::from(raw), AbortCode::Other(raw));
            assert_eq!(AbortCode::from(raw).to_u32(), raw);
        }
    }
}
