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
//! ## Its cost
//!
//! Measured by `benches/decoder_pipeline.rs` (`bus_load`) on the 100 000
//! frames of the repeated real captures, on a shared 2-core machine (load
//! average 12, so the figures are high): the count from scratch 0.59 µs
//! per frame, and [`BusLoad::frame`] 0.05 µs, because a log repeats its
//! frames and the stuff bits of the last frames seen are kept (256 slots,
//! one frame each, chosen by a hash of the frame). The summary alone
//! (`pipeline/summary-only`) took 1.24 µs per line before that cache and
//! 0.52 µs with it.
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
//! Memory is bounded: the 2 048 11-bit identifiers have a counter each,
//! at most [`MAX_COB_IDS`] 29-bit identifiers are counted one by one (the
//! others together), and the nodes' shares are summed from the identifiers'.

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
/// 29-bit identifiers counted one by one; more are counted together.
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
    /// The bits of `frame` (see the module's table).
    #[must_use]
    pub fn of(frame: &CanFrame) -> FrameBits {
        FrameBits::with_stuff(frame, stuff_bits(frame))
    }

    /// The bits of `frame` whose stuff bits are `stuff`.
    fn with_stuff(frame: &CanFrame, stuff: u32) -> FrameBits {
        let extended = frame.id().is_extended();
        let g = stuffed_field_bits(extended, data_bytes(frame));
        // CRC delimiter, ACK slot and delimiter, end of frame, intermission.
        let unstuffed = g + 1 + 2 + 7 + INTERMISSION;
        FrameBits {
            unstuffed,
            stuffed: unstuffed + stuff,
            worst_case: unstuffed + (g - 1) / 4,
        }
    }
}

/// The stuff bits `frame` needs: its bits from start of frame to the end of
/// the CRC sequence laid out, the CRC-15 computed over start of frame to
/// the data, and one stuff bit counted after every five equal bits.
///
/// The bits (at most 118: an extended 8-byte frame) are one `u128`; the
/// CRC goes a byte at a time through a table (zero bits in front of the
/// message leave a CRC that starts at 0 unchanged, so the message is
/// padded to whole bytes), and the stuffing is counted a run of equal bits
/// at a time (a run of e bits, counting a stuff bit of the same value just
/// before it, holds floor(e / 5) stuff bits, and when e is a multiple of 5
/// its last stuff bit starts the next run). The tests check it against a
/// bit-by-bit count of the same rules on every frame shape.
#[must_use]
pub fn stuff_bits(frame: &CanFrame) -> u32 {
    let (mut bits, mut len) = header(frame);
    if !frame.is_remote() {
        for &byte in frame.data() {
            bits = bits << 8 | u128::from(byte);
            len += 8;
        }
    }
    // The message in whole bytes, most significant first.
    let bytes = len.div_ceil(8);
    let mut crc: u16 = 0;
    for k in (0..bytes).rev() {
        let byte = (bits.checked_shr(8 * k).unwrap_or(0) & 0xFF) as u8;
        let index = usize::from((crc >> 7) as u8 ^ byte);
        crc = (crc << 8 ^ CRC15_TABLE.get(index).copied().unwrap_or(0)) & 0x7FFF;
    }
    let bits = bits << 15 | u128::from(crc);
    count_stuff(bits, len + 15)
}

/// Start of frame, arbitration and control fields as bits (the last one
/// lowest) and their number.
fn header(frame: &CanFrame) -> (u128, u32) {
    let rtr = u128::from(frame.is_remote());
    let dlc = u128::from(frame.dlc() & 0xF);
    match frame.id() {
        // SOF 0, identifier 11, RTR, IDE 0, r0 0, DLC 4.
        CanId::Standard(id) => ((u128::from(id) << 1 | rtr) << 6 | dlc, 19),
        // SOF 0, identifier 11, SRR 1, IDE 1, identifier 18, RTR, r1 0,
        // r0 0, DLC 4.
        CanId::Extended(id) => {
            let base = u128::from(id >> 18) << 2 | 0b11;
            let ext = (base << 18 | u128::from(id & 0x3_FFFF)) << 1 | rtr;
            (ext << 6 | dlc, 39)
        }
    }
}

