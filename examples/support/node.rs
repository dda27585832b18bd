//! Running a sans-IO node on a pipe with one consistent clock (shared by
//! the `battery_module` and `charger` examples).
//!
//! # Time
//!
//! The node is driven with one clock, in microseconds, whose time base is
//! the one the output lines are stamped in:
//!
//! - At start it is the **system clock** (wall time at start plus the
//!   monotonic clock since), so `</dev/null` or lines without timestamps
//!   give candump lines with ordinary UNIX times.
//! - The **first input line with a timestamp** switches the time base to the
//!   input's: its timestamp is taken as the time of the node's last step
//!   (its boot, or the last timer it ran), so the node's own clock never
//!   jumps, and every later output line is stamped in the input's base.
//! - A later timestamp **ahead** of the clock moves it forward: every timer
//!   due on the way runs at its own due time, in order, with output lines
//!   stamped with that time, before the line's frame is handled. A replayed
//!   script or log therefore gives the same output at any speed.
//! - A timestamp **behind** the clock (a late line) is handled at the
//!   clock's current time: the clock never goes backwards. A line without a
//!   timestamp is handled at the current time.
//! - **Between lines** the clock runs on the monotonic clock from the last
//!   timestamp that moved it, so heartbeats and TPDOs keep coming on time
//!   while the input is quiet.
//! - Timers are run at their due time, not at the moment the process wakes
//!   up, so periods do not drift. A jump of more than [`MAX_STEPS`] timer
//!   runs expires what is left once, at the target time.
//!
//! When stdin closes the node keeps running on the monotonic clock for the
//! linger time, then [`Runner::run`] returns.
//!
//! With `--speed F` ([`PipeBus::set_speed`]) the monotonic clock above is
//! the wall clock's time since start times F: the output lines are stamped
//! in that time, and everything the node does (timers, charging) happens F
//! times sooner in wall time. Both ends of a pipe run at the same F.
#![allow(dead_code)]

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use canopen_codec::machine::Machine;
use canopen_codec::{CanFrame, Timestamp};

use super::bus::{Input, PipeBus};

/// Most timer runs one catch-up performs.
const MAX_STEPS: usize = 1_000_000;

/// The clock described in this file's docs. All values are microseconds;
/// "external" is the base of the output lines, "internal" the module's.
pub struct Clock {
    /// external (live) = monotonic + `off`
    off: i128,
    /// internal = external - `shift`
    shift: i128,
    /// Whether a timestamped line has set the time base.
    anchored: bool,
    /// The last external time the node was driven at.
    pub last: i128,
}

fn micros(t: Timestamp) -> i128 {
    i128::from(t.as_micros())
}

pub fn stamp(us: i128) -> Timestamp {
    Timestamp::from_micros(u64::try_from(us.max(0)).unwrap_or(u64::MAX))
}

impl Clock {
    fn new(bus: &PipeBus) -> Self {
        let wall = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| i128::try_from(d.as_micros()).unwrap_or(0));
        let off = wall - micros(bus.now());
        Clock {
            off,
            shift: 0,
            anchored: false,
            last: wall,
        }
    }

    /// The current external time (never before the last step).
    fn now(&self, bus: &PipeBus) -> i128 {
        (micros(bus.now()) + self.off).max(self.last)
    }

    /// The external time at which to handle a line stamped `ts`.
    fn on_line(&mut self, bus: &PipeBus, ts: Option<Timestamp>) -> i128 {
        let now = self.now(bus);
        let Some(t) = ts.map(micros) else {
            return now;
        };
        if !self.anchored {
            // `t` is the time of the module's last step: internal time is
            // unchanged, only the external base moves.
            self.anchored = true;
            self.shift += t - self.last;
            self.last = t;
            self.off = t - micros(bus.now());
            return t;
        }
        if t > now {
            self.off = t - micros(bus.now());
            t
        } else {
            now
        }
    }

    fn internal(&self, external: i128) -> Timestamp {
        stamp(external - self.shift)
    }

    pub fn external(&self, internal: Timestamp) -> i128 {
        micros(internal) + self.shift
    }

    /// A deadline (external) on the bus's monotonic clock.
    fn monotonic(&self, external: i128) -> Timestamp {
        stamp(external - self.off)
    }
}

/// A state machine (the crate's [`Machine`] contract) on a pipe with its
/// clock; its events are printed on stderr in the words `describe` gives
/// them (`None`: not printed).
pub struct Runner<M: Machine> {
    pub bus: PipeBus,
    pub clock: Clock,
    pub device: M,
    describe: fn(&M::Event) -> Option<String>,
}

impl<M: Machine> Runner<M> {
    /// Starts the clock on `bus`; returns the runner and the boot instant
    /// (internal time) at which to boot the device.
    pub fn new(
        bus: PipeBus,
        device: M,
        describe: fn(&M::Event) -> Option<String>,
    ) -> (Self, Timestamp) {
        let clock = Clock::new(&bus);
        let boot = clock.internal(clock.last);
        let runner = Runner {
            bus,
            clock,
            device,
            describe,
        };
        (runner, boot)
    }

    /// Sends what the device has queued, stamped `internal`, and prints its events.
    pub fn flush(&mut self, internal: Timestamp) {
        let at = stamp(self.clock.external(internal));
        while let Some(f) = self.device.poll_transmit() {
            self.bus.send_at(&f, at);
        }
        while let Some(e) = self.device.poll_event() {
            if let Some(words) = (self.describe)(&e) {
                eprintln!("{words}");
            }
        }
    }

    /// Runs every timer due up to `target` (external) at its due time.
    fn advance(&mut self, target: i128) {
        let end = self.clock.internal(target);
        let mut steps = 0;
        while let Some(due) = self.device.poll_timeout().filter(|d| *d <= end) {
            let due = if steps >= MAX_STEPS { end } else { due };
            steps += 1;
            let now = due.max(self.clock.internal(self.clock.last));
            self.device.handle_timeout(now);
            self.clock.last = self.clock.external(now);
            self.flush(now);
            if steps > MAX_STEPS {
                break;
            }
        }
        self.clock.last = self.clock.last.max(target);
    }

    fn handle_frame(&mut self, frame: &CanFrame, ts: Option<Timestamp>) {
        let t = self.clock.on_line(&self.bus, ts);
        self.advance(t);
        let now = self.clock.internal(t);
        self.device.handle_frame(now, frame);
        self.flush(now);
    }

    /// Sleeps until `external` (or less) on the monotonic clock.
    fn sleep_until(&self, external: i128) {
        std::thread::sleep(self.bus.wait_until(self.clock.monotonic(external)));
    }

    /// Runs until stdin closes, then `linger` more.
    pub fn run(&mut self, linger: Duration) {
        loop {
            let wait = self
                .device
                .poll_timeout()
                .map(|d| self.clock.monotonic(self.clock.external(d)));
            match self.bus.recv(wait) {
                Input::Frame(f, ts) => self.handle_frame(&f, ts),
                Input::Timeout => {
                    let now = self.clock.now(&self.bus);
                    self.advance(now);
                }
                Input::Closed => break,
            }
        }
        let linger = i128::try_from(linger.as_micros()).unwrap_or(i128::MAX / 4);
        let end = self.clock.now(&self.bus) + linger;
        while linger > 0 && self.clock.now(&self.bus) < end {
            let next = self
                .device
                .poll_timeout()
                .map(|d| self.clock.external(d))
                .filter(|d| *d <= end)
                .unwrap_or(end);
            self.sleep_until(next);
            let now = self.clock.now(&self.bus).min(end);
            self.advance(now);
        }
    }
}
