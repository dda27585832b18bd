//! The charger's protections: each alarm of the Delta-Q alarm table with a
//! physical cause, raised by [`ChargeControl`] from what it measures
//! ("Delta-Q IC Series CANopen interface specification rev 2.0", section
//! 4.4.1, which names each alarm but gives neither its threshold nor its
//! clearing: every threshold and clearing here is **ours**, what an
//! industrial charger does, and the [module docs](super#protections) list
//! them).

use core::time::Duration;

use super::{ChargeAlarms, ChargeAlgorithm, ChargeControl, ChargePhase};
use crate::clock::{micros_of, Timestamp};
use crate::deltaq::OperatingMode;

/// The protection thresholds of one charge algorithm (ours: Delta-Q's
/// algorithm tables are not published). Whole-pack figures in mV, mA and
/// Q3 Ah (as 6052h).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ProtectionLimits {
    /// E-0-0-2 "battery low voltage": a battery on the output below this
    /// is not charged (deep discharge, or fewer cells than the algorithm).
    pub low_voltage_mv: u32,
    /// E-0-0-4 "battery could not meet minimum voltage": below this a
    /// cycle's bulk is a trickle (a tenth of the bulk current); the pack
    /// must reach it within [`trickle_max`](Self::trickle_max).
    pub min_voltage_mv: u32,
    /// How long the trickle may take.
    pub trickle_max: Duration,
    /// E-0-1-4 "number of cells invalid": a battery above this when a
    /// cycle starts (no current yet: its rest voltage) has more cells
    /// than the algorithm charges.
    pub cells_max_mv: u32,
    /// E-0-0-3 "charge timeout": bulk must reach the absorption voltage
    /// within this (the safety timer; a pack with shorted cells never
    /// does).
    pub safety_time: Duration,
    /// E-0-0-7 "battery amp-hour limit exceeded": the cycle's Ah (Q3 Ah)
    /// at most.
    pub ah_limit_q3: u32,
    /// E-0-0-8 "battery temperature out of range": the battery's
    /// temperature (the module's 6010h) from this, degC ...
    pub min_temperature_c: i16,
    /// ... to this, degC.
    pub max_temperature_c: i16,
}

impl ProtectionLimits {
    /// The limits of `a`, from its cell count and its chemistry's per-cell
    /// figures ([`CellFigures`](super::algorithm::CellFigures)); ours,
    /// each with its reason:
    ///
    /// - low voltage: half the empty cell's rest voltage (flooded lead
    ///   acid 0.97 V/cell, lithium ion 1.5 V/cell): a pack that low is
    ///   ruined or has fewer cells;
    /// - minimum voltage: 90 % of the empty cell's rest voltage (1.75 /
    ///   2.7 V/cell: an over-discharged pack, trickled first), within 1 h;
    /// - more cells: halfway between the full cell's rest voltage and the
    ///   high voltage (2.39 / 4.22 V/cell): no pack of the algorithm's
    ///   cell count rests that high;
    /// - safety timer: three times the absorption's maximum (12 h / 6 h);
    /// - Ah limit: what the bulk current delivers in the safety time
    ///   (both widened for a large battery whose capacity 6020h gives:
    ///   [`for_capacity`](Self::for_capacity));
    /// - temperature: -20 to 50 degC for lead acid, 0 to 45 degC for the
    ///   others (no lithium charge below freezing: plating; nickel cells
    ///   do not accept charge when cold; the cell makers' usual charge
    ///   ranges).
    #[must_use]
    pub const fn of(a: &ChargeAlgorithm) -> Self {
        let c = a.cell;
        let cells = a.cells;
        // In 32 bits: no 64-bit division in the firmware.
        let absorption_s = if a.absorption_max.as_secs() > u32::MAX as u64 {
            u32::MAX
        } else {
            a.absorption_max.as_secs() as u32
        };
        let safety = absorption_s.saturating_mul(3);
        // Q3 A (1/8 A is 125 mA) x whole hours.
        let hours = safety / 3600;
        let ah = (a.bulk_ma / 125).saturating_mul(hours);
        let lead_acid = c.battery_type >> 4 == 0b0001;
        let mid = c.rest_full_mv + c.high_mv.saturating_sub(c.rest_full_mv) / 2;
        ProtectionLimits {
            low_voltage_mv: cells.saturating_mul(c.rest_empty_mv / 2),
            min_voltage_mv: cells.saturating_mul(c.rest_empty_mv / 10 * 9),
            trickle_max: Duration::from_secs(3600),
            cells_max_mv: cells.saturating_mul(mid),
            safety_time: Duration::from_secs(safety as u64),
            ah_limit_q3: ah,
            min_temperature_c: if lead_acid { -20 } else { 0 },
            max_temperature_c: if lead_acid { 50 } else { 45 },
        }
    }

