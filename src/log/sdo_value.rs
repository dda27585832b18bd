//! The name and meaning of an object transferred by SDO: the CiA 301
//! communication objects (1000h-1FFFh, in `comm_objects`) on every node,
//! profile objects from the catalogue of the node's role: CiA 418 on the
//! battery node, the CiA 419 objects on a charger, Delta-Q's then CiA 418's
//! on a Delta-Q charger; a node without a role gets no profile names.

use crate::cia418::BATTERY_MODULE_CATALOGUE;
use crate::cia419::CHARGER_CATALOGUE as CIA419_CATALOGUE;
use crate::deltaq::CHARGER_CATALOGUE as DELTAQ_CATALOGUE;
use crate::pdo::{Catalogue, FieldValue, MappingEntry};
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
fn uint(bytes: &[u8], n: usize, exact: bool) -> Result<u64, String> {
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

/// Names and interprets `bytes` of `index`:`sub` on a node with `role`
/// (`deltaq_on_bus`: a Delta-Q charger is known to be on the bus; `eds`:
/// the catalogue built from the node's EDS, its role's tables first, which
/// then names the node's objects). `exact` is false for an expedited value
/// with s = 0.
pub fn describe(
    index: u16,
    sub: u8,
    bytes: &[u8],
    role: Role,
    deltaq_on_bus: bool,
    eds: Option<Catalogue>,
    exact: bool,
) -> Described {
    let catalogue = eds.unwrap_or(match role {
        Role::DeltaQCharger => DELTAQ_CATALOGUE,
        Role::Charger => CIA419_CATALOGUE,
        Role::Battery => BATTERY_MODULE_CATALOGUE,
        Role::Other => NO_CATALOGUE,
    });
    let ctx = crate::log::comm_objects::Context {
        role,
        deltaq_on_bus,
        catalogue,
    };
    crate::log::comm_objects::describe(index, sub, bytes, ctx, exact)
        .unwrap_or_else(|| profile(index, sub, bytes, catalogue, exact))
}

/// An object of the node's catalogue (CiA 418, Delta-Q), or bytes only.
fn profile(index: u16, sub: u8, bytes: &[u8], catalogue: Catalogue, exact: bool) -> Described {
    let Some(def) = catalogue.lookup(index, sub) else {
        return Described {
            name: None,
            value: Value::None,
            unit: None,
            meaning: None,
            string: false,
        };
    };
    let d = Described::named(def.short);
    // A BOOLEAN (1 bit in a PDO) travels by SDO as one byte.
    let raw = match uint(bytes, usize::from(def.bits().div_ceil(8)), exact) {
        Ok(raw) => raw,
        Err(e) => {
            return Described {
                meaning: Some(e),
                ..d
            }
        }
    };
    let field = catalogue.interpret(MappingEntry::new(index, sub, def.bits()), raw);
    let digits = usize::from(def.bits()).div_ceil(4);
    let (value, meaning) = match &field.value {
        FieldValue::Scaled { value, .. } | FieldValue::OutOfRange { value, .. } => (
            Value::Number(value.to_string()),
            format!("{:#.2}", field.value),
        ),
        v @ (FieldValue::Invalid | FieldValue::NoValue) => {
            (Value::None, format!("{v} (raw {raw:0digits$X}h)"))
        }
        v @ FieldValue::Chars(chars) => (
            Value::Text(
                chars
                    .iter()
                    .filter(|&&c| c != 0)
                    .map(|&c| char::from(c))
                    .collect(),
            ),
            v.to_string(),
        ),
        FieldValue::Raw
        | FieldValue::Padding
        | FieldValue::Missing
        | FieldValue::WrongWidth { .. } => (Value::None, format!("raw {raw:0digits$X}h")),
        v => (Value::Text(v.to_string()), v.to_string()),
    };
    Described {
        value,
        unit: field.value.unit().map(|u| u.symbol()),
        meaning: Some(meaning),
        ..d
    }
}
