//! Named, scaled PDO fields: a catalogue of the CiA 418 application objects
//! (6000h-6090h) and the Delta-Q charger's manufacturer objects, and a
//! decoder that turns a PDO payload plus its mapping into [`NamedField`]s
//! without allocating.
//!
//! ```
//! use canopen_codec::pdo::{Catalogue, MappingEntry, PdoMapping};
//!
//! // The real capture's charger TPDO 0, remapped by its integrator
//! // (captures/README.md): 2002h/16, 2101h/16, 2006h/16, 16 bits padding.
//! let mapping = PdoMapping::new(&[
//!     MappingEntry::new(0x2002, 0, 16),
//!     MappingEntry::new(0x2101, 0, 16),
//!     MappingEntry::new(0x2006, 0, 16),
//!     MappingEntry::new(0x0006, 0, 16), // UNSIGNED16 dummy entry
//! ]).unwrap();
//! let fields = Catalogue::DeltaQCharger.decode(&mapping, &[0x74, 0x13, 0x45, 0x4E, 0x70, 0, 0, 0]);
//! let words: Vec<String> = fields.iter().map(|f| format!("{f:.2}")).collect();
//! assert_eq!(words, [
//!     "2002h charging current 19.45 A",
//!     "2101h battery voltage 78.27 V",
//!     "2006h extended charge status: AC present, charger enabled, override external (BMS)",
//!     "0006h padding (16 bits)",
//! ]);
//! // Without a precision the value is exact: 0x1374 / 256.
//! assert_eq!(fields.as_slice()[0].to_string(), "2002h charging current 19.453125 A");
//! ```
//!
//! ## Which device's meaning
//!
//! An object's meaning belongs to the device whose dictionary holds it, so
//! a catalogue is chosen per device ([`Catalogue`]), not per index:
//!
//! - [`Catalogue::BatteryModule`] knows the CiA 418 objects only. Indexes
//!   2000h-5FFFh are manufacturer-specific; on an unknown module they have
//!   no known meaning and decode as [`FieldValue::Raw`].
//! - [`Catalogue::DeltaQCharger`] knows the Delta-Q objects and the CiA 418
//!   objects the charger implements, with the charger's meaning where it
//!   differs. The one difference known is **6052h**: both scale it by
//!   0.125 Ah, but on the charger 0xFFFF is "no value" (its default), while
//!   CiA 418 has no marker and 0xFFFF reads 8191.875 Ah.
//!
//! A PDO is decoded with the catalogue of the device that owns the PDO's
//! dictionary: a charger's TPDOs *and* RPDOs (the RPDOs write into the
//! charger's dictionary) use [`Catalogue::DeltaQCharger`].
//!
//! ## Values
//!
//! Every scale in the catalogue is a power of two, so a value is an exact
//! [`Fixed`] (`raw / 2^frac_bits`) with an exact decimal form: `Display`
//! prints every digit (`19.453125`), or rounds to a precision when one is
//! given (`{:.2}` gives `19.45`; halves away from zero). No floating point
//! is involved; [`Fixed::to_f64`] is there for callers who want one.
//!
//! - **Markers.** CiA 418 marks invalid readings (6070h 0xFFFF, 6080h /
//!   6081h 0xFF): [`FieldValue::Invalid`]. Delta-Q's 0xFFFF / 0xFFFF_FFFF
//!   defaults mean "no value": [`FieldValue::NoValue`]. For 6070h the profile
//!   says "FFh" of a 16-bit object; 0xFFFF is taken as the marker (0x00FF is
//!   a valid 15.9375 A).
//! - **6010h temperature** is CiA 418's Integer16 at 0.125 degC per bit, no
//!   offset. (The integrator's DBC for the real capture adds -40 degC; that
//!   is not the profile and is not applied here.)
//! - **Bit fields** (6000h, 6001h, 6090h, 2006h, 2008h, 4201h) decode to
//!   [`Flags`], whose `Display` says the set bits in words and keeps unknown
//!   bits (`other bits 80h`).
//! - **Widths.** A field whose mapped length differs from the object's size
//!   is not scaled: [`FieldValue::WrongWidth`]. Padding (dummy entries 0001h-
//!   001Fh and Delta-Q's 2FFAh) is [`FieldValue::Padding`] at any width.
//! - **Short frames.** A field that does not fit in the payload is
//!   [`FieldValue::Missing`] (CiA 301 would answer with EMCY 8210h); extra
//!   payload bytes past the mapping are counted in
//!   [`NamedFields::unmapped_bytes`].