    /// These limits for a battery of `capacity_ah` (6020h sub 2; 0: not
    /// known, the limits unchanged) charged at `bulk_ma`: never tighter
    /// than a normal charge of that battery needs. From empty, a pack
    /// takes up to [`CAPACITY_FACTOR_PERMILLE`] of its capacity (lead
    /// acid's coulombic efficiency and gassing, nickel's 120-140 %), so the
    /// Ah limit is at least that and the safety timer at least the time
    /// the bulk current takes to deliver it: a 600 Ah pack on a 25 A
    /// charger is not timed out after 6 h, nor a 200 Ah pack cut at 150 Ah.
    /// Ours: the Delta-Q IC Series CANopen interface specification names
    /// E-0-0-3 and E-0-0-7 (section 4.4.1) without their figures.
    #[must_use]
    pub const fn for_capacity(self, capacity_ah: u32, bulk_ma: u32) -> Self {
        if capacity_ah == 0 {
            return self;
        }
        // Q3 Ah (8 a Ah) x per mille, in 32 bits: capacity at most 2^16.
        let capacity = if capacity_ah > 65_535 {
            65_535
        } else {
            capacity_ah
        };
        let need_q3 = capacity * 8 * CAPACITY_FACTOR_PERMILLE / 1000;
        // Whole hours of the bulk current (Q3 A), rounded up.
        let q3_a = if bulk_ma / 125 == 0 { 1 } else { bulk_ma / 125 };
        let need_s = need_q3.div_ceil(q3_a).saturating_mul(3600);
        let safety_s = self.safety_time.as_secs();
        ProtectionLimits {
            safety_time: if (need_s as u64) > safety_s {
                Duration::from_secs(need_s as u64)
            } else {
                self.safety_time
            },
            ah_limit_q3: if need_q3 > self.ah_limit_q3 {
                need_q3
            } else {
                self.ah_limit_q3
            },
            ..self
        }
    }
}

/// The most a normal charge from empty puts into a pack, per mille of its
/// capacity ([`ProtectionLimits::for_capacity`]): 150 %. Ours.
pub const CAPACITY_FACTOR_PERMILLE: u32 = 1500;

/// A delivering output whose current stays below a fiftieth of its set
/// point (not voltage-limited) this long raises E-0-1-3. Ours.
pub const NO_CURRENT_TIME: Duration = Duration::from_secs(60);

/// This many AC drop-outs within [`AC_WINDOW`] raise E-0-2-5 "low AC
/// voltage oscillation"; it clears once AC has stayed up for
/// [`AC_WINDOW`]. Ours.
pub const AC_DROPS: u8 = 3;

/// See [`AC_DROPS`].
pub const AC_WINDOW: Duration = Duration::from_secs(60);

/// The battery temperature must come back this far inside the range for
/// E-0-0-8 to clear (degC). Ours.
pub const TEMPERATURE_HYSTERESIS_C: i16 = 2;

/// The battery temperatures a reading of 6010h can be (degC, inclusive):
/// a battery sensor's measuring range (-40 to 125 degC, the usual NTC
/// range of a BMS). A reading outside is no temperature (a sensor fault,
/// or a PDO whose bytes at 6010h hold something else) and is ignored:
/// E-0-0-8 keeps its state, neither raised nor cleared by it, so an
/// implausible reading between plausible ones cannot make it flap. Ours.
pub const PLAUSIBLE_TEMPERATURE_C: (i16, i16) = (-40, 125);

