//! Named, scaled PDO fields: a catalogue of object descriptions (name,
//! width, how to read the bits) and a decoder that turns a PDO payload plus
//! its mapping into [`NamedField`]s without allocating.
//!
//! This is the CiA 301 mechanism only. The tables belong to the device
//! profiles that define the objects: the CiA 418 module's application
//! objects and the Delta-Q charger's manufacturer objects are catalogued in
//! those profile modules, and a device's [`Catalogue`] lists the tables its
//! dictionary holds, first match wins.
//!
//! ```
//! use canopen_codec::od::{Access, DataType, ObjectRow};
//! use canopen_codec::pdo::{Catalogue, MappingEntry, PdoMapping, Unit};
//!
//! // A made-up manufacturer object: 2000h, U16 in 1/16 V.
//! const OBJECTS: &[ObjectRow] = &[
//!     ObjectRow::var(0x2000, "Bus Voltage", DataType::Unsigned16, Access::ReadOnly)
//!         .short("bus voltage")
//!         .scaled(4, Some(Unit::Volt)),
//! ];
//! const DEVICE: Catalogue = Catalogue::new("example device", &[OBJECTS]);
//!
//! let mapping = PdoMapping::new(&[
//!     MappingEntry::new(0x2000, 0, 16),
//!     MappingEntry::new(0x0005, 0, 8), // UNSIGNED8 dummy entry
//! ]).unwrap();
//! let fields = DEVICE.decode(&mapping, &[0xBA, 0x07, 0xFF]);
//! assert_eq!(fields.to_string(), "2000h bus voltage 123.625 V; 0005h padding (8 bits)");
//! assert_eq!(format!("{fields:.2}"), "2000h bus voltage 123.63 V; 0005h padding (8 bits)");
//! ```
//!
//! ## Values
//!
//! Every scale is a power of two, so a value is an exact [`Fixed`]
//! (`raw / 2^frac_bits`) with an exact decimal form: `Display` prints every
//! digit (`19.453125`), or rounds to a precision when one is given (`{:.2}`
//! gives `19.45`; halves away from zero). No floating point is involved;
//! [`Fixed::to_f64`] is there for callers who want one.
//!
//! - **Markers.** An object may reserve a raw value: as an invalid reading
//!   ([`FieldValue::Invalid`]) or as "no value" ([`FieldValue::NoValue`]);
//!   see [`Marker`].
//! - **Bit fields** decode to [`Flags`], described by a static
//!   [`FlagWord`]; `Display` says the set bits in words and keeps unknown
//!   bits (`other bits 80h`).
//! - **Profile values** a table cannot describe (a code with a description,
//!   a packed request word) are [`FieldValue::Formatted`], written by the
//!   profile's [`ValueFormat`].
//! - **Widths.** A number mapped with fewer bits than its object (other
//!   stacks do this: python-canopen maps an UNSIGNED8 as 4 bits) is read
//!   leniently from the bits mapped, sign-extended for a signed object, and
//!   flagged: [`FieldValue::Narrowed`]. Any other length than the object's
//!   size is not read: [`FieldValue::WrongWidth`]. Padding (CiA 301 dummy
//!   entries 0001h-001Fh, and objects catalogued as
//!   [`Interpretation::Padding`]) is [`FieldValue::Padding`] at any width.
//! - **Short frames.** A field that does not fit in the payload is
//!   [`FieldValue::Missing`] (CiA 301 would answer with EMCY 8210h); extra
//!   payload bytes past the mapping are counted in
//!   [`NamedFields::unmapped_bytes`].

use core::fmt;

use core::hash::Hash;

use super::mapping::{extract_bits, sign_extend, MappingEntry, PdoMapping, MAX_ENTRIES};

mod fixed;
mod flags;
use crate::od::ObjectRow;
pub use crate::od::{FlagField, FlagWord, Interpretation, Marker, Unit, ValueFormat};
pub use fixed::Fixed;
pub use flags::Flags;

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

/// A value written by a profile's [`ValueFormat`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Formatted {
    /// The format.
    pub format: &'static ValueFormat,
    /// The raw bits, zero-extended.
    pub raw: u64,
}

impl fmt::Display for Formatted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        (self.format.write)(self.raw, f)
    }
}

/// Whose object dictionary a PDO's entries name: a device's tables of
/// [`ObjectRow`], searched in order (an object's meaning belongs to
/// the device whose dictionary holds it, so a catalogue is chosen per
/// device, not per index).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Catalogue {
    name: &'static str,
    tables: &'static [&'static [ObjectRow]],
}

impl Catalogue {
    /// A catalogue named `name` that looks `index`:`sub` up in `tables`, in
    /// order.
    #[must_use]
    pub const fn new(name: &'static str, tables: &'static [&'static [ObjectRow]]) -> Self {
        Catalogue { name, tables }
    }

    /// The device it describes, in words.
    #[must_use]
    pub const fn name(self) -> &'static str {
        self.name
    }

