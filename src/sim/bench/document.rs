//! A scenario file as a tree of keys and values, each with the line it is
//! on: what a program makes of the file's TOML (the library reads no TOML
//! itself), and what [`Script::from_document`](super::Script::from_document)
//! reads, naming the line of every unknown key and bad value.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::fmt;
use core::time::Duration;

/// A value of the file and its line (1 for the first).
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    /// The line it starts on.
    pub line: u32,
    /// The value.
    pub value: Value,
}

/// A value (TOML's kinds; dates are not used by scenario files).
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A string.
    Text(String),
    /// An integer.
    Integer(i64),
    /// A floating-point number.
    Float(f64),
    /// A boolean.
    Bool(bool),
    /// An array (an array of tables, `[[event]]`, is an array of tables).
    List(Vec<Item>),
    /// A table: its keys in the file's order, each with its value.
    Table(Vec<(String, Item)>),
}

/// What is wrong with a scenario file, and on which line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScriptError {
    /// The line (1 for the first; 0: the file as a whole).
    pub line: u32,
    /// What is wrong.
    pub message: String,
}

impl ScriptError {
    /// `message` about `line`.
    pub fn new(line: u32, message: impl Into<String>) -> Self {
        ScriptError {
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for ScriptError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            f.write_str(&self.message)
        } else {
            write!(f, "line {}: {}", self.line, self.message)
        }
    }
}

impl core::error::Error for ScriptError {}

/// A table being read: each key is taken once; [`Fields::finish`] names the
/// first key no one took.
pub(super) struct Fields<'a> {
    /// The table's own line.
    pub line: u32,
    /// Its name, for the messages.
    pub name: &'a str,
    entries: &'a [(String, Item)],
    taken: Vec<bool>,
}

impl<'a> Fields<'a> {
    /// The table `item` (an error if it is something else).
    pub fn of(name: &'a str, item: &'a Item) -> Result<Self, ScriptError> {
        match &item.value {
            Value::Table(entries) => Ok(Fields {
                line: item.line,
                name,
                entries,
                taken: alloc::vec![false; entries.len()],
            }),
            _ => Err(ScriptError::new(
                item.line,
                format!("{name} must be a table"),
            )),
        }
    }

    /// The value of `key`, if there.
    pub fn take(&mut self, key: &str) -> Option<&'a Item> {
        let i = self.entries.iter().position(|(k, _)| k == key)?;
        if let Some(t) = self.taken.get_mut(i) {
            *t = true;
        }
        self.entries.get(i).map(|(_, item)| item)
    }

    /// The value of `key`, which must be there.
    pub fn need(&mut self, key: &str) -> Result<&'a Item, ScriptError> {
        self.take(key)
            .ok_or_else(|| ScriptError::new(self.line, format!("{}: {key} is missing", self.name)))
    }

    /// An error if a key was not taken: it is not one of the table's.
    pub fn finish(self) -> Result<(), ScriptError> {
        let unknown = self.entries.iter().zip(&self.taken).find(|(_, t)| !**t);
        match unknown {
            Some(((key, item), _)) => Err(ScriptError::new(
                item.line,
                format!("unknown key {key} in {}", self.name),
            )),
            None => Ok(()),
        }
    }
}

impl Item {
    fn bad(&self, what: &str) -> ScriptError {
        let got = match &self.value {
            Value::Text(t) => format!("\"{t}\""),
            Value::Integer(i) => i.to_string(),
            Value::Float(x) => format!("{x}"),
            Value::Bool(b) => b.to_string(),
            Value::List(_) => "an array".into(),
            Value::Table(_) => "a table".into(),
        };
        ScriptError::new(self.line, format!("expected {what}, found {got}"))
    }

    /// A number (an integer or a float) within `range`.
    pub(super) fn number(
        &self,
        what: &str,
        range: core::ops::RangeInclusive<f64>,
    ) -> Result<f64, ScriptError> {
        let x = match self.value {
            Value::Integer(i) => i as f64,
            Value::Float(x) => x,
            _ => return Err(self.bad(what)),
        };
        if range.contains(&x) {
            Ok(x)
        } else {
            Err(self.bad(&format!("{what} from {} to {}", range.start(), range.end())))
        }
    }

    /// A whole number within `range` (a cell count, an id, a byte: `24.5`
    /// is no cell count).
    pub(super) fn whole(
        &self,
        what: &str,
        range: core::ops::RangeInclusive<f64>,
    ) -> Result<f64, ScriptError> {
        let x = self.number(what, range)?;
        if x.fract() == 0.0 {
            Ok(x)
        } else {
            Err(self.bad(&format!("{what} (a whole number)")))
        }
    }

    /// A string.
    pub(super) fn text(&self, what: &str) -> Result<&str, ScriptError> {
        match &self.value {
            Value::Text(t) => Ok(t),
            _ => Err(self.bad(what)),
        }
    }

    /// An array of strings.
    pub(super) fn texts(&self, what: &str) -> Result<Vec<(u32, &str)>, ScriptError> {
        let Value::List(items) = &self.value else {
            return Err(self.bad(&format!("an array of {what}")));
        };
        items
            .iter()
            .map(|i| i.text(what).map(|t| (i.line, t)))
            .collect()
    }

    /// A simulated time or duration, `h:mm:ss` (hours any number of
    /// digits, minutes and seconds two, below 60).
    pub(super) fn time(&self) -> Result<Duration, ScriptError> {
        let what = "a time h:mm:ss";
        let text = self.text(what)?;
        parse_time(text).ok_or_else(|| self.bad(what))
    }

    /// A time `h:mm:ss` no later than `max`.
    pub(super) fn time_to(&self, max: Duration) -> Result<Duration, ScriptError> {
        let t = self.time()?;
        if t <= max {
            Ok(t)
        } else {
            let s = max.as_secs();
            let (h, m, s) = (s / 3600, s / 60 % 60, s % 60);
            Err(self.bad(&format!("a time h:mm:ss up to {h}:{m:02}:{s:02}")))
        }
    }
}

/// `h:mm:ss` as a duration.
fn parse_time(text: &str) -> Option<Duration> {
    let mut parts = text.split(':');
    let (h, m, s) = (parts.next()?, parts.next()?, parts.next()?);
    let digits = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
    if parts.next().is_some() || !digits(h) || h.len() > 4 || m.len() != 2 || s.len() != 2 {
        return None;
    }
    if !digits(m) || !digits(s) {
        return None;
    }
    let (h, m, s): (u64, u64, u64) = (h.parse().ok()?, m.parse().ok()?, s.parse().ok()?);
    (m < 60 && s < 60).then(|| Duration::from_secs(h * 3600 + m * 60 + s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_h_mm_ss() {
        assert_eq!(parse_time("0:30:00"), Some(Duration::from_secs(1800)));
        assert_eq!(parse_time("12:00:05"), Some(Duration::from_secs(43_205)));
        for bad in [
            "30:00",
            "0:60:00",
            "0:5:00",
            "0:00:0x",
            "1:00:00:00",
            "-1:00:00",
            "",
        ] {
            assert_eq!(parse_time(bad), None, "{bad}");
        }
    }
}
