//! The TIME consumer (CiA 301 section 7.2.6 "Time stamp object"): every
//! TIME received while 1012h has the consume bit, with the local time it arrived.

use super::{TimeCobId, TimeOfDay};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::queue::EventQueue;
use crate::wire::Codec;

/// What the TIME consumer reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum TimeEvent {
    /// A TIME frame arrived.
    Received {
        /// The time of day it carries.
        time: TimeOfDay,
        /// The local time it arrived.
        at: Timestamp,
    },
}

/// Receives TIME while 1012h has the consume bit; frames of another length
/// than 6 bytes are ignored.
///
/// ```
/// use canopen_codec::machine::Machine;
/// use canopen_codec::time::{TimeCobId, TimeConsumer, TimeEvent};
/// use canopen_codec::{CanFrame, Timestamp};
/// let mut c = TimeConsumer::new(TimeCobId::DEFAULT.with_consume(true));
/// let f = CanFrame::standard(0x100, &[0x00, 0x2E, 0x93, 0x02, 0x02, 0x00]).unwrap();
/// c.handle_frame(Timestamp::from_millis(7), &f);
/// let Some(TimeEvent::Received { time, at }) = c.poll_event() else { panic!() };
/// assert_eq!((time.millis, time.days, at.as_millis()), (43_200_000, 2, 7));
/// ```
#[derive(Debug, Clone)]
pub struct TimeConsumer {
    cob_id: TimeCobId,
    last: Option<TimeOfDay>,
    events: EventQueue<TimeEvent, 2>,
}

impl TimeConsumer {
    /// A consumer configured by `cob_id`.
    #[must_use]
    pub const fn new(cob_id: TimeCobId) -> Self {
        TimeConsumer {
            cob_id,
            last: None,
            events: EventQueue::new(TimeEvent::Received {
                time: TimeOfDay {
                    millis: 0,
                    days: 0,
                    reserved: 0,
                },
                at: Timestamp::ZERO,
            }),
        }
    }

    /// 1012h written.
    pub fn set_cob_id(&mut self, cob_id: TimeCobId) {
        self.cob_id = cob_id;
    }

    /// The last time of day received.
    #[must_use]
    pub const fn last(&self) -> Option<TimeOfDay> {
        self.last
    }
}

impl Machine for TimeConsumer {
    type Event = TimeEvent;

    /// TIME frames on 1012h's identifier while consuming.
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        if !self.cob_id.consumes() || frame.is_remote() || Some(frame.id()) != self.cob_id.id() {
            return;
        }
        if let Ok(time) = TimeOfDay::parse_frame(frame) {
            self.last = Some(time);
            self.events.push(TimeEvent::Received { time, at: now });
        }
    }

    /// The consumer has no timers.
    fn handle_timeout(&mut self, _now: Timestamp) {}

    fn poll_timeout(&self) -> Option<Timestamp> {
        None
    }

    crate::machine::queued_outputs!(frames: none, events: events);
}
