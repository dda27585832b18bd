//! The charger asks the battery module for its battery: 6020h sub 1
//! (battery type), sub 2 (Ah capacity) and sub 4 (number of cells), CiA
//! 418 section 7.2.1, read by the charger's SDO client once the module is
//! found and the PDO pairing is done, in local, local override and remote
//! mode when no permanent algorithm is set. The charge control picks the
//! algorithm for the answer ([`crate::deltaq::charge::Identification`]).
//!
//! The Delta-Q IC Series CANopen interface specification is silent on the
//! charger reading 6020h; ours: in remote mode the BMS commands the set
//! points (section 3.1.1), but the alarms' thresholds are still "as set by
//! the algorithm profile in operation" (section 4.4.1, E-0-0-1 and
//! E-0-0-2) and section 7 runs its algorithm use cases in remote mode too,
//! so a remote charger asks as well: its protections fit the battery. In
//! monitoring mode the charger takes nothing from the bus (section 3.1)
//! and runs its configured algorithm, so it does not ask.
//!
//! A read the module aborts is [`ChargerEvent::IdentificationFailed`] at
//! once and the charger keeps its default (the module said no: asking
//! again would say no again). A read left unanswered (the SDO timeout) is
//! asked again from the sub-index it stopped at, [`ATTEMPTS`] reads in all
//! for one finding of the module, and then fails the same way: a local
//! start waits at most that many SDO timeouts. A charger that is NMT
//! stopped when it finds the module, or stopped during the read, has no
//! SDO (CiA 301 section 7.3.2.2): the question waits and the read starts
//! (again) on its next transition into pre-operational or operational. A
//! module found again (its heartbeat back after a loss, or its boot-up)
//! is asked afresh.

use super::{sdo_allowed, ChargerDevice, ChargerEvent, ChargerProfile};
use crate::abort::AbortCode;
use crate::cia418::BATTERY_PARAMETERS;
use crate::clock::Timestamp;
use crate::deltaq::charge::{BatteryIdentity, Identification};
use crate::deltaq::{AlgorithmRequest, OperatingMode};
use crate::machine::Machine;

/// 6020h sub-indexes read, in order: battery type, Ah capacity, cells.
const SUBS: [u8; 3] = [1, 2, 4];

/// Reads of 6020h for one finding of the module: the first and two more
/// after SDO timeouts (ours).
pub(super) const ATTEMPTS: u8 = 3;

impl ChargerProfile {
    /// This charger asks the module for its battery: any mode but
    /// monitoring, no permanent algorithm.
    fn identifies(&self) -> bool {
        !matches!(self.mode, OperatingMode::MonitoringOnly)
            && self.charge.control.permanent_algorithm().is_none()
    }

    /// The module was found: a charger that asks holds its cycle until
    /// the answer (the read starts once the pairing is done).
    pub(super) fn battery_heard<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
    ) {
        self.reading = None;
        self.attempts = 1;
        if self.identifies() {
            self.identified(device, now, Identification::Pending);
        }
    }

    /// The pairing is done, or the charger may use SDO again: the read
    /// starts if the charger waits for it and none runs (while NMT
    /// stopped it waits).
    pub(super) fn start_identification<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
    ) {
        let waits = matches!(
            self.charge.control.identification(),
            Identification::Pending
        );
        if !waits || self.reading.is_some() || !sdo_allowed(device) {
            return;
        }
        self.found = BatteryIdentity {
            battery_type: 0,
            capacity_ah: 0,
            cells: 0,
        };
        self.read_sub(device, now, 0);
    }

    /// The read of `sub` ended without an answer (`code`): after an SDO
    /// timeout it is asked again while attempts are left, else it failed.
    pub(super) fn read_failed<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        sub: u8,
        code: AbortCode,
    ) {
        match self.reading {
            Some(step) if code == AbortCode::SdoProtocolTimedOut && self.attempts < ATTEMPTS => {
                self.attempts += 1;
                // The client's abort frame goes out before the new request
                // (the client holds one frame).
                if let Some(abort) = self.client.poll_transmit() {
                    device.send(abort);
                }
                self.read_sub(device, now, step);
            }
            _ => self.identification_failed(device, now, sub, code),
        }
    }

    /// NMT stopped during the read (no SDO there): the question waits for
    /// pre-operational or operational.
    pub(super) fn read_interrupted(&mut self) {
        self.reading = None;
    }

    /// Starts reading `SUBS[i]`.
    fn read_sub<const Q: usize>(&mut self, device: &mut ChargerDevice<Q>, now: Timestamp, i: u8) {
        let sub = SUBS.get(usize::from(i)).copied().unwrap_or(1);
        self.reading = Some(i);
        if self
            .client
            .start_upload(now, BATTERY_PARAMETERS, sub)
            .is_err()
        {
            self.identification_failed(device, now, sub, AbortCode::GeneralError);
        }
    }

    /// An upload of 6020h completed (`self.reading` is the step).
    pub(super) fn on_parameter<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        step: u8,
    ) {
        let [lo, hi, ..] = self.upload_value;
        let word = u16::from_le_bytes([lo, hi]);
        match step {
            0 => self.found.battery_type = lo,
            1 => self.found.capacity_ah = word,
            _ => self.found.cells = word,
        }
        if usize::from(step) + 1 < SUBS.len() {
            self.read_sub(device, now, step + 1);
            return;
        }
        self.reading = None;
        let battery = self.found;
        self.identified(device, now, Identification::Known(battery));
        let algorithm = self.charge.control.active_algorithm();
        device.push_event(ChargerEvent::BatteryIdentified { battery, algorithm });
    }

    /// The module aborted the read of `sub` or did not answer (`code`).
    pub(super) fn identification_failed<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        sub: u8,
        code: AbortCode,
    ) {
        self.reading = None;
        device.push_event(ChargerEvent::IdentificationFailed { sub, code });
        self.identified(device, now, Identification::Failed);
    }

    /// The question is over without an answer (a failed pairing, an NMT
    /// stop): the default stands. A question not asked is left alone.
    pub(super) fn identification_dropped<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
    ) {
        self.reading = None;
        if matches!(
            self.charge.control.identification(),
            Identification::Pending
        ) {
            self.identified(device, now, Identification::Failed);
        }
    }

    /// Tells the charge control; an algorithm it chose for the battery
    /// (or its default after a failed read) reads back in 2241h (its id,
    /// no flags: not stored permanently).
    fn identified<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        id: Identification,
    ) {
        let before = self.charge.control.active_algorithm();
        self.charge.control.handle_identification(now, id);
        let after = self.charge.control.active_algorithm();
        if after != before {
            let shown = after.map_or(AlgorithmRequest::NO_VALUE, u32::from);
            self.charge.algorithm = shown;
            device.update(now, |o| o.algorithm_request = shown);
        }
        let linked = self.linked();
        self.charge.publish(device, now, linked);
    }
}
