//! Bus load: how much of the bus's time a log's frames occupy, at a bit
//! rate given (`--bitrate`) or assumed ([`DEFAULT_BITRATE`], the CiA 301
//! recommendation for CANopen networks of up to 250 m, CiA 301 section
//! 7.1, and what the Delta-Q chargers use).
//!
//! ## The bit count
//!
//! A classic data or remote frame (ISO 11898-1:2015 section 10.4 "Frame
//! formats"; Bosch CAN Specification 2.0 part B section 3.1 "Frame
//! types") occupies, before stuffing:
//!
//! | field | base (11-bit) | extended (29-bit) |
//! |---|---|---|
//! | start of frame | 1 | 1 |
//! | arbitration | identifier 11, RTR 1 | identifier 11, SRR 1, IDE 1, identifier 18, RTR 1 |
//! | control | IDE 1, r0 1, DLC 4 | r1 1, r0 1, DLC 4 |
//! | data | 8 per byte (none in a remote frame) | 8 per byte |
//! | CRC | sequence 15, delimiter 1 | 15, 1 |
//! | ACK | slot 1, delimiter 1 | 1, 1 |
//! | end of frame | 7 | 7 |
//! | intermission (interframe space) | 3 | 3 |
//! | **total** | **47 + 8n** | **67 + 8n** |
//!
//! Bit stuffing (CAN 2.0 part B section 5 "Bit stuffing"; ISO 11898-1
//! section 10.5) covers start of frame through the CRC sequence (34 + 8n
//! bits in a base frame, 54 + 8n in an extended one): after five equal bits
//! the transmitter inserts one of the opposite value, which counts in the
//! next run. The worst case is one stuff bit per four bits after the first,
//! floor((g - 1) / 4) for g stuffed bits (Davis, Burns, Bril and Lukkien,
//! "Controller Area Network (CAN) schedulability analysis: refuted,
//! revisited and revised", Real-Time Systems 35(3), 2007, section 3).
//!
//! The load this module gives uses the **exact stuffed count**: the
//! frame's bits are laid out, its CRC-15 computed (generator
//! x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1, ISO 11898-1 section
//! 10.4.2.6), and the stuff bits counted; the loads of the unstuffed and
//! the worst-case counts are given beside it as bounds. For a few frames
//! (n data bytes, g stuffed bits):
//!
//! | frame | unstuffed | g | worst case | exact |
//! |---|---|---|---|---|
//! | base, 0 bytes: `000#` | 47 | 34 | 47 + 8 = 55 | 47 + 6 = 53 |
//! | base remote, DLC 0: `000#R` | 47 | 34 | 55 | 47 + 3 = 50 |
//! | base, 8 bytes: `6F8#FF000CFE00000000` | 111 | 98 | 111 + 24 = 135 | 124 |
//! | extended, 8 bytes: `18EBFF00#01A00FA6603BD140` | 131 | 118 | 131 + 29 = 160 | 141 |
//!
//! By hand: `000#` is 34 dominant bits (start of frame, identifier, RTR,
//! IDE, r0 and DLC are 19, and the CRC-15 of an all-dominant input is 0:
//! 15 more); a recessive stuff bit follows every fifth, 6 in all. `000#R`
//! is 12 dominant bits (stuff bits after the 5th and the 10th), a recessive
//! RTR, 6 dominant bits (IDE, r0, DLC: a stuff bit after the 5th), then the
//! CRC `111001111000101` (73C5h), whose longest run is 4: 3 stuff bits.
//! The two 8-byte frames are from python-can's test log `logfile.asc`,
//! written by Vector CANoe, whose `BitCount` column (intermission
//! included) gives 124 and 141; this module's count agrees with CANoe's
//! for five of that log's six frames (for the sixth, `6F9#050C000000000000`,
//! CANoe counts one bit more than the 123 computed here). The tests check
//! these counts, and that every frame's exact count lies between its
//! unstuffed and worst-case counts.
//!
//! ## The load
//!
//! The mean load is the bits of every frame over the log's duration: from
//! the start of its first frame (its time, less its own bits at the bit
//! rate: the logs time a frame when it has been received) to the time of
//! the last, all at the same bit rate. The peak is the busiest **aligned**
//! 1-second window: windows start at the first frame's time and follow each
//! other (a frame counts whole in the window of its time). Frames read but
//! not decoded are not in the load: CAN FD frames (their bit count would
//! need the data phase's rate) and error frames (the readers give no time
//! for them); the summary counts them beside it. A node's share is that of
//! the COB-IDs the CiA 301 predefined connection set gives it (section
//! 7.3.5: an RPDO or an SDO request counts for the node it addresses);
//! NMT, SYNC, TIME, extended and other identifiers count for no node.
//!
//! Memory is bounded: at most [`MAX_COB_IDS`] COB-IDs are counted one by
//! one (the others together), and the nodes are at most 127.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::prelude::rust_2021::*;

