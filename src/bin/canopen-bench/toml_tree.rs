//! A scenario file's TOML as the library's tree of values, each with the
//! line it is on (`sim::bench::Item`): the library reads the script from it.

use canopen_codec::sim::bench::{Item, ScriptError, Value};
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// The tree of `text`, or the TOML syntax error with its line.
pub fn read(text: &str) -> Result<Item, ScriptError> {
    let root = DeTable::parse(text).map_err(|e| ScriptError::new(0, e.to_string().trim_end()))?;
    let line = |at: usize| {
        let before = text.as_bytes().get(..at).unwrap_or(text.as_bytes());
        1 + before.iter().filter(|b| **b == b'\n').count() as u32
    };
    Ok(Item {
        line: 1,
        value: table(root.get_ref(), &line)?,
    })
}

fn table(t: &DeTable<'_>, line: &dyn Fn(usize) -> u32) -> Result<Value, ScriptError> {
    let entries = t
        .iter()
        .map(|(k, v)| Ok((k.get_ref().to_string(), item(v, line)?)));
    Ok(Value::Table(entries.collect::<Result<_, ScriptError>>()?))
}

fn item(v: &Spanned<DeValue<'_>>, line: &dyn Fn(usize) -> u32) -> Result<Item, ScriptError> {
    let at = line(v.span().start);
    let bad = |what: &str| ScriptError::new(at, format!("{what} out of range"));
    let value = match v.get_ref() {
        DeValue::String(s) => Value::Text(s.to_string()),
        DeValue::Integer(i) => {
            Value::Integer(i64::from_str_radix(i.as_str(), i.radix()).map_err(|_| bad("integer"))?)
        }
        DeValue::Float(f) => Value::Float(f.as_str().parse().map_err(|_| bad("float"))?),
        DeValue::Boolean(b) => Value::Bool(*b),
        DeValue::Datetime(_) => return Err(ScriptError::new(at, "a date has no use here")),
        DeValue::Array(a) => {
            Value::List(a.iter().map(|x| item(x, line)).collect::<Result<_, _>>()?)
        }
        DeValue::Table(t) => table(t, line)?,
    };
    Ok(Item { line: at, value })
}
