//! Heartbeat producer (object 1017h) and consumer (object 1016h), CiA 301,
//! as sans-IO state machines.
//!
//! - [`HeartbeatProducer`] sends the boot-up message once, then
//!   `700h + node # state` every period. By default it sends only on the
//!   period, as the Delta-Q charger does (its capture shows the first
//!   "operational" heartbeat at the next period after NMT start); set
//!   [`HeartbeatProducer::send_on_change`] for CANopenNode's behaviour of
//!   sending at once when the state changes.
//! - [`HeartbeatConsumer`] watches up to `N` nodes. An entry (node id + time
//!   in ms, as a 1016h sub-index: bits 23-16 node, 15-0 time) with node 0 or
//!   time 0 is disabled. Monitoring of a node starts at its first heartbeat.
//!   When more than `time` passes without one, it reports
//!   [`HeartbeatEvent::Lost`] once; the next heartbeat reports
//!   [`HeartbeatEvent::Restored`]. Boot-up messages and state changes are
//!   reported too.
//!
//! Both implement [`Machine`], the crate's state-machine contract. Time that goes backwards
//! never panics: deadlines are simply not reached; a jump far ahead expires
//! every running timer once.

use core::convert::Infallible;
use core::time::Duration;

use crate::clock::{earliest, timer_kind, MaybeTimestamp, Timers, Timestamp};
use crate::cob_id::{NodeId, NMT_ERROR_CONTROL_BASE};
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;
use crate::nmt::{Heartbeat, NmtState};
use crate::queue::{DropOldest, EventQueue};
use crate::wire::Codec;

/// Sends this node's boot-up message and heartbeats.
///
/// ```
/// use canopen_codec::nmt::heartbeat::HeartbeatProducer;
/// use canopen_codec::machine::Machine;
/// use canopen_codec::nmt::NmtState;
/// use canopen_codec::{NodeId, Timestamp};
/// use core::time::Duration;
/// let mut p = HeartbeatProducer::new(NodeId::new(10).unwrap(), Duration::from_millis(1000));
/// p.boot(Timestamp::ZERO);
/// assert_eq!(p.poll_transmit().unwrap().to_string(), "70A#00");
/// p.set_state(Timestamp::ZERO, NmtState::PreOperational);
/// assert_eq!(p.poll_timeout(), Some(Timestamp::from_millis(1000)));
/// p.handle_timeout(Timestamp::from_millis(1000));
/// assert_eq!(p.poll_transmit().unwrap().to_string(), "70A#7F");
/// ```
#[derive(Debug, Clone)]
pub struct HeartbeatProducer {
    node: NodeId,
    period_us: u64,
    state: NmtState,
    timers: Timers<ProducerTimer, 1>,
    /// Send at once when the state changes (CANopenNode); default false.
    pub send_on_change: bool,
    /// The states to send, as heartbeat frames when polled.
    out: DropOldest<NmtState, 2>,
}

timer_kind! {
    /// The producer's one timer.
    enum ProducerTimer {
        /// The next heartbeat.
        NextHeartbeat,
    }
}

impl HeartbeatProducer {
    /// A producer for `node` with period `period` (1017h, whole
    /// milliseconds; zero = no heartbeats).
    #[must_use]
    pub fn new(node: NodeId, period: Duration) -> Self {
        HeartbeatProducer {
            node,
            period_us: whole_millis_us(period),
            state: NmtState::BootUp,
            timers: Timers::new(),
            send_on_change: false,
            out: DropOldest::new(NmtState::BootUp),
        }
    }

    /// A producer for `node` with a period of `ms` milliseconds (1017h as
    /// it is kept; zero = no heartbeats): [`new`](Self::new) without the
    /// `Duration` (a device's reset path, from its 1017h value).
    #[must_use]
    pub(crate) const fn with_period_ms(node: NodeId, ms: u16) -> Self {
        HeartbeatProducer {
            node,
            period_us: ms as u64 * 1000,
            state: NmtState::BootUp,
            timers: Timers::new(),
            send_on_change: false,
            out: DropOldest::new(NmtState::BootUp),
        }
    }

    /// The state reported.
    #[must_use]
    pub const fn state(&self) -> NmtState {
        self.state
    }

    /// The period (whole milliseconds).
    #[must_use]
    pub const fn period(&self) -> Duration {
        Duration::from_micros(self.period_us)
    }

