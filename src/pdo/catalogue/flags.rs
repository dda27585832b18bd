//! Bit-field objects in words: a [`FlagWord`] describes the fields of one
//! object as static data, and [`Flags`] is a raw value read with it.

use core::fmt;

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

/// The decoded value of a bit-field object; `Display` says it in words.
///
/// ```
/// use canopen_codec::pdo::{FlagField, FlagWord, Flags};
/// const WORD: FlagWord = FlagWord {
///     fields: &[
///         FlagField::Bit { mask: 0x01, set: "ready", clear: Some("not ready") },
///         FlagField::Choice { mask: 0x30, values: &[(0, None), (1, Some("slow"))], unknown: "speed" },
///         FlagField::OtherBits { mask: 0xFF },
///     ],
///     when_empty: None,
/// };
/// assert_eq!(Flags::new(&WORD, 0x11).to_string(), "ready, slow");
/// assert_eq!(Flags::new(&WORD, 0xA0).to_string(), "not ready, speed 2, other bits 80h");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Flags {
    word: &'static FlagWord,
    raw: u64,
}

impl Flags {
    /// `raw` read with `word`.
    #[must_use]
    pub const fn new(word: &'static FlagWord, raw: u64) -> Self {
        Flags { word, raw }
    }

    /// The raw bits.
    #[must_use]
    pub const fn raw(self) -> u64 {
        self.raw
    }

    /// The description they are read with.
    #[must_use]
    pub const fn word(self) -> &'static FlagWord {
        self.word
    }

    /// True if every bit of `mask` is set.
    #[must_use]
    pub const fn contains(self, mask: u64) -> bool {
        self.raw & mask == mask
    }
}

/// Writes comma-separated items.
struct List<'a, 'b> {
    f: &'a mut fmt::Formatter<'b>,
    empty: bool,
}

impl List<'_, '_> {
    fn item(&mut self, args: fmt::Arguments<'_>) -> fmt::Result {
        if !self.empty {
            self.f.write_str(", ")?;
        }
        self.empty = false;
        self.f.write_fmt(args)
    }
}

impl fmt::Display for Flags {
    /// The fields in the word's order, comma-separated: `ready to charge`,
    /// `AC present, charger enabled, override external (BMS)`, ...; unknown
    /// bits as `other bits 80h`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut l = List { f, empty: true };
        let raw = self.raw;
        for field in self.word.fields {
            match *field {
                FlagField::Bit { mask, set, clear } => {
                    if raw & mask == mask && mask != 0 {
                        l.item(format_args!("{set}"))?;
                    } else if let Some(clear) = clear {
                        l.item(format_args!("{clear}"))?;
                    }
                }
                FlagField::Choice {
                    mask,
                    values,
                    unknown,
                } => {
                    let value = (raw & mask) >> (mask.trailing_zeros() % 64);
                    match values.iter().find(|&&(v, _)| v == value) {
                        Some(&(_, Some(words))) => l.item(format_args!("{words}"))?,
                        Some(&(_, None)) => {}
                        None => l.item(format_args!("{unknown} {value}"))?,
                    }
                }
                FlagField::OtherBits { mask } => {
                    let rest = raw & mask & !self.word.known_bits();
                    if rest != 0 {
                        l.item(format_args!("other bits {rest:02X}h"))?;
                    }
                }
            }
        }
        match self.word.when_empty {
            Some(words) if l.empty => l.f.write_str(words),
            _ => Ok(()),
        }
    }
}
