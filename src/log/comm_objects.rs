//! The CiA 301 communication profile area (1000h-1FFFh) for the SDO
//! transfer lines: every object named and its value explained (CiA 301,
//! section 7.5.2 "Object descriptions"; program download 1F50h-1F5xh per
//! CiA 302-3, the NMT start-up and master objects 1F80h-1F8Ah per CiA
//! 302-2). An index of the area that neither document gives an object is
//! named as reserved, so no transfer of the area goes unnamed.

use crate::cia418::DeviceType;
use crate::deltaq::{device_type, DeltaQCode};
use crate::emcy::{ErrorCode, ErrorRegister};
use crate::od::index::{
    COB_ID_EMCY, COB_ID_SYNC, COB_ID_TIME, COMMUNICATION_AREA_FIRST, COMMUNICATION_AREA_LAST,
    COMMUNICATION_CYCLE_PERIOD, CONSUMER_HEARTBEAT_TIME, DEVICE_TYPE, ERROR_BEHAVIOUR,
    ERROR_REGISTER, GUARD_TIME, IDENTITY, INHIBIT_TIME_EMCY, LIFE_TIME_FACTOR,
    MANUFACTURER_DEVICE_NAME, MANUFACTURER_HARDWARE_VERSION, MANUFACTURER_SOFTWARE_VERSION,
    PRE_DEFINED_ERROR_FIELD, PRODUCER_HEARTBEAT_TIME, RESTORE_DEFAULT_PARAMETERS,
    RPDO_COMMUNICATION, RPDO_COMMUNICATION_LAST, RPDO_MAPPING, RPDO_MAPPING_LAST,
    SDO_CLIENT_PARAMETER, SDO_SERVER_PARAMETER, STORE_PARAMETERS, SYNCHRONOUS_COUNTER_OVERFLOW,
    SYNCHRONOUS_WINDOW_LENGTH, TPDO_COMMUNICATION, TPDO_COMMUNICATION_LAST, TPDO_MAPPING,
    TPDO_MAPPING_LAST,
};
use crate::od::{comm, Address};
use crate::pdo::{Catalogue, MappingEntry};
use std::prelude::rust_2021::*;

use crate::log::manager_objects::{self, Meaning};
use crate::log::sdo_value::{unsigned, Described, Role, Value};

