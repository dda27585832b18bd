//! Playing the recording into the device: the played frames at their
//! recorded times on the replay's clock, a wait for the device's SDO answer
//! where the recording shows one, and everything the device sends, timed.
//!
//! Each line sent is stamped with its recorded time (microseconds since the
//! recording's first frame), so a device that takes its time base from its
//! input (the examples do) runs on the replay's clock at any `--speed`.
//! A device line whose stamp lies in that base is timed by it; otherwise
//! (no stamp, or the device's own wall clock) by its arrival on the
//! replay's clock. After the last played frame the device runs on its own
//! clock, so the replay listens for the rest of the recording in real time.

use std::time::{Duration, Instant};

use canopen_codec::{CanId, Timestamp};

use crate::link::{Heard, Link, Next};
use canopen_codec::log::replay::{Recorded, Recording};

pub struct Options {
    /// 0: as fast as the device answers; otherwise finite and above 0
    /// (the argument parser's range).
    pub speed: f64,
    pub sdo_timeout: Duration,
    /// The longest the replay listens after its last played frame.
    pub tail_limit: Duration,
}

/// What the device did.
pub struct Played {
    pub heard: Vec<Recorded>,
    /// Frames the device sent after the recording's end (not compared).
    pub after_end: usize,
    /// The device's boot-ups at its start, when the recording has none.
    pub boot_ups_at_start: Vec<u16>,
    /// Whether the recording's tail was longer than `--tail-limit-ms`.
    pub tail_cut: bool,
    /// SDO requests the device did not answer within the timeout.
    pub unanswered_sdo: Vec<(u64, u16)>,
}

/// Where a played SDO request expects an answer: the server's response
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

struct Clock {
    /// The recorded time of the last frame sent, and when it was sent.
    last_t: u64,
    last_at: Instant,
    speed: f64,
    playing: bool,
    end: u64,
    first_t: u64,
}

impl Clock {
    /// The recorded time a device frame is at. A stamp outside the
    /// replay's base is the device's own clock before it took the replay's
    /// (its start): the time of the first played frame.
    fn time_of(&self, h: &Heard) -> u64 {
        if let Some(s) = h.stamp.map(|s| s.as_micros()) {
            return if s <= self.end.saturating_add(3_600_000_000) {
                s
            } else {
                self.first_t
            };
        }
        let rate = if self.playing && self.speed > 0.0 {
            self.speed
        } else {
            1.0
        };
        let since = h
            .arrived
            .saturating_duration_since(self.last_at)
            .as_micros() as f64;
        self.last_t.saturating_add((since * rate) as u64)
    }
}

fn keep(out: &mut Played, clock: &Clock, h: &Heard) {
    let t = clock.time_of(h);
    if t > clock.end {
        out.after_end += 1;
    } else {
        out.heard.push(Recorded { t, frame: h.frame });
    }
}

/// `us` microseconds of the recording on the replay's clock at `speed`
/// (above 0); saturating, never a panic (`Duration::from_secs_f64` panics
/// past `Duration::MAX`).
fn scaled(us: u64, speed: f64) -> Duration {
    Duration::try_from_secs_f64(us as f64 / 1e6 / speed).unwrap_or(Duration::MAX)
}

/// `at + d`, or the latest instant the platform's clock can add to `at`
/// (`Instant + Duration` panics past it): a wait that does not end.
fn after(at: Instant, d: Duration) -> Instant {
    let mut d = d;
    loop {
        if let Some(t) = at.checked_add(d) {
            return t;
        }
        d /= 2;
    }
}

/// Why the device is gone, if it has exited.
fn gone(link: &mut Link) -> Option<String> {
    match link.exited() {
        Some(Err(e)) => Some(e),
        Some(Ok(())) => Some("the device exited before the recording ended".into()),
        None => None,
    }
}

