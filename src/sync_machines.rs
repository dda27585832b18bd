//! The SYNC producer and consumer (CiA 301 "CANopen application layer and
//! communication profile", section 7.2.5 "Synchronization object"), with
//! the objects that configure them: 1005h COB-ID SYNC ([`SyncCobId`]),
//! 1006h communication cycle period (µs), 1007h synchronous window length
//! (µs) and 1019h synchronous counter overflow value.
//!
//! - [`SyncProducer`] sends a SYNC every communication cycle period. With
//!   a counter overflow value of 2..=240 every SYNC carries a counter that
//!   runs 1, 2, ..., overflow, 1, ...; with 0 the SYNC has no data. Values
//!   1 and 241..=255 are reserved (CiA 301 section 7.5.2 "Object dictionary
//!   entries", object 1019h "Synchronous counter overflow value") and refused.
//! - [`SyncConsumer`] recognises SYNC frames on its identifier and
//!   reports each ([`SyncEvent::Received`]), a counter that does not follow
//!   the previous one ([`SyncEvent::CounterSkipped`]), and synchronous PDOs
//!   outside the window. **The window**: CiA 301 says synchronous PDOs are
//!   sent and received within the synchronous window length after the SYNC.
//!   The consumer reads it as: a synchronous PDO noted with
//!   [`SyncConsumer::note_synchronous_pdo`] later than window length after
//!   the last SYNC (or before any SYNC) is outside it and is reported as
//!   [`SyncEvent::OutsideWindow`]; a window length of 0 means no window.

use core::convert::Infallible;
use core::time::Duration;

use super::Sync;
use crate::cob_id::SYNC;
use crate::frame::{data_frame_word, CanFrame, CanId};
use crate::machine::Machine;
use crate::queue::{EventQueue, Queue};
use crate::time::{MaybeTimestamp, Timers, Timestamp};

/// True for a valid 1019h value: 0 (no counter) or 2..=240.
#[must_use]
pub const fn valid_counter_overflow(value: u8) -> bool {
    matches!(value, 0 | 2..=240)
}

/// The value of 1005h COB-ID SYNC: bit 30 "generate" (this device is the
/// SYNC producer), bit 29 the frame format (29-bit identifier), bits 28-0
/// the identifier. Bit 31 is kept as written.
///
/// ```
/// use canopen_codec::sync::SyncCobId;
/// use canopen_codec::CanId;
/// let c = SyncCobId::from_raw(0x4000_0080);
/// assert!(c.generates());
/// assert_eq!(c.id(), Some(CanId::Standard(0x080)));
/// assert_eq!(SyncCobId::DEFAULT.raw(), 0x80);
/// assert_eq!(SyncCobId::DEFAULT.with_generate(true).raw(), 0x4000_0080);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SyncCobId(u32);

impl SyncCobId {
    /// Bit 30: the device generates SYNC.
    pub const GENERATE: u32 = 0x4000_0000;
    /// Bit 29: 29-bit identifier.
    pub const EXTENDED: u32 = 0x2000_0000;
    /// 080h, consumer only (the CiA 301 default).
    pub const DEFAULT: SyncCobId = SyncCobId(SYNC as u32);

    /// From the Unsigned32 of 1005h.
    #[must_use]
    pub const fn from_raw(raw: u32) -> Self {
        SyncCobId(raw)
    }

    /// The Unsigned32.
    #[must_use]
    pub const fn raw(self) -> u32 {
        self.0
    }

    /// True when the device produces SYNC.
    #[must_use]
    pub const fn generates(self) -> bool {
        self.0 & Self::GENERATE != 0
    }

    /// The same with the generate bit set or cleared.
    #[must_use]
    pub const fn with_generate(self, generate: bool) -> Self {
        if generate {
            SyncCobId(self.0 | Self::GENERATE)
        } else {
            SyncCobId(self.0 & !Self::GENERATE)
        }
    }