use crate::cob_id::classify_standard;
use crate::{CanFrame, CanId, Timestamp};

/// The bit rate assumed when none is given (bit/s): 250 kbit/s.
pub const DEFAULT_BITRATE: u32 = 250_000;
/// The intermission after every frame (bits).
pub const INTERMISSION: u32 = 3;
/// Nodes and COB-IDs listed in words by their share (all in JSON).
pub const LISTED: usize = 10;
/// COB-IDs counted one by one; more are counted together.
pub const MAX_COB_IDS: usize = 4096;
/// The CRC-15 generator polynomial of CAN (without its x^15 term).
const CRC15_POLY: u16 = 0x4599;

/// The bits before stuffing that are covered by stuffing (start of frame
/// to the end of the CRC sequence).
const fn stuffed_field_bits(extended: bool, data_bytes: u32) -> u32 {
    (if extended { 54 } else { 34 }) + 8 * data_bytes
}

/// A frame's data bytes on the bus: none in a remote frame.
fn data_bytes(frame: &CanFrame) -> u32 {
    if frame.is_remote() {
        0
    } else {
        u32::try_from(frame.data().len()).unwrap_or(8)
    }
}

/// The bits one classic frame occupies: without stuffing, with its exact
/// stuff bits, and with the most stuff bits a frame of its shape can have.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameBits {
    /// Without stuff bits (intermission included).
    pub unstuffed: u32,
    /// With the stuff bits this frame's bits need.
    pub stuffed: u32,
    /// With one stuff bit per four bits after the first.
    pub worst_case: u32,
}

impl FrameBits {
    /// The bit counts of `frame` (see the module's table).
    #[must_use]
    pub fn of(frame: &CanFrame) -> FrameBits {
        let extended = frame.id().is_extended();
        let g = stuffed_field_bits(extended, data_bytes(frame));
        // CRC delimiter, ACK slot and delimiter, end of frame, intermission.
        let unstuffed = g + 1 + 2 + 7 + INTERMISSION;
        FrameBits {
            unstuffed,
            stuffed: unstuffed + stuff_bits(frame),
            worst_case: unstuffed + (g - 1) / 4,
        }
    }
}

/// The stuff bits `frame` needs: its bits from start of frame to the end of
/// the CRC sequence laid out, the CRC-15 computed over start of frame to
/// the data, and one stuff bit counted after every five equal bits.
#[must_use]
pub fn stuff_bits(frame: &CanFrame) -> u32 {
    let mut s = Stuffing::default();
    // Start of frame: dominant.
    s.field(0, 1);
    let rtr = u32::from(frame.is_remote());
    match frame.id() {
        CanId::Standard(id) => {
            s.field(u32::from(id), 11);
            s.field(rtr, 1);
            // IDE dominant (base format), r0.
            s.field(0, 2);
        }
        CanId::Extended(id) => {
            s.field(id >> 18, 11);
            // SRR and IDE recessive.
            s.field(0b11, 2);
            s.field(id & 0x3_FFFF, 18);
            s.field(rtr, 1);
            // r1, r0.
            s.field(0, 2);
        }
    }
    s.field(u32::from(frame.dlc()), 4);
    if !frame.is_remote() {
        for &byte in frame.data() {
            s.field(u32::from(byte), 8);
        }
    }
    let crc = s.crc;
    s.crc_done = true;
    s.field(u32::from(crc), 15);
    s.stuff
}

