//! EDS and DCF device descriptions (CiA 306, "Electronic data sheet
//! specification for CANopen"), read into an owned model (feature `alloc`).
//!
//! An EDS is INI-like text: `[Section]` headers and `Key=Value` lines.
//! [`parse`] (text) and [`parse_bytes`] (bytes that may hold non-UTF-8
//! names, a UTF-8 byte order mark and CRLF line ends) read it into an
//! [`Eds`]: the file and device information, the dummy usage, the comments,
//! the three object lists, every object `[XXXX]` with its sub-objects
//! `[XXXXsubN]`, the DCF commissioning section, and every other section and
//! key as it was written (unknown ones are kept, never an error).
//!
//! The parser is written by hand: no maintained INI crate reads these files
//! in a `no_std + alloc` build with their quirks (comments after values,
//! two spellings of `[DeviceComissioning]`, `CompactSubObj` arrays, section
//! names in any case and without padding).
//!
//! **Lenient in, strict out.** What real files get wrong but that can still
//! be read (a `SubNumber` that disagrees with the sub-objects, a listed
//! object that is missing, an unknown `AccessType`, a duplicate key) is
//! read and recorded as a [`Warning`] naming the line; only text that
//! cannot be read as a device description is an [`Error`], which also names
//! the line. No input makes the parser panic.
//!
//! ```
//! use canopen_codec::eds::{parse, DataType};
//! let eds = parse("[1017]\nParameterName=Producer heartbeat time\n\
//!                  DataType=0x0006\nAccessType=rw\nDefaultValue=1000 ; ms\n").unwrap();
//! let hb = &eds.objects[&0x1017];
//! assert_eq!(hb.entry.data_type, Some(DataType::Unsigned16));
//! assert_eq!(hb.entry.default_value.as_deref(), Some("1000"));
//! assert_eq!(eds.name(0x1017, 0), Some("Producer heartbeat time"));
//! ```

use alloc::collections::BTreeMap;
use alloc::string::String;
use alloc::vec::Vec;

mod dcf;
mod describe;
mod dictionary;
mod info;
mod parse;
mod types;
mod value;
mod write;

pub use dcf::DcfError;
pub use describe::{Described, DeviceHeader, ObjectDescription, ObjectNames, SubDescription};
pub use dictionary::{EdsDictionary, PdoDescription, Unserved, UnservedReason, MAX_VARIABLE_LEN};
pub use info::{Commissioning, DeviceInfo, FileInfo};
pub use parse::{parse, parse_bytes};
pub use types::{AccessType, DataType, ObjectType};
pub use value::{encode_value, eval_int, parse_int, uses_node_id, ValueError};
pub use write::write;

/// Keys as written, in file order (later duplicates win in [`Keys::get`]).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Keys(pub Vec<(String, String)>);

impl Keys {
    /// The value of `key`, any case.
    #[must_use]
    pub fn get(&self, key: &str) -> Option<&str> {
        self.0
            .iter()
            .rev()
            .find(|(k, _)| k.eq_ignore_ascii_case(key))
            .map(|(_, v)| v.as_str())
    }

    /// The number of keys.
    #[must_use]
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// True if there is no key.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// A section the model does not interpret, kept as written.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Section {
    /// The name between the brackets.
    pub name: String,
    /// Its line number (from 1).
    pub line: usize,
    /// Its keys.
    pub keys: Keys,
}

/// One object section `[XXXX]` or sub-object section `[XXXXsubN]` (CiA 306,
/// section 4.6 "Object descriptions"). Numbers that shape the dictionary
/// are read; values are kept as text (see [`encode_value`]).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Entry {
    /// The line of the section header (from 1); 0 for a generated entry.
    pub line: usize,
    /// `ParameterName`.
    pub name: String,
    /// `ObjectType` ([`ObjectType::Var`] when absent).
    pub object_type: ObjectType,
    /// `DataType` (hex or decimal).
    pub data_type: Option<DataType>,
    /// `AccessType`.
    pub access: Option<AccessType>,
    /// `PDOMapping`.
    pub pdo_mapping: bool,
    /// `DefaultValue`, as written (may be empty or a `$NODEID` sum).
    pub default_value: Option<String>,
    /// `ParameterValue` (DCF), as written.
    pub parameter_value: Option<String>,
    /// `Denotation` (DCF).
    pub denotation: Option<String>,
    /// `LowLimit`, as written (see [`eval_int`]).
    pub low_limit: Option<String>,
    /// `HighLimit`, as written.
    pub high_limit: Option<String>,
    /// `ObjFlags`.
    pub obj_flags: Option<u32>,
    /// `SubNumber`: the number of sub-objects.
    pub sub_number: Option<u16>,
    /// `CompactSubObj`: the number of sub-objects 1..=n described by this
    /// one section.
    pub compact_sub_obj: Option<u8>,
    /// Every other key, as written.
    pub other: Keys,
}

