//! The charger's power stage for simulation: a current- and
//! voltage-limited source into the pack, bounded by its output power, with
//! a charger temperature that follows its losses.
//!
//! Ours: the output current is the least of the current set point, what
//! holds the terminals at the voltage set point ([`Pack::current_at`]) and
//! the maximum power at the pack's rest voltage; the charger's temperature
//! goes first-order (time constant [`PowerStageModel::thermal_time_s`])
//! toward ambient plus 20 K per kW of losses (efficiency 92 %).
//!
//! What a bench drives on it: the AC input's voltage
//! ([`set_ac_voltage`](PowerStageModel::set_ac_voltage),
//! [`set_ac`](PowerStageModel::set_ac)), the battery's leads
//! ([`set_battery_connected`](PowerStageModel::set_battery_connected),
//! [`set_reverse_polarity`](PowerStageModel::set_reverse_polarity): the
//! terminals then read the pack's voltage negated and, as a real charger's
//! reverse-polarity protection does, the stage delivers nothing) and the
//! hardware faults its monitoring reports
//! ([`inject_fault`](PowerStageModel::inject_fault), F-0-0-1 to F-0-0-6 of
//! the Delta-Q IC Series CANopen interface specification rev 2.0, section
//! 4.4.1). An AC input outside the stage's working range (below
//! [`PowerStageModel::AC_WORKING_MIN_V`]) delivers nothing either.

use super::Pack;
use crate::deltaq::charge::{PowerStage, SetPoints, StageFaults};

/// The power stage's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerStageModel {
    /// AC (mains) input voltage, RMS, V (0: no AC).
    pub ac_voltage_v: f64,
    /// The battery's DC leads are connected.
    pub battery_connected: bool,
    /// The battery's leads are connected the wrong way round.
    pub reversed: bool,
    /// The hardware faults the stage reports (injected).
    pub faults: StageFaults,
    /// Maximum output power, W.
    pub max_power_w: f64,
    /// Efficiency, 0..1.
    pub efficiency: f64,
    /// Ambient temperature, degC.
    pub ambient_c: f64,
    /// The charger's thermal time constant, s.
    pub thermal_time_s: f64,
    /// The charger's temperature, degC.
    pub temperature_c: f64,
    /// The current delivered now, A.
    pub current_a: f64,
}

impl PowerStageModel {
    /// The AC input of a stage switched on, RMS, V.
    pub const AC_NOMINAL_V: f64 = 230.0;

    /// Below this AC input (RMS, V) the stage cannot work and delivers
    /// nothing (ours: a universal-input charger's stage drops out a little
    /// below its rated 85 VAC).
    pub const AC_WORKING_MIN_V: f64 = 80.0;

    /// A stage of `max_power_w`, AC on (230 V), battery connected the right
    /// way round, no fault, at 25 degC.
    #[must_use]
    pub const fn new(max_power_w: f64) -> Self {
        PowerStageModel {
            ac_voltage_v: Self::AC_NOMINAL_V,
            battery_connected: true,
            reversed: false,
            faults: StageFaults::empty(),
            max_power_w,
            efficiency: 0.92,
            ambient_c: 25.0,
            thermal_time_s: 600.0,
            temperature_c: 25.0,
            current_a: 0.0,
        }
    }

    /// Mains on (at [`AC_NOMINAL_V`](Self::AC_NOMINAL_V)) or off.
    pub fn set_ac(&mut self, on: bool) {
        self.ac_voltage_v = if on { Self::AC_NOMINAL_V } else { 0.0 };
    }

    /// The AC input is `volts` RMS (0: off; above 270 V the charger raises
    /// E-0-2-3, Delta-Q section 4.4.1).
    pub fn set_ac_voltage(&mut self, volts: f64) {
        self.ac_voltage_v = if volts.is_finite() {
            volts.max(0.0)
        } else {
            0.0
        };
    }

    /// AC is on at a voltage the stage works from.
    #[must_use]
    pub fn ac_present(&self) -> bool {
        self.ac_voltage_v >= Self::AC_WORKING_MIN_V
    }

    /// The battery's leads are connected (`true`) or unplugged.
    pub fn set_battery_connected(&mut self, on: bool) {
        self.battery_connected = on;
    }

    /// The battery's leads are connected the wrong way round (`true`) or
    /// the right way.
    pub fn set_reverse_polarity(&mut self, reversed: bool) {
        self.reversed = reversed;
    }

    /// The stage's monitoring reports `fault` (one or more flags) from now
    /// on (`true`) or no longer (`false`).
    pub fn inject_fault(&mut self, fault: StageFaults, on: bool) {
        self.faults.set(fault, on);
    }

    /// Sets the output for `set` into `pack` and runs `seconds` of heat.
    pub fn step(&mut self, seconds: f64, set: SetPoints, pack: &Pack) {
        let works = self.ac_present() && self.battery_connected && !self.reversed;
        self.current_a = if works && set.enabled {
            let held = pack.current_at(f64::from(set.voltage_mv) / 1000.0);
            let limit = f64::from(set.current_ma) / 1000.0;
            let power = self.max_power_w / pack.terminal_voltage(0.0).max(1.0);
            held.min(limit).min(power)
        } else {
            0.0
        };
        let out_w = self.current_a * pack.terminal_voltage(self.current_a);
        let loss_w = out_w * (1.0 / self.efficiency - 1.0);
        let target = self.ambient_c + loss_w * 0.02;
        let k = (seconds / self.thermal_time_s).min(1.0);
        self.temperature_c += (target - self.temperature_c) * k;
    }

