//! Transmitting one TPDO on time: event timer, inhibit time and SYNC, as a
//! sans-IO state machine (CiA 301; the start-up rule is the Delta-Q IC
//! Series CANopen interface specification rev 2.0, section 4.5.3: "at
//! start-up the charger's TPDOs shall be disabled and not transmitted even
//! if the charger is in the NMT operational state" until their COB-IDs are
//! configured).
//!
//! A [`TpdoProducer`] sends nothing while its COB-ID is not configured,
//! while the COB-ID is not valid (bit 31) or while the node is not NMT
//! operational. When all three hold, an event-driven TPDO (types 254/255) is
//! sent at once, then whenever the event timer expires and whenever the
//! application signals an event ([`TpdoProducer::trigger`] or a changed
//! payload in [`TpdoProducer::set_payload`]); every transmission restarts the
//! event timer, and none follows the previous one within the inhibit time
//! (a request inside it is deferred to its end, not dropped). Synchronous
//! types send on a SYNC frame (through `handle_frame`): type n every n-th
//! SYNC, type 0 at the first SYNC after an event.
//!
//! It implements [`Machine`], the crate's state-machine contract: SYNC
//! arrives as a frame through `handle_frame` (identifier 080h unless
//! [`TpdoProducer::set_sync_id`] says otherwise, CiA 301 object 1005h), the
//! event timer and the end of the inhibit time are its two timers. It
//! reports no events. A timestamp that goes backwards never panics;
//! deadlines are simply not reached.

use core::convert::Infallible;

use super::comm::{PdoCommParams, TransmissionType};
use crate::bytes::Payload;
use crate::cob_id::SYNC;
use crate::frame::{data_frame_word, CanFrame, CanId};
use crate::machine::Machine;
use crate::time::Timestamp;

/// A deadline kept in 8 bytes: microseconds, 0 for none. No deadline of a
/// producer is at 0: the event timer runs out strictly after the send
/// that starts it, and the end of an inhibit time (100 µs at least) after
/// the send that starts it.
const NO_DEADLINE: u64 = 0;

/// Produces one TPDO. See the module docs.
///
/// ```
/// use canopen_codec::pdo::{PdoCobId, PdoCommParams, TpdoProducer};
/// use canopen_codec::bytes::Payload;
/// use canopen_codec::machine::Machine;
/// use canopen_codec::Timestamp;
/// let mut p = TpdoProducer::new();
/// p.set_payload(Timestamp::ZERO, Payload::new(&[0x01]).unwrap());
/// p.configure(Timestamp::ZERO, PdoCommParams::event_driven(PdoCobId::standard(0x18A), 200));
/// assert_eq!(p.poll_transmit(), None); // not operational yet
/// p.set_operational(Timestamp::from_millis(5), true);
/// assert_eq!(p.poll_transmit().unwrap().data(), &[0x01]);
/// assert_eq!(p.poll_timeout(), Some(Timestamp::from_millis(205)));
/// ```
#[derive(Debug, Clone)]
pub struct TpdoProducer {
    /// When the last frame was sent (valid once `sent`), in microseconds.
    last_sent: u64,
    /// The one timer, in microseconds ([`NO_DEADLINE`] when stopped): the
    /// end of the inhibit time when `deferred`, else the event timer. A
    /// deferred send re-arms the event timer, so an event timer running
    /// out inside the inhibit time is covered by it: one timer is enough.
    deadline: u64,
    comm: Option<PdoCommParams>,
    /// The SYNC identifier as a data frame's identifier word.
    sync_word: u32,
    /// What the next frame carries: the latest payload (a PDO carries the
    /// latest value; an undrained frame is not sent twice).
    payload: Payload,
    sync_count: u8,
    operational: bool,
    sent: bool,
    /// A frame is due (drained by `poll_transmit`).
    due: bool,
    /// The deadline is the end of the inhibit time: send there.
    deferred: bool,
    /// Type 0: an event happened; send at the next SYNC.
    sync_event: bool,
}

impl Default for TpdoProducer {
    fn default() -> Self {
        Self::new()
    }
}

impl TpdoProducer {
    /// Not configured, not operational, empty payload.
    #[must_use]
    pub const fn new() -> Self {
        TpdoProducer {
            last_sent: 0,
            deadline: NO_DEADLINE,
            comm: None,
            sync_word: SYNC as u32,
            payload: Payload::EMPTY,
            sync_count: 0,
            operational: false,
            sent: false,
            due: false,
            deferred: false,
            sync_event: false,
        }
    }

    /// The SYNC identifier the producer listens to (default 080h).
    pub fn set_sync_id(&mut self, id: CanId) {
        self.sync_word = data_frame_word(id);
    }

    /// The communication parameters, once configured.
    #[must_use]
    pub const fn comm(&self) -> Option<&PdoCommParams> {
        self.comm.as_ref()
    }

    /// The parameters of a producer that may send: configured, valid and
    /// operational.
    #[inline]
    fn active(&self) -> Option<PdoCommParams> {
        match self.comm {
            Some(c) if self.operational && c.cob_id.is_valid() && c.cob_id.can_id().is_some() => {
                Some(c)
            }
            _ => None,
        }
    }

