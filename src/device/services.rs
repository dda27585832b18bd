//! The device core's error control besides the heartbeat and its SYNC and
//! TIME services: node guarding with life guarding (100Ch, 100Dh; feature
//! `guarding`), the SYNC consumer (1005h, 1007h, 1019h), the SYNC producer
//! (1005h's generate bit, 1006h) and TIME (1012h) (feature `sync-time`).
//!
//! What they do is in the [device core docs](super).

use core::time::Duration;

use super::{Device, DeviceEvent, DeviceSpec, Profile};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::machine::Machine;
#[cfg(feature = "guarding")]
use crate::nmt::guarding::GuardingSlave;
use crate::nmt::NmtState;
use crate::pdo::{PdoDirection, TransmissionType};
#[cfg(feature = "sync-time")]
use crate::sync::SyncCobId;
use crate::sync::SyncConsumer;
#[cfg(doc)]
use crate::sync::SyncEvent;
#[cfg(feature = "sync-time")]
use crate::sync::SyncProducer;
#[cfg(feature = "sync-time")]
use crate::time::{TimeCobId, TimeConsumer, TimeOfDay, TimeProducer};
use crate::{cob_id::NodeId, PdoNumber};

/// The values the services were last configured with (so that an
/// unrelated write does not restart a timer or the SYNC counter check):
/// only those compared (1005h's identifier and 1007h are put into effect
/// on every write; 1005h is kept for the SYNC producer's period test).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Applied {
    #[cfg(feature = "guarding")]
    guard_time_ms: u16,
    #[cfg(feature = "guarding")]
    life_time_factor: u8,
    #[cfg(feature = "guarding")]
    heartbeat_active: bool,
    #[cfg(feature = "sync-time")]
    sync_cob_id: SyncCobId,
    #[cfg(feature = "sync-time")]
    cycle_period_us: u32,
    sync_counter_overflow: u8,
    #[cfg(feature = "sync-time")]
    time_cob_id: TimeCobId,
}

/// The services' machines.
#[derive(Debug, Clone)]
pub(super) struct Services {
    #[cfg(feature = "guarding")]
    pub(super) guarding: GuardingSlave,
    #[cfg(feature = "sync-time")]
    pub(super) sync_producer: SyncProducer,
    /// Its events are read after every call; SYNC frames are taken
    /// without queueing [`SyncEvent::Received`] (not reported), so one
    /// call makes at most one (a skipped counter from a SYNC, or a
    /// synchronous RPDO outside the window): one slot is exact.
    pub(super) sync_consumer: SyncConsumer<1>,
    #[cfg(feature = "sync-time")]
    pub(super) time_consumer: TimeConsumer,
    /// With neither `guarding` nor `sync-time` the one value compared,
    /// 1019h, is the SYNC consumer's own (a valid 1019h is always taken).
    #[cfg(any(feature = "guarding", feature = "sync-time"))]
    applied: Option<Applied>,
}

impl Services {
    pub(super) fn new(node: NodeId) -> Self {
        #[cfg(not(feature = "guarding"))]
        let _ = node;
        Services {
            #[cfg(feature = "guarding")]
            guarding: GuardingSlave::new(node),
            #[cfg(feature = "sync-time")]
            sync_producer: SyncProducer::idle(),
            sync_consumer: SyncConsumer::with_event_capacity(),
            #[cfg(feature = "sync-time")]
            time_consumer: TimeConsumer::new(TimeCobId::DEFAULT),
            #[cfg(any(feature = "guarding", feature = "sync-time"))]
            applied: None,
        }
    }
}

impl<S: DeviceSpec, const Q: usize, const T: usize, const R: usize> Device<S, Q, T, R> {
    /// Node guarding (the slave side), for its state (feature `guarding`).
    #[cfg(feature = "guarding")]
    #[must_use]
    pub const fn guarding(&self) -> &GuardingSlave {
        &self.services.guarding
    }

    /// The SYNC consumer (1005h's identifier, 1007h, 1019h).
    #[must_use]
    pub const fn sync_consumer(&self) -> &SyncConsumer<1> {
        &self.services.sync_consumer
    }

    /// The SYNC producer (runs with 1005h's generate bit and 1006h;
    /// feature `sync-time`).
    #[cfg(feature = "sync-time")]
    #[must_use]
    pub const fn sync_producer(&self) -> &SyncProducer {
        &self.services.sync_producer
    }

    /// The last TIME received (1012h consume bit; feature `sync-time`).
    #[cfg(feature = "sync-time")]
    #[must_use]
    pub const fn last_time(&self) -> Option<TimeOfDay> {
        self.services.time_consumer.last()
    }

