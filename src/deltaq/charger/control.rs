//! The charger's charge control on its device core: the objects the bus
//! writes (6000h, 6070h, 2241h, 2271h / 2276h, 4201h, 2250h) and the
//! module's supervision go into [`ChargeControl`]; its status goes back
//! into the objects the TPDOs and the SDO server publish (2006h, 6001h bit
//! 0, 2008h, 6052h, 6080h, 2251h), the power stage's measurements into
//! 2002h, 2100h and 2101h, and its alarms onto the bus as Delta-Q EMCYs.
//! The rules are [`crate::deltaq::charge`]'s.

use super::{Alarm, ChargerDevice, ChargerEvent, ChargerProfile};
use crate::clock::Timestamp;
use crate::cob_id::NodeId;
use crate::deltaq::charge::{BusInputs, ChargeAlarms, ChargeConfig, ChargeControl, ALARM_CODES};
use crate::deltaq::{
    AlgorithmRequest, ChargerObjects, DeltaQCode, ExternalOverride, OperatingMode, VoltageRequest,
    VoltageRequest16,
};
use crate::emcy::{Emergency, ErrorRegister};
use crate::machine::Machine;

/// What the charger keeps to feed its [`ChargeControl`].
#[derive(Debug, Clone)]
pub(super) struct ControlLink {
    pub(super) control: ChargeControl,
    /// 2241h, 2271h and 2276h as last seen: what changed was written.
    pub(super) algorithm: u32,
    request_q10: u32,
    request_q8: u16,
    /// The voltage request of the one written last, mV.
    request_mv: u32,
    pub(super) bus_error: bool,
    /// The alarms whose EMCY has gone out.
    announced: ChargeAlarms,
}

/// Each alarm's Delta-Q code with the EEC of its table row, looked up
/// when the crate compiles (by bit, as [`ALARM_CODES`]).
const ALARMS: [Alarm; ALARM_CODES.len()] = {
    let mut out = [Alarm::of(DeltaQCode::NONE); ALARM_CODES.len()];
    let mut i = 0;
    while i < ALARM_CODES.len() {
        out[i] = Alarm::of(ALARM_CODES[i]);
        i += 1;
    }
    out
};

/// The alarm's Delta-Q code and EEC (a single flag; the lowest of several).
fn alarm(a: ChargeAlarms) -> Alarm {
    let bit = a.bits().trailing_zeros() as usize;
    ALARMS
        .get(bit)
        .copied()
        .unwrap_or(const { Alarm::of(DeltaQCode::NONE) })
}

/// `milli` thousandths in `q` (8 or 10) fractional bits, rounded, at
/// most FFFEh (FFFFh is "no value"): `milli x 2^q / 1000` as `milli x
/// 2^(q-3) / 125` in 32 bits.
fn q16(milli: u32, q: u32) -> u16 {
    let scaled = milli.min(4_000_000).saturating_mul(1 << (q - 3));
    ((scaled + 62) / 125).min(0xFFFE) as u16
}

/// Writes `value` into `field`; whether that changed it.
fn put<V: Copy + PartialEq>(field: &mut V, value: V) -> bool {
    core::mem::replace(field, value) != value
}

impl ControlLink {
    pub(super) const fn new(mode: OperatingMode, config: ChargeConfig) -> Self {
        ControlLink {
            control: ChargeControl::new(mode, config),
            algorithm: AlgorithmRequest::NO_VALUE,
            request_q10: u32::MAX,
            request_q8: u16::MAX,
            request_mv: config.max_voltage_mv,
            bus_error: false,
            announced: ChargeAlarms::empty(),
        }
    }

    /// At power-on the voltage requests hold the charger's maximum (the
    /// issue's reading of Delta-Q's 2271h: the BMS lowers it).
    pub(super) fn power_on_objects(&mut self, o: &mut ChargerObjects) {
        let max = self.control.config().max_voltage_mv;
        // Q10 and Q8 in 32 bits, as `q16` (at most 4 000 V).
        o.voltage_request = (max.min(4_000_000) * 128 + 62) / 125;
        o.voltage_request_q8 = q16(max, 8);
        self.request_q10 = o.voltage_request;
        self.request_q8 = o.voltage_request_q8;
        self.request_mv = max;
    }

