//! Writing a description back as EDS text (strict out: one spelling of
//! every key, sections in CiA 306 order, LF line ends, no comments).

use alloc::string::String;
use core::fmt::Write;

use super::{Eds, Entry, Keys};

/// One `Key=Value` line. Writing to a `String` cannot fail.
fn kv(out: &mut String, key: &str, value: impl core::fmt::Display) {
    let _ = writeln!(out, "{key}={value}");
}

fn section(out: &mut String, name: impl core::fmt::Display) {
    if !out.is_empty() {
        out.push('\n');
    }
    let _ = writeln!(out, "[{name}]");
}

fn keys(out: &mut String, keys: &Keys) {
    for (k, v) in &keys.0 {
        kv(out, k, v);
    }
}

fn list(out: &mut String, name: &str, objects: &[u16]) {
    section(out, name);
    kv(out, "SupportedObjects", objects.len());
    for (n, index) in objects.iter().enumerate() {
        kv(
            out,
            &alloc::format!("{}", n.saturating_add(1)),
            format_args!("0x{index:04X}"),
        );
    }
}

fn entry(out: &mut String, e: &Entry) {
    kv(out, "ParameterName", &e.name);
    kv(
        out,
        "ObjectType",
        format_args!("0x{:X}", u8::from(e.object_type)),
    );
    if let Some(n) = e.sub_number {
        kv(out, "SubNumber", n);
    }
    if let Some(n) = e.compact_sub_obj {
        kv(out, "CompactSubObj", n);
    }
    if let Some(t) = e.data_type {
        kv(out, "DataType", format_args!("0x{:04X}", u16::from(t)));
    }
    if let Some(a) = e.access {
        kv(out, "AccessType", a.as_str());
    }
    let optional = [
        ("DefaultValue", &e.default_value),
        ("ParameterValue", &e.parameter_value),
        ("Denotation", &e.denotation),
        ("LowLimit", &e.low_limit),
        ("HighLimit", &e.high_limit),
    ];
    for (k, v) in optional {
        if let Some(v) = v {
            kv(out, k, v);
        }
    }
    kv(out, "PDOMapping", u8::from(e.pdo_mapping));
    if let Some(f) = e.obj_flags {
        kv(out, "ObjFlags", f);
    }
    keys(out, &e.other);
}

/// Writes `eds` as EDS (or, with commissioning or parameter values, DCF)
/// text in the layout of CiA 306 ("Electronic data sheet specification for
/// CANopen", section 4 "EDS structure"): file and device information, dummy
/// usage, comments, the three object lists, each object followed by its
/// sub-objects, the commissioning section (spelt `[DeviceComissioning]`,
/// as CiA 306 writes it and as python-canopen and CANopenNode's tools read
/// it), then every other section.
///
/// Every key the model keeps is written, so [`parse`](super::parse) reads
/// the text back to the same model (positions and warnings aside, see
/// [`Eds::clear_positions`]). An object with `CompactSubObj` is written with
/// that key *and* its sub-objects as sections, which reads back unchanged.
/// Text values are written as they are held: the model's values never hold
/// a line break or a comment (the parser removed them).
///
/// ```
/// use canopen_codec::eds::{parse, write};
/// let mut eds = parse("[1017]\nParameterName=Heartbeat\nDataType=6\nAccessType=rw\n").unwrap();
/// let text = write(&eds);
/// assert!(text.contains("[1017]\nParameterName=Heartbeat\nObjectType=0x7\n"));
/// let mut again = parse(&text).unwrap();
/// eds.clear_positions();
/// again.clear_positions();
/// assert_eq!(again, eds);
/// ```
#[must_use]
pub fn write(eds: &Eds) -> String {
    let mut out = String::new();
    section(&mut out, "FileInfo");
    keys(&mut out, &eds.file_info.keys);
    section(&mut out, "DeviceInfo");
    keys(&mut out, &eds.device_info.keys);
    if !eds.dummy_usage.is_empty() {
        section(&mut out, "DummyUsage");
        for (index, used) in &eds.dummy_usage {
            kv(
                &mut out,
                &alloc::format!("Dummy{index:04X}"),
                u8::from(*used),
            );
        }
    }
    if !eds.comments.is_empty() {
        section(&mut out, "Comments");
        kv(&mut out, "Lines", eds.comments.len());
        for (n, line) in eds.comments.iter().enumerate() {
            kv(
                &mut out,
                &alloc::format!("Line{}", n.saturating_add(1)),
                line,
            );
        }
    }
    list(&mut out, "MandatoryObjects", &eds.mandatory);
    list(&mut out, "OptionalObjects", &eds.optional);
    list(&mut out, "ManufacturerObjects", &eds.manufacturer);
    for o in eds.objects.values() {
        section(&mut out, format_args!("{:04X}", o.index));
        entry(&mut out, &o.entry);
        for (sub, e) in &o.subs {
            section(&mut out, format_args!("{:04X}sub{sub:X}", o.index));
            entry(&mut out, e);
        }
    }
    if let Some(c) = &eds.commissioning {
        section(&mut out, "DeviceComissioning");
        keys(&mut out, &c.keys);
    }
    for s in &eds.other_sections {
        section(&mut out, &s.name);
        keys(&mut out, &s.keys);
    }
    out
}