/// The stuffing and the CRC over a frame's bits, fed most significant bit
/// first.
#[derive(Default)]
struct Stuffing {
    crc: u16,
    /// The CRC sequence is being sent: it is not its own input.
    crc_done: bool,
    /// The last bit sent (stuff bits included) and how many equal ones.
    last: bool,
    run: u8,
    stuff: u32,
}

impl Stuffing {
    /// The `n` low bits of `value`, most significant first.
    fn field(&mut self, value: u32, n: u32) {
        for i in (0..n).rev() {
            self.bit(value.checked_shr(i).unwrap_or(0) & 1 == 1);
        }
    }

    fn bit(&mut self, bit: bool) {
        if !self.crc_done {
            let top = self.crc & 0x4000 != 0;
            self.crc = (self.crc << 1) & 0x7FFF;
            if bit != top {
                self.crc ^= CRC15_POLY;
            }
        }
        if self.run > 0 && bit == self.last {
            self.run += 1;
        } else {
            self.last = bit;
            self.run = 1;
        }
        if self.run == 5 {
            // The stuff bit, of the opposite value, starts the next run.
            self.stuff += 1;
            self.last = !bit;
            self.run = 1;
        }
    }
}

/// Bits counted three ways (see [`FrameBits`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Bits {
    /// Without stuff bits.
    pub unstuffed: u64,
    /// With each frame's stuff bits.
    pub stuffed: u64,
    /// With the most stuff bits.
    pub worst_case: u64,
}

impl Bits {
    fn add(&mut self, b: FrameBits) {
        self.unstuffed = self.unstuffed.saturating_add(u64::from(b.unstuffed));
        self.stuffed = self.stuffed.saturating_add(u64::from(b.stuffed));
        self.worst_case = self.worst_case.saturating_add(u64::from(b.worst_case));
    }
}

/// Frames and their (stuffed) bits, of a node or a COB-ID.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Share {
    /// Frames.
    pub frames: u64,
    /// Their bits, stuff bits included.
    pub bits: u64,
}

impl Share {
    fn add(&mut self, bits: u32) {
        self.frames = self.frames.saturating_add(1);
        self.bits = self.bits.saturating_add(u64::from(bits));
    }
}

/// The 1-second window with the most bits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Window {
    /// Its number: it starts this many seconds after the first frame.
    pub index: u64,
    /// Frames in it.
    pub frames: u64,
    /// Their bits.
    pub bits: Bits,
}

/// A COB-ID as the load counts it: the identifier and its format.
fn cob_key(id: CanId) -> u32 {
    match id {
        CanId::Standard(raw) => u32::from(raw),
        CanId::Extended(raw) => raw | 1 << 31,
    }
}

/// The node a COB-ID belongs to in the predefined connection set (0: none).
fn node_of(id: CanId) -> u8 {
    match id {
        CanId::Standard(raw) => classify_standard(raw).node().map_or(0, |n| n.raw()),
        CanId::Extended(_) => 0,
    }
}

/// The bus load being collected (a log's frames in, the summary's figures
/// out).
#[derive(Clone, Debug)]
pub struct BusLoad {
    bitrate: u32,
    assumed: bool,
    first: Option<(Timestamp, u32)>,
    last: Option<Timestamp>,
    frames: u64,
    total: Bits,
    window: Window,
    peak: Option<Window>,
    nodes: BTreeMap<u8, Share>,
    cob_ids: BTreeMap<u32, Share>,
    /// COB-IDs past [`MAX_COB_IDS`].
    other_cob_ids: Share,
    /// Error frames read (not in the load).
    pub error_frames: u64,
    /// CAN FD frames read (not in the load).
    pub fd_frames: u64,
}

