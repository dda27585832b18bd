//! One JSON object per frame, written by hand into the output line (the
//! text after `"t"` is what the line cache keeps and repeats; serde_json
//! writes the rarer objects, a finished SDO transfer here and the summary).
//!
//! Keys: `t` (seconds or null), `rxtx` (`rx` / `tx`, only when the
//! trace says), `id`, `kind` (nmt, sync, time, emcy, tpdo,
//! rpdo, sdo_rx, sdo_tx, heartbeat, lss, unknown), `node` (or null), `role`,
//! `dlc`, `data` (hex), then per-kind fields; `error` when the frame does not
//! fit its object; `mapping`, `unmapped_bytes` and `fields` when a PDO
//! mapping is known for the frame (see main.rs). After the frame that ends
//! an SDO transfer comes one more object of kind `sdo_transfer` (see
//! [`transfer`]).

use std::fmt::Write;
use std::prelude::rust_2021::*;

use crate::cob_id::{classify, CobKind};
use crate::lss::{LssInquiry, LssMessage, LssRequest, LssResponse};
use crate::od::Address;
use crate::pdo::{FieldValue, NamedFields};
use crate::sdo::wire::view::{BlockView, CommandView, Names, CLIENT_NAMES, SERVER_NAMES};
use crate::sdo::InitiatePayload;
use crate::Message;

use crate::log::mappings::Source;
use crate::log::sdo::{End, Report};
use crate::log::sdo_value::Value;
use crate::log::words::{deltaq, described, sentence};
use crate::log::Roles;

/// Writes JSON-escaped text into a `String`: the runs that need no escape
/// are copied whole (the usual case: the whole string). The bytes that need
/// one (`"`, `\` and the controls below 20h) are ASCII, so the scan is by
/// byte.
struct Escaping<'a>(&'a mut String);

impl std::fmt::Write for Escaping<'_> {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let mut rest = s;
        while let Some(at) = rest
            .bytes()
            .position(|b| b == b'"' || b == b'\\' || b < 0x20)
        {
            let (clean, tail) = rest.split_at(at);
            self.0.push_str(clean);
            let mut chars = tail.chars();
            match chars.next() {
                Some('"') => self.0.push_str("\\\""),
                Some('\\') => self.0.push_str("\\\\"),
                Some(c) => {
                    let _ = write!(self.0, "\\u{:04x}", c as u32);
                }
                None => {}
            }
            rest = chars.as_str();
        }
        self.0.push_str(rest);
        Ok(())
    }
}

/// Appends `s` as a JSON string.
pub fn string(out: &mut String, s: &str) {
    use std::fmt::Write as _;
    out.push('"');
    let _ = Escaping(out).write_str(s);
    out.push('"');
}

/// Appends `value`'s `Display` as a JSON string, escaped as it is written
/// (no temporary `String`).
pub fn display(out: &mut String, value: &impl std::fmt::Display) {
    out.push('"');
    let _ = write!(Escaping(out), "{value}");
    out.push('"');
}

/// Appends the value of a PDO field as the machine outputs give it (this
/// JSON's `value`, the signals' cell): a number (scaled, out of range,
/// narrowed) in its exact decimal form, which is a valid JSON number;
/// words (a bit field, a formatted value, characters) through `words`.
/// False, nothing appended, for the rest (markers, padding, a missing or
/// unread field): the JSON writes `null` there.
pub fn field_value(
    out: &mut String,
    value: &FieldValue,
    words: fn(&mut String, &FieldValue),
) -> bool {
    match value {
        FieldValue::Scaled { value, .. }
        | FieldValue::OutOfRange { value, .. }
        | FieldValue::Narrowed { value, .. } => {
            let _ = write!(out, "{value}");
        }
        FieldValue::Flags(_) | FieldValue::Formatted(_) | FieldValue::Chars(_) => words(out, value),
        _ => return false,
    }
    true
}

