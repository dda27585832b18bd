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

use super::SyncMessage;
use crate::clock::{timer_kind, Timers, Timestamp};
use crate::cob_id::{cob_id_word, SYNC};
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;
use crate::queue::FrameQueue;
use crate::wire::Codec;

/// True for a valid 1019h value: 0 (no counter) or 2..=240.
#[must_use]
pub const fn valid_counter_overflow(value: u8) -> bool {
    matches!(value, 0 | 2..=240)
}

cob_id_word! {
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
    SyncCobId, "1005h",
    /// 080h, consumer only (the CiA 301 default).
    DEFAULT = SYNC,
    flags: [(GENERATE, 30, generates, with_generate, "the device generates SYNC")],
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
    timers: Timers<ProducerTimer, 1>,
    out: FrameQueue<2>,
}

timer_kind! {
    /// The producer's one timer: the next SYNC.
    enum ProducerTimer {
        /// The next SYNC.
        NextSync,
    }
}

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
            period_us: crate::clock::micros_of(period),
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
            out: FrameQueue::empty(),
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
            .set(ProducerTimer::NextSync, now.deadline_after(self.period_us));
    }

    /// Stops producing (the counter restarts at 1 with the next start).
    pub fn stop(&mut self) {
        self.running = false;
        self.timers.clear();
    }

    /// A new period (1006h written); a running producer restarts its cycle
    /// from `now`.
    pub fn set_period(&mut self, now: Timestamp, period: Duration) {
        self.period_us = crate::clock::micros_of(period);
        if self.running {
            self.timers
                .set(ProducerTimer::NextSync, now.deadline_after(self.period_us));
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
        let sync = SyncMessage {
            counter: (self.overflow != 0).then_some(self.counter),
        };
        if self.overflow != 0 {
            self.counter = if self.counter >= self.overflow {
                1
            } else {
                self.counter + 1
            };
        }
        self.out.push(sync.to_frame_on(self.id));
    }
}

impl Machine for SyncProducer {
    type Event = Infallible;

    /// The producer takes no input frames.
    fn handle_frame(&mut self, _now: Timestamp, _frame: &CanFrame) {}

    /// Sends the SYNC when due; the next one a period after the one due (no
    /// drift), or a period from `now` when the call is more than that late.
    fn handle_timeout(&mut self, now: Timestamp) {
        if self
            .timers
            .periodic(ProducerTimer::NextSync, now, self.period_us)
        {
            self.send_sync(now);
        }
    }

    // When the next SYNC is due.
    crate::machine::queued_outputs!(timers: timers, frames: out, events: none);
}
