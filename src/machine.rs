//! The state-machine contract: one trait every stateful part of the crate
//! implements, so one loop can drive any set of them.
//!
//! # Driving a machine
//!
//! ```text
//! handle_frame(now, &frame)   feed every received frame (frames not for it are ignored)
//! handle_timeout(now)         tell it time has passed (extra calls are harmless)
//! poll_transmit()             frames it wants sent, in order: call until None
//! poll_event()                what happened: call until None
//! poll_timeout()              when it next needs handle_timeout (None: no timer armed)
//! ```
//!
//! After every `handle_*` call and every command (an inherent method such as
//! [`sdo::Client::start_upload`](crate::sdo::Client::start_upload)), call
//! `poll_transmit` until it returns `None` and send the frames in that
//! order; then read `poll_timeout` again (a command or an input may arm or
//! move a timer). `poll_event` may be called at any time.
//!
//! # Back-pressure
//!
//! **An undrained queue never changes protocol behaviour.** Liveness
//! supervision, timers and transfers run by their own rules whether or not
//! the application reads what the machine produced: a heartbeat always
//! refreshes the consumer's deadline, an SDO transfer goes on or ends by
//! its own rules. Every machine keeps a fixed number of frames to send and
//! of events (no allocation), and one rule holds for both, the same in
//! every machine: **when a queue is full, its oldest item is dropped and
//! counted**, so the newest frame (the latest answer, the latest PDO
//! value) and the newest event (a transfer's terminal event) are always
//! kept. [`Machine::frames_dropped`] and [`Machine::events_dropped`] say
//! how many were; each count saturates at `u32::MAX`. A caller that drains
//! `poll_transmit` after every call, as above, never loses a frame.
//!
//! # Time
//!
//! Time is an input ([`Timestamp`], microseconds on the caller's monotonic
//! clock). A timestamp earlier than a previous one never panics: deadlines
//! are simply not reached yet. A timestamp far ahead expires every running
//! timer once.
//!
//! ```
//! use canopen_codec::nmt::heartbeat::HeartbeatProducer;
//! use canopen_codec::machine::{drive_timers, Machine};
//! use canopen_codec::{NodeId, Timestamp};
//! use core::time::Duration;
//!
//! let mut producer = HeartbeatProducer::new(NodeId::new(5).unwrap(), Duration::from_millis(100));
//! producer.boot(Timestamp::ZERO);
//! let mut sent = Vec::new();
//! drive_timers(&mut producer, Timestamp::from_millis(250), |_, frame| sent.push(frame.to_string()));
//! assert_eq!(sent, ["705#00", "705#7F", "705#7F"]);
//! ```

use crate::clock::Timestamp;
use crate::frame::CanFrame;

/// The contract of every sans-IO state machine in the crate. See the
/// [module docs](self) for the call order and the back-pressure rule.
pub trait Machine {
    /// What the machine reports (`core::convert::Infallible` for machines
    /// that report nothing).
    type Event;

    /// Feeds a received frame at `now`. Frames that are not for this
    /// machine are ignored.
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame);

    /// Tells the machine that time has reached `now`: due timers fire.
    /// Calling it early or twice is harmless.
    fn handle_timeout(&mut self, now: Timestamp);

    /// The next frame to send, in order.
    #[must_use]
    fn poll_transmit(&mut self) -> Option<CanFrame>;

    /// When [`handle_timeout`](Self::handle_timeout) must next be called.
    #[must_use]
    fn poll_timeout(&self) -> Option<Timestamp>;

    /// The next event, oldest first.
    #[must_use]
    fn poll_event(&mut self) -> Option<Self::Event>;

    /// How many events were dropped because the event queue was full
    /// (the oldest each time; saturates at `u32::MAX`).
    #[must_use]
    fn events_dropped(&self) -> u64;

    /// How many frames were dropped because the transmit queue was full
    /// (the oldest each time; saturates at `u32::MAX`). Zero for a caller
    /// that drains [`poll_transmit`](Self::poll_transmit) after every call.
    #[must_use]
    fn frames_dropped(&self) -> u64;
}

