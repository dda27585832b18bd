//! Bus load: how much of the bus's time a log's frames occupy, at a bit
//! rate given (`--bitrate`) or assumed ([`DEFAULT_BITRATE`], the CiA 301
//! recommendation for CANopen networks of up to 250 m, CiA 301 section
//! 7.1, and what the Delta-Q chargers use). The data phase of a CAN FD
//! frame whose BRS is set runs at the data bit rate given
//! (`--data-bitrate`) or assumed ([`DEFAULT_DATA_BITRATE`], said to be
//! assumed when such a frame is read); a data bit rate below the nominal
//! one is taken as the nominal one (CAN FD's data phase is never slower).
//!
//! ## The bit count
//!
//! [`crate::log::frame_bits`] counts each frame's bits three ways: without
//! stuff bits, with the **exact stuff bits** its bits need (the load this
//! module gives) and with the most a frame of its shape can have (the
//! loads of the two bounds are given beside it). A classic frame of n data
//! bytes is 47 + 8n bits unstuffed (11-bit identifier) or 67 + 8n (29-bit),
//! all at the nominal bit rate. A CAN FD frame is 62 + 8n or 81 + 8n bits
//! (n <= 16; 5 more above, its CRC-21), of which, when its BRS is set, ESI
//! through the CRC field (5 + 8n + 27 or 32 bits and their stuff bits) run
//! at the data bit rate. An error frame is 17 bits in the unstuffed and
//! exact counts, 23 in the worst case (no or 6 superposed error flag bits).
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
//! A frame's time on the bus is its bits at the nominal rate over that
//! rate plus its bits at the data rate over that one; it is kept exactly,
//! in ticks of 1 / (nominal rate x data rate) second ([`BusTime`]). The
//! mean load is the time of every frame over the log's duration: from the
//! start of its first frame (its time, less its own time on the bus: the
//! logs time a frame when it has been received) to the time of the last.
//! The peak is the busiest **aligned** 1-second window: windows start at
//! the first frame's time and follow each other (a frame counts whole in
//! the window of its time). Error frames and CAN FD frames are in the
//! load; one read without a time (the error frames of candump screen, PCAN
//! trc and python-can CSV lines; candump and ASC lines, BLF, pcap and MF4
//! give theirs) takes the time of the frame before it, and a CAN FD frame
//! whose reader does not give its identifier and data (BLF, MF4, candump
//! screen, trc) is only counted, beside the load. A node's share
//! (of the bus time) is that of
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
/// The data bit rate of CAN FD frames with BRS set assumed when none is
/// given (bit/s): 2 Mbit/s, a usual data phase rate of CAN FD networks
/// (the summary says it is assumed).
pub const DEFAULT_DATA_BITRATE: u32 = 2_000_000;
/// Nodes and COB-IDs listed in words by their share (all in JSON).
pub const LISTED: usize = 10;
/// 29-bit identifiers counted one by one; more are counted together.
pub const MAX_COB_IDS: usize = 4096;

pub use crate::log::frame_bits::{stuff_bits, Counts, FrameBits, INTERMISSION};
use crate::trace::{FdFrame, OnBus};

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

/// Time on the bus counted three ways (see [`Counts`]), in ticks of
/// 1 / (nominal rate x data rate) second: a bit at the nominal rate is
/// as many ticks as the data rate in bit/s, a bit at the data rate as
/// many as the nominal rate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BusTime {
    /// Without stuff bits.
    pub unstuffed: u64,
    /// With each frame's stuff bits.
    pub stuffed: u64,
    /// With the most stuff bits.
    pub worst_case: u64,
}

impl BusTime {
    fn add(&mut self, t: BusTime) {
        self.unstuffed = self.unstuffed.saturating_add(t.unstuffed);
        self.stuffed = self.stuffed.saturating_add(t.stuffed);
        self.worst_case = self.worst_case.saturating_add(t.worst_case);
    }
}

/// Frames, their bits and their time on the bus (stuff bits included),
/// of a node or a COB-ID.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Share {
    /// Frames.
    pub frames: u64,
    /// Their bits, at either rate.
    pub bits: u64,
    /// Their time on the bus in [`BusTime`]'s ticks.
    pub time: u64,
}

