//! One simulated CAN bus for any number of state machines (feature `sim`):
//! quinn-proto's two-endpoint test `Pair` generalised to a broadcast bus,
//! sans-IO like the machines on it. Time is the bus's own clock, from
//! [`Timestamp::ZERO`], moved only by the caller's `run_until`, `step` or
//! `drive_bounded`; the same calls give the same log, faults included.
//!
//! - **Machines** of any types implementing [`Machine`] are added by name
//!   ([`Bus::add`]); the typed [`Handle`] gives typed access to the
//!   machine ([`Bus::machine`], [`Bus::with`]) and to its events
//!   ([`Bus::events`]). A machine can be unplugged and another plugged into
//!   its place ([`Bus::unplug`], [`Bus::plug`]), or disconnected while it
//!   runs on ([`Bus::set_connected`]: a cable pulled).
//! - **Delivery**: every frame reaches every *other* plugged, connected
//!   machine one latency after it was sent ([`Bus::set_latency`]), in send
//!   order and to the machines in the order they were added. The caller can
//!   put frames on the bus itself ([`Bus::inject`], sender [`OUTSIDE`]).
//!   CAN arbitration is not modelled: frames sent at the same instant go
//!   out in the order they were made.
//! - **A step** ([`Bus::step`]) moves the clock to the earliest of the next
//!   delivery and every plugged machine's `poll_timeout`, delivers every
//!   frame due by then, then calls `handle_timeout(now)` on every plugged
//!   machine. After every call into a machine (and every command run with
//!   [`Bus::with`]) its `poll_transmit` queue is drained onto the bus (so a
//!   machine never loses a frame to back-pressure) and its `poll_event`
//!   queue into the bus's record of its events, with the time, unless
//!   [`Bus::set_drain_events`] leaves them to the caller.
//! - **Faults**: frames are numbered from 0 in send order, injected ones
//!   included. A drop, duplicate or delay applies to the frames a predicate
//!   picks ([`Bus::drop_if`], [`Bus::duplicate_if`], [`Bus::delay_if`]; the
//!   predicate sees the [`Sent`] record, sender included, so faults can be
//!   per direction) or to one frame by number ([`Bus::drop_nth`],
//!   [`Bus::duplicate_nth`]). A random loss ([`Bus::set_loss`]) drops each
//!   frame with a probability drawn from a seeded generator (SplitMix64):
//!   the same seed loses the same frames.
//! - **Bus-off** ([`Bus::bus_off`]): for a window of time nothing is sent
//!   or delivered. Frames the machines send during it are lost (fate
//!   [`Fate::BusOff`], counted by [`Bus::lost_to_bus_off`]), and so are
//!   frames in flight that fall due in it. The machines are not told: a CAN
//!   controller's bus-off (CiA 301 section 7.2.8, the error counters of
//!   ISO 11898-1) is reported to a device by its application, which a test
//!   does through [`Bus::with`] (for example `Charger::set_bus_error`).
//! - **Fault confinement** ([`Bus::confine_errors`], off by default): each
//!   machine's CAN controller counts the errors it sees (ISO 11898-1), so
//!   a lossy bus takes it error passive and a bus that is off takes it
//!   bus-off, deaf and mute until it recovers ([`Bus::controller_state`]).
//! - **Observation**: [`Bus::run_until_observed`] and
//!   [`Bus::step_observed`] call an observer around every single delivery
//!   ([`Delivery`]: which frame, to which machine, before or after it was
//!   handled) with the whole bus to look at, for checks that must hold at
//!   each frame rather than after a step (a fuzz target's invariants).
//! - **Log**: every frame sent, with its number, send time, sender and fate
//!   ([`Bus::log`], [`Bus::lines`]); [`Bus::set_logging`] turns it off for
//!   long runs and benches (frames are still numbered).
//! - [`Bus::run_until`] runs every delivery and timer up to and including
//!   an instant; [`Bus::drive_bounded`] runs until quiescent (nothing in
//!   flight, no timer armed). Both stop with a [`Livelock`] error after a
//!   bounded number of steps (a machine that keeps re-arming a timer at
//!   the same instant, two machines answering each other forever).
//!
//! ```
//! use canopen_codec::nmt::heartbeat::{ConsumerEntry, HeartbeatConsumer, HeartbeatEvent, HeartbeatProducer};
//! use canopen_codec::sim::bus::{Bus, Fate};
//! use canopen_codec::{NodeId, Timestamp};
//! use core::time::Duration;
//!
//! let node = NodeId::new(5).unwrap();
//! let mut bus = Bus::new(Duration::from_micros(500));
//! let p = bus.add("Producer", HeartbeatProducer::new(node, Duration::from_millis(100)));
//! let mut consumer = HeartbeatConsumer::<1>::new();
//! consumer.set_entry(Timestamp::ZERO, 0, ConsumerEntry::new(node, Duration::from_millis(250)));
//! let c = bus.add("Consumer", consumer);
//! bus.with(p, |producer, now| producer.boot(now));
//! bus.run_until(Timestamp::from_millis(350)).unwrap();
//! // The boot-up and three heartbeats, each heard half a millisecond later.
//! assert_eq!(bus.lines(0, 350)[1], "   100.000 Producer 705#7F");
//! assert_eq!(bus.log().len(), 4);
//!
//! // From 400 ms the bus is off for a second: the consumer loses the node,
//! // and finds it again once the bus is back.
//! bus.bus_off(Timestamp::from_millis(400), Timestamp::from_millis(1400));
//! bus.run_until(Timestamp::from_millis(1600)).unwrap();
//! assert!(bus.log()[4..14].iter().all(|s| s.fate == Fate::BusOff));
//! assert_eq!(bus.lost_to_bus_off(), 10);
//! use canopen_codec::nmt::NmtState::PreOperational;
//! assert_eq!(
//!     bus.event_list(c),
//!     [
//!         HeartbeatEvent::BootUp(node),
//!         HeartbeatEvent::StateChanged { node, state: PreOperational },
//!         HeartbeatEvent::Lost(node),
//!         HeartbeatEvent::Restored { node, state: PreOperational },
//!     ]
//! );
//! ```

