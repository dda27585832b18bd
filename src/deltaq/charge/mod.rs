//! The charger's own charge logic: [`ChargeControl`], a sans-IO machine
//! that turns what the bus says (the battery module's heartbeat, 6000h,
//! 6070h, 2271h / 2276h, 2241h, 4201h, the Ah target, EMCYs) and what the
//! power stage measures (AC present, output voltage and current,
//! temperature) into the power stage's current and voltage set points,
//! the charge phase, and every status object the charger reports (2006h,
//! 6001h bit 0, 2008h, 6052h, 6080h, the elapsed time) with the Delta-Q
//! alarms it raises.
//!
//! Sources: "Delta-Q IC Series CANopen interface specification rev 2.0",
//! section 3.1 (operating modes), section 4.1 (what the charger supports
//! beyond the standard: voltage set-point control, algorithm selection,
//! an Ah target, the sensed current, charge cycle status), section 4.4
//! (alarms, the EMCY consumer), section 5 (the objects) and section 7
//! (the use cases). The document leaves most behaviour to application
//! notes we do not have; every choice below is ours and says so.
//!
//! ## The rules, per operating mode
//!
//! **Remote** (section 3.1.1: "the charger requires the presence of an
//! external Battery Management System to start, stop and generally
//! control the charging process"): the charger delivers charge only while
//! *all* of these hold, and stops as soon as one does not:
//!
//! - the battery module's heartbeat is present (1016h supervision),
//! - 6000h bit 0 says the battery is ready,
//! - 6070h holds a valid current request (not FFFFh),
//! - AC is present, no CAN bus error, no shutdown by a module EMCY (section
//!   4.4.2: "the charger shall shutdown on receiving any error code"; ours:
//!   until the module sends its error reset, EEC 00xxh, or its heartbeat is
//!   lost and found again), no battery high-voltage or disconnected alarm.
//!
//! The current set point is the request, the voltage set point the voltage
//! request (2271h, or 2276h in 16 bits: whichever was written last), which
//! starts at the charger's maximum ([`ChargeConfig::max_voltage_mv`]).
//! The active algorithm runs no cycle in remote mode; it sets the
//! protections' thresholds (section 4.4.1: "as set by the algorithm
//! profile in operation"; until the module's 6020h answers, with no
//! algorithm, the high-voltage threshold is the charger's maximum). The
//! output does not wait for that answer: the BMS runs the charge.
//! 2006h shows charge type "none", indication "inactive" and override
//! "external" in remote mode: the BMS runs the cycle (what the real ICL1500
//! capture shows, 2006h = 0050h idle and 0070h while delivering).
//!
//! **Local** (section 3.1.2: "the charger normally has full control of the
//! charge cycle ... the BMS may override"): the charger runs the active
//! algorithm's cycle ([`algorithm`]). With AC present and a battery on the
//! output (its voltage at least [`ChargeConfig::battery_detect_mv`]):
//!
//! - a BMS present (heartbeat) that says ready (6000h bit 0) starts the
//!   cycle with the active algorithm (2241h, or the permanent one of the
//!   configuration); with none, E-0-2-0 "active algorithm not set" and no
//!   charge. A BMS present that says not ready holds the start.
//! - Without a BMS the charger waits the CAN hold-off time
//!   ([`ChargeConfig::can_hold_off`]; section 7's "local mode with CAN
//!   hold-off") and then charges with its no-CAN algorithm
//!   ([`ChargeConfig::no_can_algorithm`], "a different default algo if no
//!   CAN available"), or the active one.
//! - The voltage request (2271h / 2276h) is a limit in local mode (Delta-Q's
//!   object list: "limit in local mode, set-point in remote mode").
//! - 6000h falling to not ready while a cycle runs **terminates** it
//!   (section 7, "terminate charge via battery ready status object 6000h");
//!   so does a module EMCY outside 8xxxh while delivering or resting
//!   (section 4.4.2). A terminated
//!   cycle stays terminated, also when the BMS is lost afterwards (section
//!   7.1.6, "communication failure after charge termination"), until AC is
//!   lost, the battery is unplugged, or 2241h is written.
//! - Writing 2241h selects and restarts (section 7, "restart charge via set
//!   active algorithm", "change algorithm"); selecting a float algorithm
//!   completes the charge and floats the pack ("complete charge via set
//!   active algo to float 2241h"); an id the charger does not have raises
//!   E-0-2-8 "incompatible algorithm" and stops the charge until a valid
//!   one is written. Bit 31 (store permanently) makes it the permanent
//!   algorithm; bit 30 (revert after AC loss) goes back to the permanent
//!   one when AC is lost.
//! - An Ah target ([`AH_TARGET`], ours: the documents give no index) ends
//!   bulk or absorption once the Ah returned reach it, while the BMS is
//!   present (section 7, "set Ah target").
//! - Losing the BMS while charging does not stop a local cycle (section
//!   7.1.4, "communication failure default"): the charger carries on with
//!   its own algorithm; the heartbeat-lost alarm is the charger's
//!   ([`Charger`](super::Charger)).
//!
//! **Local override** is local mode in which the BMS also limits the
//! current (6070h, as a limit) and asks for equalize or maintenance
//! (4201h bits 0 and 1) — application note 740-0024 is not public; these
//! are our reading. In local and local override mode 2006h bits 7-6 say
//! "external" while a BMS limit (the voltage request, or 6070h in local
//! override) is below the algorithm's value.
//!
//! **Monitoring** (section 3.1: "allow other CANopen devices to monitor the
//! charging parameters"): the charger runs its own cycle and takes no
//! command from the bus (6000h, 6070h, 2271h/2276h, 2241h, 4201h and the
//! module's EMCYs change nothing); no hold-off; its active algorithm, or
//! with none its no-CAN algorithm (it is as a charger without CAN).
//!
//! ## Alarms
//!
//! Raised and cleared as [`ChargeEvent::Alarm`]; the charger sends them as
//! EMCYs. E-0-2-0 active algorithm not set, E-0-2-8 incompatible
//! algorithm, E-0-2-9 CAN-bus communication error (the CAN controller's
//! error state, [`BusInputs::bus_error`]: remote mode stops, local mode
//! carries on without the bus), E-0-4-5 battery disconnected (a BMS that
//! says ready but no battery voltage on the output: section 7.1.8, "CAN
//! connected with battery unplugged"), and the protections.
//!
//! ## Protections
//!
//! Every alarm of section 4.4.1 with a physical cause, raised from what
//! the charge control measures, with the active algorithm's thresholds
//! ([`ChargeAlgorithm::high_voltage_mv`], [`ProtectionLimits`]); the
//! document gives neither thresholds nor clearing, so both are ours. A
//! *latched* alarm ends the charge (terminated) until the cycle ends (AC
//! lost, battery unplugged, 2241h written; in remote mode also the BMS
//! saying not ready); the others hold the output off while their cause
//! stands ([`ChargeAlarms::STOPS_OUTPUT`]).
//!
//! - E-0-0-1 high voltage: the output at the algorithm's threshold
//!   (within 0.5 %) or above, in every mode (the voltage set point never exceeds it:
//!   a remote BMS asking more cannot push the pack past it); cleared 2 %
//!   below.
//! - E-0-0-2 low voltage (local): a battery below `low_voltage_mv`; no
//!   cycle starts.
//! - E-0-0-3 charge timeout (local, latched): bulk longer than
//!   `safety_time`.
//! - E-0-0-4 minimum voltage (local, latched): below `min_voltage_mv` bulk
//!   trickles at a tenth of its current; still below after `trickle_max`.
//! - E-0-0-7 Ah limit (latched): the cycle's Ah reach `ah_limit_q3`.
//!   With the capacity known from 6020h, neither the safety timer nor the
//!   Ah limit is tighter than a normal charge of that battery needs
//!   ([`ProtectionLimits::for_capacity`]).
//! - E-0-0-8 battery temperature (the module's 6010h, while present):
//!   outside the algorithm's range the charge **pauses** (phase kept,
//!   output off; the BMS's 6000h falling meanwhile does not terminate it)
//!   and resumes [`TEMPERATURE_HYSTERESIS_C`] back inside; a reading
//!   outside [`PLAUSIBLE_TEMPERATURE_C`] is no temperature and changes
//!   nothing.
//! - E-0-1-2 reverse polarity: the output reads negative.
//! - E-0-1-3 no current (latched): the output on, not voltage-limited,
//!   under a fiftieth of its set current for [`NO_CURRENT_TIME`].
//! - E-0-1-4 cells invalid (local, latched): a cycle about to start finds
//!   the battery at rest above `cells_max_mv`.
//! - E-0-2-3 high AC: above [`ChargeConfig::ac_max_mv`].
//! - E-0-2-5 low AC oscillation: [`AC_DROPS`] drop-outs within
//!   [`AC_WINDOW`]; cleared after AC stays up that long.
//! - E-0-3-6 temperature sensor: the module's EMCY 5010h (half current, as
//!   in derating below) until its error reset.
//! - F-0-0-1 to F-0-0-6: the power stage's [`PowerStage::faults`], while
//!   it reports them.
//!
//! ## Derating (2008h)
//!
//! Ours: the current falls linearly to zero between
//! [`ChargeConfig::derate_start_c`] and [`ChargeConfig::derate_stop_c`] of
//! the charger's temperature (reason "temperature"), is halved while the
//! module reports its temperature sensor fault (EEC 5010h, whose handling
//! section 4.4.2 refers to a missing section; reason "temperature"), and
//! is limited to the output power [`ChargeConfig::max_power_w`] (reason
//! "AC current limit": the charger's power is bounded by its AC input).
//!
//! ```
//! use canopen_codec::deltaq::charge::{BusInputs, ChargeConfig, ChargeControl, ChargePhase, PowerStage};
//! use canopen_codec::machine::Machine;
//! use canopen_codec::Timestamp;
//! use core::time::Duration;
//!
//! use canopen_codec::deltaq::OperatingMode;
//! let mut c = ChargeControl::new(OperatingMode::Local, ChargeConfig::example());
//! let t = Timestamp::ZERO;
//! // AC on, a 48 V lead-acid pack on the output, no BMS on the bus.
//! c.handle_power_stage(t, PowerStage { ac_mv: 230_000, voltage_mv: 48_000, ..PowerStage::OFF });
//! assert_eq!(c.phase(), ChargePhase::HoldOff);
//! // The CAN hold-off passes: the no-CAN algorithm charges at its bulk current.
//! c.handle_timeout(t.add_duration(Duration::from_secs(10)));
//! assert_eq!(c.phase(), ChargePhase::Bulk);
//! assert_eq!(c.set_points().current_ma, 25_000);
//! ```

