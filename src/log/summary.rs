//! `--summary`: the bus health of a log, per node and per PDO, after the
//! frames (or alone with `--summary-only`). Memory is bounded by the number
//! of nodes and COB-IDs, not by the log's length: the heartbeat period is
//! the median of a node's first [`PERIOD_SAMPLES`] gaps.
//!
//! Per node: its role, the NMT states its heartbeats reported and the
//! transitions, the heartbeat period (median) and the largest gap, every
//! silence longer than 3 periods (with its end, or "until the end of the
//! log"), boot-ups and whether an NMT reset preceded them, EMCYs with their
//! names (Delta-Q labels on a Delta-Q charger) and whether an error reset cleared
//! them, SDO transfers (count, aborts with object and code), node-guarding
//! requests and replies. Per PDO COB-ID: frames and rate. LSS (CiA 305):
//! frames, fastscans started, and the node-IDs a slave accepted by
//! configure node-ID. The bus load ([`crate::log::bus_load`]): the mean,
//! the busiest 1-second window, each node's and COB-ID's share, error
//! frames and CAN FD frames (both in the load). A node is listed when it
//! has something to say (a node addressed by NMT commands that never sends
//! is not). `--check` makes
//! the program exit 3 when a problem is still open at the end: a node
//! silent until the end, or an EMCY not cleared.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::prelude::rust_2021::*;

use crate::deltaq::DeltaQCode;
use crate::lss::{Fastscan, LssMessage, LssRequest, LssResponse};
use crate::nmt::{NmtCommandSpecifier, NmtState, NmtTarget};
use crate::{CanFrame, Message, NodeId, Timestamp};

use crate::log::bus_load::BusLoad;
use crate::log::sdo::{End, Report};
use crate::log::Roles;
use crate::trace::OnBus;

/// Heartbeat gaps kept per node for the period (the median of them).
pub const PERIOD_SAMPLES: usize = 64;
/// At most this many items of a kind are listed per node (counted beyond).
const LISTED: usize = 32;

#[derive(Default)]
struct Node {
    heartbeats: u64,
    last_heartbeat: Option<Timestamp>,
    gaps: Vec<u64>,
    /// The median of `gaps`, recomputed only when a gap is added.
    period: Option<u64>,
    largest_gap: u64,
    /// (start, end) of gaps longer than 3 periods; end `None`: until the end.
    silences: Vec<(Timestamp, Option<Timestamp>)>,
    state: Option<NmtState>,
    transitions: Vec<(Timestamp, NmtState)>,
    boot_ups: Vec<(Timestamp, Option<&'static str>)>,
    /// The last NMT reset addressed to this node, not yet followed by a boot-up.
    reset_pending: Option<&'static str>,
    /// EMCYs: time, text, cleared.
    emcys: Vec<(Timestamp, String, bool)>,
    emcys_more: u64,
    sdo_transfers: u64,
    sdo_aborts: Vec<String>,
    guard_requests: u64,
    guard_replies: u64,
}

impl Node {
    /// Nothing to list: only addressed (an NMT reset), never heard.
    fn is_empty(&self) -> bool {
        self.heartbeats == 0
            && self.boot_ups.is_empty()
            && self.emcys.is_empty()
            && self.emcys_more == 0
            && self.sdo_transfers == 0
            && self.guard_requests == 0
            && self.guard_replies == 0
    }
}

/// The summary being collected.
#[derive(Default)]
pub struct Summary {
    nodes: BTreeMap<u8, Node>,
    /// COB-ID -> (frames, first, last).
    pdos: BTreeMap<u32, (u64, Timestamp, Timestamp)>,
    first: Option<Timestamp>,
    last: Option<Timestamp>,
    lss: Lss,
    /// The silences until the end are closed ([`Summary::finish`]).
    finished: bool,
    /// The bus load of every frame read.
    bus: BusLoad,
}

/// LSS traffic: frames, fastscans (reset steps) and accepted node-IDs.
#[derive(Default)]
struct Lss {
    frames: u64,
    fastscans: u64,
    /// The node-ID of the last configure node-ID request.
    asked: Option<u8>,
    configured: Vec<u8>,
}

/// A time as the log gives it.
fn secs(t: Timestamp) -> String {
    t.to_string()
}

/// One decoded frame as the pipeline hands it to the summary and to the
/// report.
#[derive(Clone, Copy, Debug)]
pub struct Decoded<'a> {
    /// Its time, if the log gives one.
    pub t: Option<Timestamp>,
    /// Its identifier.
    pub cob_id: u32,
    /// The frame itself.
    pub frame: &'a CanFrame,
    /// What it carries.
    pub msg: &'a Message,
    /// A heartbeat-shaped frame that answers a node-guarding request (CiA
    /// 301 section 7.2.8.3.2.1: the reply has the heartbeat's identifier).
    pub guard_reply: bool,
    /// Which nodes are the charger and the battery module.
    pub roles: &'a Roles,
}