/// Appends `bytes` as a JSON string of lower-case hex digits.
pub fn hex_string(out: &mut String, bytes: &[u8]) {
    const DIGITS: &[u8; 16] = b"0123456789abcdef";
    out.push('"');
    for b in bytes {
        out.push(char::from(DIGITS[usize::from(b >> 4)]));
        out.push(char::from(DIGITS[usize::from(b & 0x0F)]));
    }
    out.push('"');
}

/// Appends `,"key":` to `out`; `k` is one of the program's own key names,
/// which need no escape.
pub fn key(out: &mut String, k: &str) {
    debug_assert!(!k.bytes().any(|b| b == b'"' || b == b'\\' || b < 0x20));
    out.push_str(",\"");
    out.push_str(k);
    out.push_str("\":");
}

/// The `kind` key of a frame: `nmt`, `sync`, `emcy`, `tpdo`, `sdo_rx`, `heartbeat`, ...
pub fn kind_name(kind: CobKind) -> &'static str {
    match kind {
        CobKind::Nmt => "nmt",
        CobKind::Sync => "sync",
        CobKind::Emcy(_) => "emcy",
        CobKind::Time => "time",
        CobKind::Tpdo(..) => "tpdo",
        CobKind::Rpdo(..) => "rpdo",
        CobKind::SdoRx(_) => "sdo_rx",
        CobKind::SdoTx(_) => "sdo_tx",
        CobKind::NmtErrorControl(_) => "heartbeat",
        CobKind::Lss(_) => "lss",
        CobKind::Unknown => "unknown",
    }
}
/// `{"t":..`: the start of a frame's object.
pub fn time(
    out: &mut String,
    column: &mut crate::log::time_column::TimeColumn,
    timestamp: Option<crate::Timestamp>,
) {
    out.push_str("{\"t\":");
    match timestamp {
        Some(t) => column.write(out, t),
        None => out.push_str("null"),
    }
}

/// `,"rxtx":"rx"` or `"tx"` when the trace says which (ASC, `.trc`
/// 1.1 and later, BLF, candump lines with python-can's `R` / `T` flag);
/// nothing when it does not.
pub fn rxtx(out: &mut String, direction: Option<crate::trace::RxTx>) {
    match direction {
        Some(crate::trace::RxTx::Rx) => out.push_str(",\"rxtx\":\"rx\""),
        Some(crate::trace::RxTx::Tx) => out.push_str(",\"rxtx\":\"tx\""),
        None => {}
    }
}

/// The rest of a frame's object after `"t"` (the same for the same frame
/// while roles and mappings stay).
pub fn rest(out: &mut String, line: &crate::log::FrameLine<'_>) {
    let crate::log::FrameLine {
        log: l,
        decoded: m,
        roles,
        fields: pdo,
        notes,
    } = *line;
    let guard_reply = notes.guard_reply;
    let kind = classify(l.frame.id());
    let _ = write!(out, ",\"id\":{}", l.frame.id().raw());
    key(out, "kind");
    string(out, kind_name(kind));
    key(out, "node");
    match kind.node() {
        Some(n) => {
            let _ = write!(out, "{n}");
        }
        None => out.push_str("null"),
    }
    key(out, "role");
    match roles.role(kind.node()) {
        Some(r) => string(out, r),
        None => out.push_str("null"),
    }
    let _ = write!(
        out,
        ",\"extended\":{},\"remote\":{},\"dlc\":{}",
        l.frame.id().is_extended(),
        l.frame.is_remote(),
        l.frame.dlc()
    );
    key(out, "data");
    hex_string(out, l.frame.data());
    match (m, &notes.block_segment) {
        (_, Some(seg)) => {
            key(out, "text");
            display(out, &seg);
            command(out, "block segment");
            let _ = write!(out, ",\"seqno\":{},\"last\":{}", seg.seqno, seg.last);
            key(out, "segment_data");
            hex_string(out, seg.data.as_slice());
        }
        (Ok(msg), None) => fields(out, msg, roles, guard_reply),
        (Err(e), None) => {
            key(out, "error");
            display(out, &e);
        }
    }
    if let Some((source, fields)) = pdo {
        pdo_fields(out, *source, fields);
    }
    if let Some(d) = notes.deviation {
        key(out, "deviation");
        display(out, &d);
    }
    out.push('}');
}

