//! A simple BMS policy for the simulated battery module: it asks for
//! constant current, then for the current that holds the pack at its
//! constant-voltage limit, and, when it ends the charge itself
//! ([`BmsPolicy::ends_charge`], remote mode), says "not ready" (6000h bit 0
//! clear) once that current has fallen below its end current. So the CV
//! taper and the end of charge emerge from the loop of module, charger and
//! pack.
//!
//! Ours (CiA 418 leaves the BMS's policy to the application): the CV limit
//! per cell is the absorption voltage of the battery type's charge figures
//! ([`figures_for`]: 2.45 V flooded lead acid, 1.50 V NiCd, 4.15 V lithium
//! ion, ...), compensated for the pack's temperature as a charger does
//! ([`CellFigures::compensation_uv`]); the end current is a twentieth of
//! the maximum; above 55 degC (lead acid) or 50 degC (the others) the
//! module is not ready: 5 degC above the charger's own charge range
//! ([`ProtectionLimits`](crate::deltaq::charge::ProtectionLimits): -20 to
//! 50 / 0 to 45 degC), so that a pack warming up meets the charger's
//! E-0-0-8 pause first and the BMS's cut only if that fails (with the same
//! 50 degC both, the module said "not ready" at 50.0 degC before the
//! charger's whole-degree reading passed 50, and the charger took it as
//! the BMS ending the charge: terminated without an alarm). Not ready
//! below 0 degC for lithium ion either (charging it there plates lithium),
//! nor below -20 degC for the others; after the end it asks again once the
//! state of charge falls below 95 %.

use super::{Pack, PackSpec};
use crate::cia418::Chemistry;
use crate::deltaq::charge::algorithm::figures_for;
#[cfg(doc)]
use crate::deltaq::charge::algorithm::CellFigures;

/// What the module asks of the charger.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BmsRequest {
    /// 6000h bit 0: ready to be charged.
    pub ready: bool,
    /// 6070h: the current to charge with, A.
    pub current_a: f64,
}

/// The BMS's settings and its one bit of state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BmsPolicy {
    /// The most it asks for (6020h sub 3), A.
    pub max_current_a: f64,
    /// Its constant-voltage limit for the pack at 25 degC, V.
    pub cv_volts: f64,
    /// How the limit moves per degC of the pack above 25 degC, V (taken
    /// within -20..=50 degC).
    pub compensation_v_per_c: f64,
    /// Below this the battery is not ready, degC.
    pub min_temperature_c: f64,
    /// Below this the charge is over, A.
    pub end_current_a: f64,
    /// Above this the battery is not ready, degC.
    pub max_temperature_c: f64,
    /// After the end, it asks again below this state of charge.
    pub resume_soc: f64,
    /// An extra limit the application sets (a BMS reducing the current), A.
    pub current_limit_a: Option<f64>,
    /// The application holds the battery not ready (a BMS ending the charge).
    pub hold: bool,
    /// It ends the charge itself at the end current (remote mode); a BMS
    /// that only monitors a local-mode charger (`false`) stays ready.
    pub ends_charge: bool,
    done: bool,
}

impl BmsPolicy {
    /// The policy for `spec` asking at most `max_current_a`.
    #[must_use]
    pub fn for_pack(spec: &PackSpec, max_current_a: f64) -> Self {
        let figures = figures_for(u8::from(spec.battery_type));
        let cells = f64::from(spec.cells);
        let (cell, compensation) = figures.map_or((2.45, 0.0), |f| {
            (
                f64::from(f.absorption_mv) / 1000.0,
                f64::from(f.compensation_uv) * 1e-6,
            )
        });
        BmsPolicy {
            max_current_a,
            cv_volts: cell * cells,
            compensation_v_per_c: compensation * cells,
            min_temperature_c: if spec.chemistry == Chemistry::LithiumIon {
                0.0
            } else {
                -20.0
            },
            end_current_a: max_current_a / 20.0,
            max_temperature_c: if spec.chemistry == Chemistry::LeadAcid {
                55.0
            } else {
                50.0
            },
            resume_soc: 0.95,
            current_limit_a: None,
            hold: false,
            ends_charge: true,
            done: false,
        }
    }

    /// True once the charge ended by the end current.
    #[must_use]
    pub const fn is_done(&self) -> bool {
        self.done
    }