impl Default for BusLoad {
    fn default() -> Self {
        BusLoad::new(None)
    }
}

impl BusLoad {
    /// A load at `bitrate` bit/s; `None` (or 0): [`DEFAULT_BITRATE`],
    /// said to be assumed.
    #[must_use]
    pub fn new(bitrate: Option<u32>) -> Self {
        let given = bitrate.filter(|&b| b > 0);
        BusLoad {
            bitrate: given.unwrap_or(DEFAULT_BITRATE),
            assumed: given.is_none(),
            first: None,
            last: None,
            frames: 0,
            total: Bits::default(),
            window: Window::default(),
            peak: None,
            nodes: BTreeMap::new(),
            cob_ids: BTreeMap::new(),
            other_cob_ids: Share::default(),
            error_frames: 0,
            fd_frames: 0,
        }
    }

    /// The bit rate (bit/s) and whether it is assumed.
    #[must_use]
    pub fn bitrate(&self) -> (u32, bool) {
        (self.bitrate, self.assumed)
    }

    /// One frame at `t` (a frame without a time takes the latest one).
    /// Returns its bits.
    pub fn frame(&mut self, t: Option<Timestamp>, frame: &CanFrame) -> FrameBits {
        let bits = FrameBits::of(frame);
        let t = t.or(self.last).unwrap_or(Timestamp::ZERO);
        let (start, _) = *self.first.get_or_insert((t, bits.stuffed));
        self.last = Some(self.last.map_or(t, |l| l.max(t)));
        let index = t.saturating_micros_since(start) / 1_000_000;
        // A frame out of order joins the current window.
        if index > self.window.index {
            self.close_window();
            self.window = Window {
                index,
                ..Window::default()
            };
        }
        self.window.frames = self.window.frames.saturating_add(1);
        self.window.bits.add(bits);
        self.frames = self.frames.saturating_add(1);
        self.total.add(bits);
        self.nodes
            .entry(node_of(frame.id()))
            .or_default()
            .add(bits.stuffed);
        let key = cob_key(frame.id());
        if self.cob_ids.len() < MAX_COB_IDS || self.cob_ids.contains_key(&key) {
            self.cob_ids.entry(key).or_default().add(bits.stuffed);
        } else {
            self.other_cob_ids.add(bits.stuffed);
        }
        bits
    }

    fn close_window(&mut self) {
        if self.window.frames > 0
            && self
                .peak
                .is_none_or(|p| self.window.bits.stuffed > p.bits.stuffed)
        {
            self.peak = Some(self.window);
        }
    }

    /// Frames counted.
    #[must_use]
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The bits of every frame.
    #[must_use]
    pub fn bits(&self) -> Bits {
        self.total
    }

    /// The log's duration in seconds (see the module's doc), 0 with no frame.
    #[must_use]
    pub fn duration(&self) -> f64 {
        match (self.first, self.last) {
            (Some((first, bits)), Some(last)) => {
                last.saturating_micros_since(first) as f64 / 1e6
                    + f64::from(bits) / f64::from(self.bitrate)
            }
            _ => 0.0,
        }
    }

    /// `bits` in percent of the bus's capacity over `seconds`.
    fn percent(&self, bits: u64, seconds: f64) -> f64 {
        if seconds > 0.0 {
            bits as f64 * 100.0 / (f64::from(self.bitrate) * seconds)
        } else {
            0.0
        }
    }

    /// The mean load in percent: with the exact stuff bits, and the bounds
    /// without stuff bits and with the most (unstuffed, stuffed, worst case).
    #[must_use]
    pub fn mean_percent(&self) -> (f64, f64, f64) {
        let d = self.duration();
        (
            self.percent(self.total.unstuffed, d),
            self.percent(self.total.stuffed, d),
            self.percent(self.total.worst_case, d),
        )
    }

