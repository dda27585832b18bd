//! What the charge control gives out besides its events: the power
//! stage's set points (with the derating of 2008h) and the status objects
//! (2006h, 6001h bit 0, 2008h, 6052h, 6080h, the elapsed time), from the
//! phase and the inputs as they stand (see the [module docs](super)).

use core::time::Duration;

use super::{ChargeAlarms, ChargeControl, ChargePhase, ChargeStatus, SetPoints};
use crate::deltaq::{
    ChargeIndication, ChargeStatusFlags, ChargeType, DerateReasons, ExtendedChargeStatus,
    OperatingMode, OverrideSource,
};

impl ChargeControl {
    /// The status objects.
    #[must_use]
    pub fn status(&self) -> ChargeStatus {
        use ChargePhase as P;
        let (charge_type, indication) = match self.phase {
            P::Bulk => (ChargeType::Normal, ChargeIndication::Below80),
            P::Absorption => {
                let finishing = self
                    .algorithm()
                    .is_some_and(|a| self.stage.current_ma <= a.termination_ma * 2);
                let indication = if finishing {
                    ChargeIndication::Finishing
                } else {
                    ChargeIndication::Above80
                };
                (ChargeType::Normal, indication)
            }
            P::Equalize => (ChargeType::Normal, ChargeIndication::Equalize),
            P::Rest => (ChargeType::Normal, ChargeIndication::Resting),
            P::Complete => (ChargeType::Normal, ChargeIndication::Complete),
            P::Float => (ChargeType::Maintenance, ChargeIndication::Complete),
            P::Idle | P::HoldOff | P::Remote | P::Terminated => {
                (ChargeType::None, ChargeIndication::Inactive)
            }
        };
        let external = self.external_limit || matches!(self.mode, OperatingMode::Remote);
        let mut flags = ChargeStatusFlags::empty();
        flags.set(ChargeStatusFlags::CHARGER_ENABLED, self.set.enabled);
        flags.set(ChargeStatusFlags::AC_PRESENT, self.ac_present());
        flags.set(ChargeStatusFlags::DERATING, !self.derate.is_empty());
        let faults = self.alarms.intersection(ChargeAlarms::FAULTS);
        flags.set(ChargeStatusFlags::ALARM_ACTIVE, self.alarms != faults);
        flags.set(ChargeStatusFlags::FAULT_ACTIVE, !faults.is_empty());
        flags.set(
            ChargeStatusFlags::HW_SHUTDOWN,
            self.alarms.intersects(ChargeAlarms::STOPS_OUTPUT),
        );
        let ah = self.meter.q3;
        ChargeStatus {
            extended: ExtendedChargeStatus {
                charge_type,
                indication,
                override_source: if external {
                    OverrideSource::External
                } else {
                    OverrideSource::Internal
                },
                flags,
            },
            charger_status: u8::from(self.set.enabled),
            derate: self.derate,
            // FFFFh is "no value": a cycle that returned more shows FFFEh.
            ah_returned: if self.cycle {
                ah.min(0xFFFE) as u16
            } else {
                0xFFFF
            },
            charger_soc: self.charger_soc(),
            elapsed: Duration::from_secs(self.meter.seconds as u64),
        }
    }

    /// 6080h, the charger's state of charge (ours; the Delta-Q IC Series
    /// CANopen interface specification gives the object, not how it is
    /// reckoned): 100 % once complete or floating; while a local cycle
    /// counts, the active algorithm's estimate
    /// ([`ChargeAlgorithm::estimate_soc`](super::ChargeAlgorithm::estimate_soc):
    /// the battery's voltage when the cycle started, the Ah delivered
    /// since times the chemistry's efficiency, over the capacity the
    /// module gave in 6020h sub 2), at most 99 %; otherwise the module's
    /// 6081h when valid, else FFh (unknown).
    fn charger_soc(&self) -> u8 {
        let local = !matches!(self.mode, OperatingMode::Remote);
        match (self.phase, self.algorithm()) {
            (ChargePhase::Complete | ChargePhase::Float, _) => 100,
            (_, Some(a)) if local && self.cycle && self.meter.start_mv > 0 => {
                a.estimate_soc(self.meter.start_mv, self.meter.q3, self.capacity_ah())
            }
            _ if self.bus.battery_soc <= 100 => self.bus.battery_soc,
            _ => 0xFF,
        }
    }
}

