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
//!   so does a module EMCY outside 8xxxh (section 4.4.2). A terminated
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
//! - An Ah target ([`AH_TARGET`], ours: the documents name no object)
//!   ends bulk or absorption once the Ah returned reach it (section 7, "set
//!   Ah target").
//! - Losing the BMS while charging does not stop a local cycle (section
//!   7.1.4, "communication failure default"): the charger carries on with
//!   its own algorithm; the heartbeat-lost alarm is the charger's
//!   ([`Charger`](super::Charger)).
//!
//! **Local override** is local mode in which the BMS also limits the
//! current (6070h, as a limit) and asks for equalize or maintenance
//! (4201h bits 0 and 1) — application note 740-0024 is not public; these
//! are our reading. 2006h bits 7-6 say "external" while a BMS limit is
//! below the algorithm's value.
//!
//! **Monitoring** (section 3.1: "allow other CANopen devices to monitor the
//! charging parameters"): the charger runs its own cycle and takes no
//! command from the bus (6000h, 6070h, 2271h/2276h, 2241h, 4201h and the
//! module's EMCYs change nothing); no hold-off.
//!
//! ## Alarms
//!
//! Raised and cleared as [`ChargeEvent::Alarm`]; the charger sends them as
//! EMCYs. E-0-0-1 battery high voltage (the output above the algorithm's
//! threshold, or the charger's maximum in remote mode: the output goes off
//! until it is 2 % below), E-0-2-0 active algorithm not set, E-0-2-8
//! incompatible algorithm, E-0-2-9 CAN-bus communication error (the CAN
//! controller's error state, [`BusInputs::bus_error`]: remote mode stops,
//! local mode carries on without the bus), E-0-4-5 battery disconnected (a
//! BMS that says ready but no battery voltage on the output: section 7.1.8,
//! "CAN connected with battery unplugged").
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
//! use canopen_codec::Timestamp;
//! use core::time::Duration;
//!
//! use canopen_codec::deltaq::OperatingMode;
//! let mut c = ChargeControl::new(OperatingMode::Local, ChargeConfig::example());
//! let t = Timestamp::ZERO;
//! // AC on, a 48 V lead-acid pack on the output, no BMS on the bus.
//! c.handle_power_stage(t, PowerStage { ac_present: true, voltage_mv: 48_000, ..PowerStage::OFF });
//! assert_eq!(c.phase(), ChargePhase::HoldOff);
//! // The CAN hold-off passes: the no-CAN algorithm charges at its bulk current.
//! c.handle_timeout(t.add_duration(Duration::from_secs(10)));
//! assert_eq!(c.phase(), ChargePhase::Bulk);
//! assert_eq!(c.set_points().current_ma, 25_000);
//! ```

pub mod algorithm;

use core::time::Duration;

use super::AlgorithmRequest;
use super::{
    ChargeIndication, ChargeStatusFlags, ChargeType, DeltaQCode, DerateReasons,
    ExtendedChargeStatus, ExternalOverride, OperatingMode, OverrideSource, Reaction,
};
use crate::clock::{micros_of, Timestamp};
use crate::emcy::Emergency;
use crate::queue::EventQueue;
pub use algorithm::{AlgorithmKind, ChargeAlgorithm, EXAMPLE_ALGORITHMS};

/// 2250h, Ah target (U16, Q3 Ah as 6052h, FFFFh none), read-write,
/// PDO-mappable. **Ours**: the Delta-Q document lists "setting an Ah target"
/// (section 4.1) but names no object for it; 2250h is free in Delta-Q's
/// published object list.
pub const AH_TARGET: u16 = 0x2250;

/// 2251h, charge cycle elapsed time (U32, seconds), read-only,
/// PDO-mappable. **Ours**, like [`AH_TARGET`]: "reading charge cycle status
/// information" (section 4.1) without a named object.
pub const ELAPSED_TIME: u16 = 0x2251;

/// Absorption lasts at least this long before its end-current test (the
/// power stage's current settles after the change from bulk). Ours.
pub const ABSORPTION_MIN: Duration = Duration::from_secs(60);