use core::fmt;

use crate::cia418::{BatteryStatus, BatteryType, ChargerStatus, WaterLevelStatus};
use crate::deltaq::{
    AlgorithmRequest, ChargeIndication, ChargeStatusFlags, ChargeType, DerateReasons,
    DisplayedError, ExtendedChargeStatus, ExternalOverride, OverrideSource,
};

use super::mapping::{extract_bits, sign_extend, MappingEntry, PdoMapping, MAX_ENTRIES};

mod flags;
mod tables;
pub use flags::Flags;
pub use tables::{CIA418_OBJECTS, DELTAQ_OBJECTS};

/// A unit of a scaled value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Unit {
    /// Ampere.
    Ampere,
    /// Volt (also V rms for the AC voltage).
    Volt,
    /// Ampere-hour.
    AmpereHour,
    /// Degree Celsius.
    DegreeCelsius,
    /// Percent.
    Percent,
    /// Milliohm.
    Milliohm,
    /// Minute.
    Minute,
    /// Day.
    Day,
}

impl Unit {
    /// The symbol: `A`, `V`, `Ah`, `degC`, `%`, `mOhm`, `min`, `d`.
    #[must_use]
    pub const fn symbol(self) -> &'static str {
        match self {
            Unit::Ampere => "A",
            Unit::Volt => "V",
            Unit::AmpereHour => "Ah",
            Unit::DegreeCelsius => "degC",
            Unit::Percent => "%",
            Unit::Milliohm => "mOhm",
            Unit::Minute => "min",
            Unit::Day => "d",
        }
    }
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// An exact binary fixed-point number: `raw / 2^frac_bits`.
///
/// ```
/// use canopen_codec::pdo::Fixed;
/// let v = Fixed::new(0x07BA, 4); // 1978 / 16
/// assert_eq!(v.to_string(), "123.625");
/// assert_eq!(format!("{v:.2}"), "123.63");
/// assert_eq!(format!("{:.2}", Fixed::new(82 * 256, 8)), "82.00");
/// assert_eq!(format!("{:#.2}", Fixed::new(82 * 256, 8)), "82"); // at most 2 places
/// assert_eq!(format!("{:.1}", Fixed::new(-3, 3)), "-0.4");
/// assert_eq!(v.to_f64(), 123.625);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fixed {
    raw: i64,
    frac_bits: u8,
}

impl Fixed {
    /// Most fractional bits (larger values are clamped to it).
    pub const MAX_FRAC_BITS: u8 = 32;

    /// `raw / 2^frac_bits`; `frac_bits` above 32 is taken as 32.
    #[must_use]
    pub const fn new(raw: i64, frac_bits: u8) -> Self {
        let frac_bits = if frac_bits > Self::MAX_FRAC_BITS {
            Self::MAX_FRAC_BITS
        } else {
            frac_bits
        };
        Fixed { raw, frac_bits }
    }

    /// The integer numerator.
    #[must_use]
    pub const fn raw(self) -> i64 {
        self.raw
    }

    /// The number of fractional bits.
    #[must_use]
    pub const fn frac_bits(self) -> u8 {
        self.frac_bits
    }

    /// The value as `f64` (exact while `|raw| < 2^53`).
    #[must_use]
    pub fn to_f64(self) -> f64 {
        self.raw as f64 / (1u64 << self.frac_bits) as f64
    }
}

impl fmt::Display for Fixed {
    /// Exact decimal digits, or rounded (halves away from zero) to the
    /// formatter's precision (at most 18 places); with `#` as well
    /// (`{:#.2}`), trailing zeros after rounding are dropped: at most that
    /// many places.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let q = u32::from(self.frac_bits.min(Self::MAX_FRAC_BITS));
        let magnitude = u128::from(self.raw.unsigned_abs());
        let negative = self.raw < 0;
        match f.precision() {
            None => {
                let int = magnitude >> q;
                let frac = magnitude & ((1u128 << q) - 1);
                if negative {
                    f.write_str("-")?;
                }
                write!(f, "{int}")?;
                if frac != 0 {
                    // frac / 2^q = frac * 5^q / 10^q: exactly q digits.
                    let mut digits = frac * 5u128.pow(q);
                    let mut width = q as usize;
                    while digits % 10 == 0 && width > 1 {
                        digits /= 10;
                        width -= 1;
                    }
                    write!(f, ".{digits:0width$}")?;
                }
                Ok(())
            }
            Some(places) => {
                let places = places.min(18);
                let scale = 10u128.pow(places as u32);
                let half = if q == 0 { 0 } else { 1u128 << (q - 1) };
                let rounded = (magnitude * scale + half) >> q;
                if negative && rounded != 0 {
                    f.write_str("-")?;
                }
                write!(f, "{}", rounded / scale)?;
                let (mut frac, mut places) = (rounded % scale, places);
                if f.alternate() {
                    // `{:#.2}`: at most 2 places, trailing zeros dropped.
                    while places > 0 && frac % 10 == 0 {
                        frac /= 10;
                        places -= 1;
                    }
                }
                if places > 0 {
                    write!(f, ".{frac:0places$}")?;
                }
                Ok(())
            }
        }
    }
}