/// `"mapping":..,"unmapped_bytes":..,"fields":[{"index":..,"sub":..,"bits":..,
/// "name":..,"raw":..,"kind":..,"value":..,"unit":..,"text":..}, ...]`.
fn pdo_fields(out: &mut String, source: Source, fields: &NamedFields) {
    key(out, "mapping");
    string(out, source.name());
    let _ = write!(out, ",\"unmapped_bytes\":{}", fields.unmapped_bytes());
    key(out, "fields");
    out.push('[');
    for (i, f) in fields.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        let _ = write!(
            out,
            "{{\"index\":{},\"sub\":{},\"bits\":{}",
            f.entry.index, f.entry.sub, f.entry.bits
        );
        key(out, "name");
        string(out, f.name);
        let _ = write!(out, ",\"raw\":{}", f.raw);
        key(out, "kind");
        string(out, f.value.kind());
        key(out, "value");
        if !field_value(out, &f.value, display) {
            out.push_str("null");
        }
        if let Some(unit) = f.value.unit() {
            key(out, "unit");
            string(out, unit.symbol());
        }
        key(out, "text");
        display(out, &f);
        out.push('}');
    }
    out.push(']');
}

fn fields(out: &mut String, msg: &Message, roles: &Roles, guard_reply: bool) {
    key(out, "text");
    display(out, &crate::log::words::Text { msg, guard_reply });
    if guard_reply {
        out.push_str(",\"guard_reply\":true");
    }
    match msg {
        Message::Nmt(c) => {
            key(out, "command");
            display(out, &c.command);
            let _ = write!(out, ",\"target\":{}", u8::from(c.target));
        }
        Message::Sync(s) => match s.counter {
            Some(c) => {
                let _ = write!(out, ",\"counter\":{c}");
            }
            None => out.push_str(",\"counter\":null"),
        },
        Message::Time(t) => {
            let _ = write!(out, ",\"days\":{},\"millis\":{}", t.days, t.millis);
            key(out, "utc");
            match crate::log::calendar::time_frame(t) {
                Some(utc) => string(out, &utc),
                None => out.push_str("null"),
            }
        }
        Message::Emcy { emcy, .. } => {
            let _ = write!(out, ",\"code\":{}", emcy.code.raw());
            key(out, "code_name");
            string(out, emcy.code.name());
            let _ = write!(out, ",\"register\":{}", emcy.register.bits());
            key(out, "mfr");
            hex_string(out, &emcy.manufacturer);
            key(out, "deltaq");
            match deltaq(msg, roles) {
                Some((label, description)) => {
                    out.push_str("{\"label\":");
                    string(out, &label);
                    key(out, "description");
                    string(out, description);
                    out.push('}');
                }
                None => out.push_str("null"),
            }
        }
        Message::Tpdo { pdo, payload, .. } | Message::Rpdo { pdo, payload, .. } => {
            let _ = write!(out, ",\"pdo\":{}", pdo.raw());
            key(out, "payload");
            hex_string(out, payload.as_slice());
        }
        Message::TpdoRequest { pdo, dlc, .. } => {
            let _ = write!(
                out,
                ",\"pdo\":{},\"request\":true,\"requested_dlc\":{dlc}",
                pdo.raw()
            );
        }
        Message::SdoRequest { sdo, .. } => sdo_command(out, sdo.command.view(), &CLIENT_NAMES),
        Message::SdoResponse { sdo, .. } => sdo_command(out, sdo.command.view(), &SERVER_NAMES),
        Message::Heartbeat { heartbeat, .. } => {
            key(out, "state");
            display(out, &heartbeat.state);
            let _ = write!(
                out,
                ",\"state_raw\":{},\"toggle\":{}",
                heartbeat.state.bits(),
                heartbeat.toggle
            );
        }
        Message::NodeGuardRequest { dlc, .. } => {
            let _ = write!(out, ",\"guard_request\":true,\"requested_dlc\":{dlc}");
        }
        Message::Lss(lss) => lss_fields(out, lss),
        Message::Unknown(_) => {}
    }
}

