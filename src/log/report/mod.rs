//! `--report FILE.html`: the session as one self-contained page (scripts
//! and styles inline, no network access): the bus summary at the top, a
//! timeline per node (NMT states from the heartbeats, silences marked,
//! boot-ups, EMCYs by name, SDO transfers and aborts, node guarding, NMT
//! commands on the bus row), the bus's traffic as plots for any trace (the
//! bus load per 1-second window, CAN FD and error frames included as the
//! summary counts them, the frames per second of each node, and
//! the raw bytes of the PDOs no mapping names) and a plot of every named
//! PDO field over time with its unit, zoom, pan and values on hover. A
//! node with no frame of its own (only addressed by NMT commands) has no
//! row: its marks go to the bus row.
//!
//! Memory is bounded by the number of nodes and fields, not by the log:
//! each field is decimated as it streams in ([`series`]: the lowest and
//! highest sample per column, every sample of a short series), and each
//! node keeps at most [`MAX_MARKS`] marks and [`MAX_STATES`] state changes
//! for drawing; the page says how many it did not draw, and the summary
//! above it counts everything.

mod page;
pub mod series;

use std::collections::BTreeMap;
use std::prelude::rust_2021::*;

use crate::nmt::NmtTarget;
use crate::pdo::{FieldValue, NamedFields};
use crate::{Message, NodeId, Timestamp};

use crate::log::bus_load::DEFAULT_BITRATE;
use crate::log::sdo::{End, Report as Transfer};
use crate::log::summary::Decoded;
use crate::log::Roles;
use series::{PerSecond, Series};

/// Marks drawn per timeline row (more are counted, not drawn).
pub const MAX_MARKS: usize = 5000;
/// State changes drawn per timeline row (more are counted, not drawn).
pub const MAX_STATES: usize = 5000;
/// PDO COB-IDs without a mapping whose bytes are plotted (the first seen;
/// more are counted, not drawn).
pub const MAX_RAW_PDOS: usize = 8;
/// Nodes whose frames per second are plotted (those with the most frames;
/// more are counted, not drawn).
pub const MAX_NODE_PLOTS: usize = 16;

/// What a mark on a node's timeline is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum MarkKind {
    /// A boot-up.
    BootUp,
    /// An EMCY.
    Emcy,
    /// An EMCY error reset (no error).
    EmcyReset,
    /// A completed SDO transfer.
    Sdo,
    /// An aborted SDO transfer.
    SdoAbort,
    /// An SDO transfer broken off.
    SdoIncomplete,
    /// A node-guarding request.
    GuardRequest,
    /// An NMT command.
    Nmt,
}

impl MarkKind {
    /// The name the page's script draws it by.
    pub const fn name(self) -> &'static str {
        match self {
            MarkKind::BootUp => "boot-up",
            MarkKind::Emcy => "emcy",
            MarkKind::EmcyReset => "emcy-reset",
            MarkKind::Sdo => "sdo",
            MarkKind::SdoAbort => "sdo-abort",
            MarkKind::SdoIncomplete => "sdo-incomplete",
            MarkKind::GuardRequest => "guard",
            MarkKind::Nmt => "nmt",
        }
    }
}

/// A mark: when (µs since the log's start), what, and its text.
struct Mark {
    t: u64,
    kind: MarkKind,
    text: String,
}

/// One node's timeline (node 0: the bus row, for NMT commands).
#[derive(Default)]
struct Row {
    /// State changes: when, and the state from then on.
    states: Vec<(u64, String)>,
    state: Option<String>,
    states_not_drawn: u64,
    last_heartbeat: Option<u64>,
    marks: Vec<Mark>,
    not_drawn: BTreeMap<MarkKind, u64>,
}

impl Row {
    fn mark(&mut self, t: u64, kind: MarkKind, text: String) {
        if self.marks.len() < MAX_MARKS {
            self.marks.push(Mark { t, kind, text });
        } else {
            *self.not_drawn.entry(kind).or_default() += 1;
        }
    }

    fn state(&mut self, t: u64, state: String) {
        if self.state.as_deref() == Some(state.as_str()) {
            return;
        }
        self.state = Some(state.clone());
        if self.states.len() < MAX_STATES {
            self.states.push((t, state));
        } else {
            self.states_not_drawn += 1;
        }
    }
}