    /// Gives the control what the objects and the supervision say now;
    /// `algorithm_written`: an SDO download to 2241h completed (a write of
    /// the same value restarts the cycle too).
    pub(super) fn sync<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        battery: NodeId,
        algorithm_written: bool,
        linked: bool,
    ) {
        let present = device.heartbeat_consumer().is_alive(battery);
        let o: &ChargerObjects = device.objects();
        let max = self.control.config().max_voltage_mv;
        if o.voltage_request != self.request_q10 {
            self.request_q10 = o.voltage_request;
            self.request_mv =
                VoltageRequest::from_raw(o.voltage_request).map_or(max, |v| v.millivolts());
        }
        if o.voltage_request_q8 != self.request_q8 {
            self.request_q8 = o.voltage_request_q8;
            self.request_mv =
                VoltageRequest16::from_raw(o.voltage_request_q8).map_or(max, |v| v.millivolts());
        }
        let bus = BusInputs {
            battery_present: present,
            battery_status: o.battery_status,
            current_request: o.current_requested,
            voltage_request_mv: self.request_mv,
            external_override: ExternalOverride::from_bits_retain(o.external_override),
            ah_target: o.ah_target,
            battery_soc: o.battery_soc,
            bus_error: self.bus_error,
            battery_temperature: o.temperature,
        };
        let algorithm = o.algorithm_request;
        if bus != *self.control.bus() {
            self.control.handle_bus(now, bus);
        }
        if algorithm_written || algorithm != self.algorithm {
            self.algorithm = algorithm;
            self.control
                .request_algorithm(now, AlgorithmRequest::from_u32(algorithm));
        }
        self.publish(device, now, linked);
    }

    /// The module's EMCY.
    pub(super) fn battery_emcy<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        emcy: &Emergency,
        linked: bool,
    ) {
        self.control.handle_battery_emcy(now, emcy);
        self.publish(device, now, linked);
    }

    /// Writes the status into the objects and sends the alarms: one EMCY
    /// a call (an alarm raised with others at once goes out on the next
    /// call, so a call adds at most one frame to the charger's queue); the
    /// error reset EMCY goes out when the last alarm clears and the module
    /// is `linked` (no heartbeat or configuration error of the charger's is
    /// left).
    pub(super) fn publish<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        linked: bool,
    ) {
        let status = self.control.status();
        let stage = *self.control.power_stage();
        // 2060h: the fault or alarm shown, as its 1003h entry (0 none).
        let shown = self.control.alarms().displayed();
        let displayed = if shown.is_empty() {
            0
        } else {
            let Alarm(code, eec) = alarm(shown);
            code.to_error_field(eec)
        };
        // Called on every input: most calls change nothing, and then the
        // TPDOs need not read the objects again.
        device.update_changed(now, |o| {
            let charger_status = o.charger_status & !1 | status.charger_status;
            let elapsed_s = u32::try_from(status.elapsed.as_secs()).unwrap_or(u32::MAX);
            put(&mut o.extended_status, status.extended.to_u16())
                | put(&mut o.charger_status, charger_status)
                | put(&mut o.derate_reasons, status.derate.bits())
                | put(&mut o.ah_returned, status.ah_returned)
                | put(&mut o.charger_soc, status.charger_soc)
                | put(&mut o.elapsed_s, elapsed_s)
                | put(&mut o.charging_current, q16(stage.current_ma, 8))
                | put(&mut o.battery_voltage_q8, q16(stage.battery_mv(), 8))
                | put(&mut o.battery_voltage_q10, q16(stage.battery_mv(), 10))
                | put(&mut o.ac_voltage, q16(stage.ac_mv, 4))
                | put(&mut o.displayed_error, displayed)
        });
        while let Some(e) = self.control.poll_event() {
            device.push_event(ChargerEvent::Charge(e));
        }
        let active = self.control.alarms();
        let gone = !self.announced.difference(active).is_empty();
        self.announced &= active;
        if let Some(a) = active.difference(self.announced).iter().next() {
            self.announced |= a;
            ChargerProfile::raise(device, alarm(a));
        } else if gone && active.is_empty() && linked {
            device.clear_error(ErrorRegister::GENERIC);
        }
    }
}
