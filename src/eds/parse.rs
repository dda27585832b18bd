//! The hand-written reader: lines, sections, then the model.

use alloc::collections::BTreeMap;
use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;

use super::value::{eval_int, parse_int};
use super::{
    AccessType, Commissioning, DataType, DeviceInfo, Eds, Entry, Error, FileInfo, Key, Keys,
    Object, ObjectType, Section, Warning, WarningKind,
};

/// One `Key=Value` line: key, value (comment stripped, trimmed), line.
type RawKey<'a> = (&'a str, &'a str, usize);

/// A section as read, before interpretation.
struct RawSection<'a> {
    name: &'a str,
    line: usize,
    keys: Vec<RawKey<'a>>,
}

/// Reads an EDS or DCF from text. A leading byte order mark and CRLF line
/// ends are accepted.
pub fn parse(text: &str) -> Result<Eds, Error> {
    // A byte order mark at the start (one) is not part of the first line.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut warnings = Vec::new();
    let sections = split_sections(text, &mut warnings)?;
    build(&sections, warnings)
}

/// Reads an EDS or DCF from bytes: a UTF-8 byte order mark is skipped, and
/// a line that is not UTF-8 (a name in Latin-1, say) is read with its
/// invalid bytes replaced by U+FFFD and a [`WarningKind::NotUtf8`].
pub fn parse_bytes(bytes: &[u8]) -> Result<Eds, Error> {
    // UTF-8 text reads exactly as `parse` reads it (which skips the mark).
    if let Ok(text) = core::str::from_utf8(bytes) {
        return parse(text);
    }
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let mut warnings = Vec::new();
    let mut text = String::with_capacity(bytes.len());
    for (n, line) in bytes.split(|b| *b == b'\n').enumerate() {
        if n > 0 {
            text.push('\n');
        }
        match core::str::from_utf8(line) {
            Ok(s) => text.push_str(s),
            Err(_) => {
                text.push_str(&String::from_utf8_lossy(line));
                warnings.push(Warning {
                    line: n.saturating_add(1),
                    kind: WarningKind::NotUtf8,
                });
            }
        }
    }
    let sections = split_sections(&text, &mut warnings)?;
    build(&sections, warnings)
}

/// Cuts a value at a `;` comment that follows white space, and trims it.
fn strip_comment(v: &str) -> &str {
    let mut prev_space = false;
    for (i, c) in v.char_indices() {
        if c == ';' && prev_space {
            return v.get(..i).unwrap_or(v).trim();
        }
        prev_space = c.is_whitespace();
    }
    v.trim()
}

fn split_sections<'a>(
    text: &'a str,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<RawSection<'a>>, Error> {
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    let mut sections: Vec<RawSection<'a>> = Vec::new();
    // Lower-cased name to position, to merge a section given twice.
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    let mut current: Option<usize> = None;
    for (n, raw) in text.split('\n').enumerate() {
        let line = n.saturating_add(1);
        let l = raw.trim();
        if l.is_empty() || l.starts_with(';') {
            continue;
        }
        if let Some(rest) = l.strip_prefix('[') {
            let (name, _) = rest
                .split_once(']')
                .ok_or(Error::UnterminatedSection { line })?;
            let name = name.trim();
            let lower = name.to_ascii_lowercase();
            if let Some(&at) = seen.get(&lower) {
                warnings.push(Warning {
                    line,
                    kind: WarningKind::DuplicateSection,
                });
                current = Some(at);
            } else {
                seen.insert(lower, sections.len());
                current = Some(sections.len());
                sections.push(RawSection {
                    name,
                    line,
                    keys: Vec::new(),
                });
            }
            continue;
        }
        let (k, v) = l.split_once('=').ok_or(Error::NotAKeyValue { line })?;
        let k = k.trim();
        if k.is_empty() {
            return Err(Error::NotAKeyValue { line });
        }
        let Some(section) = current.and_then(|i| sections.get_mut(i)) else {
            warnings.push(Warning {
                line,
                kind: WarningKind::KeyOutsideSection,
            });
            continue;
        };
        if section
            .keys
            .iter()
            .any(|(old, _, _)| old.eq_ignore_ascii_case(k))
        {
            warnings.push(Warning {
                line,
                kind: WarningKind::DuplicateKey,
            });
        }
        section.keys.push((k, strip_comment(v), line));
    }
    Ok(sections)
}