/// `direction` (`master_to_slave` / `slave_to_master`), `service` (a snake
/// case name, `unknown` for a frame kept raw) and the service's values.
fn lss_fields(out: &mut String, lss: &LssMessage) {
    let num = |out: &mut String, k: &str, v: u64| {
        key(out, k);
        let _ = write!(out, "{v}");
    };
    // A service that names an identity field (or the node-ID) and its value.
    let field_value = |out: &mut String, service: &str, field: &str, v: u64| {
        string(out, service);
        key(out, "field");
        string(out, field);
        num(out, "value", v);
    };
    key(out, "direction");
    string(
        out,
        match lss {
            LssMessage::Request(_) => "master_to_slave",
            LssMessage::Response(_) => "slave_to_master",
        },
    );
    key(out, "service");
    match lss {
        LssMessage::Request(r) => match *r {
            LssRequest::SwitchStateGlobal(mode) => {
                string(out, "switch_state_global");
                num(out, "mode", u8::from(mode).into());
            }
            LssRequest::SwitchStateSelective(field, v) => {
                field_value(out, "switch_state_selective", field.name(), v.into());
            }
            LssRequest::ConfigureNodeId(id) => {
                string(out, "configure_node_id");
                num(out, "node_id", id.into());
            }
            LssRequest::ConfigureBitTiming { table, index } => {
                string(out, "configure_bit_timing");
                num(out, "table", table.into());
                num(out, "index", index.into());
            }
            LssRequest::ActivateBitTiming { delay_ms } => {
                string(out, "activate_bit_timing");
                num(out, "delay_ms", delay_ms.into());
            }
            LssRequest::StoreConfiguration => string(out, "store_configuration"),
            LssRequest::Inquire(what) => {
                string(out, "inquire");
                key(out, "field");
                string(
                    out,
                    match what {
                        LssInquiry::Address(f) => f.name(),
                        LssInquiry::NodeId => "node_id",
                    },
                );
            }
            LssRequest::IdentifyRemoteSlave(part, v) => {
                field_value(
                    out,
                    "identify_remote_slave",
                    &part.name().replace(' ', "_"),
                    v.into(),
                );
            }
            LssRequest::IdentifyNonConfigured => {
                string(out, "identify_non_configured_remote_slave");
            }
            LssRequest::Fastscan(f) => {
                string(out, "fastscan");
                num(out, "id_number", f.id_number.into());
                num(out, "bit_checked", f.bit_checked.into());
                num(out, "lss_sub", f.sub.into());
                num(out, "lss_next", f.next.into());
            }
            _ => string(out, "unknown"),
        },
        LssMessage::Response(r) => match *r {
            LssResponse::SwitchStateSelective => string(out, "switch_state_selective_response"),
            LssResponse::ConfigureNodeId(s)
            | LssResponse::ConfigureBitTiming(s)
            | LssResponse::StoreConfiguration(s) => {
                string(
                    out,
                    match r {
                        LssResponse::ConfigureNodeId(_) => "configure_node_id_response",
                        LssResponse::ConfigureBitTiming(_) => "configure_bit_timing_response",
                        _ => "store_configuration_response",
                    },
                );
                num(out, "error_code", u8::from(s.code).into());
                num(out, "specific_error", s.specific.into());
            }
            LssResponse::Address(field, v) => {
                field_value(out, "inquire_response", field.name(), v.into());
            }
            LssResponse::NodeId(id) => {
                field_value(out, "inquire_response", "node_id", id.into());
            }
            LssResponse::IdentifySlave => string(out, "identify_slave"),
            LssResponse::IdentifyNonConfigured => string(out, "identify_non_configured_slave"),
            _ => string(out, "unknown"),
        },
    }
}

