//! Values of the Delta-Q manufacturer objects (Delta-Q's published object
//! list) and of
//! 6052h as the charger scales it; scaling and "no value" rules are in the
//! parent module's docs.

use core::fmt;

use crate::emcy::ErrorCode;
use crate::error::{exact_len, DecodeError};

use super::codes::{AlarmFaultEntry, DeltaQCode};

/// Reads exactly `N` little-endian bytes.
fn le_bytes<const N: usize>(data: &[u8]) -> Result<[u8; N], DecodeError> {
    exact_len(data, N)?;
    let mut out = [0u8; N];
    for (o, b) in out.iter_mut().zip(data) {
        *o = *b;
    }
    Ok(out)
}

/// Rounds `raw / 2^q` milli-units to the nearest integer, halves up.
const fn to_milli(raw: u64, q: u32) -> u64 {
    (raw * 1000 + (1 << q >> 1)) >> q
}

/// Rounds `milli * 2^q / 1000` to the nearest integer, halves up.
const fn from_milli(milli: u64, q: u32) -> u64 {
    ((milli << q) + 500) / 1000
}

/// The Delta-Q fixed-point objects: `scaled! { /// docs
/// Name(raw type, bytes), q: fractional bits, volts | amps | amp_hours; ... }`,
/// each with its unit's and milli-unit's accessors.
macro_rules! scaled {
    ($($(#[$doc:meta])* $name:ident($raw:ty, $bytes:literal), q: $q:literal, $unit:ident;)+) => {
        $(scaled! { @unit $unit, $(#[$doc])* $name($raw, $bytes), q: $q })+
    };
    (@unit volts, $(#[$doc:meta])* $name:ident($raw:ty, $bytes:literal), q: $q:literal) => {
        scaled! { @object $(#[$doc])* $name($raw, $bytes), q: $q, unit: "V",
        milli: millivolts, from_milli: from_millivolts, milli_unit: "mV" }
    };
    (@unit amps, $(#[$doc:meta])* $name:ident($raw:ty, $bytes:literal), q: $q:literal) => {
        scaled! { @object $(#[$doc])* $name($raw, $bytes), q: $q, unit: "A",
        milli: milliamps, from_milli: from_milliamps, milli_unit: "mA" }
    };
    (@unit amp_hours, $(#[$doc:meta])* $name:ident($raw:ty, $bytes:literal), q: $q:literal) => {
        scaled! { @object $(#[$doc])* $name($raw, $bytes), q: $q, unit: "Ah",
        milli: milliamp_hours, from_milli: from_milliamp_hours, milli_unit: "mAh" }
    };
    (
        @object $(#[$doc:meta])*
        $name:ident($raw:ty, $bytes:literal), q: $q:literal, unit: $unit:literal,
        milli: $milli:ident, from_milli: $from_milli:ident, milli_unit: $milli_unit:literal
    ) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name($raw);

        impl $name {
            /// The raw "no value" sentinel.
            pub const NO_VALUE: $raw = <$raw>::MAX;
            /// Zero.
            pub const ZERO: $name = $name(0);
            /// The largest value (one step below the sentinel).
            pub const MAX: $name = $name(<$raw>::MAX - 1);
            /// Fractional bits: the value is `raw / 2^FRAC_BITS`
            #[doc = concat!(" ", $unit, ".")]
            pub const FRAC_BITS: u32 = $q;

            /// `None` for the "no value" sentinel, else the value.
            #[must_use]
            pub const fn from_raw(raw: $raw) -> Option<Self> {
                if raw == Self::NO_VALUE {
                    None
                } else {
                    Some($name(raw))
                }
            }

            /// The raw integer (never the sentinel).
            #[must_use]
            pub const fn raw(self) -> $raw {
                self.0
            }

            /// The raw integer of an optional value: the sentinel for `None`.
            #[must_use]
            pub const fn encode_raw(value: Option<Self>) -> $raw {
                match value {
                    Some(v) => v.0,
                    None => Self::NO_VALUE,
                }
            }

            /// Decodes the object's little-endian bytes (exact length).
            pub fn decode(data: &[u8]) -> Result<Option<Self>, DecodeError> {
                Ok(Self::from_raw(<$raw>::from_le_bytes(le_bytes(data)?)))
            }

            /// The object's little-endian bytes for an optional value.
            #[must_use]
            pub const fn encode(value: Option<Self>) -> [u8; $bytes] {
                Self::encode_raw(value).to_le_bytes()
            }

            #[doc = concat!("The value in ", $unit, " as `f32`",
                " (exact for 16-bit values; 32-bit values above 2^24 round).")]
            #[must_use]
            pub fn as_f32(self) -> f32 {
                self.0 as f32 / (1u32 << $q) as f32
            }

            #[doc = concat!("The value in ", $unit, " as `f64` (exact).")]
            #[must_use]
            pub fn as_f64(self) -> f64 {
                f64::from(self.0) / f64::from(1u32 << $q)
            }

            #[doc = concat!("The value in ", $milli_unit,
                ", rounded to the nearest (halves up).")]
            #[must_use]
            pub const fn $milli(self) -> u32 {
                to_milli(self.0 as u64, $q) as u32
            }

            #[doc = concat!("The value nearest to `milli` ", $milli_unit,
                " (halves up); `None` if it would not fit below the sentinel.")]
            #[must_use]
            pub const fn $from_milli(milli: u32) -> Option<Self> {
                let raw = from_milli(milli as u64, $q);
                if raw < Self::NO_VALUE as u64 {
                    Some($name(raw as $raw))
                } else {
                    None
                }
            }
        }

        impl fmt::Display for $name {
            #[doc = concat!("The value in ", $unit, ", e.g. `19.453125 ", $unit, "`.")]
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{} {}", self.as_f64(), $unit)
            }
        }
    };
}

scaled! {
    /// 2002h charging current: U16, Q8 A (1/256 A), 0..255.99 A. The BMS may
    /// write its own measured current here.
    ChargingCurrent(u16, 2), q: 8, amps;

    /// 2100h battery voltage (legacy): U16, **Q10 V** (1/1024 V), 0..64 V.
    ///
    /// Erratum ("Delta-Q IC Series CANopen interface specification rev
    /// 2.0", section 4.6.1, Table 2): the document's PDO table calls 2100h
    /// "Battery Voltage Q8 UINT16", but its revision 1.6 note says 2100h "was
    /// limited in range to 0 - 64V" and added 2101h ([`BatteryVoltage`], Q8)
    /// to replace it in the PDO; 0..64 V in 16 bits is Q10, as Delta-Q's
    /// object list says. On a 48 V charger the range may be exceeded (read
    /// 2101h or 6060h instead); a saturated reading of 0xFFFF is
    /// indistinguishable from "no value" and decodes as `None`.
    BatteryVoltageLegacy(u16, 2), q: 10, volts;

    /// 2101h battery voltage: U16, Q8 V (1/256 V), 0..255.99 V.
    BatteryVoltage(u16, 2), q: 8, volts;

    /// 2200h AC voltage: U16, Q4 V rms (1/16 V).
    AcVoltage(u16, 2), q: 4, volts;

    /// 2271h voltage request: U32, Q10 V (1/1024 V). Writable only while the
    /// BMS heartbeat is present; a limit in local mode, the set-point in
    /// remote mode.
    VoltageRequest(u32, 4), q: 10, volts;

    /// 2276h voltage request (16 bit): U16, Q8 V (1/256 V); same semantics as
    /// 2271h ([`VoltageRequest`]).
    VoltageRequest16(u16, 2), q: 8, volts;

    /// 6052h Ah returned during the last charge, as the Delta-Q charger has
    /// it: U16, Q3 Ah (0.125 Ah, as CiA 418), default 0xFFFF = no value.
    /// The milli-unit accessors are exact (1 step = 125 mAh).
    ChargerAhReturned(u16, 2), q: 3, amp_hours;
}

/// Extended charge status 2006h, bits 15-12: charge type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ChargeType {
    /// 0: none.
    None,
    /// 1: normal charge.
    Normal,
    /// 2: maintenance charge.
    Maintenance,
    /// Any other 4-bit value (3..=15), kept.
    Other(u8),
}

impl ChargeType {
    /// From the 4-bit field (higher bits ignored).
    #[must_use]
    pub const fn from_bits(v: u8) -> Self {
        match v & 0x0F {
            0 => ChargeType::None,
            1 => ChargeType::Normal,
            2 => ChargeType::Maintenance,
            v => ChargeType::Other(v),
        }
    }

    /// The 4-bit field (an `Other` above 15 is masked to 4 bits).
    #[must_use]
    pub const fn bits(self) -> u8 {
        match self {
            ChargeType::None => 0,
            ChargeType::Normal => 1,
            ChargeType::Maintenance => 2,
            ChargeType::Other(v) => v & 0x0F,
        }
    }
}

/// Extended charge status 2006h, bits 11-8: charge indication.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ChargeIndication {
    /// 0: inactive.
    Inactive,
    /// 1: below 80 % charged.
    Below80,
    /// 2: above 80 % charged.
    Above80,
    /// 3: finishing.
    Finishing,
    /// 4: complete.
    Complete,
    /// 5: resting.
    Resting,
    /// 6: equalize.
    Equalize,
    /// 7: power-supply mode.
    PowerSupplyMode,
    /// Any other 4-bit value (8..=15), kept.
    Other(u8),
}

impl ChargeIndication {
    /// From the 4-bit field (higher bits ignored).
    #[must_use]
    pub const fn from_bits(v: u8) -> Self {
        match v & 0x0F {
            0 => ChargeIndication::Inactive,
            1 => ChargeIndication::Below80,
            2 => ChargeIndication::Above80,
            3 => ChargeIndication::Finishing,
            4 => ChargeIndication::Complete,
            5 => ChargeIndication::Resting,
            6 => ChargeIndication::Equalize,
            7 => ChargeIndication::PowerSupplyMode,
            v => ChargeIndication::Other(v),
        }
    }

    /// The 4-bit field (an `Other` above 15 is masked to 4 bits).
    #[must_use]
    pub const fn bits(self) -> u8 {
        match self {
            ChargeIndication::Inactive => 0,
            ChargeIndication::Below80 => 1,
            ChargeIndication::Above80 => 2,
            ChargeIndication::Finishing => 3,
            ChargeIndication::Complete => 4,
            ChargeIndication::Resting => 5,
            ChargeIndication::Equalize => 6,
            ChargeIndication::PowerSupplyMode => 7,
            ChargeIndication::Other(v) => v & 0x0F,
        }
    }
}

/// Extended charge status 2006h, bits 7-6: who controls the charge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OverrideSource {
    /// 0: the charger's own (internal) control.
    Internal,
    /// 1: overridden externally (by the BMS).
    External,
    /// 2 or 3, kept.
    Other(u8),
}

impl OverrideSource {
    /// From the 2-bit field (higher bits ignored).
    #[must_use]
    pub const fn from_bits(v: u8) -> Self {
        match v & 0x03 {
            0 => OverrideSource::Internal,
            1 => OverrideSource::External,
            v => OverrideSource::Other(v),
        }
    }

    /// The 2-bit field (an `Other` above 3 is masked to 2 bits).
    #[must_use]
    pub const fn bits(self) -> u8 {
        match self {
            OverrideSource::Internal => 0,
            OverrideSource::External => 1,
            OverrideSource::Other(v) => v & 0x03,
        }
    }
}

bitflags::bitflags! {
    /// Extended charge status 2006h, bits 5-0. All six bits are named; bits
    /// 1-0 are reserved (zero) on older firmware.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
    pub struct ChargeStatusFlags: u8 {
        /// Bit 5: charger enabled, able to charge (= 6001h bit 0).
        const CHARGER_ENABLED = 1 << 5;
        /// Bit 4: AC present.
        const AC_PRESENT = 1 << 4;
        /// Bit 3: de-rating active.
        const DERATING = 1 << 3;
        /// Bit 2: hardware shutdown.
        const HW_SHUTDOWN = 1 << 2;
        /// Bit 1: an alarm is active.
        const ALARM_ACTIVE = 1 << 1;
        /// Bit 0: a fault is active.
        const FAULT_ACTIVE = 1 << 0;
    }
}

/// Extended charge status, object 2006h (U16), split into its fields. Every
/// `u16` decodes, and [`to_u16`](Self::to_u16) gives it back exactly
/// (unknown field values are kept in the `Other` variants). 0xFFFF is not a
/// sentinel here: it decodes like any other value.
///
/// ```
/// use canopen_codec::deltaq::{
///     ChargeIndication, ChargeType, ExtendedChargeStatus, OverrideSource, ChargeStatusFlags,
/// };
/// // The capture's worked example: 0x0070.
/// let s = ExtendedChargeStatus::from_u16(0x0070);
/// assert_eq!(s.charge_type, ChargeType::None);
/// assert_eq!(s.indication, ChargeIndication::Inactive);
/// assert_eq!(s.override_source, OverrideSource::External);
/// assert_eq!(s.flags, ChargeStatusFlags::CHARGER_ENABLED | ChargeStatusFlags::AC_PRESENT);
/// assert_eq!(s.to_u16(), 0x0070);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ExtendedChargeStatus {
    /// Bits 15-12.
    pub charge_type: ChargeType,
    /// Bits 11-8.
    pub indication: ChargeIndication,
    /// Bits 7-6.
    pub override_source: OverrideSource,
    /// Bits 5-0 (bits 6-7 of the flags byte are masked off on encode).
    pub flags: ChargeStatusFlags,
}