impl ChargeControl {
    /// The battery's temperature for the algorithm's temperature
    /// compensation ([`ChargeAlgorithm::compensated`](super::ChargeAlgorithm::compensated)), whole
    /// degC: the module's 6010h while a BMS is heard (`bms`) and has not
    /// reported its temperature sensor faulty (EMCY 5010h); otherwise
    /// none, and the algorithm's 25 degC voltages (ours: what a charger
    /// without a battery sensor does).
    pub(super) fn battery_c(&self, bms: bool) -> Option<i16> {
        (bms && !self.temperature_fault).then_some(self.bus.battery_temperature >> 3)
    }

    /// The set points of the phase, limited by the BMS, the charger's
    /// maxima, the derating and the power (see the module docs).
    pub(super) fn update_set_points(&mut self, bms: bool) {
        use ChargePhase as P;
        let a = self.algorithm();
        let (mut current, mut voltage) = match (self.phase, a) {
            (P::Bulk | P::Absorption, Some(a)) => (
                a.bulk_ma,
                a.compensated(a.absorption_mv, self.battery_c(bms)),
            ),
            (P::Equalize, Some(a)) => (
                a.bulk_ma / 10,
                a.compensated(a.equalize_mv, self.battery_c(bms)),
            ),
            (P::Float, Some(a)) => (a.float_ma, a.compensated(a.float_mv, self.battery_c(bms))),
            // 1/16 A per bit: 62.5 mA.
            (P::Remote, _) => (
                u32::from(self.bus.current_request) * 125 / 2,
                self.bus.voltage_request_mv,
            ),
            _ => (0, 0),
        };
        // Below the minimum voltage, bulk is a trickle (E-0-0-4).
        if let (P::Bulk, Some(a), Some(l)) = (self.phase, a, self.limits()) {
            if self.stage.battery_mv() < l.min_voltage_mv {
                current = a.bulk_ma / 10;
            }
        }
        let own = (current, voltage);
        if bms && !matches!(self.phase, P::Remote) {
            voltage = voltage.min(self.bus.voltage_request_mv);
            if matches!(self.mode, OperatingMode::LocalOverride)
                && self.bus.current_request != 0xFFFF
            {
                current = current.min(u32::from(self.bus.current_request) * 125 / 2);
            }
        }
        self.external_limit = (current, voltage) != own;
        current = current.min(self.config.max_current_ma);
        voltage = voltage
            .min(self.config.max_voltage_mv)
            .min(self.high_voltage_mv());

        let mut derate = DerateReasons::empty();
        let c = &self.config;
        let t = self.stage.temperature_c;
        if t > c.derate_start_c && current > 0 {
            // current x left / span in 32 bits (span at most 65 535).
            let span = (i32::from(c.derate_stop_c) - i32::from(c.derate_start_c)).max(1) as u32;
            let left = (i32::from(c.derate_stop_c) - i32::from(t)).clamp(0, span as i32) as u32;
            current = current / span * left + current % span * left / span;
            derate |= DerateReasons::TEMPERATURE;
        }
        if self.temperature_fault && current > 0 {
            current /= 2;
            derate |= DerateReasons::TEMPERATURE;
        }
        // The power at the output's voltage: W x 10^6 / mV = mA, in 32 bits
        // (the output at most 4 000 V).
        let v = self.stage.battery_mv().max(voltage / 2).clamp(1, 4_000_000);
        let milli_watts = c.max_power_w.saturating_mul(1000);
        let power_limit = (milli_watts / v)
            .saturating_mul(1000)
            .saturating_add(milli_watts % v * 1000 / v);
        if current > power_limit {
            current = power_limit;
            derate |= DerateReasons::AC_CURRENT_LIMIT;
        }
        // A BMS present and not ready holds a local cycle (paused for
        // the battery's temperature: E-0-0-8).
        let held = bms && !self.was_ready;
        let enabled = self.phase.delivers()
            && !self.alarms.intersects(ChargeAlarms::STOPS_OUTPUT)
            && !held
            && current > 0
            && voltage > 0;
        self.derate = if enabled {
            derate
        } else {
            DerateReasons::empty()
        };
        self.set = if enabled {
            SetPoints {
                enabled,
                current_ma: current,
                voltage_mv: voltage,
            }
        } else {
            SetPoints::default()
        };
    }
}
