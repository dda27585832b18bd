//! The TIME producer and consumer (CiA 301 "CANopen application layer and
//! communication profile", section 7.2.6 "Time stamp object") and 1012h
//! COB-ID TIME ([`TimeCobId`]): bit 31 "consume", bit 30 "produce", bit 29
//! the frame format, bits 28-0 the identifier (default 100h).
//!
//! CiA 301 defines no period for TIME: [`TimeProducer::send_time`] is a
//! command, sent only while 1012h has the produce bit.
//! [`TimeConsumer`] reports every TIME received while 1012h has the
//! consume bit ([`TimeEvent::Received`]), with the local time it arrived.

use core::convert::Infallible;

use super::TimeOfDay;
use crate::clock::Timestamp;
use crate::cob_id::{cob_id_word, TIME};
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::queue::FrameQueue;
use crate::wire::Codec;

cob_id_word! {
    /// The value of 1012h COB-ID TIME.
    ///
    /// ```
    /// use canopen_codec::time::TimeCobId;
    /// use canopen_codec::CanId;
    /// let c = TimeCobId::from_raw(0x8000_0100);
    /// assert!(c.consumes() && !c.produces());
    /// assert_eq!(c.id(), Some(CanId::Standard(0x100)));
    /// assert_eq!(TimeCobId::DEFAULT.with_produce(true).raw(), 0x4000_0100);
    /// ```
    TimeCobId, "1012h",
    /// 100h, neither consumer nor producer.
    DEFAULT = TIME,
    flags: [
        (CONSUME, 31, consumes, with_consume, "the device consumes TIME"),
        (PRODUCE, 30, produces, with_produce, "the device produces TIME"),
    ],
}

/// Sends TIME on command while 1012h has the produce bit.
///
/// ```
/// use canopen_codec::machine::Machine;
/// use canopen_codec::time::{TimeCobId, TimeOfDay, TimeProducer};
/// use canopen_codec::Timestamp;
/// let mut p = TimeProducer::new(TimeCobId::DEFAULT.with_produce(true));
/// assert!(p.send_time(Timestamp::ZERO, TimeOfDay::new(12 * 3_600_000, 2).unwrap()));
/// assert_eq!(p.poll_transmit().unwrap().to_string(), "100#002E93020200");
/// ```
#[derive(Debug, Clone)]
pub struct TimeProducer {
    cob_id: TimeCobId,
    out: FrameQueue<2>,
}

impl TimeProducer {
    /// A producer configured by `cob_id`.
    #[must_use]
    pub const fn new(cob_id: TimeCobId) -> Self {
        TimeProducer {
            cob_id,
            out: FrameQueue::empty(),
        }
    }

    /// 1012h written.
    pub fn set_cob_id(&mut self, cob_id: TimeCobId) {
        self.cob_id = cob_id;
    }

    /// 1012h.
    #[must_use]
    pub const fn cob_id(&self) -> TimeCobId {
        self.cob_id
    }

    /// Queues a TIME frame with `time`; false when 1012h has no produce bit
    /// or no valid identifier.
    pub fn send_time(&mut self, now: Timestamp, time: TimeOfDay) -> bool {
        let _ = now;
        let Some(id) = self.cob_id.id().filter(|_| self.cob_id.produces()) else {
            return false;
        };
        self.out.push(time.to_frame_on(id));
        true
    }
}

impl Machine for TimeProducer {
    type Event = Infallible;

    /// The producer takes no input frames.
    fn handle_frame(&mut self, _now: Timestamp, _frame: &CanFrame) {}

    /// The producer has no timers.
    fn handle_timeout(&mut self, _now: Timestamp) {}

    fn poll_timeout(&self) -> Option<Timestamp> {
        None
    }

    crate::machine::queued_outputs!(frames: out, events: none);
}
