//! Bit-field objects in words: a [`FlagWord`] describes the fields of one
//! object as static data, and [`Flags`] is a raw value read with it.

use core::fmt;

use crate::od::{FlagField, FlagWord};

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
