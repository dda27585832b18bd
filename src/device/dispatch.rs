//! The device core's inputs and outputs: a received frame, a timeout, the
//! next frame to send and the next deadline, with the profile passed in
//! (what [`ProfiledDevice`](super::ProfiledDevice) calls for its
//! [`Machine`] methods), and where their results go: the SDO server's
//! events, the RPDOs written into the mapped objects, the events handed to
//! the profile.
//!
//! What they do is in the [device core docs](super) (CiA 301 sections
//! 7.2.2 PDO, 7.2.4 SDO and 7.2.8 network management).

use super::{Device, DeviceEvent, DeviceSpec, Profile};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
#[cfg(feature = "lss")]
use crate::lss::LssSlave;
use crate::machine::Machine;
#[cfg(feature = "heartbeat-consumer")]
use crate::od::index::CONSUMER_HEARTBEAT_TIME;
use crate::od::index::PRODUCER_HEARTBEAT_TIME;
#[cfg(feature = "store")]
use crate::od::index::{RESTORE_DEFAULT_PARAMETERS, STORE_PARAMETERS};
use crate::pdo::{PdoDirection, PdoFrame, RpdoReceiver};
use crate::sdo::ServerEvent;

impl<S: DeviceSpec, const Q: usize, const T: usize, const R: usize> Device<S, Q, T, R> {
    /// Feeds a received frame: NMT, heartbeats of 1016h's nodes, SYNC, this
    /// node's SDO requests and RPDOs, then the profile's frames.
    pub(super) fn handle_frame_with<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        frame: &CanFrame,
        profile: &mut P,
    ) {
        #[cfg(feature = "lss")]
        if self.powered {
            if let Some(lss) = self.lss.as_mut() {
                lss.handle_frame(now, frame);
                self.drain_lss(now, profile);
            }
        }
        if !self.nmt.is_running() {
            return;
        }
        if let Some(event) = self.nmt.take_frame(frame) {
            // An NMT command that changed something: not for anyone else.
            self.nmt_event(now, event, profile);
            return;
        }
        #[cfg(feature = "heartbeat-consumer")]
        self.consumer_frame(now, frame, profile);
        if self.nmt.sdo_allowed() {
            // A request, or a frame while a transfer runs, may write the
            // objects (a download's value, or its abort).
            self.tpdos_stale |= self.server.is_busy() || self.server.is_request(frame);
            self.server.handle_frame(now, frame);
            self.drain_server(now, profile);
        }
        // Guarding requests, SYNC (which runs the synchronous TPDOs) and TIME.
        self.services_frame(now, frame, profile);
        self.drain_rpdos(now, frame, profile);
        profile.on_frame(self, now, frame);
    }

    /// Tells the device time has passed: heartbeat, supervision, SDO
    /// timeout, the profile's timers, TPDO timers.
    pub(super) fn handle_timeout_with<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        profile: &mut P,
    ) {
        if !self.nmt.is_running() {
            return;
        }
        self.heartbeat.handle_timeout(now);
        #[cfg(feature = "heartbeat-consumer")]
        self.consumer_timeout(now, profile);
        self.services_timeout(now, profile);
        // A transfer that times out aborts its download in the dictionary.
        self.tpdos_stale |= self.server.is_busy();
        self.server.handle_timeout(now);
        self.drain_server(now, profile);
        profile.on_timeout(self, now);
        self.refresh_stale_tpdos(now);
        self.tpdos.handle_timeout(now);
    }

    // ----- outputs ---------------------------------------------------------

    /// The next frame to send (order in the module docs).
    #[must_use]
    pub(super) fn poll_transmit_with<P: Profile<S, Q, T, R>>(
        &mut self,
        profile: &mut P,
    ) -> Option<CanFrame> {
        // The order of the module docs: the first source with a frame.
        if let Some(frame) = self.heartbeat.poll_transmit() {
            return Some(frame);
        }
        #[cfg(feature = "guarding")]
        if let Some(frame) = self.services.guarding.poll_transmit() {
            return Some(frame);
        }
        if let Some(frame) = self.transmit.pop() {
            return Some(frame);
        }
        #[cfg(feature = "lss")]
        if let Some(frame) = self.lss.as_mut().and_then(LssSlave::poll_transmit) {
            return Some(frame);
        }
        if let Some(frame) = self.server.poll_transmit() {
            return Some(frame);
        }
        if let Some(frame) = profile.poll_transmit() {
            return Some(frame);
        }
        self.tpdos.poll_transmit()
    }

    /// The earliest deadline of the core's and the profile's timers.
    #[must_use]
    pub(super) fn poll_timeout_with<P: Profile<S, Q, T, R>>(
        &self,
        profile: &P,
    ) -> Option<Timestamp> {
        if !self.nmt.is_running() {
            return None;
        }
        crate::clock::earliest([
            self.heartbeat.poll_timeout(),
            #[cfg(feature = "heartbeat-consumer")]
            self.consumer.poll_timeout(),
            #[cfg(feature = "guarding")]
            self.services.guarding.poll_timeout(),
            #[cfg(feature = "sync-time")]
            self.services.sync_producer.poll_timeout(),
            self.server.poll_timeout(),
            profile.poll_timeout(),
            self.tpdos.poll_timeout(),
        ])
    }

    pub(super) fn emit<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        event: DeviceEvent,
        profile: &mut P,
    ) {
        if profile.keep_event(&event) {
            self.events.push(<S::Event>::from(event));
        }
        profile.on_event(self, now, &event);
    }

    /// Hands the SDO server's events on and puts written objects into effect.
    pub(super) fn drain_server<P: Profile<S, Q, T, R>>(&mut self, now: Timestamp, profile: &mut P) {
        while let Some(event) = self.server.poll_event() {
            match event {
                ServerEvent::Downloaded { index, sub, .. } => {
                    match index {
                        PRODUCER_HEARTBEAT_TIME => self.apply_heartbeat_period(now),
                        // A "save" or "load" the dictionary accepted; a
                        // storage that fails aborts it instead.
                        #[cfg(feature = "store")]
                        STORE_PARAMETERS | RESTORE_DEFAULT_PARAMETERS
                            if self.store_command(now, index, sub, profile).is_err() =>
                        {
                            continue;
                        }
                        #[cfg(feature = "heartbeat-consumer")]
                        CONSUMER_HEARTBEAT_TIME => self.apply_consumers(),
                        _ if PdoDirection::from_index(index).is_some() => {
                            self.reconfigure_pdos(now);
                        }
                        _ => {}
                    }
                    // 100Ch, 100Dh, 1005h-1007h, 1012h, 1019h; 1017h too.
                    self.apply_services(now);
                    self.refresh_tpdos(now);
                    self.emit(now, DeviceEvent::ObjectWritten { index, sub }, profile);
                }
                ServerEvent::Aborted {
                    index,
                    sub,
                    code,
                    origin,
                } => self.emit(
                    now,
                    DeviceEvent::SdoAborted {
                        index,
                        sub,
                        code,
                        origin,
                    },
                    profile,
                ),
                _ => {}
            }
        }
    }

    /// The RPDO `frame` is on, if any, written into the mapped objects at
    /// once (what the receiver's `handle_frame` and `poll_event` would
    /// give, without its event slot: a frame is at most one RPDO).
    pub(super) fn drain_rpdos<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        frame: &CanFrame,
        profile: &mut P,
    ) {
        if let Some(pdo) = self.rpdos.rpdo_of(frame) {
            let Ok(data) = PdoFrame::of_frame(frame) else {
                return;
            };
            // Values the objects already hold change nothing the TPDOs
            // read: no refresh for them (unless something else asks). On
            // a host, where long simulated sessions make the read-back
            // pay; a no-alloc firmware, whose RPDOs come a few times a
            // second, keeps the 290 B of flash it takes and reads again.
            let od = self.server.od_mut();
            #[cfg(feature = "alloc")]
            let changes = self.tpdos_stale || !RpdoReceiver::holds_data(pdo, data.as_bytes(), od);
            #[cfg(not(feature = "alloc"))]
            let changes = true;
            self.tpdos_stale = changes;
            let Some(result) = RpdoReceiver::apply_data(pdo, data.as_bytes(), od) else {
                return;
            };
            match result {
                Ok(_) => {
                    self.note_rpdo(now, pdo, profile);
                    self.emit(now, DeviceEvent::RpdoReceived { pdo }, profile);
                }
                Err(error) => {
                    if let Some(emcy) = profile.rpdo_emergency(self.error_register(), &error) {
                        self.send_emergency(&emcy);
                    }
                    self.emit(now, DeviceEvent::RpdoRefused { pdo, error }, profile);
                }
            }
            self.refresh_stale_tpdos(now);
        }
    }
}
