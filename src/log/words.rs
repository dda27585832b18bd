//! One line of words per frame.

use std::fmt::Write;
use std::prelude::rust_2021::*;

use crate::cob_id::classify;
use crate::deltaq::DeltaQCode;
use crate::pdo::{Catalogue, FieldValue, NamedFields};
use crate::{Message, NodeId};

use crate::log::mappings::Source;
use crate::log::naming::describe;
use crate::log::sdo::{End, Report, Side};
use crate::log::sdo_value::{quote, Described, Role};
use crate::log::Roles;

/// A message in words; a frame on 700h + node that answers a node-guarding
/// remote request is a guarding reply whatever its toggle bit (CiA 301:
/// the toggle alternates from 0), not a heartbeat.
pub struct Text<'a> {
    /// The message.
    pub msg: &'a Message,
    /// It answers a node-guarding request.
    pub guard_reply: bool,
}

impl std::fmt::Display for Text<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.msg {
            Message::Heartbeat { node, heartbeat } if self.guard_reply => write!(
                f,
                "node guarding reply node {node}: {}, toggle {}",
                heartbeat.state,
                u8::from(heartbeat.toggle)
            ),
            msg => write!(f, "{msg}"),
        }
    }
}

/// The time column of a frame's line, `1756955653.612992` in
/// `1756955653.612992  08A  charger  EMCY node 10: 8130h ..., Delta-Q E-0-3-2 heartbeat lost`.
pub fn time(
    out: &mut String,
    column: &mut crate::log::time_column::TimeColumn,
    timestamp: Option<crate::Timestamp>,
) {
    match timestamp {
        Some(t) => column.write(out, t),
        None => out.push_str("                -"),
    }
}

/// Everything after the time column: identifier, role and message (the
/// same for the same frame while roles and mappings stay).
pub fn rest(out: &mut String, line: &crate::log::FrameLine<'_>) {
    let crate::log::FrameLine {
        log: l,
        decoded: _m,
        roles,
        fields: _,
        notes: _,
    } = *line;
    let id = l.frame.id();
    let (raw, width) = match id {
        crate::CanId::Standard(r) => (u32::from(r), 3),
        crate::CanId::Extended(r) => (r, 8),
    };
    let mut hex = [b' '; 8];
    for (k, slot) in hex.iter_mut().rev().take(width).enumerate() {
        *slot = b"0123456789ABCDEF"[((raw >> (4 * k)) & 0xF) as usize];
    }
    out.push_str("  ");
    out.push_str(std::str::from_utf8(&hex).unwrap_or(""));
    out.push_str("  ");
    let role = roles.role(classify(id).node()).unwrap_or("-");
    out.push_str(role);
    for _ in role.len()..7 {
        out.push(' ');
    }
    out.push_str("  ");
    message(out, line);
}

/// The message part of a line (after the time, identifier and role
/// columns): what the CSV output's `text` column holds too.
pub fn message(out: &mut String, line: &crate::log::FrameLine<'_>) {
    let crate::log::FrameLine {
        log: l,
        decoded: m,
        roles,
        fields,
        notes,
    } = *line;
    let guard_reply = notes.guard_reply;
    if let Some(seg) = &notes.block_segment {
        let _ = write!(out, "{seg}");
        return;
    }
    match m {
        Ok(msg) => {
            let _ = write!(out, "{}", Text { msg, guard_reply });
            if let Message::Time(t) = msg {
                match crate::log::calendar::time_frame(t) {
                    Some(utc) => {
                        let _ = write!(out, " = {utc}");
                    }
                    None => out.push_str(" (not a time of day: 86 400 000 ms or more)"),
                }
            }
            if let Some((label, description)) = deltaq(msg, roles) {
                let _ = write!(out, ", Delta-Q {label} {description}");
            }
            if let Some((source, fields)) = fields {
                pdo_fields(out, *source, fields);
            }
            if let Some(d) = notes.deviation {
                let _ = write!(out, " [deviates: {d}]");
            }
        }
        Err(e) => {
            let _ = write!(
                out,
                "malformed {:?} frame {}: {e}",
                classify(l.frame.id()),
                l.frame
            );
        }
    }
}

/// The Delta-Q label and description of a Delta-Q charger's EMCY, if it
/// carries a code (none without Delta-Q evidence: see [`Roles`]).
pub fn deltaq(msg: &Message, roles: &Roles) -> Option<(String, &'static str)> {
    let Message::Emcy { node, emcy } = msg else {
        return None;
    };
    if !roles.is_deltaq_charger(*node) || emcy.is_reset() {
        return None;
    }
    let code = DeltaQCode::from_emergency(emcy);
    let description = code
        .entry()
        .map_or("unknown Delta-Q code", |e| e.description);
    Some((code.to_string(), description))
}