/// Keeps what the device sends until `deadline`, or until it sends the
/// frame `answer` names (an SDO answer's identifier); whether that came.
/// An error when the device closed its output.
fn listen(
    link: &mut Link,
    out: &mut Played,
    clock: &Clock,
    deadline: Instant,
    answer: Option<u16>,
) -> Result<bool, String> {
    loop {
        let now = Instant::now();
        if now >= deadline {
            return Ok(false);
        }
        match link.next(deadline - now) {
            Next::Frame(h) => {
                keep(out, clock, &h);
                if answer.is_some_and(|id| h.frame.id() == CanId::Standard(id)) {
                    return Ok(true);
                }
            }
            Next::Timeout => return Ok(false),
            Next::Closed => return Err(gone(link).unwrap_or("the device closed its output".into())),
        }
    }
}

/// Plays `rec` into `link`; `Err` when the device stopped or died.
pub fn play(rec: &Recording, link: &mut Link, o: &Options) -> Result<Played, String> {
    let awaited = awaited_answers(rec);
    let mut out = Played {
        heard: Vec::new(),
        after_end: 0,
        boot_ups_at_start: Vec::new(),
        tail_cut: false,
        unanswered_sdo: Vec::new(),
    };
    let first_t = rec.played.first().map_or(0, |p| p.t);
    let mut clock = Clock {
        last_t: first_t,
        last_at: Instant::now(),
        speed: o.speed,
        playing: true,
        end: rec.end,
        first_t,
    };
    let origin = Instant::now();
    // Time lost waiting for SDO answers moves the rest of the schedule.
    let mut shift = Duration::ZERO;
    for (p, answer) in rec.played.iter().zip(&awaited) {
        if o.speed > 0.0 {
            let due = after(
                origin,
                scaled(p.t.saturating_sub(first_t), o.speed).saturating_add(shift),
            );
            listen(link, &mut out, &clock, due, None)?;
        }
        // Whatever the device has said by now belongs before this frame.
        while let Next::Frame(h) = link.next(Duration::ZERO) {
            keep(&mut out, &clock, &h);
        }
        if !link.send(&p.frame, Timestamp::from_micros(p.t)) {
            return Err(gone(link).unwrap_or("the device closed its input".into()));
        }
        clock.last_t = p.t;
        clock.last_at = Instant::now();
        if let Some(answer) = answer {
            let start = Instant::now();
            let deadline = after(start, o.sdo_timeout);
            if !listen(link, &mut out, &clock, deadline, Some(*answer))? {
                out.unanswered_sdo.push((p.t, *answer));
            }
            if o.speed > 0.0 {
                let waited = start.elapsed();
                let planned = rec
                    .played
                    .iter()
                    .find(|n| n.t > p.t)
                    .map_or(Duration::ZERO, |n| scaled(n.t.saturating_sub(p.t), o.speed));
                shift = shift.saturating_add(waited.saturating_sub(planned));
            }
        }
        if let Some(e) = gone(link) {
            return Err(e);
        }
    }
    // The rest of the recording on the device's own clock.
    clock.playing = false;
    let tail = Duration::from_micros(rec.end.saturating_sub(clock.last_t));
    out.tail_cut = tail > o.tail_limit;
    let tail = tail.min(o.tail_limit);
    let until = after(
        Instant::now(),
        tail.saturating_add(Duration::from_millis(100)),
    );
    listen(link, &mut out, &clock, until, None)?;
    out.heard.sort_by_key(|r| r.t);
    // A recording that starts after the device's boot has no boot-up: the
    // device's boot-up at its start is then not compared.
    let booted = |id: CanId| {
        rec.expected
            .iter()
            .any(|e| e.frame.id() == id && e.frame.data() == [0])
    };
    out.boot_ups_at_start = out
        .heard
        .iter()
        .filter(|h| h.t <= first_t && h.frame.data() == [0] && !booted(h.frame.id()))
        .filter_map(|h| match h.frame.id() {
            CanId::Standard(id) if id & 0x780 == 0x700 => Some(id),
            _ => None,
        })
        .collect();
    Ok(out)
}
