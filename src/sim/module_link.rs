//! The battery module's side of a simulated pack: the objects a CiA 418
//! module reports from its pack and its BMS policy ([`publish`]), and, for
//! a module that runs without the charger's DC link in the same program
//! (a module on a pipe, the charger elsewhere), the charge the charger says
//! it has returned ([`ReturnedCharge`]).
//!
//! A CiA 418 module has no object for the charger's output current: what
//! reaches it over CAN is the charger's status (6001h), the Ah returned
//! during the current charge (6052h, 1/8 Ah) and the charger's state of
//! charge (6080h) (CiA 418 v1.0.1, 6.2.3-6.2.5, the RPDOs). So a module
//! that models its pack from the bus takes the charge from 6052h: each
//! increase goes into the pack, spread over the time since the last one;
//! a decrease is a new charge starting from zero. The resolution is 1/8 Ah,
//! so the state of charge of a 100 Ah pack moves in 0.125 % steps.

use super::{BmsRequest, Pack};
use crate::cia418::{
    BatteryObjects, BatteryStatus, BatteryVoltage, ChargeCurrentRequested, EighthAmpHours,
    StateOfCharge, Temperature,
};

/// Writes what the module reports from `pack` (carrying `current_a` into
/// the pack now) and from the BMS's `request`: 6000h bit 0, 6010h, 6060h,
/// 6070h and 6081h, each rounded to its own step.
pub fn publish(o: &mut BatteryObjects, pack: &Pack, current_a: f64, request: BmsRequest) {
    o.battery_status = if request.ready {
        BatteryStatus::READY_TO_CHARGE
    } else {
        BatteryStatus::empty()
    };
    let eighths = (pack.temperature_c() * 8.0)
        .round()
        .clamp(-32768.0, 32767.0);
    o.temperature = Temperature::from_raw(eighths as i16);
    let q10 = (pack.terminal_voltage(current_a).max(0.0) * 1024.0).round();
    o.battery_voltage = BatteryVoltage::from_raw(q10.min(f64::from(u32::MAX)) as u32);
    let sixteenths = (request.current_a * 16.0).round().clamp(0.0, 65534.0);
    o.charge_current_requested = ChargeCurrentRequested::from_raw(sixteenths as u16);
    let percent = (pack.soc() * 100.0).round().clamp(0.0, 100.0) as u8;
    o.battery_state_of_charge = StateOfCharge::new(percent).unwrap_or_default();
}

/// The charge the charger reports in 6052h, turned into the current that
/// flows into the pack (see the module docs): each increase is added to
/// what is still to flow, and flows at the rate the last increase came in
/// (its size over the time since the increase before), never more than
/// was reported.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ReturnedCharge {
    last: Option<EighthAmpHours>,
    last_rise_s: Option<f64>,
    pending_ah: f64,
    rate_a: f64,
    max_rate_a: f64,
}

/// No more than this flows by default, whatever the reports say (a
/// charger reporting a jump of kAh in a second is not followed into
/// absurd numbers), A.
const MAX_RATE_A: f64 = 10_000.0;

impl ReturnedCharge {
    /// Nothing reported yet.
    #[must_use]
    pub const fn new() -> Self {
        ReturnedCharge {
            last: None,
            last_rise_s: None,
            pending_ah: 0.0,
            rate_a: 0.0,
            max_rate_a: MAX_RATE_A,
        }
    }

    /// The same, flowing at most `amps` (a module's own bound: a report
    /// that bunches up, as when the module's steps stall and catch up, then
    /// flows over the next steps instead of as one spike of current).
    #[must_use]
    pub fn with_max_rate(amps: f64) -> Self {
        let mut r = Self::new();
        if amps > 0.0 {
            r.max_rate_a = amps.min(MAX_RATE_A);
        }
        r
    }

    /// Takes the 6052h value seen at `at_s` (simulated seconds); returns
    /// the Ah it adds. The first report is only the baseline (a charge in
    /// progress before the module listened is not the module's to add); a
    /// value below the last one starts a new charge: all of it is new.
    pub fn report(&mut self, at_s: f64, reported: EighthAmpHours) -> f64 {
        let added = match self.last {
            None => 0,
            Some(last) if reported.raw() >= last.raw() => reported.raw() - last.raw(),
            Some(_) => reported.raw(),
        };
        if self.last.is_none() {
            self.last_rise_s = Some(at_s);
        }
        self.last = Some(reported);
        let added_ah = f64::from(added) / 8.0;
        if added > 0 {
            if let Some(span) = self.last_rise_s.map(|t| at_s - t).filter(|s| *s > 0.0) {
                self.rate_a = (added_ah * 3600.0 / span).min(self.max_rate_a);
            } else if self.rate_a == 0.0 {
                // Two reports at one instant: all of it in the next step.
                self.rate_a = self.max_rate_a;
            }
            self.last_rise_s = Some(at_s);
            self.pending_ah += added_ah;
        }
        added_ah
    }