pub mod algorithm;
mod identify;
mod meter;
mod outputs;
mod protect;
mod types;

use core::time::Duration;

use super::AlgorithmRequest;
use super::{DerateReasons, ExternalOverride, OperatingMode, Reaction};
use crate::clock::{micros_of, timer_kind, Timers, Timestamp};
use crate::emcy::Emergency;
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::queue::EventQueue;
pub use algorithm::{AlgorithmKind, ChargeAlgorithm, EXAMPLE_ALGORITHMS};
pub use identify::{BatteryIdentity, Identification};
use meter::CycleMeter;
use protect::ProtectState;
pub use protect::{
    ProtectionLimits, AC_DROPS, AC_WINDOW, CAPACITY_FACTOR_PERMILLE, NO_CURRENT_TIME,
    PLAUSIBLE_TEMPERATURE_C, TEMPERATURE_HYSTERESIS_C,
};
pub use types::{
    BusInputs, ChargeAlarms, ChargeConfig, ChargeEvent, ChargePhase, ChargeStatus, PowerStage,
    SetPoints, StageFaults, ALARM_CODES,
};

/// 2250h, Ah target (U16, Q3 Ah as 6052h, FFFFh none), read-write,
/// PDO-mappable. **Ours**: the Delta-Q document lists "setting an Ah target"
/// (section 4.1), and its revision history an "Ah return target object",
/// but gives no index for it; 2250h is free in Delta-Q's published object
/// list. Honoured in local and local override mode while the BMS is
/// present.
pub const AH_TARGET: u16 = 0x2250;

