//! What the device sent against what the recording shows for it: per
//! COB-ID the frame kinds and rates, PDO field values, NMT state changes
//! (from heartbeats) and EMCYs with their times relative to the played
//! frame before them.

use std::collections::{BTreeMap, BTreeSet};
use std::prelude::rust_2021::*;

use crate::deltaq::DeltaQCode;
use crate::pdo::PdoMapping;
use crate::CanId;

use super::Recorded;

/// How far the device may be from the recording.
pub struct Tolerances {
    /// PDO field values, in raw units of the field.
    pub value: u64,
    /// Rates: a period may differ by this fraction.
    pub period: f64,
    /// Event times (EMCYs), microseconds.
    pub time: u64,
}

/// One difference, with a stable `kind` for scripts.
pub struct Difference {
    /// `missing`, `unexpected`, `kinds`, `period`, `nmt`, `emcy missing`,
    /// `emcy time`, `emcy unexpected`, `pdo length`, `pdo value` (the
    /// program adds `sdo unanswered`).
    pub kind: &'static str,
    /// The COB-ID it is about, if one.
    pub cob_id: Option<u16>,
    /// The difference in words.
    pub words: String,
}

/// A COB-ID's traffic on one side.
#[derive(Default, Clone)]
pub struct Traffic {
    /// Frames.
    pub count: usize,
    /// What they were ([`kind`]).
    pub kinds: BTreeSet<&'static str>,
    /// The median time between frames, microseconds.
    pub period: Option<u64>,
}

/// An NMT state change seen in heartbeats: time, from, to.
pub type StateChange = (u64, u8, u8);

/// An EMCY: time, its 8 bytes, the time since the played frame before it.
#[derive(Clone)]
pub struct Emcy {
    /// Microseconds since the recording's start.
    pub t: u64,
    /// The frame's bytes.
    pub data: Vec<u8>,
    /// Microseconds since the played frame before it.
    pub after_cause: Option<u64>,
}

/// One side (recording or device) summarised.
#[derive(Default)]
pub struct Side {
    /// Traffic per COB-ID.
    pub traffic: BTreeMap<u16, Traffic>,
    /// NMT state changes per node.
    pub states: BTreeMap<u8, Vec<StateChange>>,
    /// EMCYs per COB-ID.
    pub emcys: BTreeMap<u16, Vec<Emcy>>,
}

fn cob(r: &Recorded) -> u16 {
    match r.frame.id() {
        CanId::Standard(id) => id,
        CanId::Extended(id) => (id & 0x7FF) as u16,
    }
}

/// A frame's kind by the CiA 301 pre-defined connection set.
pub fn kind(r: &Recorded) -> &'static str {
    let id = cob(r);
    let node = id & 0x7F;
    if matches!(r.frame.id(), CanId::Extended(_)) {
        return "extended";
    }
    match (id & 0x780, node) {
        (0x000, 0) => "NMT command",
        (0x080, 0) => "SYNC",
        (0x080, _) => "EMCY",
        (0x100, 0) => "TIME",
        (0x180 | 0x280 | 0x380 | 0x480, _) => "TPDO",
        (0x200 | 0x300 | 0x400 | 0x500, _) => "RPDO",
        (0x580, _) => "SDO response",
        (0x600, _) => "SDO request",
        (0x700, _) => match r.frame.data() {
            [0x00] => "boot-up",
            [_] => "heartbeat",
            [] => "guarding request",
            _ => "other",
        },
        _ => "other",
    }
}

/// The name of an EMCY: its error code, register and, when its
/// manufacturer field holds a Delta-Q alarm or fault code (Delta-Q CANopen
/// specification, the alarm and fault table), that code's label.
pub fn emcy_name(data: &[u8]) -> String {
    match data {
        [e0, e1, reg, m0, m1, ..] => {
            let eec = u16::from_le_bytes([*e0, *e1]);
            let dq = DeltaQCode::from_raw(u16::from_le_bytes([*m0, *m1]));
            let label = if eec != 0 && dq.label_parts().is_some() {
                format!(" {dq}")
            } else {
                String::new()
            };
            format!("EEC {eec:04X}h reg {reg:02X}h{label}")
        }
        _ => format!("EMCY of {} bytes", data.len()),
    }
}

fn median(mut v: Vec<u64>) -> Option<u64> {
    v.sort_unstable();
    v.get(v.len() / 2).copied()
}

