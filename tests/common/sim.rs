//! `Sim`: any number of state machines on one simulated CAN bus, driven
//! through the library's [`Machine`] trait only (quinn-proto's two-endpoint
//! `Pair` generalised).
//!
//! - **Machines** of any types are added with a name
//!   (`let c = sim.add("Charger", charger)`); the typed [`Handle`] gives
//!   typed access: [`Sim::machine`], [`Sim::machine_mut`], [`Sim::events`].
//!   A machine can be unplugged and a new one plugged into its place.
//! - **Clock** from `Timestamp::ZERO`; every frame reaches every *other*
//!   plugged machine `latency_us` after it was sent, in send order (a
//!   broadcast bus). The test can put frames on the bus itself
//!   ([`Sim::inject`], sender [`TEST`]) and run commands at the current time
//!   ([`Sim::with`]).
//! - **A step** moves the clock to the earliest of the next delivery and
//!   every plugged machine's `poll_timeout`, delivers every frame due by
//!   then (to each machine in the order they were added), then calls
//!   `handle_timeout(now)` on every plugged machine. After every call (and
//!   every command) the machine's `poll_transmit` queue is drained onto the
//!   bus, and its `poll_event` queue into [`Sim::events`] with the time,
//!   unless [`Sim::set_drain_events`] switched that off for the machine.
//! - **Faults**: frames are numbered from 0 in send order, injected ones
//!   included; [`Sim::drop_nth`], [`Sim::drop_if`], [`Sim::duplicate_nth`],
//!   [`Sim::duplicate_if`] (a predicate sees the sender, so faults can be
//!   per direction), [`Sim::delay_if`] (a frame arrives later than the
//!   ones sent after it: reordered).
//! - **Log**: every frame sent, with its number, send time, sender and fate
//!   ([`Sim::log`], [`Sim::lines`], [`Sim::frames_on`]).
//! - [`Sim::run_until`] runs every delivery and timer up to and including
//!   `end` (panics on livelock); [`Sim::drive_bounded`] runs until
//!   quiescent (nothing in flight, no timer armed) and fails after
//!   `max_steps` steps.

use std::any::Any;
use std::collections::VecDeque;
use std::marker::PhantomData;

use canopen_codec::machine::Machine;
use canopen_codec::{CanFrame, CanId, Timestamp};

/// The sender name of frames the test injects.
pub const TEST: &str = "Test";

/// A typed reference to a machine added to a [`Sim`].
pub struct Handle<M> {
    index: usize,
    _machine: PhantomData<fn() -> M>,
}

impl<M> Clone for Handle<M> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<M> Copy for Handle<M> {}

impl<M> std::fmt::Debug for Handle<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Handle({})", self.index)
    }
}

/// One frame put on the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sent {
    /// Send number, from 0.
    pub n: usize,
    /// Send time.
    pub at: Timestamp,
    /// The sender's name ([`TEST`] for injected frames).
    pub from: &'static str,
    pub frame: CanFrame,
    /// Lost: it reached no machine.
    pub dropped: bool,
    /// Delivered twice, one copy right after the other.
    pub duplicated: bool,
    /// Microseconds it arrives after the latency (0: on time).
    pub delay_us: u64,
}

/// A machine with its recorded events, behind `dyn Node`.
struct Slot<M: Machine> {
    machine: Option<M>,
    events: Vec<(Timestamp, M::Event)>,
    drain: bool,
}

/// What the bus needs of a slot, whatever the machine's type.
trait Node {
    fn is_plugged(&self) -> bool;
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame);
    fn handle_timeout(&mut self, now: Timestamp);
    fn poll_transmit(&mut self) -> Option<CanFrame>;
    fn poll_timeout(&self) -> Option<Timestamp>;
    fn record_events(&mut self, now: Timestamp);
    fn clear_events(&mut self);
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