/// The configuration of [`ChargeControl`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChargeConfig {
    /// The charger's algorithms (2241h selects among them by id).
    pub algorithms: &'static [ChargeAlgorithm],
    /// The permanent algorithm at power-on (None: E-0-2-0 until 2241h).
    pub permanent_algorithm: Option<u16>,
    /// Local mode without CAN after the hold-off: this algorithm (None: the
    /// active one).
    pub no_can_algorithm: Option<u16>,
    /// How long local mode waits for a BMS before charging on its own.
    pub can_hold_off: Duration,
    /// The rest (output off) between absorption and float or complete.
    pub rest: Duration,
    /// The charger's maximum output current, mA.
    pub max_current_ma: u32,
    /// The charger's maximum output voltage, mV; the voltage request starts here.
    pub max_voltage_mv: u32,
    /// The charger's maximum output power, W.
    pub max_power_w: u32,
    /// An output voltage at least this high means a battery is connected, mV.
    pub battery_detect_mv: u32,
    /// Charger temperature where derating starts, degC.
    pub derate_start_c: i16,
    /// Charger temperature where the current reaches zero, degC.
    pub derate_stop_c: i16,
}

impl ChargeConfig {
    /// Our 1.5 kW, 48 V example charger (the ICL1500's class: up to 25 A,
    /// 72 V) with [`EXAMPLE_ALGORITHMS`]: permanent
    /// algorithm 1 (flooded lead acid), no-CAN algorithm 1, a 10 s CAN
    /// hold-off, 60 s rest, battery detected from 12 V, derating from 70 to
    /// 90 degC.
    #[must_use]
    pub const fn example() -> Self {
        ChargeConfig {
            algorithms: &EXAMPLE_ALGORITHMS,
            permanent_algorithm: Some(1),
            no_can_algorithm: Some(1),
            can_hold_off: Duration::from_secs(10),
            rest: Duration::from_secs(60),
            max_current_ma: 25_000,
            max_voltage_mv: 72_000,
            max_power_w: 1500,
            battery_detect_mv: 12_000,
            derate_start_c: 70,
            derate_stop_c: 90,
        }
    }

    /// The algorithm `id` of the table.
    #[must_use]
    pub fn algorithm(&self, id: u16) -> Option<&'static ChargeAlgorithm> {
        self.algorithms.iter().find(|a| a.id == id)
    }
}

/// What the power stage measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PowerStage {
    /// AC (mains) present.
    pub ac_present: bool,
    /// Output (battery) voltage, mV.
    pub voltage_mv: u32,
    /// Output current, mA.
    pub current_ma: u32,
    /// The charger's temperature, degC.
    pub temperature_c: i16,
}

impl PowerStage {
    /// No AC, nothing on the output, 25 degC.
    pub const OFF: PowerStage = PowerStage {
        ac_present: false,
        voltage_mv: 0,
        current_ma: 0,
        temperature_c: 25,
    };
}

/// What the bus says (the charger's objects and its supervision).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BusInputs {
    /// The battery module's heartbeat is present.
    pub battery_present: bool,
    /// 6000h battery status (bit 0: ready to charge).
    pub battery_status: u8,
    /// 6070h charge current requested (1/16 A; FFFFh invalid).
    pub current_request: u16,
    /// The voltage request of 2271h / 2276h (the one written last), mV.
    pub voltage_request_mv: u32,
    /// 4201h external override.
    pub external_override: ExternalOverride,
    /// The Ah target ([`AH_TARGET`], Q3 Ah; FFFFh none).
    pub ah_target: u16,
    /// 6081h battery state of charge (%; FFh invalid).
    pub battery_soc: u8,
    /// The CAN controller reports a bus error (error passive or bus off).
    pub bus_error: bool,
}

impl BusInputs {
    /// Nothing on the bus: no module, no request, the voltage request at
    /// `max_voltage_mv`.
    #[must_use]
    pub const fn none(max_voltage_mv: u32) -> Self {
        BusInputs {
            battery_present: false,
            battery_status: 0,
            current_request: 0xFFFF,
            voltage_request_mv: max_voltage_mv,
            external_override: ExternalOverride::empty(),
            ah_target: 0xFFFF,
            battery_soc: 0xFF,
            bus_error: false,
        }
    }
}

