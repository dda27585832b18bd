//! The device core's heartbeat consumer (1016h; feature
//! `heartbeat-consumer`): the nodes of 1016h's entries are supervised and
//! their events reported as [`DeviceEvent::Heartbeat`]. Without the
//! feature the device has no 1016h and watches no other node.
//!
//! The consumer keeps no events of its own here (its queue has no slot):
//! a frame makes at most one, which is reported at once, and a timeout
//! call reports the nodes whose time ran out one by one, in slot order.
//!
//! What it does is in the [device core docs](super).

use super::{Device, DeviceEvent, DeviceSpec, Profile, MAX_CONSUMERS};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::nmt::heartbeat::{HeartbeatConsumer, HeartbeatEvent};

/// The device's consumer: one watch per 1016h entry, no event slot (see
/// the module docs).
pub(super) type DeviceConsumer = HeartbeatConsumer<MAX_CONSUMERS, 0>;

impl<S: DeviceSpec, const Q: usize, const T: usize, const R: usize> Device<S, Q, T, R> {
    /// The heartbeat consumer (1016h), for its nodes' states (feature
    /// `heartbeat-consumer`). Its events are the device's
    /// ([`DeviceEvent::Heartbeat`]); it keeps none itself.
    #[must_use]
    pub const fn heartbeat_consumer(&self) -> &HeartbeatConsumer<MAX_CONSUMERS, 0> {
        &self.consumer
    }

    /// Boot or reset: the supervision starts over from the restored 1016h.
    pub(super) fn reset_consumer(&mut self) {
        let entries = self.server.od().inner.comm.consumers();
        self.consumer.load_entries(entries, true);
    }

    /// Puts 1016h's entries into effect: changed entries restart their
    /// supervision, the others run on.
    pub(super) fn apply_consumers(&mut self) {
        let entries = self.server.od().inner.comm.consumers();
        self.consumer.load_entries(entries, false);
    }

    /// Feeds a received frame to the consumer and reports its event.
    pub(super) fn consumer_frame<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        frame: &CanFrame,
        profile: &mut P,
    ) {
        if let Some(e) = self.consumer.take_frame(now, frame) {
            self.emit(now, DeviceEvent::Heartbeat(e), profile);
        }
    }

    /// Reports every node whose time has run out.
    pub(super) fn consumer_timeout<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        profile: &mut P,
    ) {
        while let Some(node) = self.consumer.expire_one(now) {
            self.emit(
                now,
                DeviceEvent::Heartbeat(HeartbeatEvent::Lost(node)),
                profile,
            );
        }
    }
}
