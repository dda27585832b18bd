//! Playing a recording into a device under test, sans-IO: the played
//! frames at their recorded times on the replay's clock, a wait for the
//! device's SDO answer where the recording shows one (CiA 301 section
//! 7.2.4: the server answers on 580h plus its node-ID what the client asked
//! on 600h plus that node-ID), and everything the device sends, timed on
//! the recording's time base.
//!
//! The caller owns the clock and the link to the device (`canopen-replay`
//! runs it on a candump-line pipe and the wall clock): it feeds each line
//! the device sends to [`Player::handle_heard`], calls
//! [`Player::handle_timeout`] when [`Player::poll_timeout`] is due, sends
//! what [`Player::poll_transmit`] gives, stamped with the frame's recorded
//! time, and collects the outcome with [`Player::finish`] once
//! `poll_timeout` says `None`.
//!
//! A device that takes its time base from its input (the examples do) then
//! runs on the replay's clock at any speed. A device line whose stamp lies
//! in that base is timed by it; otherwise (no stamp, or the device's own
//! wall clock) by its arrival on the replay's clock. After the last played
//! frame the device runs on its own clock, so the player listens for the
//! rest of the recording in real time (at most [`Options::tail_limit`]).

use core::time::Duration;
use std::prelude::rust_2021::*;

use crate::pdo::PdoMapping;
use crate::{CanFrame, CanId, Timestamp};

use super::diff::{self, Difference, Side, Tolerances};
use super::{Recorded, Recording};

/// How the recording is played.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// The time scale: 2 plays twice as fast. 0 (or anything not above 0,
    /// NaN included) plays each frame as soon as the device has answered
    /// the one before it.
    pub speed: f64,
    /// How long to wait for the device's SDO answer.
    pub sdo_timeout: Duration,
    /// The longest the player listens after its last played frame.
    pub tail_limit: Duration,
}

/// A frame from the device: when it arrived on the replay's clock, the
/// time its line gives (if any), and the frame.
#[derive(Clone, Copy, Debug)]
pub struct Heard {
    /// When the frame arrived, on the clock the caller gives the player.
    pub arrived: Timestamp,
    /// The time stamp of the device's line, if it has one.
    pub stamp: Option<Timestamp>,
    /// The frame.
    pub frame: CanFrame,
}

/// What the device did during the replay.
pub struct Played {
    /// The device's frames on the recording's time base, in time order.
    pub heard: Vec<Recorded>,
    /// Frames the device sent after the recording's end (not compared).
    pub after_end: usize,
    /// The COB-IDs of the device's boot-ups at its start, when the
    /// recording has none (it begins after the node's boot).
    pub boot_ups_at_start: Vec<u16>,
    /// Whether the recording's tail was longer than [`Options::tail_limit`].
    pub tail_cut: bool,
    /// SDO requests the device did not answer within the timeout: the
    /// request's recorded time and the COB-ID of the awaited answer.
    pub unanswered_sdo: Vec<(u64, u16)>,
}

/// The two sides of a replay and their differences ([`Played::compare`]).
pub struct Comparison {
    /// The recording's side: what the device should send.
    pub recording: Side,
    /// What the device sent.
    pub device: Side,
    /// The differences, unanswered SDO requests last.
    pub differences: Vec<Difference>,
}

/// Where the player is.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Phase {
    /// Waiting for the next played frame's time.
    Due,
    /// Waiting for the answer `id` to the SDO request sent at recorded time
    /// `t` (at `start` on the replay's clock) until `deadline`.
    Answer {
        id: u16,
        t: u64,
        start: Timestamp,
        deadline: Timestamp,
    },
    /// Listening to the device on its own clock until `until`.
    Tail { until: Timestamp },
    /// The replay is over.
    Done,
}

/// The replay of one recording into one device (module docs for the
/// loop). Call order: `handle_heard` for each device frame in arrival
/// order, `handle_timeout` when `poll_timeout` is due (extra calls are
/// harmless), then `poll_transmit` until `None`.
pub struct Player<'r> {
    rec: &'r Recording,
    awaited: Vec<Option<u16>>,
    options: Options,
    /// The index of the next played frame.
    next: usize,
    phase: Phase,
    pending: Option<Recorded>,
    /// When the replay started, on the caller's clock.
    origin: Timestamp,
    /// Time lost waiting for SDO answers: it moves the rest of the schedule.
    shift: Duration,
    /// The recorded time of the last frame sent, and when it was sent.
    last_t: u64,
    last_at: Timestamp,
    first_t: u64,
    out: Played,
}