impl ExtendedChargeStatus {
    /// Splits the U16.
    #[must_use]
    pub const fn from_u16(raw: u16) -> Self {
        ExtendedChargeStatus {
            charge_type: ChargeType::from_bits((raw >> 12) as u8),
            indication: ChargeIndication::from_bits((raw >> 8) as u8),
            override_source: OverrideSource::from_bits((raw >> 6) as u8),
            flags: ChargeStatusFlags::from_bits_retain(raw as u8 & 0x3F),
        }
    }

    /// The U16.
    #[must_use]
    pub const fn to_u16(self) -> u16 {
        (self.charge_type.bits() as u16) << 12
            | (self.indication.bits() as u16) << 8
            | (self.override_source.bits() as u16) << 6
            | (self.flags.bits() & 0x3F) as u16
    }

    /// Decodes the 2 little-endian bytes.
    pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
        Ok(Self::from_u16(u16::from_le_bytes(le_bytes(data)?)))
    }

    /// The 2 little-endian bytes.
    #[must_use]
    pub const fn encode(self) -> [u8; 2] {
        self.to_u16().to_le_bytes()
    }
}

crate::bytes::raw_word!(ExtendedChargeStatus: u16, ExtendedChargeStatus::from_u16, ExtendedChargeStatus::to_u16);

