//! The report page: the collected data as one JSON document inside the
//! HTML, drawn by the page's own script (`page.js`) and styled by
//! `page.css`, both inline, so the file opens anywhere with no network.

use std::fmt::Write as _;
use std::prelude::rust_2021::*;

use crate::log::json::{array, float, opt_text, text};
use crate::{NodeId, Timestamp};

use super::{Collector, MarkKind};
use crate::log::Roles;

const SCRIPT: &str = include_str!("page.js");
const STYLE: &str = include_str!("page.css");

/// The page's data, in the shapes `page.js` reads.
struct Data<'a> {
    title: &'a str,
    /// The log's first time, as the log gives it (seconds).
    start: String,
    /// Seconds from the first to the last frame.
    span: f64,
    rows: Vec<Row<'a>>,
    series: Vec<Series<'a>>,
    /// The bus's traffic: load, frames per second per node, raw PDO bytes.
    plots: Vec<Plot>,
    /// What of the traffic was counted but not plotted.
    plots_not_drawn: String,
    /// Marks and silences to draw, in all (the page checks it drew them).
    marks: usize,
}

struct Row<'a> {
    node: u8,
    label: String,
    /// [seconds, state] from then on.
    states: Vec<(f64, &'a str)>,
    states_not_drawn: u64,
    /// [seconds, kind, text].
    marks: Vec<(f64, &'static str, &'a str)>,
    /// [from, to] in seconds; to `null`: until the end of the log.
    silences: Vec<(f64, Option<f64>)>,
    /// Marks of each kind counted but not drawn.
    not_drawn: Vec<(&'static str, u64)>,
}

struct Series<'a> {
    label: String,
    cob_id: u32,
    index: u16,
    sub: u8,
    name: &'a str,
    unit: Option<&'a str>,
    line: Line,
}

/// What the page's script draws of a line, a signal's or a traffic plot's.
#[derive(Default)]
struct Line {
    /// A bit field or code (or a PDO byte) drawn as its raw bits.
    raw: bool,
    /// Samples (or windows, or frames) behind the points.
    samples: u64,
    /// Samples without a value.
    invalid: u64,
    /// Every sample is drawn (none merged into a column).
    exact: bool,
    /// The times, in seconds from the start of the log.
    t: Vec<f64>,
    /// The values at those times.
    v: Vec<f64>,
    /// Times of samples without a value (the line breaks there).
    gaps: Vec<f64>,
}

impl Line {
    /// The line's figures and arrays, and the end of its object.
    fn json(&self, out: &mut String) {
        let _ = write!(
            out,
            ",\"raw\":{},\"samples\":{},\"invalid\":{},\"exact\":{}",
            self.raw, self.samples, self.invalid, self.exact
        );
        for (name, values) in [("t", &self.t), ("v", &self.v), ("gaps", &self.gaps)] {
            let _ = write!(out, ",\"{name}\":");
            array(out, values, |out, v| float(out, *v));
        }
        out.push('}');
    }
}

/// A plot of the bus's traffic (drawn as steps: one value per window, or a
/// byte's value until the next frame).
struct Plot {
    label: String,
    /// "bus-load", "node-rate" or "pdo-byte".
    kind: &'static str,
    unit: &'static str,
    /// Its line: `samples` counts the windows or frames behind the
    /// points; a traffic plot has no gaps and no invalid samples.
    line: Line,
}

impl Plot {
    fn new(label: String, kind: &'static str, unit: &'static str) -> Self {
        Plot {
            label,
            kind,
            unit,
            line: Line {
                raw: kind == "pdo-byte",
                exact: true,
                ..Line::default()
            },
        }
    }

    fn json(&self, out: &mut String) {
        out.push_str("{\"label\":");
        text(out, &self.label);
        out.push_str(",\"kind\":");
        text(out, self.kind);
        out.push_str(",\"unit\":");
        text(out, self.unit);
        out.push_str(",\"step\":true");
        self.line.json(out);
    }
}

