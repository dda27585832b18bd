//! The PDO pairing (CiA 419 section 7.2; Delta-Q IC Series CANopen
//! interface specification, section 4.5.5): the module's 1000h, then the
//! COB-ID of each pair its device type declares, copied to the charger's
//! paired PDO. A request left unanswered (the SDO timeout) is asked again,
//! [`ATTEMPTS`] in all for one finding of the module, as a lossy bus may
//! lose one frame of it; an abort from the module, or the last attempt's
//! timeout, fails the pairing (E-0-3-0) until the module is found again.

use super::battery::ATTEMPTS;
use super::config::default_pdos;
use super::{Alarm, ChargerDevice, ChargerEvent, ChargerProfile, Link, PAIRS};
use crate::abort::AbortCode;
use crate::bytes::InlineData;
use crate::clock::Timestamp;
use crate::deltaq::DeltaQCode;
use crate::emcy::ErrorRegister;
use crate::machine::Machine;
use crate::od::index::DEVICE_TYPE;
use crate::pdo::{PdoCobId, PdoSlot};

impl ChargerProfile {
    /// The pairing failed ([`Link::Failed`]): no 6020h read follows.
    pub(super) fn config_failed<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
    ) {
        self.link = Link::Failed;
        self.identification_dropped(device, now);
    }

    /// Reads the module's 1000h with a fresh client: a transfer of an
    /// earlier attempt (a module that rebooted meanwhile) ends silently.
    pub(super) fn start_configuration<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
    ) {
        self.fresh_client();
        self.link = Link::DeviceType;
        if self.client.start_upload(now, DEVICE_TYPE, 0).is_err() {
            self.config_failed(device, now);
        }
    }

    /// Back to the not-valid default COB-IDs (when configuring them).
    pub(super) fn forget_pairing<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
    ) {
        if self.configure_cob_ids {
            let power_on = *device.power_on();
            device.update_pdos(now, |c| default_pdos(&power_on, c));
        }
        self.link = Link::Absent;
        device.set_tpdos_enabled(now, false);
    }

    /// Configured ([`Link::Ready`]): reported, the error cleared, the TPDOs
    /// on.
    pub(super) fn configured<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
    ) {
        self.link = Link::Ready;
        let config = device.pdo_config();
        // Bit n: PDO n is there and valid (the slots are PDO 0..3 in order).
        let mask = |slots: &[Option<PdoSlot>]| {
            slots.iter().rev().fold(0u8, |m, slot| {
                m << 1 | u8::from(slot.as_ref().is_some_and(PdoSlot::is_valid))
            })
        };
        let (tpdos, rpdos) = (mask(config.tpdos()), mask(config.rpdos()));
        device.push_event(ChargerEvent::Configured { tpdos, rpdos });
        if self.charge.control.alarms().is_empty() {
            device.clear_error(ErrorRegister::GENERIC);
        }
        device.set_tpdos_enabled(now, true);
        // The 6020h read gets its own attempts.
        self.attempts = 1;
        self.start_identification(device, now);
    }

    pub(super) fn on_upload_data(&mut self, offset: usize, data: InlineData<7>) {
        // Values read here are at most 4 bytes; keep them in the pending slot.
        if offset == 0 {
            self.upload_value = [0; 4];
        }
        for (i, b) in data.as_slice().iter().enumerate() {
            if let Some(slot) = self.upload_value.get_mut(offset + i) {
                *slot = *b;
            }
        }
    }

    pub(super) fn on_uploaded<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
    ) {
        let value = u32::from_le_bytes(self.upload_value);
        // One call of `next_pair`: the pair to look from and the device type.
        let (from, device_type) = match self.link {
            Link::DeviceType if value & 0xFFFF != 418 => {
                self.config_failed(device, now);
                device.push_event(ChargerEvent::NotABatteryModule { device_type: value });
                Self::raise(device, const { Alarm::of(DeltaQCode::CAN_CONFIGURATION) });
                return;
            }
            Link::DeviceType => (0, value),
            Link::CobId(i, device_type) => {
                if let Some(p) = PAIRS.get(usize::from(i)) {
                    let module = PdoCobId::from_u32(value);
                    let mine = PdoCobId::from_u32(module.to_u32() & !PdoCobId::NOT_VALID);
                    let (dir, n) = (p.charger_direction, p.charger_pdo);
                    device.update_pdos(now, |c| {
                        if let Some(slot) = c.get_mut(dir, n) {
                            slot.comm.cob_id = mine;
                        }
                    });
                }
                (i.saturating_add(1), device_type)
            }
            _ => return,
        };
        self.next_pair(device, now, from, device_type);
    }

    /// Starts reading the next pair the device type declares, or finishes.
    pub(super) fn next_pair<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        from: u8,
        dt: u32,
    ) {
        // Every charger PDO of `PAIRS` has its slot (`default_pdos` writes
        // all seven at every reset and none is ever removed).
        let mut i = from;
        while let Some(p) = PAIRS.get(usize::from(i)) {
            if p.is_declared(dt) {
                self.link = Link::CobId(i, dt);
                if self
                    .client
                    .start_upload(now, p.module_comm_index, 1)
                    .is_err()
                {
                    self.config_failed(device, now);
                }
                return;
            }
            i += 1;
        }
        self.configured(device, now);
    }

    /// A pairing request ended without an answer (`code`, the module's
    /// abort or our SDO timeout): a timeout is asked again while attempts
    /// are left; anything else fails the pairing with E-0-3-0.
    pub(super) fn pairing_aborted<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        index: u16,
        sub: u8,
        code: AbortCode,
    ) {
        if code == AbortCode::SdoProtocolTimedOut && self.attempts < ATTEMPTS {
            self.attempts += 1;
            // The client's abort frame goes out before the new request
            // (the client holds one frame).
            if let Some(abort) = self.client.poll_transmit() {
                device.send(abort);
            }
            match self.link {
                Link::CobId(i, device_type) => self.next_pair(device, now, i, device_type),
                _ => self.start_configuration(device, now),
            }
            return;
        }
        self.config_failed(device, now);
        device.push_event(ChargerEvent::ConfigurationFailed { index, sub, code });
        Self::raise(
            device,
            const { Alarm::of(DeltaQCode::BATTERY_MODULE_COMMUNICATION) },
        );
    }
}