/// The power stage's orders.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SetPoints {
    /// Output on.
    pub enabled: bool,
    /// Current limit, mA (0 when off).
    pub current_ma: u32,
    /// Voltage limit, mV (0 when off).
    pub voltage_mv: u32,
}

/// Where the charge stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ChargePhase {
    /// No charge: no AC, no battery, or (remote) a condition missing.
    Idle,
    /// Local mode: waiting the CAN hold-off for a BMS.
    HoldOff,
    /// Constant current.
    Bulk,
    /// Constant voltage; the current tapers.
    Absorption,
    /// Equalize (lead acid), at the algorithm's equalize voltage.
    Equalize,
    /// Output off between absorption and float or complete.
    Rest,
    /// Maintenance at the float voltage.
    Float,
    /// The cycle is complete; output off.
    Complete,
    /// Remote mode: delivering the BMS's request.
    Remote,
    /// The BMS (6000h) or a module EMCY ended the charge.
    Terminated,
}

impl ChargePhase {
    /// The phase in words.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ChargePhase::Idle => "idle",
            ChargePhase::HoldOff => "CAN hold-off",
            ChargePhase::Bulk => "bulk (constant current)",
            ChargePhase::Absorption => "absorption (constant voltage)",
            ChargePhase::Equalize => "equalize",
            ChargePhase::Rest => "rest",
            ChargePhase::Float => "float",
            ChargePhase::Complete => "complete",
            ChargePhase::Remote => "remote (BMS request)",
            ChargePhase::Terminated => "terminated",
        }
    }

    /// The phases in which the charger delivers current.
    #[must_use]
    pub const fn delivers(self) -> bool {
        matches!(
            self,
            ChargePhase::Bulk
                | ChargePhase::Absorption
                | ChargePhase::Equalize
                | ChargePhase::Float
                | ChargePhase::Remote
        )
    }
}

impl core::fmt::Display for ChargePhase {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

bitflags::bitflags! {
    /// The alarms [`ChargeControl`] raises (each a Delta-Q code).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct ChargeAlarms: u8 {
        /// E-0-0-1 battery high voltage.
        const HIGH_VOLTAGE = 1 << 0;
        /// E-0-2-0 active algorithm not set.
        const ALGORITHM_NOT_SET = 1 << 1;
        /// E-0-2-8 incompatible algorithm.
        const INCOMPATIBLE_ALGORITHM = 1 << 2;
        /// E-0-2-9 CAN-bus communication error.
        const BUS_ERROR = 1 << 3;
        /// E-0-4-5 battery disconnected.
        const BATTERY_DISCONNECTED = 1 << 4;
    }
}

impl ChargeAlarms {
    /// The Delta-Q code of a single alarm flag (section 4.4.1).
    #[must_use]
    pub fn code(self) -> DeltaQCode {
        if self == ChargeAlarms::HIGH_VOLTAGE {
            DeltaQCode::Alarm(1)
        } else if self == ChargeAlarms::ALGORITHM_NOT_SET {
            DeltaQCode::Alarm(20)
        } else if self == ChargeAlarms::INCOMPATIBLE_ALGORITHM {
            DeltaQCode::Alarm(28)
        } else if self == ChargeAlarms::BUS_ERROR {
            DeltaQCode::CAN_BUS_COMMUNICATION
        } else {
            DeltaQCode::BATTERY_DISCONNECTED
        }
    }
}

/// What [`ChargeControl`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ChargeEvent {
    /// The phase changed.
    Phase {
        /// Before.
        from: ChargePhase,
        /// Now.
        to: ChargePhase,
    },
    /// An alarm was raised (`active`) or cleared.
    Alarm {
        /// The alarm (one flag).
        alarm: ChargeAlarms,
        /// Raised or cleared.
        active: bool,
    },
}