impl Share {
    fn add(&mut self, bits: &FrameBits, time: u64) {
        self.frames = self.frames.saturating_add(1);
        self.bits = self.bits.saturating_add(u64::from(bits.total().stuffed));
        self.time = self.time.saturating_add(time);
    }

    fn sum(&mut self, s: &Share) {
        self.frames = self.frames.saturating_add(s.frames);
        self.bits = self.bits.saturating_add(s.bits);
        self.time = self.time.saturating_add(s.time);
    }
}

/// The 1-second window with the most bus time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Window {
    /// Its number: it starts this many seconds after the first frame.
    pub index: u64,
    /// Frames in it.
    pub frames: u64,
    /// Their time on the bus.
    pub time: BusTime,
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
    data_bitrate: u32,
    data_assumed: bool,
    first: Option<(Timestamp, u64)>,
    last: Option<Timestamp>,
    frames: u64,
    total: BusTime,
    window: Window,
    peak: Option<Window>,
    /// Each 11-bit identifier's share, by identifier (the nodes' shares
    /// are summed from them when asked).
    standard: Vec<Share>,
    /// Each 29-bit identifier's share.
    extended: BTreeMap<u32, Share>,
    /// 29-bit identifiers past [`MAX_COB_IDS`].
    other_cob_ids: Share,
    /// Error frames' share.
    errors: Share,
    cache: StuffCache,
    /// CAN FD frames in the load, and those of them with BRS set.
    fd_frames: u64,
    fd_brs_frames: u64,
    /// CAN FD frames read without their identifier and data (not in the
    /// load).
    fd_not_in_load: u64,
}

impl Default for BusLoad {
    fn default() -> Self {
        BusLoad::new(None)
    }
}

impl BusLoad {
    /// A load at `bitrate` bit/s; `None` (or 0): [`DEFAULT_BITRATE`],
    /// said to be assumed. The data bit rate is
    /// [`DEFAULT_DATA_BITRATE`], assumed ([`BusLoad::with_data_bitrate`]
    /// gives it).
    #[must_use]
    pub fn new(bitrate: Option<u32>) -> Self {
        let given = bitrate.filter(|&b| b > 0);
        BusLoad {
            bitrate: given.unwrap_or(DEFAULT_BITRATE),
            assumed: given.is_none(),
            data_bitrate: DEFAULT_DATA_BITRATE.max(given.unwrap_or(DEFAULT_BITRATE)),
            data_assumed: true,
            first: None,
            last: None,
            frames: 0,
            total: BusTime::default(),
            window: Window::default(),
            peak: None,
            standard: vec![Share::default(); 0x800],
            extended: BTreeMap::new(),
            other_cob_ids: Share::default(),
            errors: Share::default(),
            cache: StuffCache::new(),
            fd_frames: 0,
            fd_brs_frames: 0,
            fd_not_in_load: 0,
        }
    }

    /// The load with the data phase of CAN FD frames whose BRS is set at
    /// `data_bitrate` bit/s (`None` or 0: [`DEFAULT_DATA_BITRATE`], said to
    /// be assumed; below the nominal rate: the nominal rate).
    #[must_use]
    pub fn with_data_bitrate(mut self, data_bitrate: Option<u32>) -> Self {
        let given = data_bitrate.filter(|&b| b > 0);
        self.data_bitrate = given.unwrap_or(DEFAULT_DATA_BITRATE).max(self.bitrate);
        self.data_assumed = given.is_none();
        self
    }

    /// The bit rate (bit/s) and whether it is assumed.
    #[must_use]
    pub fn bitrate(&self) -> (u32, bool) {
        (self.bitrate, self.assumed)
    }

    /// The data bit rate of CAN FD frames with BRS set (bit/s) and
    /// whether it is assumed.
    #[must_use]
    pub fn data_bitrate(&self) -> (u32, bool) {
        (self.data_bitrate, self.data_assumed)
    }

    /// The time of `bits` on the bus, in [`BusTime`]'s ticks.
    #[must_use]
    pub fn time(&self, bits: &FrameBits) -> BusTime {
        let (n, d) = (u64::from(self.bitrate), u64::from(self.data_bitrate));
        let ticks = |nominal: u32, data: u32| {
            u64::from(nominal)
                .saturating_mul(d)
                .saturating_add(u64::from(data).saturating_mul(n))
        };
        BusTime {
            unstuffed: ticks(bits.nominal.unstuffed, bits.data.unstuffed),
            stuffed: ticks(bits.nominal.stuffed, bits.data.stuffed),
            worst_case: ticks(bits.nominal.worst_case, bits.data.worst_case),
        }
    }