/// `us` microseconds of the recording at `speed` (above 0); saturating.
fn scaled(us: u64, speed: f64) -> Duration {
    Duration::try_from_secs_f64(us as f64 / 1e6 / speed).unwrap_or(Duration::MAX)
}

/// Where each played SDO request expects an answer: the server's response
/// COB-ID (580h + node) when the recording shows one before the next
/// played frame.
fn awaited_answers(rec: &Recording) -> Vec<Option<u16>> {
    let played = &rec.played;
    played
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let CanId::Standard(id) = p.frame.id() else {
                return None;
            };
            if id & 0x780 != 0x600 || id & 0x7F == 0 {
                return None;
            }
            let answer = 0x580 + (id & 0x7F);
            let until = played.get(i + 1).map_or(rec.end, |n| n.t);
            rec.expected
                .iter()
                .any(|e| e.t >= p.t && e.t <= until && e.frame.id() == CanId::Standard(answer))
                .then_some(answer)
        })
        .collect()
}

impl<'r> Player<'r> {
    /// A replay of `rec` starting at `now` on the caller's clock.
    pub fn new(rec: &'r Recording, options: &Options, now: Timestamp) -> Self {
        let first_t = rec.played.first().map_or(0, |p| p.t);
        let mut player = Player {
            rec,
            awaited: awaited_answers(rec),
            options: *options,
            next: 0,
            phase: Phase::Due,
            pending: None,
            origin: now,
            shift: Duration::ZERO,
            last_t: first_t,
            last_at: now,
            first_t,
            out: Played {
                heard: Vec::new(),
                after_end: 0,
                boot_ups_at_start: Vec::new(),
                tail_cut: false,
                unanswered_sdo: Vec::new(),
            },
        };
        if rec.played.is_empty() {
            player.tail(now);
        }
        player
    }

    fn paced(&self) -> bool {
        self.options.speed > 0.0
    }

    /// Whether frames are still to be played (before the tail).
    pub fn is_playing(&self) -> bool {
        matches!(self.phase, Phase::Due | Phase::Answer { .. })
    }

    /// The recorded time a device frame is at. A stamp outside the
    /// replay's base is the device's own clock before it took the
    /// replay's (its start): the time of the first played frame.
    fn time_of(&self, h: &Heard) -> u64 {
        if let Some(s) = h.stamp.map(Timestamp::as_micros) {
            return if s <= self.rec.end.saturating_add(3_600_000_000) {
                s
            } else {
                self.first_t
            };
        }
        let rate = if self.is_playing() && self.paced() {
            self.options.speed
        } else {
            1.0
        };
        let since = h.arrived.saturating_micros_since(self.last_at) as f64;
        self.last_t.saturating_add((since * rate) as u64)
    }

    /// Feeds a frame the device sent: kept on the recording's time base,
    /// and the end of the wait when it is the awaited SDO answer (one that
    /// arrived before the wait's end).
    pub fn handle_heard(&mut self, h: &Heard) {
        match self.phase {
            Phase::Done => return,
            Phase::Tail { until } if h.arrived.has_reached(until) => return,
            _ => {}
        }
        let t = self.time_of(h);
        if t > self.rec.end {
            self.out.after_end += 1;
        } else {
            self.out.heard.push(Recorded { t, frame: h.frame });
        }
        if let Phase::Answer { id, deadline, .. } = self.phase {
            if h.frame.id() == CanId::Standard(id) && !h.arrived.has_reached(deadline) {
                self.answered(h.arrived);
            }
        }
    }

    /// Tells the player the time: a played frame whose time has come is
    /// made ready for [`Player::poll_transmit`] (one per call), an SDO wait
    /// past its timeout ends unanswered, the tail ends.
    pub fn handle_timeout(&mut self, now: Timestamp) {
        match self.phase {
            Phase::Due if self.pending.is_none() => {
                let Some(p) = self.rec.played.get(self.next).copied() else {
                    return self.tail(now);
                };
                if self.paced() && !now.has_reached(self.due(&p)) {
                    return;
                }
                self.pending = Some(p);
                self.last_t = p.t;
                self.last_at = now;
                match self.awaited.get(self.next).copied().flatten() {
                    Some(id) => {
                        self.phase = Phase::Answer {
                            id,
                            t: p.t,
                            start: now,
                            deadline: now.add_duration(self.options.sdo_timeout),
                        };
                    }
                    None => self.advance(now),
                }
            }
            Phase::Answer {
                id, t, deadline, ..
            } if now.has_reached(deadline) => {
                self.out.unanswered_sdo.push((t, id));
                self.answered(now);
            }
            Phase::Tail { until } if now.has_reached(until) => self.phase = Phase::Done,
            _ => {}
        }
    }

