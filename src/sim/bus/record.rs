//! What the simulated bus hands out and records: typed handles, the log
//! of frames with their fates, the livelock error, and the seeded
//! generator of the random loss.

use core::fmt;
use core::marker::PhantomData;
use core::time::Duration;

use crate::clock::Timestamp;
use crate::frame::CanFrame;

#[cfg(doc)]
use super::{Bus, OUTSIDE};

/// A typed reference to a machine added to a [`Bus`]. It is meaningful
/// only on the bus that made it: on another bus the calls find no machine.
pub struct Handle<M> {
    pub(super) index: usize,
    pub(super) machine: PhantomData<fn() -> M>,
}

impl<M> Clone for Handle<M> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<M> Copy for Handle<M> {}

impl<M> fmt::Debug for Handle<M> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Handle({})", self.index)
    }
}

impl<M> PartialEq for Handle<M> {
    fn eq(&self, other: &Self) -> bool {
        self.index == other.index
    }
}

impl<M> Eq for Handle<M> {}

/// What became of a frame put on the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Fate {
    /// Delivered once to every other plugged, connected machine.
    Delivered,
    /// Delivered twice (a duplicate fault), one copy right after the other.
    Duplicated,
    /// Lost by a drop fault.
    Dropped,
    /// Lost by the random loss of [`Bus::set_loss`].
    Lost,
    /// Lost because the bus was off when it was sent or when it fell due.
    BusOff,
    /// Lost because its sender was disconnected ([`Bus::set_connected`]).
    Disconnected,
}

impl Fate {
    /// Whether the frame reached the other machines.
    #[must_use]
    pub const fn reached_the_bus(self) -> bool {
        matches!(self, Fate::Delivered | Fate::Duplicated)
    }

    /// The word [`Sent`]'s display appends (empty for a delivered frame).
    const fn suffix(self) -> &'static str {
        match self {
            Fate::Delivered => "",
            Fate::Duplicated => " duplicated",
            Fate::Dropped => " dropped",
            Fate::Lost => " lost",
            Fate::BusOff => " bus-off",
            Fate::Disconnected => " disconnected",
        }
    }
}

/// One frame put on the bus, as the log keeps it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sent {
    /// Send number, from 0.
    pub n: usize,
    /// Send time.
    pub at: Timestamp,
    /// The sender's name ([`OUTSIDE`] for injected frames).
    pub from: &'static str,
    /// The frame.
    pub frame: CanFrame,
    /// What became of it.
    pub fate: Fate,
    /// How much later than the latency it arrives (a delay fault).
    pub delay: Duration,
}

impl fmt::Display for Sent {
    /// `"ms.µs sender frame"`, the milliseconds right-aligned in six
    /// columns, the fate appended when the frame was not simply delivered
    /// (` dropped`, ` duplicated`, ` lost`, ` bus-off`, ` disconnected`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:>6}.{:03} {} {}{}",
            self.at.as_millis(),
            self.at.as_micros() % 1000,
            self.from,
            self.frame,
            self.fate.suffix()
        )
    }
}

/// The bus did not get where it was asked to in the steps it was given:
/// a machine keeps re-arming a timer that is already due, or machines
/// keep answering each other without end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("livelock: not done after {steps} steps (the bus clock at {now})")]
pub struct Livelock {
    /// The steps taken.
    pub steps: usize,
    /// The bus's clock when it gave up.
    pub now: Timestamp,
}

/// SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number
/// generators", OOPSLA 2014): one 64-bit word of state, every seed good.
#[derive(Debug, Clone, Copy)]
pub(super) struct SplitMix64(pub(super) u64);

impl SplitMix64 {
    pub(super) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// The random loss: a frame is lost when the generator's next word is
/// below `threshold` (probability `threshold / 2^64`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Loss {
    pub(super) threshold: u64,
    pub(super) all: bool,
    pub(super) rng: SplitMix64,
}

/// One frame handed to one machine during a step, as an observer of
/// [`Bus::run_until_observed`] or [`Bus::step_observed`] sees it: once
/// just before the machine handles it (`handled` false) and once just
/// after, when what the machine queued in answer is already on the bus
/// (in its log) and its events are recorded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Delivery {
    /// The frame's send number (its index in the log while logging).
    pub n: usize,
    /// When it is delivered (the bus's clock).
    pub at: Timestamp,
    /// Who sent it ([`OUTSIDE`] for an injected frame).
    pub from: &'static str,
    /// The machine it is handed to, by the name it was added with.
    pub to: &'static str,
    /// The frame.
    pub frame: CanFrame,
    /// Whether the machine has handled it yet.
    pub handled: bool,
}