/// What a section name says it is.
enum Kind {
    FileInfo,
    DeviceInfo,
    DummyUsage,
    Comments,
    Mandatory,
    Optional,
    Manufacturer,
    Commissioning,
    Object(u16),
    Sub(u16, u8),
    Names(u16),
    Values(u16),
    Denotations(u16),
    Other,
}

/// 1 to `max` hex digits, any case.
fn hex(s: &str, max: usize) -> Option<u32> {
    if s.is_empty() || s.len() > max || !s.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u32::from_str_radix(s, 16).ok()
}

fn hex_index(s: &str) -> Option<u16> {
    hex(s, 4).and_then(|n| u16::try_from(n).ok())
}

fn classify(name: &str) -> Kind {
    let lower = name.to_ascii_lowercase();
    match lower.as_str() {
        "fileinfo" => return Kind::FileInfo,
        "deviceinfo" => return Kind::DeviceInfo,
        "dummyusage" => return Kind::DummyUsage,
        "comments" => return Kind::Comments,
        "mandatoryobjects" => return Kind::Mandatory,
        "optionalobjects" => return Kind::Optional,
        "manufacturerobjects" => return Kind::Manufacturer,
        "devicecommissioning" | "devicecomissioning" => return Kind::Commissioning,
        _ => {}
    }
    if let Some(i) = hex_index(&lower) {
        return Kind::Object(i);
    }
    if let Some((i, s)) = lower.split_once("sub") {
        // A sub-index is hex (up to two digits, leading zeros allowed).
        let sub = s.trim_start_matches('0');
        let sub = if sub.is_empty() && !s.is_empty() {
            "0"
        } else {
            sub
        };
        if let (Some(i), Some(s)) = (hex_index(i), hex(sub, 2)) {
            if let Ok(s) = u8::try_from(s) {
                return Kind::Sub(i, s);
            }
        }
    }
    let suffixed = |suffix: &str| lower.strip_suffix(suffix).and_then(hex_index);
    if let Some(i) = suffixed("name") {
        return Kind::Names(i);
    }
    if let Some(i) = suffixed("value") {
        return Kind::Values(i);
    }
    if let Some(i) = suffixed("denotation") {
        return Kind::Denotations(i);
    }
    Kind::Other
}

fn keys_of(sec: &RawSection<'_>) -> Keys {
    Keys(
        sec.keys
            .iter()
            .map(|(k, v, _)| (k.to_string(), v.to_string()))
            .collect(),
    )
}

/// A non-negative number that fits `T`; an empty value is absent.
fn number<T: TryFrom<i128>>(v: &str, line: usize, key: Key) -> Result<Option<T>, Error> {
    if v.is_empty() {
        return Ok(None);
    }
    parse_int(v)
        .and_then(|n| T::try_from(n).ok())
        .map(Some)
        .ok_or(Error::InvalidNumber { line, key })
}

/// True if a limit reads as an integer (with `$NODEID` for any node) or a
/// real number.
fn limit_ok(v: &str) -> bool {
    eval_int(v, Some(1)).is_ok() || v.parse::<f64>().is_ok()
}

fn read_entry(sec: &RawSection<'_>, warnings: &mut Vec<Warning>) -> Result<Entry, Error> {
    let mut e = Entry {
        line: sec.line,
        ..Entry::default()
    };
    for &(k, v, line) in &sec.keys {
        let is = |name: &str| k.eq_ignore_ascii_case(name);
        if is("ParameterName") {
            e.name = v.to_string();
        } else if is("ObjectType") {
            if let Some(t) = number::<u8>(v, line, Key::ObjectType)? {
                e.object_type = ObjectType::from(t);
            }
        } else if is("DataType") {
            e.data_type = number::<u16>(v, line, Key::DataType)?.map(DataType::from);
        } else if is("AccessType") {
            e.access = AccessType::parse(v);
            if e.access.is_none() {
                warnings.push(Warning {
                    line,
                    kind: WarningKind::UnknownAccessType,
                });
            }
        } else if is("PDOMapping") {
            e.pdo_mapping = number::<u8>(v, line, Key::PdoMapping)?.is_some_and(|n| n != 0);
        } else if is("DefaultValue") {
            e.default_value = Some(v.to_string());
        } else if is("ParameterValue") {
            e.parameter_value = Some(v.to_string());
        } else if is("Denotation") {
            e.denotation = Some(v.to_string());
        } else if is("LowLimit") || is("HighLimit") {
            if v.is_empty() {
                continue;
            }
            if !limit_ok(v) {
                warnings.push(Warning {
                    line,
                    kind: WarningKind::InvalidLimit,
                });
            }
            let slot = if is("LowLimit") {
                &mut e.low_limit
            } else {
                &mut e.high_limit
            };
            *slot = Some(v.to_string());
        } else if is("ObjFlags") {
            e.obj_flags = number(v, line, Key::ObjFlags)?;
        } else if is("SubNumber") {
            e.sub_number = number(v, line, Key::SubNumber)?;
        } else if is("CompactSubObj") {
            e.compact_sub_obj = number(v, line, Key::CompactSubObj)?;
        } else {
            e.other.0.push((k.to_string(), v.to_string()));
        }
    }
    Ok(e)
}

