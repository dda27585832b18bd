//! Naming: the names, units and meanings of objects and their values. An
//! object transferred by SDO is named by the CiA 301 communication objects
//! (1000h-1FFFh, [`describe_comm_object`]) on every node, and by the
//! catalogue of the node's role past them: CiA 418 on the battery node,
//! the CiA 419 objects on a charger, Delta-Q's then CiA 418's on a Delta-Q
//! charger; a node without a role gets no profile names ([`describe`]).

use std::prelude::rust_2021::*;

use crate::cia418::BATTERY_MODULE_CATALOGUE;
use crate::cia419::CHARGER_CATALOGUE as CIA419_CATALOGUE;
use crate::deltaq::CHARGER_CATALOGUE as DELTAQ_CATALOGUE;
use crate::pdo::{Catalogue, FieldValue, MappingEntry};

pub use super::comm_objects::{describe as describe_comm_object, Context};
use super::sdo_value::uint;
pub use super::sdo_value::{quote, unsigned, Described, Role, Value, NO_CATALOGUE};

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
    let ctx = Context {
        role,
        deltaq_on_bus,
        catalogue,
    };
    describe_comm_object(index, sub, bytes, ctx, exact)
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
