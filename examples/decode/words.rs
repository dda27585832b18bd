//! One line of words per frame.

use std::fmt::Write;

use canopen_codec::candump::LogLine;
use canopen_codec::cob_id::classify;
use canopen_codec::deltaq::DeltaQCode;
use canopen_codec::pdo::{FieldValue, NamedFields};
use canopen_codec::{DecodeError, Message};

use crate::pdo_args::Source;
use crate::Roles;

/// `1756955653.612992  08A  charger  EMCY node 10: 8130h ..., Delta-Q E-0-3-2 heartbeat lost`
pub fn line(
    out: &mut String,
    l: &LogLine<'_>,
    m: &Result<Message, DecodeError>,
    roles: &Roles,
    fields: Option<&(Source, NamedFields)>,
) {
    match l.timestamp {
        Some(t) => {
            let _ = write!(out, "{:>17}", t.to_string());
        }
        None => out.push_str("                -"),
    }
    let node = classify(l.frame.id()).node();
    let _ = write!(
        out,
        "  {:>8}  {:<7}  ",
        l.frame.id().to_string(),
        roles.role(node).unwrap_or("-")
    );
    match m {
        Ok(msg) => {
            let _ = write!(out, "{msg}");
            if let Some((label, description)) = deltaq(msg, roles) {
                let _ = write!(out, ", Delta-Q {label} {description}");
            }
            if let Some((source, fields)) = fields {
                pdo_fields(out, *source, fields);
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

/// The Delta-Q label and description of a charger's EMCY, if it carries a code.
pub fn deltaq(msg: &Message, roles: &Roles) -> Option<(String, &'static str)> {
    let Message::Emcy { node, emcy } = msg else {
        return None;
    };
    if *node != roles.charger || emcy.is_reset() {
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
