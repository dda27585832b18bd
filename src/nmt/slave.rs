//! The NMT slave (CiA 301, network management): the NMT state of one node
//! and its answer to the master's module-control commands, as a
//! [`Machine`].
//!
//! | command (`000# cs node`) | from | to |
//! |---|---|---|
//! | start remote node (01h) | pre-operational, stopped | operational |
//! | stop remote node (02h) | pre-operational, operational | stopped |
//! | enter pre-operational (80h) | operational, stopped | pre-operational |
//! | reset node (81h) | any | initialisation, then boot-up and pre-operational |
//! | reset communication (82h) | any | initialisation, then boot-up and pre-operational |
//!
//! A command addresses this node when its node byte is the node id or 0
//! (all nodes); others, unknown specifiers and frames of the wrong length
//! are ignored, as is everything before [`NmtSlave::boot`]. A reset is
//! reported as [`NmtSlaveEvent::Reset`]: the owner restores its objects
//! (all of them for reset node, the communication objects 1000h-1FFFh for
//! reset communication, CiA 301 7.3.2.2.1) and calls [`NmtSlave::boot`]
//! again, which sends nothing itself (the boot-up message is the heartbeat
//! producer's); the state change is then reported from the state before
//! the reset to pre-operational. The slave sends no frames and arms no timers.

use super::{NmtCommandSpecifier, NmtFrame, NmtState};
use crate::clock::Timestamp;
use crate::cob_id::{NodeId, NMT};
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;
use crate::queue::EventQueue;

/// Which NMT reset the master commanded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ResetKind {
    /// Reset node (81h): every object back to its power-on value.
    Node,
    /// Reset communication (82h): the communication objects (1000h-1FFFh)
    /// back to their power-on values; application objects are kept.
    Communication,
}

/// What the NMT slave reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum NmtSlaveEvent {
    /// The state changed (boot, a command, or a reset).
    StateChanged {
        /// The state before ([`NmtState::BootUp`] while initialising).
        from: NmtState,
        /// The new state.
        to: NmtState,
    },
    /// The master commanded a reset; the slave is initialising until the
    /// owner calls [`NmtSlave::boot`].
    Reset(ResetKind),
}

/// The NMT state machine of node `node`. See the module docs.
///
/// ```
/// use canopen_codec::machine::Machine;
/// use canopen_codec::nmt::{NmtSlave, NmtSlaveEvent, NmtState};
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
/// let mut nmt = NmtSlave::new(NodeId::new(10).unwrap());
/// nmt.boot(Timestamp::ZERO);
/// nmt.handle_frame(Timestamp::ZERO, &CanFrame::standard(0x000, &[0x01, 0x0A]).unwrap());
/// assert_eq!(nmt.state(), NmtState::Operational);
/// assert_eq!(nmt.poll_event(), Some(NmtSlaveEvent::StateChanged {
///     from: NmtState::BootUp, to: NmtState::PreOperational }));
/// assert_eq!(nmt.poll_event(), Some(NmtSlaveEvent::StateChanged {
///     from: NmtState::PreOperational, to: NmtState::Operational }));
/// ```
///
/// The slave reports at most one event per call. Its queue keeps the latest
/// `E` (default 8) for an owner that does not drain it after every call; an
/// owner that does can make it small ([`NmtSlave::with_event_capacity`]).
/// The device core keeps no queue: it handles each event as the call
/// that makes it returns it.
#[derive(Debug, Clone)]
pub struct NmtSlave<const E: usize = 8> {
    core: NmtCore,
    events: EventQueue<NmtSlaveEvent, E>,
}

impl NmtSlave {
    /// A node that has not booted yet ([`NmtState::BootUp`]: initialising),
    /// keeping the latest 8 events.
    #[must_use]
    pub const fn new(node: NodeId) -> Self {
        Self::with_event_capacity(node)
    }
}

impl<const E: usize> NmtSlave<E> {
    /// As [`NmtSlave::new`], keeping the latest `E` events.
    #[must_use]
    pub const fn with_event_capacity(node: NodeId) -> Self {
        NmtSlave {
            core: NmtCore::new(node),
            events: EventQueue::new(NmtSlaveEvent::Reset(ResetKind::Node)),
        }
    }

    /// The node id.
    #[must_use]
    pub const fn node(&self) -> NodeId {
        self.core.node
    }

    /// The current state.
    #[must_use]
    pub const fn state(&self) -> NmtState {
        self.core.state
    }

    /// True once booted and not initialising after a reset.
    #[must_use]
    pub const fn is_running(&self) -> bool {
        self.core.is_running()
    }

    /// True in pre-operational and operational, where SDO and EMCY are
    /// served (CiA 301: not in stopped).
    #[must_use]
    pub const fn sdo_allowed(&self) -> bool {
        self.core.sdo_allowed()
    }

    /// Initialisation finished (power-on or after a reset): enters
    /// pre-operational. After a reset the state change is reported from the
    /// state the reset left (none when that was pre-operational).
    pub fn boot(&mut self, now: Timestamp) {
        let _ = now;
        let event = self.core.boot().map(|from| NmtSlaveEvent::StateChanged {
            from,
            to: NmtState::PreOperational,
        });
        self.queue(event);
    }