/// Summarises `frames`; `played` (sorted by time) gives each EMCY its cause.
pub fn side(frames: &[Recorded], played: &[Recorded]) -> Side {
    let mut s = Side::default();
    let mut times: BTreeMap<u16, Vec<u64>> = BTreeMap::new();
    let mut state: BTreeMap<u8, u8> = BTreeMap::new();
    for r in frames {
        let id = cob(r);
        let k = kind(r);
        let t = s.traffic.entry(id).or_default();
        t.count += 1;
        t.kinds.insert(k);
        times.entry(id).or_default().push(r.t);
        let node = (id & 0x7F) as u8;
        match (k, r.frame.data()) {
            ("heartbeat", [b]) => {
                let now = b & 0x7F;
                match state.insert(node, now) {
                    Some(before) if before != now => {
                        s.states.entry(node).or_default().push((r.t, before, now));
                    }
                    _ => {}
                }
            }
            // A node enters pre-operational with its boot-up (CiA 301
            // section 7.3.2.2.1).
            ("boot-up", _) => {
                state.insert(node, 0x7F);
            }
            ("EMCY", data) => {
                let cause = played.iter().rev().find(|p| p.t <= r.t).map(|p| r.t - p.t);
                s.emcys.entry(id).or_default().push(Emcy {
                    t: r.t,
                    data: data.to_vec(),
                    after_cause: cause,
                });
            }
            _ => {}
        }
    }
    for (id, ts) in times {
        let gaps: Vec<u64> = ts.windows(2).map(|w| w[1].saturating_sub(w[0])).collect();
        if let Some(t) = s.traffic.get_mut(&id) {
            t.period = median(gaps);
        }
    }
    s
}

fn ms(us: u64) -> String {
    format!("{:.1} ms", us as f64 / 1000.0)
}

/// Signed difference of two times in ms, for the words.
fn delta(a: u64, b: u64) -> String {
    format!("{:+.1} ms", (a as f64 - b as f64) / 1000.0)
}