/// 2251h, charge cycle elapsed time (U32, seconds), read-only,
/// PDO-mappable. **Ours**, like [`AH_TARGET`]: "reading charge cycle status
/// information" (section 4.1). The document's revision history mentions an
/// "Elapsed Time signal (2005h)" that its text does not define (no type or
/// unit), so that index is not reused.
pub const ELAPSED_TIME: u16 = 0x2251;

/// Absorption lasts at least this long before its end-current test (the
/// power stage's current settles after the change from bulk). Ours.
pub const ABSORPTION_MIN: Duration = Duration::from_secs(60);

timer_kind! {
    /// The charge control's deadlines, each a slot of its timer table.
    enum ChargeTimer {
        /// The CAN hold-off ([`ChargeConfig::can_hold_off`], local mode
        /// without a BMS) runs out: the no-CAN algorithm starts.
        HoldOff,
        /// The timed phase running ends: absorption after its maximum
        /// (at least [`ABSORPTION_MIN`]), equalize after its time, rest
        /// after [`ChargeConfig::rest`] (one phase runs at a time).
        PhaseEnd,
    }
}

/// Why a charge was ended from outside.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Latch {
    None,
    /// Local: terminated (6000h or a module EMCY).
    Terminated,
    /// Remote: shut down by a module EMCY.
    ShutDown,
}