impl Summary {
    /// A summary whose bus load is at `bitrate` bit/s (`None`: assumed,
    /// [`crate::log::bus_load::DEFAULT_BITRATE`]), CAN FD data phases at
    /// `data_bitrate` (`None`: assumed,
    /// [`crate::log::bus_load::DEFAULT_DATA_BITRATE`]).
    #[must_use]
    pub fn with_bitrates(bitrate: Option<u32>, data_bitrate: Option<u32>) -> Self {
        Summary {
            bus: BusLoad::new(bitrate).with_data_bitrate(data_bitrate),
            ..Summary::default()
        }
    }

    /// The bus load so far.
    #[must_use]
    pub fn bus_load(&self) -> &BusLoad {
        &self.bus
    }

    /// Any classic frame read, decoded or not, for the bus load; returns
    /// its time on the bus in bit times at the nominal rate.
    pub fn bus_frame(&mut self, t: Option<Timestamp>, frame: &CanFrame) -> f64 {
        let bits = self.bus.frame(t, frame);
        self.bus.nominal_bit_times(self.bus.time(&bits).stuffed)
    }

    /// A CAN FD or error frame read (not decoded), for the bus load;
    /// returns its time on the bus as [`Summary::bus_frame`] does.
    pub fn on_bus(&mut self, t: Option<Timestamp>, what: &OnBus) -> f64 {
        let bits = self.bus.on_bus(t, what);
        self.bus.nominal_bit_times(self.bus.time(&bits).stuffed)
    }

    /// A CAN FD frame read without its identifier and data: counted beside
    /// the bus load.
    pub fn fd_frame_not_read(&mut self) {
        self.bus.fd_frame_not_read();
    }

    fn node(&mut self, n: NodeId) -> &mut Node {
        self.nodes.entry(n.raw()).or_default()
    }