    /// The played frame to send now, stamped with its recorded time
    /// (microseconds since the recording's first frame).
    #[must_use]
    pub fn poll_transmit(&mut self) -> Option<Recorded> {
        self.pending.take()
    }

    /// When the player next needs [`Player::handle_timeout`]; `None` when
    /// the replay is over ([`Player::finish`]).
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Timestamp> {
        match self.phase {
            _ if self.pending.is_some() => Some(self.last_at),
            Phase::Due => match self.rec.played.get(self.next) {
                Some(p) if self.paced() => Some(self.due(p)),
                _ => Some(self.last_at),
            },
            Phase::Answer { deadline, .. } => Some(deadline),
            Phase::Tail { until } => Some(until),
            Phase::Done => None,
        }
    }

    /// What the device did, its frames in time order.
    #[must_use]
    pub fn finish(self) -> Played {
        let mut out = self.out;
        out.heard.sort_by_key(|r| r.t);
        // A recording that starts after the device's boot has no boot-up:
        // the device's boot-up at its start is then not compared.
        let rec = self.rec;
        let booted = |id: CanId| {
            rec.expected
                .iter()
                .any(|e| e.frame.id() == id && e.frame.data() == [0])
        };
        let first_t = self.first_t;
        out.boot_ups_at_start = out
            .heard
            .iter()
            .filter(|h| h.t <= first_t && h.frame.data() == [0] && !booted(h.frame.id()))
            .filter_map(|h| match h.frame.id() {
                CanId::Standard(id) if id & 0x780 == 0x700 => Some(id),
                _ => None,
            })
            .collect();
        out
    }

    /// When the played frame `p` is due on the caller's clock (paced).
    fn due(&self, p: &Recorded) -> Timestamp {
        let at = scaled(p.t.saturating_sub(self.first_t), self.options.speed);
        self.origin.add_duration(at.saturating_add(self.shift))
    }

    /// The end of an SDO wait at `now`: the time it took beyond the
    /// schedule moves the rest of it.
    fn answered(&mut self, now: Timestamp) {
        if let (Phase::Answer { t, start, .. }, true) = (self.phase, self.paced()) {
            let waited = now.saturating_duration_since(start);
            let speed = self.options.speed;
            let planned = self
                .rec
                .played
                .iter()
                .find(|n| n.t > t)
                .map_or(Duration::ZERO, |n| scaled(n.t.saturating_sub(t), speed));
            self.shift = self.shift.saturating_add(waited.saturating_sub(planned));
        }
        self.advance(now);
    }

    fn advance(&mut self, now: Timestamp) {
        self.next = self.next.saturating_add(1);
        self.phase = Phase::Due;
        if self.next >= self.rec.played.len() {
            self.tail(now);
        }
    }

    /// The rest of the recording on the device's own clock, from `now`.
    fn tail(&mut self, now: Timestamp) {
        let tail = Duration::from_micros(self.rec.end.saturating_sub(self.last_t));
        self.out.tail_cut = tail > self.options.tail_limit;
        let listen = tail.min(self.options.tail_limit);
        self.phase = Phase::Tail {
            until: now.add_duration(listen.saturating_add(Duration::from_millis(100))),
        };
    }
}

