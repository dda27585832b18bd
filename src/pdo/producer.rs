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
//! event timer and the end of the inhibit time are its deadlines (one at a
//! time: a deferred send restarts the event timer). It reports no events.
//! A timestamp that goes backwards never panics; deadlines are simply not
//! reached.
//!
//! A frame carries the payload as it is when the frame is taken
//! ([`Machine::poll_transmit`]): a change between the transmission and the
//! poll is in the frame (and, as every change, an event for the next one).

use core::convert::Infallible;

use super::comm::PdoCommParams;
use super::wire::PdoFrame;
use crate::bytes::Payload;
use crate::clock::{timer_kind, MaybeTimestamp, Timers, Timestamp};
use crate::cob_id::SYNC;
use crate::frame::{data_frame_identity, CanFrame, CanId};
use crate::machine::Machine;

timer_kind! {
    /// The producer's one timer.
    enum TpdoTimer {
        /// The end of the inhibit time when a transmission is deferred,
        /// else the event timer. A deferred send re-arms the event timer,
        /// so an event timer running out inside the inhibit time is
        /// covered by it: one timer is enough.
        Next,
    }
}

/// The identifier word kept for a TPDO that may not send (not
/// configured, not valid, or bits 28-11 set on an 11-bit COB-ID): the
/// word of no data frame (see `data_frame_identity`).
const NO_ID: u32 = u32::MAX;