    /// The busiest aligned 1-second window so far (the current one
    /// included), if there was a frame.
    #[must_use]
    pub fn peak(&self) -> Option<Window> {
        let mut l = self.clone();
        l.close_window();
        l.peak
    }

    /// A window's load in percent of one second (unstuffed, stuffed, worst
    /// case).
    #[must_use]
    pub fn window_percent(&self, w: &Window) -> (f64, f64, f64) {
        (
            self.percent(w.bits.unstuffed, 1.0),
            self.percent(w.bits.stuffed, 1.0),
            self.percent(w.bits.worst_case, 1.0),
        )
    }

    /// When a window starts.
    fn window_start(&self, w: &Window) -> Timestamp {
        let start = self.first.map_or(Timestamp::ZERO, |f| f.0);
        Timestamp::from_micros(
            start
                .as_micros()
                .saturating_add(w.index.saturating_mul(1_000_000)),
        )
    }

    /// Each node's share (node 0: frames of no node), the largest first.
    #[must_use]
    pub fn nodes(&self) -> Vec<(u8, Share)> {
        let mut v: Vec<(u8, Share)> = self.nodes.iter().map(|(n, s)| (*n, *s)).collect();
        v.sort_by(|a, b| b.1.bits.cmp(&a.1.bits).then(a.0.cmp(&b.0)));
        v
    }

    /// Each COB-ID's share, the largest first, and the COB-IDs counted
    /// together past [`MAX_COB_IDS`].
    #[must_use]
    pub fn cob_ids(&self) -> (Vec<(CanId, Share)>, Share) {
        let mut v: Vec<(CanId, Share)> = self
            .cob_ids
            .iter()
            .filter_map(|(k, s)| {
                let id = if k & 1 << 31 != 0 {
                    CanId::extended(k & !(1 << 31))
                } else {
                    u16::try_from(*k).ok().and_then(CanId::standard)
                };
                id.map(|id| (id, *s))
            })
            .collect();
        v.sort_by(|a, b| b.1.bits.cmp(&a.1.bits).then(a.0.cmp(&b.0)));
        (v, self.other_cob_ids)
    }

    /// A share in percent of every frame's bits.
    fn share_percent(&self, s: &Share) -> f64 {
        if self.total.stuffed == 0 {
            0.0
        } else {
            s.bits as f64 * 100.0 / self.total.stuffed as f64
        }
    }

    /// The load in words (the summary's lines).
    pub fn words(&self, out: &mut String) {
        let (bitrate, assumed) = self.bitrate();
        let rate = if assumed {
            format!("{bitrate} bit/s (assumed: --bitrate gives it)")
        } else {
            format!("{bitrate} bit/s")
        };
        let (lo, mean, hi) = self.mean_percent();
        let _ = writeln!(
            out,
            "  bus load at {rate}: {mean:.2}% mean over {:.3} s ({} frames; {lo:.2}% without stuff bits, {hi:.2}% with the most)",
            self.duration(),
            self.frames
        );
        if let Some(p) = self.peak() {
            let (lo, mid, hi) = self.window_percent(&p);
            let _ = writeln!(
                out,
                "    peak 1-second window (aligned to the first frame) from {}: {mid:.2}% ({} frames; {lo:.2}% to {hi:.2}%)",
                self.window_start(&p),
                p.frames
            );
        }
        let nodes: Vec<(String, Share)> = self
            .nodes()
            .into_iter()
            .map(|(n, s)| {
                let who = if n == 0 {
                    "no node".to_string()
                } else {
                    format!("node {n}")
                };
                (who, s)
            })
            .collect();
        self.listed(out, "node", "nodes", nodes, Share::default());
        let (ids, other) = self.cob_ids();
        let ids = ids
            .into_iter()
            .map(|(id, s)| (format!("{id}h"), s))
            .collect();
        self.listed(out, "COB-ID", "COB-IDs", ids, other);
        if self.error_frames > 0 || self.fd_frames > 0 {
            let _ = writeln!(
                out,
                "    error frames: {}; CAN FD frames: {} (neither in the load)",
                self.error_frames, self.fd_frames
            );
        } else {
            let _ = writeln!(out, "    error frames: 0");
        }
    }

