//! The name and meaning of an object transferred by SDO: well-known CiA 301
//! objects here, profile objects from the PDO catalogue (CiA 418 for the
//! battery node and any node without a role, Delta-Q then CiA 418 for the
//! charger node).

use canopen_codec::cia418::{DeviceType, BATTERY_MODULE_CATALOGUE};
use canopen_codec::deltaq::{device_type, DeltaQCode, CHARGER_CATALOGUE};
use canopen_codec::emcy::{ErrorCode, ErrorRegister};
use canopen_codec::pdo::{Catalogue, FieldValue, MappingEntry};

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
    pub name: Option<String>,
    pub value: Value,
    pub unit: Option<&'static str>,
    /// Words, e.g. `4000 ms`, `charger enabled`.
    pub meaning: Option<String>,
    /// The value is a visible string: words print it quoted instead of hex.
    pub string: bool,
}

impl Described {
    fn named(name: impl Into<String>) -> Self {
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
    Charger,
    Battery,
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
fn unsigned(
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

fn error_register(r: u8) -> String {
    if r == 0 {
        return "no error".into();
    }
    let names: Vec<String> = ErrorRegister::from_bits_retain(r)
        .iter_names()
        .map(|(n, _)| n.to_lowercase().replace('_', " "))
        .collect();
    names.join(", ")
}

fn device_type(v: u32) -> String {
    let dt = DeviceType::from_raw(v);
    if !dt.is_cia418() {
        return format!(
            "profile {}, additional information {:04X}h",
            dt.profile_number(),
            dt.additional_info()
        );
    }
    let list = |s: canopen_codec::cia418::PdoSet| {
        s.iter()
            .map(|p| p.to_string())
            .collect::<Vec<_>>()
            .join("/")
    };
    let mut s = format!(
        "CiA 418 battery module, RPDOs {}, TPDOs {}",
        list(device_type::module_rpdos(dt)),
        list(dt.tpdos())
    );
    if device_type::deprecated(dt) {
        s.push_str(", Delta-Q deprecated bit 21");
    }
    let other = dt.cia418_reserved_bits() & !(device_type::RPDO_3 | device_type::DEPRECATED);
    if other != 0 {
        s.push_str(&format!(", reserved bits {other:08X}h"));
    }
    s
}

fn error_field(v: u32, role: Role) -> String {
    let eec = ErrorCode::from(v as u16);
    let mut s = format!("{eec}, information {:04X}h", v >> 16);
    if role == Role::Charger {
        let (_, code) = DeltaQCode::from_error_field(v);
        if code != DeltaQCode::NONE {
            s.push_str(&format!(", Delta-Q {code}"));
            if let Some(d) = code.description() {
                s.push_str(&format!(" {d}"));
            }
        }
    }
    s
}

fn cob_id(v: u32) -> String {
    let mut s = if v & (1 << 29) != 0 {
        format!("{:08X}h (29-bit)", v & 0x1FFF_FFFF)
    } else {
        format!("{:03X}h", v & 0x7FF)
    };
    s.push_str(if v & (1 << 31) != 0 {
        ", invalid"
    } else {
        ", valid"
    });
    if v & (1 << 30) != 0 {
        s.push_str(", no RTR");
    }
    s
}

fn transmission_type(v: u64) -> String {
    match v {
        0 => "synchronous (acyclic)".into(),
        1..=240 => format!("synchronous, every {v} SYNC"),
        252 => "synchronous, RTR only".into(),
        253 => "event-driven, RTR only".into(),
        254 => "event-driven (manufacturer-specific)".into(),
        255 => "event-driven (device profile)".into(),
        _ => "reserved".into(),
    }
}

/// A PDO mapping entry with the mapped object's name where the catalogue
/// knows it.
fn mapping_entry(v: u32, catalogue: Catalogue) -> String {
    let (index, sub, bits) = ((v >> 16) as u16, (v >> 8) as u8, v as u8);
    let mut s = format!("{index:04X}h:{sub:02X}/{bits}");
    if v == 0 {
        return "empty".into();
    }
    if MappingEntry::new(index, sub, bits).is_dummy() {
        s.push_str(" padding");
    } else if let Some(e) = catalogue.lookup(index, sub) {
        s.push(' ');
        s.push_str(e.name);
    }
    s
}

/// Names and interprets `bytes` of `index`:`sub` on a node with `role`.
/// `exact` is false for an expedited value with s = 0.
pub fn describe(index: u16, sub: u8, bytes: &[u8], role: Role, exact: bool) -> Described {
    let catalogue = match role {
        Role::Charger => CHARGER_CATALOGUE,
        Role::Battery | Role::Other => BATTERY_MODULE_CATALOGUE,
    };
    let entries = |what: &str| Described::named(format!("{what}: highest sub-index"));
    let count = |d: Described| unsigned(d, bytes, 1, exact, |v| v.to_string());
    match (index, sub) {
        (0x1000, 0) => unsigned(Described::named("device type"), bytes, 4, exact, |v| {
            device_type(v as u32)
        }),
        (0x1001, 0) => unsigned(Described::named("error register"), bytes, 1, exact, |v| {
            error_register(v as u8)
        }),
        (0x1003, 0) => count(Described::named("number of errors")),
        (0x1003, _) => unsigned(
            Described::named("pre-defined error field"),
            bytes,
            4,
            exact,
            |v| error_field(v as u32, role),
        ),
        (0x1008..=0x100A, 0) => {
            let name = match index {
                0x1008 => "manufacturer device name",
                0x1009 => "manufacturer hardware version",
                _ => "manufacturer software version",
            };
            let mut d = Described::named(name);
            d.string = true;
            d.value = Value::Text(String::from_utf8_lossy(bytes).into_owned());
            d
        }
        (0x1016, 0) => count(entries("consumer heartbeat time")),
        (0x1016, _) => unsigned(
            Described::named("consumer heartbeat time"),
            bytes,
            4,
            exact,
            |v| {
                let (node, ms) = ((v >> 16) & 0xFF, v & 0xFFFF);
                if node == 0 || ms == 0 {
                    format!("disabled (node {node}, {ms} ms)")
                } else {
                    format!("node {node}, {ms} ms")
                }
            },
        ),
        (0x1017, 0) => {
            let mut d = unsigned(
                Described::named("producer heartbeat time"),
                bytes,
                2,
                exact,
                |v| match v {
                    0 => "disabled".into(),
                    v => format!("{v} ms"),
                },
            );
            if d.value != Value::None {
                d.unit = Some("ms");
            }
            d
        }
        (0x1018, 0) => count(entries("identity")),
        (0x1018, 1..=4) => {
            let name = [
                "identity vendor-ID",
                "identity product code",
                "identity revision number",
                "identity serial number",
            ][usize::from(sub - 1)];
            unsigned(Described::named(name), bytes, 4, exact, |v| {
                format!("{v:08X}h")
            })
        }
        (0x1400..=0x15FF | 0x1800..=0x19FF, _) => {
            let pdo = format!(
                "{}{} communication",
                if index < 0x1800 { "RPDO" } else { "TPDO" },
                index & 0x1FF
            );
            match sub {
                0 => count(entries(&pdo)),
                1 => unsigned(
                    Described::named(format!("{pdo}: COB-ID")),
                    bytes,
                    4,
                    exact,
                    |v| cob_id(v as u32),
                ),
                2 => unsigned(
                    Described::named(format!("{pdo}: transmission type")),
                    bytes,
                    1,
                    exact,
                    transmission_type,
                ),
                3 => unsigned(
                    Described::named(format!("{pdo}: inhibit time")),
                    bytes,
                    2,
                    exact,
                    |v| format!("{} us", v * 100),
                ),
                5 => unsigned(
                    Described::named(format!("{pdo}: event timer")),
                    bytes,
                    2,
                    exact,
                    |v| format!("{v} ms"),
                ),
                6 => count(Described::named(format!("{pdo}: SYNC start value"))),
                _ => Described::named(format!("{pdo}: sub-index {sub}")),
            }
        }
        (0x1600..=0x17FF | 0x1A00..=0x1BFF, _) => {
            let pdo = format!(
                "{}{} mapping",
                if index < 0x1A00 { "RPDO" } else { "TPDO" },
                index & 0x1FF
            );
            match sub {
                0 => count(Described::named(format!("{pdo}: number of entries"))),
                _ => unsigned(
                    Described::named(format!("{pdo}: entry {sub}")),
                    bytes,
                    4,
                    exact,
                    |v| mapping_entry(v as u32, catalogue),
                ),
            }
        }
        _ => profile(index, sub, bytes, catalogue, exact),
    }
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
    let d = Described::named(def.name);
    let raw = match uint(bytes, usize::from(def.bits / 8), exact) {
        Ok(raw) => raw,
        Err(e) => {
            return Described {
                meaning: Some(e),
                ..d
            }
        }
    };
    let field = catalogue.interpret(MappingEntry::new(index, sub, def.bits), raw);
    let digits = usize::from(def.bits).div_ceil(4);
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