    /// The identifier (`None` when an 11-bit one is above 7FFh).
    #[must_use]
    pub const fn id(self) -> Option<CanId> {
        crate::cob_id::can_id_of_cob_word(self.0)
    }
}

impl Default for SyncCobId {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Sends SYNC every communication cycle period, with the counter of 1019h.
///
/// ```
/// use canopen_codec::machine::{drive_timers, Machine};
/// use canopen_codec::sync::SyncProducer;
/// use canopen_codec::Timestamp;
/// use core::time::Duration;
/// let mut p = SyncProducer::new(Duration::from_millis(10), 3).unwrap();
/// p.start(Timestamp::ZERO);
/// let mut sent = Vec::new();
/// drive_timers(&mut p, Timestamp::from_millis(40), |_, f| sent.push(f.to_string()));
/// assert_eq!(sent, ["080#01", "080#02", "080#03", "080#01"]);
/// ```
#[derive(Debug, Clone)]
pub struct SyncProducer {
    id: CanId,
    period_us: u64,
    overflow: u8,
    /// The counter of the next SYNC (1..=overflow).
    counter: u8,
    running: bool,
    timers: Timers<1>,
    out: Queue<CanFrame, 2>,
}

/// The producer's one timer: the next SYNC.
const NEXT_SYNC: usize = 0;

impl SyncProducer {
    /// A producer on 080h with communication cycle period `period` (1006h,
    /// whole microseconds; zero sends nothing on its own) and counter
    /// overflow value `overflow` (1019h); `None` for a reserved overflow
    /// value. Not started.
    #[must_use]
    pub fn new(period: Duration, overflow: u8) -> Option<Self> {
        if !valid_counter_overflow(overflow) {
            return None;
        }
        Some(SyncProducer {
            period_us: crate::time::micros_of(period),
            overflow,
            ..Self::idle()
        })
    }

    /// A producer on 080h with no period and no counter, not started.
    #[must_use]
    pub const fn idle() -> Self {
        SyncProducer {
            id: CanId::Standard(SYNC),
            period_us: 0,
            overflow: 0,
            counter: 1,
            running: false,
            timers: Timers::new(),
            out: Queue::new(CanFrame::EMPTY),
        }
    }

    /// The SYNC identifier (1005h).
    pub fn set_id(&mut self, id: CanId) {
        self.id = id;
    }

    /// The identifier used.
    #[must_use]
    pub const fn id(&self) -> CanId {
        self.id
    }

    /// The counter the next SYNC carries (1 when 1019h is 0, unused).
    #[must_use]
    pub const fn next_counter(&self) -> u8 {
        self.counter
    }

    /// True while producing.
    #[must_use]
    pub const fn is_running(&self) -> bool {
        self.running
    }

    /// Starts producing: the first SYNC one period from now, counter 1.
    pub fn start(&mut self, now: Timestamp) {
        self.running = true;
        self.counter = 1;
        self.timers
            .set(NEXT_SYNC, now.deadline_after(self.period_us));
    }

    /// Stops producing (the counter restarts at 1 with the next start).
    pub fn stop(&mut self) {
        self.running = false;
        self.timers.clear();
    }

    /// A new period (1006h written); a running producer restarts its cycle
    /// from `now`.
    pub fn set_period(&mut self, now: Timestamp, period: Duration) {
        self.period_us = crate::time::micros_of(period);
        if self.running {
            self.timers
                .set(NEXT_SYNC, now.deadline_after(self.period_us));
        }
    }

    /// A new counter overflow value (1019h); false (nothing changed) for a
    /// reserved value. The counter restarts at 1.
    pub fn set_counter_overflow(&mut self, overflow: u8) -> bool {
        if !valid_counter_overflow(overflow) {
            return false;
        }
        self.overflow = overflow;
        self.counter = 1;
        true
    }