/// The SDO command's name: `"command":"<name>"`.
fn command(out: &mut String, name: &str) {
    key(out, "command");
    string(out, name);
}

/// A command whose only field is the t bit (an upload segment request,
/// a download segment acknowledgement).
fn toggle_command(out: &mut String, name: &str, toggle: bool) {
    command(out, name);
    let _ = write!(out, ",\"toggle\":{toggle}");
}

fn multiplexer(out: &mut String, name: &str, at: Address) {
    command(out, name);
    let _ = write!(out, ",\"index\":{},\"sub\":{}", at.index, at.sub);
}

/// An initiate that carries a payload (a download request, an upload
/// response): its multiplexer, then expedited data or the size.
fn initiate(out: &mut String, name: &str, at: Address, p: &InitiatePayload) {
    multiplexer(out, name, at);
    match p {
        InitiatePayload::Expedited {
            data,
            size_indicated,
        } => {
            let _ = write!(
                out,
                ",\"expedited\":true,\"size_indicated\":{size_indicated}"
            );
            key(out, "bytes");
            hex_string(out, data.as_slice());
        }
        InitiatePayload::Segmented { size } => {
            out.push_str(",\"expedited\":false,\"size\":");
            match size {
                Some(n) => {
                    let _ = write!(out, "{n}");
                }
                None => out.push_str("null"),
            }
        }
    }
}

fn abort(out: &mut String, at: Address, code: crate::abort::AbortCode) {
    multiplexer(out, "abort", at);
    let _ = write!(out, ",\"abort_code\":{}", code.to_u32());
    key(out, "abort_meaning");
    string(out, code.description());
}

fn segment(out: &mut String, name: &str, s: &crate::sdo::Segment) {
    command(out, name);
    let _ = write!(out, ",\"toggle\":{},\"last\":{}", s.toggle, s.last);
    key(out, "bytes");
    hex_string(out, s.data.as_slice());
}

/// One command of either side, `names` naming the side's shapes.
fn sdo_command(out: &mut String, view: CommandView<'_>, names: &Names) {
    match view {
        CommandView::Segment(s) => segment(out, names.segment.json, s),
        CommandView::Toggle(t) => toggle_command(out, names.toggle.json, t),
        CommandView::InitiateData(at, p) => initiate(out, names.initiate_data.json, at, p),
        CommandView::Initiate(at) => multiplexer(out, names.initiate.json, at),
        CommandView::Abort(at, code) => abort(out, at, code),
        CommandView::Block(BlockView::ClientUpload(_) | BlockView::ServerUpload(_)) => {
            command(out, "block_upload")
        }
        CommandView::Block(BlockView::ClientDownload(_) | BlockView::ServerDownload(_)) => {
            command(out, "block_download")
        }
        CommandView::Unknown(_) => command(out, "invalid"),
    }
}