    /// The period in microseconds (whole milliseconds), as the device
    /// core's timers count it.
    pub(crate) const fn period_us(&self) -> u64 {
        self.period_us
    }

    fn arm(&mut self, now: Timestamp) {
        // Zero period: no heartbeat; at the end of the clock: no later one.
        self.timers.set(
            ProducerTimer::NextHeartbeat,
            now.deadline_after(self.period_us),
        );
    }

    /// Queues a frame; a full queue (the caller did not drain
    /// `poll_transmit`) drops its oldest: a heartbeat carries the state now.
    fn send(&mut self, state: NmtState) {
        self.out.push(state);
    }

    /// (Re)boots: sends the boot-up message and enters pre-operational; the
    /// first heartbeat follows one period later.
    pub fn boot(&mut self, now: Timestamp) {
        self.send(NmtState::BootUp);
        self.state = NmtState::PreOperational;
        self.arm(now);
    }

    /// Changes the reported NMT state.
    pub fn set_state(&mut self, now: Timestamp, state: NmtState) {
        let changed = state != self.state;
        self.state = state;
        if changed && self.send_on_change && self.period_us > 0 {
            self.send(state);
            self.arm(now);
        }
    }

    /// Changes the period (1017h written; whole milliseconds, zero stops
    /// the heartbeat). Restarts the timer.
    pub fn set_period(&mut self, now: Timestamp, period: Duration) {
        self.period_us = whole_millis_us(period);
        self.arm(now);
    }

    /// [`set_period`](Self::set_period) with 1017h's milliseconds (a
    /// device's 1017h written): no `Duration`, no saturating arithmetic.
    pub(crate) fn set_period_ms(&mut self, now: Timestamp, ms: u16) {
        self.period_us = u64::from(ms) * 1000;
        self.arm(now);
    }
}

/// `d` truncated to whole milliseconds, in microseconds (1016h and 1017h
/// count milliseconds).
fn whole_millis_us(d: Duration) -> u64 {
    crate::clock::millis_of(d).saturating_mul(1000)
}

impl Machine for HeartbeatProducer {
    type Event = Infallible;

    /// The producer takes no input frames.
    fn handle_frame(&mut self, _now: Timestamp, _frame: &CanFrame) {}

    /// Sends the heartbeat when its time has come. The next one is due one
    /// period after the one just due (a late call does not make the period
    /// drift), or one period from `now` when the call is more than a period
    /// late.
    fn handle_timeout(&mut self, now: Timestamp) {
        let next = ProducerTimer::NextHeartbeat;
        if self.timers.periodic(next, now, self.period_us) {
            self.send(self.state);
        }
    }

    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.out
            .pop()
            .map(|state| Heartbeat::new(state).to_frame(self.node))
    }

    // When the next heartbeat is due.
    crate::machine::queued_outputs!(timers: timers, events: none);

    fn frames_dropped(&self) -> u64 {
        self.out.dropped()
    }
}

/// One consumer entry (a 1016h sub-index).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ConsumerEntry {
    /// The node watched (0 disables the entry).
    pub node: u8,
    /// Heartbeat consumer time in ms (0 disables the entry).
    pub time_ms: u16,
}

impl ConsumerEntry {
    /// The disabled entry (node 0, time 0): 1016h sub-index value 0.
    pub const DISABLED: ConsumerEntry = ConsumerEntry {
        node: 0,
        time_ms: 0,
    };

    /// From the Unsigned32 of a 1016h sub-index.
    #[must_use]
    pub const fn from_u32(raw: u32) -> Self {
        ConsumerEntry {
            node: (raw >> 16) as u8,
            time_ms: raw as u16,
        }
    }

    /// The Unsigned32 (bits 31-24 reserved, 0).
    #[must_use]
    pub const fn to_u32(self) -> u32 {
        (self.node as u32) << 16 | self.time_ms as u32
    }

    /// An entry watching `node` with consumer time `time` (whole
    /// milliseconds, saturating at 65535 ms).
    #[must_use]
    pub fn new(node: NodeId, time: Duration) -> Self {
        ConsumerEntry {
            node: node.raw(),
            time_ms: crate::clock::millis_u16(time),
        }
    }

    /// The consumer time.
    #[must_use]
    pub const fn time(self) -> Duration {
        Duration::from_millis(self.time_ms as u64)
    }