    /// Its tables, searched in order.
    #[must_use]
    pub const fn tables(self) -> &'static [&'static [ObjectRow]] {
        self.tables
    }

    /// The catalogue entry of `index`:`sub`, if known: the first match in
    /// the first table that has one.
    #[must_use]
    pub fn lookup(self, index: u16, sub: u8) -> Option<&'static ObjectRow> {
        self.tables
            .iter()
            .find_map(|t| t.iter().find(|e| e.covers(index, sub)))
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
            return named(def.short, FieldValue::Padding);
        }
        if entry.bits < def.bits() {
            // Lenient in: the mapped bits are the low bits of the object.
            let value = match def.interpretation {
                Interpretation::Unsigned {
                    frac_bits, unit, ..
                } => i64::try_from(raw)
                    .ok()
                    .map(|v| (Fixed::new(v, frac_bits), unit)),
                Interpretation::Signed { frac_bits, unit } => {
                    Some((Fixed::new(sign_extend(raw, bits), frac_bits), unit))
                }
                _ => None,
            };
            if let Some((value, unit)) = value {
                return named(
                    def.short,
                    FieldValue::Narrowed {
                        value,
                        unit,
                        object_bits: def.bits(),
                    },
                );
            }
        }
        if def.bits() != entry.bits {
            return named(
                def.short,
                FieldValue::WrongWidth {
                    object_bits: def.bits(),
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
            Interpretation::Flags(word) => FieldValue::Flags(Flags::new(word, raw)),
            Interpretation::Formatted(format) if (format.has_value)(raw) => {
                FieldValue::Formatted(Formatted { format, raw })
            }
            Interpretation::Formatted(_) => FieldValue::NoValue,
            Interpretation::Chars => FieldValue::Chars((raw as u32).to_le_bytes()),
            Interpretation::Padding => FieldValue::Padding,
        };
        named(def.short, value)
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
    /// A value its profile writes ([`ValueFormat`]).
    Formatted(Formatted),
    /// Four characters of a packed string (zero bytes are padding).
    Chars([u8; 4]),
    /// The object's "invalid" marker ([`Marker::Invalid`]).
    Invalid,
    /// The object's "no value" marker ([`Marker::NoValue`]), or a
    /// [`ValueFormat`] that finds no value in the bits.
    NoValue,
    /// Padding bits.
    Padding,
    /// The field lies (partly) past the end of the payload.
    Missing,
    /// A number mapped with fewer bits than its object's size (a deviation
    /// from CiA 301, which maps an object whole), read from the bits mapped:
    /// the low bits of the object, sign-extended when it is signed.
    Narrowed {
        /// The value of the mapped bits.
        value: Fixed,
        /// The unit.
        unit: Option<Unit>,
        /// The object's size in bits.
        object_bits: u8,
    },
    /// The mapping gives the object a length other than its size, and the
    /// bits cannot be read as its value; the raw bits are kept in
    /// [`NamedField::raw`].
    WrongWidth {
        /// The object's size in bits.
        object_bits: u8,
    },
    /// An object the catalogue does not know; see [`NamedField::raw`].
    Raw,
}

impl FieldValue {
    /// A short name of the variant, for machine output: `scaled`,
    /// `out_of_range`, `flags`, the [`ValueFormat::kind`] of a formatted
    /// value, `chars`, `invalid`, `no_value`, `padding`, `missing`,
    /// `narrowed`, `wrong_width`, `raw`.
    #[must_use]
    pub const fn kind(&self) -> &'static str {
        match self {
            FieldValue::Scaled { .. } => "scaled",
            FieldValue::OutOfRange { .. } => "out_of_range",
            FieldValue::Flags(_) => "flags",
            FieldValue::Formatted(v) => v.format.kind,
            FieldValue::Chars(_) => "chars",
            FieldValue::Invalid => "invalid",
            FieldValue::NoValue => "no_value",
            FieldValue::Padding => "padding",
            FieldValue::Missing => "missing",
            FieldValue::Narrowed { .. } => "narrowed",
            FieldValue::WrongWidth { .. } => "wrong_width",
            FieldValue::Raw => "raw",
        }
    }

    /// The number, for scaled, out-of-range and narrowed values.
    #[must_use]
    pub const fn number(&self) -> Option<Fixed> {
        match self {
            FieldValue::Scaled { value, .. }
            | FieldValue::OutOfRange { value, .. }
            | FieldValue::Narrowed { value, .. } => Some(*value),
            _ => None,
        }
    }

    /// The unit, for scaled, out-of-range and narrowed values that have one.
    #[must_use]
    pub const fn unit(&self) -> Option<Unit> {
        match self {
            FieldValue::Scaled { unit, .. }
            | FieldValue::OutOfRange { unit, .. }
            | FieldValue::Narrowed { unit, .. } => *unit,
            _ => None,
        }
    }
}

impl fmt::Display for FieldValue {
    /// The value alone: `19.453125 A` (precision and `#` passed on to the
    /// number, see [`Fixed`]'s `Display`), a bit field in words,
    /// `invalid`, `no value`, ...
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
            FieldValue::Formatted(v) => forward(f, v),
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
            FieldValue::Narrowed {
                value,
                unit,
                object_bits,
            } => {
                forward(f, value)?;
                if let Some(u) = unit {
                    write!(f, " {u}")?;
                }
                write!(f, " (narrowed: object has {object_bits} bits)")
            }
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
    /// `82.00 V`), `2008h derate reasons: AC voltage, temperature`,
    /// `6080h charger state of charge: invalid (raw FFh)`,
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
            FieldValue::Narrowed {
                value,
                unit,
                object_bits,
            } => {
                f.write_str(" ")?;
                forward(f, value)?;
                if let Some(u) = unit {
                    write!(f, " {u}")?;
                }
                write!(
                    f,
                    " [deviates: mapped as {} bits, object has {object_bits}]",
                    e.bits
                )
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
pub(crate) mod test_support;
#[cfg(test)]
mod tests;