    /// One decoded frame.
    pub fn frame(&mut self, seen: &Decoded<'_>) {
        let Decoded {
            t,
            cob_id: id,
            msg,
            guard_reply,
            roles,
            ..
        } = *seen;
        let t = t.or(self.last).unwrap_or(Timestamp::ZERO);
        self.first.get_or_insert(t);
        self.last = Some(self.last.map_or(t, |l| l.max(t)));
        match *msg {
            Message::Nmt(cmd) => {
                let what = match cmd.command {
                    NmtCommandSpecifier::ResetNode => "reset node",
                    NmtCommandSpecifier::ResetCommunication => "reset communication",
                    _ => return,
                };
                let targets: Vec<NodeId> = match cmd.target {
                    NmtTarget::Node(n) => vec![n],
                    NmtTarget::All => self.nodes.keys().filter_map(|k| NodeId::new(*k)).collect(),
                    _ => Vec::new(),
                };
                for n in targets {
                    self.node(n).reset_pending = Some(what);
                }
            }
            Message::Heartbeat { node, heartbeat } => {
                let n = self.node(node);
                if guard_reply {
                    n.guard_replies += 1;
                } else {
                    n.heartbeats += 1;
                    if let Some(prev) = n.last_heartbeat {
                        let gap = t.saturating_micros_since(prev);
                        n.largest_gap = n.largest_gap.max(gap);
                        if n.gaps.len() < PERIOD_SAMPLES {
                            n.gaps.push(gap);
                            n.period = period(&n.gaps);
                        }
                        if let Some(p) = n.period {
                            if gap > p.saturating_mul(3) && n.silences.len() < LISTED {
                                n.silences.push((prev, Some(t)));
                            }
                        }
                    }
                    n.last_heartbeat = Some(t);
                }
                if heartbeat.is_boot_up() {
                    let after = n.reset_pending.take();
                    if n.boot_ups.len() < LISTED {
                        n.boot_ups.push((t, after));
                    }
                } else if n.state != Some(heartbeat.state) {
                    n.state = Some(heartbeat.state);
                    if n.transitions.len() < LISTED {
                        n.transitions.push((t, heartbeat.state));
                    }
                }
            }
            Message::NodeGuardRequest { node, .. } => self.node(node).guard_requests += 1,
            Message::Emcy { node, emcy } => {
                let charger = roles.is_deltaq_charger(node);
                let n = self.node(node);
                if emcy.is_reset() {
                    for e in &mut n.emcys {
                        e.2 = true;
                    }
                    return;
                }
                let text = emcy_text(&emcy, charger);
                if n.emcys.len() < LISTED {
                    n.emcys.push((t, text, false));
                } else {
                    n.emcys_more += 1;
                }
            }
            Message::Lss(lss) => {
                let l = &mut self.lss;
                l.frames += 1;
                match lss {
                    LssMessage::Request(LssRequest::Fastscan(f))
                        if f.bit_checked == Fastscan::RESET =>
                    {
                        l.fastscans += 1;
                    }
                    LssMessage::Request(LssRequest::ConfigureNodeId(raw)) => l.asked = Some(raw),
                    LssMessage::Response(LssResponse::ConfigureNodeId(st)) if st.is_ok() => {
                        if let Some(raw) = l.asked.take() {
                            if l.configured.len() < LISTED {
                                l.configured.push(raw);
                            }
                        }
                    }
                    _ => {}
                }
            }
            Message::Tpdo { .. } | Message::Rpdo { .. } => {
                let e = self.pdos.entry(id).or_insert((0, t, t));
                e.0 += 1;
                e.2 = t;
            }
            _ => {}
        }
    }

    /// A finished SDO transfer.
    pub fn transfer(&mut self, r: &Report) {
        let n = self.node(r.node);
        n.sdo_transfers += 1;
        if let End::Aborted { code, by } = &r.end {
            if n.sdo_aborts.len() < LISTED {
                n.sdo_aborts.push(format!(
                    "{:04X}h:{:02X} {} by the {}",
                    r.index,
                    r.sub,
                    code,
                    by.name()
                ));
            }
        }
    }

    /// Closes open silences at the end of the log; true when a problem is
    /// still open (a node silent until the end, an EMCY not cleared).
    /// Closing twice changes nothing.
    fn finish(&mut self) -> bool {
        let end = self.last.unwrap_or(Timestamp::ZERO);
        let mut open = false;
        let first_time = !std::mem::replace(&mut self.finished, true);
        for n in self.nodes.values_mut() {
            if let (Some(last), Some(p)) = (n.last_heartbeat, period(&n.gaps)) {
                if end.saturating_micros_since(last) > p.saturating_mul(3) {
                    if first_time {
                        n.silences.push((last, None));
                    }
                    open = true;
                }
            }
            open |= n.emcys.iter().any(|e| !e.2);
        }
        open
    }

    /// Every node's heartbeat silences (node, from, to; to `None`: until
    /// the end of the log), closed at the end of the log.
    pub fn silences(&mut self) -> Vec<(u8, Timestamp, Option<Timestamp>)> {
        self.finish();
        self.nodes
            .iter()
            .flat_map(|(id, n)| n.silences.iter().map(|(a, b)| (*id, *a, *b)))
            .collect()
    }

    /// Seconds from the first frame of the log to `t`.
    fn offset(&self, t: Timestamp) -> String {
        let us = t.saturating_micros_since(self.first.unwrap_or(t));
        format!("+{}.{:03} s", us / 1_000_000, us % 1_000_000 / 1000)
    }

