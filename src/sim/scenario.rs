//! The use cases of "Delta-Q IC Series CANopen interface specification rev
//! 2.0", section 7, as scripted sessions: each [`Scenario`] sets up a
//! [`Session`], makes the bus events of its use case happen at fixed
//! simulated times, and runs until its outcome shows. The program
//! `examples/charge_session.rs` runs them by name; `tests/sessions/charge_sessions.rs`
//! asserts what each one's bus shows.

use core::time::Duration;

use super::{PackError, Session, SessionConfig};
use crate::cia418::Chemistry;
use crate::clock::Timestamp;
use crate::deltaq::charge::{ChargePhase, AH_TARGET};
use crate::deltaq::{index, AlgorithmRequest, OperatingMode};

/// One use case of section 7.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scenario {
    /// A whole charge in local mode with a monitoring BMS: bulk,
    /// absorption, rest, float (section 7.1.1).
    NormalLocal,
    /// A whole charge in remote mode: the BMS asks constant current, then
    /// the tapering current, then says not ready.
    NormalRemote,
    /// Local: the BMS sets 6000h to not ready at 20 min (section 7.1.3).
    Terminate6000h,
    /// Local: the BMS selects the float algorithm by 2241h at 20 min
    /// (section 7.1.2, "stop charge and float").
    CompleteFloat,
    /// Remote: at 10 min the BMS asks 10 A (6070h) and lowers the voltage
    /// request (2271h) by 2 V.
    ReduceCurrentVoltage,
    /// Local: the BMS is on the bus but not ready, and is lost at 5 s: the
    /// charger charges after its hold-off (section 7.1.4).
    BmsLostBefore,
    /// The BMS is lost at 10 min while charging (remote: the charge stops).
    BmsLostDuring,
    /// The bus is off from 5 to 6 min (a CAN bus error): the charger's
    /// controller goes bus-off and reports it.
    CanBusError,
    /// No BMS ever appears: local mode charges after the hold-off with its
    /// no-CAN algorithm; remote mode never charges.
    NeverCan,
    /// Local: the BMS selects another algorithm (12 A) at 10 min.
    ChangeAlgorithm,
    /// Local: the BMS sets a 20 Ah target (2250h, ours) at the start.
    AhTarget,
    /// Remote: the BMS is lost at 5 min and back 30 s later (section
    /// 7.1.7): the charger re-configures, clears its alarm and charges.
    CommunicationRestored,
    /// Remote: the BMS is on the bus and ready, the battery's leads are not
    /// connected until 2 min (section 7.1.8).
    BatteryUnplugged,
    /// Local: once the pack floats the BMS restarts the charge by 2241h
    /// (section 7.1.5).
    RestartCharge,
}

/// What a scenario may be run with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScenarioOptions {
    /// The operating mode (default: the scenario's own).
    pub mode: Option<OperatingMode>,
    /// State of charge at the start, 0..=1 (default 0.2).
    pub soc: f64,
    /// Capacity, Ah (default 100).
    pub capacity_ah: f64,
    /// Chemistry (default lead acid).
    pub chemistry: Chemistry,
}

impl Default for ScenarioOptions {
    fn default() -> Self {
        ScenarioOptions {
            mode: None,
            soc: 0.2,
            capacity_ah: 100.0,
            chemistry: Chemistry::LeadAcid,
        }
    }
}

const fn minutes(n: u64) -> Duration {
    Duration::from_secs(n * 60)
}

/// A whole charge runs at most this long.
const WHOLE_CHARGE: Duration = Duration::from_secs(16 * 3600);

impl Scenario {
    /// Every scenario.
    pub const ALL: [Scenario; 14] = [
        Scenario::NormalLocal,
        Scenario::NormalRemote,
        Scenario::Terminate6000h,
        Scenario::CompleteFloat,
        Scenario::ReduceCurrentVoltage,
        Scenario::BmsLostBefore,
        Scenario::BmsLostDuring,
        Scenario::CanBusError,
        Scenario::NeverCan,
        Scenario::ChangeAlgorithm,
        Scenario::AhTarget,
        Scenario::CommunicationRestored,
        Scenario::BatteryUnplugged,
        Scenario::RestartCharge,
    ];