    /// Sends one SYNC now (a command, besides the period), advancing the
    /// counter.
    pub fn send_sync(&mut self, now: Timestamp) {
        let _ = now;
        let sync = Sync {
            counter: (self.overflow != 0).then_some(self.counter),
        };
        if self.overflow != 0 {
            self.counter = if self.counter >= self.overflow {
                1
            } else {
                self.counter + 1
            };
        }
        let (data, len) = sync.encode();
        if let Ok(frame) = CanFrame::new(self.id, data.get(..len).unwrap_or(&[])) {
            if !self.out.push(frame) {
                let _ = self.out.pop();
                let _ = self.out.push(frame);
            }
        }
    }
}

impl Machine for SyncProducer {
    type Event = Infallible;

    /// The producer takes no input frames.
    fn handle_frame(&mut self, _now: Timestamp, _frame: &CanFrame) {}

    /// Sends the SYNC when due; the next one a period after the one due (no
    /// drift), or a period from `now` when the call is more than that late.
    fn handle_timeout(&mut self, now: Timestamp) {
        let Some(due) = self.timers.get(NEXT_SYNC) else {
            return;
        };
        if !self.timers.expire(NEXT_SYNC, now) {
            return;
        }
        self.send_sync(now);
        let next = match due.deadline_after(self.period_us) {
            Some(next) if !now.has_reached(next) => Some(next),
            _ => now.deadline_after(self.period_us),
        };
        self.timers.set(NEXT_SYNC, next);
    }

    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.out.pop()
    }

    /// When the next SYNC is due.
    fn poll_timeout(&self) -> Option<Timestamp> {
        self.timers.next()
    }

    fn poll_event(&mut self) -> Option<Infallible> {
        None
    }

    fn events_dropped(&self) -> u64 {
        0
    }
}

/// What the SYNC consumer reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum SyncEvent {
    /// A SYNC arrived.
    Received {
        /// Its counter, if it has one.
        counter: Option<u8>,
    },
    /// The counter did not follow the previous SYNC's (1019h set): one or
    /// more SYNCs were missed, or the producer restarted.
    CounterSkipped {
        /// The counter that should have come.
        expected: u8,
        /// The counter that came.
        got: u8,
    },
    /// A synchronous PDO after the synchronous window (1007h) had closed,
    /// or before any SYNC.
    OutsideWindow {
        /// Microseconds since the last SYNC, saturating at `u32::MAX`
        /// (about 71 minutes; the window, 1007h, is an Unsigned32 of µs,
        /// so a saturated value is outside any window), and `u32::MAX`
        /// before any SYNC.
        since_sync_us: u32,
    },
}