/// ` = 2002h charging current 19.45 A; ...`: numbers rounded to at most 2
/// decimals (`{:#.2}`: `82 V`, `19.45 A`), padding
/// left out, the source named when it is a default.
fn pdo_fields(out: &mut String, source: Source, fields: &NamedFields) {
    out.push_str(" =");
    if source != Source::Given {
        let _ = write!(out, " [{}]", source.name());
    }
    let mut first = true;
    for f in fields.iter().filter(|f| f.value != FieldValue::Padding) {
        let _ = write!(out, "{} {f:#.2}", if first { "" } else { ";" });
        first = false;
    }
    if fields.unmapped_bytes() > 0 {
        let _ = write!(out, " (+{} unmapped bytes)", fields.unmapped_bytes());
    }
}

/// The role of a node, for naming its objects.
pub fn role(node: NodeId, roles: &Roles) -> Role {
    match roles.role(Some(node)) {
        Some("charger") if roles.is_deltaq_charger(node) => Role::DeltaQCharger,
        Some("charger") => Role::Charger,
        Some("battery") => Role::Battery,
        _ => Role::Other,
    }
}

/// The name and meaning of a complete transfer's value; `eds` is the
/// catalogue built from the node's EDS (`--eds`), which names its objects.
pub fn described(r: &Report, roles: &Roles, eds: Option<Catalogue>) -> Described {
    describe(
        r.index,
        r.sub,
        &r.bytes,
        role(r.node, roles),
        roles.deltaq.is_some(),
        eds,
        r.size_indicated,
    )
}

fn hex_spaced(bytes: &[u8]) -> String {
    let v: Vec<String> = bytes.iter().map(|b| format!("{b:02X}")).collect();
    v.join(" ")
}

/// `SDO upload 1008h:00 from node 1: 26 bytes "Tiny ..." (manufacturer
/// device name)`, `SDO download 1017h:00 to node 2: A0 0F (producer
/// heartbeat time: 4000 ms)`, `SDO upload 1018h:01 from node 2 aborted:
/// 06090011h Sub-index does not exist`.
pub fn sentence(r: &Report, d: &Described) -> String {
    let mut s = format!(
        "SDO {} {:04X}h:{:02X} {} node {}",
        r.protocol(),
        r.index,
        r.sub,
        r.direction.preposition(),
        r.node
    );
    let so_far = |s: &mut String| {
        let _ = write!(s, " ({} bytes transferred", r.total);
        if let Some(n) = r.indicated {
            let _ = write!(s, " of {n} indicated");
        }
        s.push(')');
    };
    match &r.end {
        End::Aborted { code, by } => {
            match by {
                Side::Server => s.push_str(" aborted: "),
                Side::Client => s.push_str(" aborted by the client: "),
            }
            let _ = write!(s, "{code}");
            if r.total > 0 {
                so_far(&mut s);
            }
            return s;
        }
        End::Incomplete(why) => {
            let _ = write!(s, " incomplete: {why}");
            so_far(&mut s);
            return s;
        }
        End::Complete => {}
    }
    s.push_str(": ");
    // The value's size: what was transferred, but the indicated size of an
    // upload that sent more (the value kept, as python-canopen keeps it).
    let size = if r.truncated() {
        r.total
    } else {
        r.bytes.len()
    };
    if d.string {
        let _ = write!(s, "{size} bytes {}", quote(&r.bytes));
    } else if size == 0 {
        s.push_str("0 bytes");
    } else if size <= 8 {
        s.push_str(&hex_spaced(&r.bytes));
    } else {
        let _ = write!(s, "{size} bytes {}", hex_spaced(&r.bytes));
    }
    match (&d.name, &d.meaning) {
        (Some(n), Some(m)) => {
            let _ = write!(s, " ({n}: {m})");
        }
        (Some(n), None) => {
            let _ = write!(s, " ({n})");
        }
        (None, Some(m)) => {
            let _ = write!(s, " ({m})");
        }
        (None, None) => {}
    }
    if r.truncated() {
        let _ = write!(
            s,
            " [truncated: the first {} of {} bytes kept]",
            r.bytes.len(),
            r.total
        );
    }
    if let Some(n) = r.size_mismatch() {
        let _ = write!(
            s,
            " [size mismatch: {n} bytes indicated, {} transferred]",
            r.total
        );
    }
    if !r.size_indicated {
        s.push_str(" [size not indicated]");
    }
    if r.crc_checked {
        s.push_str(" [CRC checked]");
    }
    if let (Some(b), None) = (&r.broken, r.size_mismatch()) {
        let _ = write!(s, " [{b}; accepted]");
    }
    s
}

/// The extra line after the frame that ended a transfer, in the columns of
/// the frame lines with `transfer` in the identifier column.
pub fn transfer(out: &mut String, r: &Report, roles: &Roles, eds: Option<Catalogue>) {
    match r.t {
        Some(t) => {
            // Right-aligned in 17 columns, without a temporary string.
            let (secs, micros) = (t.as_micros() / 1_000_000, t.as_micros() % 1_000_000);
            let _ = write!(out, "{secs:>10}.{micros:06}");
        }
        None => out.push_str("                -"),
    }
    let _ = write!(
        out,
        "  transfer  {:<7}  {}",
        roles.role(Some(r.node)).unwrap_or("-"),
        sentence(r, &described(r, roles, eds))
    );
}
