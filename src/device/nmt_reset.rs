//! The device core's NMT state changes: boot and the two resets (what they
//! restore, the boot-up message, pre-operational), and what entering a
//! state starts or stops (the SDO transfer, the heartbeat, the services,
//! the PDOs).
//!
//! What they do is in the [device core docs](super) (CiA 301 section
//! 7.3.2, NMT slave).

#[cfg(feature = "lss")]
use super::PowerOn;
use super::{Device, DeviceEvent, DeviceSpec, PowerOnValues, Profile, Restarted};
use crate::clock::Timestamp;
#[cfg(feature = "lss")]
use crate::lss::LssSlave;
#[cfg(feature = "lss")]
use crate::nmt::NmtCore;
use crate::nmt::{NmtSlaveEvent, NmtState, ResetKind};

impl<S: DeviceSpec, const Q: usize, const T: usize, const R: usize> Device<S, Q, T, R> {
    /// Handles an event of the NMT slave. A reset restores the device
    /// first, so the profile sees it as the reset left it (pre-operational,
    /// running) and may act on it, e.g. start itself; the boot's state
    /// change follows ([`report_nmt_boot`](Self::report_nmt_boot)).
    pub(super) fn nmt_event<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        event: NmtSlaveEvent,
        profile: &mut P,
    ) {
        match event {
            NmtSlaveEvent::Reset(kind) => {
                #[cfg(feature = "store")]
                let stored = self.restart(now, kind);
                #[cfg(not(feature = "store"))]
                self.restart(now, kind);
                let node = kind == ResetKind::Node;
                self.emit(now, DeviceEvent::Reset { node }, profile);
                #[cfg(feature = "store")]
                self.report_storage(now, stored, profile);
                self.report_nmt_boot(now, profile);
            }
            NmtSlaveEvent::StateChanged { from, to } => {
                self.entered(now, to);
                self.emit(now, DeviceEvent::NmtStateChanged { from, to }, profile);
            }
        }
    }

    /// Reports the held state change of the boot after a reset, if any.
    pub(super) fn report_nmt_boot<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        profile: &mut P,
    ) {
        if let Some(from) = self.nmt_boot.take() {
            let to = NmtState::PreOperational;
            self.nmt_event(now, NmtSlaveEvent::StateChanged { from, to }, profile);
        }
    }

    /// Boot or reset: restores the objects `kind` says (and loads what is
    /// stored of them, feature `store`), boot-up message, pre-operational.
    pub(super) fn restart(&mut self, now: Timestamp, kind: ResetKind) -> Restarted {
        // The LSS node-ID configured since takes effect (CiA 305).
        #[cfg(feature = "lss")]
        if let Some(node) = self.lss.as_mut().and_then(LssSlave::reset_communication) {
            if node != self.node || !self.nmt.is_running() {
                self.config.move_node(node);
                self.node = node;
                self.nmt = NmtCore::new(node);
            }
        }
        // A running transfer ends silently; a download is aborted in the
        // dictionary before the application objects are kept.
        self.server.cancel();
        if kind == ResetKind::Node {
            self.tpdos_stale = true;
            self.server.od_mut().inner.app.restore(&self.power_on);
        }
        self.load_power_on();
        #[cfg(feature = "store")]
        let stored = self.load_stored(kind);
        #[cfg(feature = "store")]
        self.apply_heartbeat_period(now);
        self.heartbeat.boot(now);
        #[cfg(feature = "heartbeat-consumer")]
        self.reset_consumer();
        self.tpdos.reset();
        self.reconfigure_pdos(now);
        self.nmt_boot = self.nmt.boot();
        self.reset_services(now);
        #[cfg(feature = "store")]
        stored
    }

    /// The core's part of entering `to`.
    pub(super) fn entered(&mut self, now: Timestamp, to: NmtState) {
        if to == NmtState::Stopped {
            // No SDO in stopped: the running transfer ends silently (a
            // download is aborted in the dictionary).
            self.tpdos_stale |= self.server.is_busy();
            self.server.cancel();
        }
        self.heartbeat.set_state(now, to);
        self.services_entered(now, to);
        self.gate_pdos(now);
    }

    pub(super) fn gate_pdos(&mut self, now: Timestamp) {
        let operational = self.nmt.state() == NmtState::Operational;
        self.rpdos.set_enabled(operational);
        let run = operational && self.tpdos_enabled;
        if run {
            self.refresh_tpdos(now);
        }
        self.tpdos.set_operational(now, run);
    }

    pub(super) fn reconfigure_pdos(&mut self, now: Timestamp) {
        self.refresh_tpdos(now);
        self.tpdos.reconfigure(now, &self.server.od().config);
        self.rpdos.reconfigure(&self.server.od().config);
        self.gate_pdos(now);
    }

    pub(super) fn apply_heartbeat_period(&mut self, now: Timestamp) {
        let ms = self.comm().heartbeat_ms;
        // Compared in microseconds: no 64-bit division on a 32-bit target.
        if u64::from(ms) * 1000 != self.heartbeat.period_us() {
            self.heartbeat.set_period_ms(now, ms);
        }
    }
}
