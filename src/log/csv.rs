//! `--output csv`: one row per frame, for spreadsheets. Columns:
//!
//! | column | content |
//! |---|---|
//! | `time` | seconds with microseconds, as the trace gives it (empty when the line has none) |
//! | `id` | the identifier in hex (3 digits: 11-bit, 8 digits: 29-bit) |
//! | `extended`, `remote` | `1` or `0` |
//! | `dlc` | the length |
//! | `data` | the data bytes in hex, no spaces |
//! | `kind` | the CANopen object kind, as in the JSON output (`nmt`, `emcy`, `tpdo`, `heartbeat`, ...) |
//! | `node` | the node id, empty for NMT, SYNC, TIME |
//! | `role` | `charger`, `battery` or empty |
//! | `text` | the frame in words, as the words output's message column |
//! | `deviation` | how the frame deviates from CiA 301, empty when it does not |
//! | `error` | why the frame does not decode, empty when it does |
//!
//! Fields are quoted (RFC 4180) when they hold a comma, a quote or a line
//! break. SDO transfer and role lines of the other outputs are not rows.

use std::fmt::Write;
use std::prelude::rust_2021::*;

use crate::cob_id::classify;

use crate::log::Notes;

/// The header row.
pub const HEADER: &str = "time,id,extended,remote,dlc,data,kind,node,role,text,deviation,error";

/// Appends `field`, quoted when it needs to be.
pub fn field(out: &mut String, field: &str) {
    if field.contains([',', '"', '\n', '\r']) {
        out.push('"');
        out.push_str(&field.replace('"', "\"\""));
        out.push('"');
    } else {
        out.push_str(field);
    }
}

/// The `time` column.
pub fn time(
    out: &mut String,
    column: &mut crate::log::time_column::TimeColumn,
    timestamp: Option<crate::Timestamp>,
) {
    if let Some(t) = timestamp {
        column.write(out, t);
    }
}

/// The columns after `time` (the same for the same frame while roles and
/// mappings stay).
pub fn rest(out: &mut String, line: &crate::log::FrameLine<'_>) {
    let crate::log::FrameLine {
        log: l,
        decoded: m,
        roles,
        fields: _,
        notes,
    } = *line;
    let kind = classify(l.frame.id());
    let _ = write!(
        out,
        ",{},{},{},{},",
        l.frame.id(),
        u8::from(l.frame.id().is_extended()),
        u8::from(l.frame.is_remote()),
        l.frame.dlc()
    );
    for b in l.frame.data() {
        let _ = write!(out, "{b:02X}");
    }
    let _ = write!(out, ",{},", crate::log::json::kind_name(kind));
    if let Some(n) = kind.node() {
        let _ = write!(out, "{n}");
    }
    out.push(',');
    field(out, roles.role(kind.node()).unwrap_or(""));
    out.push(',');
    let mut text = String::new();
    if m.is_ok() || notes.block_segment.is_some() {
        let notes = Notes {
            deviation: None,
            ..*notes
        };
        crate::log::words::message(
            &mut text,
            &crate::log::FrameLine {
                notes: &notes,
                ..*line
            },
        );
    }
    field(out, &text);
    out.push(',');
    if let Some(d) = notes.deviation {
        field(out, &d.to_string());
    }
    out.push(',');
    if let (Err(e), None) = (m, notes.block_segment) {
        field(out, &e.to_string());
    }
}