/// A field plotted: its COB-ID and object, name, unit and samples.
struct Field {
    cob_id: u32,
    index: u16,
    sub: u8,
    name: &'static str,
    unit: Option<&'static str>,
    /// A bit field or code, plotted as its raw bits (a step line).
    raw: bool,
    series: Series,
}

/// The bus's traffic over time, for any trace.
#[derive(Default)]
struct Traffic {
    /// Stuffed bit times at the nominal rate per window (the bus load
    /// once divided by the rate).
    bits: PerSecond,
    /// Frames per window of each node (0: frames of no node), and their
    /// count.
    nodes: BTreeMap<u8, (u64, PerSecond)>,
    /// The bytes of PDOs without a mapping: COB-ID -> one series per byte.
    raw_pdos: BTreeMap<u32, Vec<Series>>,
    /// PDO COB-IDs without a mapping past [`MAX_RAW_PDOS`].
    raw_pdos_not_drawn: std::collections::BTreeSet<u32>,
}

/// The report being collected.
pub struct Collector {
    start: Option<Timestamp>,
    /// The latest time seen (µs since the start).
    last: u64,
    rows: BTreeMap<u8, Row>,
    fields: BTreeMap<(u32, u16, u8), Field>,
    /// The bit rate of the bus-load plot (bit/s).
    bitrate: u32,
    traffic: Traffic,
}

impl Default for Collector {
    fn default() -> Self {
        Collector::with_bitrate(None)
    }
}

impl Collector {
    /// A report whose bus-load plot is at `bitrate` bit/s (`None` or 0:
    /// [`DEFAULT_BITRATE`], as the summary assumes).
    #[must_use]
    pub fn with_bitrate(bitrate: Option<u32>) -> Self {
        Collector {
            start: None,
            last: 0,
            rows: BTreeMap::new(),
            fields: BTreeMap::new(),
            bitrate: bitrate.filter(|&b| b > 0).unwrap_or(DEFAULT_BITRATE),
            traffic: Traffic::default(),
        }
    }

    /// Any frame read, decoded or not (CAN FD and error frames included),
    /// with its time on the bus in bit times at the nominal rate (as
    /// [`crate::log::summary::Summary::bus_frame`] gives it): the bus load
    /// and the frames per second of the node its COB-ID belongs to (none:
    /// an error frame, in the load only).
    pub fn bus_frame(&mut self, t: Option<Timestamp>, id: Option<crate::CanId>, bit_times: f64) {
        let t = self.at(t);
        self.traffic.bits.add(t, bit_times);
        let node = match id {
            Some(crate::CanId::Standard(raw)) => crate::cob_id::classify_standard(raw)
                .node()
                .map_or(0, |n| n.raw()),
            Some(crate::CanId::Extended(_)) => 0,
            None => return,
        };
        let (count, per_second) = self.traffic.nodes.entry(node).or_default();
        *count = count.saturating_add(1);
        per_second.add(t, 1.0);
    }

    /// A PDO's bytes when no mapping names its fields.
    fn raw_pdo(&mut self, t: u64, cob_id: u32, data: &[u8]) {
        let traffic = &mut self.traffic;
        if !traffic.raw_pdos.contains_key(&cob_id) && traffic.raw_pdos.len() >= MAX_RAW_PDOS {
            traffic.raw_pdos_not_drawn.insert(cob_id);
            return;
        }
        let bytes = traffic.raw_pdos.entry(cob_id).or_default();
        for (i, &b) in data.iter().enumerate() {
            if bytes.len() <= i {
                bytes.push(Series::default());
            }
            if let Some(s) = bytes.get_mut(i) {
                s.push(t, f64::from(b));
            }
        }
    }

    /// Microseconds since the log's first frame (a frame without a time
    /// takes the latest one seen).
    fn at(&mut self, t: Option<Timestamp>) -> u64 {
        let Some(t) = t else { return self.last };
        let start = *self.start.get_or_insert(t);
        let us = t.saturating_micros_since(start);
        self.last = self.last.max(us);
        us
    }

    fn row(&mut self, node: NodeId) -> &mut Row {
        self.rows.entry(node.raw()).or_default()
    }

