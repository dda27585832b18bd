//! The device core's heartbeat consumer (1016h; feature
//! `heartbeat-consumer`): the nodes of 1016h's entries are supervised and
//! their events reported as [`DeviceEvent::Heartbeat`]. Without the
//! feature the device has no 1016h and watches no other node.
//!
//! What it does is in the [device core docs](super).

use super::{Device, DeviceEvent, PowerOn, PowerOnValues, Profile, MAX_CONSUMERS};
use crate::heartbeat::{ConsumerEntry, HeartbeatConsumer};
use crate::machine::Machine;
use crate::od::ObjectDictionary;
use crate::time::Timestamp;

impl<A, E, const Q: usize, C, const T: usize, const R: usize> Device<A, E, Q, C, T, R>
where
    A: ObjectDictionary + PowerOnValues,
    E: Copy + From<DeviceEvent>,
    C: PowerOn,
{
    /// The heartbeat consumer (1016h), for its nodes' states (feature
    /// `heartbeat-consumer`).
    #[must_use]
    pub const fn heartbeat_consumer(&self) -> &HeartbeatConsumer<MAX_CONSUMERS, MAX_CONSUMERS> {
        &self.consumer
    }

    /// Boot or reset: the supervision starts over from the restored 1016h.
    pub(super) fn reset_consumer(&mut self, now: Timestamp) {
        self.consumer = HeartbeatConsumer::new();
        self.apply_consumers(now);
    }

    /// Puts 1016h's entries into effect: changed entries restart their
    /// supervision, the others run on.
    pub(super) fn apply_consumers(&mut self, now: Timestamp) {
        let entries = self.server.od().inner.comm.consumers();
        let wanted = |slot: usize| entries.get(slot).copied().unwrap_or_default();
        // Changed slots are freed first, so a node that moves to another
        // sub-index is not refused as a duplicate of its old one.
        for slot in 0..MAX_CONSUMERS {
            if self.consumer.entry(slot) != Some(wanted(slot)) {
                let _ = self.consumer.set_entry(now, slot, ConsumerEntry::default());
            }
        }
        for slot in 0..MAX_CONSUMERS {
            let _ = self.consumer.set_entry(now, slot, wanted(slot));
        }
    }

    /// Reports the consumer's events.
    pub(super) fn drain_consumer<P: Profile<A, E, Q, C, T, R>>(
        &mut self,
        now: Timestamp,
        profile: &mut P,
    ) {
        while let Some(e) = self.consumer.poll_event() {
            self.emit(now, DeviceEvent::Heartbeat(e), profile);
        }
    }
}
