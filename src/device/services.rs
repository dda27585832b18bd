//! The device core's error control besides the heartbeat and its SYNC and
//! TIME services: node guarding with life guarding (100Ch, 100Dh), the SYNC
//! producer and consumer (1005h, 1006h, 1007h, 1019h) and TIME (1012h).
//!
//! What they do is in the [device core docs](super).

use core::time::Duration;

use super::{Device, DeviceEvent, Profile};
use crate::frame::CanFrame;
use crate::guarding::GuardingSlave;
use crate::machine::Machine;
use crate::nmt::NmtState;
use crate::od::ObjectDictionary;
use crate::pdo::{PdoDirection, TransmissionType};
use crate::sync::{SyncCobId, SyncConsumer, SyncEvent, SyncProducer};
use crate::time::Timestamp;
use crate::time_of_day::{TimeCobId, TimeConsumer, TimeOfDay, TimeProducer};
use crate::{cob_id::NodeId, PdoNumber};

/// The values the services were last configured with (so that an
/// unrelated write does not restart a timer).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Applied {
    guard_time_ms: u16,
    life_time_factor: u8,
    heartbeat_active: bool,
    sync_cob_id: SyncCobId,
    cycle_period_us: u32,
    sync_window_us: u32,
    sync_counter_overflow: u8,
    time_cob_id: TimeCobId,
}

/// The services' machines.
#[derive(Debug, Clone)]
pub(super) struct Services {
    pub(super) guarding: GuardingSlave,
    pub(super) sync_producer: SyncProducer,
    pub(super) sync_consumer: SyncConsumer,
    pub(super) time_consumer: TimeConsumer,
    applied: Option<Applied>,
}

impl Services {
    pub(super) fn new(node: NodeId) -> Self {
        Services {
            guarding: GuardingSlave::new(node),
            sync_producer: SyncProducer::idle(),
            sync_consumer: SyncConsumer::new(),
            time_consumer: TimeConsumer::new(TimeCobId::DEFAULT),
            applied: None,
        }
    }

    /// The earliest deadline of the services.
    pub(super) fn poll_timeout(&self) -> Option<Timestamp> {
        [
            self.guarding.poll_timeout(),
            self.sync_producer.poll_timeout(),
        ]
        .into_iter()
        .flatten()
        .min()
    }
}