/// Bits of [`TpdoProducer::flags`].
const OPERATIONAL: u8 = 1 << 0;
/// `last_sent` holds a transmission.
const SENT: u8 = 1 << 1;
/// A frame is due (drained by `poll_transmit`).
const DUE: u8 = 1 << 2;
/// The deadline is the end of the inhibit time: send there.
const DEFERRED: u8 = 1 << 3;
/// Type 0: an event happened; send at the next SYNC.
const SYNC_EVENT: u8 = 1 << 4;

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
    /// When the last frame was sent (once `SENT`), in microseconds.
    last_sent: MaybeTimestamp,
    /// Only armed while active (every send follows an `is_active` check,
    /// and every way out of active stops it), so the timer paths need no
    /// check of their own.
    timers: Timers<TpdoTimer, 1>,
    /// Undrained frames replaced by a newer one (saturating).
    dropped: u32,
    /// What the next frame carries: the latest payload (a PDO carries the
    /// latest value; an undrained frame is not sent twice).
    next: PdoFrame,
    /// Of the communication parameters, what the producer uses: the
    /// COB-ID's identifier as the word of its data frames ([`NO_ID`] when
    /// it may not send: a frame is made from it without a conversion),
    /// the transmission type, the inhibit time and the event timer.
    frame_identity: u32,
    /// The SYNC identifier as a data frame's identifier word.
    sync_identity: u32,
    inhibit_time_100us: u16,
    event_timer_ms: u16,
    transmission_type: u8,
    sync_count: u8,
    flags: u8,
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
            last_sent: MaybeTimestamp::NONE,
            timers: Timers::new(),
            dropped: 0,
            next: PdoFrame::from_word(0, 0),
            frame_identity: NO_ID,
            sync_identity: SYNC as u32,
            inhibit_time_100us: 0,
            event_timer_ms: 0,
            transmission_type: 0,
            sync_count: 0,
            flags: 0,
        }
    }

    /// The SYNC identifier the producer listens to (default 080h).
    pub fn set_sync_id(&mut self, id: CanId) {
        self.sync_identity = data_frame_identity(id);
    }

    #[inline]
    fn has(&self, flag: u8) -> bool {
        self.flags & flag != 0
    }

    #[inline]
    fn set_flag(&mut self, flag: u8, on: bool) {
        if on {
            self.flags |= flag;
        } else {
            self.flags &= !flag;
        }
    }

    /// True when frames may be sent: configured, valid and operational.
    #[must_use]
    #[inline]
    pub fn is_active(&self) -> bool {
        self.has(OPERATIONAL) && self.frame_identity != NO_ID
    }

    /// Sets the communication parameters (a new COB-ID takes effect at
    /// once; the same parameters again change nothing).
    pub fn configure(&mut self, now: Timestamp, comm: PdoCommParams) {
        let was_active = self.is_active();
        let cob = comm.cob_id;
        self.frame_identity = match cob.can_id() {
            Some(id) if cob.is_valid() => data_frame_identity(id),
            _ => NO_ID,
        };
        self.transmission_type = comm.transmission_type.to_u8();
        self.inhibit_time_100us = comm.inhibit_time_100us;
        self.event_timer_ms = comm.event_timer_ms;
        self.became(now, was_active);
    }

    /// Forgets the configuration: nothing is sent until `configure` again.
    pub fn unconfigure(&mut self) {
        self.frame_identity = NO_ID;
        self.stop();
    }

    /// Tells the producer whether the node is NMT operational.
    pub fn set_operational(&mut self, now: Timestamp, operational: bool) {
        let was_active = self.is_active();
        self.set_flag(OPERATIONAL, operational);
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
        self.flags &= OPERATIONAL | SENT;
    }

    /// The payload to send. For an event-driven TPDO a changed payload is
    /// an event (sent now, or at the end of the inhibit time).
    pub fn set_payload(&mut self, now: Timestamp, payload: Payload) {
        let word = payload
            .as_slice()
            .iter()
            .rev()
            .fold(0u64, |w, &b| w << 8 | u64::from(b));
        self.set_payload_word(now, word, payload.len() as u8);
    }

    /// [`Self::set_payload`] with the payload as `len` little-endian bytes
    /// of `word` (bytes past `len` zero).
    #[inline]
    pub(crate) fn set_payload_word(&mut self, now: Timestamp, word: u64, len: u8) {
        let next = PdoFrame::from_word(word, len);
        if next != self.next {
            self.next = next;
            self.trigger(now);
        }
    }

    /// An application event: send as soon as the rules allow.
    pub fn trigger(&mut self, now: Timestamp) {
        if self.is_active() {
            self.request(now);
        }
    }

    /// Types 254 and 255 (event-driven); 241-253 are never configured.
    #[inline]
    fn is_event_driven(&self) -> bool {
        self.transmission_type > 240
    }

    fn request(&mut self, now: Timestamp) {
        match self.transmission_type {
            0 => self.flags |= SYNC_EVENT,
            1..=240 => {}
            _ => self.send_or_defer(now),
        }
    }

    #[inline(never)]
    fn send_or_defer(&mut self, now: Timestamp) {
        let inhibit = u64::from(self.inhibit_time_100us) * 100;
        let end = self
            .last_sent
            .get()
            .unwrap_or(Timestamp::ZERO)
            .add_micros(inhibit);
        if self.has(SENT) && inhibit > 0 && !now.has_reached(end) {
            self.timers.set(TpdoTimer::Next, Some(end));
            self.flags |= DEFERRED;
        } else {
            self.send(now);
        }
    }

    #[inline(never)]
    fn send(&mut self, now: Timestamp) {
        if self.has(DUE) {
            // The caller did not drain: the newer frame replaces it.
            self.dropped = self.dropped.saturating_add(1);
        }
        self.flags = (self.flags | DUE | SENT) & !DEFERRED;
        self.last_sent = MaybeTimestamp::new(Some(now));
        // No event timer (0), or none later than the end of the clock.
        let event = if self.is_event_driven() {
            now.deadline_after(u64::from(self.event_timer_ms) * 1000)
        } else {
            None
        };
        self.timers.set(TpdoTimer::Next, event);
    }

    /// A SYNC was received: synchronous types send here.
    pub(crate) fn handle_sync(&mut self, now: Timestamp) {
        if !self.is_active() {
            return;
        }
        match self.transmission_type {
            0 if self.has(SYNC_EVENT) => {
                self.flags &= !SYNC_EVENT;
                self.send(now);
            }
            n @ 1..=240 => {
                self.sync_count = self.sync_count.saturating_add(1);
                if self.sync_count >= n {
                    self.sync_count = 0;
                    self.send(now);
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
        if frame.identity() == self.sync_identity {
            self.handle_sync(now);
        }
    }

    /// The event timer and a deferred transmission fire here.
    fn handle_timeout(&mut self, now: Timestamp) {
        // A deadline is only set while active (see `timers`).
        if !self.timers.expire(TpdoTimer::Next, now) {
            return;
        }
        if self.has(DEFERRED) {
            self.send(now);
        } else {
            self.send_or_defer(now);
        }
    }

    /// The frame to send, if one is due, with the latest payload. A newer
    /// transmission replaces an undrained one (a PDO carries the latest
    /// value).
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        if !self.has(DUE) {
            return None;
        }
        self.flags &= !DUE;
        // DUE implies active (a send is), so the identifier is valid; a
        // producer that may not send never sends.
        if self.frame_identity == NO_ID {
            return None;
        }
        Some(self.next.frame_on_identity(self.frame_identity))
    }

    // The earlier of the event timer and the end of the inhibit time.
    crate::machine::queued_outputs!(timers: timers, events: none);

    fn frames_dropped(&self) -> u64 {
        u64::from(self.dropped)
    }
}

#[cfg(test)]
#[path = "producer_tests.rs"]
mod tests;