/// What naming a value may rely on besides the object: the node's role and
/// whether a Delta-Q charger is known to be on the bus (Delta-Q's reading
/// of a battery module's 1000h bits 20 and 21 applies only then).
#[derive(Clone, Copy, Debug)]
pub struct Context {
    /// The role of the node the object belongs to.
    pub role: Role,
    /// A Delta-Q device is on the bus (Delta-Q names for its objects).
    pub deltaq_on_bus: bool,
    /// The catalogue PDO mapping entries name objects with.
    pub catalogue: Catalogue,
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

fn device_type(v: u32, deltaq: bool) -> String {
    let dt = DeviceType::from_raw(v);
    match dt.profile_number() {
        418 => {}
        419 => {
            return format!(
                "CiA 419 battery charger, additional information {:04X}h",
                dt.additional_info()
            )
        }
        p => {
            return format!(
                "profile {p}, additional information {:04X}h",
                dt.additional_info()
            )
        }
    }
    let list = |s: crate::cia418::PdoSet| {
        s.iter()
            .map(|p| p.to_string())
            .collect::<Vec<_>>()
            .join("/")
    };
    let rpdos = if deltaq {
        device_type::module_rpdos(dt)
    } else {
        dt.rpdos()
    };
    let mut s = format!(
        "CiA 418 battery module, RPDOs {}, TPDOs {}",
        list(rpdos),
        list(dt.tpdos())
    );
    let mut known = 0;
    if deltaq {
        known = device_type::RPDO_3 | device_type::DEPRECATED;
        if device_type::deprecated(dt) {
            s.push_str(", Delta-Q deprecated bit 21");
        }
    }
    let other = dt.cia418_reserved_bits() & !known;
    if other != 0 {
        s.push_str(&format!(", reserved bits {other:08X}h"));
    }
    s
}

fn error_field(v: u32, role: Role) -> String {
    let eec = ErrorCode::from(v as u16);
    let mut s = format!("{eec}, information {:04X}h", v >> 16);
    if role == Role::DeltaQCharger {
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

/// The identifier of a COB-ID entry (bit 29: a 29-bit identifier).
fn identifier(v: u32) -> String {
    if v & (1 << 29) != 0 {
        format!("{:08X}h (29-bit)", v & 0x1FFF_FFFF)
    } else {
        format!("{:03X}h", v & 0x7FF)
    }
}

/// A PDO, EMCY or SDO COB-ID: bit 31 set means not valid; for a PDO bit 30
/// set means no remote frame allowed, for an SDO a dynamically assigned
/// identifier (`bit30`).
fn cob_id(v: u32, bit30: &str) -> String {
    let mut s = identifier(v);
    s.push_str(if v & (1 << 31) != 0 {
        ", invalid"
    } else {
        ", valid"
    });
    if v & (1 << 30) != 0 {
        s.push_str(", ");
        s.push_str(bit30);
    }
    s
}

/// 1005h COB-ID SYNC: bit 30 set, the device produces SYNC.
fn cob_id_sync(v: u32) -> String {
    let mut s = identifier(v);
    s.push_str(if v & (1 << 30) != 0 {
        ", SYNC producer"
    } else {
        ", SYNC consumer"
    });
    s
}

/// 1012h COB-ID TIME: bit 31 consumes TIME, bit 30 produces it.
fn cob_id_time(v: u32) -> String {
    let mut s = identifier(v);
    match (v & (1 << 31) != 0, v & (1 << 30) != 0) {
        (true, true) => s.push_str(", TIME consumer and producer"),
        (true, false) => s.push_str(", TIME consumer"),
        (false, true) => s.push_str(", TIME producer"),
        (false, false) => s.push_str(", neither consumes nor produces TIME"),
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
        s.push_str(e.short);
    }
    s
}

/// 1010h / 1011h: the signature a write carries ("save", "load"), or what
/// a read says the device does.
fn store_restore(v: u64, signature: u64, what: &str) -> String {
    if v == signature {
        let word = if signature == SAVE { "save" } else { "load" };
        return format!("signature \"{word}\": {what} now");
    }
    let mut s = String::new();
    if v & 1 != 0 {
        s.push_str(&format!("{what} on command"));
    }
    if signature == SAVE && v & 2 != 0 {
        if !s.is_empty() {
            s.push_str(", ");
        }
        s.push_str("saves autonomously");
    }
    if s.is_empty() {
        // "saves" -> "does not save".
        s.push_str(&format!(
            "does not {} on command",
            what.strip_suffix('s').unwrap_or(what)
        ));
    }
    let rest = v & !if signature == SAVE { 3 } else { 1 };
    if rest != 0 {
        s.push_str(&format!(", other bits {rest:08X}h"));
    }
    s
}

/// "save" in the byte order of the SDO wire, read as a little-endian U32.
const SAVE: u64 = 0x6576_6173;
/// "load".
const LOAD: u64 = 0x6461_6F6C;

/// Which group of parameters a 1010h / 1011h sub-index stands for.
fn parameter_group(sub: u8) -> String {
    match sub {
        1 => "all parameters".into(),
        2 => "communication parameters".into(),
        3 => "application parameters".into(),
        4..=0x7F => format!("manufacturer-specific parameters {sub}"),
        _ => format!("reserved sub-index {sub}"),
    }
}

/// A code whose values from 0 up are `listed`, the rest up to 7Fh
/// reserved and 80h-FFh manufacturer-specific (the convention of CiA 301's
/// 1029h and CiA 302-3's 1F51h).
fn listed_code(v: u64, listed: &[&str]) -> String {
    match usize::try_from(v).ok().and_then(|i| listed.get(i)) {
        Some(text) => (*text).into(),
        None if v <= 0x7F => "reserved".into(),
        None => "manufacturer-specific".into(),
    }
}

/// 1029h: the state a communication or other error sends the device to.
fn error_behaviour(v: u64) -> String {
    listed_code(
        v,
        &[
            "pre-operational (if operational)",
            "no change of state",
            "stopped",
        ],
    )
}

/// 1F51h program control.
fn program_control(v: u64) -> String {
    listed_code(
        v,
        &[
            "stop program / program stopped",
            "start program / program started",
            "reset program",
            "clear program / no program available",
        ],
    )
}

/// 1F57h flash status identification: bit 0 in progress, bits 1-7 status.
fn flash_status(v: u64) -> String {
    let status = match (v >> 1) & 0x7F {
        0 => "ok",
        1 => "no valid program",
        2 => "data format unknown",
        3 => "data format error or checksum error",
        4 => "flash not cleared before write",
        5 => "flash write error",
        6 => "general address error",
        7 => "flash secured (write access denied)",
        63 => "unspecified error",
        _ => "reserved status",
    };
    let mut s = format!(
        "{}, {status}",
        if v & 1 != 0 {
            "in progress"
        } else {
            "not in progress"
        }
    );
    if v >> 8 != 0 {
        s.push_str(&format!(", manufacturer-specific {:06X}h", v >> 8));
    }
    s
}

/// 1F80h NMT start-up (CiA 302-2): bit 0 NMT master, bit 1 start all
/// nodes, bit 2 do not enter operational by itself, bit 3 do not start the
/// slaves, bit 4 reset all nodes on a mandatory slave's error, bit 5
/// flying master, bit 6 stop all nodes on a mandatory slave's error.
fn nmt_startup(v: u64) -> String {
    let mut s = vec![if v & 1 != 0 {
        "NMT master"
    } else {
        "NMT slave"
    }];
    for (bit, what) in [
        (1, "starts all nodes"),
        (2, "does not enter operational by itself"),
        (3, "does not start the slaves"),
        (4, "resets all nodes on a mandatory slave's error"),
        (5, "flying master"),
        (6, "stops all nodes on a mandatory slave's error"),
    ] {
        if v & (1 << bit) != 0 {
            s.push(what);
        }
    }
    let mut s = s.join(", ");
    if v >> 7 != 0 {
        s.push_str(&format!(", reserved bits {:08X}h", v & !0x7F));
    }
    s
}

fn days_since_1984(v: u64) -> String {
    format!(
        "{v} days since 1984-01-01 ({})",
        crate::log::calendar::date(v)
    )
}

fn ms_after_midnight(v: u64) -> String {
    format!(
        "{v} ms after midnight ({})",
        crate::log::calendar::time_of_day(v)
    )
}

fn ms(v: u64) -> String {
    format!("{v} ms")
}

fn us(v: u64) -> String {
    format!("{v} us")
}

fn times_100us(v: u64) -> String {
    format!("{} us", v * 100)
}

fn hex32(v: u64) -> String {
    format!("{v:08X}h")
}

fn decimal(v: u64) -> String {
    v.to_string()
}

/// `bytes` of the entry `address` of the communication table
/// ([`comm::COMM_OBJECTS`]): named and sized by its row, explained by
/// `meaning`.
fn from_row(
    address: Address,
    bytes: &[u8],
    exact: bool,
    meaning: impl Fn(u64) -> String,
) -> Described {
    match comm::find(address) {
        Some(row) => unsigned(
            Described::named(row.short),
            bytes,
            usize::from(row.size()),
            exact,
            meaning,
        ),
        None => Described::named(format!("{address:#}")),
    }
}

/// Names and explains `bytes` of `index`:`sub` in the communication
/// profile area; `None` outside it. `exact` is false for an expedited value
/// with s = 0.
pub fn describe(index: u16, sub: u8, bytes: &[u8], ctx: Context, exact: bool) -> Option<Described> {
    if !(COMMUNICATION_AREA_FIRST..=COMMUNICATION_AREA_LAST).contains(&index) {
        return None;
    }
    let num = |name: String, n: usize, meaning: fn(u64) -> String| {
        unsigned(Described::named(name), bytes, n, exact, meaning)
    };
    let highest = |what: &str| num(format!("{what}: highest sub-index"), 1, decimal);
    // The two halves of a TIME_OF_DAY kept apart (1020h in CiA 301, the
    // CiA 302 date and time objects): Unsigned32 days since 1984-01-01,
    // Unsigned32 milliseconds after midnight.
    let date = |name: String| num(name, 4, days_since_1984);
    let time = |name: String| num(name, 4, ms_after_midnight);
    let text = |name: &str| {
        let mut d = Described::named(name);
        d.string = true;
        d.value = Value::Text(String::from_utf8_lossy(bytes).into_owned());
        d
    };
    let bytes_only = |name: String| Described::named(name);
    // An entry of the communication table (od::comm) at sub-index `$sub`
    // of `index`: its decoder name and size from its row, `$meaning` from
    // here.
    macro_rules! row {
        ($sub:expr, $meaning:expr $(,)?) => {
            from_row(Address::new(index, $sub), bytes, exact, $meaning)
        };
    }
    let d = match (index, sub) {
        (DEVICE_TYPE, 0) => row!(sub, |v| device_type(v as u32, ctx.deltaq_on_bus)),
        (ERROR_REGISTER, 0) => row!(sub, |v| error_register(v as u8)),
        (0x1002, 0) => num("manufacturer status register".into(), 4, hex32),
        (PRE_DEFINED_ERROR_FIELD, 0) => row!(0, decimal),
        // Every sub-index past 0 is read as an entry, 255 too.
        (PRE_DEFINED_ERROR_FIELD, _) => row!(1, |v| error_field(v as u32, ctx.role)),
        (COB_ID_SYNC, 0) => row!(sub, |v| cob_id_sync(v as u32)),
        (COMMUNICATION_CYCLE_PERIOD, 0) => {
            row!(sub, |v| match v {
                0 => "0 us (no SYNC produced)".into(),
                v => us(v),
            })
        }
        (SYNCHRONOUS_WINDOW_LENGTH, 0) => row!(sub, |v| match v {
            0 => "0 us (no window)".into(),
            v => us(v),
        }),
        (
            MANUFACTURER_DEVICE_NAME
            | MANUFACTURER_HARDWARE_VERSION
            | MANUFACTURER_SOFTWARE_VERSION,
            0,
        ) => text(comm::find(Address::index(index)).map_or("", |r| r.short)),
        (GUARD_TIME, 0) => row!(sub, |v| match v {
            0 => "0 ms (no node guarding)".into(),
            v => ms(v),
        }),
        (LIFE_TIME_FACTOR, 0) => row!(sub, |v| match v {
            0 => "0 (no life guarding)".into(),
            v => format!("node life time = {v} x guard time"),
        }),
        (STORE_PARAMETERS, 0) => row!(0, decimal),
        (STORE_PARAMETERS, _) => unsigned(
            Described::named(format!("store parameters: {}", parameter_group(sub))),
            bytes,
            4,
            exact,
            |v| store_restore(v, SAVE, "saves"),
        ),
        (RESTORE_DEFAULT_PARAMETERS, 0) => row!(0, decimal),
        (RESTORE_DEFAULT_PARAMETERS, _) => unsigned(
            Described::named(format!(
                "restore default parameters: {}",
                parameter_group(sub)
            )),
            bytes,
            4,
            exact,
            |v| store_restore(v, LOAD, "restores"),
        ),
        (COB_ID_TIME, 0) => row!(sub, |v| cob_id_time(v as u32)),
        (0x1013, 0) => num("high resolution time stamp".into(), 4, us),
        (COB_ID_EMCY, 0) => row!(sub, |v| cob_id(v as u32, "reserved bit 30")),
        (INHIBIT_TIME_EMCY, 0) => row!(sub, times_100us),
        (CONSUMER_HEARTBEAT_TIME, 0) => row!(0, decimal),
        // Every sub-index past 0 is read as an entry, 128-255 too.
        (CONSUMER_HEARTBEAT_TIME, _) => row!(1, |v| {
            let (node, ms) = ((v >> 16) & 0xFF, v & 0xFFFF);
            if node == 0 || ms == 0 {
                format!("disabled (node {node}, {ms} ms)")
            } else {
                format!("node {node}, {ms} ms")
            }
        }),
        (PRODUCER_HEARTBEAT_TIME, 0) => {
            let mut d = row!(sub, |v| match v {
                0 => "disabled".into(),
                v => ms(v),
            });
            if d.value != Value::None {
                d.unit = Some("ms");
            }
            d
        }
        (IDENTITY, 0) => row!(0, decimal),
        (IDENTITY, 1..=4) => row!(sub, hex32),
        (SYNCHRONOUS_COUNTER_OVERFLOW, 0) => row!(sub, |v| match v {
            0 => "0 (SYNC without counter)".into(),
            2..=240 => format!("counter counts 1 to {v}"),
            _ => format!("{v} (reserved)"),
        }),
        (0x1020, 0) => highest("verify configuration"),
        (0x1020, 1) => date("verify configuration: configuration date".into()),
        (0x1020, 2) => time("verify configuration: configuration time".into()),
        (0x1021, 0) => bytes_only("store EDS".into()),
        (0x1022, 0) => num("store format".into(), 1, |v| match v {
            0 => "0 (ISO 10646, not compressed)".into(),
            1..=127 => format!("{v} (reserved)"),
            v => format!("{v} (manufacturer-specific)"),
        }),
        (0x1023, 0) => highest("OS command"),
        (0x1023, 1) => bytes_only("OS command: command".into()),
        (0x1023, 2) => num("OS command: status".into(), 1, decimal),
        (0x1023, 3) => bytes_only("OS command: reply".into()),
        (0x1024, 0) => num("OS command mode".into(), 1, decimal),
        (0x1025, 0) => highest("OS debugger interface"),
        (0x1025, _) => bytes_only(format!("OS debugger interface: sub-index {sub}")),
        (0x1026, 0) => highest("OS prompt"),
        (0x1026, 1) => bytes_only("OS prompt: StdIn".into()),
        (0x1026, 2) => bytes_only("OS prompt: StdOut".into()),
        (0x1026, 3) => bytes_only("OS prompt: StdErr".into()),
        (0x1027, 0) => num(
            "module list: number of connected modules".into(),
            1,
            decimal,
        ),
        (0x1027, _) => num(format!("module list: module {sub}"), 2, decimal),
        (0x1028, 0) => highest("emergency consumer"),
        (0x1028, _) => unsigned(
            Described::named(format!("emergency consumer: node {sub}")),
            bytes,
            4,
            exact,
            |v| cob_id(v as u32, "reserved bit 30"),
        ),
        (ERROR_BEHAVIOUR, 0) => row!(sub, decimal),
        (ERROR_BEHAVIOUR, _) => {
            let what = match sub {
                1 => "communication error".to_string(),
                _ => format!("error class {sub}"),
            };
            num(format!("error behaviour: {what}"), 1, error_behaviour)
        }
        (0x102A, 0) => num("NMT inhibit time".into(), 2, times_100us),
        (SDO_SERVER_PARAMETER..=0x12FF, _) => {
            let client = index >= SDO_CLIENT_PARAMETER;
            let sdo = format!(
                "SDO {} parameter {}",
                if client { "client" } else { "server" },
                index & 0x7F
            );
            match sub {
                0 => highest(&sdo),
                1 | 2 => unsigned(
                    Described::named(format!(
                        "{sdo}: COB-ID {}",
                        if sub == 1 {
                            "client to server"
                        } else {
                            "server to client"
                        }
                    )),
                    bytes,
                    4,
                    exact,
                    |v| cob_id(v as u32, "dynamically assigned"),
                ),
                3 => num(
                    format!(
                        "{sdo}: node-ID of the SDO {}",
                        if client { "server" } else { "client" }
                    ),
                    1,
                    decimal,
                ),
                _ => bytes_only(format!("{sdo}: sub-index {sub}")),
            }
        }
        (
            RPDO_COMMUNICATION..=RPDO_COMMUNICATION_LAST
            | TPDO_COMMUNICATION..=TPDO_COMMUNICATION_LAST,
            _,
        ) => {
            let pdo = format!(
                "{}{} communication",
                if index < TPDO_COMMUNICATION {
                    "RPDO"
                } else {
                    "TPDO"
                },
                index & 0x1FF
            );
            match sub {
                0 => highest(&pdo),
                1 => unsigned(
                    Described::named(format!("{pdo}: COB-ID")),
                    bytes,
                    4,
                    exact,
                    |v| cob_id(v as u32, "no RTR"),
                ),
                2 => num(format!("{pdo}: transmission type"), 1, transmission_type),
                3 => num(format!("{pdo}: inhibit time"), 2, times_100us),
                4 => num(format!("{pdo}: reserved (compatibility entry)"), 1, decimal),
                5 => num(format!("{pdo}: event timer"), 2, ms),
                6 => num(format!("{pdo}: SYNC start value"), 1, decimal),
                _ => bytes_only(format!("{pdo}: sub-index {sub}")),
            }
        }
        (RPDO_MAPPING..=RPDO_MAPPING_LAST | TPDO_MAPPING..=TPDO_MAPPING_LAST, _) => {
            let pdo = format!(
                "{}{} mapping",
                if index < TPDO_MAPPING { "RPDO" } else { "TPDO" },
                index & 0x1FF
            );
            match sub {
                0 => num(format!("{pdo}: number of entries"), 1, decimal),
                _ => unsigned(
                    Described::named(format!("{pdo}: entry {sub}")),
                    bytes,
                    4,
                    exact,
                    |v| mapping_entry(v as u32, ctx.catalogue),
                ),
            }
        }
        (0x1F50, _) => bytes_only(format!("program data {sub}")),
        (0x1F51, 0) => highest("program control"),
        (0x1F51, _) => num(format!("program control {sub}"), 1, program_control),
        _ if manager_objects::is_manager_object(index) => {
            let (name, size, meaning) = manager_objects::entry(Address::new(index, sub));
            let meaning: fn(u64) -> String = match meaning {
                Meaning::Count | Meaning::Decimal => decimal,
                Meaning::Date => days_since_1984,
                Meaning::Time => ms_after_midnight,
                Meaning::NmtStartup => nmt_startup,
                Meaning::Ms => ms,
                Meaning::Hex => hex32,
            };
            match size {
                0 => Described::named(name),
                n => num(name, usize::from(n), meaning),
            }
        }
        (0x1F57, 0) => highest("flash status identification"),
        (0x1F57, _) => num(
            format!("flash status identification {sub}"),
            4,
            flash_status,
        ),
        (0x1F8A, 0) => highest("restore configuration"),
        (0x1F8A, _) => num(format!("restore configuration of node {sub}"), 4, hex32),
        (0x1F20, _) => bytes_only(format!("store DCF {sub}")),
        (0x1F21, _) => num(format!("storage format {sub}"), 1, decimal),
        (0x1F25, _) => num(format!("configuration request {sub}"), 4, hex32),
        (0x1F26, _) => date(format!("expected configuration date of node {sub}")),
        (0x1F27, _) => time(format!("expected configuration time of node {sub}")),
        _ => bytes_only(format!(
            "{index:04X}h:{sub:02X}, reserved in the communication profile area"
        )),
    };
    Some(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log::sdo_value::NO_CATALOGUE;

    const CTX: Context = Context {
        role: Role::Other,
        deltaq_on_bus: false,
        catalogue: NO_CATALOGUE,
    };

    fn meaning(index: u16, sub: u8, bytes: &[u8]) -> (String, String) {
        let d = describe(index, sub, bytes, CTX, true).unwrap();
        (d.name.unwrap(), d.meaning.unwrap_or_default())
    }

    #[test]
    fn every_index_of_the_area_is_named() {
        for index in 0x1000..=0x1FFFu16 {
            for sub in [0u8, 1, 2, 0x7F, 0xFF] {
                let d = describe(index, sub, &[0; 4], CTX, false).unwrap();
                assert!(d.name.is_some(), "{index:04X}h:{sub:02X}");
            }
        }
        assert!(describe(0x2000, 0, &[0], CTX, true).is_none());
        assert!(describe(0x0FFF, 0, &[0], CTX, true).is_none());
    }

    #[test]
    fn the_tables_entries_are_named_and_sized_by_their_rows() {
        let name = |index, sub, bytes: &[u8]| meaning(index, sub, bytes).0;
        assert_eq!(name(0x1018, 2, &[0; 4]), "identity product code");
        assert_eq!(name(0x1018, 0, &[4]), "identity: highest sub-index");
        // Past the rows' runs the entries keep their names.
        assert_eq!(name(0x1003, 255, &[0; 4]), "pre-defined error field");
        assert_eq!(name(0x1016, 200, &[0; 4]), "consumer heartbeat time");
        assert_eq!(meaning(0x1017, 0, &[0xE8, 3]).1, "1000 ms");
        assert_eq!(
            meaning(0x1017, 0, &[0xE8, 3, 0, 0]).1,
            "4 bytes, the object has 2"
        );
        assert_eq!(meaning(0x1019, 0, &[10, 0]).1, "2 bytes, the object has 1");
        assert_eq!(name(0x1008, 0, b"x"), "manufacturer device name");
        assert_eq!(name(0x100A, 0, b"x"), "manufacturer software version");
        assert_eq!(
            meaning(0x1015, 0, &[3, 0]),
            ("inhibit time EMCY".into(), "300 us".into())
        );
        assert_eq!(name(0x1029, 0, &[1]), "error behaviour: highest sub-index");
    }

    #[test]
    fn values_explained() {
        assert_eq!(
            meaning(0x1010, 2, &[3, 0, 0, 0]),
            (
                "store parameters: communication parameters".into(),
                "saves on command, saves autonomously".into()
            )
        );
        assert_eq!(
            meaning(0x1280, 3, &[5]).0,
            "SDO client parameter 0: node-ID of the SDO server"
        );
        // (index, sub, value, what it means)
        let meanings: [(u16, u8, &[u8], &str); 12] = [
            (0x1011, 1, b"load", "signature \"load\": restores now"),
            (0x1011, 1, &[0, 0, 0, 0], "does not restore on command"),
            (
                0x1012,
                0,
                &[0x00, 0x01, 0x00, 0xC0],
                "100h, TIME consumer and producer",
            ),
            (0x1014, 0, &[0x8A, 0, 0, 0x80], "08Ah, invalid"),
            (0x1029, 2, &[2], "stopped"),
            (0x1029, 1, &[3], "reserved"),
            (0x1029, 1, &[200], "manufacturer-specific"),
            (0x1F51, 1, &[3], "clear program / no program available"),
            (
                0x1F80,
                0,
                &[0x0F, 0, 0, 0],
                "NMT master, starts all nodes, does not enter operational by itself, \
                 does not start the slaves",
            ),
            (
                0x1F57,
                1,
                &[0x00, 0x01, 0, 0],
                "not in progress, ok, manufacturer-specific 000001h",
            ),
            (
                0x1020,
                1,
                &[2, 0, 0, 0],
                "2 days since 1984-01-01 (1984-01-03)",
            ),
            // A value of the wrong size says so instead of a meaning.
            (0x100C, 0, &[1], "1 bytes, the object has 2"),
        ];
        for (index, sub, value, want) in meanings {
            assert_eq!(meaning(index, sub, value).1, want, "{index:04X}h:{sub}");
        }
    }
}