    /// Sends TIME with `time` (1012h produce bit; pre-operational and
    /// operational; feature `sync-time`). False when nothing was sent.
    #[cfg(feature = "sync-time")]
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
        self.services = Services::new(self.node);
        self.apply_services(now);
        self.services_entered(now, NmtState::PreOperational);
    }

    /// Puts changed service objects into effect.
    pub(super) fn apply_services(&mut self, now: Timestamp) {
        let comm = self.comm();
        let want = Applied {
            #[cfg(feature = "guarding")]
            guard_time_ms: comm.guard_time_ms,
            #[cfg(feature = "guarding")]
            life_time_factor: comm.life_time_factor,
            #[cfg(feature = "guarding")]
            heartbeat_active: comm.heartbeat_ms != 0,
            #[cfg(feature = "sync-time")]
            sync_cob_id: comm.sync_cob_id,
            #[cfg(feature = "sync-time")]
            cycle_period_us: comm.cycle_period_us,
            sync_counter_overflow: comm.sync_counter_overflow,
            #[cfg(feature = "sync-time")]
            time_cob_id: comm.time_cob_id,
        };
        let comm_sync_id = comm.sync_cob_id.id();
        let sync_window_us = comm.sync_window_us;
        #[cfg(any(feature = "guarding", feature = "sync-time"))]
        let old = self.services.applied.replace(want);
        #[cfg(not(any(feature = "guarding", feature = "sync-time")))]
        let old = Some(Applied {
            sync_counter_overflow: self.services.sync_consumer.counter_overflow(),
        });
        let changed = |f: fn(&Applied) -> u64| old.as_ref().map(f) != Some(f(&want));
        let s = &mut self.services;
        #[cfg(feature = "guarding")]
        {
            if changed(|a| u64::from(a.guard_time_ms) << 8 | u64::from(a.life_time_factor)) {
                s.guarding.set_life_guarding(
                    now,
                    Duration::from_millis(u64::from(want.guard_time_ms)),
                    want.life_time_factor,
                );
            }
            s.guarding.set_heartbeat_active(now, want.heartbeat_active);
        }
        if let Some(id) = comm_sync_id {
            s.sync_consumer.set_id(id);
            #[cfg(feature = "sync-time")]
            s.sync_producer.set_id(id);
        }
        s.sync_consumer
            .set_window(Duration::from_micros(u64::from(sync_window_us)));
        if changed(|a| u64::from(a.sync_counter_overflow)) {
            let _ = s
                .sync_consumer
                .set_counter_overflow(want.sync_counter_overflow);
            #[cfg(feature = "sync-time")]
            let _ = s
                .sync_producer
                .set_counter_overflow(want.sync_counter_overflow);
        }
        #[cfg(feature = "sync-time")]
        {
            s.time_consumer.set_cob_id(want.time_cob_id);
            if changed(|a| u64::from(a.cycle_period_us) << 32 | u64::from(a.sync_cob_id.raw())) {
                s.sync_producer
                    .set_period(now, Duration::from_micros(u64::from(want.cycle_period_us)));
                s.sync_producer.stop();
                self.run_sync_producer(now);
            }
        }
        #[cfg(not(any(feature = "guarding", feature = "sync-time")))]
        let _ = now;
    }

    /// Starts or stops the SYNC producer as 1005h, 1006h and the NMT state say.
    #[cfg(feature = "sync-time")]
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
        #[cfg(feature = "guarding")]
        self.services.guarding.set_state(to);
        #[cfg(feature = "sync-time")]
        self.run_sync_producer(now);
        let _ = (now, to);
    }

    /// A received frame: guarding requests, SYNC, TIME.
    pub(super) fn services_frame<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        frame: &CanFrame,
        profile: &mut P,
    ) {
        #[cfg(feature = "guarding")]
        self.services.guarding.handle_frame(now, frame);
        if self.nmt.sdo_allowed() {
            self.take_sync(now, frame);
            #[cfg(feature = "sync-time")]
            self.services.time_consumer.handle_frame(now, frame);
        }
        self.drain_services(now, profile);
    }

    /// A SYNC frame (received or the device's own) on 1005h's identifier
    /// runs the synchronous TPDOs; its event (a skipped counter, the SYNC
    /// consumer's one slot) is the caller's to drain.
    fn take_sync(&mut self, now: Timestamp, frame: &CanFrame) {
        if self.services.sync_consumer.accept_quietly(now, frame)
            && self.nmt.state() == NmtState::Operational
        {
            self.refresh_tpdos(now);
            self.tpdos.handle_sync(now);
        }
    }

    /// Time has passed: life guarding, the SYNC producer.
    pub(super) fn services_timeout<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        profile: &mut P,
    ) {
        #[cfg(feature = "guarding")]
        self.services.guarding.handle_timeout(now);
        #[cfg(feature = "sync-time")]
        {
            self.services.sync_producer.handle_timeout(now);
            while let Some(frame) = self.services.sync_producer.poll_transmit() {
                self.send(frame);
                self.take_sync(now, &frame);
                // The SYNC consumer's one event slot, drained per SYNC.
                self.drain_services(now, profile);
            }
        }
        self.drain_services(now, profile);
    }

    /// A synchronous RPDO was received: outside the window it is an event.
    pub(super) fn note_rpdo<P: Profile<S, Q, T, R>>(
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
    pub(super) fn drain_services<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        profile: &mut P,
    ) {
        #[cfg(feature = "guarding")]
        while let Some(e) = self.services.guarding.poll_event() {
            self.emit(now, DeviceEvent::LifeGuarding(e), profile);
        }
        // No `Received` among them (SYNC frames are taken quietly).
        while let Some(e) = self.services.sync_consumer.poll_event() {
            self.emit(now, DeviceEvent::Sync(e), profile);
        }
        #[cfg(feature = "sync-time")]
        while let Some(e) = self.services.time_consumer.poll_event() {
            self.emit(now, DeviceEvent::Time(e), profile);
        }
    }
}