/// The status objects, as the charger reports them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChargeStatus {
    /// 2006h extended charge status.
    pub extended: ExtendedChargeStatus,
    /// 6001h charger status (bit 0: delivering, able to charge).
    pub charger_status: u8,
    /// 2008h derate reasons.
    pub derate: DerateReasons,
    /// 6052h Ah returned during this charge (Q3 Ah).
    pub ah_returned: u16,
    /// 6080h charger state of charge (%; FFh unknown).
    pub charger_soc: u8,
    /// Time since the cycle started ([`ELAPSED_TIME`]).
    pub elapsed: Duration,
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

/// The charger's charge logic (see the module docs). Inputs:
/// [`handle_power_stage`](Self::handle_power_stage),
/// [`handle_bus`](Self::handle_bus),
/// [`request_algorithm`](Self::request_algorithm),
/// [`handle_battery_emcy`](Self::handle_battery_emcy),
/// [`handle_timeout`](Self::handle_timeout); outputs:
/// [`set_points`](Self::set_points), [`status`](Self::status),
/// [`phase`](Self::phase), [`poll_event`](Self::poll_event) and
/// [`poll_timeout`](Self::poll_timeout). After any input, poll the events
/// until `None`; an undrained event queue changes nothing (oldest dropped
/// and counted).
#[derive(Debug, Clone)]
pub struct ChargeControl {
    mode: OperatingMode,
    config: ChargeConfig,
    phase: ChargePhase,
    phase_since: Timestamp,
    active: Option<u16>,
    permanent: Option<u16>,
    revert_on_ac_loss: bool,
    incompatible: bool,
    alarms: ChargeAlarms,
    bus: BusInputs,
    stage: PowerStage,
    hold_off_until: Option<Timestamp>,
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
    events: EventQueue<ChargeEvent, 4>,
}

/// mA x ms in one Q3 Ah (1/8 Ah = 450 C).
const Q3_MILLIAMP_MILLIS: u32 = 450_000_000;

/// A cycle's Ah (Q3, as 6052h) and seconds, counted in 32-bit steps (a
/// charger's controller divides 32-bit numbers in hardware, 64-bit ones
/// in a library routine).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct CycleMeter {
    q3: u32,
    /// Charge below one Q3 step, mA x ms.
    rest_mams: u32,
    /// Time below one millisecond (for the charge), us.
    rest_ms_us: u32,
    seconds: u32,
    /// Time below one second, us.
    rest_s_us: u32,
}

impl CycleMeter {
    /// `current_ma` flowed for `dt_us`. A gap over an hour between two
    /// inputs counts as an hour, a current over 1 048 A as that much (a
    /// clock jump or a wild reading cannot stall the count).
    fn add(&mut self, current_ma: u32, dt_us: u64) {
        let dt = dt_us.min(3_600_000_000) as u32;
        let us = self.rest_s_us + dt;
        self.seconds = self.seconds.saturating_add(us / 1_000_000);
        self.rest_s_us = us % 1_000_000;
        let us = self.rest_ms_us + dt;
        let mut ms = us / 1000;
        self.rest_ms_us = us % 1000;
        let i = current_ma.min(1 << 20);
        while ms > 0 {
            // 2047 ms x 2^20 mA plus the rest stays below 2^32.
            let chunk = ms.min(2047);
            ms -= chunk;
            let sum = self.rest_mams + i * chunk;
            self.q3 = self.q3.saturating_add(sum / Q3_MILLIAMP_MILLIS);
            self.rest_mams = sum % Q3_MILLIAMP_MILLIS;
        }
    }
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
            active: config.permanent_algorithm,
            permanent: config.permanent_algorithm,
            revert_on_ac_loss: false,
            incompatible: false,
            alarms: ChargeAlarms::empty(),
            bus: BusInputs::none(config.max_voltage_mv),
            stage: PowerStage::OFF,
            hold_off_until: None,
            was_ready: false,
            latch: Latch::None,
            temperature_fault: false,
            last_step: None,
            cycle: false,
            meter: CycleMeter {
                q3: 0,
                rest_mams: 0,
                rest_ms_us: 0,
                seconds: 0,
                rest_s_us: 0,
            },
            set: SetPoints {
                enabled: false,
                current_ma: 0,
                voltage_mv: 0,
            },
            derate: DerateReasons::empty(),
            external_limit: false,
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