    /// True when the entry watches a node.
    #[must_use]
    pub const fn is_enabled(self) -> bool {
        self.time_ms != 0 && NodeId::new(self.node).is_some()
    }
}

/// What the consumer reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum HeartbeatEvent {
    /// The node sent its boot-up message.
    BootUp(NodeId),
    /// The node's reported state changed (not reported for the first
    /// heartbeat, which starts monitoring).
    StateChanged {
        /// The node.
        node: NodeId,
        /// Its new state.
        state: NmtState,
    },
    /// No heartbeat within the consumer time (reported once per silence).
    Lost(NodeId),
    /// A heartbeat arrived after `Lost`.
    Restored {
        /// The node.
        node: NodeId,
        /// The state it reports.
        state: NmtState,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Watch {
    entry: ConsumerEntry,
    deadline: MaybeTimestamp,
    state: Option<NmtState>,
    lost: bool,
}

impl Watch {
    /// The entry is enabled and names `node` (a node id is never 0 or past
    /// 127, so the node test is [`ConsumerEntry::is_enabled`]'s too).
    const fn watches(&self, node: NodeId) -> bool {
        self.entry.node == node.raw() && self.entry.time_ms != 0
    }
}

const IDLE: Watch = Watch {
    entry: ConsumerEntry {
        node: 0,
        time_ms: 0,
    },
    deadline: MaybeTimestamp::NONE,
    state: None,
    lost: false,
};

/// Watches the heartbeats of up to `N` nodes (1016h sub 1..=N).
///
/// Every heartbeat of a watched node refreshes its deadline, whether or not
/// the application reads the events (the back-pressure rule of
/// [`crate::machine`]): a node that beats within its time is never reported
/// lost. The queue keeps the latest `E` events (default 8). A frame makes
/// at most one event (it feeds the watch of its node only) and a timeout
/// call at most one per watched node, so an owner that drains it after
/// every call needs no more than `N`; the device core keeps none (`E` = 0:
/// it takes each event as it is made).
///
/// ```
/// use canopen_codec::nmt::heartbeat::{ConsumerEntry, HeartbeatConsumer, HeartbeatEvent};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
/// use core::time::Duration;
/// let node = NodeId::new(1).unwrap();
/// let mut c: HeartbeatConsumer<4> = HeartbeatConsumer::new();
/// c.set_entry(Timestamp::ZERO, 0, ConsumerEntry::new(node, Duration::from_millis(2000)));
/// let hb = CanFrame::standard(0x701, &[0x05]).unwrap();
/// c.handle_frame(Timestamp::from_millis(100), &hb);
/// c.handle_timeout(Timestamp::from_millis(2100));
/// assert_eq!(c.poll_event(), Some(HeartbeatEvent::Lost(node)));
/// ```
#[derive(Debug, Clone)]
pub struct HeartbeatConsumer<const N: usize, const E: usize = 8> {
    watches: [Watch; N],
    events: EventQueue<HeartbeatEvent, E>,
}

impl<const N: usize, const E: usize> Default for HeartbeatConsumer<N, E> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize, const E: usize> HeartbeatConsumer<N, E> {
    /// No node watched.
    #[must_use]
    pub const fn new() -> Self {
        HeartbeatConsumer {
            watches: [IDLE; N],
            events: EventQueue::new(HeartbeatEvent::BootUp(NodeId::MIN)),
        }
    }

    /// Sets entry `slot` (0-based: 1016h sub `slot + 1`). A changed entry
    /// restarts monitoring (it waits for the next heartbeat). Returns false
    /// when `slot` is out of range or another enabled entry already watches
    /// the node (CiA 301 forbids duplicates).
    pub fn set_entry(&mut self, now: Timestamp, slot: usize, entry: ConsumerEntry) -> bool {
        let _ = now;
        let duplicate = entry.is_enabled()
            && self
                .watches
                .iter()
                .enumerate()
                .any(|(i, w)| i != slot && w.entry.is_enabled() && w.entry.node == entry.node);
        match self.watches.get_mut(slot) {
            Some(w) if !duplicate => {
                if w.entry != entry {
                    *w = Watch { entry, ..IDLE };
                }
                true
            }
            _ => false,
        }
    }

    /// Entry `slot`.
    #[must_use]
    pub fn entry(&self, slot: usize) -> Option<ConsumerEntry> {
        self.watches.get(slot).map(|w| w.entry)
    }

    /// The last state a node reported, if it is watched and has been heard.
    #[must_use]
    pub fn state(&self, node: NodeId) -> Option<NmtState> {
        self.watch(node).and_then(|w| w.state)
    }

    /// True when the node is watched, has been heard and is not lost.
    #[must_use]
    pub fn is_alive(&self, node: NodeId) -> bool {
        self.watch(node)
            .is_some_and(|w| w.state.is_some() && !w.lost)
    }

    /// Puts `entries` (1016h sub 1.. in order; slots past them are
    /// disabled) into effect: a changed slot, or every slot with `restart`,
    /// waits for its node's next heartbeat; the others run on. No
    /// duplicate check (a device's 1016h refuses them): of two enabled
    /// slots for one node, only the first is ever fed, so the second
    /// never starts and reports nothing.
    #[cfg(feature = "heartbeat-consumer")]
    pub(crate) fn load_entries(&mut self, entries: &[ConsumerEntry], restart: bool) {
        let mut entries = entries.iter();
        for w in &mut self.watches {
            let entry = entries.next().copied().unwrap_or_default();
            if restart || w.entry != entry {
                *w = Watch { entry, ..IDLE };
            }
        }
    }

    /// What a received frame makes: at most one event, as a heartbeat
    /// feeds only the watch of its node (the first enabled one).
    pub(crate) fn take_frame(
        &mut self,
        now: Timestamp,
        frame: &CanFrame,
    ) -> Option<HeartbeatEvent> {
        let CanId::Standard(raw) = frame.id() else {
            return None;
        };
        if raw & 0x780 != NMT_ERROR_CONTROL_BASE {
            return None;
        }
        let node = NodeId::new((raw & 0x7F) as u8)?;
        let hb = Heartbeat::parse_frame(frame).ok()?;
        let w = self.watches.iter_mut().find(|w| w.watches(node))?;
        // At most 65 535 000 µs: no overflow, no saturating multiply.
        let time_us = u64::from(w.entry.time_ms) * 1000;
        w.deadline = MaybeTimestamp::new(Some(now.add_micros(time_us)));
        let previous = w.state.replace(hb.state);
        let was_lost = core::mem::replace(&mut w.lost, false);
        if hb.is_boot_up() {
            Some(HeartbeatEvent::BootUp(node))
        } else if was_lost {
            Some(HeartbeatEvent::Restored {
                node,
                state: hb.state,
            })
        } else {
            match previous {
                Some(p) if p != hb.state => Some(HeartbeatEvent::StateChanged {
                    node,
                    state: hb.state,
                }),
                _ => None,
            }
        }
    }

    /// The first node (in slot order) whose time has run out at `now`, its
    /// watch marked lost and its deadline stopped: called until none, it
    /// reports each silence once, in slot order.
    pub(crate) fn expire_one(&mut self, now: Timestamp) -> Option<NodeId> {
        for w in &mut self.watches {
            let Some(deadline) = w.deadline.get() else {
                continue;
            };
            if !now.has_reached(deadline) {
                continue;
            }
            w.deadline = MaybeTimestamp::NONE;
            w.lost = true;
            // Always a node: only an enabled entry's watch is armed.
            if let Some(node) = NodeId::new(w.entry.node) {
                return Some(node);
            }
        }
        None
    }

    fn watch(&self, node: NodeId) -> Option<&Watch> {
        self.watches.iter().find(|w| w.watches(node))
    }
}

impl<const N: usize, const E: usize> Machine for HeartbeatConsumer<N, E> {
    type Event = HeartbeatEvent;

    /// Feeds a received frame; only heartbeats of watched nodes matter.
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        if let Some(e) = self.take_frame(now, frame) {
            self.events.push(e);
        }
    }

    /// Reports `Lost` for every node whose time has run out.
    fn handle_timeout(&mut self, now: Timestamp) {
        while let Some(node) = self.expire_one(now) {
            self.events.push(HeartbeatEvent::Lost(node));
        }
    }

    /// The earliest deadline of the watches.
    fn poll_timeout(&self) -> Option<Timestamp> {
        earliest(self.watches.iter().map(|w| w.deadline.get()))
    }

    crate::machine::queued_outputs!(frames: none, events: events);
}

#[cfg(test)]
#[path = "heartbeat_tests.rs"]
mod tests;