use alloc::boxed::Box;
use alloc::collections::VecDeque;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;
use core::marker::PhantomData;
use core::time::Duration;

use crate::clock::Timestamp;
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;

/// The sender name of frames put on the bus with [`Bus::inject`]: a node
/// that is not simulated (an NMT master, a tool).
pub const OUTSIDE: &str = "Outside";

/// Clock steps [`Bus::run_until`] takes before it reports a [`Livelock`].
pub const RUN_UNTIL_MAX_STEPS: usize = 1_000_000;

mod controller;
mod record;
mod slot;

pub use controller::{ControllerState, RECOVERY};
pub use record::{Delivery, Fate, Handle, Livelock, Sent};
use record::{Loss, SplitMix64};
use slot::{Entry, Slot};

/// What [`Bus::step_observed`] calls around every delivery.
type Observer<'a> = &'a mut dyn FnMut(&Delivery, &Bus);

struct InFlight {
    arrives: Timestamp,
    /// Send number (the log's index when logging).
    n: usize,
    /// Index of the sender (`None`: injected).
    from: Option<usize>,
    frame: CanFrame,
}

enum FaultKind {
    Drop,
    Duplicate,
    Delay(Duration),
}

struct Fault {
    kind: FaultKind,
    applies: Box<dyn FnMut(&Sent) -> bool>,
}

/// The simulated bus. See the [module docs](self).
pub struct Bus {
    now: Timestamp,
    latency: Duration,
    entries: Vec<Entry>,
    log: Vec<Sent>,
    logging: bool,
    sent: usize,
    in_flight: VecDeque<InFlight>,
    faults: Vec<Fault>,
    loss: Option<Loss>,
    /// The bus-off window, `[from, until)`.
    off: Option<(Timestamp, Timestamp)>,
    lost_to_bus_off: u64,
    /// The controllers' fault confinement is modelled.
    confine: bool,
}

impl fmt::Debug for Bus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Bus")
            .field("now", &self.now)
            .field("latency", &self.latency)
            .field(
                "machines",
                &self.entries.iter().map(|e| e.name).collect::<Vec<_>>(),
            )
            .field("sent", &self.sent)
            .field("in_flight", &self.in_flight.len())
            .finish_non_exhaustive()
    }
}