/// Writes `v` with the formatter's precision and `#` flag (and nothing
/// else) passed on.
fn forward<T: fmt::Display>(f: &mut fmt::Formatter<'_>, v: &T) -> fmt::Result {
    match (f.precision(), f.alternate()) {
        (Some(p), true) => write!(f, "{v:#.p$}"),
        (Some(p), false) => write!(f, "{v:.p$}"),
        (None, true) => write!(f, "{v:#}"),
        (None, false) => write!(f, "{v}"),
    }
}

/// A raw value with a special meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Marker {
    /// No special value.
    None,
    /// This raw value marks an invalid reading (CiA 418).
    Invalid(u64),
    /// This raw value means "no value" (Delta-Q defaults).
    NoValue(u64),
}

/// Which bit-field object a [`Interpretation::Flags`] entry is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FlagsKind {
    /// 6000h battery status.
    BatteryStatus,
    /// 6001h charger status.
    ChargerStatus,
    /// 6090h water level status.
    WaterLevelStatus,
    /// 2006h Delta-Q extended charge status.
    ExtendedChargeStatus,
    /// 2008h Delta-Q derate reasons.
    DerateReasons,
    /// 4201h Delta-Q external override.
    ExternalOverride,
}

/// How a catalogue entry turns raw bits into a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Interpretation {
    /// Unsigned integer: `raw / 2^frac_bits` in `unit`.
    Unsigned {
        /// Fractional bits of the scale (Q8 is 8).
        frac_bits: u8,
        /// The unit, if the object has one.
        unit: Option<Unit>,
        /// A raw value with a special meaning.
        marker: Marker,
        /// Largest raw value in the object's range, if it has one.
        max: Option<u64>,
    },
    /// Two's complement integer: `raw / 2^frac_bits` in `unit`.
    Signed {
        /// Fractional bits of the scale.
        frac_bits: u8,
        /// The unit, if the object has one.
        unit: Option<Unit>,
    },
    /// A bit-field object.
    Flags(FlagsKind),
    /// 2060h: a 1003h-style error entry ([`DisplayedError`]).
    DisplayedError,
    /// 2241h: an algorithm request ([`AlgorithmRequest`]).
    AlgorithmRequest,
    /// 6020h sub 1: the battery type byte ([`BatteryType`]).
    BatteryType,
    /// One Unsigned32 element of a packed string: four ISO 646 characters,
    /// the first in the least significant byte.
    Chars,
    /// Padding: the bits carry nothing.
    Padding,
}

/// One object (or a run of sub-indexes) of a catalogue.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CatalogueEntry {
    /// Object index.
    pub index: u16,
    /// First sub-index covered.
    pub first_sub: u8,
    /// Last sub-index covered.
    pub last_sub: u8,
    /// Name in words (lower case, as in "2002h charging current").
    pub name: &'static str,
    /// The object's size in bits.
    pub bits: u8,
    /// How to read it.
    pub interpretation: Interpretation,
}

impl CatalogueEntry {
    /// True if this entry describes `index`:`sub`.
    #[must_use]
    pub const fn covers(&self, index: u16, sub: u8) -> bool {
        self.index == index && sub >= self.first_sub && sub <= self.last_sub
    }
}

/// Whose object dictionary a PDO's entries name (see the module docs,
/// "Which device's meaning").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Catalogue {
    /// A CiA 418 battery module: [`CIA418_OBJECTS`] only.
    BatteryModule,
    /// The Delta-Q IC Series charger: [`DELTAQ_OBJECTS`], then
    /// [`CIA418_OBJECTS`].
    DeltaQCharger,
}