impl Entry {
    /// The value a device starts with: `ParameterValue` if given (DCF),
    /// else `DefaultValue`. An empty `ParameterValue=` (common in DCFs:
    /// a tool writes the key for every entry) gives no value for a number,
    /// so it falls back to `DefaultValue` as python-canopen does; for a
    /// string or domain an empty value is the empty string.
    ///
    /// ```
    /// use canopen_codec::eds::{DataType, Entry};
    /// let mut e = Entry::default();
    /// e.data_type = Some(DataType::Unsigned16);
    /// e.default_value = Some("500".into());
    /// e.parameter_value = Some(" ".into());
    /// assert_eq!(e.value(), Some("500"));
    /// e.parameter_value = Some("1000".into());
    /// assert_eq!(e.value(), Some("1000"));
    /// e.data_type = Some(DataType::VisibleString);
    /// e.parameter_value = Some("".into());
    /// assert_eq!(e.value(), Some(""));
    /// ```
    #[must_use]
    pub fn value(&self) -> Option<&str> {
        let text_like = matches!(
            self.data_type,
            Some(
                DataType::VisibleString
                    | DataType::OctetString
                    | DataType::UnicodeString
                    | DataType::Domain
            )
        );
        self.parameter_value
            .as_deref()
            .filter(|v| text_like || !v.trim().is_empty())
            .or(self.default_value.as_deref())
    }
}

/// An object: its own section and its sub-objects by sub-index.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Object {
    /// The index.
    pub index: u16,
    /// The `[XXXX]` section.
    pub entry: Entry,
    /// The `[XXXXsubN]` sections, or the sub-objects a `CompactSubObj`
    /// generates (sub-index 0 and 1..=n).
    pub subs: BTreeMap<u8, Entry>,
}

/// A device description read from an EDS or DCF.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Eds {
    /// `[FileInfo]`.
    pub file_info: FileInfo,
    /// `[DeviceInfo]`.
    pub device_info: DeviceInfo,
    /// `[DummyUsage]`: the dummy data type indexes and whether each may be
    /// mapped (`Dummy0005=1`).
    pub dummy_usage: BTreeMap<u16, bool>,
    /// `[Comments]`: the lines `Line1..=LineN`.
    pub comments: Vec<String>,
    /// `[MandatoryObjects]`, in list order.
    pub mandatory: Vec<u16>,
    /// `[OptionalObjects]`, in list order.
    pub optional: Vec<u16>,
    /// `[ManufacturerObjects]`, in list order.
    pub manufacturer: Vec<u16>,
    /// Every object, by index.
    pub objects: BTreeMap<u16, Object>,
    /// `[DeviceComissioning]` (DCF).
    pub commissioning: Option<Commissioning>,
    /// Every section not interpreted above, in file order.
    pub other_sections: Vec<Section>,
    /// What the file got wrong but could still be read.
    pub warnings: Vec<Warning>,
}

impl Eds {
    /// The `ParameterName` of `index`/`sub`: the sub-object's, or for a VAR
    /// (which has no sub-objects) the object's at sub-index 0.
    #[must_use]
    pub fn name(&self, index: u16, sub: u8) -> Option<&str> {
        let o = self.objects.get(&index)?;
        match o.subs.get(&sub) {
            Some(e) => Some(e.name.as_str()),
            None if sub == 0 && o.subs.is_empty() => Some(o.entry.name.as_str()),
            None => None,
        }
    }

    /// Forgets where things were read from: every line number becomes 0
    /// and the warnings are dropped. Two texts that describe the same
    /// device (a file and its [`write()`] output) then compare equal.
    pub fn clear_positions(&mut self) {
        self.warnings.clear();
        for s in &mut self.other_sections {
            s.line = 0;
        }
        for o in self.objects.values_mut() {
            o.entry.line = 0;
            for e in o.subs.values_mut() {
                e.line = 0;
            }
        }
    }

    /// The entry that describes the value at `index`/`sub` (as [`name`](Self::name)).
    #[must_use]
    pub fn entry(&self, index: u16, sub: u8) -> Option<&Entry> {
        let o = self.objects.get(&index)?;
        match o.subs.get(&sub) {
            Some(e) => Some(e),
            None if sub == 0 && o.subs.is_empty() => Some(&o.entry),
            None => None,
        }
    }
}