/// The differences of the device's side `dev` from the recording's `rec`
/// within `tol`: traffic, periods, PDO field values (of the mappings
/// `pdos`, from the frames `expected` and `heard`), NMT states and EMCYs.
pub fn compare(
    rec: &Side,
    dev: &Side,
    expected: &[Recorded],
    heard: &[Recorded],
    pdos: &[(u16, PdoMapping)],
    tol: &Tolerances,
) -> Vec<Difference> {
    let mut d = Vec::new();
    let mut push = |kind, cob_id, words: String| {
        d.push(Difference {
            kind,
            cob_id,
            words,
        })
    };
    let ids = either(&rec.traffic, &dev.traffic);
    for id in ids {
        match (rec.traffic.get(&id), dev.traffic.get(&id)) {
            (Some(r), None) => push(
                "missing",
                Some(id),
                format!(
                    "{id:03X}h: the recording has {} frames ({}), the device sent none",
                    r.count,
                    kinds(r)
                ),
            ),
            (None, Some(v)) => push(
                "unexpected",
                Some(id),
                format!(
                    "{id:03X}h: the device sent {} frames ({}), the recording has none",
                    v.count,
                    kinds(v)
                ),
            ),
            (Some(r), Some(v)) => {
                if r.kinds != v.kinds {
                    push(
                        "kinds",
                        Some(id),
                        format!(
                            "{id:03X}h: the recording has {}, the device sent {}",
                            kinds(r),
                            kinds(v)
                        ),
                    );
                }
                // SDO requests and answers (580h-67Fh) have no period of
                // their own: the client's pace sets it, and the player's
                // pace is the replay's (`--speed`), so only the answers
                // count for them (`unanswered_sdo`).
                let sdo = (0x580..=0x67F).contains(&id);
                if let (Some(rp), Some(vp), false) = (r.period, v.period, sdo) {
                    if (vp as f64 - rp as f64).abs() > rp as f64 * tol.period {
                        push(
                            "period",
                            Some(id),
                            format!(
                                "{id:03X}h: period {} in the recording, {} from the device",
                                ms(rp),
                                ms(vp)
                            ),
                        );
                    }
                }
            }
            (None, None) => {}
        }
    }
    let nodes = either(&rec.states, &dev.states);
    for node in nodes {
        let (r, v) = (
            rec.states.get(&node).cloned().unwrap_or_default(),
            dev.states.get(&node).cloned().unwrap_or_default(),
        );
        // A state is seen at the node's next heartbeat: its time is known to
        // one recorded heartbeat period.
        let hb = rec
            .traffic
            .get(&(0x700 + u16::from(node)))
            .and_then(|t| t.period)
            .unwrap_or(0)
            .max(tol.time);
        let same = r.len() == v.len()
            && r.iter()
                .zip(&v)
                .all(|(a, b)| a.1 == b.1 && a.2 == b.2 && a.0.abs_diff(b.0) <= hb);
        if !same {
            push(
                "nmt",
                Some(0x700 + u16::from(node)),
                format!(
                    "node {node}: NMT states {} in the recording, {} from the device",
                    changes(&r),
                    changes(&v)
                ),
            );
        }
    }
    let ids = either(&rec.emcys, &dev.emcys);
    for id in ids {
        let (r, v) = (
            rec.emcys.get(&id).cloned().unwrap_or_default(),
            dev.emcys.get(&id).cloned().unwrap_or_default(),
        );
        // Each recorded EMCY is matched, in order, with the device's next
        // EMCY of the same bytes.
        let mut used = vec![false; v.len()];
        let mut from = 0;
        for e in &r {
            let Some(j) = (from..v.len()).find(|&j| v[j].data == e.data) else {
                push(
                    "emcy missing",
                    Some(id),
                    format!(
                        "{id:03X}h: EMCY {} at {} is missing",
                        emcy_name(&e.data),
                        ms(e.t)
                    ),
                );
                continue;
            };
            used[j] = true;
            from = j + 1;
            let g = &v[j];
            if g.t.abs_diff(e.t) > tol.time {
                push(
                    "emcy time",
                    Some(id),
                    format!(
                        "{id:03X}h: EMCY {} at {} ({} after the played frame before it), the device's {} off",
                        emcy_name(&e.data),
                        ms(e.t),
                        e.after_cause.map_or("-".into(), ms),
                        delta(g.t, e.t)
                    ),
                );
            }
        }
        for (g, _) in v.iter().zip(&used).filter(|(_, u)| !**u) {
            push(
                "emcy unexpected",
                Some(id),
                format!(
                    "{id:03X}h: the device sent EMCY {} at {}, the recording has none",
                    emcy_name(&g.data),
                    ms(g.t)
                ),
            );
        }
    }
    for (id, mapping) in pdos {
        let (fields, unfit) = pdo_values(*id, mapping, expected, heard, tol.value);
        if unfit > 0 {
            push(
                "pdo length",
                Some(*id),
                format!("{id:03X}h: {unfit} frames (the device's or the recording's) do not fit the mapping of {} bits", mapping.total_bits()),
            );
        }
        for (field, worst, count) in fields {
            push(
                "pdo value",
                Some(*id),
                format!(
                    "{id:03X}h field {field}: {count} frames beyond the tolerance, at most {worst} raw units off"
                ),
            );
        }
    }
    d
}

fn kinds(t: &Traffic) -> String {
    t.kinds.iter().copied().collect::<Vec<_>>().join(", ")
}

