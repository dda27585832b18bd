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
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;
use crate::time::{Timers, Timestamp};

/// The producer's timers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(usize)]
enum Timer {
    /// The event timer (1800h sub 5) of an event-driven TPDO.
    Event,
    /// A transmission deferred to the end of the inhibit time (1800h sub 3).
    InhibitEnd,
}

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
    comm: Option<PdoCommParams>,
    operational: bool,
    payload: Payload,
    last_sent: Option<Timestamp>,
    timers: Timers<2>,
    /// Type 0: an event happened; send at the next SYNC.
    sync_event: bool,
    sync_count: u8,
    sync_id: CanId,
    out: Option<CanFrame>,
}

impl Default for TpdoProducer {
    fn default() -> Self {
        Self::new()
    }
}

impl TpdoProducer {
    /// An unconfigured, non-operational producer with an empty payload.
    #[must_use]
    pub const fn new() -> Self {
        TpdoProducer {
            comm: None,
            operational: false,
            payload: Payload::EMPTY,
            last_sent: None,
            timers: Timers::new(),
            sync_event: false,
            sync_count: 0,
            sync_id: CanId::Standard(SYNC),
            out: None,
        }
    }

    /// The SYNC identifier the producer listens to (default 080h).
    pub fn set_sync_id(&mut self, id: CanId) {
        self.sync_id = id;
    }

    /// The communication parameters, once configured.
    #[must_use]
    pub const fn comm(&self) -> Option<&PdoCommParams> {
        self.comm.as_ref()
    }

    /// True when frames may be sent: configured, valid and operational.
    #[must_use]
    pub fn is_active(&self) -> bool {
        self.operational
            && self
                .comm
                .is_some_and(|c| c.cob_id.is_valid() && c.cob_id.can_id().is_some())
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
        self.timers.clear();
        self.sync_event = false;
        self.out = None;
    }

    /// The payload to send. For an event-driven TPDO a changed payload is
    /// an event (sent now, or at the end of the inhibit time).
    pub fn set_payload(&mut self, now: Timestamp, payload: Payload) {
        let changed = payload != self.payload;
        self.payload = payload;
        if changed {
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

    fn inhibit_end(&self, comm: &PdoCommParams) -> Option<Timestamp> {
        let last = self.last_sent?;
        let end = last.add_micros(comm.inhibit_time_us());
        (comm.inhibit_time_us() > 0).then_some(end)
    }

    fn send_or_defer(&mut self, now: Timestamp, comm: PdoCommParams) {
        match self.inhibit_end(&comm) {
            Some(end) if !now.has_reached(end) => {
                self.timers.set(Timer::InhibitEnd as usize, Some(end));
                // The deferred send re-arms the event timer; an expiry inside
                // the inhibit time is covered by it.
                if self
                    .timers
                    .get(Timer::Event as usize)
                    .is_some_and(|at| at <= end)
                {
                    self.timers.set(Timer::Event as usize, None);
                }
            }
            _ => self.send(now, comm),
        }
    }

    fn send(&mut self, now: Timestamp, comm: PdoCommParams) {
        let Some(id) = comm.cob_id.can_id() else {
            return;
        };
        self.out = CanFrame::new(id, self.payload.as_slice()).ok();
        self.last_sent = Some(now);
        self.timers.set(Timer::InhibitEnd as usize, None);
        // No event timer (0), or none later than the end of the clock.
        let event = if comm.transmission_type.is_event_driven() {
            now.deadline_after(u64::from(comm.event_timer_ms).saturating_mul(1000))
        } else {
            None
        };
        self.timers.set(Timer::Event as usize, event);
    }

    /// A SYNC was received: synchronous types send here.
    pub(crate) fn handle_sync(&mut self, now: Timestamp) {
        let Some(comm) = self.comm.filter(|_| self.is_active()) else {
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
        if frame.id() == self.sync_id && !frame.is_remote() {
            self.handle_sync(now);
        }
    }

    /// The event timer and a deferred transmission fire here.
    fn handle_timeout(&mut self, now: Timestamp) {
        let Some(comm) = self.comm.filter(|_| self.is_active()) else {
            return;
        };
        if self.timers.expire(Timer::InhibitEnd as usize, now) {
            return self.send(now, comm);
        }
        if self.timers.expire(Timer::Event as usize, now) {
            self.send_or_defer(now, comm);
        }
    }

    /// The frame to send, if one is due. A newer transmission replaces an
    /// undrained one (a PDO carries the latest value).
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.out.take()
    }

    /// The earlier of the event timer and the end of the inhibit time.
    fn poll_timeout(&self) -> Option<Timestamp> {
        if !self.is_active() {
            return None;
        }
        self.timers.next()
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