/// Receives SYNC on its identifier (1005h) and reports each
/// ([`SyncEvent::Received`]), a counter that does not follow the previous
/// one when 1019h is set ([`SyncEvent::CounterSkipped`]), and synchronous
/// PDOs outside the window.
///
/// **The window** (1007h): CiA 301 says synchronous PDOs are sent and
/// received within the synchronous window length after the SYNC. The
/// consumer reads it as: a synchronous PDO noted with
/// [`note_synchronous_pdo`](Self::note_synchronous_pdo) later than window
/// length after the last SYNC (or before any SYNC) is outside it and is
/// reported as [`SyncEvent::OutsideWindow`]; a window length of 0 means no
/// window. (The device core sends its synchronous TPDOs at the SYNC, inside
/// the window by construction, and notes its synchronous RPDOs.) The queue
/// keeps the latest `E` events (default 2, what one SYNC frame can make:
/// [`SyncEvent::Received`] and [`SyncEvent::CounterSkipped`]): read them
/// after every frame. (The device core, which reads them after every call
/// and does not report `Received`, takes its SYNC frames without queueing
/// `Received`, so one slot is its exact bound.)
///
/// ```
/// use canopen_codec::machine::Machine;
/// use canopen_codec::sync::{SyncConsumer, SyncEvent};
/// use canopen_codec::{CanFrame, Timestamp};
/// use core::time::Duration;
/// let mut c = SyncConsumer::new();
/// c.set_counter_overflow(4);
/// c.set_window(Duration::from_micros(500));
/// c.handle_frame(Timestamp::ZERO, &CanFrame::standard(0x080, &[1]).unwrap());
/// assert_eq!(c.poll_event(), Some(SyncEvent::Received { counter: Some(1) }));
/// c.handle_frame(Timestamp::from_millis(1), &CanFrame::standard(0x080, &[3]).unwrap());
/// assert_eq!(c.poll_event(), Some(SyncEvent::Received { counter: Some(3) }));
/// assert_eq!(c.poll_event(), Some(SyncEvent::CounterSkipped { expected: 2, got: 3 }));
/// assert!(c.note_synchronous_pdo(Timestamp::from_micros(1_400)));
/// assert!(!c.note_synchronous_pdo(Timestamp::from_micros(1_600)));
/// ```
#[derive(Debug, Clone)]
pub struct SyncConsumer<const E: usize = 2> {
    /// The identifier as the word of a data frame on it
    /// (`frame::data_frame_word`; `u32::MAX`, which no frame has, for one
    /// out of range): 4 bytes, not the 8 of a `CanId`, and one compare.
    id_word: u32,
    overflow: u8,
    /// 1007h (µs).
    window_us: u32,
    last_sync: MaybeTimestamp,
    last_counter: Option<u8>,
    events: EventQueue<SyncEvent, E>,
}

impl Default for SyncConsumer {
    fn default() -> Self {
        Self::new()
    }
}

impl SyncConsumer {
    /// A consumer on 080h, no counter check, no window.
    #[must_use]
    pub const fn new() -> Self {
        Self::with_event_capacity()
    }
}

impl<const E: usize> SyncConsumer<E> {
    /// A consumer on 080h, no counter check, no window, whose queue keeps
    /// the latest `E` events.
    ///
    /// ```
    /// use canopen_codec::sync::SyncConsumer;
    /// let c = SyncConsumer::<1>::with_event_capacity();
    /// assert_eq!(c.last_sync(), None);
    /// ```
    #[must_use]
    pub const fn with_event_capacity() -> Self {
        SyncConsumer {
            id_word: data_frame_word(CanId::Standard(SYNC)),
            overflow: 0,
            window_us: 0,
            last_sync: MaybeTimestamp::NONE,
            last_counter: None,
            events: EventQueue::new(SyncEvent::Received { counter: None }),
        }
    }

    /// The SYNC identifier (1005h). One out of range (which no frame has)
    /// leaves the consumer listening to nothing.
    pub fn set_id(&mut self, id: CanId) {
        self.id_word = data_frame_word(id);
    }

    /// The identifier listened to; none after an identifier out of range
    /// was set.
    ///
    /// ```
    /// use canopen_codec::sync::SyncConsumer;
    /// use canopen_codec::CanId;
    /// let mut c = SyncConsumer::new();
    /// assert_eq!(c.id(), Some(CanId::Standard(0x080)));
    /// c.set_id(CanId::Extended(0x1000_0080));
    /// assert_eq!(c.id(), Some(CanId::Extended(0x1000_0080)));
    /// c.set_id(CanId::Standard(0x800));
    /// assert_eq!(c.id(), None);
    /// ```
    #[must_use]
    pub fn id(&self) -> Option<CanId> {
        const EXTENDED: u32 = 1 << 31;
        match self.id_word {
            u32::MAX => None,
            w if w & EXTENDED != 0 => Some(CanId::Extended(w & !EXTENDED)),
            w => u16::try_from(w).ok().map(CanId::Standard),
        }
    }

    /// The counter overflow value (1019h) the producer uses: 0 no counter
    /// check; false (nothing changed) for a reserved value.
    pub fn set_counter_overflow(&mut self, overflow: u8) -> bool {
        if !valid_counter_overflow(overflow) {
            return false;
        }
        self.overflow = overflow;
        self.last_counter = None;
        true
    }