    /// Enters `to` by the node's own decision (e.g. a device that starts
    /// itself); reported like a commanded change.
    pub fn set_state(&mut self, now: Timestamp, to: NmtState) {
        let _ = now;
        let event = self.core.set_state(to);
        self.queue(event);
    }

    fn queue(&mut self, event: Option<NmtSlaveEvent>) {
        if let Some(event) = event {
            self.events.push(event);
        }
    }
}

/// The NMT slave without its event queue, for an owner that handles each
/// event as it is made (the device core): every call returns the one
/// event it makes, if any (the return type is the proof that a call makes
/// at most one). [`NmtSlave`] is this plus the queue of a [`Machine`].
#[derive(Debug, Clone)]
pub(crate) struct NmtCore {
    node: NodeId,
    state: NmtState,
    /// The state a reset left (reported as the `from` of the boot after it).
    before_reset: Option<NmtState>,
}

impl NmtCore {
    /// A node that has not booted yet.
    pub(crate) const fn new(node: NodeId) -> Self {
        NmtCore {
            node,
            state: NmtState::BootUp,
            before_reset: None,
        }
    }

    /// The current state.
    pub(crate) const fn state(&self) -> NmtState {
        self.state
    }

    /// As [`NmtSlave::is_running`].
    pub(crate) const fn is_running(&self) -> bool {
        !matches!(self.state, NmtState::BootUp)
    }

    /// As [`NmtSlave::sdo_allowed`].
    pub(crate) const fn sdo_allowed(&self) -> bool {
        matches!(self.state, NmtState::PreOperational | NmtState::Operational)
    }

    /// As [`NmtSlave::boot`]; returns the state the change to
    /// pre-operational is from (none when there is no change).
    pub(crate) fn boot(&mut self) -> Option<NmtState> {
        let from = self.before_reset.take().unwrap_or(self.state);
        self.state = NmtState::PreOperational;
        (from != NmtState::PreOperational).then_some(from)
    }

    /// As [`NmtSlave::set_state`]; returns the state change.
    pub(crate) fn set_state(&mut self, to: NmtState) -> Option<NmtSlaveEvent> {
        let from = self.state;
        if from == to {
            return None;
        }
        self.state = to;
        Some(NmtSlaveEvent::StateChanged { from, to })
    }

    /// As [`Machine::handle_frame`] on [`NmtSlave`]: obeys an NMT
    /// module-control command addressed to this node; returns what it did.
    pub(crate) fn take_frame(&mut self, frame: &CanFrame) -> Option<NmtSlaveEvent> {
        if !self.is_running() || frame.is_remote() || frame.id() != CanId::Standard(NMT) {
            return None;
        }
        // A command is for this node when its node byte is 0 (all) or the
        // node-ID (an invalid node byte, 128..=255, is neither): what
        // `NmtTarget::addresses` says, read from the checked view without
        // building the target.
        let command = NmtFrame::new_checked(frame.data()).ok()?;
        let target = command.target();
        if target != 0 && target != self.node.raw() {
            return None;
        }
        match NmtCommandSpecifier::from(command.command()) {
            NmtCommandSpecifier::Start => self.set_state(NmtState::Operational),
            NmtCommandSpecifier::Stop => self.set_state(NmtState::Stopped),
            NmtCommandSpecifier::EnterPreOperational => self.set_state(NmtState::PreOperational),
            NmtCommandSpecifier::ResetNode => Some(self.reset(ResetKind::Node)),
            NmtCommandSpecifier::ResetCommunication => Some(self.reset(ResetKind::Communication)),
            NmtCommandSpecifier::Unknown(_) => None,
        }
    }

    fn reset(&mut self, kind: ResetKind) -> NmtSlaveEvent {
        self.before_reset = Some(self.state);
        self.state = NmtState::BootUp;
        NmtSlaveEvent::Reset(kind)
    }
}

impl<const E: usize> Machine for NmtSlave<E> {
    type Event = NmtSlaveEvent;

