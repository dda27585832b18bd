//! The charger's power stage for simulation: a current- and
//! voltage-limited source into the pack, bounded by its output power, with
//! a charger temperature that follows its losses.
//!
//! Ours: the output current is the least of the current set point, what
//! holds the terminals at the voltage set point ([`Pack::current_at`]) and
//! the maximum power at the pack's rest voltage; the charger's temperature
//! goes first-order (time constant [`PowerStageModel::thermal_time_s`])
//! toward ambient plus 20 K per kW of losses (efficiency 92 %).

use super::Pack;
use crate::deltaq::charge::{PowerStage, SetPoints};

/// The power stage's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerStageModel {
    /// AC (mains) present.
    pub ac_present: bool,
    /// The battery's DC leads are connected.
    pub battery_connected: bool,
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
    /// A stage of `max_power_w`, AC on, battery connected, at 25 degC.
    #[must_use]
    pub const fn new(max_power_w: f64) -> Self {
        PowerStageModel {
            ac_present: true,
            battery_connected: true,
            max_power_w,
            efficiency: 0.92,
            ambient_c: 25.0,
            thermal_time_s: 600.0,
            temperature_c: 25.0,
            current_a: 0.0,
        }
    }

    /// Sets the output for `set` into `pack` and runs `seconds` of heat.
    pub fn step(&mut self, seconds: f64, set: SetPoints, pack: &Pack) {
        self.current_a = if self.ac_present && self.battery_connected && set.enabled {
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
    /// takes): no voltage without the battery's leads.
    #[must_use]
    pub fn measure(&self, pack: &Pack) -> PowerStage {
        let volts = if self.battery_connected {
            pack.terminal_voltage(self.current_a)
        } else {
            0.0
        };
        PowerStage {
            ac_present: self.ac_present,
            voltage_mv: (volts * 1000.0).round() as u32,
            current_ma: (self.current_a * 1000.0).round() as u32,
            temperature_c: self.temperature_c.round() as i16,
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

    #[test]
    fn the_least_of_current_voltage_and_power() {
        let mut s = PowerStageModel::new(1500.0);
        let p = pack(0.2);
        s.step(1.0, set(20, 60), &p);
        assert!((s.current_a - 20.0).abs() < 1e-9, "current-limited");
        s.step(1.0, set(100, 60), &p);
        assert!(
            (s.current_a - 1500.0 / p.rest_voltage()).abs() < 1e-9,
            "power-limited"
        );
        let v = p.rest_voltage() + 0.144 * 5.0;
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
        let p = pack(0.5);
        let mut s = PowerStageModel::new(1500.0);
        s.ac_present = false;
        s.step(1.0, set(20, 60), &p);
        assert_eq!(s.current_a, 0.0);
        s.ac_present = true;
        s.battery_connected = false;
        s.step(1.0, set(20, 60), &p);
        assert_eq!(s.measure(&p).voltage_mv, 0);
        s.battery_connected = true;
        s.step(1.0, SetPoints::default(), &p);
        assert_eq!(s.current_a, 0.0);
        assert_eq!(
            s.measure(&p).voltage_mv,
            (p.rest_voltage() * 1000.0).round() as u32
        );
    }

    #[test]
    fn the_charger_warms_with_its_losses() {
        let p = pack(0.2);
        let mut s = PowerStageModel::new(1500.0);
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