/// The extra object after the frame that ended an SDO transfer:
/// `{"t":..,"kind":"sdo_transfer","node":..,"role":..,"direction":..,
/// "block":..,"crc_checked":..,"index":..,"sub":..,
/// "status":"complete"|"aborted"|"incomplete",
/// "size":..,"indicated_size":..,"size_indicated":..,"size_mismatch":..,
/// "truncated":..,"bytes":"hex","name":..,"value":..,"unit":..,
/// "meaning":..,"text":..}`, with `"abort":{"code":..,"meaning":..,"by":..}`
/// or `"incomplete":"why"` where the transfer did not complete (before
/// `text`), and `"pdo_config"` last when it changed a PDO's configuration.
/// `value`, `unit` and `meaning` are null unless it completed.
pub fn transfer(
    out: &mut String,
    r: &Report,
    roles: &Roles,
    eds: Option<crate::pdo::Catalogue>,
    pdo_config: Option<&str>,
) {
    let d = described(r, roles, eds);
    let complete = r.end == End::Complete;
    out.push_str("{\"t\":");
    match r.t {
        Some(t) => {
            let _ = write!(out, "{t}");
        }
        None => out.push_str("null"),
    }
    out.push_str(",\"kind\":\"sdo_transfer\"");
    let _ = write!(out, ",\"node\":{}", r.node.raw());
    key(out, "role");
    opt_text(out, roles.role(Some(r.node)));
    key(out, "direction");
    text(out, r.direction.name());
    let _ = write!(
        out,
        ",\"block\":{},\"crc_checked\":{},\"index\":{},\"sub\":{}",
        r.block, r.crc_checked, r.index, r.sub
    );
    key(out, "status");
    text(
        out,
        match r.end {
            End::Complete => "complete",
            End::Aborted { .. } => "aborted",
            End::Incomplete(_) => "incomplete",
        },
    );
    let _ = write!(out, ",\"size\":{},\"indicated_size\":", r.total);
    match r.indicated {
        Some(n) => {
            let _ = write!(out, "{n}");
        }
        None => out.push_str("null"),
    }
    let _ = write!(
        out,
        ",\"size_indicated\":{},\"size_mismatch\":{},\"truncated\":{}",
        r.size_indicated,
        r.size_mismatch().is_some(),
        r.truncated()
    );
    key(out, "bytes");
    hex_string(out, &r.bytes);
    key(out, "name");
    opt_text(out, d.name.as_deref());
    key(out, "value");
    match &d.value {
        Value::Number(n) if complete && is_number(n) => out.push_str(n),
        Value::Number(n) | Value::Text(n) if complete => text(out, n),
        _ => out.push_str("null"),
    }
    key(out, "unit");
    opt_text(out, d.unit.filter(|_| complete));
    key(out, "meaning");
    opt_text(out, d.meaning.as_deref().filter(|_| complete));
    match &r.end {
        End::Aborted { code, by } => {
            let _ = write!(out, ",\"abort\":{{\"code\":{}", code.to_u32());
            key(out, "meaning");
            text(out, code.description());
            key(out, "by");
            text(out, by.name());
            out.push('}');
        }
        End::Incomplete(why) => {
            key(out, "incomplete");
            text(out, why);
        }
        End::Complete => {}
    }
    key(out, "text");
    text(out, &sentence(r, &d));
    if let Some(note) = pdo_config {
        key(out, "pdo_config");
        text(out, note);
    }
    out.push('}');
}

/// Appends `s` as a JSON string escaped as serde_json escapes it (`\"`,
/// `\\`, `\b`, `\f`, `\n`, `\r`, `\t`, `\u00XX` for the other controls
/// below 20h): the objects serde_json once wrote keep their bytes.
pub fn text(out: &mut String, s: &str) {
    out.push('"');
    let mut rest = s;
    while let Some(at) = rest
        .bytes()
        .position(|b| b == b'"' || b == b'\\' || b < 0x20)
    {
        let (clean, tail) = rest.split_at(at);
        out.push_str(clean);
        let mut chars = tail.chars();
        match chars.next() {
            Some('"') => out.push_str("\\\""),
            Some('\\') => out.push_str("\\\\"),
            Some('\u{8}') => out.push_str("\\b"),
            Some('\u{c}') => out.push_str("\\f"),
            Some('\n') => out.push_str("\\n"),
            Some('\r') => out.push_str("\\r"),
            Some('\t') => out.push_str("\\t"),
            Some(c) => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            None => {}
        }
        rest = chars.as_str();
    }
    out.push_str(rest);
    out.push('"');
}

/// [`text`], or `null`.
pub fn opt_text(out: &mut String, s: Option<&str>) {
    match s {
        Some(s) => text(out, s),
        None => out.push_str("null"),
    }
}