/// The charger's charge logic (see the module docs), a
/// [`Machine`] of the crate's contract with no
/// frames of its own. Inputs (commands):
/// [`handle_power_stage`](Self::handle_power_stage),
/// [`handle_bus`](Self::handle_bus),
/// [`request_algorithm`](Self::request_algorithm),
/// [`handle_battery_emcy`](Self::handle_battery_emcy), and the trait's
/// `handle_timeout`; outputs: [`set_points`](Self::set_points),
/// [`status`](Self::status), [`phase`](Self::phase), and the trait's
/// `poll_event` and `poll_timeout` (`poll_transmit` is always `None`).
/// After any input, poll the events until `None`; an undrained event
/// queue changes nothing (oldest dropped and counted).
#[derive(Debug, Clone)]
pub struct ChargeControl {
    mode: OperatingMode,
    config: ChargeConfig,
    phase: ChargePhase,
    phase_since: Timestamp,
    /// When the charge paused for the battery's temperature (E-0-0-8):
    /// the pause is not time spent in the phase.
    paused_since: Option<Timestamp>,
    active: Option<u16>,
    permanent: Option<u16>,
    revert_on_ac_loss: bool,
    incompatible: bool,
    alarms: ChargeAlarms,
    bus: BusInputs,
    stage: PowerStage,
    /// Its deadlines ([`ChargeTimer`]).
    timers: Timers<ChargeTimer, 2>,
    /// The CAN hold-off ran out with no BMS heard (until the cycle ends,
    /// a cycle starts or a BMS is heard).
    held_off: bool,
    /// The BMS said ready at the last step (6000h edge).
    was_ready: bool,
    latch: Latch,
    temperature_fault: bool,
    last_step: Option<Timestamp>,
    /// A cycle started (its Ah and time are counted, and kept after it).
    cycle: bool,
    meter: CycleMeter,
    set: SetPoints,
    derate: DerateReasons,
    external_limit: bool,
    /// The protections' state ([`protect`]).
    protect: ProtectState,
    /// The battery the module described ([`identify`]).
    identity: Identification,
    events: EventQueue<ChargeEvent, 4>,
}