/// The output half of a [`Machine`] impl, from the machine's queues: the
/// one back-pressure rule of the [module docs](self) (`FrameQueue` and
/// `EventQueue` drop the oldest item and count it), written once.
/// `frames: none` / `events: none` for a machine that sends or reports
/// nothing; `events: none` alone for one that makes its frames itself.
/// A leading `timers: FIELD` also answers `poll_timeout` with the earliest
/// deadline of the machine's [`Timers`](crate::clock::Timers) table, for
/// the machines whose deadlines all live there.
macro_rules! queued_outputs {
    (timers: $timers:ident, $($outputs:tt)*) => {
        fn poll_timeout(&self) -> Option<$crate::clock::Timestamp> {
            self.$timers.next()
        }
        $crate::machine::queued_outputs!($($outputs)*);
    };
    (events: none) => {
        fn poll_event(&mut self) -> Option<Self::Event> {
            None
        }
        fn events_dropped(&self) -> u64 {
            0
        }
    };
    (frames: none, events: $events:ident) => {
        fn poll_transmit(&mut self) -> Option<$crate::frame::CanFrame> {
            None
        }
        fn frames_dropped(&self) -> u64 {
            0
        }
        $crate::machine::queued_outputs!(@events $events);
    };
    (frames: $frames:ident, events: none) => {
        $crate::machine::queued_outputs!(@frames $frames);
        $crate::machine::queued_outputs!(events: none);
    };
    (frames: $frames:ident, events: $events:ident) => {
        $crate::machine::queued_outputs!(@frames $frames);
        $crate::machine::queued_outputs!(@events $events);
    };
    (@frames $frames:ident) => {
        fn poll_transmit(&mut self) -> Option<$crate::frame::CanFrame> {
            self.$frames.pop()
        }
        fn frames_dropped(&self) -> u64 {
            self.$frames.dropped()
        }
    };
    (@events $events:ident) => {
        fn poll_event(&mut self) -> Option<Self::Event> {
            self.$events.pop()
        }
        fn events_dropped(&self) -> u64 {
            self.$events.dropped()
        }
    };
}
pub(crate) use queued_outputs;

/// Runs every timer of `machine` that is due up to `until`, each at its
/// own due time and in order, handing every frame sent to `send` with the
/// time it was sent. Events are left in the machine's queue. Stops after
/// `u16::MAX` timer runs (a machine that re-arms a timer in the past would
/// otherwise never finish) and returns how many it ran.
pub fn drive_timers<M: Machine + ?Sized>(
    machine: &mut M,
    until: Timestamp,
    mut send: impl FnMut(Timestamp, CanFrame),
) -> usize {
    let mut runs = 0;
    while let Some(due) = machine.poll_timeout().filter(|t| *t <= until) {
        if runs >= usize::from(u16::MAX) {
            break;
        }
        runs += 1;
        machine.handle_timeout(due);
        while let Some(frame) = machine.poll_transmit() {
            send(due, frame);
        }
    }
    runs
}

/// Test support for the contract's deadlines: `m` names `due` as its next
/// deadline, and time passing up to a millisecond before it sends nothing
/// and leaves that deadline as it was (the deadline is exact). Events are
/// left in the queue.
#[cfg(test)]
pub(crate) fn assert_quiet_until<M: Machine + ?Sized>(m: &mut M, due: Timestamp) {
    assert_eq!(m.poll_timeout(), Some(due), "the next deadline");
    m.handle_timeout(Timestamp::from_micros(due.as_micros() - 1000));
    assert!(m.poll_transmit().is_none(), "a frame before {due}");
    assert_eq!(
        m.poll_timeout(),
        Some(due),
        "the deadline after time passed"
    );
}