impl Catalogue {
    /// The catalogue entry of `index`:`sub`, if known.
    ///
    /// ```
    /// use canopen_codec::pdo::Catalogue;
    /// assert_eq!(Catalogue::DeltaQCharger.lookup(0x2002, 0).unwrap().name, "charging current");
    /// assert!(Catalogue::BatteryModule.lookup(0x2002, 0).is_none());
    /// ```
    #[must_use]
    pub fn lookup(self, index: u16, sub: u8) -> Option<&'static CatalogueEntry> {
        let find = |t: &'static [CatalogueEntry]| t.iter().find(|e| e.covers(index, sub));
        match self {
            Catalogue::BatteryModule => find(CIA418_OBJECTS),
            Catalogue::DeltaQCharger => find(DELTAQ_OBJECTS).or_else(|| find(CIA418_OBJECTS)),
        }
    }

    /// Names and interprets one field: `raw` holds the entry's bits as
    /// [`extract_bits`] returns them.
    #[must_use]
    pub fn interpret(self, entry: MappingEntry, raw: u64) -> NamedField {
        let bits = u32::from(entry.bits);
        let named = |name, value| NamedField {
            entry,
            name,
            raw,
            value,
        };
        if entry.is_dummy() {
            return named("padding", FieldValue::Padding);
        }
        let Some(def) = self.lookup(entry.index, entry.sub) else {
            return named("unknown object", FieldValue::Raw);
        };
        if def.interpretation == Interpretation::Padding {
            return named(def.name, FieldValue::Padding);
        }
        if def.bits != entry.bits {
            return named(
                def.name,
                FieldValue::WrongWidth {
                    object_bits: def.bits,
                },
            );
        }
        let value = match def.interpretation {
            Interpretation::Unsigned {
                frac_bits,
                unit,
                marker,
                max,
            } => match (marker, i64::try_from(raw)) {
                (Marker::Invalid(m), _) if m == raw => FieldValue::Invalid,
                (Marker::NoValue(m), _) if m == raw => FieldValue::NoValue,
                (_, Err(_)) => FieldValue::Raw,
                (_, Ok(v)) => {
                    let value = Fixed::new(v, frac_bits);
                    match max {
                        Some(max) if raw > max => FieldValue::OutOfRange { value, unit },
                        _ => FieldValue::Scaled { value, unit },
                    }
                }
            },
            Interpretation::Signed { frac_bits, unit } => FieldValue::Scaled {
                value: Fixed::new(sign_extend(raw, bits), frac_bits),
                unit,
            },
            Interpretation::Flags(kind) => FieldValue::Flags(Flags::from_raw(kind, raw)),
            Interpretation::DisplayedError => {
                FieldValue::Error(DisplayedError::from_u32(raw as u32))
            }
            Interpretation::AlgorithmRequest => match AlgorithmRequest::from_u32(raw as u32) {
                Some(r) => FieldValue::Algorithm(r),
                None => FieldValue::NoValue,
            },
            Interpretation::BatteryType => FieldValue::BatteryType(BatteryType::from_u8(raw as u8)),
            Interpretation::Chars => FieldValue::Chars((raw as u32).to_le_bytes()),
            Interpretation::Padding => FieldValue::Padding,
        };
        named(def.name, value)
    }

    /// Decodes a PDO payload with its mapping into named fields, in entry
    /// order. Total: any payload decodes; fields past its end are
    /// [`FieldValue::Missing`]. Payloads longer than 8 bytes are read as
    /// their first 8 (a CAN frame carries at most 8).
    #[must_use]
    pub fn decode(self, mapping: &PdoMapping, payload: &[u8]) -> NamedFields {
        let have_bits = (payload.len().min(8) * 8) as u32;
        let mut out = NamedFields {
            fields: [NamedField::EMPTY; MAX_ENTRIES],
            len: 0,
            unmapped_bytes: payload.len().saturating_sub(mapping.byte_len()).min(255) as u8,
        };
        for ((slot, entry), offset) in out
            .fields
            .iter_mut()
            .zip(mapping.entries())
            .zip(mapping.offsets())
        {
            let bits = u32::from(entry.bits);
            *slot = if offset.saturating_add(bits) > have_bits {
                let mut f = self.interpret(*entry, 0);
                f.value = FieldValue::Missing;
                f
            } else {
                self.interpret(*entry, extract_bits(payload, offset, bits))
            };
            out.len += 1;
        }
        out
    }
}