/// The alarms a protection latched (cleared when the cycle ends: AC lost,
/// battery unplugged, 2241h written; in remote mode also when the BMS
/// says not ready).
pub(super) const LATCHING: ChargeAlarms = ChargeAlarms::CHARGE_TIMEOUT
    .union(ChargeAlarms::MINIMUM_VOLTAGE)
    .union(ChargeAlarms::AH_LIMIT)
    .union(ChargeAlarms::NO_CURRENT)
    .union(ChargeAlarms::CELLS_INVALID);

/// What the protections keep between steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct ProtectState {
    /// Latched alarms ([`LATCHING`]).
    pub(super) tripped: ChargeAlarms,
    /// Since when the output takes no current.
    no_current_since: Option<Timestamp>,
    /// AC was present at the last step.
    ac_was: bool,
    /// AC drop-outs in the window that starts at `ac_window`.
    ac_drops: u8,
    ac_window: Timestamp,
    /// Since when AC is up.
    ac_since: Timestamp,
    /// E-0-2-5 stands.
    oscillating: bool,
}

impl ProtectState {
    pub(super) const NEW: ProtectState = ProtectState {
        tripped: ChargeAlarms::empty(),
        no_current_since: None,
        ac_was: false,
        ac_drops: 0,
        ac_window: Timestamp::ZERO,
        ac_since: Timestamp::ZERO,
        oscillating: false,
    };
}

impl ChargeControl {
    /// The active algorithm's protection limits for the battery 6020h
    /// described (one copy of their arithmetic in the firmware).
    #[inline(never)]
    pub(super) fn limits(&self) -> Option<ProtectionLimits> {
        let capacity = self.capacity_ah();
        self.algorithm()
            .map(|a| ProtectionLimits::of(a).for_capacity(capacity, a.bulk_ma))
    }

    /// The E-0-0-1 threshold: the algorithm's high voltage, or the
    /// charger's maximum without an algorithm (also in remote mode: a BMS
    /// asking more must not push the pack past it).
    pub(super) fn high_voltage_mv(&self) -> u32 {
        self.algorithm()
            .map_or(self.config.max_voltage_mv, |a| a.high_voltage_mv)
    }

    /// Follows the AC input (E-0-2-5), before the rules.
    pub(super) fn watch_ac(&mut self, now: Timestamp) {
        let ac = self.ac_present();
        let p = &mut self.protect;
        if p.ac_was && !ac {
            if now.saturating_micros_since(p.ac_window) > micros_of(AC_WINDOW) {
                p.ac_window = now;
                p.ac_drops = 0;
            }
            p.ac_drops = p.ac_drops.saturating_add(1);
            if p.ac_drops >= AC_DROPS {
                p.oscillating = true;
            }
        }
        if ac && !p.ac_was {
            p.ac_since = now;
        }
        if ac && p.oscillating && now.saturating_micros_since(p.ac_since) >= micros_of(AC_WINDOW) {
            p.oscillating = false;
            p.ac_drops = 0;
        }
        p.ac_was = ac;
    }