    /// The current into the pack for the next `dt_s` seconds, A.
    pub fn draw(&mut self, dt_s: f64) -> f64 {
        if dt_s <= 0.0 || self.pending_ah <= 0.0 {
            return 0.0;
        }
        let ah = (self.rate_a * dt_s / 3600.0).min(self.pending_ah);
        self.pending_ah -= ah;
        ah * 3600.0 / dt_s
    }

    /// Reported charge that has not flowed yet, Ah.
    #[must_use]
    pub const fn pending_ah(&self) -> f64 {
        self.pending_ah
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cia418::Chemistry;
    use crate::sim::{BmsPolicy, PackSpec};

    #[test]
    fn the_first_report_is_a_baseline_then_increases_add() {
        let mut r = ReturnedCharge::new();
        assert_eq!(r.report(0.0, EighthAmpHours::from_raw(80)), 0.0);
        assert_eq!(r.draw(1.0), 0.0);
        assert_eq!(r.report(1.0, EighthAmpHours::from_raw(80)), 0.0);
        assert_eq!(r.report(18.0, EighthAmpHours::from_raw(81)), 0.125);
        // 1/8 Ah in 18 s: 25 A, until the 1/8 Ah has flowed.
        assert!((r.draw(9.0) - 25.0).abs() < 1e-9);
        assert!((r.draw(9.0) - 25.0).abs() < 1e-9);
        assert!(r.draw(1.0).abs() < 1e-9);
        // A new charge: 6052h back to 3/8 Ah, all of it new, at the rate
        // over the time since the last rise.
        assert_eq!(r.report(36.0, EighthAmpHours::from_raw(3)), 0.375);
        let flowed: f64 = (0..100).map(|_| r.draw(1.0) / 3600.0).sum();
        assert!((flowed - 0.375).abs() < 1e-9, "{flowed}");
        assert_eq!(r.pending_ah(), 0.0);
    }

    #[test]
    fn a_bound_spreads_a_bunched_report() {
        let mut r = ReturnedCharge::with_max_rate(50.0);
        r.report(0.0, EighthAmpHours::from_raw(0));
        // 2 Ah reported 0.25 s after the baseline: 50 A until it has flowed.
        r.report(0.25, EighthAmpHours::from_raw(16));
        let mut flowed = 0.0;
        for _ in 0..144 {
            let i = r.draw(1.0);
            assert!(i <= 50.0 + 1e-9, "{i}");
            flowed += i / 3600.0;
        }
        assert!((flowed - 2.0).abs() < 1e-9, "{flowed}");
    }

    #[test]
    fn a_jump_flows_bounded_and_nothing_more_than_reported() {
        let mut r = ReturnedCharge::new();
        r.report(5.0, EighthAmpHours::from_raw(0));
        r.report(5.0, EighthAmpHours::MAX);
        assert_eq!(r.draw(1.0), MAX_RATE_A);
        let mut total = MAX_RATE_A / 3600.0;
        while r.pending_ah() > 0.0 {
            let i = r.draw(1.0);
            assert!(i <= MAX_RATE_A);
            total += i / 3600.0;
        }
        assert!((total - 65535.0 / 8.0).abs() < 1e-6, "{total}");
        assert_eq!(r.draw(0.0), 0.0);
    }

    #[test]
    fn published_objects_round_to_their_steps() {
        let spec = PackSpec::new(Chemistry::LeadAcid, 24, 100.0).unwrap();
        let pack = Pack::new(spec, 0.456);
        let mut bms = BmsPolicy::for_pack(&spec, 25.0);
        let request = bms.request(&pack);
        let mut o = BatteryObjects::default();
        publish(&mut o, &pack, 0.0, request);
        assert_eq!(o.battery_status, BatteryStatus::READY_TO_CHARGE);
        assert_eq!(o.battery_state_of_charge.percent(), Some(46));
        assert_eq!(o.charge_current_requested.raw(), 25 * 16);
        assert_eq!(o.temperature.raw(), 25 * 8);
        let volts = f64::from(o.battery_voltage.raw()) / 1024.0;
        assert!((volts - pack.rest_voltage()).abs() < 0.001, "{volts}");
        bms.hold = true;
        publish(&mut o, &pack, 0.0, bms.request(&pack));
        assert_eq!(o.battery_status, BatteryStatus::empty());
        assert_eq!(o.charge_current_requested.raw(), 0);
    }
}