    /// Ticks of [`BusTime`] as bit times at the nominal rate.
    #[must_use]
    pub fn nominal_bit_times(&self, ticks: u64) -> f64 {
        ticks as f64 / f64::from(self.data_bitrate)
    }

    /// One classic frame at `t` (a frame without a time takes the latest
    /// one). Returns its bits.
    pub fn frame(&mut self, t: Option<Timestamp>, frame: &CanFrame) -> FrameBits {
        let bits = self.cache.bits(frame);
        self.count(t, Some(frame.id()), &bits);
        bits
    }

    /// A CAN FD or an error frame at `t` (as [`BusLoad::frame`]). Returns
    /// its bits.
    pub fn on_bus(&mut self, t: Option<Timestamp>, what: &OnBus) -> FrameBits {
        match what {
            OnBus::Fd(frame) => self.fd_frame(t, frame),
            OnBus::ErrorFrame => {
                let bits = FrameBits::error_frame();
                self.count(t, None, &bits);
                bits
            }
        }
    }

    /// A CAN FD frame at `t` (as [`BusLoad::frame`]). Returns its bits.
    pub fn fd_frame(&mut self, t: Option<Timestamp>, frame: &FdFrame) -> FrameBits {
        let bits = FrameBits::of_fd(frame);
        self.fd_frames = self.fd_frames.saturating_add(1);
        self.fd_brs_frames = self.fd_brs_frames.saturating_add(u64::from(frame.brs()));
        self.count(t, Some(frame.id()), &bits);
        bits
    }

    /// A CAN FD frame read without its identifier and data: counted, not
    /// in the load.
    pub fn fd_frame_not_read(&mut self) {
        self.fd_not_in_load = self.fd_not_in_load.saturating_add(1);
    }

    /// A frame of `bits` with identifier `id` (none: an error frame) at `t`.
    fn count(&mut self, t: Option<Timestamp>, id: Option<CanId>, bits: &FrameBits) {
        let time = self.time(bits);
        let t = t.or(self.last).unwrap_or(Timestamp::ZERO);
        let (start, _) = *self.first.get_or_insert((t, time.stuffed));
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
        self.window.time.add(time);
        self.frames = self.frames.saturating_add(1);
        self.total.add(time);
        match id {
            Some(CanId::Standard(raw)) => {
                if let Some(s) = self.standard.get_mut(usize::from(raw)) {
                    s.add(bits, time.stuffed);
                }
            }
            Some(CanId::Extended(raw)) => {
                if self.extended.len() < MAX_COB_IDS || self.extended.contains_key(&raw) {
                    self.extended
                        .entry(raw)
                        .or_default()
                        .add(bits, time.stuffed);
                } else {
                    self.other_cob_ids.add(bits, time.stuffed);
                }
            }
            None => self.errors.add(bits, time.stuffed),
        }
    }

    fn close_window(&mut self) {
        if self.window.frames > 0
            && self
                .peak
                .is_none_or(|p| self.window.time.stuffed > p.time.stuffed)
        {
            self.peak = Some(self.window);
        }
    }

    /// Frames counted (error frames included).
    #[must_use]
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Error frames counted.
    #[must_use]
    pub fn error_frames(&self) -> u64 {
        self.errors.frames
    }

    /// CAN FD frames: in the load, of them with BRS set, and read without
    /// their identifier and data (not in the load).
    #[must_use]
    pub fn fd_frames(&self) -> (u64, u64, u64) {
        (self.fd_frames, self.fd_brs_frames, self.fd_not_in_load)
    }

    /// The time on the bus of every frame.
    #[must_use]
    pub fn time_on_bus(&self) -> BusTime {
        self.total
    }

    /// The ticks of [`BusTime`] in one second.
    fn ticks_per_second(&self) -> f64 {
        f64::from(self.bitrate) * f64::from(self.data_bitrate)
    }