    /// `    by WHAT: ` the first [`LISTED`] shares, then the others (and
    /// `other`, counted together) as one.
    fn listed(
        &self,
        out: &mut String,
        what: &str,
        plural: &str,
        shares: Vec<(String, Share)>,
        other: Share,
    ) {
        if shares.is_empty() {
            return;
        }
        let mut list: Vec<String> = shares
            .iter()
            .take(LISTED)
            .map(|(name, s)| format!("{name} {:.1}%", self.share_percent(s)))
            .collect();
        let more = shares.len().saturating_sub(LISTED);
        let rest = shares.iter().skip(LISTED).fold(other, |mut acc, (_, s)| {
            acc.frames = acc.frames.saturating_add(s.frames);
            acc.bits = acc.bits.saturating_add(s.bits);
            acc
        });
        if rest.frames > 0 {
            let n = if other.frames > 0 {
                format!("{more} and more")
            } else {
                more.to_string()
            };
            list.push(format!(
                "{n} other {plural} {:.1}%",
                self.share_percent(&rest)
            ));
        }
        let _ = writeln!(out, "    by {what}: {}", list.join(", "));
    }

    /// The load as the JSON summary's `"bus_load"` object.
    pub fn json(&self, out: &mut String) {
        use crate::log::json::float;
        let (bitrate, assumed) = self.bitrate();
        let (lo, mean, hi) = self.mean_percent();
        let _ = write!(
            out,
            "{{\"bitrate\":{bitrate},\"bitrate_assumed\":{assumed},\"bit_count\":\"exact stuffed\",\"frames\":{},\"duration_s\":",
            self.frames
        );
        float(out, self.duration());
        out.push_str(",\"bus_load_percent\":");
        float(out, mean);
        out.push_str(",\"unstuffed_percent\":");
        float(out, lo);
        out.push_str(",\"worst_case_percent\":");
        float(out, hi);
        out.push_str(",\"peak_window\":");
        match self.peak() {
            Some(p) => {
                let (lo, mid, hi) = self.window_percent(&p);
                let _ = write!(
                    out,
                    "{{\"aligned\":true,\"seconds\":1,\"start\":{},\"frames\":{},\"bus_load_percent\":",
                    self.window_start(&p),
                    p.frames
                );
                float(out, mid);
                out.push_str(",\"unstuffed_percent\":");
                float(out, lo);
                out.push_str(",\"worst_case_percent\":");
                float(out, hi);
                out.push('}');
            }
            None => out.push_str("null"),
        }
        out.push_str(",\"nodes\":[");
        for (i, (n, s)) in self.nodes().iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            out.push_str("{\"node\":");
            if *n == 0 {
                out.push_str("null");
            } else {
                let _ = write!(out, "{n}");
            }
            let _ = write!(
                out,
                ",\"frames\":{},\"bits\":{},\"share_percent\":",
                s.frames, s.bits
            );
            float(out, self.share_percent(s));
            out.push('}');
        }
        out.push_str("],\"cob_ids\":[");
        let (ids, other) = self.cob_ids();
        for (i, (id, s)) in ids.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            let _ = write!(
                out,
                "{{\"cob_id\":{},\"extended\":{},\"frames\":{},\"bits\":{},\"share_percent\":",
                id.raw(),
                id.is_extended(),
                s.frames,
                s.bits
            );
            float(out, self.share_percent(s));
            out.push('}');
        }
        let _ = write!(
            out,
            "],\"other_cob_ids\":{{\"frames\":{},\"bits\":{}}},\"error_frames\":{},\"fd_frames\":{}}}",
            other.frames, other.bits, self.error_frames, self.fd_frames
        );
    }
}

#[cfg(test)]
#[path = "bus_load_tests.rs"]
mod tests;