/// The stuff bits of the `len` low bits of `bits` (sent highest first).
fn count_stuff(bits: u128, len: u32) -> u32 {
    let Some(mut s) = bits.checked_shl(128u32.saturating_sub(len)) else {
        return 0;
    };
    let mut left = len.min(128);
    let mut stuff = 0;
    // A stuff bit ended the last run: it has the next run's value.
    let mut carry = 0;
    while left > 0 {
        let ones = s >> 127 == 1;
        let run = if ones { !s } else { s }.leading_zeros().min(left);
        let e = run + carry;
        stuff += e / 5;
        carry = u32::from(e % 5 == 0);
        s = s.checked_shl(run).unwrap_or(0);
        left -= run;
    }
    stuff
}

/// CRC-15 of CAN one byte at a time: entry i is the register after the 8
/// bits of i entered a register of `i << 7`.
const CRC15_TABLE: [u16; 256] = crate::sdo::crc::msb_first_table(15, CRC15_POLY);

/// Slots of [`StuffCache`].
const CACHE_SLOTS: usize = 256;

/// The stuff bits of frames seen lately, one frame per slot chosen by a
/// hash of the frame: logs repeat their frames (heartbeats, PDOs whose
/// values hold), and a hit costs a hash and a comparison instead of the
/// CRC and the count (benches/decoder_pipeline.rs, `bus_load`).
#[derive(Clone, Debug)]
struct StuffCache {
    slots: Vec<Option<(CanFrame, u32)>>,
}

impl StuffCache {
    fn new() -> Self {
        StuffCache {
            slots: vec![None; CACHE_SLOTS],
        }
    }