impl Played {
    /// The device's side against the recording's within `tolerances`, the
    /// PDOs of `pdos` (COB-ID and mapping) compared field by field ([`diff::compare`]): the
    /// device's boot-ups at its start are left out, and each unanswered
    /// SDO request is a difference of kind `sdo unanswered`.
    pub fn compare(
        &self,
        rec: &Recording,
        pdos: &[(u16, PdoMapping)],
        tolerances: &Tolerances,
    ) -> Comparison {
        let recording = diff::side(&rec.expected, &rec.played);
        let mut device = diff::side(&self.heard, &rec.played);
        for id in &self.boot_ups_at_start {
            if let Some(t) = device.traffic.get_mut(id) {
                t.kinds.remove("boot-up");
                t.count = t.count.saturating_sub(1);
                if t.count == 0 {
                    device.traffic.remove(id);
                }
            }
        }
        let mut differences = diff::compare(
            &recording,
            &device,
            &rec.expected,
            &self.heard,
            pdos,
            tolerances,
        );
        differences.extend(self.unanswered_sdo.iter().map(|(t, id)| Difference {
            kind: "sdo unanswered",
            cob_id: Some(*id),
            words: format!(
                "the SDO request at {:.1} ms got no answer on {id:03X}h",
                *t as f64 / 1000.0
            ),
        }));
        Comparison {
            recording,
            device,
            differences,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::frame::standard_frame as f;

    fn at(us: u64) -> Timestamp {
        Timestamp::from_micros(us)
    }

    fn r(t: u64, id: u16, data: &[u8]) -> Recorded {
        Recorded {
            t,
            frame: f(id, data),
        }
    }

    fn options(speed: f64) -> Options {
        Options {
            speed,
            sdo_timeout: Duration::from_millis(50),
            tail_limit: Duration::from_secs(60),
        }
    }

    /// The battery module (node 1) plays its heartbeat and an SDO read of
    /// the charger's (node 10) 1000h; the charger answers 1 ms later.
    fn recording() -> Recording {
        Recording {
            played: vec![
                r(0, 0x701, &[0x05]),
                r(1_000_000, 0x60A, &[0x40, 0, 0x10, 0, 0, 0, 0, 0]),
                r(2_000_000, 0x701, &[0x05]),
            ],
            expected: vec![
                r(500_000, 0x70A, &[0x7F]),
                r(1_001_000, 0x58A, &[0x43, 0, 0x10, 0, 0x19, 0x01, 0, 0]),
            ],
            end: 3_000_000,
        }
    }

    fn heard(arrived: u64, stamp: Option<u64>, id: u16, data: &[u8]) -> Heard {
        Heard {
            arrived: at(arrived),
            stamp: stamp.map(Timestamp::from_micros),
            frame: f(id, data),
        }
    }

    #[test]
    fn paced_frames_go_at_their_scaled_times_and_an_sdo_answer_is_awaited() {
        let rec = recording();
        let mut p = Player::new(&rec, &options(2.0), at(10));
        p.handle_timeout(at(10));
        assert_eq!(p.poll_transmit().map(|r| r.t), Some(0));
        assert_eq!(p.poll_transmit().map(|r| r.t), None);
        // At speed 2 the request recorded 1 s later is due 0.5 s later.
        assert_eq!(p.poll_timeout(), Some(at(500_010)));
        p.handle_timeout(at(500_009));
        assert!(p.poll_transmit().is_none());
        p.handle_timeout(at(500_010));
        assert_eq!(p.poll_transmit().map(|r| r.t), Some(1_000_000));
        // The answer is awaited for the SDO timeout.
        assert_eq!(p.poll_timeout(), Some(at(550_010)));
        // It comes 40 ms later, within the 0.5 s planned before the next
        // frame: the schedule does not move.
        p.handle_heard(&heard(
            540_010,
            None,
            0x58A,
            &[0x43, 0, 0x10, 0, 0x19, 0x01, 0, 0],
        ));
        assert_eq!(p.poll_timeout(), Some(at(1_000_010)));
        assert!(p.is_playing());
        p.handle_timeout(at(1_000_010));
        assert_eq!(p.poll_transmit().map(|r| r.t), Some(2_000_000));
        assert!(!p.is_playing());
        // The tail: the recording's last second in real time, and 100 ms.
        assert_eq!(p.poll_timeout(), Some(at(2_100_010)));
        p.handle_timeout(at(2_100_010));
        assert_eq!(p.poll_timeout(), None);
        let played = p.finish();
        assert!(played.unanswered_sdo.is_empty());
        assert!(!played.tail_cut);
        // Unstamped, the answer is timed by its arrival: 40 ms after the
        // request on the replay's clock is 80 ms of recording at speed 2.
        assert_eq!(played.heard.len(), 1);
        assert_eq!(played.heard[0].t, 1_080_000);
    }

    #[test]
    fn an_unanswered_request_waits_its_timeout_and_is_said() {
        let rec = recording();
        let mut p = Player::new(&rec, &options(0.0), at(0));
        p.handle_timeout(at(0));
        assert!(p.poll_transmit().is_some());
        // As fast as the device answers: the request at once.
        assert_eq!(p.poll_timeout(), Some(at(0)));
        p.handle_timeout(at(7));
        assert_eq!(p.poll_transmit().map(|r| r.t), Some(1_000_000));
        assert_eq!(p.poll_timeout(), Some(at(50_007)));
        // An answer from another node does not end the wait.
        p.handle_heard(&heard(20_000, None, 0x58B, &[0x60, 0, 0, 0, 0, 0, 0, 0]));
        p.handle_timeout(at(50_006));
        assert!(p.poll_transmit().is_none());
        p.handle_timeout(at(50_007));
        p.handle_timeout(at(50_008));
        assert_eq!(p.poll_transmit().map(|r| r.t), Some(2_000_000));
        // The answer after the timeout is kept but answers nothing.
        p.handle_heard(&heard(60_000, None, 0x58A, &[0x43, 0, 0x10, 0, 0, 0, 0, 0]));
        let played = p.finish();
        assert_eq!(played.unanswered_sdo, vec![(1_000_000, 0x58A)]);
        assert_eq!(played.heard.len(), 2);
    }

    #[test]
    fn stamps_in_the_replays_base_time_a_frame_and_others_do_not() {
        let rec = recording();
        let mut p = Player::new(&rec, &options(1.0), at(0));
        // In the base (up to an hour past the end): the stamp.
        p.handle_heard(&heard(5, Some(400_000), 0x70A, &[0x7F]));
        // The device's own wall clock: the first played frame's time.
        p.handle_heard(&heard(6, Some(1_700_000_000_000_000), 0x70A, &[0x00]));
        // Past the recording's end: counted, not compared.
        p.handle_heard(&heard(7, Some(3_000_001), 0x70A, &[0x7F]));
        let played = p.finish();
        let times: Vec<u64> = played.heard.iter().map(|h| h.t).collect();
        assert_eq!(times, [0, 400_000]);
        assert_eq!(played.after_end, 1);
        // The boot-up at the device's start, which the recording lacks.
        assert_eq!(played.boot_ups_at_start, [0x70A]);
    }

    #[test]
    fn a_long_tail_is_cut_at_the_limit() {
        let rec = recording();
        let o = Options {
            tail_limit: Duration::from_millis(200),
            ..options(0.0)
        };
        let mut p = Player::new(&rec, &o, at(0));
        for now in [0, 1, 2, 50_002, 50_003] {
            p.handle_timeout(at(now));
            let _ = p.poll_transmit();
        }
        assert!(!p.is_playing());
        assert_eq!(p.poll_timeout(), Some(at(50_003 + 300_000)));
        // Nothing that arrives after the tail counts.
        p.handle_heard(&heard(350_003, None, 0x70A, &[0x7F]));
        p.handle_timeout(at(350_003));
        assert_eq!(p.poll_timeout(), None);
        let played = p.finish();
        assert!(played.tail_cut);
        assert!(played.heard.is_empty());
    }

    #[test]
    fn the_comparison_leaves_out_the_start_boot_up_and_names_unanswered_requests() {
        let rec = recording();
        let played = Played {
            heard: vec![
                r(0, 0x70A, &[0x00]),
                r(500_000, 0x70A, &[0x7F]),
                r(1_001_000, 0x58A, &[0x43, 0, 0x10, 0, 0x19, 0x01, 0, 0]),
            ],
            after_end: 0,
            boot_ups_at_start: vec![0x70A],
            tail_cut: false,
            unanswered_sdo: vec![(2_000_000, 0x58A)],
        };
        let tol = Tolerances {
            value: 0,
            period: 0.1,
            time: 100_000,
        };
        let c = played.compare(&rec, &[], &tol);
        assert_eq!(c.device.traffic.get(&0x70A).map(|t| t.count), Some(1));
        assert!(!c.device.traffic[&0x70A].kinds.contains("boot-up"));
        let kinds: Vec<&str> = c.differences.iter().map(|d| d.kind).collect();
        assert_eq!(kinds, ["sdo unanswered"]);
        assert_eq!(
            c.differences[0].words,
            "the SDO request at 2000.0 ms got no answer on 58Ah"
        );
    }
}