/// A line a device description could not be read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A `[` with no closing `]`.
    #[error("line {line}: section header without ']'")]
    UnterminatedSection {
        /// The line (from 1).
        line: usize,
    },
    /// A line that is neither a header, a comment nor `Key=Value`.
    #[error("line {line}: neither a section, a comment nor Key=Value")]
    NotAKeyValue {
        /// The line (from 1).
        line: usize,
    },
    /// A key that must hold a number (or a list entry an index) does not.
    #[error("line {line}: {key:?} is not a valid number")]
    InvalidNumber {
        /// The line (from 1).
        line: usize,
        /// Which key.
        key: Key,
    },
}

/// The keys whose values the parser reads as numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Key {
    /// `ObjectType`.
    ObjectType,
    /// `DataType`.
    DataType,
    /// `PDOMapping`.
    PdoMapping,
    /// `SubNumber`.
    SubNumber,
    /// `CompactSubObj`.
    CompactSubObj,
    /// `ObjFlags`.
    ObjFlags,
    /// An entry of an object list (`1=0x1000`).
    ListEntry,
}

/// A deviation from CiA 306 that the parser read past.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Warning {
    /// The line (from 1); 0 when it concerns the whole file.
    pub line: usize,
    /// What was wrong.
    pub kind: WarningKind,
}

/// What a [`Warning`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum WarningKind {
    /// The line is not UTF-8; invalid bytes were replaced by U+FFFD.
    NotUtf8,
    /// A `Key=Value` before any section header (ignored).
    KeyOutsideSection,
    /// A key given twice in one section (the last one counts).
    DuplicateKey,
    /// A section given twice (its keys are merged, the last value counts).
    DuplicateSection,
    /// An `AccessType` that is none of the CiA 306 keywords (left unset).
    UnknownAccessType,
    /// A sub-object section whose object is not described (kept in
    /// [`Eds::other_sections`]).
    OrphanSubObject {
        /// The index.
        index: u16,
    },
    /// A listed object with no section.
    ListedObjectMissing {
        /// The index.
        index: u16,
    },
    /// An object list whose `SupportedObjects` disagrees with its entries.
    ListCountMismatch {
        /// `SupportedObjects`.
        declared: u16,
        /// Entries found.
        found: usize,
    },
    /// `SubNumber` disagrees with the sub-objects described.
    SubNumberMismatch {
        /// The index.
        index: u16,
        /// `SubNumber`.
        declared: u16,
        /// Sub-objects found.
        found: usize,
    },
    /// A `LowLimit` or `HighLimit` that is not a number.
    InvalidLimit,
}

impl core::fmt::Display for Warning {
    /// The line and the deviation in words:
    /// `line 1042: 3050h has SubNumber=7 but 3 sub-objects are described`.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.line != 0 {
            write!(f, "line {}: ", self.line)?;
        }
        write!(f, "{}", self.kind)
    }
}

impl core::fmt::Display for WarningKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            WarningKind::NotUtf8 => f.write_str("not UTF-8 (invalid bytes read as U+FFFD)"),
            WarningKind::KeyOutsideSection => {
                f.write_str("Key=Value before any section header (ignored)")
            }
            WarningKind::DuplicateKey => {
                f.write_str("a key given twice in one section (the last one counts)")
            }
            WarningKind::DuplicateSection => {
                f.write_str("a section given twice (its keys merged, the last value counts)")
            }
            WarningKind::UnknownAccessType => f.write_str(
                "AccessType is none of const, ro, wo, rw, rwr, rww (left unset)",
            ),
            WarningKind::OrphanSubObject { index } => write!(
                f,
                "a sub-object of {index:04X}h, which has no [{index:04X}] section (kept as an unknown section)"
            ),
            WarningKind::ListedObjectMissing { index } => {
                write!(f, "{index:04X}h is in an object list but has no section")
            }
            WarningKind::ListCountMismatch { declared, found } => write!(
                f,
                "the object list says SupportedObjects={declared} but has {found} {}",
                if found == 1 { "entry" } else { "entries" }
            ),
            WarningKind::SubNumberMismatch {
                index,
                declared,
                found,
            } => write!(
                f,
                "{index:04X}h has SubNumber={declared} but {found} {} described",
                if found == 1 { "sub-object is" } else { "sub-objects are" }
            ),
            WarningKind::InvalidLimit => {
                f.write_str("a LowLimit or HighLimit that is not a number (kept as text)")
            }
        }
    }
}

#[cfg(test)]
mod parse_tests;