/// The traffic plots: the bus load, the nodes with the most frames, the
/// raw bytes of unmapped PDOs; and what was not plotted, in words.
fn plots(c: &Collector) -> (Vec<Plot>, String) {
    let mut plots = Vec::new();
    let t = &c.traffic;
    if t.bits.windows() > 0 {
        let (points, exact) = t.bits.points();
        let rate = f64::from(c.bitrate);
        let mut p = Plot::new(
            format!(
                "bus load per 1-second window (aligned to the first frame) at {} bit/s [%]",
                c.bitrate
            ),
            "bus-load",
            "%",
        );
        p.line.samples = t.bits.windows();
        p.line.exact = exact;
        p.line.t = points.iter().map(|s| secs(s.t)).collect();
        p.line.v = points.iter().map(|s| s.v * 100.0 / rate).collect();
        plots.push(p);
    }
    let mut nodes: Vec<(&u8, &(u64, super::series::PerSecond))> = t.nodes.iter().collect();
    nodes.sort_by(|a, b| b.1 .0.cmp(&a.1 .0).then(a.0.cmp(b.0)));
    let mut notes = Vec::new();
    if nodes.len() > super::MAX_NODE_PLOTS {
        notes.push(format!(
            "{} more nodes' frames per second not plotted (those with the fewest frames)",
            nodes.len() - super::MAX_NODE_PLOTS
        ));
    }
    nodes.truncate(super::MAX_NODE_PLOTS);
    nodes.sort_by_key(|n| *n.0);
    for (node, (count, per_second)) in nodes {
        let who = if *node == 0 {
            "frames of no node (NMT, SYNC, TIME, other identifiers)".to_string()
        } else {
            format!("node {node} frames")
        };
        let (points, exact) = per_second.points();
        let mut p = Plot::new(
            format!("{who} per second ({count} in all)"),
            "node-rate",
            "frames/s",
        );
        p.line.samples = per_second.windows();
        p.line.exact = exact;
        p.line.t = points.iter().map(|s| secs(s.t)).collect();
        p.line.v = points.iter().map(|s| s.v).collect();
        plots.push(p);
    }
    for (cob_id, bytes) in &t.raw_pdos {
        for (i, series) in bytes.iter().enumerate() {
            let points = series.points();
            let mut p = Plot::new(
                format!("{cob_id:03X}h byte {i} (no mapping) [raw]"),
                "pdo-byte",
                "raw",
            );
            p.line.samples = series.samples;
            p.line.exact = series.exact();
            p.line.t = points.iter().map(|s| secs(s.t)).collect();
            p.line.v = points.iter().map(|s| s.v).collect();
            plots.push(p);
        }
    }
    if !t.raw_pdos_not_drawn.is_empty() {
        notes.push(format!(
            "{} more PDO COB-IDs without a mapping not plotted",
            t.raw_pdos_not_drawn.len()
        ));
    }
    (plots, notes.join("; "))
}

/// Seconds, rounded to the microsecond the logs carry.
fn secs(us: u64) -> f64 {
    us as f64 / 1e6
}