fn changes(c: &[StateChange]) -> String {
    if c.is_empty() {
        return "(no change)".into();
    }
    c.iter()
        .map(|(t, a, b)| format!("{a:02X}h->{b:02X}h at {}", ms(*t)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Per mapped field of PDO `id`: the fields where a device frame differs
/// from the recorded frame nearest in time by more than `tol` raw units
/// (field `INDEX:SUB`, the largest difference, how many frames).
fn pdo_values(
    id: u16,
    mapping: &PdoMapping,
    expected: &[Recorded],
    heard: &[Recorded],
    tol: u64,
) -> (Vec<(String, u64, usize)>, usize) {
    let of = |v: &[Recorded]| -> Vec<Recorded> {
        v.iter()
            .filter(|r| r.frame.id() == CanId::Standard(id))
            .copied()
            .collect()
    };
    let (rec, dev) = (of(expected), of(heard));
    let mut worst: BTreeMap<usize, (u64, usize)> = BTreeMap::new();
    let mut unfit = 0;
    for g in &dev {
        let i = rec.partition_point(|r| r.t < g.t);
        let near = [i.checked_sub(1), Some(i)]
            .into_iter()
            .flatten()
            .filter_map(|i| rec.get(i))
            .min_by_key(|r| r.t.abs_diff(g.t));
        let Some(near) = near else { continue };
        let (Ok(a), Ok(b)) = (
            mapping.unpack(near.frame.data()),
            mapping.unpack(g.frame.data()),
        ) else {
            unfit += 1;
            continue;
        };
        for (n, ((e, x), (_, y))) in a.iter().zip(b.iter()).enumerate() {
            if e.is_dummy() {
                continue;
            }
            let off = x.abs_diff(y);
            if off > tol {
                let w = worst.entry(n).or_default();
                w.0 = w.0.max(off);
                w.1 += 1;
            }
        }
    }
    let fields = worst
        .into_iter()
        .filter_map(|(n, (off, count))| {
            let e = mapping.entries().get(n)?;
            Some((format!("{:04X}h:{:02X}h", e.index, e.sub), off, count))
        })
        .collect();
    (fields, unfit)
}

/// The keys of two maps, the recording's and the device's, in order, once:
/// what either side has, so that what one side lacks is compared too.
fn either<K: Ord + Copy, A, B>(rec: &BTreeMap<K, A>, dev: &BTreeMap<K, B>) -> BTreeSet<K> {
    rec.keys().chain(dev.keys()).copied().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::CanFrame;

    fn at(t_ms: u64, id: u16, data: &[u8]) -> Recorded {
        Recorded {
            t: t_ms * 1000,
            frame: CanFrame::standard(id, data).unwrap(),
        }
    }

    const TOL: Tolerances = Tolerances {
        value: 0,
        period: 0.1,
        time: 100_000,
    };

    #[test]
    fn emcys_are_named_with_their_delta_q_code() {
        let lost = [0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0];
        assert_eq!(emcy_name(&lost), "EEC 8130h reg 01h E-0-3-2");
        assert_eq!(emcy_name(&[0; 8]), "EEC 0000h reg 00h");
        assert_eq!(emcy_name(&[1]), "EMCY of 1 bytes");
    }

    #[test]
    fn states_rates_and_emcy_times_are_compared() {
        let played = [at(0, 0x701, &[5]), at(100, 0x701, &[5])];
        let lost = [0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0];
        let rec = [
            at(0, 0x70A, &[0x7F]),
            at(1000, 0x70A, &[5]),
            at(2000, 0x70A, &[5]),
            at(440, 0x08A, &lost),
        ];
        let r = side(&rec, &played);
        assert_eq!(r.states[&10], vec![(1_000_000, 0x7F, 5)]);
        assert_eq!(r.traffic[&0x70A].period, Some(1_000_000));
        assert_eq!(r.emcys[&0x08A][0].after_cause, Some(340_000));
        // The same device, its EMCY 150 ms late and its heartbeat at 500 ms.
        let dev = [
            at(0, 0x70A, &[0]),
            at(500, 0x70A, &[0x7F]),
            at(1000, 0x70A, &[5]),
            at(1500, 0x70A, &[5]),
            at(590, 0x08A, &lost),
        ];
        let mut dev_sorted = dev.to_vec();
        dev_sorted.sort_by_key(|r| r.t);
        let d = side(&dev_sorted, &played);
        let kinds: Vec<&str> = compare(&r, &d, &rec, &dev_sorted, &[], &TOL)
            .iter()
            .map(|d| d.kind)
            .collect();
        assert_eq!(kinds, ["kinds", "period", "emcy time"]);
        // Against itself, nothing differs.
        assert!(compare(&r, &r, &rec, &rec, &[], &TOL).is_empty());
    }

    #[test]
    fn pdo_fields_beyond_the_tolerance_are_named() {
        let (_, mapping) = crate::log::pdo_syntax::parse_pdo("18A=2002:0:16,2101:0:16").unwrap();
        let rec = [at(0, 0x18A, &[0x7C, 0x13, 0x45, 0x4E])];
        let dev = [
            at(10, 0x18A, &[0x7C, 0x13, 0x50, 0x4E]),
            at(20, 0x18A, &[1]),
        ];
        let s = side(&rec, &[]);
        let d = side(&dev, &[]);
        let found = compare(&s, &d, &rec, &dev, &[(0x18A, mapping)], &TOL);
        let words: Vec<&str> = found.iter().map(|d| d.words.as_str()).collect();
        assert_eq!(
            words,
            [
                "18Ah: 1 frames (the device's or the recording's) do not fit the mapping of 32 bits",
                "18Ah field 2101h:00h: 1 frames beyond the tolerance, at most 11 raw units off",
            ]
        );
        let loose = Tolerances { value: 11, ..TOL };
        assert_eq!(
            compare(&s, &d, &rec, &dev, &[(0x18A, mapping)], &loose).len(),
            1
        );
    }
}
