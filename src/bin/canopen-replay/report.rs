//! The diff report, in words or as one JSON object.

use serde_json::{json, Value};

use canopen_codec::log::replay::diff::{emcy_name, Difference, Side};
use canopen_codec::log::replay::player::Played;

pub struct Report<'a> {
    pub recording: &'a Side,
    pub device: &'a Side,
    pub played: &'a Played,
    pub sent: usize,
    pub differences: &'a [Difference],
}

fn ms(us: u64) -> f64 {
    (us as f64 / 100.0).round() / 10.0
}

impl Report<'_> {
    pub fn words(&self) -> String {
        let mut out = String::new();
        out += &format!(
            "replay: {} frames played, {} heard from the device ({} after the recording's end, not compared)\n",
            self.sent,
            self.played.heard.len(),
            self.played.after_end
        );
        if self.played.tail_cut {
            out += "the recording's tail after the last played frame was cut at --tail-limit-ms\n";
        }
        if !self.played.boot_ups_at_start.is_empty() {
            out += "the device's boot-up at its start is not compared (the recording begins after its node's boot)\n";
        }
        out += "COB-ID   recording            device\n";
        let ids: std::collections::BTreeSet<u16> = self
            .recording
            .traffic
            .keys()
            .chain(self.device.traffic.keys())
            .copied()
            .collect();
        for id in ids {
            let cell = |s: &Side| {
                s.traffic.get(&id).map_or("-".to_string(), |t| {
                    let p = t.period.map_or("-".into(), |p| format!("{} ms", ms(p)));
                    format!("{} every {p}", t.count)
                })
            };
            out += &format!(
                "{id:03X}h     {:<20} {}\n",
                cell(self.recording),
                cell(self.device)
            );
        }
        for (who, side) in [("recording", self.recording), ("device", self.device)] {
            for (id, list) in &side.emcys {
                for e in list {
                    out += &format!(
                        "{who}: {id:03X}h EMCY {} at {} ms ({} ms after the played frame before it)\n",
                        emcy_name(&e.data),
                        ms(e.t),
                        e.after_cause.map_or(f64::NAN, ms)
                    );
                }
            }
        }
        for (t, id) in &self.played.unanswered_sdo {
            out += &format!("SDO request at {} ms: no answer on {id:03X}h\n", ms(*t));
        }
        if self.differences.is_empty() {
            out += "the device matches the recording within tolerance\n";
        } else {
            out += &format!("{} differences:\n", self.differences.len());
            for d in self.differences {
                out += &format!("  {}: {}\n", d.kind, d.words);
            }
        }
        out
    }

    pub fn json(&self) -> Value {
        let traffic = |s: &Side| -> Value {
            s.traffic
                .iter()
                .map(|(id, t)| {
                    (
                        format!("{id:03X}"),
                        json!({"count": t.count, "kinds": t.kinds, "period_ms": t.period.map(ms)}),
                    )
                })
                .collect::<serde_json::Map<_, _>>()
                .into()
        };
        let emcys = |s: &Side| -> Vec<Value> {
            s.emcys
                .iter()
                .flat_map(|(id, l)| {
                    l.iter().map(move |e| {
                        json!({"cob_id": format!("{id:03X}"), "name": emcy_name(&e.data),
                               "t_ms": ms(e.t), "after_cause_ms": e.after_cause.map(ms)})
                    })
                })
                .collect()
        };
        let states = |s: &Side| -> Vec<Value> {
            s.states
                .iter()
                .flat_map(|(node, l)| {
                    l.iter().map(
                        move |(t, a, b)| json!({"node": node, "t_ms": ms(*t), "from": a, "to": b}),
                    )
                })
                .collect()
        };
        json!({
            "played": self.sent,
            "heard": self.played.heard.len(),
            "after_end": self.played.after_end,
            "boot_ups_at_start": self.played.boot_ups_at_start,
            "tail_cut": self.played.tail_cut,
            "recording": {"traffic": traffic(self.recording), "emcys": emcys(self.recording), "nmt": states(self.recording)},
            "device": {"traffic": traffic(self.device), "emcys": emcys(self.device), "nmt": states(self.device)},
            "unanswered_sdo": self.played.unanswered_sdo.iter().map(|(t, id)| json!({"t_ms": ms(*t), "cob_id": format!("{id:03X}")})).collect::<Vec<_>>(),
            "matches": self.differences.is_empty(),
            "differences": self.differences.iter().map(|d| json!({"kind": d.kind, "cob_id": d.cob_id.map(|c| format!("{c:03X}")), "words": d.words})).collect::<Vec<_>>(),
        })
    }
}