/// The numbered entries of an object list or a name/value section
/// (`1=...`, `2=...`), by number.
fn numbered<'a>(sec: &RawSection<'a>) -> BTreeMap<u16, (&'a str, usize)> {
    sec.keys
        .iter()
        .filter_map(|&(k, v, line)| Some((k.parse::<u16>().ok()?, (v, line))))
        .collect()
}

fn object_list(sec: &RawSection<'_>, warnings: &mut Vec<Warning>) -> Result<Vec<u16>, Error> {
    let entries = numbered(sec);
    let list = entries
        .values()
        .map(|&(v, line)| {
            parse_int(v)
                .and_then(|n| u16::try_from(n).ok())
                .ok_or(Error::InvalidNumber {
                    line,
                    key: Key::ListEntry,
                })
        })
        .collect::<Result<Vec<u16>, Error>>()?;
    let declared = sec
        .keys
        .iter()
        .rev()
        .find(|(k, _, _)| k.eq_ignore_ascii_case("SupportedObjects"))
        .and_then(|(_, v, _)| parse_int(v).and_then(|n| u16::try_from(n).ok()));
    if let Some(declared) = declared {
        if usize::from(declared) != list.len() {
            warnings.push(Warning {
                line: sec.line,
                kind: WarningKind::ListCountMismatch {
                    declared,
                    found: list.len(),
                },
            });
        }
    }
    Ok(list)
}

/// The sub-objects a `CompactSubObj=n` describes (CiA 306, section 4.6
/// "Object descriptions", compact storage): sub-index 0 is an UNSIGNED8
/// `ro` holding n, named `NrOfObjects`; sub-indexes 1..=n take the
/// object's data type, access, mapping and default, and their names from
/// `[XXXXName]` or, where it gives none, `<ParameterName><n>` (n decimal).
fn expand_compact(o: &mut Object, n: u8, names: &BTreeMap<u16, (&str, usize)>) {
    let count = Entry {
        name: String::from("NrOfObjects"),
        data_type: Some(DataType::Unsigned8),
        access: Some(AccessType::ReadOnly),
        default_value: Some(format!("{n}")),
        ..Entry::default()
    };
    o.subs.entry(0).or_insert(count);
    for sub in 1..=n {
        let name = match names.get(&u16::from(sub)) {
            Some((name, _)) => name.to_string(),
            None => format!("{}{sub}", o.entry.name),
        };
        o.subs.entry(sub).or_insert_with(|| Entry {
            name,
            object_type: ObjectType::Var,
            data_type: o.entry.data_type,
            access: o.entry.access,
            pdo_mapping: o.entry.pdo_mapping,
            default_value: o.entry.default_value.clone(),
            low_limit: o.entry.low_limit.clone(),
            high_limit: o.entry.high_limit.clone(),
            ..Entry::default()
        });
    }
}

