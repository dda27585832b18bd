//! How to read an object's value in words: its scale and [`Unit`], a
//! raw value with a special meaning ([`Marker`]), the bits of a flag word
//! ([`FlagWord`]) or a profile's own format ([`ValueFormat`]), gathered as
//! an [`Interpretation`]. These are facts of the object (the profile that
//! defines it says them: CiA 418 v1.0.1 section 7.3, the Delta-Q object
//! list), stated once in its [`ObjectRow`](super::ObjectRow); the PDO
//! decoder ([`crate::pdo::Catalogue`]) and the log analysis read them.

use core::fmt;
use core::hash::{Hash, Hasher};

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

/// A raw value with a special meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Marker {
    /// No special value.
    None,
    /// This raw value marks an invalid reading (CiA 418 marks its sensor
    /// readings this way).
    Invalid(u64),
    /// This raw value means "no value" (Delta-Q's defaults of 0xFFFF and
    /// 0xFFFF_FFFF are).
    NoValue(u64),
}

/// How a profile writes a value that a table cannot describe: a function
/// of the raw bits, named by `kind`. Formats are told apart by `kind`
/// alone (equality and hashing ignore the functions).
#[derive(Debug, Clone, Copy)]
pub struct ValueFormat {
    /// A short name for machine output (`error`, `algorithm`,
    /// `battery_type`); [`FieldValue::kind`](crate::pdo::FieldValue::kind) returns it.
    pub kind: &'static str,
    /// False for raw values that mean "no value"; the field then decodes as
    /// [`FieldValue::NoValue`](crate::pdo::FieldValue::NoValue).
    pub has_value: fn(u64) -> bool,
    /// Writes the value in words (precision and `#` are the formatter's).
    pub write: fn(u64, &mut fmt::Formatter<'_>) -> fmt::Result,
}

impl PartialEq for ValueFormat {
    fn eq(&self, other: &Self) -> bool {
        self.kind == other.kind
    }
}

impl Eq for ValueFormat {}

impl Hash for ValueFormat {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.kind.hash(state);
    }
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
    /// A bit-field object, described by its flag word.
    Flags(&'static FlagWord),
    /// A value the profile writes itself.
    Formatted(&'static ValueFormat),
    /// One Unsigned32 element of a packed string: four ISO 646 characters,
    /// the first in the least significant byte.
    Chars,
    /// Padding: the bits carry nothing.
    Padding,
}

/// One field of a bit-field object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FlagField {
    /// A flag: says `set` when every bit of `mask` is set, otherwise
    /// `clear` (or nothing).
    Bit {
        /// The flag's bit(s).
        mask: u64,
        /// Words when set.
        set: &'static str,
        /// Words when clear, if any.
        clear: Option<&'static str>,
    },
    /// A multi-bit field whose values have names: `(value, words)`, with
    /// `None` for a value that says nothing. An unlisted value reads
    /// `"{unknown} {value}"`.
    Choice {
        /// The field's bits (contiguous); the value is shifted down to bit 0.
        mask: u64,
        /// The named values.
        values: &'static [(u64, Option<&'static str>)],
        /// What an unlisted value is called (`charge type` gives
        /// `charge type 15`).
        unknown: &'static str,
    },
    /// Bits within `mask` that no [`FlagField::Bit`] or
    /// [`FlagField::Choice`] of the word covers: when any is set, says
    /// `other bits XXh` (in place, two hex digits at least).
    OtherBits {
        /// Where unknown bits are looked for.
        mask: u64,
    },
}

/// How to say a bit-field object in words: its fields in the order they
/// are written, and what to say when none of them writes anything.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct FlagWord {
    /// The fields, in writing order.
    pub fields: &'static [FlagField],
    /// Written when no field wrote anything (`none`), if anything.
    pub when_empty: Option<&'static str>,
}

impl FlagWord {
    /// The bits some [`FlagField::Bit`] or [`FlagField::Choice`] covers.
    #[must_use]
    pub const fn known_bits(&self) -> u64 {
        let mut known = 0;
        let mut rest = self.fields;
        while let [field, tail @ ..] = rest {
            known |= match *field {
                FlagField::Bit { mask, .. } | FlagField::Choice { mask, .. } => mask,
                FlagField::OtherBits { .. } => 0,
            };
            rest = tail;
        }
        known
    }
}