    /// One decoded frame; `fields` are its named PDO fields.
    pub fn frame(&mut self, seen: &Decoded<'_>, fields: Option<&NamedFields>) {
        let Decoded {
            t,
            cob_id,
            msg,
            guard_reply,
            roles,
            ..
        } = *seen;
        let t = self.at(t);
        match msg {
            Message::Heartbeat { node, heartbeat } => {
                let row = self.row(*node);
                if heartbeat.is_boot_up() {
                    row.mark(t, MarkKind::BootUp, format!("node {node} boot-up"));
                    row.state(t, "boot-up".into());
                } else {
                    row.state(t, heartbeat.state.to_string());
                }
                if !guard_reply {
                    row.last_heartbeat = Some(t);
                }
            }
            Message::NodeGuardRequest { node, .. } => {
                self.row(*node)
                    .mark(t, MarkKind::GuardRequest, "node-guarding request".into());
            }
            Message::Emcy { node, emcy } => {
                let (kind, text) = if emcy.is_reset() {
                    (MarkKind::EmcyReset, "EMCY error reset".to_string())
                } else {
                    let charger = roles.is_deltaq_charger(*node);
                    (
                        MarkKind::Emcy,
                        crate::log::summary::emcy_text(emcy, charger),
                    )
                };
                self.row(*node).mark(t, kind, text);
            }
            Message::Nmt(cmd) => {
                let text = msg.to_string();
                match cmd.target {
                    NmtTarget::Node(n) => self.row(n).mark(t, MarkKind::Nmt, text),
                    _ => self.rows.entry(0).or_default().mark(t, MarkKind::Nmt, text),
                }
            }
            Message::Tpdo { .. } | Message::Rpdo { .. } => match fields {
                Some(fields) => self.pdo(t, cob_id, fields),
                None => self.raw_pdo(t, cob_id, seen.frame.data()),
            },
            _ => {}
        }
    }

    /// A PDO's named fields: numbers as values, bit fields and codes as
    /// their raw bits, the "invalid" and "no value" markers as gaps.
    fn pdo(&mut self, t: u64, cob_id: u32, fields: &NamedFields) {
        for f in fields {
            let (raw, sample) = match &f.value {
                v @ (FieldValue::Scaled { .. }
                | FieldValue::OutOfRange { .. }
                | FieldValue::Narrowed { .. }) => {
                    (false, v.number().map_or(f64::NAN, |n| n.to_f64()))
                }
                FieldValue::Flags(_) | FieldValue::Formatted(_) => (true, f.raw as f64),
                FieldValue::Invalid | FieldValue::NoValue => (false, f64::NAN),
                _ => continue,
            };
            let key = (cob_id, f.entry.index, f.entry.sub);
            let field = self.fields.entry(key).or_insert_with(|| Field {
                cob_id,
                index: f.entry.index,
                sub: f.entry.sub,
                name: f.name,
                unit: f.value.unit().map(|u| u.symbol()),
                raw,
                series: Series::default(),
            });
            // A field first seen as a marker takes its kind and unit from
            // its first value.
            if field.series.samples == field.series.invalid && sample.is_finite() {
                field.raw = raw;
                field.unit = field.unit.or(f.value.unit().map(|u| u.symbol()));
            }
            field.series.push(t, sample);
        }
    }

    /// A finished SDO transfer, with its line in words.
    pub fn transfer(&mut self, transfer: &Transfer, text: &str) {
        let t = self.at(transfer.t);
        let kind = match transfer.end {
            End::Complete => MarkKind::Sdo,
            End::Aborted { .. } => MarkKind::SdoAbort,
            _ => MarkKind::SdoIncomplete,
        };
        self.row(transfer.node).mark(t, kind, text.to_string());
    }

    /// The page: `title` names the log, `summary` is the bus summary in
    /// words, `silences` the heartbeat silences it found (node, from, to;
    /// `None`: until the end).
    pub fn page(
        &self,
        title: &str,
        summary: &str,
        silences: &[(u8, Timestamp, Option<Timestamp>)],
        roles: &Roles,
    ) -> String {
        page::write(self, title, summary, silences, roles)
    }
}