    /// The counter overflow value (1019h) checked: 0 none.
    #[must_use]
    pub const fn counter_overflow(&self) -> u8 {
        self.overflow
    }

    /// The synchronous window length (1007h, whole µs, saturating at
    /// `u32::MAX`, the largest 1007h; zero: no window).
    pub fn set_window(&mut self, window: Duration) {
        self.window_us = crate::time::micros_u32(window);
    }

    /// Forgets the last SYNC (a reset).
    pub fn reset(&mut self) {
        self.last_sync = MaybeTimestamp::NONE;
        self.last_counter = None;
    }

    /// When the last SYNC arrived.
    #[must_use]
    pub const fn last_sync(&self) -> Option<Timestamp> {
        self.last_sync.get()
    }

    /// True when `now` is within the window after the last SYNC (always
    /// true with no window).
    #[must_use]
    pub fn within_window(&self, now: Timestamp) -> bool {
        self.window_us == 0
            || self
                .last_sync
                .get()
                .is_some_and(|at| now.saturating_micros_since(at) <= u64::from(self.window_us))
    }

    /// A synchronous PDO is sent or received at `now`: true when within
    /// the window, else [`SyncEvent::OutsideWindow`] is reported and false
    /// returned.
    pub fn note_synchronous_pdo(&mut self, now: Timestamp) -> bool {
        if self.within_window(now) {
            return true;
        }
        let since_sync_us = self.last_sync.get().map_or(u32::MAX, |at| {
            u32::try_from(now.saturating_micros_since(at)).unwrap_or(u32::MAX)
        });
        self.events.push(SyncEvent::OutsideWindow { since_sync_us });
        false
    }

    /// Takes a SYNC frame on the consumer's identifier (a data frame of 0
    /// or 1 bytes); true when it was one. The device core calls this to
    /// run its synchronous TPDOs, from the bus and from its own producer.
    pub fn accept(&mut self, now: Timestamp, frame: &CanFrame) -> bool {
        self.take(now, frame, true)
    }

    /// [`accept`](Self::accept) without queueing [`SyncEvent::Received`]
    /// (the device core, which does not report it): at most one event
    /// (a skipped counter) per frame.
    pub(crate) fn accept_quietly(&mut self, now: Timestamp, frame: &CanFrame) -> bool {
        self.take(now, frame, false)
    }

    fn take(&mut self, now: Timestamp, frame: &CanFrame, report_received: bool) -> bool {
        // A remote frame's word has the remote flag: it matches no data
        // frame's.
        if frame.word() != self.id_word {
            return false;
        }
        let Ok(sync) = Sync::decode(frame.data()) else {
            return false;
        };
        self.last_sync = MaybeTimestamp::new(Some(now));
        if report_received {
            self.events.push(SyncEvent::Received {
                counter: sync.counter,
            });
        }
        if let (Some(got), true) = (sync.counter, self.overflow != 0) {
            if let Some(previous) = self.last_counter {
                let expected = if previous >= self.overflow {
                    1
                } else {
                    previous.saturating_add(1)
                };
                if got != expected {
                    self.events
                        .push(SyncEvent::CounterSkipped { expected, got });
                }
            }
            self.last_counter = Some(got);
        }
        true
    }
}

impl<const E: usize> Machine for SyncConsumer<E> {
    type Event = SyncEvent;

    /// SYNC frames on the consumer's identifier; others are ignored.
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        let _ = self.accept(now, frame);
    }

    /// The consumer has no timers.
    fn handle_timeout(&mut self, _now: Timestamp) {}

    /// The consumer sends nothing.
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        None
    }

    fn poll_timeout(&self) -> Option<Timestamp> {
        None
    }

    fn poll_event(&mut self) -> Option<SyncEvent> {
        self.events.pop()
    }

    fn events_dropped(&self) -> u64 {
        self.events.dropped()
    }
}