    /// Obeys an NMT module-control command addressed to this node.
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        let _ = now;
        let event = self.core.take_frame(frame);
        self.queue(event);
    }

    /// The slave has no timers.
    fn handle_timeout(&mut self, _now: Timestamp) {}

    fn poll_timeout(&self) -> Option<Timestamp> {
        None
    }

    crate::machine::queued_outputs!(frames: none, events: events);
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    fn nmt(cs: u8, node: u8) -> CanFrame {
        CanFrame::standard(NMT, &[cs, node]).unwrap()
    }

    fn drain(s: &mut NmtSlave) -> Vec<NmtSlaveEvent> {
        core::iter::from_fn(|| s.poll_event()).collect()
    }

    #[test]
    fn every_command_row() {
        use NmtState::{BootUp, Operational as Op, PreOperational as Pre, Stopped};
        let t = Timestamp::ZERO;
        let mut s = NmtSlave::new(NodeId::new(10).unwrap());
        s.handle_frame(t, &nmt(0x01, 10));
        assert_eq!(s.state(), BootUp, "ignored before boot");
        s.boot(t);
        // (command, node byte, state after)
        let rows = [
            (0x01, 10, Op),
            (0x02, 0, Stopped),
            (0x80, 10, Pre),
            (0x02, 10, Stopped),
            (0x01, 10, Op),
            (0x80, 0, Pre),
            (0x01, 11, Pre),   // another node
            (0x02, 0x8A, Pre), // not a node-ID (10 + 80h)
            (0x02, 0xFF, Pre), // not a node-ID
            (0x55, 10, Pre),   // unknown specifier
        ];
        for (cs, node, want) in rows {
            s.handle_frame(t, &nmt(cs, node));
            assert_eq!(s.state(), want, "command {cs:02X}h node {node}");
        }
        let _ = drain(&mut s);
        for (cs, kind) in [(0x81, ResetKind::Node), (0x82, ResetKind::Communication)] {
            s.handle_frame(t, &nmt(0x01, 10));
            s.handle_frame(t, &nmt(cs, 10));
            assert_eq!(
                drain(&mut s)[1..],
                [NmtSlaveEvent::Reset(kind)],
                "no state change until boot"
            );
            assert!(!s.is_running());
            s.handle_frame(t, &nmt(0x01, 10));
            assert_eq!(s.state(), BootUp, "initialising until boot");
            s.boot(t);
            assert_eq!(
                drain(&mut s),
                [NmtSlaveEvent::StateChanged { from: Op, to: Pre }]
            );
        }
        // Wrong length, remote frames and other identifiers are ignored.
        s.handle_frame(t, &CanFrame::standard(NMT, &[0x01]).unwrap());
        s.handle_frame(t, &CanFrame::standard(NMT, &[0x01, 10, 0]).unwrap());
        s.handle_frame(t, &CanFrame::remote(CanId::Standard(NMT), 2).unwrap());
        s.handle_frame(t, &CanFrame::standard(0x001, &[0x01, 10]).unwrap());
        assert_eq!((s.state(), drain(&mut s)), (Pre, Vec::new()));
        assert!(s.sdo_allowed());
    }

    proptest::proptest! {
        #![proptest_config(crate::testing::proptest_config("tests/proptest-regressions/src-nmt-slave.txt"))]
        /// At most one event per call, whatever the call and the frame:
        /// what lets the device core keep two slots.
        #[test]
        fn one_event_per_call_at_most(
            calls in proptest::collection::vec((0u8..4, proptest::num::u8::ANY, 0u8..12, 0u8..4), 0..64)
        ) {
            let states = [NmtState::PreOperational, NmtState::Operational, NmtState::Stopped, NmtState::BootUp];
            let cs = [0x01, 0x02, 0x80, 0x81, 0x82, 0x00, 0x55];
            let mut s: NmtSlave<2> = NmtSlave::with_event_capacity(NodeId::new(10).unwrap());
            let t = Timestamp::ZERO;
            for (kind, byte, node, state) in calls {
                match kind {
                    0 => s.boot(t),
                    1 => s.set_state(t, states[usize::from(state)]),
                    _ => s.handle_frame(t, &nmt(cs[usize::from(byte) % cs.len()], node)),
                }
                let first = s.poll_event();
                proptest::prop_assert_eq!(s.poll_event(), None);
                proptest::prop_assert_eq!(s.events_dropped(), 0);
                let _ = first;
            }
        }

        /// The queue-less core makes, call for call, the event the slave
        /// queues: the device core (which uses it) reports what a
        /// standalone slave would.
        #[test]
        fn core_returns_what_the_slave_queues(
            calls in proptest::collection::vec((0u8..4, proptest::num::u8::ANY, 0u8..12, 0u8..4), 0..64)
        ) {
            let states = [NmtState::PreOperational, NmtState::Operational, NmtState::Stopped, NmtState::BootUp];
            let cs = [0x01, 0x02, 0x80, 0x81, 0x82, 0x00, 0x55];
            let node = NodeId::new(10).unwrap();
            let mut s = NmtSlave::new(node);
            let mut core = NmtCore::new(node);
            let t = Timestamp::ZERO;
            for (kind, byte, target, state) in calls {
                let made = match kind {
                    0 => {
                        s.boot(t);
                        core.boot().map(|from| NmtSlaveEvent::StateChanged { from, to: NmtState::PreOperational })
                    }
                    1 => {
                        let to = states[usize::from(state)];
                        s.set_state(t, to);
                        core.set_state(to)
                    }
                    _ => {
                        let frame = nmt(cs[usize::from(byte) % cs.len()], target);
                        s.handle_frame(t, &frame);
                        core.take_frame(&frame)
                    }
                };
                proptest::prop_assert_eq!(s.poll_event(), made);
                proptest::prop_assert_eq!(s.poll_event(), None);
                proptest::prop_assert_eq!(
                    (s.state(), s.is_running(), s.sdo_allowed()),
                    (core.state(), core.is_running(), core.sdo_allowed())
                );
            }
        }
    }
}