    /// The log's duration in seconds (see the module's doc), 0 with no frame.
    #[must_use]
    pub fn duration(&self) -> f64 {
        match (self.first, self.last) {
            (Some((first, ticks)), Some(last)) => {
                last.saturating_micros_since(first) as f64 / 1e6
                    + ticks as f64 / self.ticks_per_second()
            }
            _ => 0.0,
        }
    }

    /// `ticks` in percent of the bus's time over `seconds`.
    fn percent(&self, ticks: u64, seconds: f64) -> f64 {
        if seconds > 0.0 {
            ticks as f64 * 100.0 / (self.ticks_per_second() * seconds)
        } else {
            0.0
        }
    }

    /// The mean load in percent: without stuff bits, with the exact stuff
    /// bits and with the most (unstuffed, stuffed, worst case).
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
            (Some(p), Some(c)) if c.time.stuffed > p.time.stuffed => Some(c),
            (Some(p), _) => Some(p),
            (None, c) => c,
        }
    }

    /// A window's load in percent of one second (unstuffed, stuffed, worst
    /// case).
    #[must_use]
    pub fn window_percent(&self, w: &Window) -> (f64, f64, f64) {
        (
            self.percent(w.time.unstuffed, 1.0),
            self.percent(w.time.stuffed, 1.0),
            self.percent(w.time.worst_case, 1.0),
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

    /// Each node's share (node 0: frames of no node; error frames are no
    /// node's), the largest first.
    #[must_use]
    pub fn nodes(&self) -> Vec<(u8, Share)> {
        let mut nodes: BTreeMap<u8, Share> = BTreeMap::new();
        for (id, s) in self.standard_ids() {
            let node = CanId::standard(id).map_or(0, node_of);
            nodes.entry(node).or_default().sum(&s);
        }
        for s in self.extended.values().chain([&self.other_cob_ids]) {
            if s.frames > 0 {
                nodes.entry(0).or_default().sum(s);
            }
        }
        let mut v: Vec<(u8, Share)> = nodes.into_iter().collect();
        v.sort_by(|a, b| b.1.time.cmp(&a.1.time).then(a.0.cmp(&b.0)));
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
        v.sort_by(|a, b| b.1.time.cmp(&a.1.time).then(a.0.cmp(&b.0)));
        (v, self.other_cob_ids)
    }

    /// A share in percent of every frame's time on the bus.
    fn share_percent(&self, s: &Share) -> f64 {
        if self.total.stuffed == 0 {
            0.0
        } else {
            s.time as f64 * 100.0 / self.total.stuffed as f64
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
        let _ = writeln!(
            out,
            "    error frames: {} ({:.2}% of the bus time: {} bits each, {} with superposed error flags)",
            self.errors.frames,
            self.share_percent(&self.errors),
            crate::log::frame_bits::ERROR_FRAME,
            crate::log::frame_bits::ERROR_FRAME + crate::log::frame_bits::ERROR_SUPERPOSITION,
        );
        if self.fd_frames > 0 || self.fd_not_in_load > 0 {
            let (data, assumed) = self.data_bitrate();
            let assumed = if assumed {
                " (assumed: --data-bitrate gives it)"
            } else {
                ""
            };
            let _ = write!(
                out,
                "    CAN FD frames: {} in the load ({} with BRS, their data phase at {data} bit/s{assumed})",
                self.fd_frames, self.fd_brs_frames
            );
            if self.fd_not_in_load > 0 {
                let _ = write!(
                    out,
                    "; {} more read without their identifier and data, not in the load",
                    self.fd_not_in_load
                );
            }
            out.push('\n');
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
            acc.sum(s);
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
        let (data, data_assumed) = self.data_bitrate();
        let _ = write!(
            out,
            "{{\"bitrate\":{bitrate},\"bitrate_assumed\":{assumed},\"data_bitrate\":{data},\"data_bitrate_assumed\":{data_assumed},\"bit_count\":\"exact stuffed\",\"frames\":{},\"duration_s\":",
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
            ",\"other_cob_ids\":{{\"frames\":{},\"bits\":{}}},\"error_frames\":{},\"error_frames_share_percent\":",
            other.frames, other.bits, self.errors.frames
        );
        float(out, self.share_percent(&self.errors));
        let _ = write!(
            out,
            ",\"fd_frames\":{},\"fd_brs_frames\":{},\"fd_frames_not_in_load\":{}}}",
            self.fd_frames, self.fd_brs_frames, self.fd_not_in_load
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