impl ChargeControl {
    /// A charger in operating `mode` (section 3.1) at power-on: no AC,
    /// idle, the permanent algorithm active.
    #[must_use]
    pub const fn new(mode: OperatingMode, config: ChargeConfig) -> Self {
        ChargeControl {
            mode,
            config,
            phase: ChargePhase::Idle,
            phase_since: Timestamp::ZERO,
            paused_since: None,
            active: config.permanent_algorithm,
            permanent: config.permanent_algorithm,
            revert_on_ac_loss: false,
            incompatible: false,
            alarms: ChargeAlarms::empty(),
            bus: BusInputs::none(config.max_voltage_mv),
            stage: PowerStage::OFF,
            timers: Timers::new(),
            held_off: false,
            was_ready: false,
            latch: Latch::None,
            temperature_fault: false,
            last_step: None,
            cycle: false,
            meter: CycleMeter::ZERO,
            set: SetPoints {
                enabled: false,
                current_ma: 0,
                voltage_mv: 0,
            },
            derate: DerateReasons::empty(),
            external_limit: false,
            protect: ProtectState::NEW,
            identity: Identification::Unknown,
            events: EventQueue::new(ChargeEvent::Phase {
                from: ChargePhase::Idle,
                to: ChargePhase::Idle,
            }),
        }
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &ChargeConfig {
        &self.config
    }

    /// The operating mode.
    #[must_use]
    pub const fn mode(&self) -> OperatingMode {
        self.mode
    }

    /// The phase.
    #[must_use]
    pub const fn phase(&self) -> ChargePhase {
        self.phase
    }

    /// The power stage's set points.
    #[must_use]
    pub const fn set_points(&self) -> SetPoints {
        self.set
    }

    /// The active algorithm's id.
    #[must_use]
    pub const fn active_algorithm(&self) -> Option<u16> {
        self.active
    }

    /// The alarms now active.
    #[must_use]
    pub const fn alarms(&self) -> ChargeAlarms {
        self.alarms
    }

    /// The bus inputs last given.
    #[must_use]
    pub const fn bus(&self) -> &BusInputs {
        &self.bus
    }

    /// The power stage's measurements last given.
    #[must_use]
    pub const fn power_stage(&self) -> &PowerStage {
        &self.stage
    }

    /// AC is present: the measured input at least
    /// [`ChargeConfig::ac_min_mv`].
    #[must_use]
    pub const fn ac_present(&self) -> bool {
        self.stage.ac_mv >= self.config.ac_min_mv
    }

    /// The power stage measured `stage`.
    pub fn handle_power_stage(&mut self, now: Timestamp, stage: PowerStage) {
        self.integrate(now);
        self.stage = stage;
        self.step(now);
    }

    /// The bus inputs are now `bus`.
    pub fn handle_bus(&mut self, now: Timestamp, bus: BusInputs) {
        self.integrate(now);
        if !bus.battery_present && matches!(self.latch, Latch::ShutDown) {
            // Remote: a module lost and found again starts afresh.
            self.latch = Latch::None;
        }
        self.bus = bus;
        self.step(now);
    }

    /// 2241h was written (`None`: FFFFFFFFh, no request, ignored). Ignored
    /// in monitoring mode.
    pub fn request_algorithm(&mut self, now: Timestamp, request: Option<AlgorithmRequest>) {
        let Some(request) = request else { return };
        if matches!(self.mode, OperatingMode::MonitoringOnly) {
            return;
        }
        self.integrate(now);
        let id = request.algorithm;
        self.incompatible = self.config.algorithm(id).is_none();
        if !self.incompatible {
            self.active = Some(id);
            if request.store_permanently {
                self.permanent = Some(id);
            }
            self.revert_on_ac_loss = request.revert_after_ac_loss;
        }
        // Restart: the cycle begins again under the usual rules.
        self.latch = Latch::None;
        self.end_cycle(now);
        self.step(now);
    }

    /// The battery module sent `emcy` (the Delta-Q consumer policy of the
    /// mode decides; see the module docs).
    pub fn handle_battery_emcy(&mut self, now: Timestamp, emcy: &Emergency) {
        self.integrate(now);
        match super::emergency_reaction(self.mode, emcy) {
            Reaction::Continue if emcy.code.0 >> 8 == 0 => {
                // Error reset: the module's errors are gone.
                self.temperature_fault = false;
                if matches!(self.latch, Latch::ShutDown) {
                    self.latch = Latch::None;
                }
            }
            Reaction::Continue => {}
            Reaction::TemperatureSensorFault => self.temperature_fault = true,
            Reaction::ShutDown => self.latch = Latch::ShutDown,
            Reaction::TerminateCharging => {
                if self.phase.delivers() || matches!(self.phase, ChargePhase::Rest) {
                    self.latch = Latch::Terminated;
                }
            }
        }
        self.step(now);
    }

    fn algorithm(&self) -> Option<&'static ChargeAlgorithm> {
        self.active.and_then(|id| self.config.algorithm(id))
    }