pub fn write(
    c: &Collector,
    title: &str,
    summary: &str,
    silences: &[(u8, Timestamp, Option<Timestamp>)],
    roles: &Roles,
) -> String {
    let start = c.start.unwrap_or(Timestamp::ZERO);
    let rel = |t: Timestamp| secs(t.saturating_micros_since(start));
    let mut rows: Vec<Row<'_>> = c
        .rows
        .iter()
        .map(|(node, r)| Row {
            node: *node,
            label: match (*node, roles.role(NodeId::new(*node))) {
                (0, _) => "bus (NMT)".to_string(),
                (n, Some(role)) => format!("node {n} ({role})"),
                (n, None) => format!("node {n}"),
            },
            states: r
                .states
                .iter()
                .map(|(t, s)| (secs(*t), s.as_str()))
                .collect(),
            states_not_drawn: r.states_not_drawn,
            marks: r
                .marks
                .iter()
                .map(|m| (secs(m.t), m.kind.name(), m.text.as_str()))
                .collect(),
            silences: Vec::new(),
            not_drawn: r
                .not_drawn
                .iter()
                .map(|(k, n): (&MarkKind, &u64)| (k.name(), *n))
                .collect(),
        })
        .collect();
    // A node with no frame of its own (only addressed by NMT commands) has
    // no row: its marks go to the bus row.
    let heard = |node: u8| {
        c.traffic.nodes.is_empty() || c.traffic.nodes.get(&node).is_some_and(|n| n.0 > 0)
    };
    let (kept, unheard): (Vec<Row<'_>>, Vec<Row<'_>>) =
        rows.into_iter().partition(|r| r.node == 0 || heard(r.node));
    rows = kept;
    if !unheard.is_empty() {
        if rows.first().is_none_or(|r| r.node != 0) {
            rows.insert(
                0,
                Row {
                    node: 0,
                    label: "bus (NMT)".to_string(),
                    states: Vec::new(),
                    states_not_drawn: 0,
                    marks: Vec::new(),
                    silences: Vec::new(),
                    not_drawn: Vec::new(),
                },
            );
        }
        if let Some(bus) = rows.first_mut() {
            for r in unheard {
                bus.marks.extend(r.marks);
                bus.not_drawn.extend(r.not_drawn);
            }
            bus.marks.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
    }
    for &(node, from, to) in silences {
        if let Some(row) = rows.iter_mut().find(|r| r.node == node) {
            row.silences.push((rel(from), to.map(rel)));
        }
    }
    let series: Vec<Series<'_>> = c
        .fields
        .values()
        .map(|f| {
            let points = f.series.points();
            let unit = if f.raw { Some("raw") } else { f.unit };
            Series {
                label: format!(
                    "{:03X}h {:04X}h{} {}{}",
                    f.cob_id,
                    f.index,
                    if f.sub == 0 {
                        String::new()
                    } else {
                        format!(":{:02X}", f.sub)
                    },
                    f.name,
                    unit.map_or(String::new(), |u| format!(" [{u}]"))
                ),
                cob_id: f.cob_id,
                index: f.index,
                sub: f.sub,
                name: f.name,
                unit,
                line: Line {
                    raw: f.raw,
                    samples: f.series.samples,
                    invalid: f.series.invalid,
                    exact: f.series.exact(),
                    t: points.iter().map(|p| secs(p.t)).collect(),
                    v: points.iter().map(|p| p.v).collect(),
                    gaps: f.series.gaps().iter().map(|&g| secs(g)).collect(),
                },
            }
        })
        .collect();
    let marks = rows.iter().map(|r| r.marks.len() + r.silences.len()).sum();
    let (plots, plots_not_drawn) = plots(c);
    let data = Data {
        title,
        start: start.to_string(),
        span: secs(c.last),
        rows,
        series,
        plots,
        plots_not_drawn,
        marks,
    };
    // The JSON has no "</" of its own: nothing in the data can end the
    // script element early, but a text may hold "</script>", so "</" is
    // escaped.
    let json = data.json().replace("</", "<\\/");
    let mut html = String::with_capacity(json.len() + SCRIPT.len() + summary.len() + 4096);
    html.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    html.push_str("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n");
    html.push_str("<title>canopen-decode report: ");
    escape(&mut html, title);
    html.push_str("</title>\n<style>\n");
    html.push_str(STYLE);
    html.push_str("</style>\n</head>\n<body>\n<header><h1>CANopen session report</h1><p>");
    escape(&mut html, title);
    html.push_str(" &middot; first frame at ");
    escape(&mut html, &data.start);
    html.push_str(&format!(
        " s &middot; {:.3} s &middot; {} timeline rows &middot; {} signals &middot; {} traffic plots</p></header>\n",
        data.span,
        data.rows.len(),
        data.series.len(),
        data.plots.len()
    ));
    html.push_str("<section id=\"summary\"><h2>Bus summary</h2><pre>");
    escape(&mut html, summary);
    html.push_str("</pre></section>\n");
    html.push_str(
        "<section id=\"timeline\"><h2>Timeline</h2>\
         <p class=\"help\">Wheel: zoom &middot; drag: pan &middot; double-click: whole log \
         &middot; hover: details</p><div id=\"legend\"></div>\
         <canvas id=\"timeline-canvas\"></canvas><p id=\"not-drawn\"></p></section>\n",
    );
    html.push_str(
        "<section id=\"traffic\"><h2>Bus traffic</h2><p id=\"traffic-not-drawn\"></p></section>\n",
    );
    html.push_str("<section id=\"plots\"><h2>Signals</h2></section>\n");
    html.push_str("<div id=\"tooltip\" hidden></div>\n<pre id=\"selftest\" hidden></pre>\n");
    html.push_str("<script type=\"application/json\" id=\"report-data\">");
    html.push_str(&json);
    html.push_str("</script>\n<script>\n");
    html.push_str(SCRIPT);
    html.push_str("</script>\n</body>\n</html>\n");
    html
}

impl Data<'_> {
    /// The data as one JSON object, keys in declaration order (as
    /// serde_json wrote them before: `tests/decoder/log_json.rs` compares).
    fn json(&self) -> String {
        let mut out = String::with_capacity(4096);
        out.push_str("{\"title\":");
        text(&mut out, self.title);
        out.push_str(",\"start\":");
        text(&mut out, &self.start);
        out.push_str(",\"span\":");
        float(&mut out, self.span);
        out.push_str(",\"rows\":");
        array(&mut out, &self.rows, |out, r| r.json(out));
        out.push_str(",\"series\":");
        array(&mut out, &self.series, |out, s| s.json(out));
        out.push_str(",\"plots\":");
        array(&mut out, &self.plots, |out, p| p.json(out));
        out.push_str(",\"plots_not_drawn\":");
        text(&mut out, &self.plots_not_drawn);
        let _ = write!(out, ",\"marks\":{}}}", self.marks);
        out
    }
}