    /// Trips the latching protections of a running cycle (before the
    /// rules, which then end the charge: phase terminated).
    pub(super) fn check_trips(&mut self, now: Timestamp) {
        use ChargePhase as P;
        let Some(l) = self.limits() else { return };
        let local = !matches!(self.mode, OperatingMode::Remote);
        let in_phase = now.saturating_micros_since(self.phase_since);
        let v = self.stage.battery_mv();
        let mut trip = ChargeAlarms::empty();
        if local && self.phase == P::Bulk {
            trip.set(
                ChargeAlarms::CHARGE_TIMEOUT,
                in_phase >= micros_of(l.safety_time),
            );
            trip.set(
                ChargeAlarms::MINIMUM_VOLTAGE,
                v < l.min_voltage_mv && in_phase >= micros_of(l.trickle_max),
            );
        }
        if self.cycle && self.phase.delivers() && self.meter.q3 >= l.ah_limit_q3 {
            trip |= ChargeAlarms::AH_LIMIT;
        }
        // No current: the output on and not voltage-limited.
        let set = self.set;
        let starved = set.enabled
            && set.current_ma > 0
            && self.stage.current_ma < set.current_ma / 50
            && v < set.voltage_mv - set.voltage_mv / 50;
        let p = &mut self.protect;
        if !starved {
            p.no_current_since = None;
        } else if let Some(since) = p.no_current_since {
            if now.saturating_micros_since(since) >= micros_of(NO_CURRENT_TIME) {
                trip |= ChargeAlarms::NO_CURRENT;
            }
        } else {
            p.no_current_since = Some(now);
        }
        p.tripped |= trip.intersection(LATCHING);
    }

    /// A cycle about to start from rest: E-0-1-4 when the battery's rest
    /// voltage says it has more cells than the algorithm. True when the
    /// start may go on.
    pub(super) fn cells_valid(&mut self) -> bool {
        let Some(l) = self.limits() else { return true };
        if self.stage.current_ma == 0 && self.stage.battery_mv() > l.cells_max_mv {
            self.protect.tripped |= ChargeAlarms::CELLS_INVALID;
            return false;
        }
        true
    }

    /// The alarms from the measurements as they stand (the latched ones
    /// included).
    pub(super) fn measured_alarms(&self, bms: bool, detected: bool) -> ChargeAlarms {
        let mut a = self.protect.tripped;
        let s = &self.stage;
        let threshold = self.high_voltage_mv();
        let v = s.battery_mv();
        // The set point stops at the threshold: reaching it (within
        // 0.5 %) is the alarm.
        let high = v >= threshold - threshold / 200
            || (self.alarms.contains(ChargeAlarms::HIGH_VOLTAGE) && v > threshold - threshold / 50);
        a.set(ChargeAlarms::HIGH_VOLTAGE, high);
        let local = !matches!(self.mode, OperatingMode::Remote);
        if let Some(l) = self.limits() {
            a.set(
                ChargeAlarms::LOW_VOLTAGE,
                local && detected && v < l.low_voltage_mv,
            );
            // 6010h in 1/8 degC, while the module reports it.
            let t = self.bus.battery_temperature >> 3;
            let was = self.alarms.contains(ChargeAlarms::TEMPERATURE);
            let margin = if was { TEMPERATURE_HYSTERESIS_C } else { 0 };
            let (lowest, highest) = PLAUSIBLE_TEMPERATURE_C;
            let out = if (lowest..=highest).contains(&t) {
                t < l.min_temperature_c.saturating_add(margin)
                    || t > l.max_temperature_c.saturating_sub(margin)
            } else {
                was
            };
            a.set(ChargeAlarms::TEMPERATURE, bms && out);
        }
        a.set(
            ChargeAlarms::REVERSE_POLARITY,
            s.voltage_mv < 0 && s.voltage_mv.unsigned_abs() >= self.config.battery_detect_mv,
        );
        a.set(ChargeAlarms::HIGH_AC, s.ac_mv > self.config.ac_max_mv);
        a.set(ChargeAlarms::AC_OSCILLATION, self.protect.oscillating);
        a.set(ChargeAlarms::TEMPERATURE_SENSOR, self.temperature_fault);
        a | ChargeAlarms::of_faults(s.faults)
    }

    /// A step's end: a latched alarm of a charge that is over (the battery
    /// unplugged, AC lost, or, in remote mode, the BMS no longer ready)
    /// clears.
    pub(super) fn clear_trips(&mut self, ready: bool, detected: bool) {
        let remote_done = matches!(self.mode, OperatingMode::Remote) && !ready;
        if !detected || !self.ac_present() || remote_done {
            self.protect.tripped = ChargeAlarms::empty();
            self.protect.no_current_since = None;
        }
    }
}