    /// Adds the charge delivered since the last step.
    fn integrate(&mut self, now: Timestamp) {
        if let Some(last) = self.last_step {
            if self.cycle {
                let dt = now.saturating_micros_since(last);
                self.meter.add(self.stage.current_ma, dt);
            }
        }
        self.last_step = Some(now);
    }

    /// The cycle ends (AC lost, battery unplugged, restart): idle, the
    /// counters kept for reading until the next cycle starts.
    fn end_cycle(&mut self, now: Timestamp) {
        self.stop_hold_off();
        self.protect.tripped = ChargeAlarms::empty();
        self.enter(now, ChargePhase::Idle);
    }

    /// No hold-off runs or ran out.
    fn stop_hold_off(&mut self) {
        self.timers.set(ChargeTimer::HoldOff, None);
        self.held_off = false;
    }

    /// Enters `to` (if not in it) and arms the end of a timed phase.
    fn enter(&mut self, now: Timestamp, to: ChargePhase) {
        if self.phase != to {
            self.events.push(ChargeEvent::Phase {
                from: self.phase,
                to,
            });
            self.phase = to;
            self.phase_since = now;
            self.paused_since = None;
            let lasts = match to {
                ChargePhase::Absorption => self
                    .algorithm()
                    .map(|a| a.absorption_max.max(ABSORPTION_MIN)),
                ChargePhase::Equalize => self.algorithm().map(|a| a.equalize_time),
                ChargePhase::Rest => Some(self.config.rest),
                _ => None,
            };
            let end = lasts.map(|d| now.add_duration(d));
            self.timers.set(ChargeTimer::PhaseEnd, end);
        }
    }

    /// A new cycle's Ah and time from zero.
    fn restart_meter(&mut self) {
        self.cycle = true;
        self.meter = CycleMeter::from_rest(self.stage.battery_mv());
    }

    /// Starts a cycle with `id` (bulk, or float for a float algorithm).
    fn start(&mut self, now: Timestamp, id: Option<u16>) {
        let Some(a) = id.and_then(|id| self.config.algorithm(id)) else {
            return;
        };
        self.active = Some(a.id);
        self.stop_hold_off();
        let to = match a.kind {
            AlgorithmKind::Cycle => ChargePhase::Bulk,
            AlgorithmKind::Float => ChargePhase::Float,
        };
        if !self.cells_valid() {
            self.enter(now, ChargePhase::Terminated);
            return;
        }
        // A float algorithm completes the charge that ran: its Ah and
        // time go on; a cycle (or a float from nothing) starts afresh.
        if to == ChargePhase::Bulk || !self.cycle {
            self.restart_meter();
        }
        self.enter(now, to);
    }

    /// Applies every rule to the inputs as they stand, until the phase
    /// settles (a chain of zero-length phases runs through in one call, so
    /// no timer is ever left at or before `now`).
    fn step(&mut self, now: Timestamp) {
        // The timers due run out first (the rules below read the phase's
        // time themselves): a hold-off that ran out is remembered.
        if self.timers.expire(ChargeTimer::HoldOff, now) {
            self.held_off = true;
        }
        let _ = self.timers.expire(ChargeTimer::PhaseEnd, now);
        let mode = self.mode;
        let listens = !matches!(mode, OperatingMode::MonitoringOnly) && !self.bus.bus_error;
        let bms = listens && self.bus.battery_present;
        let ready = bms && self.bus.battery_status & 1 != 0;
        let detected = self.stage.battery_mv() >= self.config.battery_detect_mv;
        self.watch_ac(now);
        self.check_trips(now);
        self.clear_trips(ready, detected);
        // A phase chain is at most bulk, absorption, equalize, rest, float.
        for _ in 0..8 {
            let before = self.phase;
            self.update_alarms(bms, ready, detected);
            if !self.ac_present() {
                if self.phase != ChargePhase::Idle && self.revert_on_ac_loss {
                    self.active = self.permanent;
                }
                if !matches!(self.latch, Latch::ShutDown) {
                    self.latch = Latch::None;
                }
                self.end_cycle(now);
            } else if matches!(mode, OperatingMode::Remote) {
                self.step_remote(now, ready, detected);
            } else {
                self.step_local(now, bms, ready, detected);
            }
            if self.phase == before {
                break;
            }
        }
        self.was_ready = ready;
        self.update_set_points(bms);
    }