impl Row<'_> {
    fn json(&self, out: &mut String) {
        let _ = write!(out, "{{\"node\":{},\"label\":", self.node);
        text(out, &self.label);
        out.push_str(",\"states\":");
        array(out, &self.states, |out, (t, s)| {
            out.push('[');
            float(out, *t);
            out.push(',');
            text(out, s);
            out.push(']');
        });
        let _ = write!(
            out,
            ",\"states_not_drawn\":{},\"marks\":",
            self.states_not_drawn
        );
        array(out, &self.marks, |out, (t, kind, what)| {
            out.push('[');
            float(out, *t);
            out.push(',');
            text(out, kind);
            out.push(',');
            text(out, what);
            out.push(']');
        });
        out.push_str(",\"silences\":");
        array(out, &self.silences, |out, (from, to)| {
            out.push('[');
            float(out, *from);
            out.push(',');
            match to {
                Some(t) => float(out, *t),
                None => out.push_str("null"),
            }
            out.push(']');
        });
        out.push_str(",\"not_drawn\":");
        array(out, &self.not_drawn, |out, (kind, n)| {
            out.push('[');
            text(out, kind);
            let _ = write!(out, ",{n}]");
        });
        out.push('}');
    }
}

impl Series<'_> {
    fn json(&self, out: &mut String) {
        out.push_str("{\"label\":");
        text(out, &self.label);
        let _ = write!(
            out,
            ",\"cob_id\":{},\"index\":{},\"sub\":{},\"name\":",
            self.cob_id, self.index, self.sub
        );
        text(out, self.name);
        out.push_str(",\"unit\":");
        opt_text(out, self.unit);
        self.line.json(out);
    }
}

/// Text into HTML.
fn escape(out: &mut String, text: &str) {
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
}