    /// What the stage measures (what the charger's [`PowerStage`] input
    /// takes): no voltage without the battery's leads, a negative one with
    /// them reversed, the injected faults.
    #[must_use]
    pub fn measure(&self, pack: &Pack) -> PowerStage {
        let volts = match (self.battery_connected, self.reversed) {
            (false, _) => 0.0,
            (true, false) => pack.terminal_voltage(self.current_a),
            (true, true) => -pack.terminal_voltage(0.0),
        };
        PowerStage {
            ac_mv: (self.ac_voltage_v * 1000.0).round() as u32,
            voltage_mv: (volts * 1000.0).round() as i32,
            current_ma: (self.current_a * 1000.0).round() as u32,
            temperature_c: self.temperature_c.round() as i16,
            faults: self.faults,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cia418::Chemistry;
    use crate::sim::PackSpec;

    fn pack(soc: f64) -> Pack {
        Pack::new(PackSpec::new(Chemistry::LeadAcid, 24, 100.0).unwrap(), soc)
    }

    fn set(amps: u32, volts: u32) -> SetPoints {
        SetPoints {
            enabled: true,
            current_ma: amps * 1000,
            voltage_mv: volts * 1000,
        }
    }

    /// A 1.5 kW stage on the 24-cell, 100 Ah lead-acid pack at `soc`.
    fn stage(soc: f64) -> (PowerStageModel, Pack) {
        (PowerStageModel::new(1500.0), pack(soc))
    }

    /// One second asking 20 A up to 60 V: the current the stage gives, A.
    fn ask(s: &mut PowerStageModel, p: &Pack) -> f64 {
        s.step(1.0, set(20, 60), p);
        s.current_a
    }

    #[test]
    fn the_least_of_current_voltage_and_power() {
        let (mut s, p) = stage(0.2);
        assert!((ask(&mut s, &p) - 20.0).abs() < 1e-9, "current-limited");
        s.step(1.0, set(100, 60), &p);
        assert!(
            (s.current_a - 1500.0 / p.rest_voltage()).abs() < 1e-9,
            "power-limited"
        );
        let v = p.terminal_voltage(5.0);
        s.step(
            1.0,
            SetPoints {
                voltage_mv: (v * 1000.0) as u32,
                ..set(20, 0)
            },
            &p,
        );
        assert!(
            (s.current_a - 5.0).abs() < 0.01,
            "voltage-limited: {}",
            s.current_a
        );
    }

    #[test]
    fn nothing_without_ac_leads_or_enable() {
        let (mut s, p) = stage(0.5);
        s.set_ac(false);
        assert_eq!(ask(&mut s, &p), 0.0);
        assert_eq!(s.measure(&p).ac_mv, 0);
        s.set_ac_voltage(60.0);
        assert_eq!(ask(&mut s, &p), 0.0, "below the stage's working range");
        s.set_ac(true);
        s.battery_connected = false;
        s.step(1.0, set(20, 60), &p);
        assert_eq!(s.measure(&p).voltage_mv, 0);
        s.battery_connected = true;
        s.step(1.0, SetPoints::default(), &p);
        assert_eq!(s.current_a, 0.0);
        assert_eq!(
            s.measure(&p).voltage_mv,
            (p.rest_voltage() * 1000.0).round() as i32
        );
    }

    #[test]
    fn reversed_leads_read_negative_and_deliver_nothing() {
        let (mut s, p) = stage(0.5);
        s.set_reverse_polarity(true);
        assert_eq!(ask(&mut s, &p), 0.0);
        let m = s.measure(&p);
        assert_eq!(m.voltage_mv, -((p.rest_voltage() * 1000.0).round() as i32));
        assert_eq!(m.battery_mv(), 0);
        s.set_reverse_polarity(false);
        assert!(ask(&mut s, &p) > 0.0);
    }

    #[test]
    fn injected_faults_are_measured_until_cleared() {
        let (mut s, p) = stage(0.5);
        s.inject_fault(StageFaults::RELAY, true);
        s.inject_fault(StageFaults::OUTPUT_STAGE, true);
        assert_eq!(
            s.measure(&p).faults,
            StageFaults::RELAY | StageFaults::OUTPUT_STAGE
        );
        s.inject_fault(StageFaults::RELAY, false);
        assert_eq!(s.measure(&p).faults, StageFaults::OUTPUT_STAGE);
        s.set_ac_voltage(280.0);
        assert_eq!(s.measure(&p).ac_mv, 280_000);
    }

    #[test]
    fn the_charger_warms_with_its_losses() {
        let (mut s, p) = stage(0.2);
        for _ in 0..3600 {
            s.step(1.0, set(25, 60), &p);
        }
        // 1.2 kW out at 92 %: about 104 W lost, 2 K above ambient.
        assert!(
            s.temperature_c > 26.5 && s.temperature_c < 28.0,
            "{}",
            s.temperature_c
        );
    }
}