/// What a field's bits mean.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum FieldValue {
    /// A number, exact, in a unit if the object has one.
    Scaled {
        /// The value.
        value: Fixed,
        /// The unit.
        unit: Option<Unit>,
    },
    /// A number outside the object's value range (e.g. a state of charge of
    /// 150 %), kept.
    OutOfRange {
        /// The value.
        value: Fixed,
        /// The unit.
        unit: Option<Unit>,
    },
    /// A bit-field object.
    Flags(Flags),
    /// 2060h: the displayed error (0 is none).
    Error(DisplayedError),
    /// 2241h: an algorithm request.
    Algorithm(AlgorithmRequest),
    /// 6020h sub 1: the battery type.
    BatteryType(BatteryType),
    /// Four characters of a packed string (zero bytes are padding).
    Chars([u8; 4]),
    /// The object's "invalid" marker (CiA 418).
    Invalid,
    /// The object's "no value" marker (Delta-Q).
    NoValue,
    /// Padding bits.
    Padding,
    /// The field lies (partly) past the end of the payload.
    Missing,
    /// The mapping gives the object a length other than its size; the raw
    /// bits are kept in [`NamedField::raw`].
    WrongWidth {
        /// The object's size in bits.
        object_bits: u8,
    },
    /// An object the catalogue does not know; see [`NamedField::raw`].
    Raw,
}

impl FieldValue {
    /// A short name of the variant, for machine output: `scaled`,
    /// `out_of_range`, `flags`, `error`, `algorithm`, `battery_type`,
    /// `chars`, `invalid`, `no_value`, `padding`, `missing`, `wrong_width`,
    /// `raw`.
    #[must_use]
    pub const fn kind(&self) -> &'static str {
        match self {
            FieldValue::Scaled { .. } => "scaled",
            FieldValue::OutOfRange { .. } => "out_of_range",
            FieldValue::Flags(_) => "flags",
            FieldValue::Error(_) => "error",
            FieldValue::Algorithm(_) => "algorithm",
            FieldValue::BatteryType(_) => "battery_type",
            FieldValue::Chars(_) => "chars",
            FieldValue::Invalid => "invalid",
            FieldValue::NoValue => "no_value",
            FieldValue::Padding => "padding",
            FieldValue::Missing => "missing",
            FieldValue::WrongWidth { .. } => "wrong_width",
            FieldValue::Raw => "raw",
        }
    }

    /// The number, for scaled and out-of-range values.
    #[must_use]
    pub const fn number(&self) -> Option<Fixed> {
        match self {
            FieldValue::Scaled { value, .. } | FieldValue::OutOfRange { value, .. } => Some(*value),
            _ => None,
        }
    }

    /// The unit, for scaled and out-of-range values that have one.
    #[must_use]
    pub const fn unit(&self) -> Option<Unit> {
        match self {
            FieldValue::Scaled { unit, .. } | FieldValue::OutOfRange { unit, .. } => *unit,
            _ => None,
        }
    }
}

impl fmt::Display for FieldValue {
    /// The value alone: `19.453125 A` (precision and `#` passed on to the
    /// number, see [`Fixed`]'s `Display`),
    /// `AC present, ...`, `invalid`, `no value`, ...
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FieldValue::Scaled { value, unit } | FieldValue::OutOfRange { value, unit } => {
                forward(f, value)?;
                if let Some(u) = unit {
                    write!(f, " {u}")?;
                }
                if matches!(self, FieldValue::OutOfRange { .. }) {
                    f.write_str(" (out of range)")?;
                }
                Ok(())
            }
            FieldValue::Flags(flags) => write!(f, "{flags}"),
            FieldValue::Error(e) if e.is_none() => f.write_str("none"),
            FieldValue::Error(e) => {
                write!(f, "{}", e.code)?;
                if let Some(d) = e.code.description() {
                    write!(f, " {d}")?;
                }
                write!(f, " (EEC {:04X}h)", e.eec.raw())
            }
            FieldValue::Algorithm(r) => {
                write!(f, "algorithm {} variant {}", r.algorithm, r.variant)?;
                if r.revert_after_ac_loss {
                    f.write_str(", revert after AC loss")?;
                }
                if r.store_permanently {
                    f.write_str(", store permanently")?;
                }
                Ok(())
            }
            FieldValue::BatteryType(t) => write!(f, "{} ({:02X}h)", t.chemistry(), t.to_u8()),
            FieldValue::Chars(chars) => {
                f.write_str("\"")?;
                for &c in chars.iter().filter(|&&c| c != 0) {
                    if (0x20..0x7F).contains(&c) && c != b'"' && c != b'\\' {
                        write!(f, "{}", char::from(c))?;
                    } else {
                        write!(f, "\\x{c:02X}")?;
                    }
                }
                f.write_str("\"")
            }
            FieldValue::Invalid => f.write_str("invalid"),
            FieldValue::NoValue => f.write_str("no value"),
            FieldValue::Padding => f.write_str("padding"),
            FieldValue::Missing => f.write_str("missing (past the end of the frame)"),
            FieldValue::WrongWidth { object_bits } => {
                write!(
                    f,
                    "mapped with the wrong width (object has {object_bits} bits)"
                )
            }
            FieldValue::Raw => f.write_str("raw"),
        }
    }
}

