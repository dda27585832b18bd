//! Each machine's CAN controller under the fault confinement of ISO
//! 11898-1 (its transmit and receive error counters and the three error
//! states), for a bus that models it ([`Bus::confine_errors`]).
//!
//! The rules kept: a frame its sender could not get through (lost to the
//! random loss) adds 8 to the sender's transmit error counter and 1 to the
//! receive error counter of every other node on the bus; a frame that got
//! through takes 1 off each. A controller is error passive once a counter
//! passes 127 and bus-off once its transmit counter passes 255. On a bus
//! that is off (shorted, unterminated: [`Bus::bus_off`]) a controller
//! retransmits its frame automatically and every attempt fails, so the
//! first frame it sends there takes it to bus-off (32 attempts of 8). A
//! bus-off controller sends and hears nothing until it has seen 128
//! occurrences of 11 recessive bits on a working bus ([`RECOVERY`]), then
//! is error active again with both counters at 0. Acknowledgement errors
//! (a node alone on the bus) are not modelled.

use core::time::Duration;

use super::{Bus, Fate, Handle};
use crate::clock::Timestamp;

/// The error state of a CAN controller (ISO 11898-1, fault confinement):
/// what its application reads from its status register and reports (CiA
/// 301 section 7.2.7: EMCY 8120h "CAN in error passive mode", 8140h
/// "recovered from bus off").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ControllerState {
    /// Both error counters at most 127: the controller takes full part in
    /// the bus.
    ErrorActive,
    /// An error counter above 127: the controller still sends and
    /// receives, but signals errors passively.
    ErrorPassive,
    /// The transmit error counter passed 255: the controller is off the
    /// bus until it recovers.
    BusOff,
}

/// How long a bus-off controller takes to recover on a working bus: 128
/// occurrences of 11 recessive bits at 125 kbit/s, the Delta-Q charger's
/// default bit rate ("Delta-Q IC Series CANopen interface specification
/// rev 2.0").
pub const RECOVERY: Duration = Duration::from_micros(128 * 11 * 8);

/// One controller's counters.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Controller {
    tec: u16,
    rec: u16,
    /// While bus-off: when it is error active again.
    recovers: Option<Timestamp>,
}

impl Controller {
    /// Its state at `now` (a bus-off controller whose recovery time has
    /// come is error active).
    pub(super) fn state(&self, now: Timestamp) -> ControllerState {
        match self.recovers {
            Some(back) if !now.has_reached(back) => ControllerState::BusOff,
            Some(_) => ControllerState::ErrorActive,
            None if self.tec > 127 || self.rec > 127 => ControllerState::ErrorPassive,
            None => ControllerState::ErrorActive,
        }
    }

    /// When a bus-off controller recovers.
    pub(super) const fn recovers(&self) -> Option<Timestamp> {
        self.recovers
    }

    /// Applies a recovery whose time has come: both counters back to 0.
    pub(super) fn refresh(&mut self, now: Timestamp) {
        if self.recovers.is_some_and(|back| now.has_reached(back)) {
            *self = Controller::default();
        }
    }

    /// A frame it sent got through.
    pub(super) fn sent(&mut self) {
        self.tec = self.tec.saturating_sub(1);
    }

    /// A frame it sent failed: bus-off past 255, recovering at `back`.
    pub(super) fn send_failed(&mut self, back: Timestamp) {
        self.tec = self.tec.saturating_add(8);
        if self.tec > 255 {
            self.recovers = Some(back);
        }
    }

    /// The bus is off: its frame's retransmissions all fail, it is bus-off
    /// until `back`.
    pub(super) fn go_bus_off(&mut self, back: Timestamp) {
        self.tec = 256;
        self.recovers = Some(back);
    }

    /// It received a frame.
    pub(super) fn received(&mut self) {
        // ISO 11898-1: above 127 the counter drops back into 119..=127.
        self.rec = if self.rec > 127 {
            127
        } else {
            self.rec.saturating_sub(1)
        };
    }

    /// It saw a frame fail (capped: an error-passive receiver stays so).
    pub(super) fn receive_failed(&mut self) {
        self.rec = self.rec.saturating_add(1).min(255);
    }

    /// A later bus-off window ending at `until` keeps a controller that
    /// would recover inside it off until the window is over.
    pub(super) fn extend(&mut self, from: Timestamp, until: Timestamp) {
        if let Some(back) = self.recovers.filter(|b| b.has_reached(from)) {
            self.recovers = Some(back.max(until.add_duration(RECOVERY)));
        }
    }
}

impl Bus {
    /// Models each machine's CAN controller (`true`) or not (the default):
    /// its error counters and states under ISO 11898-1's fault
    /// confinement, as [`controller_state`](Self::controller_state) reads
    /// them. A machine whose controller is bus-off sends and hears nothing
    /// (its frames' fate [`Fate::BusOff`]) until it recovers.
    pub fn confine_errors(&mut self, on: bool) {
        self.confine = on;
    }

    /// The error state of the machine's CAN controller now (always error
    /// active unless [`confine_errors`](Self::confine_errors)): what its
    /// application reads from the controller and reports.
    #[must_use]
    pub fn controller_state<M>(&self, h: Handle<M>) -> ControllerState {
        self.entries
            .get(h.index)
            .filter(|_| self.confine)
            .map_or(ControllerState::ErrorActive, |e| {
                e.controller.state(self.now)
            })
    }

    /// When the machine's bus-off controller is error active again (`None`
    /// unless it is bus-off).
    #[must_use]
    pub fn recovers_at<M>(&self, h: Handle<M>) -> Option<Timestamp> {
        let e = self.entries.get(h.index).filter(|_| self.confine)?;
        e.controller
            .recovers()
            .filter(|t| !self.now.has_reached(*t))
    }

    /// Whether a frame machine `from` sends now is lost to its controller
    /// being bus-off, or taking it there on a bus that is off.
    pub(super) fn confined_off(&mut self, from: Option<usize>) -> bool {
        let (now, off) = (self.now, self.off);
        let bus_is_off = self.is_off(now);
        let Some(c) = from
            .and_then(|i| self.entries.get_mut(i))
            .map(|e| &mut e.controller)
            .filter(|_| self.confine)
        else {
            return false;
        };
        c.refresh(now);
        if c.state(now) == ControllerState::BusOff {
            return true;
        }
        if let Some((_, until)) = off.filter(|_| bus_is_off) {
            c.go_bus_off(until.add_duration(RECOVERY));
        }
        false
    }

    /// Whether machine `i`'s controller is bus-off now (never unless
    /// confining).
    pub(super) fn deaf(&self, i: usize) -> bool {
        self.confine
            && self
                .entries
                .get(i)
                .is_some_and(|e| e.controller.state(self.now) == ControllerState::BusOff)
    }

    /// The error counters after machine `i` sent a frame whose fate is
    /// `fate`: the loss is an error its sender and every listener saw.
    pub(super) fn confine_sent(&mut self, i: usize, fate: Fate) {
        let failed = fate == Fate::Lost;
        let back = self.now.add_duration(RECOVERY);
        for (j, e) in self.entries.iter_mut().enumerate() {
            e.controller.refresh(self.now);
            let listens =
                e.node.is_connected() && e.controller.state(self.now) != ControllerState::BusOff;
            match (j == i, failed) {
                (true, true) => e.controller.send_failed(back),
                (true, false) => e.controller.sent(),
                (false, true) if listens => e.controller.receive_failed(),
                (false, false) if listens => e.controller.received(),
                _ => {}
            }
        }
    }
}