    /// The summary as one JSON object (`"kind":"summary"`, its keys in
    /// the order serde_json once wrote them); true when a problem is still
    /// open.
    pub fn json(&mut self, out: &mut String, roles: &Roles) -> bool {
        use crate::log::json::{array, opt_text, text};
        let open = self.finish();
        let secs = |out: &mut String, t: Timestamp| {
            let _ = write!(out, "{t}");
        };
        // `[{"<first>":<t>,"<second>":..},..]` of `items`, `value` writing
        // each second field.
        fn timed<V>(
            out: &mut String,
            items: &[(Timestamp, V)],
            first: &str,
            second: &str,
            value: &dyn Fn(&mut String, &V),
        ) {
            array(out, items, |out, (t, v)| {
                let _ = write!(out, "{{\"{first}\":{t},\"{second}\":");
                value(out, v);
                out.push('}');
            });
        }
        out.push_str("{\"kind\":\"summary\",\"nodes\":");
        let nodes: Vec<(&u8, &Node)> = self.nodes.iter().filter(|n| !n.1.is_empty()).collect();
        array(out, &nodes, |out, (id, n)| {
            let _ = write!(out, "{{\"node\":{id},\"role\":");
            opt_text(out, roles.role(NodeId::new(**id)));
            let _ = write!(out, ",\"heartbeats\":{},\"period_ms\":", n.heartbeats);
            match period(&n.gaps) {
                Some(p) => {
                    let _ = write!(out, "{}", p / 1000);
                }
                None => out.push_str("null"),
            }
            let _ = write!(out, ",\"largest_gap_ms\":{}", n.largest_gap / 1000);
            out.push_str(",\"states\":");
            timed(out, &n.transitions, "t", "state", &|out, st| {
                text(out, &st.to_string())
            });
            out.push_str(",\"boot_ups\":");
            timed(out, &n.boot_ups, "t", "after", &|out, after| {
                opt_text(out, *after)
            });
            out.push_str(",\"silences\":");
            timed(out, &n.silences, "from", "to", &|out, to| match to {
                Some(t) => secs(out, *t),
                None => out.push_str("null"),
            });
            out.push_str(",\"emcys\":");
            array(out, &n.emcys, |out, (t, what, cleared)| {
                out.push_str("{\"t\":");
                secs(out, *t);
                out.push_str(",\"text\":");
                text(out, what);
                let _ = write!(out, ",\"cleared\":{cleared}}}");
            });
            let _ = write!(
                out,
                ",\"sdo_transfers\":{},\"sdo_aborts\":",
                n.sdo_transfers
            );
            array(out, &n.sdo_aborts, |out, a| text(out, a));
            let _ = write!(
                out,
                ",\"guard_requests\":{},\"guard_replies\":{}}}",
                n.guard_requests, n.guard_replies
            );
        });
        out.push_str(",\"pdos\":");
        let pdos: Vec<_> = self.pdos.iter().collect();
        array(out, &pdos, |out, (id, (frames, first, last))| {
            let _ = write!(out, "{{\"cob_id\":{id},\"frames\":{frames},\"first\":");
            secs(out, *first);
            out.push_str(",\"last\":");
            secs(out, *last);
            out.push('}');
        });
        let _ = write!(
            out,
            ",\"lss\":{{\"frames\":{},\"fastscans\":{},\"node_ids_configured\":",
            self.lss.frames, self.lss.fastscans
        );
        array(out, &self.lss.configured, |out, n| {
            let _ = write!(out, "{n}");
        });
        out.push_str("},\"bus_load_percent\":");
        crate::log::json::float(out, self.bus.mean_percent().1);
        out.push_str(",\"bus_load\":");
        self.bus.json(out);
        let _ = write!(out, ",\"open_problems\":{open}}}");
        open
    }