    /// Its name on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Scenario::NormalLocal => "normal-local",
            Scenario::NormalRemote => "normal-remote",
            Scenario::Terminate6000h => "terminate-6000h",
            Scenario::CompleteFloat => "complete-float",
            Scenario::ReduceCurrentVoltage => "reduce-current-voltage",
            Scenario::BmsLostBefore => "bms-lost-before",
            Scenario::BmsLostDuring => "bms-lost-during",
            Scenario::CanBusError => "can-bus-error",
            Scenario::NeverCan => "never-can",
            Scenario::ChangeAlgorithm => "change-algorithm",
            Scenario::AhTarget => "ah-target",
            Scenario::CommunicationRestored => "communication-restored",
            Scenario::BatteryUnplugged => "battery-unplugged",
            Scenario::RestartCharge => "restart-charge",
        }
    }

    /// The scenario named `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Scenario> {
        Scenario::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The mode it runs in unless told otherwise.
    #[must_use]
    pub const fn default_mode(self) -> OperatingMode {
        match self {
            Scenario::NormalRemote
            | Scenario::ReduceCurrentVoltage
            | Scenario::BmsLostDuring
            | Scenario::CanBusError
            | Scenario::CommunicationRestored
            | Scenario::BatteryUnplugged => OperatingMode::Remote,
            _ => OperatingMode::Local,
        }
    }

    /// Runs it; the session is left at its end, for its log and result.
    pub fn run(self, options: &ScenarioOptions) -> Result<Session, PackError> {
        let mode = options.mode.unwrap_or(self.default_mode());
        let mut config =
            SessionConfig::new(mode, options.chemistry, options.capacity_ah, options.soc)?;
        let lithium = matches!(options.chemistry, Chemistry::LithiumIon);
        if matches!(self, Scenario::NeverCan) {
            config.module_on_can = false;
        }
        let mut s = Session::new(&config);
        match self {
            Scenario::BmsLostBefore => s.bms.hold = true,
            Scenario::BatteryUnplugged => s.stage.battery_connected = false,
            _ => {}
        }
        s.start();
        for step in self.script() {
            step.run(&mut s, lithium);
        }
        Ok(s)
    }
}

impl Scenario {
    /// Its bus events at their simulated times, after the session's start.
    fn script(self) -> &'static [Step] {
        use Step::{
            Algorithm, BatteryConnected, BusOff, CurrentLimit, Hold, LowerVoltage, Minutes,
            ModuleOnCan, Seconds, SetAhTarget, UntilFinished, UntilMs,
        };
        match self {
            Scenario::NormalLocal | Scenario::NeverCan | Scenario::NormalRemote => {
                &[UntilFinished, Minutes(5)]
            }
            Scenario::Terminate6000h => &[Minutes(20), Hold, Minutes(5)],
            Scenario::CompleteFloat => &[Minutes(20), Algorithm(Pick::Float), Minutes(10)],
            Scenario::ReduceCurrentVoltage => &[
                Minutes(10),
                CurrentLimit(10.0),
                LowerVoltage { mv: 2000 },
                Minutes(10),
            ],
            Scenario::BmsLostBefore => &[UntilMs(5000), ModuleOnCan(false), Minutes(10)],
            Scenario::BmsLostDuring => &[Minutes(10), ModuleOnCan(false), Minutes(2)],
            Scenario::CanBusError => &[Minutes(5), BusOff(60), Minutes(6)],
            Scenario::ChangeAlgorithm => &[Minutes(10), Algorithm(Pick::Other), Minutes(10)],
            Scenario::AhTarget => &[
                UntilMs(1000),
                SetAhTarget { ah: 20 },
                UntilFinished,
                Minutes(5),
            ],
            Scenario::CommunicationRestored => &[
                Minutes(5),
                ModuleOnCan(false),
                Seconds(30),
                ModuleOnCan(true),
                Minutes(5),
            ],
            Scenario::BatteryUnplugged => &[Minutes(2), BatteryConnected(true), Minutes(5)],
            Scenario::RestartCharge => &[
                UntilFinished,
                Minutes(5),
                Algorithm(Pick::Cycle),
                Minutes(5),
            ],
        }
    }
}

/// Which of the chemistry's charge algorithms the BMS asks for (2241h):
/// lead acid 1, 2, 3; lithium-ion 11, 13, 12.
#[derive(Debug, Clone, Copy)]
enum Pick {
    /// The normal charge cycle.
    Cycle,
    /// Another algorithm (12 A).
    Other,
    /// Float.
    Float,
}