impl<A, E> Device<A, E>
where
    A: ObjectDictionary + Clone,
    E: Copy + From<DeviceEvent>,
{
    /// Node guarding (the slave side), for its state.
    #[must_use]
    pub const fn guarding(&self) -> &GuardingSlave {
        &self.services.guarding
    }

    /// The SYNC consumer (1005h's identifier, 1007h, 1019h).
    #[must_use]
    pub const fn sync_consumer(&self) -> &SyncConsumer {
        &self.services.sync_consumer
    }

    /// The SYNC producer (runs with 1005h's generate bit and 1006h).
    #[must_use]
    pub const fn sync_producer(&self) -> &SyncProducer {
        &self.services.sync_producer
    }

    /// The last TIME received (1012h consume bit).
    #[must_use]
    pub const fn last_time(&self) -> Option<TimeOfDay> {
        self.services.time_consumer.last()
    }

    /// Sends TIME with `time` (1012h produce bit; pre-operational and
    /// operational). False when nothing was sent.
    pub fn send_time(&mut self, now: Timestamp, time: TimeOfDay) -> bool {
        let mut producer = TimeProducer::new(self.comm().time_cob_id);
        if !self.nmt.sdo_allowed() || !producer.send_time(now, time) {
            return false;
        }
        while let Some(frame) = producer.poll_transmit() {
            self.send(frame);
        }
        true
    }

    /// Boot or reset: the services start over from the restored objects
    /// (toggle 0, life guarding waiting for the first request, SYNC counter 1).
    pub(super) fn reset_services(&mut self, now: Timestamp) {
        self.services = Services::new(self.config.node);
        self.apply_services(now);
        self.services_entered(now, NmtState::PreOperational);
    }

    /// Puts changed service objects into effect.
    pub(super) fn apply_services(&mut self, now: Timestamp) {
        let comm = self.comm();
        let want = Applied {
            guard_time_ms: comm.guard_time_ms,
            life_time_factor: comm.life_time_factor,
            heartbeat_active: comm.heartbeat_ms != 0,
            sync_cob_id: comm.sync_cob_id,
            cycle_period_us: comm.cycle_period_us,
            sync_window_us: comm.sync_window_us,
            sync_counter_overflow: comm.sync_counter_overflow,
            time_cob_id: comm.time_cob_id,
        };
        let old = self.services.applied.replace(want);
        let changed = |f: fn(&Applied) -> u64| old.as_ref().map(f) != Some(f(&want));
        let s = &mut self.services;
        if changed(|a| u64::from(a.guard_time_ms) << 8 | u64::from(a.life_time_factor)) {
            s.guarding.set_life_guarding(
                now,
                Duration::from_millis(u64::from(want.guard_time_ms)),
                want.life_time_factor,
            );
        }
        s.guarding.set_heartbeat_active(now, want.heartbeat_active);
        if let Some(id) = want.sync_cob_id.id() {
            s.sync_consumer.set_id(id);
            s.sync_producer.set_id(id);
        }
        s.sync_consumer
            .set_window(Duration::from_micros(u64::from(want.sync_window_us)));
        if changed(|a| u64::from(a.sync_counter_overflow)) {
            let _ = s
                .sync_consumer
                .set_counter_overflow(want.sync_counter_overflow);
            let _ = s
                .sync_producer
                .set_counter_overflow(want.sync_counter_overflow);
        }
        s.time_consumer.set_cob_id(want.time_cob_id);
        if changed(|a| u64::from(a.cycle_period_us) << 32 | u64::from(a.sync_cob_id.raw())) {
            s.sync_producer
                .set_period(now, Duration::from_micros(u64::from(want.cycle_period_us)));
            s.sync_producer.stop();
            self.run_sync_producer(now);
        }
    }

    /// Starts or stops the SYNC producer as 1005h, 1006h and the NMT state say.
    fn run_sync_producer(&mut self, now: Timestamp) {
        let comm = self.comm();
        let wanted = comm.sync_cob_id.generates()
            && comm.cycle_period_us != 0
            && comm.sync_cob_id.id().is_some()
            && self.nmt.sdo_allowed();
        let producer = &mut self.services.sync_producer;
        if wanted && !producer.is_running() {
            producer.start(now);
        } else if !wanted {
            producer.stop();
        }
    }

    /// The services' part of entering `to`.
    pub(super) fn services_entered(&mut self, now: Timestamp, to: NmtState) {
        self.services.guarding.set_state(to);
        self.run_sync_producer(now);
    }

    /// A received frame: guarding requests, SYNC, TIME.
    pub(super) fn services_frame<P: Profile<A, E>>(
        &mut self,
        now: Timestamp,
        frame: &CanFrame,
        profile: &mut P,
    ) {
        self.services.guarding.handle_frame(now, frame);
        if self.nmt.sdo_allowed() {
            self.take_sync(now, frame, profile);
            self.services.time_consumer.handle_frame(now, frame);
        }
        self.drain_services(now, profile);
    }

    /// A SYNC frame (received or the device's own) on 1005h's identifier
    /// runs the synchronous TPDOs.
    fn take_sync<P: Profile<A, E>>(&mut self, now: Timestamp, frame: &CanFrame, profile: &mut P) {
        if self.services.sync_consumer.accept(now, frame)
            && self.nmt.state() == NmtState::Operational
        {
            self.refresh_tpdos(now);
            self.tpdos.handle_sync(now);
        }
        self.drain_services(now, profile);
    }

    /// Time has passed: life guarding, the SYNC producer.
    pub(super) fn services_timeout<P: Profile<A, E>>(&mut self, now: Timestamp, profile: &mut P) {
        self.services.guarding.handle_timeout(now);
        self.services.sync_producer.handle_timeout(now);
        while let Some(frame) = self.services.sync_producer.poll_transmit() {
            self.send(frame);
            self.take_sync(now, &frame, profile);
        }
        self.drain_services(now, profile);
    }

    /// A synchronous RPDO was received: outside the window it is an event.
    pub(super) fn note_rpdo<P: Profile<A, E>>(
        &mut self,
        now: Timestamp,
        pdo: PdoNumber,
        profile: &mut P,
    ) {
        let synchronous = self
            .server
            .od()
            .config
            .get(PdoDirection::Receive, pdo)
            .is_some_and(|slot| {
                !matches!(
                    slot.comm.transmission_type,
                    TransmissionType::EventManufacturer | TransmissionType::EventProfile
                )
            });
        if synchronous {
            let _ = self.services.sync_consumer.note_synchronous_pdo(now);
        }
        self.drain_services(now, profile);
    }

    /// The services' events into the device's queue.
    pub(super) fn drain_services<P: Profile<A, E>>(&mut self, now: Timestamp, profile: &mut P) {
        while let Some(e) = self.services.guarding.poll_event() {
            self.emit(now, DeviceEvent::LifeGuarding(e), profile);
        }
        while let Some(e) = self.services.sync_consumer.poll_event() {
            if !matches!(e, SyncEvent::Received { .. }) {
                self.emit(now, DeviceEvent::Sync(e), profile);
            }
        }
        while let Some(e) = self.services.time_consumer.poll_event() {
            self.emit(now, DeviceEvent::Time(e), profile);
        }
    }
}