impl Bus {
    /// An empty bus at [`Timestamp::ZERO`] whose frames arrive `latency`
    /// after they are sent (rounded down to the microsecond).
    #[must_use]
    pub fn new(latency: Duration) -> Self {
        Bus {
            now: Timestamp::ZERO,
            latency,
            entries: Vec::new(),
            log: Vec::new(),
            logging: true,
            sent: 0,
            in_flight: VecDeque::new(),
            faults: Vec::new(),
            loss: None,
            off: None,
            lost_to_bus_off: 0,
            confine: false,
        }
    }

    /// The bus's clock.
    #[must_use]
    pub const fn now(&self) -> Timestamp {
        self.now
    }

    /// The one-way latency.
    #[must_use]
    pub const fn latency(&self) -> Duration {
        self.latency
    }

    /// Sets the one-way latency of the frames sent from now on.
    pub fn set_latency(&mut self, latency: Duration) {
        self.latency = latency;
    }

    /// Adds a machine; anything it has queued already goes on the bus now.
    pub fn add<M: Machine + 'static>(&mut self, name: &'static str, machine: M) -> Handle<M> {
        let h = self.add_unplugged(name);
        if let Some(slot) = self.slot_mut(h) {
            slot.machine = Some(machine);
        }
        self.flush(h.index);
        h
    }

    /// Adds a place for a machine of type `M` with nothing plugged in yet.
    pub fn add_unplugged<M: Machine + 'static>(&mut self, name: &'static str) -> Handle<M> {
        self.entries.push(Entry::new::<M>(name));
        Handle {
            index: self.entries.len().saturating_sub(1),
            machine: PhantomData,
        }
    }

    /// Plugs `machine` into the place of `h`, replacing (and returning)
    /// the one that was there; its recorded events are kept. What it has
    /// queued goes on the bus now.
    ///
    /// # Errors
    ///
    /// Hands `machine` back if `h` is not a handle of this bus.
    pub fn plug<M: Machine + 'static>(&mut self, h: Handle<M>, machine: M) -> Result<Option<M>, M> {
        let Some(slot) = self.slot_mut(h) else {
            return Err(machine);
        };
        let old = slot.machine.replace(machine);
        self.flush(h.index);
        Ok(old)
    }

    /// Takes the machine off the bus: it receives nothing and its timers
    /// no longer run. Frames it already sent are still delivered.
    pub fn unplug<M: Machine + 'static>(&mut self, h: Handle<M>) -> Option<M> {
        self.slot_mut(h)?.machine.take()
    }

    /// Whether a machine is plugged into the place of `h`.
    #[must_use]
    pub fn is_plugged<M: Machine + 'static>(&self, h: Handle<M>) -> bool {
        self.slot(h).is_some_and(|s| s.machine.is_some())
    }

    /// Connects the machine to the bus (the default) or disconnects it: a
    /// disconnected machine keeps running (its timers and commands), but
    /// hears nothing and its frames are lost ([`Fate::Disconnected`]).
    pub fn set_connected<M: Machine + 'static>(&mut self, h: Handle<M>, connected: bool) {
        if let Some(slot) = self.slot_mut(h) {
            slot.connected = connected;
        }
    }

    /// The name the machine was added with.
    #[must_use]
    pub fn name<M>(&self, h: Handle<M>) -> Option<&'static str> {
        self.entries.get(h.index).map(|e| e.name)
    }

    /// The machine, if plugged.
    #[must_use]
    pub fn machine<M: Machine + 'static>(&self, h: Handle<M>) -> Option<&M> {
        self.slot(h)?.machine.as_ref()
    }

    /// The machine, if plugged. What a call through this reference queues
    /// goes on the bus at the next step; [`Bus::with`] puts it on now.
    pub fn machine_mut<M: Machine + 'static>(&mut self, h: Handle<M>) -> Option<&mut M> {
        self.slot_mut(h)?.machine.as_mut()
    }

    /// Runs a command on the machine at the bus's time, then puts what it
    /// queued on the bus and records its events. `None` (and nothing run)
    /// if no machine is plugged there.
    pub fn with<M: Machine + 'static, R>(
        &mut self,
        h: Handle<M>,
        command: impl FnOnce(&mut M, Timestamp) -> R,
    ) -> Option<R> {
        let now = self.now;
        let r = command(self.machine_mut(h)?, now);
        self.flush(h.index);
        Some(r)
    }

    /// The machine's recorded events, with the time each was drained.
    #[must_use]
    pub fn events<M: Machine + 'static>(&self, h: Handle<M>) -> &[(Timestamp, M::Event)] {
        self.slot(h).map_or(&[], |s| &s.events)
    }

    /// The machine's recorded events, without their times.
    #[must_use]
    pub fn event_list<M: Machine + 'static>(&self, h: Handle<M>) -> Vec<M::Event>
    where
        M::Event: Clone,
    {
        self.events(h).iter().map(|(_, e)| e.clone()).collect()
    }

    /// Takes the machine's recorded events.
    pub fn take_events<M: Machine + 'static>(
        &mut self,
        h: Handle<M>,
    ) -> Vec<(Timestamp, M::Event)> {
        self.slot_mut(h)
            .map(|s| core::mem::take(&mut s.events))
            .unwrap_or_default()
    }

    /// Forgets the recorded events of every machine (keeping their
    /// storage: a loop that clears them allocates no more).
    pub fn clear_events(&mut self) {
        for e in &mut self.entries {
            e.node.clear_events();
        }
    }

    /// Whether the bus drains the machine's events into its record after
    /// every call (the default). Switched off, they stay in the machine's
    /// own queue for the caller (which keeps only so many: see
    /// [`Machine::events_dropped`]).
    pub fn set_drain_events<M: Machine + 'static>(&mut self, h: Handle<M>, drain: bool) {
        if let Some(slot) = self.slot_mut(h) {
            slot.drain = drain;
        }
    }

    /// Loses the frame with send number `n`.
    pub fn drop_nth(&mut self, n: usize) {
        self.drop_if(move |s| s.n == n);
    }

    /// Loses every frame for which `applies` is true (called once per
    /// frame, in the order the faults were added).
    pub fn drop_if(&mut self, applies: impl FnMut(&Sent) -> bool + 'static) {
        self.add_fault(FaultKind::Drop, applies);
    }

    /// Delivers the frame with send number `n` twice.
    pub fn duplicate_nth(&mut self, n: usize) {
        self.duplicate_if(move |s| s.n == n);
    }

    /// Delivers every frame for which `applies` is true twice (a lost
    /// frame stays lost).
    pub fn duplicate_if(&mut self, applies: impl FnMut(&Sent) -> bool + 'static) {
        self.add_fault(FaultKind::Duplicate, applies);
    }

    /// Delivers every frame for which `applies` is true `delay` after the
    /// latency, behind the frames sent after it meanwhile (a frame
    /// reordered); its copies, if duplicated, are delayed alike.
    pub fn delay_if(&mut self, delay: Duration, applies: impl FnMut(&Sent) -> bool + 'static) {
        self.add_fault(FaultKind::Delay(delay), applies);
    }

    /// Loses each frame sent from now on with `probability` (0 or less, or
    /// NaN: none; 1 or more: all), drawn from a SplitMix64 generator
    /// seeded with `seed`: the same seed and the same traffic lose the
    /// same frames. Frames lost to a fault, a disconnection or bus-off
    /// draw no number.
    pub fn set_loss(&mut self, probability: f64, seed: u64) {
        // 2^64: the generator's words are uniform on [0, 2^64).
        const SPAN: f64 = 18_446_744_073_709_551_616.0;
        // `as` saturates: a probability of 1 or more is `all`.
        self.loss = (probability > 0.0).then_some(Loss {
            threshold: (probability * SPAN) as u64,
            all: probability >= 1.0,
            rng: SplitMix64(seed),
        });
    }

    /// The bus is off from `from` until just before `until`: frames sent
    /// in that window, and frames in flight that fall due in it, are lost
    /// ([`Fate::BusOff`]). Replaces an earlier window.
    pub fn bus_off(&mut self, from: Timestamp, until: Timestamp) {
        self.off = Some((from, until));
        for e in &mut self.entries {
            e.controller.extend(from, until);
        }
    }

    /// Whether the bus is off at `at`.
    #[must_use]
    pub fn is_off(&self, at: Timestamp) -> bool {
        self.off
            .is_some_and(|(from, until)| at.has_reached(from) && !at.has_reached(until))
    }

    /// How many frames bus-off has lost so far (sent during it or due
    /// during it).
    #[must_use]
    pub const fn lost_to_bus_off(&self) -> u64 {
        self.lost_to_bus_off
    }

    /// Puts a frame on the bus from outside (e.g. an NMT master that is not
    /// simulated): it reaches every machine.
    pub fn inject(&mut self, frame: CanFrame) {
        self.put(None, frame);
    }

    /// Keeps a log of every frame (the default) or none, for long runs and
    /// benches: frames are still numbered and faults still see them.
    pub fn set_logging(&mut self, on: bool) {
        self.logging = on;
    }

    /// Every frame sent so far (while logging).
    #[must_use]
    pub fn log(&self) -> &[Sent] {
        &self.log
    }

    /// Takes the log so far, leaving it empty (frames are still numbered
    /// on): for a caller that keeps its own record of a long run. A frame
    /// taken while still in flight keeps the fate it had when taken.
    pub fn take_log(&mut self) -> Vec<Sent> {
        core::mem::take(&mut self.log)
    }

    /// [`take_log`](Self::take_log) into `into` (emptied first), the bus
    /// keeping `into`'s storage for the log that follows: a caller that
    /// takes the log after every step allocates no more for it.
    pub fn take_log_into(&mut self, into: &mut Vec<Sent>) {
        into.clear();
        core::mem::swap(&mut self.log, into);
    }

    /// How many frames were sent so far (logged or not).
    #[must_use]
    pub const fn frames_sent(&self) -> usize {
        self.sent
    }

    /// Frames sent by the machine or sender called `from`.
    pub fn sent_by<'a>(&'a self, from: &'a str) -> impl Iterator<Item = &'a Sent> + 'a {
        self.log.iter().filter(move |s| s.from == from)
    }

    /// The log between two instants (milliseconds, both included), one
    /// line per frame as [`Sent`] displays it.
    #[must_use]
    pub fn lines(&self, from_ms: u64, to_ms: u64) -> Vec<String> {
        self.log
            .iter()
            .filter(|s| (from_ms..=to_ms).contains(&s.at.as_millis()))
            .map(alloc::string::ToString::to_string)
            .collect()
    }

    /// Frames sent with this standard identifier (lost ones included), as
    /// (send time in microseconds, data).
    #[must_use]
    pub fn frames_on(&self, id: u16) -> Vec<(u64, Vec<u8>)> {
        self.log
            .iter()
            .filter(|s| s.frame.id() == CanId::Standard(id))
            .map(|s| (s.at.as_micros(), s.frame.data().to_vec()))
            .collect()
    }

    /// When something is next due: the earliest of the next delivery and
    /// every plugged machine's timer (`None`: quiescent).
    #[must_use]
    pub fn next_due(&self) -> Option<Timestamp> {
        let deliveries = self.in_flight.iter().map(|d| Some(d.arrives));
        crate::clock::earliest(deliveries.chain(self.entries.iter().map(Entry::due)))
    }

    /// Moves the clock to `to` (never back) without running anything:
    /// for a caller that has run everything due before it.
    pub fn advance(&mut self, to: Timestamp) {
        self.now = self.now.max(to);
    }

    /// One clock step (see the [module docs](self)) if something is due
    /// no later than `limit`; returns whether it took one.
    pub fn step(&mut self, limit: Timestamp) -> bool {
        self.step_until(Some(limit), None)
    }

    /// [`Bus::step`], calling `observe` with the bus just before and just
    /// after each machine handles each frame delivered in the step (see
    /// [`Delivery`]). Timers run after the deliveries, unobserved.
    pub fn step_observed(
        &mut self,
        limit: Timestamp,
        observe: &mut dyn FnMut(&Delivery, &Bus),
    ) -> bool {
        self.step_until(Some(limit), Some(observe))
    }

    /// [`Bus::run_until`], calling `observe` around every delivery as
    /// [`Bus::step_observed`] does.
    ///
    /// # Errors
    ///
    /// [`Livelock`] after [`RUN_UNTIL_MAX_STEPS`] steps.
    pub fn run_until_observed(
        &mut self,
        end: Timestamp,
        observe: &mut dyn FnMut(&Delivery, &Bus),
    ) -> Result<(), Livelock> {
        self.run_until_with(end, Some(observe))
    }

    /// Runs every delivery and timer up to and including `end`; the clock
    /// is then at `end` (or later, if it already was).
    ///
    /// # Errors
    ///
    /// [`Livelock`] after [`RUN_UNTIL_MAX_STEPS`] steps (the clock stays
    /// where the last step left it).
    pub fn run_until(&mut self, end: Timestamp) -> Result<(), Livelock> {
        self.run_until_with(end, None)
    }

    /// [`run_until`](Self::run_until), each delivery shown to `observe`
    /// when there is one.
    fn run_until_with(
        &mut self,
        end: Timestamp,
        mut observe: Option<Observer<'_>>,
    ) -> Result<(), Livelock> {
        for _ in 0..RUN_UNTIL_MAX_STEPS {
            let again = observe.as_mut().map(|o| &mut **o as Observer<'_>);
            if !self.step_until(Some(end), again) {
                self.advance(end);
                return Ok(());
            }
        }
        Err(Livelock {
            steps: RUN_UNTIL_MAX_STEPS,
            now: self.now,
        })
    }

    /// Runs until nothing is in flight and no timer is armed.
    ///
    /// # Errors
    ///
    /// [`Livelock`] if still busy after `max_steps` clock steps.
    pub fn drive_bounded(&mut self, max_steps: usize) -> Result<(), Livelock> {
        for _ in 0..max_steps {
            if !self.step_until(None, None) {
                return Ok(());
            }
        }
        Err(Livelock {
            steps: max_steps,
            now: self.now,
        })
    }

    fn add_fault(&mut self, kind: FaultKind, applies: impl FnMut(&Sent) -> bool + 'static) {
        self.faults.push(Fault {
            kind,
            applies: Box::new(applies),
        });
    }

    fn slot<M: Machine + 'static>(&self, h: Handle<M>) -> Option<&Slot<M>> {
        self.entries.get(h.index)?.node.as_any().downcast_ref()
    }

    /// The slot, for the caller: what it does there is flushed at the
    /// next step, and the machine's deadline asked again.
    fn slot_mut<M: Machine + 'static>(&mut self, h: Handle<M>) -> Option<&mut Slot<M>> {
        let e = self.entries.get_mut(h.index)?;
        e.due.set(None);
        e.touched = true;
        e.node.as_any_mut().downcast_mut()
    }

    /// The fate of a frame sent now by `from`, with its delay.
    fn fate(&mut self, sent: &mut Sent, from: Option<usize>) {
        if self.confined_off(from) || self.is_off(self.now) {
            sent.fate = Fate::BusOff;
            self.lost_to_bus_off = self.lost_to_bus_off.saturating_add(1);
            return;
        }
        let connected = from
            .and_then(|i| self.entries.get(i))
            .is_none_or(|e| e.node.is_connected());
        if !connected {
            sent.fate = Fate::Disconnected;
            return;
        }
        let (mut dropped, mut duplicated, mut delay) = (false, false, Duration::ZERO);
        for fault in &mut self.faults {
            if (fault.applies)(sent) {
                match fault.kind {
                    FaultKind::Drop => dropped = true,
                    FaultKind::Duplicate => duplicated = true,
                    FaultKind::Delay(d) => delay = delay.saturating_add(d),
                }
            }
        }
        sent.delay = delay;
        sent.fate = if dropped {
            Fate::Dropped
        } else if self.loss.as_mut().is_some_and(|l| {
            let word = l.rng.next_u64();
            l.all || word < l.threshold
        }) {
            Fate::Lost
        } else if duplicated {
            Fate::Duplicated
        } else {
            Fate::Delivered
        };
        if let Some(i) = from.filter(|_| self.confine) {
            self.confine_sent(i, sent.fate);
        }
    }

    fn put(&mut self, from: Option<usize>, frame: CanFrame) {
        let mut sent = Sent {
            n: self.sent,
            at: self.now,
            from: from
                .and_then(|i| self.entries.get(i))
                .map_or(OUTSIDE, |e| e.name),
            frame,
            fate: Fate::Delivered,
            delay: Duration::ZERO,
        };
        self.sent = self.sent.saturating_add(1);
        self.fate(&mut sent, from);
        let copies = match sent.fate {
            Fate::Delivered => 1,
            Fate::Duplicated => 2,
            _ => 0,
        };
        let arrives = self
            .now
            .add_duration(self.latency.saturating_add(sent.delay));
        for _ in 0..copies {
            self.in_flight.push_back(InFlight {
                arrives,
                n: sent.n,
                from,
                frame,
            });
        }
        if self.logging {
            self.log.push(sent);
        }
    }

    /// Puts what machine `i` queued on the bus and records its events.
    fn flush(&mut self, i: usize) {
        while let Some(f) = self.entries.get_mut(i).and_then(|e| e.node.poll_transmit()) {
            self.put(Some(i), f);
        }
        if let Some(e) = self.entries.get_mut(i) {
            e.node.record_events(self.now);
            // A call into the machine, its sending included, may move
            // its deadline.
            e.due.set(None);
            e.touched = false;
        }
    }

    /// A frame in flight falls due while the bus is off: it is lost.
    fn lost_in_flight(&mut self, n: usize) {
        self.lost_to_bus_off = self.lost_to_bus_off.saturating_add(1);
        // The log's index is the send number while logging was on from
        // the start; otherwise find the record by its number.
        let at = match self.log.get(n) {
            Some(s) if s.n == n => Some(n),
            _ => self.log.iter().position(|s| s.n == n),
        };
        if let Some(s) = at.and_then(|i| self.log.get_mut(i)) {
            s.fate = Fate::BusOff;
        }
    }

    /// One clock step, if something is due no later than `limit`.
    fn step_until(&mut self, limit: Option<Timestamp>, mut observe: Option<Observer<'_>>) -> bool {
        // What the caller did to a machine since (every call of the bus's
        // own is flushed at once).
        for i in 0..self.entries.len() {
            if self.entries.get(i).is_some_and(|e| e.touched) {
                self.flush(i);
            }
        }
        let Some(next) = self
            .next_due()
            .filter(|t| limit.is_none_or(|l| l.has_reached(*t)))
        else {
            return false;
        };
        self.advance(next);
        while let Some(pos) = self
            .in_flight
            .iter()
            .position(|d| self.now.has_reached(d.arrives))
        {
            let Some(d) = self.in_flight.remove(pos) else {
                break;
            };
            if self.is_off(self.now) {
                self.lost_in_flight(d.n);
                continue;
            }
            let from = d
                .from
                .and_then(|i| self.entries.get(i))
                .map_or(OUTSIDE, |e| e.name);
            for i in 0..self.entries.len() {
                let Some(e) = self.entries.get(i) else {
                    break;
                };
                if Some(i) == d.from || !e.node.is_connected() || self.deaf(i) {
                    continue;
                }
                let mut seen = Delivery {
                    n: d.n,
                    at: self.now,
                    from,
                    to: e.name,
                    frame: d.frame,
                    handled: false,
                };
                if let Some(o) = observe.as_mut() {
                    o(&seen, self);
                }
                if let Some(e) = self.entries.get_mut(i) {
                    e.node.handle_frame(self.now, &d.frame);
                }
                self.flush(i);
                if let Some(o) = observe.as_mut() {
                    seen.handled = true;
                    o(&seen, self);
                }
            }
        }
        for i in 0..self.entries.len() {
            let Some(e) = self.entries.get_mut(i) else {
                break;
            };
            if e.node.is_plugged() {
                e.node.handle_timeout(self.now);
                self.flush(i);
            }
        }
        true
    }
}
