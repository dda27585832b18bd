//! Scaled quantities of CiA 418 (v1.0.1, 7.3.3-7.3.17): each is a newtype over
//! the raw object value, with exact integer conversions to a sub-unit that
//! divides the resolution (0.125 degC = 125 millidegrees, 0.125 Ah = 125 mAh,
//! 1/16 A = 62 500 uA, 1/1024 V = 976 562 500 pV) and a float view for
//! display.

use crate::error::DecodeError;

use super::exact;

/// `value` in steps of `step` when it is a whole number of them and at
/// most `max` steps: the exact conversions from a fine unit to an object's
/// raw value.
const fn whole_steps(value: u64, step: u64, max: u64) -> Option<u64> {
    if step == 0 || !value.is_multiple_of(step) || value / step > max {
        None
    } else {
        Some(value / step)
    }
}

/// The raw side of a CiA 418 quantity `$name($raw)`, an object of
/// `$bytes` little-endian bytes: `from_raw` (any raw value, kept as is),
/// `raw`, `decode` (exactly `$bytes` bytes, else a [`DecodeError`]) and
/// `encode`; `$per_bit` says what one raw step is. Optionally the
/// checked ways in: `whole: fn` from whole units (`$steps` raw steps per
/// unit, `None` when the raw value would overflow), after a comma
/// optionally `float: fn`, the way out to those units as a float (raw
/// over `$steps`), then `fine: fn` from a sub-unit that divides the
/// resolution (`$per_step` of it per raw step, declared as
/// `Self::$per_name`; `None` unless a whole number of steps, at most
/// `$max`), and optionally `exact: fn`, the way out to that sub-unit (raw
/// times `$per_step`): each scale is declared once for both directions.
macro_rules! object_value {
    (
        $name:ident($raw:ty; $bytes:literal), $per_bit:literal;
        $(
            $(#[$wdoc:meta])* whole: fn $whole:ident($w:ident) * $steps:literal
            $(, $(#[$float_doc:meta])* float: fn $float:ident -> $float_ty:ty)?;
            $(
                $(#[$fdoc:meta])*
                fine: fn $fine:ident($f:ident: $fty:ty) / $per_name:ident = $per_step:literal, max $max:expr;
                $($(#[$edoc:meta])* exact: fn $exact:ident;)?
            )?
        )?
    ) => {
        impl $name {
            /// Wraps a raw object value (any value, kept as is).
            #[must_use]
            pub const fn from_raw(raw: $raw) -> Self {
                $name(raw)
            }

            #[doc = concat!("The raw object value (", $per_bit, " per bit).")]
            #[must_use]
            pub const fn raw(self) -> $raw {
                self.0
            }

            #[doc = concat!("Decodes the ", $bytes, " little-endian byte(s) of the object.")]
            pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
                exact(data).map(<$raw>::from_le_bytes).map($name)
            }

            #[doc = concat!("The ", $bytes, " little-endian byte(s) of the object.")]
            #[must_use]
            pub const fn encode(self) -> [u8; $bytes] {
                self.0.to_le_bytes()
            }

            $(
                $(#[$wdoc])*
                #[must_use]
                pub const fn $whole($w: $raw) -> Option<Self> {
                    match $w.checked_mul($steps) {
                        Some(raw) => Some($name(raw)),
                        None => None,
                    }
                }

                $(
                    $(#[$float_doc])*
                    #[must_use]
                    pub fn $float(self) -> $float_ty {
                        let steps: $raw = $steps;
                        <$float_ty>::from(self.0) / <$float_ty>::from(steps)
                    }
                )?

                $(
                    #[doc = concat!("The sub-unit of [`", stringify!($fine), "`](Self::", stringify!($fine), ") per bit (one bit is ", $per_bit, ").")]
                    pub const $per_name: $fty = $per_step;

                    $(#[$fdoc])*
                    #[must_use]
                    #[allow(clippy::cast_possible_truncation)]
                    pub const fn $fine($f: $fty) -> Option<Self> {
                        // At most `$max` steps, which fits `$raw`.
                        match whole_steps($f as u64, Self::$per_name as u64, $max as u64) {
                            Some(raw) => Some($name(raw as $raw)),
                            None => None,
                        }
                    }

                    $(
                        $(#[$edoc])*
                        #[must_use]
                        pub const fn $exact(self) -> $fty {
                            self.0 as $fty * Self::$per_name
                        }
                    )?
                )?
            )?
        }
    };
}

/// 6010h temperature, Integer16, 0.125 degC per bit (CiA 418 section 7.3.3).
///
/// ```
/// use canopen_codec::cia418::Temperature;
/// let t = Temperature::decode(&[0xC8, 0x00]).unwrap(); // 200 * 0.125
/// assert_eq!(t.millidegrees_c(), 25_000);
/// assert_eq!(t.as_celsius_f32(), 25.0);
/// assert_eq!(Temperature::from_millidegrees_c(-40_000), Some(Temperature::from_raw(-320)));
/// assert_eq!(Temperature::from_millidegrees_c(10), None); // not a multiple of 125
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Temperature(i16);

object_value! {
    Temperature(i16; 2), "0.125 degC";
    /// Whole degrees Celsius; `None` outside the `i16` range (beyond
    /// -4096..=4095 degC).
    whole: fn from_celsius(deg) * 8,
        /// Degrees Celsius as `f32` (exact: every raw value is representable).
        float: fn as_celsius_f32 -> f32;
}

impl Temperature {
    /// Millidegrees Celsius per bit.
    pub const MILLIDEGREES_PER_BIT: i32 = 125;
    /// Lower end of the range every module must cover: -320 (-40.0 degC).
    pub const SPECIFIED_MIN: Temperature = Temperature(-320);
    /// Upper end of the range every module must cover: 680 (85.0 degC).
    pub const SPECIFIED_MAX: Temperature = Temperature(680);

    /// Exact value in millidegrees Celsius (raw * 125).
    #[must_use]
    pub const fn millidegrees_c(self) -> i32 {
        self.0 as i32 * Self::MILLIDEGREES_PER_BIT
    }

    /// `Some` if `mdeg` is a multiple of 125 that fits the `i16` range.
    #[must_use]
    pub const fn from_millidegrees_c(mdeg: i32) -> Option<Self> {
        if mdeg % Self::MILLIDEGREES_PER_BIT != 0 {
            return None;
        }
        let raw = mdeg / Self::MILLIDEGREES_PER_BIT;
        if raw < i16::MIN as i32 || raw > i16::MAX as i32 {
            None
        } else {
            Some(Temperature(raw as i16))
        }
    }

    /// True inside the range CiA 418 requires a module to cover
    /// (-40.0..=85.0 degC).
    #[must_use]
    pub const fn in_specified_range(self) -> bool {
        self.0 >= Self::SPECIFIED_MIN.0 && self.0 <= Self::SPECIFIED_MAX.0
    }
}

/// 6050h cumulative total Ah charge, Unsigned32, 1 Ah per bit (CiA 418
/// section 7.3.9).
///
/// ```
/// use canopen_codec::cia418::AmpHours;
/// let ah = AmpHours::decode(&[0x10, 0x27, 0, 0]).unwrap();
/// assert_eq!(ah.amp_hours(), 10_000);
/// assert_eq!(ah.encode(), [0x10, 0x27, 0, 0]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct AmpHours(u32);

object_value! { AmpHours(u32; 4), "1 Ah"; }

impl AmpHours {
    /// Ampere-hours (the raw value: 1 Ah per bit).
    #[must_use]
    pub const fn amp_hours(self) -> u32 {
        self.0
    }

    /// Exact milliampere-hours.
    #[must_use]
    pub const fn milliamp_hours(self) -> u64 {
        self.0 as u64 * 1000
    }
}

/// 6051h / 6052h / 6053h ampere-hours, Unsigned16, 0.125 Ah per bit (CiA 418
/// sections 7.3.10-7.3.12).
///
/// CiA 418 defines no "no value" marker for these objects: 0xFFFF is the
/// largest reading, 8191.875 Ah ([`EighthAmpHours::MAX`]). A device profile
/// that reserves 0xFFFF as "no value" reads the object with a type of its
/// own.
///
/// ```
/// use canopen_codec::cia418::EighthAmpHours;
/// let ah = EighthAmpHours::decode(&[0x0C, 0x00]).unwrap(); // 12 * 0.125
/// assert_eq!(ah.milliamp_hours(), 1_500);
/// assert_eq!(EighthAmpHours::from_milliamp_hours(1_500), Some(ah));
/// assert_eq!(ah.as_amp_hours_f32(), 1.5);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct EighthAmpHours(u16);

object_value! {
    EighthAmpHours(u16; 2), "0.125 Ah";
    /// Whole ampere-hours; `None` above 8191 Ah.
    whole: fn from_amp_hours(ah) * 8,
        /// Ampere-hours as `f32` (exact).
        float: fn as_amp_hours_f32 -> f32;
    /// `Some` if `mah` is a multiple of 125 mAh that fits 16 bits.
    fine: fn from_milliamp_hours(mah: u32) / MILLIAMP_HOURS_PER_BIT = 125, max u16::MAX;
    /// Exact milliampere-hours (raw * 125).
    exact: fn milliamp_hours;
}

impl EighthAmpHours {
    /// 0xFFFF, the largest value: 8191.875 Ah (CiA 418 gives it no special
    /// meaning).
    pub const MAX: EighthAmpHours = EighthAmpHours(0xFFFF);
}

/// 6060h battery voltage, Unsigned32, 1/1024 V per bit (CiA 418 section
/// 7.3.14).
///
/// 1/1024 V is exactly 976 562 500 pV, so [`BatteryVoltage::picovolts`] is
/// exact; [`BatteryVoltage::as_volts_f64`] is exact too (a `u32` over a power
/// of two fits an `f64` mantissa).
///
/// ```
/// use canopen_codec::cia418::BatteryVoltage;
/// let v = BatteryVoltage::decode(&[0x00, 0xC0, 0x00, 0x00]).unwrap(); // 48 * 1024
/// assert_eq!(v.as_volts_f64(), 48.0);
/// assert_eq!(BatteryVoltage::from_volts(48), Some(v));
/// assert_eq!(BatteryVoltage::from_raw(1).picovolts(), 976_562_500);
/// assert_eq!(BatteryVoltage::from_raw(1).millivolts_rounded(), 1);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct BatteryVoltage(u32);

object_value! {
    BatteryVoltage(u32; 4), "1/1024 V";
    /// Whole volts; `None` above 4 194 303 V.
    whole: fn from_volts(volts) * 1024,
        /// Volts as `f64` (exact).
        float: fn as_volts_f64 -> f64;
    /// `Some` if `pv` is a whole number of 1/1024 V steps that fits 32 bits.
    fine: fn from_picovolts(pv: u64) / PICOVOLTS_PER_BIT = 976_562_500, max u32::MAX;
    /// Exact picovolts (raw * 976 562 500; never overflows `u64`).
    exact: fn picovolts;
}

impl BatteryVoltage {
    /// Millivolts rounded to nearest (half up); not exact.
    #[must_use]
    pub const fn millivolts_rounded(self) -> u32 {
        ((self.0 as u64 * 1000 + 512) / 1024) as u32
    }
}

/// 6070h charge current requested, Unsigned16, 1/16 A per bit (CiA 418
/// section 7.3.15).
///
/// **Invalid marker**: the profile says "FFh shall indicate an invalid value"
/// for this 16-bit object. This crate treats **0xFFFF** as the invalid marker
/// ([`ChargeCurrentRequested::INVALID`]); 0x00FF is 15.9375 A, a valid
/// request (CiA 418 v1.0.1, 7.3.15).
///
/// ```
/// use canopen_codec::cia418::ChargeCurrentRequested;
/// let i = ChargeCurrentRequested::decode(&[0xA0, 0x00]).unwrap(); // 160 / 16
/// assert_eq!(i.microamps(), Some(10_000_000));
/// assert_eq!(i.as_amps_f32(), Some(10.0));
/// let ff = ChargeCurrentRequested::decode(&[0xFF, 0x00]).unwrap();
/// assert_eq!(ff.as_amps_f32(), Some(15.9375));
/// assert!(ChargeCurrentRequested::decode(&[0xFF, 0xFF]).unwrap().is_invalid());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ChargeCurrentRequested(u16);

object_value! {
    ChargeCurrentRequested(u16; 2), "1/16 A";
    /// Whole amperes; `None` above 4095 A.
    whole: fn from_amps(amps) * 16;
    /// `Some` if `ua` is a multiple of 62 500 uA below the invalid marker
    /// (at most 4095.875 A).
    fine: fn from_microamps(ua: u32) / MICROAMPS_PER_BIT = 62_500, max Self::INVALID.0 - 1;
}

impl ChargeCurrentRequested {
    /// 0xFFFF: no valid request.
    pub const INVALID: ChargeCurrentRequested = ChargeCurrentRequested(0xFFFF);

    /// True for the invalid marker 0xFFFF.
    #[must_use]
    pub const fn is_invalid(self) -> bool {
        self.0 == Self::INVALID.0
    }

    /// Exact microamperes, `None` for the invalid marker.
    #[must_use]
    pub const fn microamps(self) -> Option<u32> {
        if self.is_invalid() {
            None
        } else {
            Some(self.0 as u32 * Self::MICROAMPS_PER_BIT)
        }
    }

    /// Amperes as `f32` (exact), `None` for the invalid marker.
    #[must_use]
    pub fn as_amps_f32(self) -> Option<f32> {
        if self.is_invalid() {
            None
        } else {
            Some(f32::from(self.0) / 16.0)
        }
    }
}

/// What a [`StateOfCharge`] byte says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SocReading {
    /// 0..=100 %.
    Percent(u8),
    /// 0xFF: no valid estimate (6080h's default).
    Invalid,
    /// 101..=254: outside the profile's value range; kept raw.
    OutOfRange(u8),
}

/// 6080h charger state of charge / 6081h battery state of charge, Unsigned8,
/// 1 % per bit, value range 0..=100 and 0xFF (CiA 418 sections 7.3.16,
/// 7.3.17).
///
/// Any byte decodes: 101..=254 lie outside the profile's value range and are
/// kept as [`SocReading::OutOfRange`] (never dropped or clamped), so every
/// byte round-trips.
///
/// ```
/// use canopen_codec::cia418::{SocReading, StateOfCharge};
/// assert_eq!(StateOfCharge::decode(&[80]).unwrap().percent(), Some(80));
/// assert_eq!(StateOfCharge::decode(&[0xFF]).unwrap().reading(), SocReading::Invalid);
/// assert_eq!(StateOfCharge::decode(&[150]).unwrap().reading(), SocReading::OutOfRange(150));
/// assert_eq!(StateOfCharge::new(101), None);
/// assert_eq!(StateOfCharge::default(), StateOfCharge::INVALID); // 6080h default
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct StateOfCharge(u8);

object_value! { StateOfCharge(u8; 1), "1 %"; }

impl Default for StateOfCharge {
    /// 0xFF (invalid), the default of 6080h.
    fn default() -> Self {
        Self::INVALID
    }
}

impl StateOfCharge {
    /// 0xFF: no valid estimate.
    pub const INVALID: StateOfCharge = StateOfCharge(0xFF);

    /// A percentage `0..=100` (a byte [`reading`](Self::reading) reads as
    /// [`SocReading::Percent`]); `None` otherwise.
    #[must_use]
    pub const fn new(percent: u8) -> Option<Self> {
        let soc = StateOfCharge(percent);
        match soc.reading() {
            SocReading::Percent(_) => Some(soc),
            _ => None,
        }
    }

    /// What the byte means.
    #[must_use]
    pub const fn reading(self) -> SocReading {
        match self.0 {
            0..=100 => SocReading::Percent(self.0),
            0xFF => SocReading::Invalid,
            other => SocReading::OutOfRange(other),
        }
    }

    /// The percentage, `None` for invalid and out-of-range bytes.
    #[must_use]
    pub const fn percent(self) -> Option<u8> {
        match self.reading() {
            SocReading::Percent(p) => Some(p),
            _ => None,
        }
    }

    /// True for the invalid marker 0xFF.
    #[must_use]
    pub const fn is_invalid(self) -> bool {
        self.0 == 0xFF
    }

    /// True for 101..=254.
    #[must_use]
    pub const fn is_out_of_range(self) -> bool {
        matches!(self.reading(), SocReading::OutOfRange(_))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temperature_vectors() {
        // -40.0 degC = -320 = 0xFEC0, 85.0 degC = 680 = 0x02A8 (value range).
        let cold = Temperature::decode(&[0xC0, 0xFE]).unwrap();
        assert_eq!(cold, Temperature::SPECIFIED_MIN);
        assert_eq!(cold.millidegrees_c(), -40_000);
        assert_eq!(cold.as_celsius_f32(), -40.0);
        let hot = Temperature::decode(&[0xA8, 0x02]).unwrap();
        assert_eq!(hot, Temperature::SPECIFIED_MAX);
        assert_eq!(hot.millidegrees_c(), 85_000);
        assert_eq!(hot.encode(), [0xA8, 0x02]);
        assert!(hot.in_specified_range());
        assert!(!Temperature::from_raw(681).in_specified_range());
        assert_eq!(Temperature::from_raw(1).millidegrees_c(), 125);
        assert_eq!(Temperature::from_raw(-1).as_celsius_f32(), -0.125);
        assert_eq!(
            Temperature::from_celsius(25),
            Some(Temperature::from_raw(200))
        );
        assert_eq!(Temperature::from_celsius(4096), None);
        assert_eq!(
            Temperature::from_millidegrees_c(i16::MIN as i32 * 125),
            Some(Temperature::from_raw(i16::MIN))
        );
        assert_eq!(
            Temperature::from_millidegrees_c((i16::MAX as i32 + 1) * 125),
            None
        );
        assert_eq!(Temperature::from_millidegrees_c(-1), None);
        assert_eq!(
            Temperature::decode(&[1]),
            Err(DecodeError::Truncated { need: 2, got: 1 })
        );
    }

    #[test]
    fn temperature_every_raw_round_trips() {
        for raw in i16::MIN..=i16::MAX {
            let t = Temperature::from_raw(raw);
            assert_eq!(
                Temperature::from_millidegrees_c(t.millidegrees_c()),
                Some(t)
            );
            assert_eq!(Temperature::decode(&t.encode()), Ok(t));
        }
    }

    #[test]
    fn amp_hour_vectors() {
        let ah = AmpHours::decode(&[0x78, 0x56, 0x34, 0x12]).unwrap();
        assert_eq!(ah.raw(), 0x1234_5678);
        assert_eq!(ah.milliamp_hours(), 0x1234_5678u64 * 1000);
        assert_eq!(ah.encode(), [0x78, 0x56, 0x34, 0x12]);
        assert!(AmpHours::decode(&[0; 3]).is_err());

        let e = EighthAmpHours::decode(&[0xFF, 0xFF]).unwrap();
        assert_eq!(e, EighthAmpHours::MAX);
        assert_eq!(e.milliamp_hours(), 8_191_875);
        assert_eq!(EighthAmpHours::from_milliamp_hours(8_191_875), Some(e));
        assert_eq!(EighthAmpHours::from_milliamp_hours(8_192_000), None);
        assert_eq!(EighthAmpHours::from_milliamp_hours(100), None);
        assert_eq!(
            EighthAmpHours::from_amp_hours(100).map(EighthAmpHours::encode),
            Some([0x20, 0x03])
        );
        assert_eq!(EighthAmpHours::from_amp_hours(8192), None);
        assert_eq!(EighthAmpHours::from_raw(1).as_amp_hours_f32(), 0.125);
    }

    #[test]
    fn voltage_vectors() {
        let v = BatteryVoltage::decode(&[0x01, 0x00, 0x00, 0x00]).unwrap();
        assert_eq!(v.picovolts(), 976_562_500);
        assert_eq!(BatteryVoltage::from_picovolts(976_562_500), Some(v));
        assert_eq!(BatteryVoltage::from_picovolts(1), None);
        let max = BatteryVoltage::from_raw(u32::MAX);
        assert_eq!(BatteryVoltage::from_picovolts(max.picovolts()), Some(max));
        assert_eq!(
            BatteryVoltage::from_picovolts(max.picovolts() + BatteryVoltage::PICOVOLTS_PER_BIT),
            None
        );
        assert_eq!(max.millivolts_rounded(), 4_194_303_999);
        assert_eq!(BatteryVoltage::from_volts(4_194_304), None);
        assert_eq!(
            BatteryVoltage::from_volts(24).map(BatteryVoltage::encode),
            Some([0x00, 0x60, 0x00, 0x00])
        );
        assert_eq!(BatteryVoltage::from_raw(512).as_volts_f64(), 0.5);
        assert_eq!(BatteryVoltage::from_raw(511).millivolts_rounded(), 499);
    }

    #[test]
    fn charge_current_vectors() {
        let i = ChargeCurrentRequested::decode(&[0xFE, 0xFF]).unwrap();
        assert!(!i.is_invalid());
        assert_eq!(i.microamps(), Some(65_534 * 62_500));
        assert_eq!(
            ChargeCurrentRequested::from_microamps(65_534 * 62_500),
            Some(i)
        );
        assert_eq!(
            ChargeCurrentRequested::from_microamps(65_535 * 62_500),
            None
        );
        assert_eq!(ChargeCurrentRequested::from_microamps(1), None);
        let inv = ChargeCurrentRequested::decode(&[0xFF, 0xFF]).unwrap();
        assert_eq!(inv, ChargeCurrentRequested::INVALID);
        assert_eq!(inv.microamps(), None);
        assert_eq!(inv.as_amps_f32(), None);
        assert_eq!(inv.encode(), [0xFF, 0xFF]);
        let ff = ChargeCurrentRequested::from_raw(0x00FF);
        assert_eq!(ff.microamps(), Some(15_937_500));
        assert_eq!(
            ChargeCurrentRequested::from_amps(10).map(ChargeCurrentRequested::encode),
            Some([0xA0, 0x00])
        );
        assert_eq!(ChargeCurrentRequested::from_amps(4096), None);
    }

    #[test]
    fn soc_every_byte() {
        for raw in 0..=u8::MAX {
            let s = StateOfCharge::decode(&[raw]).unwrap();
            assert_eq!(s.encode(), [raw]);
            match raw {
                0..=100 => {
                    assert_eq!(s.reading(), SocReading::Percent(raw));
                    assert_eq!(StateOfCharge::new(raw), Some(s));
                }
                0xFF => assert!(s.is_invalid() && s.percent().is_none()),
                _ => {
                    assert_eq!(s.reading(), SocReading::OutOfRange(raw));
                    assert!(s.is_out_of_range());
                    assert_eq!(StateOfCharge::new(raw), None);
                }
            }
        }
        assert_eq!(StateOfCharge::default().encode(), [0xFF]);
    }
}