    /// Time has passed.
    pub fn handle_timeout(&mut self, now: Timestamp) {
        self.integrate(now);
        self.step(now);
    }

    /// When the next timer (hold-off, absorption limit, equalize, rest)
    /// runs out.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Timestamp> {
        let since = |d: Duration| Some(self.phase_since.add_duration(d));
        match self.phase {
            ChargePhase::HoldOff => self.hold_off_until,
            ChargePhase::Absorption => self
                .algorithm()
                .and_then(|a| since(a.absorption_max.max(ABSORPTION_MIN))),
            ChargePhase::Equalize => self.algorithm().and_then(|a| since(a.equalize_time)),
            ChargePhase::Rest => since(self.config.rest),
            _ => None,
        }
    }

    /// The next event.
    #[must_use]
    pub fn poll_event(&mut self) -> Option<ChargeEvent> {
        self.events.pop()
    }

    /// Events dropped because the queue was full.
    #[must_use]
    pub fn events_dropped(&self) -> u64 {
        self.events.dropped()
    }

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
        flags.set(ChargeStatusFlags::AC_PRESENT, self.stage.ac_present);
        flags.set(ChargeStatusFlags::DERATING, !self.derate.is_empty());
        flags.set(ChargeStatusFlags::ALARM_ACTIVE, !self.alarms.is_empty());
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

    /// 6080h (ours): 100 % once complete or floating; in absorption 80 %
    /// plus the share of the taper done (up to 99 %); otherwise the
    /// module's 6081h when valid, else FFh.
    fn charger_soc(&self) -> u8 {
        match (self.phase, self.algorithm()) {
            (ChargePhase::Complete | ChargePhase::Float, _) => 100,
            (ChargePhase::Absorption, Some(a)) if a.bulk_ma > a.termination_ma => {
                let span = a.bulk_ma - a.termination_ma;
                let done = a.bulk_ma.saturating_sub(self.stage.current_ma).min(span);
                (80 + done * 19 / span) as u8
            }
            _ if self.bus.battery_soc <= 100 => self.bus.battery_soc,
            _ => 0xFF,
        }
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
        self.hold_off_until = None;
        self.enter(now, ChargePhase::Idle);
    }

    fn enter(&mut self, now: Timestamp, to: ChargePhase) {
        if self.phase != to {
            self.events.push(ChargeEvent::Phase {
                from: self.phase,
                to,
            });
            self.phase = to;
            self.phase_since = now;
        }
    }

    /// A new cycle's Ah and time from zero.
    fn restart_meter(&mut self) {
        self.cycle = true;
        self.meter = CycleMeter::default();
    }

    /// Starts a cycle with `id` (bulk, or float for a float algorithm).
    fn start(&mut self, now: Timestamp, id: Option<u16>) {
        let Some(a) = id.and_then(|id| self.config.algorithm(id)) else {
            return;
        };
        self.active = Some(a.id);
        self.hold_off_until = None;
        let to = match a.kind {
            AlgorithmKind::Cycle => ChargePhase::Bulk,
            AlgorithmKind::Float => ChargePhase::Float,
        };
        // A float algorithm completes the charge that ran: its Ah and
        // time go on; a cycle (or a float from nothing) starts afresh.
        if to == ChargePhase::Bulk || !self.cycle {
            self.restart_meter();
        }
        self.enter(now, to);
    }

    /// Applies every rule to the inputs as they stand.
    fn step(&mut self, now: Timestamp) {
        let mode = self.mode;
        let listens = !matches!(mode, OperatingMode::MonitoringOnly) && !self.bus.bus_error;
        let bms = listens && self.bus.battery_present;
        let ready = bms && self.bus.battery_status & 1 != 0;
        let detected = self.stage.voltage_mv >= self.config.battery_detect_mv;
        self.update_alarms(ready, detected);

        if !self.stage.ac_present {
            if self.phase != ChargePhase::Idle && self.revert_on_ac_loss {
                self.active = self.permanent;
            }
            self.latch = if matches!(self.latch, Latch::ShutDown) {
                Latch::ShutDown
            } else {
                Latch::None
            };
            self.end_cycle(now);
        } else if matches!(mode, OperatingMode::Remote) {
            self.step_remote(now, ready);
        } else {
            self.step_local(now, bms, ready, detected);
        }
        self.was_ready = ready;
        self.update_set_points(bms);
    }

    fn step_remote(&mut self, now: Timestamp, ready: bool) {
        let blocked = self
            .alarms
            .intersects(ChargeAlarms::HIGH_VOLTAGE | ChargeAlarms::BATTERY_DISCONNECTED);
        let to = if matches!(self.latch, Latch::ShutDown) {
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
        if !matches!(self.latch, Latch::None) {
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
                    self.hold_off_until = None;
                    if ready && self.active.is_some() {
                        self.start(now, self.active);
                    } else {
                        self.enter(now, P::Idle);
                    }
                } else if matches!(self.mode, OperatingMode::MonitoringOnly) {
                    self.start(now, self.active);
                } else {
                    let until = *self
                        .hold_off_until
                        .get_or_insert(now.add_duration(self.config.can_hold_off));
                    if now.has_reached(until) {
                        self.start(now, self.config.no_can_algorithm.or(self.active));
                    } else {
                        self.enter(now, P::HoldOff);
                    }
                }
            }
            _ if bms && self.was_ready && !ready => {
                // 6000h: the BMS ends the charge (section 7).
                self.latch = Latch::Terminated;
                self.enter(now, P::Terminated);
            }
            phase => self.advance(now, phase, bms),
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
                if self.stage.voltage_mv
                    >= a.absorption_mv
                        - a.absorption_mv / 1000 * algorithm::ABSORPTION_ENTRY_PERMILLE =>
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

    fn update_alarms(&mut self, ready: bool, detected: bool) {
        let threshold = match (self.mode, self.algorithm()) {
            (OperatingMode::Remote, _) | (_, None) => self.config.max_voltage_mv,
            (_, Some(a)) => a.high_voltage_mv,
        };
        let v = self.stage.voltage_mv;
        let high = v > threshold
            || (self.alarms.contains(ChargeAlarms::HIGH_VOLTAGE) && v > threshold - threshold / 50);
        let local = !matches!(self.mode, OperatingMode::Remote);
        let mut now = ChargeAlarms::empty();
        now.set(ChargeAlarms::HIGH_VOLTAGE, high);
        now.set(
            ChargeAlarms::ALGORITHM_NOT_SET,
            local && ready && self.active.is_none(),
        );
        now.set(ChargeAlarms::INCOMPATIBLE_ALGORITHM, self.incompatible);
        now.set(ChargeAlarms::BUS_ERROR, self.bus.bus_error);
        now.set(
            ChargeAlarms::BATTERY_DISCONNECTED,
            ready && !detected && self.stage.ac_present,
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

    fn update_set_points(&mut self, bms: bool) {
        use ChargePhase as P;
        let a = self.algorithm();
        let (mut current, mut voltage) = match (self.phase, a) {
            (P::Bulk | P::Absorption, Some(a)) => (a.bulk_ma, a.absorption_mv),
            (P::Equalize, Some(a)) => (a.bulk_ma / 10, a.equalize_mv),
            (P::Float, Some(a)) => (a.float_ma, a.float_mv),
            // 1/16 A per bit: 62.5 mA.
            (P::Remote, _) => (
                u32::from(self.bus.current_request) * 125 / 2,
                self.bus.voltage_request_mv,
            ),
            _ => (0, 0),
        };
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
        voltage = voltage.min(self.config.max_voltage_mv);

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
        let v = self.stage.voltage_mv.max(voltage / 2).clamp(1, 4_000_000);
        let milli_watts = c.max_power_w.saturating_mul(1000);
        let power_limit = (milli_watts / v).saturating_mul(1000) + milli_watts % v * 1000 / v;
        if current > power_limit {
            current = power_limit;
            derate |= DerateReasons::AC_CURRENT_LIMIT;
        }
        let stop = ChargeAlarms::HIGH_VOLTAGE | ChargeAlarms::BATTERY_DISCONNECTED;
        let enabled =
            self.phase.delivers() && !self.alarms.intersects(stop) && current > 0 && voltage > 0;
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

#[cfg(test)]
mod tests;