    /// The summary in words; true when a problem is still open.
    pub fn words(&mut self, out: &mut String, roles: &Roles) -> bool {
        let open = self.finish();
        let _ = writeln!(out, "summary:");
        for (id, n) in self.nodes.iter().filter(|n| !n.1.is_empty()) {
            let node = NodeId::new(*id);
            let role = roles
                .role(node)
                .map_or(String::new(), |r| format!(" ({r})"));
            let _ = writeln!(out, "  node {id}{role}:");
            if n.heartbeats > 0 {
                let p = period(&n.gaps).map_or("-".into(), |p| format!("{} ms", p / 1000));
                let _ = writeln!(
                    out,
                    "    heartbeats: {}, period {p}, largest gap {} ms",
                    n.heartbeats,
                    n.largest_gap / 1000
                );
            }
            if !n.transitions.is_empty() {
                let list: Vec<String> = n
                    .transitions
                    .iter()
                    .map(|(t, s)| format!("{s} at {}", secs(*t)))
                    .collect();
                let _ = writeln!(out, "    states: {}", list.join(", "));
            }
            for (t, after) in &n.boot_ups {
                let why = after.map_or("not preceded by an NMT reset".into(), |w| {
                    format!("after {w}")
                });
                let _ = writeln!(out, "    boot-up at {} ({why})", secs(*t));
            }
            for (from, to) in &n.silences {
                let _ = match to {
                    Some(to) => writeln!(
                        out,
                        "    silent from {} ({}) to {} ({})",
                        secs(*from),
                        self.offset(*from),
                        secs(*to),
                        self.offset(*to)
                    ),
                    None => writeln!(
                        out,
                        "    silent from {} ({}, its last heartbeat) until the end of the log",
                        secs(*from),
                        self.offset(*from)
                    ),
                };
            }
            for (t, text, cleared) in &n.emcys {
                let state = if *cleared {
                    "cleared by an error reset"
                } else {
                    "not cleared"
                };
                let _ = writeln!(
                    out,
                    "    EMCY at {} ({}): {text} ({state})",
                    secs(*t),
                    self.offset(*t)
                );
            }
            if n.emcys_more > 0 {
                let _ = writeln!(out, "    ... {} more EMCYs", n.emcys_more);
            }
            if n.sdo_transfers > 0 {
                let _ = writeln!(
                    out,
                    "    SDO transfers: {}, aborted: {}",
                    n.sdo_transfers,
                    n.sdo_aborts.len()
                );
                for a in &n.sdo_aborts {
                    let _ = writeln!(out, "      abort {a}");
                }
            }
            if n.guard_requests > 0 || n.guard_replies > 0 {
                let _ = writeln!(
                    out,
                    "    node guarding: {} requests, {} replies",
                    n.guard_requests, n.guard_replies
                );
            }
        }
        for (id, (count, first, last)) in &self.pdos {
            let span = last.saturating_micros_since(*first);
            let rate = if span > 0 && *count > 1 {
                format!("{:.1}/s", (*count - 1) as f64 * 1e6 / span as f64)
            } else {
                "-".into()
            };
            let _ = writeln!(out, "  PDO {id:03X}h: {count} frames, {rate}");
        }
        if self.lss.frames > 0 {
            let configured: Vec<String> = self.lss.configured.iter().map(u8::to_string).collect();
            let _ = writeln!(
                out,
                "  LSS: {} frames, {} fastscans, node-IDs configured: {}",
                self.lss.frames,
                self.lss.fastscans,
                if configured.is_empty() {
                    "none".to_string()
                } else {
                    configured.join(", ")
                }
            );
        }
        self.bus.words(out);
        let _ = writeln!(
            out,
            "  open problems at the end: {}",
            if open { "yes" } else { "none" }
        );
        open
    }
}

/// An EMCY in words: its error code, and the Delta-Q code with its
/// label on a Delta-Q charger.
pub fn emcy_text(emcy: &crate::emcy::Emergency, deltaq_charger: bool) -> String {
    let mut text = emcy.code.to_string();
    if deltaq_charger {
        let code = DeltaQCode::from_emergency(emcy);
        if let Some(d) = code.description() {
            let _ = write!(text, ", Delta-Q {code} {d}");
        }
    }
    text
}

/// The median of the gaps (µs), once there are 3.
fn period(gaps: &[u64]) -> Option<u64> {
    if gaps.len() < 3 {
        return None;
    }
    let mut g = gaps.to_vec();
    g.sort_unstable();
    g.get(g.len() / 2).copied()
}
