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
    /// The charger's CAN controller reports a bus error from 5 to 6 min.
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
        let (cycle, other, float) = if lithium { (11, 13, 12) } else { (1, 2, 3) };
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
        let at = |s: &Session, d: Duration| s.now().add_duration(d);
        let algorithm = |id: u16| AlgorithmRequest::new(id).to_u32().to_le_bytes();
        match self {
            Scenario::NormalLocal | Scenario::NeverCan | Scenario::NormalRemote => {
                let limit = at(&s, WHOLE_CHARGE);
                s.run_while(limit, |s| !finished(s));
                let end = at(&s, minutes(5));
                s.run_until(end);
            }
            Scenario::Terminate6000h => {
                s.run_until(at(&s, minutes(20)));
                s.bms.hold = true;
                s.run_until(at(&s, minutes(5)));
            }
            Scenario::CompleteFloat => {
                s.run_until(at(&s, minutes(20)));
                s.write_charger(index::ALGORITHM_REQUEST, 0, &algorithm(float));
                s.run_until(at(&s, minutes(10)));
            }
            Scenario::ReduceCurrentVoltage => {
                s.run_until(at(&s, minutes(10)));
                s.bms.current_limit_a = Some(10.0);
                let lowered_mv = (s.bms.cv_volts * 1000.0) as u32 - 2000;
                let q10 = (u64::from(lowered_mv) * 1024 / 1000) as u32;
                s.write_charger(index::VOLTAGE_REQUEST, 0, &q10.to_le_bytes());
                s.run_until(at(&s, minutes(10)));
            }
            Scenario::BmsLostBefore => {
                s.run_until(Timestamp::from_millis(5000));
                s.set_module_on_can(false);
                s.run_until(at(&s, minutes(10)));
            }
            Scenario::BmsLostDuring => {
                s.run_until(at(&s, minutes(10)));
                s.set_module_on_can(false);
                s.run_until(at(&s, minutes(2)));
            }
            Scenario::CanBusError => {
                s.run_until(at(&s, minutes(5)));
                s.set_bus_error(true);
                s.run_until(at(&s, minutes(1)));
                s.set_bus_error(false);
                s.run_until(at(&s, minutes(5)));
            }
            Scenario::ChangeAlgorithm => {
                s.run_until(at(&s, minutes(10)));
                s.write_charger(index::ALGORITHM_REQUEST, 0, &algorithm(other));
                s.run_until(at(&s, minutes(10)));
            }
            Scenario::AhTarget => {
                s.run_until(Timestamp::from_millis(1000));
                s.write_charger(AH_TARGET, 0, &(20u16 * 8).to_le_bytes());
                let limit = at(&s, WHOLE_CHARGE);
                s.run_while(limit, |s| !finished(s));
                s.run_until(at(&s, minutes(5)));
            }
            Scenario::CommunicationRestored => {
                s.run_until(at(&s, minutes(5)));
                s.set_module_on_can(false);
                s.run_until(at(&s, Duration::from_secs(30)));
                s.set_module_on_can(true);
                s.run_until(at(&s, minutes(5)));
            }
            Scenario::BatteryUnplugged => {
                s.run_until(at(&s, minutes(2)));
                s.set_battery_connected(true);
                s.run_until(at(&s, minutes(5)));
            }
            Scenario::RestartCharge => {
                let limit = at(&s, WHOLE_CHARGE);
                s.run_while(limit, |s| !finished(s));
                s.run_until(at(&s, minutes(5)));
                s.write_charger(index::ALGORITHM_REQUEST, 0, &algorithm(cycle));
                s.run_until(at(&s, minutes(5)));
            }
        }
        Ok(s)
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