    fn bits(&mut self, frame: &CanFrame) -> FrameBits {
        let data = u64::from_le_bytes(frame.padded_data());
        let key = u64::from(frame.id().raw())
            ^ u64::from(frame.dlc()) << 32
            ^ u64::from(frame.id().is_extended()) << 40
            ^ u64::from(frame.is_remote()) << 41
            ^ data.rotate_left(17);
        let slot = (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 56) as usize % CACHE_SLOTS;
        match self.slots.get_mut(slot) {
            Some(Some((f, stuff))) if f == frame => FrameBits::with_stuff(frame, *stuff),
            Some(entry) => {
                let stuff = stuff_bits(frame);
                *entry = Some((*frame, stuff));
                FrameBits::with_stuff(frame, stuff)
            }
            None => FrameBits::of(frame),
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
    /// Each 11-bit identifier's share, by identifier (the nodes' shares
    /// are summed from them when asked).
    standard: Vec<Share>,
    /// Each 29-bit identifier's share.
    extended: BTreeMap<u32, Share>,
    /// 29-bit identifiers past [`MAX_COB_IDS`].
    other_cob_ids: Share,
    cache: StuffCache,
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
            standard: vec![Share::default(); 0x800],
            extended: BTreeMap::new(),
            other_cob_ids: Share::default(),
            cache: StuffCache::new(),
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
        let bits = self.cache.bits(frame);
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
        match frame.id() {
            CanId::Standard(raw) => {
                if let Some(s) = self.standard.get_mut(usize::from(raw)) {
                    s.add(bits.stuffed);
                }
            }
            CanId::Extended(raw) => {
                if self.extended.len() < MAX_COB_IDS || self.extended.contains_key(&raw) {
                    self.extended.entry(raw).or_default().add(bits.stuffed);
                } else {
                    self.other_cob_ids.add(bits.stuffed);
                }
            }
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
        let current = (self.window.frames > 0).then_some(self.window);
        match (self.peak, current) {
            (Some(p), Some(c)) if c.bits.stuffed > p.bits.stuffed => Some(c),
            (Some(p), _) => Some(p),
            (None, c) => c,
        }
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

    /// The 11-bit identifiers with frames, and their shares.
    fn standard_ids(&self) -> impl Iterator<Item = (u16, Share)> + '_ {
        (0u16..)
            .zip(self.standard.iter())
            .filter(|(_, s)| s.frames > 0)
            .map(|(id, s)| (id, *s))
    }

    /// Each node's share (node 0: frames of no node), the largest first.
    #[must_use]
    pub fn nodes(&self) -> Vec<(u8, Share)> {
        let mut nodes: BTreeMap<u8, Share> = BTreeMap::new();
        let mut sum = |node: u8, s: &Share| {
            let n = nodes.entry(node).or_default();
            n.frames = n.frames.saturating_add(s.frames);
            n.bits = n.bits.saturating_add(s.bits);
        };
        for (id, s) in self.standard_ids() {
            let node = CanId::standard(id).map_or(0, node_of);
            sum(node, &s);
        }
        for s in self.extended.values().chain([&self.other_cob_ids]) {
            if s.frames > 0 {
                sum(0, s);
            }
        }
        let mut v: Vec<(u8, Share)> = nodes.into_iter().collect();
        v.sort_by(|a, b| b.1.bits.cmp(&a.1.bits).then(a.0.cmp(&b.0)));
        v
    }

    /// Each COB-ID's share, the largest first, and the 29-bit identifiers
    /// counted together past [`MAX_COB_IDS`].
    #[must_use]
    pub fn cob_ids(&self) -> (Vec<(CanId, Share)>, Share) {
        let mut v: Vec<(CanId, Share)> = self
            .standard_ids()
            .filter_map(|(id, s)| CanId::standard(id).map(|id| (id, s)))
            .chain(
                self.extended
                    .iter()
                    .filter_map(|(id, s)| CanId::extended(*id).map(|id| (id, *s))),
            )
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
        use crate::log::json::{array, float};
        let (bitrate, assumed) = self.bitrate();
        let (lo, mean, hi) = self.mean_percent();
        let _ = write!(
            out,
            "{{\"bitrate\":{bitrate},\"bitrate_assumed\":{assumed},\"bit_count\":\"exact stuffed\",\"frames\":{},\"duration_s\":",
            self.frames
        );
        float(out, self.duration());
        json_percents(out, (lo, mean, hi));
        out.push_str(",\"peak_window\":");
        match self.peak() {
            Some(p) => {
                let _ = write!(
                    out,
                    "{{\"aligned\":true,\"seconds\":1,\"start\":{},\"frames\":{}",
                    self.window_start(&p),
                    p.frames
                );
                json_percents(out, self.window_percent(&p));
                out.push('}');
            }
            None => out.push_str("null"),
        }
        out.push_str(",\"nodes\":");
        array(out, &self.nodes(), |out, (n, s)| {
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
        });
        out.push_str(",\"cob_ids\":");
        let (ids, other) = self.cob_ids();
        array(out, &ids, |out, (id, s)| {
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
        });
        let _ = write!(
            out,
            ",\"other_cob_ids\":{{\"frames\":{},\"bits\":{}}},\"error_frames\":{},\"fd_frames\":{}}}",
            other.frames, other.bits, self.error_frames, self.fd_frames
        );
    }
}

/// One load (the mean, or the peak window's) as the JSON summary gives
/// it, from `(unstuffed, stuffed, worst case)` as
/// [`BusLoad::mean_percent`] and [`BusLoad::window_percent`] return them:
/// `bus_load_percent` with the stuff bits the frames have,
/// `unstuffed_percent` without any, `worst_case_percent` with the most
/// bit stuffing can add (ISO 11898-1 section 10.5).
fn json_percents(out: &mut String, (lo, mid, hi): (f64, f64, f64)) {
    use crate::log::json::float;
    out.push_str(",\"bus_load_percent\":");
    float(out, mid);
    out.push_str(",\"unstuffed_percent\":");
    float(out, lo);
    out.push_str(",\"worst_case_percent\":");
    float(out, hi);
}

#[cfg(test)]
#[path = "bus_load_tests.rs"]
mod tests;