    fn step_remote(&mut self, now: Timestamp, ready: bool, detected: bool) {
        // No battery on the output: the charge that ran is over, and the
        // next one counts its Ah and time from zero (as in local mode).
        if !detected {
            self.cycle = false;
        }
        let blocked = self
            .alarms
            .intersects(ChargeAlarms::HIGH_VOLTAGE | ChargeAlarms::BATTERY_DISCONNECTED);
        let to = if matches!(self.latch, Latch::ShutDown) || !self.protect.tripped.is_empty() {
            ChargePhase::Terminated
        } else if ready && self.bus.current_request != 0xFFFF && !blocked {
            ChargePhase::Remote
        } else {
            ChargePhase::Idle
        };
        if to == ChargePhase::Remote && !self.cycle {
            self.restart_meter();
        }
        self.enter(now, to);
    }

    fn step_local(&mut self, now: Timestamp, bms: bool, ready: bool, detected: bool) {
        use ChargePhase as P;
        if !detected {
            // No battery on the output: whatever ran is over.
            self.latch = Latch::None;
            self.cycle = false;
            self.end_cycle(now);
            return;
        }
        if !matches!(self.latch, Latch::None) || !self.protect.tripped.is_empty() {
            self.enter(now, P::Terminated);
            return;
        }
        if self.incompatible {
            self.enter(now, P::Idle);
            return;
        }
        match self.phase {
            P::Idle | P::HoldOff | P::Terminated => {
                if bms {
                    self.stop_hold_off();
                    if self.alarms.contains(ChargeAlarms::LOW_VOLTAGE) {
                        self.enter(now, P::Idle);
                    } else if ready && self.active.is_some() && !self.identifying() {
                        self.start(now, self.active);
                    } else {
                        self.enter(now, P::Idle);
                    }
                } else if matches!(self.mode, OperatingMode::MonitoringOnly) {
                    // Nothing from the bus: its own algorithm, else its
                    // default without CAN.
                    if !self.alarms.contains(ChargeAlarms::LOW_VOLTAGE) {
                        self.start(now, self.active.or(self.config.no_can_algorithm));
                    }
                } else {
                    if !self.held_off && self.timers.get(ChargeTimer::HoldOff).is_none() {
                        let until = now.add_duration(self.config.can_hold_off);
                        self.timers.set(ChargeTimer::HoldOff, Some(until));
                    }
                    if self.timers.expire(ChargeTimer::HoldOff, now) {
                        self.held_off = true;
                    }
                    if !self.held_off {
                        self.enter(now, P::HoldOff);
                    } else if self.alarms.contains(ChargeAlarms::LOW_VOLTAGE) {
                        self.enter(now, P::Idle);
                    } else if self.no_can_algorithm().is_some() {
                        self.start(now, self.no_can_algorithm());
                    } else {
                        // Nothing to charge with: E-0-2-0, no timer left.
                        self.enter(now, P::Idle);
                    }
                }
            }
            // A BMS not ready for the battery's temperature pauses with
            // E-0-0-8 instead (the output stays off until it is ready).
            _ if bms
                && self.was_ready
                && !ready
                && !self.alarms.contains(ChargeAlarms::TEMPERATURE) =>
            {
                // 6000h: the BMS ends the charge (section 7).
                self.latch = Latch::Terminated;
                self.enter(now, P::Terminated);
            }
            // Paused for the battery's temperature (E-0-0-8): the phase is
            // kept as it is; its output is off, so the current it reads is
            // no sign of a full battery (absorption's termination current).
            _ if self.alarms.contains(ChargeAlarms::TEMPERATURE) => {
                self.paused_since.get_or_insert(now);
            }
            phase => {
                // Back from a pause: the phase's clock (absorption's limit,
                // the safety timer) counts the time it charged, not the pause.
                if let Some(at) = self.paused_since.take() {
                    let paused = now.saturating_micros_since(at);
                    self.phase_since = self.phase_since.add_micros(paused);
                }
                self.advance(now, phase, bms)
            }
        }
    }