bitflags::bitflags! {
    /// Derate reasons, object 2008h (U8). Unknown bits are kept
    /// (`from_bits_retain`).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
    pub struct DerateReasons: u8 {
        /// Bit 0: AC voltage.
        const AC_VOLTAGE = 1 << 0;
        /// Bit 1: battery voltage.
        const BATTERY_VOLTAGE = 1 << 1;
        /// Bit 2: temperature.
        const TEMPERATURE = 1 << 2;
        /// Bit 3: AC current limit.
        const AC_CURRENT_LIMIT = 1 << 3;
    }
}

bitflags::bitflags! {
    /// External override, object 4201h (U8), written by the BMS. Unknown bits
    /// are kept (`from_bits_retain`).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
    pub struct ExternalOverride: u8 {
        /// Bit 0: equalize.
        const EQUALIZE = 1 << 0;
        /// Bit 1: maintenance.
        const MAINTENANCE = 1 << 1;
    }
}

/// Current displayed error or fault, object 2060h (U32): the same layout as
/// a 1003h entry (low word EEC, high word the Delta-Q code byte-swapped; see
/// [`DeltaQCode::from_error_field`]). 0 means nothing is displayed.
///
/// ```
/// use canopen_codec::deltaq::{DeltaQCode, DisplayedError};
/// use canopen_codec::emcy::ErrorCode;
/// let e = DisplayedError::from_u32(0x2080_8130);
/// assert_eq!((e.eec, e.code), (ErrorCode::HEARTBEAT, DeltaQCode::Alarm(32)));
/// assert_eq!(e.to_u32(), 0x2080_8130);
/// assert!(DisplayedError::from_u32(0).is_none());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct DisplayedError {
    /// The CiA 301 emergency error code (low word).
    pub eec: ErrorCode,
    /// The Delta-Q code (high word, bytes swapped).
    pub code: DeltaQCode,
}

