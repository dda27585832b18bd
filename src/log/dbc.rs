//! `--dbc FILE.dbc`: the PDO mappings in use, as a DBC file for CAN tools
//! (cantools, SavvyCAN, asammdf).
//!
//! The mappings are those the decoder applied to the log's PDO frames (a
//! role's defaults, an EDS, `--pdo`, or learned from SDO transfers in the
//! log), and every `--pdo` mapping besides, seen or not. One message per
//! COB-ID (`BO_`, named `TPDO0_node10` after the frame lines' numbering,
//! transmitted by `node10` for a TPDO), one signal per mapped object
//! (`SG_`): its start bit (the entry's offset in the mapping), its length,
//! Intel byte order (`@1`: CANopen is little-endian, CiA 301 section
//! 7.1), `+` unsigned or `-` signed from the object's type, the scale
//! `1/2^n` of a fixed-point object and no offset (the profiles define none),
//! the range of the raw bits scaled, and the unit. Bit fields and codes
//! are raw integers (scale 1). Padding has no signal. The comments (`CM_`)
//! give each message's origin and each signal's object (`2002h charging
//! current`).
//!
//! A COB-ID whose mapping changes during the log (a remapping by SDO)
//! keeps the first mapping applied; the change is reported on stderr.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::prelude::rust_2021::*;

use crate::cob_id::{classify_standard, CobKind};
use crate::pdo::{Catalogue, PdoMapping};

use crate::log::mappings::Source;
use crate::log::signals::describe;

/// The mappings collected for the DBC.
#[derive(Default)]
pub struct Dbc {
    messages: BTreeMap<u16, (Source, Catalogue, PdoMapping)>,
    /// COB-IDs whose mapping changed (reported once).
    changed: Vec<u16>,
}

/// A DBC identifier from an object's name: `charging current` gives
/// `charging_current`.
fn identifier(name: &str) -> String {
    let mut id = String::new();
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            id.push(c);
        } else if !id.ends_with('_') && !id.is_empty() {
            id.push('_');
        }
    }
    while id.ends_with('_') {
        id.pop();
    }
    if id.is_empty() || id.starts_with(|c: char| c.is_ascii_digit()) {
        id.insert_str(0, "obj_");
    }
    id
}

/// A DBC comment's text (no double quotes inside).
fn comment(text: &str) -> String {
    text.replace('"', "'")
}

impl Dbc {
    /// Notes the mapping applied to a frame on `cob_id`; returns the note
    /// for stderr the first time a COB-ID's mapping changes.
    pub fn frame(
        &mut self,
        cob_id: u16,
        source: Source,
        catalogue: Catalogue,
        mapping: PdoMapping,
    ) -> Option<String> {
        match self.messages.get(&cob_id) {
            None => {
                self.messages.insert(cob_id, (source, catalogue, mapping));
                None
            }
            Some((_, _, m)) if m.entries() != mapping.entries() => {
                if self.changed.contains(&cob_id) {
                    return None;
                }
                self.changed.push(cob_id);
                Some(format!(
                    "canopen-decode: --dbc: the mapping of {cob_id:03X}h changed during the log; the DBC has the first one"
                ))
            }
            Some(_) => None,
        }
    }

    /// Adds a mapping not seen in the log (a `--pdo` mapping).
    pub fn given(&mut self, cob_id: u16, catalogue: Catalogue, mapping: PdoMapping) {
        self.messages
            .entry(cob_id)
            .or_insert((Source::Given, catalogue, mapping));
    }

    /// The number of messages and the DBC text.
    pub fn text(&self) -> (usize, String) {
        let mut nodes: Vec<String> = Vec::new();
        let mut body = String::new();
        let mut comments = String::new();
        for (&cob_id, (source, catalogue, mapping)) in &self.messages {
            let (name, sender) = match classify_standard(cob_id) {
                CobKind::Tpdo(n, node) => (
                    format!("TPDO{}_node{node}", n.raw()),
                    Some(format!("node{node}")),
                ),
                CobKind::Rpdo(n, node) => (format!("RPDO{}_node{node}", n.raw()), None),
                _ => (format!("PDO_{cob_id:03X}h"), None),
            };
            let sender = match sender {
                Some(s) => {
                    if !nodes.contains(&s) {
                        nodes.push(s.clone());
                    }
                    s
                }
                None => "Vector__XXX".to_string(),
            };
            let _ = writeln!(body, "BO_ {cob_id} {name}: {} {sender}", mapping.byte_len());
            let _ = writeln!(
                comments,
                "CM_ BO_ {cob_id} \"{} on {cob_id:03X}h, mapping: {}\";",
                name.replace('_', " of "),
                source.name()
            );
            let mut used: Vec<String> = Vec::new();
            for (entry, offset) in mapping.entries().iter().zip(mapping.offsets()) {
                let Some(signal) = describe(*catalogue, *entry) else {
                    continue;
                };
                let base = if signal.known {
                    identifier(signal.name)
                } else {
                    format!("obj_{:04X}h_{:02X}", entry.index, entry.sub)
                };
                let mut sg = base.clone();
                let mut k = 2;
                while used.contains(&sg) {
                    sg = format!("{base}_{k}");
                    k += 1;
                }
                used.push(sg.clone());
                let bits = u32::from(entry.bits);
                let scale = 1.0 / (1u64 << signal.frac_bits) as f64;
                let (lo, hi) = if signal.signed {
                    let half = 2f64.powi(bits as i32 - 1);
                    (-half, half - 1.0)
                } else {
                    (0.0, 2f64.powi(bits as i32) - 1.0)
                };
                let _ = writeln!(
                    body,
                    " SG_ {sg} : {offset}|{bits}@1{} ({scale},0) [{}|{}] \"{}\" Vector__XXX",
                    if signal.signed { '-' } else { '+' },
                    lo * scale,
                    hi * scale,
                    signal.unit.map_or("", |u| u.symbol())
                );
                let mut object = format!("{:04X}h", entry.index);
                if entry.sub != 0 {
                    let _ = write!(object, ":{:02X}", entry.sub);
                }
                let _ = writeln!(
                    comments,
                    "CM_ SG_ {cob_id} {sg} \"{object} {}\";",
                    comment(signal.name)
                );
            }
            body.push('\n');
        }
        let mut out = String::from("VERSION \"\"\n\nNS_ :\n\nBS_:\n\nBU_:");
        for n in &nodes {
            out.push(' ');
            out.push_str(n);
        }
        out.push_str("\n\n");
        out.push_str(&body);
        out.push_str(&comments);
        (self.messages.len(), out)
    }
}