impl<M: Machine + 'static> Node for Slot<M> {
    fn is_plugged(&self) -> bool {
        self.machine.is_some()
    }
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        if let Some(m) = &mut self.machine {
            m.handle_frame(now, frame);
        }
    }
    fn handle_timeout(&mut self, now: Timestamp) {
        if let Some(m) = &mut self.machine {
            m.handle_timeout(now);
        }
    }
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.machine.as_mut()?.poll_transmit()
    }
    fn poll_timeout(&self) -> Option<Timestamp> {
        self.machine.as_ref()?.poll_timeout()
    }
    fn record_events(&mut self, now: Timestamp) {
        if !self.drain {
            return;
        }
        if let Some(m) = &mut self.machine {
            while let Some(e) = m.poll_event() {
                self.events.push((now, e));
            }
        }
    }
    fn clear_events(&mut self) {
        self.events.clear();
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

struct Entry {
    name: &'static str,
    node: Box<dyn Node>,
}

struct InFlight {
    arrives: Timestamp,
    /// Index of the sender (`None`: the test).
    from: Option<usize>,
    frame: CanFrame,
}

enum FaultKind {
    Drop,
    Duplicate,
    Delay(u64),
}

struct Fault {
    kind: FaultKind,
    applies: Box<dyn FnMut(&Sent) -> bool>,
}

/// The simulated bus. See the module docs.
pub struct Sim {
    now: Timestamp,
    /// One-way latency in microseconds (for frames sent from now on).
    pub latency_us: u64,
    /// Steps after which [`Sim::run_until`] gives up (livelock).
    pub max_run_steps: usize,
    entries: Vec<Entry>,
    log: Vec<Sent>,
    in_flight: VecDeque<InFlight>,
    faults: Vec<Fault>,
}

impl Sim {
    /// An empty bus at `Timestamp::ZERO` with this one-way latency.
    pub fn new(latency_us: u64) -> Self {
        Sim {
            now: Timestamp::ZERO,
            latency_us,
            max_run_steps: 1_000_000,
            entries: Vec::new(),
            log: Vec::new(),
            in_flight: VecDeque::new(),
            faults: Vec::new(),
        }
    }

    /// Adds a machine; anything it has queued already goes on the bus now.
    pub fn add<M: Machine + 'static>(&mut self, name: &'static str, machine: M) -> Handle<M> {
        let h = self.add_unplugged(name);
        self.plug(h, machine);
        h
    }

    /// Adds a place for a machine of type `M` with nothing plugged in yet.
    pub fn add_unplugged<M: Machine + 'static>(&mut self, name: &'static str) -> Handle<M> {
        self.entries.push(Entry {
            name,
            node: Box::new(Slot::<M> {
                machine: None,
                events: Vec::new(),
                drain: true,
            }),
        });
        Handle {
            index: self.entries.len() - 1,
            _machine: PhantomData,
        }
    }

    /// Plugs `machine` into the place of `h` (replacing what was there);
    /// its recorded events are kept.
    pub fn plug<M: Machine + 'static>(&mut self, h: Handle<M>, machine: M) {
        self.slot_mut(h).machine = Some(machine);
        self.flush(h.index);
    }

    /// Takes the machine off the bus: it receives nothing and its timers
    /// no longer run. Frames it already sent are still delivered.
    pub fn unplug<M: Machine + 'static>(&mut self, h: Handle<M>) -> Option<M> {
        self.slot_mut(h).machine.take()
    }

    pub fn is_plugged<M: Machine + 'static>(&self, h: Handle<M>) -> bool {
        self.slot(h).machine.is_some()
    }

    pub fn name<M>(&self, h: Handle<M>) -> &'static str {
        self.entries[h.index].name
    }

    pub fn now(&self) -> Timestamp {
        self.now
    }

    pub fn machine<M: Machine + 'static>(&self, h: Handle<M>) -> &M {
        let name = self.name(h);
        self.slot(h)
            .machine
            .as_ref()
            .unwrap_or_else(|| panic!("{name} is unplugged"))
    }

    pub fn machine_mut<M: Machine + 'static>(&mut self, h: Handle<M>) -> &mut M {
        let name = self.name(h);
        self.slot_mut(h)
            .machine
            .as_mut()
            .unwrap_or_else(|| panic!("{name} is unplugged"))
    }

    /// Runs a command on the machine at the current time, then puts what
    /// it queued on the bus.
    pub fn with<M: Machine + 'static, R>(
        &mut self,
        h: Handle<M>,
        command: impl FnOnce(&mut M, Timestamp) -> R,
    ) -> R {
        let now = self.now;
        let r = command(self.machine_mut(h), now);
        self.flush(h.index);
        r
    }

    /// The machine's events so far, with the time they were drained.
    pub fn events<M: Machine + 'static>(&self, h: Handle<M>) -> &[(Timestamp, M::Event)] {
        &self.slot(h).events
    }

    /// The machine's events so far, without their times.
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
        std::mem::take(&mut self.slot_mut(h).events)
    }

    /// Forgets the recorded events of every machine.
    pub fn clear_events(&mut self) {
        for e in &mut self.entries {
            e.node.clear_events();
        }
    }

    /// Whether the bus reads the machine's events after every call (the
    /// default). Switched off, they stay in the machine's own queue.
    pub fn set_drain_events<M: Machine + 'static>(&mut self, h: Handle<M>, drain: bool) {
        self.slot_mut(h).drain = drain;
    }

    /// Loses the frame with send number `n`.
    pub fn drop_nth(&mut self, n: usize) {
        self.drop_if(move |s| s.n == n);
    }

    /// Loses every frame for which `applies` is true (called once per frame).
    pub fn drop_if(&mut self, applies: impl FnMut(&Sent) -> bool + 'static) {
        self.faults.push(Fault {
            kind: FaultKind::Drop,
            applies: Box::new(applies),
        });
    }

    /// Delivers the frame with send number `n` twice.
    pub fn duplicate_nth(&mut self, n: usize) {
        self.duplicate_if(move |s| s.n == n);
    }

    /// Delivers every frame for which `applies` is true twice (a dropped
    /// frame stays dropped).
    pub fn duplicate_if(&mut self, applies: impl FnMut(&Sent) -> bool + 'static) {
        self.faults.push(Fault {
            kind: FaultKind::Duplicate,
            applies: Box::new(applies),
        });
    }

    /// Delivers every frame for which `applies` is true `delay_us` after
    /// the latency, behind the frames sent after it meanwhile (a frame
    /// reordered); its copies, if duplicated, are delayed alike.
    pub fn delay_if(&mut self, delay_us: u64, applies: impl FnMut(&Sent) -> bool + 'static) {
        self.faults.push(Fault {
            kind: FaultKind::Delay(delay_us),
            applies: Box::new(applies),
        });
    }

    /// Puts a frame on the bus from the test (e.g. as the NMT master): it
    /// reaches every machine.
    pub fn inject(&mut self, frame: CanFrame) {
        self.put(None, frame);
    }

    /// Every frame sent so far.
    pub fn log(&self) -> &[Sent] {
        &self.log
    }

    /// Frames sent by the machine or sender called `from`.
    pub fn sent_by(&self, from: &str) -> impl Iterator<Item = &Sent> + '_ {
        let from = from.to_string();
        self.log.iter().filter(move |s| s.from == from)
    }

    /// Runs every delivery and timer up to and including `end`; the clock
    /// is then at `end` (or later, if it was already). Panics after
    /// `max_run_steps` steps (livelock).
    pub fn run_until(&mut self, end: Timestamp) {
        for _ in 0..self.max_run_steps {
            if !self.step(Some(end)) {
                self.now = self.now.max(end);
                return;
            }
        }
        panic!(
            "livelock: the bus never reached {end} ({} steps, now {})",
            self.max_run_steps, self.now
        );
    }

    /// Runs until nothing is in flight and no timer is armed. Fails after
    /// `max_steps` clock steps (livelock).
    pub fn drive_bounded(&mut self, max_steps: usize) -> Result<(), String> {
        for _ in 0..max_steps {
            if !self.step(None) {
                return Ok(());
            }
        }
        Err(format!(
            "livelock: not quiescent after {max_steps} steps (now {})",
            self.now
        ))
    }

    /// The log between two instants (ms, inclusive) as
    /// `"ms.µs sender frame"` lines (` dropped` / ` duplicated` appended).
    pub fn lines(&self, from_ms: u64, to_ms: u64) -> Vec<String> {
        self.log
            .iter()
            .filter(|s| s.at.as_millis() >= from_ms && s.at.as_millis() <= to_ms)
            .map(|s| {
                let fate = match (s.dropped, s.duplicated) {
                    (true, _) => " dropped",
                    (false, true) => " duplicated",
                    (false, false) => "",
                };
                format!(
                    "{:>6}.{:03} {} {}{fate}",
                    s.at.as_millis(),
                    s.at.as_micros() % 1000,
                    s.from,
                    s.frame
                )
            })
            .collect()
    }

    /// Frames sent with this standard identifier (dropped ones included),
    /// as (send time in µs, data).
    pub fn frames_on(&self, id: u16) -> Vec<(u64, Vec<u8>)> {
        self.log
            .iter()
            .filter(|s| s.frame.id() == CanId::Standard(id))
            .map(|s| (s.at.as_micros(), s.frame.data().to_vec()))
            .collect()
    }

    fn slot<M: Machine + 'static>(&self, h: Handle<M>) -> &Slot<M> {
        let e = &self.entries[h.index];
        e.node
            .as_any()
            .downcast_ref()
            .unwrap_or_else(|| panic!("{}: a handle of another type", e.name))
    }

    fn slot_mut<M: Machine + 'static>(&mut self, h: Handle<M>) -> &mut Slot<M> {
        let e = &mut self.entries[h.index];
        let name = e.name;
        e.node
            .as_any_mut()
            .downcast_mut()
            .unwrap_or_else(|| panic!("{name}: a handle of another type"))
    }

    fn put(&mut self, from: Option<usize>, frame: CanFrame) {
        let mut sent = Sent {
            n: self.log.len(),
            at: self.now,
            from: from.map_or(TEST, |i| self.entries[i].name),
            frame,
            dropped: false,
            duplicated: false,
            delay_us: 0,
        };
        for fault in &mut self.faults {
            if (fault.applies)(&sent) {
                match fault.kind {
                    FaultKind::Drop => sent.dropped = true,
                    FaultKind::Duplicate => sent.duplicated = true,
                    FaultKind::Delay(us) => sent.delay_us = sent.delay_us.saturating_add(us),
                }
            }
        }
        sent.duplicated &= !sent.dropped;
        let copies = match (sent.dropped, sent.duplicated) {
            (true, _) => 0,
            (false, false) => 1,
            (false, true) => 2,
        };
        for _ in 0..copies {
            self.in_flight.push_back(InFlight {
                arrives: self
                    .now
                    .add_micros(self.latency_us.saturating_add(sent.delay_us)),
                from,
                frame,
            });
        }
        self.log.push(sent);
    }

    /// Puts what machine `i` queued on the bus and records its events.
    fn flush(&mut self, i: usize) {
        while let Some(f) = self.entries[i].node.poll_transmit() {
            self.put(Some(i), f);
        }
        self.entries[i].node.record_events(self.now);
    }

    /// One clock step (module docs), if there is something to do no later
    /// than `limit`.
    fn step(&mut self, limit: Option<Timestamp>) -> bool {
        for i in 0..self.entries.len() {
            self.flush(i);
        }
        let next = self
            .in_flight
            .iter()
            .map(|d| d.arrives)
            .chain(self.entries.iter().filter_map(|e| e.node.poll_timeout()))
            .min();
        let Some(next) = next.filter(|t| limit.is_none_or(|l| *t <= l)) else {
            return false;
        };
        self.now = self.now.max(next);
        while let Some(pos) = self.in_flight.iter().position(|d| d.arrives <= self.now) {
            let d = self.in_flight.remove(pos).expect("position is in range");
            for i in 0..self.entries.len() {
                if Some(i) != d.from && self.entries[i].node.is_plugged() {
                    self.entries[i].node.handle_frame(self.now, &d.frame);
                    self.flush(i);
                }
            }
        }
        for i in 0..self.entries.len() {
            if self.entries[i].node.is_plugged() {
                self.entries[i].node.handle_timeout(self.now);
                self.flush(i);
            }
        }
        true
    }
}