    /// True when frames may be sent: configured, valid and operational.
    #[must_use]
    pub fn is_active(&self) -> bool {
        self.active().is_some()
    }

    /// Sets the communication parameters (a new COB-ID takes effect at once).
    pub fn configure(&mut self, now: Timestamp, comm: PdoCommParams) {
        let was_active = self.is_active();
        self.comm = Some(comm);
        self.became(now, was_active);
    }

    /// Forgets the configuration: nothing is sent until `configure` again.
    pub fn unconfigure(&mut self) {
        self.comm = None;
        self.stop();
    }

    /// Tells the producer whether the node is NMT operational.
    pub fn set_operational(&mut self, now: Timestamp, operational: bool) {
        let was_active = self.is_active();
        self.operational = operational;
        self.became(now, was_active);
    }

    fn became(&mut self, now: Timestamp, was_active: bool) {
        match (was_active, self.is_active()) {
            (false, true) => {
                self.sync_count = 0;
                self.request(now);
            }
            (true, false) => self.stop(),
            _ => {}
        }
    }

    fn stop(&mut self) {
        self.deadline = NO_DEADLINE;
        self.deferred = false;
        self.sync_event = false;
        self.due = false;
    }

    /// The payload to send. For an event-driven TPDO a changed payload is
    /// an event (sent now, or at the end of the inhibit time).
    pub fn set_payload(&mut self, now: Timestamp, payload: Payload) {
        if payload != self.payload {
            self.payload = payload;
            self.trigger(now);
        }
    }

    /// An application event: send as soon as the rules allow.
    pub fn trigger(&mut self, now: Timestamp) {
        if self.is_active() {
            self.request(now);
        }
    }

    fn request(&mut self, now: Timestamp) {
        let Some(comm) = self.comm else { return };
        match comm.transmission_type {
            TransmissionType::SynchronousAcyclic => self.sync_event = true,
            TransmissionType::SynchronousCyclic(_) => {}
            _ => self.send_or_defer(now, comm),
        }
    }

    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    fn send_or_defer(&mut self, now: Timestamp, comm: PdoCommParams) {
        let inhibit = comm.inhibit_time_us();
        let end = Timestamp::from_micros(self.last_sent).add_micros(inhibit);
        if self.sent && inhibit > 0 && !now.has_reached(end) {
            self.deadline = end.as_micros();
            self.deferred = true;
        } else {
            self.send(now, comm);
        }
    }

    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    fn send(&mut self, now: Timestamp, comm: PdoCommParams) {
        self.due = true;
        self.sent = true;
        self.last_sent = now.as_micros();
        self.deferred = false;
        // No event timer (0), or none later than the end of the clock.
        let event = if comm.transmission_type.is_event_driven() {
            now.deadline_after(u64::from(comm.event_timer_ms).saturating_mul(1000))
        } else {
            None
        };
        self.deadline = event.map_or(NO_DEADLINE, Timestamp::as_micros);
    }

    /// A SYNC was received: synchronous types send here.
    pub(crate) fn handle_sync(&mut self, now: Timestamp) {
        let Some(comm) = self.active() else {
            return;
        };
        match comm.transmission_type {
            TransmissionType::SynchronousAcyclic if self.sync_event => {
                self.sync_event = false;
                self.send(now, comm);
            }
            TransmissionType::SynchronousCyclic(n) => {
                self.sync_count = self.sync_count.saturating_add(1);
                if self.sync_count >= n {
                    self.sync_count = 0;
                    self.send(now, comm);
                }
            }
            _ => {}
        }
    }
}

impl Machine for TpdoProducer {
    type Event = Infallible;

    /// A SYNC frame (the producer's SYNC identifier, not remote): the
    /// synchronous transmission types send here. Other frames are ignored.
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        if frame.word() == self.sync_word {
            self.handle_sync(now);
        }
    }

    /// The event timer and a deferred transmission fire here.
    fn handle_timeout(&mut self, now: Timestamp) {
        let Some(comm) = self.active() else {
            return;
        };
        if self.deadline == NO_DEADLINE || !now.has_reached(Timestamp::from_micros(self.deadline)) {
            return;
        }
        self.deadline = NO_DEADLINE;
        if self.deferred {
            self.send(now, comm);
        } else {
            self.send_or_defer(now, comm);
        }
    }

    /// The frame to send, if one is due, with the latest payload. A newer
    /// transmission replaces an undrained one (a PDO carries the latest
    /// value).
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        if !core::mem::take(&mut self.due) {
            return None;
        }
        let id = self.comm?.cob_id.can_id()?;
        CanFrame::new(id, self.payload.as_slice()).ok()
    }

    /// The earlier of the event timer and the end of the inhibit time.
    fn poll_timeout(&self) -> Option<Timestamp> {
        if self.deadline == NO_DEADLINE || !self.is_active() {
            return None;
        }
        Some(Timestamp::from_micros(self.deadline))
    }

    fn poll_event(&mut self) -> Option<Infallible> {
        None
    }

    fn events_dropped(&self) -> u64 {
        0
    }
}

#[cfg(test)]
#[path = "producer_tests.rs"]
mod tests;
