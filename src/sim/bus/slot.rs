//! A place on the simulated bus: a machine of any type (or none) with its
//! recorded events, behind one object-safe trait.

use alloc::vec::Vec;
use core::any::Any;

use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::machine::Machine;

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
