//! A place on the simulated bus: a machine of any type (or none) with its
//! recorded events, behind one object-safe trait.

use alloc::boxed::Box;
use alloc::vec::Vec;
use core::any::Any;
use core::cell::Cell;

use super::controller::Controller;

use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::machine::Machine;

/// A place on the bus: its name, its machine and the machine's CAN
/// controller.
pub(super) struct Entry {
    pub(super) name: &'static str,
    pub(super) node: Box<dyn Node>,
    pub(super) controller: Controller,
    /// The machine's `poll_timeout` as last asked (`None`: to ask again).
    /// Asked at most once between two calls into the machine: every
    /// call the bus makes is followed by `Bus::flush`, and every access
    /// of the caller's goes through `Bus::slot_mut`, which both forget it.
    pub(super) due: Cell<Option<Option<Timestamp>>>,
    /// The caller reached the machine since its last flush: it may have
    /// queued frames or events (the step flushes it first).
    pub(super) touched: bool,
}

impl Entry {
    /// A place called `name` for a machine of type `M`, none plugged in.
    pub(super) fn new<M: Machine + 'static>(name: &'static str) -> Self {
        Entry {
            name,
            node: Box::new(Slot::<M> {
                machine: None,
                events: Vec::new(),
                drain: true,
                connected: true,
            }),
            controller: Controller::default(),
            due: Cell::new(None),
            touched: false,
        }
    }

    /// The machine's next deadline, asked only when not known.
    pub(super) fn due(&self) -> Option<Timestamp> {
        self.due.get().unwrap_or_else(|| {
            let due = self.node.poll_timeout();
            self.due.set(Some(due));
            due
        })
    }
}

/// A machine with its recorded events, behind `dyn Node`.
pub(super) struct Slot<M: Machine> {
    pub(super) machine: Option<M>,
    pub(super) events: Vec<(Timestamp, M::Event)>,
    pub(super) drain: bool,
    pub(super) connected: bool,
}

/// What the bus needs of a slot, whatever the machine's type.
pub(super) trait Node {
    fn is_plugged(&self) -> bool;
    fn is_connected(&self) -> bool;
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
    fn is_connected(&self) -> bool {
        self.connected && self.machine.is_some()
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