/// One step of a scenario's script.
#[derive(Debug, Clone, Copy)]
enum Step {
    /// Runs the session this many minutes.
    Minutes(u64),
    /// Runs the session this many seconds.
    Seconds(u64),
    /// Runs the session until its clock reads this many milliseconds.
    UntilMs(u64),
    /// Runs the session until the charge is over ([`finished`]), a whole
    /// charge at most.
    UntilFinished,
    /// The BMS holds: 6000h not ready.
    Hold,
    /// The BMS asks for one of the chemistry's algorithms (2241h).
    Algorithm(Pick),
    /// The BMS asks for at most this current, A (6070h).
    CurrentLimit(f64),
    /// The BMS lowers its voltage request (2271h, 1/1024 V) below its
    /// constant voltage by `mv` millivolts.
    LowerVoltage {
        /// How far below, mV.
        mv: u32,
    },
    /// The battery module's node is on the bus, or off it.
    ModuleOnCan(bool),
    /// The bus is off (a CAN bus error) for this many seconds.
    BusOff(u64),
    /// The battery's leads are connected, or not.
    BatteryConnected(bool),
    /// The BMS sets an Ah target (2250h, ours: 1/8 Ah).
    SetAhTarget {
        /// The target, Ah.
        ah: u16,
    },
}

impl Step {
    /// Makes the step happen on `s` (`lithium`: the chemistry's algorithm
    /// numbers).
    fn run(self, s: &mut Session, lithium: bool) {
        let at = |s: &Session, d: Duration| s.now().add_duration(d);
        match self {
            Step::Minutes(n) => s.run_until(at(s, minutes(n))),
            Step::Seconds(n) => s.run_until(at(s, Duration::from_secs(n))),
            Step::UntilMs(ms) => s.run_until(Timestamp::from_millis(ms)),
            Step::UntilFinished => {
                let limit = at(s, WHOLE_CHARGE);
                s.run_while(limit, |s| !finished(s));
            }
            Step::Hold => s.bms.hold = true,
            Step::Algorithm(pick) => {
                let id = match (pick, lithium) {
                    (Pick::Cycle, false) => 1,
                    (Pick::Other, false) => 2,
                    (Pick::Float, false) => 3,
                    (Pick::Cycle, true) => 11,
                    (Pick::Other, true) => 13,
                    (Pick::Float, true) => 12,
                };
                let value = AlgorithmRequest::new(id).to_u32().to_le_bytes();
                s.write_charger(index::ALGORITHM_REQUEST, 0, &value);
            }
            Step::CurrentLimit(a) => s.bms.current_limit_a = Some(a),
            Step::LowerVoltage { mv } => {
                let lowered_mv = ((s.bms.cv_volts * 1000.0) as u32).saturating_sub(mv);
                let q10 = (u64::from(lowered_mv) * 1024 / 1000) as u32;
                s.write_charger(index::VOLTAGE_REQUEST, 0, &q10.to_le_bytes());
            }
            Step::ModuleOnCan(on) => s.set_module_on_can(on),
            Step::BusOff(n) => s.bus_off(Duration::from_secs(n)),
            Step::BatteryConnected(on) => s.set_battery_connected(on),
            Step::SetAhTarget { ah } => {
                s.write_charger(AH_TARGET, 0, &ah.saturating_mul(8).to_le_bytes())
            }
        }
    }
}

impl core::fmt::Display for Scenario {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// The charge is over: floating or complete (local; an Ah target's rest
/// leads to float or complete), or the BMS said it is done and the charger
/// stopped (remote);
/// a remote session without a BMS never charges, so it is over at once
/// after the hold-off a local one would wait.
fn finished(s: &Session) -> bool {
    let phase = s.phase();
    let Some(charger) = s.charger() else {
        return true;
    };
    match charger.charge_control().mode() {
        OperatingMode::Remote => {
            (s.bms.is_done() && phase == ChargePhase::Idle)
                || (!charger.heartbeat_consumer().is_alive(super::MODULE_NODE)
                    && s.now() > Timestamp::from_millis(60_000))
        }
        _ => matches!(phase, ChargePhase::Float | ChargePhase::Complete),
    }
}