fn build(sections: &[RawSection<'_>], mut warnings: Vec<Warning>) -> Result<Eds, Error> {
    let mut eds = Eds::default();
    let mut subs: Vec<(u16, u8, &RawSection<'_>)> = Vec::new();
    let mut compact: Vec<(Kind, &RawSection<'_>)> = Vec::new();
    for sec in sections {
        match classify(sec.name) {
            Kind::FileInfo => eds.file_info = FileInfo::from_keys(keys_of(sec)),
            Kind::DeviceInfo => eds.device_info = DeviceInfo::from_keys(keys_of(sec)),
            Kind::Commissioning => eds.commissioning = Some(Commissioning::from_keys(keys_of(sec))),
            Kind::DummyUsage => {
                for (k, v, _) in &sec.keys {
                    let idx = k
                        .get(..5)
                        .filter(|p| p.eq_ignore_ascii_case("Dummy"))
                        .and_then(|_| k.get(5..))
                        .and_then(hex_index);
                    if let Some(i) = idx {
                        eds.dummy_usage
                            .insert(i, parse_int(v).is_some_and(|n| n != 0));
                    }
                }
            }
            Kind::Comments => {
                eds.comments = sec
                    .keys
                    .iter()
                    .filter_map(|(k, v, _)| {
                        k.get(..4).filter(|p| p.eq_ignore_ascii_case("Line"))?;
                        Some((k.get(4..)?.parse::<u16>().ok()?, v.to_string()))
                    })
                    .collect::<BTreeMap<u16, String>>()
                    .into_values()
                    .collect();
            }
            Kind::Mandatory => eds.mandatory = object_list(sec, &mut warnings)?,
            Kind::Optional => eds.optional = object_list(sec, &mut warnings)?,
            Kind::Manufacturer => eds.manufacturer = object_list(sec, &mut warnings)?,
            Kind::Object(index) => {
                let entry = read_entry(sec, &mut warnings)?;
                eds.objects.insert(
                    index,
                    Object {
                        index,
                        entry,
                        subs: BTreeMap::new(),
                    },
                );
            }
            Kind::Sub(index, sub) => subs.push((index, sub, sec)),
            k @ (Kind::Names(_) | Kind::Values(_) | Kind::Denotations(_)) => {
                compact.push((k, sec));
            }
            Kind::Other => eds.other_sections.push(Section {
                name: sec.name.to_string(),
                line: sec.line,
                keys: keys_of(sec),
            }),
        }
    }
    for (index, sub, sec) in subs {
        let entry = read_entry(sec, &mut warnings)?;
        match eds.objects.get_mut(&index) {
            Some(o) => {
                o.subs.insert(sub, entry);
            }
            None => {
                warnings.push(Warning {
                    line: sec.line,
                    kind: WarningKind::OrphanSubObject { index },
                });
                eds.other_sections.push(Section {
                    name: sec.name.to_string(),
                    line: sec.line,
                    keys: keys_of(sec),
                });
            }
        }
    }
    let no_names = BTreeMap::new();
    let names_of = |index: u16| {
        compact
            .iter()
            .find(|(k, _)| matches!(k, Kind::Names(i) if *i == index))
            .map(|(_, sec)| numbered(sec))
    };
    for o in eds.objects.values_mut() {
        if let Some(n) = o.entry.compact_sub_obj.filter(|n| *n > 0) {
            let names = names_of(o.index);
            expand_compact(o, n, names.as_ref().unwrap_or(&no_names));
        }
    }
    for (kind, sec) in &compact {
        let (index, is_value) = match kind {
            Kind::Values(i) => (*i, true),
            Kind::Denotations(i) => (*i, false),
            _ => continue,
        };
        let Some(o) = eds.objects.get_mut(&index) else {
            warnings.push(Warning {
                line: sec.line,
                kind: WarningKind::OrphanSubObject { index },
            });
            continue;
        };
        for (n, (v, _)) in numbered(sec) {
            if let Some(e) = u8::try_from(n).ok().and_then(|s| o.subs.get_mut(&s)) {
                let slot = if is_value {
                    &mut e.parameter_value
                } else {
                    &mut e.denotation
                };
                *slot = Some(v.to_string());
            }
        }
    }
    check(&mut eds, &mut warnings);
    eds.warnings = warnings;
    Ok(eds)
}

/// The cross-section checks: listed objects exist, `SubNumber` agrees.
fn check(eds: &mut Eds, warnings: &mut Vec<Warning>) {
    let listed = eds
        .mandatory
        .iter()
        .chain(&eds.optional)
        .chain(&eds.manufacturer);
    for &index in listed {
        if !eds.objects.contains_key(&index) {
            warnings.push(Warning {
                line: 0,
                kind: WarningKind::ListedObjectMissing { index },
            });
        }
    }
    for o in eds.objects.values() {
        if let Some(declared) = o.entry.sub_number {
            if o.entry.compact_sub_obj.is_none() && usize::from(declared) != o.subs.len() {
                warnings.push(Warning {
                    line: o.entry.line,
                    kind: WarningKind::SubNumberMismatch {
                        index: o.index,
                        declared,
                        found: o.subs.len(),
                    },
                });
            }
        }
    }
}