    /// What to ask for, given the pack now.
    pub fn request(&mut self, pack: &Pack) -> BmsRequest {
        if self.done && pack.soc() < self.resume_soc {
            self.done = false;
        }
        let t = pack.temperature_c();
        let cv = self.cv_volts + self.compensation_v_per_c * (t.clamp(-20.0, 50.0) - 25.0);
        let wanted = pack
            .current_at(cv)
            .min(self.max_current_a)
            .min(self.current_limit_a.unwrap_or(f64::MAX));
        if !self.done && pack.current_at(cv) < self.end_current_a {
            self.done = true;
        }
        let over = self.done && self.ends_charge;
        let ready =
            !over && !self.hold && t <= self.max_temperature_c && t >= self.min_temperature_c;
        BmsRequest {
            ready,
            current_a: if ready { wanted } else { 0.0 },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_current_then_the_holding_current_then_done() {
        let spec = PackSpec::new(Chemistry::LeadAcid, 24, 100.0).unwrap();
        let mut bms = BmsPolicy::for_pack(&spec, 25.0);
        let mut pack = Pack::new(spec, 0.2);
        let r = bms.request(&pack);
        assert_eq!(
            r,
            BmsRequest {
                ready: true,
                current_a: 25.0
            }
        );
        let mut tapered = false;
        for _ in 0..20 * 3600 {
            let r = bms.request(&pack);
            if !r.ready {
                break;
            }
            tapered |= r.current_a < 24.0;
            pack.step(1.0, r.current_a);
        }
        assert!(tapered && bms.is_done());
        assert!(pack.soc() > 0.97, "{}", pack.soc());
        assert!(!bms.request(&pack).ready);
        // Discharged below the resume level: ready again.
        pack.step(3600.0, -10.0);
        assert!(bms.request(&pack).ready);
    }

    #[test]
    fn the_limit_is_the_types_absorption_compensated_for_temperature() {
        let nicd = PackSpec::new(Chemistry::NickelCadmium, 40, 100.0).unwrap();
        assert!((BmsPolicy::for_pack(&nicd, 25.0).cv_volts - 60.0).abs() < 1e-9);
        let spec = PackSpec::new(Chemistry::LeadAcid, 24, 100.0).unwrap();
        let mut bms = BmsPolicy::for_pack(&spec, 25.0);
        assert!((bms.cv_volts - 58.8).abs() < 1e-9);
        assert!((bms.compensation_v_per_c + 0.096).abs() < 1e-9);
        // Warm, the pack takes less at the limit than it would at 25 degC.
        let mut warm = Pack::new(spec, 0.99);
        warm.set_temperature_c(40.0);
        let asked = bms.request(&warm).current_a;
        assert!(asked < warm.current_at(58.8) * 0.8, "{asked}");
        assert!((asked - warm.current_at(58.8 - 0.096 * 15.0)).abs() < 1e-9);
        // -20 degC and below: not ready.
        warm.set_temperature_c(-21.0);
        assert!(!bms.request(&warm).ready);
    }

    #[test]
    fn hold_limit_and_temperature() {
        let spec = PackSpec::new(Chemistry::LithiumIon, 13, 50.0).unwrap();
        let mut bms = BmsPolicy::for_pack(&spec, 25.0);
        let pack = Pack::new(spec, 0.3);
        bms.current_limit_a = Some(10.0);
        assert_eq!(bms.request(&pack).current_a, 10.0);
        bms.hold = true;
        assert_eq!(
            bms.request(&pack),
            BmsRequest {
                ready: false,
                current_a: 0.0
            }
        );
        bms.hold = false;
        bms.max_temperature_c = 10.0;
        assert!(!bms.request(&pack).ready);
        // Lithium ion below freezing: not ready.
        bms.max_temperature_c = 50.0;
        let mut cold = pack;
        cold.set_temperature_c(-1.0);
        assert!(!bms.request(&cold).ready);
        cold.set_temperature_c(1.0);
        assert!(bms.request(&cold).ready);
        // A monitoring BMS stays ready after the end current.
        let mut full = Pack::new(spec, 1.0);
        let mut monitor = BmsPolicy::for_pack(&spec, 25.0);
        monitor.ends_charge = false;
        assert!(monitor.request(&full).ready && monitor.is_done());
        full.step(1.0, 0.0);
        assert!(!BmsPolicy::for_pack(&spec, 25.0).request(&full).ready);
    }
}