impl DisplayedError {
    /// Nothing displayed (value 0).
    pub const NONE: DisplayedError = DisplayedError {
        eec: ErrorCode::NO_ERROR,
        code: DeltaQCode::NONE,
    };

    /// Splits the U32 (total; lossless).
    #[must_use]
    pub const fn from_u32(raw: u32) -> Self {
        let (eec, code) = DeltaQCode::from_error_field(raw);
        DisplayedError { eec, code }
    }

    /// The U32.
    #[must_use]
    pub const fn to_u32(self) -> u32 {
        self.code.to_error_field(self.eec)
    }

    /// True when nothing is displayed (the value is 0).
    #[must_use]
    pub const fn is_none(self) -> bool {
        self.to_u32() == 0
    }

    /// The alarm / fault table row of the code, if listed.
    #[must_use]
    pub fn entry(self) -> Option<&'static AlarmFaultEntry> {
        self.code.entry()
    }

    /// Decodes the 4 little-endian bytes.
    pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
        Ok(Self::from_u32(u32::from_le_bytes(le_bytes(data)?)))
    }

    /// The 4 little-endian bytes.
    #[must_use]
    pub const fn encode(self) -> [u8; 4] {
        self.to_u32().to_le_bytes()
    }
}

/// Active algorithm request, object 2241h (U32). 0xFFFF_FFFF means "no
/// request" and decodes to `None`.
///
/// ```
/// use canopen_codec::deltaq::AlgorithmRequest;
/// let r = AlgorithmRequest::from_u32(0x8000_000B).unwrap();
/// assert_eq!(r.algorithm, 11);
/// assert!(r.store_permanently);
/// assert!(!r.revert_after_ac_loss);
/// assert_eq!(r, AlgorithmRequest::new(11).permanent());
/// assert_eq!(r.to_u32(), 0x8000_000B);
/// assert_eq!(AlgorithmRequest::from_u32(0xFFFF_FFFF), None);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct AlgorithmRequest {
    /// Bits 0-15: algorithm id.
    pub algorithm: u16,
    /// Bits 16-23: algorithm variant.
    pub variant: u8,
    /// Bits 24-29: reserved, kept as read (6 bits; masked on encode).
    pub reserved: u8,
    /// Bit 30: revert to the permanent algorithm after AC loss.
    pub revert_after_ac_loss: bool,
    /// Bit 31: store the algorithm permanently.
    pub store_permanently: bool,
}

