//! The SYNC consumer (CiA 301 section 7.2.5 "Synchronization object"): SYNC
//! frames on 1005h's identifier, the counter, and the synchronous window (1007h).

use core::time::Duration;

use super::{valid_counter_overflow, SyncMessage};
use crate::clock::{MaybeTimestamp, Timestamp};
use crate::cob_id::SYNC;
use crate::frame::{data_frame_identity, CanFrame, CanId};
use crate::machine::Machine;
use crate::queue::EventQueue;
use crate::wire::Codec;

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
    /// (`frame::data_frame_identity`; `u32::MAX`, which no frame has, for one
    /// out of range): a received frame is on it when its word is this one.
    identity: u32,
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
            identity: data_frame_identity(CanId::Standard(SYNC)),
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
        self.identity = data_frame_identity(id);
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
        match self.identity {
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
        self.window_us = crate::clock::micros_u32(window);
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
        if frame.identity() != self.identity {
            return false;
        }
        let Ok(sync) = SyncMessage::parse_frame(frame) else {
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

    fn poll_timeout(&self) -> Option<Timestamp> {
        None
    }

    crate::machine::queued_outputs!(frames: none, events: events);
}