/// One decoded field of a PDO.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NamedField {
    /// The mapping entry.
    pub entry: MappingEntry,
    /// The object's name (`"unknown object"`, `"padding"` where none).
    pub name: &'static str,
    /// The raw bits, zero-extended (0 for a missing field).
    pub raw: u64,
    /// What they mean.
    pub value: FieldValue,
}

impl NamedField {
    const EMPTY: NamedField = NamedField {
        entry: MappingEntry::new(0, 0, 0),
        name: "",
        raw: 0,
        value: FieldValue::Padding,
    };
}

impl fmt::Display for NamedField {
    /// `2002h charging current 19.453125 A` (a precision rounds the number:
    /// `{:.2}` gives `19.45 A`; `{:#.2}` gives at most 2 places, `82 V` for
    /// `82.00 V`), `2006h extended charge status: AC present,
    /// ...`, `6080h charger state of charge: invalid (raw FFh)`,
    /// `2FFAh:01 padding (8 bits)`. The sub-index is shown when not 0.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let e = self.entry;
        write!(f, "{:04X}h", e.index)?;
        if e.sub != 0 {
            write!(f, ":{:02X}", e.sub)?;
        }
        write!(f, " {}", self.name)?;
        let digits = usize::from(e.bits).div_ceil(4).max(1);
        match &self.value {
            v @ (FieldValue::Scaled { .. } | FieldValue::OutOfRange { .. }) => {
                f.write_str(" ")?;
                forward(f, v)
            }
            FieldValue::Padding => write!(f, " ({} bits)", e.bits),
            FieldValue::Invalid | FieldValue::NoValue => {
                write!(f, ": {} (raw {:0digits$X}h)", self.value, self.raw)
            }
            FieldValue::WrongWidth { object_bits } => write!(
                f,
                ": raw {:0digits$X}h, mapped as {} bits, object has {object_bits}",
                self.raw, e.bits
            ),
            FieldValue::Raw => write!(f, ": raw {:0digits$X}h ({} bits)", self.raw, e.bits),
            v => write!(f, ": {v}"),
        }
    }
}

/// The fields of one PDO, in mapping order (at most 8, no allocation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NamedFields {
    fields: [NamedField; MAX_ENTRIES],
    len: u8,
    unmapped_bytes: u8,
}

impl NamedFields {
    /// The fields.
    #[must_use]
    pub fn as_slice(&self) -> &[NamedField] {
        self.fields.get(..usize::from(self.len)).unwrap_or(&[])
    }

    /// The fields, in order.
    pub fn iter(&self) -> core::slice::Iter<'_, NamedField> {
        self.as_slice().iter()
    }

    /// Number of fields.
    #[must_use]
    pub fn len(&self) -> usize {
        self.as_slice().len()
    }

    /// True when the mapping is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Payload bytes past the end of the mapping (a frame longer than its
    /// mapping; CiA 301 lets a receiver ignore them).
    #[must_use]
    pub const fn unmapped_bytes(&self) -> usize {
        self.unmapped_bytes as usize
    }
}

impl<'a> IntoIterator for &'a NamedFields {
    type Item = &'a NamedField;
    type IntoIter = core::slice::Iter<'a, NamedField>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl fmt::Display for NamedFields {
    /// The fields separated by `; ` (a precision and `#` apply to each
    /// number).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, field) in self.iter().enumerate() {
            if i > 0 {
                f.write_str("; ")?;
            }
            forward(f, field)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