impl AlgorithmRequest {
    /// The raw "no request" sentinel.
    pub const NO_VALUE: u32 = 0xFFFF_FFFF;

    /// A request for `algorithm`, variant 0, no flags.
    #[must_use]
    pub const fn new(algorithm: u16) -> Self {
        AlgorithmRequest {
            algorithm,
            variant: 0,
            reserved: 0,
            revert_after_ac_loss: false,
            store_permanently: false,
        }
    }

    /// The same request with bit 31 (store permanently) set.
    #[must_use]
    pub const fn permanent(mut self) -> Self {
        self.store_permanently = true;
        self
    }

    /// `None` for 0xFFFF_FFFF, else the fields.
    #[must_use]
    pub const fn from_u32(raw: u32) -> Option<Self> {
        if raw == Self::NO_VALUE {
            return None;
        }
        Some(AlgorithmRequest {
            algorithm: raw as u16,
            variant: (raw >> 16) as u8,
            reserved: (raw >> 24) as u8 & 0x3F,
            revert_after_ac_loss: raw & 1 << 30 != 0,
            store_permanently: raw & 1 << 31 != 0,
        })
    }

    /// The U32. (A request with every field at its maximum is the sentinel
    /// 0xFFFF_FFFF and reads back as `None`.)
    #[must_use]
    pub const fn to_u32(self) -> u32 {
        (self.store_permanently as u32) << 31
            | (self.revert_after_ac_loss as u32) << 30
            | ((self.reserved & 0x3F) as u32) << 24
            | (self.variant as u32) << 16
            | self.algorithm as u32
    }

    /// The U32 of an optional request: 0xFFFF_FFFF for `None`.
    #[must_use]
    pub const fn encode_raw(value: Option<Self>) -> u32 {
        match value {
            Some(r) => r.to_u32(),
            None => Self::NO_VALUE,
        }
    }

    /// Decodes the 4 little-endian bytes.
    pub fn decode(data: &[u8]) -> Result<Option<Self>, DecodeError> {
        Ok(Self::from_u32(u32::from_le_bytes(le_bytes(data)?)))
    }

    /// The 4 little-endian bytes of an optional request.
    #[must_use]
    pub const fn encode(value: Option<Self>) -> [u8; 4] {
        Self::encode_raw(value).to_le_bytes()
    }
}

#[cfg(test)]
#[path = "objects_tests.rs"]
mod tests;