/// True when `s` is a JSON number (RFC 8259, section 6): `-`, digits
/// without a leading zero, a fraction, an exponent.
pub fn is_number(s: &str) -> bool {
    let digits = |b: &[u8]| b.iter().take_while(|c| c.is_ascii_digit()).count();
    let b = s.as_bytes();
    let b = b.strip_prefix(b"-").unwrap_or(b);
    let int = digits(b);
    if int == 0 || (int > 1 && b.first() == Some(&b'0')) {
        return false;
    }
    let mut rest = b.get(int..).unwrap_or(&[]);
    if let Some(frac) = rest.strip_prefix(b".") {
        let n = digits(frac);
        if n == 0 {
            return false;
        }
        rest = frac.get(n..).unwrap_or(&[]);
    }
    if let Some(exp) = rest.strip_prefix(b"e").or_else(|| rest.strip_prefix(b"E")) {
        let exp = exp
            .strip_prefix(b"+")
            .or_else(|| exp.strip_prefix(b"-"))
            .unwrap_or(exp);
        let n = digits(exp);
        if n == 0 {
            return false;
        }
        rest = exp.get(n..).unwrap_or(&[]);
    }
    rest.is_empty()
}

/// Appends a JSON array of `items`, `item` writing each one (the commas
/// between them are written here): every list of the summary, the bus
/// load and the report's data goes through it.
///
/// ```
/// use canopen_codec::log::json::array;
/// let mut out = String::new();
/// array(&mut out, &[1, 2, 3], |out, n| out.push_str(&(n * 10).to_string()));
/// assert_eq!(out, "[10,20,30]");
/// ```
pub fn array<T>(out: &mut String, items: &[T], mut item: impl FnMut(&mut String, &T)) {
    out.push('[');
    for (i, x) in items.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        item(out, x);
    }
    out.push(']');
}

/// Appends `v` as serde_json writes an `f64`: the shortest digits that
/// read back as `v`, laid out as serde_json lays them out (`1.0`, `0.25`,
/// `1e-7`, `1.5e+300`), and `null` for NaN and the infinities. Where two
/// shortest digit strings are equally near `v` (a tie, only at 16 or 17
/// significant digits) std's pick may differ from serde_json's in the last
/// digit; both read back as `v` (`tests/decoder/log_json.rs`).
pub fn float(out: &mut String, v: f64) {
    if !v.is_finite() {
        out.push_str("null");
        return;
    }
    // `{:e}` gives the shortest round-trip digits: `-1.2345e-7`.
    let sci = format!("{v:e}");
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let (sign, mantissa) = match mantissa.strip_prefix('-') {
        Some(m) => ("-", m),
        None => ("", mantissa),
    };
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let exp: i32 = exp.parse().unwrap_or(0);
    out.push_str(sign);
    if digits.bytes().all(|d| d == b'0') {
        out.push_str("0.0");
        return;
    }
    let length = i32::try_from(digits.len()).unwrap_or(i32::MAX);
    // The value is 0.DIGITS * 10^kk.
    let kk = exp + 1;
    let k = kk - length;
    if 0 <= k && kk <= 16 {
        out.push_str(&digits);
        for _ in 0..k {
            out.push('0');
        }
        out.push_str(".0");
    } else if 0 < kk && kk <= 16 {
        let (head, tail) = digits.split_at(usize::try_from(kk).unwrap_or(0));
        out.push_str(head);
        out.push('.');
        out.push_str(tail);
    } else if -5 < kk && kk <= 0 {
        out.push_str("0.");
        for _ in 0..-kk {
            out.push('0');
        }
        out.push_str(&digits);
    } else {
        let (head, tail) = digits.split_at(1);
        out.push_str(head);
        if !tail.is_empty() {
            out.push('.');
            out.push_str(tail);
        }
        let _ = write!(out, "e{:+}", kk - 1);
    }
}
