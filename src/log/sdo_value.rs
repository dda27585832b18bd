//! What the name and meaning of an object transferred by SDO is made of
//! ([`Described`], [`Value`]), the role of its node ([`Role`]) and the
//! readings every table shares ([`unsigned`], [`quote`]); the naming
//! itself is [`naming::describe`](super::naming::describe).

use crate::pdo::Catalogue;
use std::prelude::rust_2021::*;

/// The objects of a node with no role: CiA 301 names nothing past 1FFFh.
pub const NO_CATALOGUE: Catalogue = Catalogue::new("a device without a known profile", &[]);

/// What a value is, for JSON.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// No value: unknown object or wrong size.
    None,
    /// A number, as an exact JSON number literal.
    Number(String),
    /// Text (a visible string, or a value only words can say).
    Text(String),
}

/// The name and meaning of one transferred value.
#[derive(Clone, Debug)]
pub struct Described {
    /// The object's name, where it is known.
    pub name: Option<String>,
    /// The value.
    pub value: Value,
    /// The unit's symbol.
    pub unit: Option<&'static str>,
    /// Words, e.g. `4000 ms`, `charger enabled`.
    pub meaning: Option<String>,
    /// The value is a visible string: words print it quoted instead of hex.
    pub string: bool,
}

impl Described {
    /// Named `name`, with no value.
    pub fn named(name: impl Into<String>) -> Self {
        Described {
            name: Some(name.into()),
            value: Value::None,
            unit: None,
            meaning: None,
            string: false,
        }
    }

    fn number(mut self, n: u64, meaning: String) -> Self {
        self.value = Value::Number(n.to_string());
        self.meaning = Some(meaning);
        self
    }
}

/// The role of the node the object belongs to.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Role {
    /// A charger with Delta-Q evidence.
    DeltaQCharger,
    /// A CiA 419 charger (no Delta-Q evidence).
    Charger,
    /// The CiA 418 battery module.
    Battery,
    /// No role known.
    Other,
}

/// Quotes a visible string: printable ASCII as is, `"` and `\` escaped,
/// everything else as `\xNN`.
pub fn quote(bytes: &[u8]) -> String {
    let mut s = String::from("\"");
    for &b in bytes {
        match b {
            b'"' | b'\\' => {
                s.push('\\');
                s.push(char::from(b));
            }
            0x20..=0x7E => s.push(char::from(b)),
            _ => s.push_str(&format!("\\x{b:02X}")),
        }
    }
    s.push('"');
    s
}

/// Little-endian unsigned of exactly `n` bytes; with `exact` false (an
/// expedited s = 0 value, "up to 4 bytes") a longer value is cut to `n`.
pub(super) fn uint(bytes: &[u8], n: usize, exact: bool) -> Result<u64, String> {
    let b = match bytes.get(..n) {
        Some(b) if bytes.len() == n || !exact => b,
        _ => return Err(format!("{} bytes, the object has {n}", bytes.len())),
    };
    Ok(b.iter().rev().fold(0, |acc, &x| acc << 8 | u64::from(x)))
}

/// The value of a `n`-byte unsigned object with its meaning in words, or the
/// size problem as the meaning.
pub fn unsigned(
    d: Described,
    bytes: &[u8],
    n: usize,
    exact: bool,
    meaning: impl Fn(u64) -> String,
) -> Described {
    match uint(bytes, n, exact) {
        Ok(v) => d.number(v, meaning(v)),
        Err(e) => Described {
            meaning: Some(e),
            ..d
        },
    }
}