    /// The cycle's own progress.
    fn advance(&mut self, now: Timestamp, phase: ChargePhase, bms: bool) {
        use ChargePhase as P;
        let Some(a) = self.algorithm() else { return };
        let in_phase = now.saturating_micros_since(self.phase_since);
        let ask = if bms && matches!(self.mode, OperatingMode::LocalOverride) {
            self.bus.external_override
        } else {
            ExternalOverride::empty()
        };
        let target = self.bus.ah_target;
        let target_reached = bms && target != 0xFFFF && self.meter.q3 >= u32::from(target);
        let can_equalize = a.equalize_mv > 0 && ask.contains(ExternalOverride::EQUALIZE);
        let next = match phase {
            P::Bulk | P::Absorption if target_reached => P::Rest,
            P::Bulk
                if self.stage.battery_mv() >= {
                    let mv = a.compensated(a.absorption_mv, self.battery_c(bms));
                    mv - mv / 1000 * algorithm::ABSORPTION_ENTRY_PERMILLE
                } =>
            {
                P::Absorption
            }
            P::Absorption
                if in_phase >= micros_of(ABSORPTION_MIN)
                    && (self.stage.current_ma <= a.termination_ma
                        || in_phase >= micros_of(a.absorption_max)) =>
            {
                if can_equalize {
                    P::Equalize
                } else {
                    P::Rest
                }
            }
            P::Equalize if in_phase >= micros_of(a.equalize_time) => P::Rest,
            P::Rest if in_phase >= micros_of(self.config.rest) => {
                if a.float_mv > 0 {
                    P::Float
                } else {
                    P::Complete
                }
            }
            P::Float | P::Complete if can_equalize => P::Equalize,
            P::Complete if a.float_mv > 0 && ask.contains(ExternalOverride::MAINTENANCE) => {
                P::Float
            }
            other => other,
        };
        self.enter(now, next);
    }

    fn update_alarms(&mut self, bms: bool, ready: bool, detected: bool) {
        let local = !matches!(self.mode, OperatingMode::Remote);
        let mut now = self.measured_alarms(bms, detected);
        let held_off = self.held_off;
        let nothing = (ready && self.active.is_none() && !self.identifying())
            || (held_off && !ready && self.no_can_algorithm().is_none());
        now.set(ChargeAlarms::ALGORITHM_NOT_SET, local && nothing);
        now.set(ChargeAlarms::INCOMPATIBLE_ALGORITHM, self.incompatible);
        now.set(ChargeAlarms::BUS_ERROR, self.bus.bus_error);
        now.set(
            ChargeAlarms::BATTERY_DISCONNECTED,
            ready && !detected && self.ac_present(),
        );
        let changed = now.symmetric_difference(self.alarms);
        for alarm in changed.iter() {
            self.events.push(ChargeEvent::Alarm {
                alarm,
                active: now.contains(alarm),
            });
        }
        self.alarms = now;
    }
}

/// The charge control is a machine of the crate's contract
/// ([`crate::machine`]) with no frames of its own: what it needs of the
/// bus comes decoded, as commands ([`handle_bus`](ChargeControl::handle_bus),
/// [`handle_battery_emcy`](ChargeControl::handle_battery_emcy),
/// [`request_algorithm`](ChargeControl::request_algorithm)), from its owner
/// that reads the objects and the battery module's supervision (the
/// [`Charger`](crate::deltaq::Charger)); the power stage's readings come
/// by [`handle_power_stage`](ChargeControl::handle_power_stage).
impl Machine for ChargeControl {
    type Event = ChargeEvent;

    /// Ignored: the bus inputs come decoded (see the impl's docs).
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        let _ = (now, frame);
    }

    /// Time has passed: the Ah returned count up to `now`, the timers due
    /// run out, and the rules apply (an early or repeated call changes
    /// nothing but the count).
    fn handle_timeout(&mut self, now: Timestamp) {
        self.integrate(now);
        self.step(now);
    }

    // When the next timer (the CAN hold-off, the end of the absorption,
    // equalize or rest phase) runs out.
    crate::machine::queued_outputs!(timers: timers, frames: none, events: events);
}

#[cfg(test)]
mod tests;

#[cfg(test)]
#[path = "timer_tests.rs"]
mod timer_tests;

#[cfg(test)]
#[path = "protect_tests.rs"]
mod protect_tests;
