//! The script of a bench run ([`Script`]): the charger's mode, the
//! battery, the bus, the timed actions, how long it runs and what must hold
//! at its end, read from a scenario file's [`Item`] tree.

use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::time::Duration;

use super::document::{Fields, Item, ScriptError, Value};
use crate::cia418::BatteryType;
use crate::deltaq::charge::{ChargePhase, StageFaults};
use crate::deltaq::{DeltaQCode, OperatingMode};
use crate::sim::PackSpec;

/// A bench run (see [the module docs](super) for the file format).
#[derive(Debug, Clone, PartialEq)]
pub struct Script {
    /// The charger's operating mode (`[charger] mode`).
    pub mode: OperatingMode,
    /// Its permanent algorithm (`[charger] algorithm`, an id of its
    /// table); none: it charges with the algorithm for the battery the
    /// module reports in 6020h.
    pub algorithm: Option<u16>,
    /// Its default without CAN (`[charger] no_can_algorithm`); none: the
    /// table's for the battery.
    pub no_can_algorithm: Option<u16>,
    /// The battery (`[battery]`).
    pub battery: Battery,
    /// The bus (`[bus]`; a perfect bus without it).
    pub bus: BusSetup,
    /// The actions at their simulated times (`[[event]]`), in time order
    /// (the file's order at the same time).
    pub events: Vec<TimedAction>,
    /// How long the run lasts (`[run] until`).
    pub until: Duration,
    /// What must hold at the end (`[expect]`).
    pub expect: Expect,
}

/// The battery at the start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Battery {
    /// Its 6020h battery type (by name: `flooded`, `agm`, `li-ion`, ..;
    /// [`BatteryType::from_name`]).
    pub battery_type: BatteryType,
    /// Cells in series.
    pub cells: u16,
    /// Capacity, Ah.
    pub capacity_ah: f64,
    /// State of charge at the start, percent.
    pub soc_percent: f64,
    /// Temperature at the start (and the room's), degC.
    pub temperature_c: f64,
}

/// The bus's imperfections at the start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BusSetup {
    /// The probability that a frame is lost.
    pub loss: f64,
    /// The time a frame takes to the other nodes.
    pub latency: Duration,
    /// The seed of the loss (the same seed loses the same frames).
    pub seed: u64,
}

/// An action at a simulated time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimedAction {
    /// When, from the start.
    pub at: Duration,
    /// What.
    pub action: Action,
    /// The line of its `[[event]]` in the file.
    pub line: u32,
}

/// What happens to the charger, the battery or the bus (the `action` of an
/// `[[event]]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    /// `ac-off`: mains lost at the charger.
    AcOff,
    /// `ac-on`: mains back.
    AcOn,
    /// `ac-voltage`: the mains voltage, V RMS.
    AcVoltage(f64),
    /// `bms-silent`: the battery module leaves the CAN bus.
    BmsSilent,
    /// `bms-back`: it is back.
    BmsBack,
    /// `bus-off`: the bus is off for this long (the charger's controller
    /// reports it).
    BusOff(Duration),
    /// `bus-loss`: from now each frame is lost with this probability.
    BusLoss(f64),
    /// `temperature`: the battery's temperature, degC (what 6010h reports).
    Temperature(f64),
    /// `unplug`: the battery's DC leads are disconnected.
    Unplug,
    /// `plug`: they are connected, the right way round.
    Plug,
    /// `reverse-polarity`: they are connected the wrong way round.
    ReversePolarity,
    /// `battery-status`: the module's 6000h (bit 0: ready to charge).
    BatteryStatus(u8),
    /// `request`: the BMS asks for a current (6070h) and/or a voltage
    /// (2271h).
    Request {
        /// A, if given.
        current_a: Option<f64>,
        /// V, if given.
        voltage_v: Option<f64>,
    },
    /// `ah-target`: the BMS sets an Ah target (2250h), Ah.
    AhTarget(f64),
    /// `algorithm`: the BMS selects a charge algorithm (2241h).
    Algorithm(u16),
    /// `bms-emcy`: the battery module sends this EMCY code.
    BmsEmcy(u16),
    /// `fault`: a hardware fault of the charger's power stage (F-0-0-1..6).
    Fault(StageFaults),
    /// `cell-short`: this many cells of the pack are shorted.
    CellShort(u16),
}

/// What must hold at the end of a run (every key optional).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Expect {
    /// `alarms`: exactly these are active at the end.
    pub alarms: Option<Vec<DeltaQCode>>,
    /// `raised`: each was raised at some time.
    pub raised: Vec<DeltaQCode>,
    /// `not_raised`: none of these was ever raised.
    pub not_raised: Vec<DeltaQCode>,
    /// `state`: the charge's state at the end.
    pub state: Option<ChargePhase>,
    /// `states`: the charge entered these, in this order (others between).
    pub states: Vec<ChargePhase>,
    /// `output`: the output is delivering current at the end (`"on"`) or
    /// not (`"off"`).
    pub output: Option<bool>,
    /// `ah_min`, `ah_max`: bounds of the charge delivered, Ah.
    pub ah: (Option<f64>, Option<f64>),
    /// `soc_min`, `soc_max`: bounds of the state of charge at the end, %.
    pub soc: (Option<f64>, Option<f64>),
    /// `voltage_max`: the battery's terminal voltage never went above
    /// this during the run, V.
    pub voltage_max: Option<f64>,
}

/// The longest run a file may ask for (`[run] until`): three days, longer
/// than any charge's safety timer; the session keeps its bus log in memory
/// (a few MB a simulated hour), so a far longer run would take minutes and
/// gigabytes for nothing a charge can show.
pub const MAX_RUN: Duration = Duration::from_secs(72 * 3600);

/// The actions' names in the file, in [`Action`]'s order.
pub const ACTIONS: [&str; 18] = [
    "ac-off",
    "ac-on",
    "ac-voltage",
    "bms-silent",
    "bms-back",
    "bus-off",
    "bus-loss",
    "temperature",
    "unplug",
    "plug",
    "reverse-polarity",
    "battery-status",
    "request",
    "ah-target",
    "algorithm",
    "bms-emcy",
    "fault",
    "cell-short",
];

/// The charge's states by name, as the bench writes and reads them.
pub const STATES: [(ChargePhase, &str); 10] = [
    (ChargePhase::Idle, "idle"),
    (ChargePhase::HoldOff, "hold-off"),
    (ChargePhase::Bulk, "bulk"),
    (ChargePhase::Absorption, "absorption"),
    (ChargePhase::Equalize, "equalize"),
    (ChargePhase::Rest, "rest"),
    (ChargePhase::Float, "float"),
    (ChargePhase::Complete, "complete"),
    (ChargePhase::Remote, "remote"),
    (ChargePhase::Terminated, "terminated"),
];

/// The bench's name of a state.
#[must_use]
pub fn state_name(phase: ChargePhase) -> &'static str {
    STATES
        .iter()
        .find(|(p, _)| *p == phase)
        .map_or("unknown", |(_, n)| n)
}

/// A Delta-Q code from its label, `E-0-x-y` or `F-0-x-y`.
#[must_use]
pub fn parse_code(label: &str) -> Option<DeltaQCode> {
    let b = label.as_bytes();
    let digit = |i: usize| b.get(i).filter(|c| c.is_ascii_digit()).map(|c| c - b'0');
    if b.len() != 7 || b.get(1..4) != Some(b"-0-") || b.get(5) != Some(&b'-') {
        return None;
    }
    let (x, y) = (digit(4)?, digit(6)?);
    match b.first() {
        Some(b'E') => DeltaQCode::alarm(x, y),
        Some(b'F') => DeltaQCode::fault(x, y),
        _ => None,
    }
}

impl Script {
    /// Reads a scenario file's tree (see [the module docs](super)).
    ///
    /// # Errors
    ///
    /// The first unknown key, missing key or bad value, with its line.
    pub fn from_document(root: &Item) -> Result<Script, ScriptError> {
        let mut file = Fields::of("the file", root)?;
        let mut charger = Fields::of("[charger]", file.need("charger")?)?;
        let mode = charger.need("mode")?;
        let mode = match mode.text("a mode")? {
            "local" => OperatingMode::Local,
            "remote" => OperatingMode::Remote,
            "local-override" => OperatingMode::LocalOverride,
            "monitoring" => OperatingMode::MonitoringOnly,
            m => {
                return Err(unknown(
                    mode.line,
                    "mode",
                    m,
                    "local, remote, local-override, monitoring",
                ))
            }
        };
        let algorithm = charger.take("algorithm").map(algorithm_id).transpose()?;
        let no_can_algorithm = charger
            .take("no_can_algorithm")
            .map(algorithm_id)
            .transpose()?;
        charger.finish()?;
        let battery = read_battery(file.need("battery")?)?;
        let bus = match file.take("bus") {
            Some(item) => read_bus(item)?,
            None => BusSetup {
                loss: 0.0,
                latency: Duration::ZERO,
                seed: crate::sim::DEFAULT_SEED,
            },
        };
        let mut events = Vec::new();
        if let Some(list) = file.take("event") {
            let Value::List(items) = &list.value else {
                return Err(ScriptError::new(
                    list.line,
                    "event must be [[event]] tables",
                ));
            };
            for item in items {
                events.push(read_event(item, battery.cells)?);
            }
        }
        events.sort_by_key(|e| e.at);
        let mut run = Fields::of("[run]", file.need("run")?)?;
        let until = run.need("until")?.time_to(MAX_RUN)?;
        run.finish()?;
        let expect = match file.take("expect") {
            Some(item) => read_expect(item)?,
            None => Expect::default(),
        };
        file.finish()?;
        Ok(Script {
            mode,
            algorithm,
            no_can_algorithm,
            battery,
            bus,
            events,
            until,
            expect,
        })
    }
}

fn unknown(line: u32, what: &str, got: &str, known: &str) -> ScriptError {
    ScriptError::new(line, format!("unknown {what} \"{got}\" (known: {known})"))
}

/// An algorithm id of the simulated charger's table
/// ([`EXAMPLE_ALGORITHMS`](crate::deltaq::charge::EXAMPLE_ALGORITHMS)).
fn algorithm_id(item: &Item) -> Result<u16, ScriptError> {
    let table = &crate::deltaq::charge::EXAMPLE_ALGORITHMS;
    let id = item.number("an algorithm id", 0.0..=65535.0)? as u16;
    if table.iter().any(|a| a.id == id) {
        return Ok(id);
    }
    let known: Vec<String> = table.iter().map(|a| format!("{}", a.id)).collect();
    Err(unknown(
        item.line,
        "algorithm",
        &format!("{id}"),
        &known.join(", "),
    ))
}

fn read_battery(item: &Item) -> Result<Battery, ScriptError> {
    let mut f = Fields::of("[battery]", item)?;
    let name = f.need("chemistry")?;
    let text = name.text("a 6020h battery type name")?;
    let battery_type = BatteryType::from_name(text).ok_or_else(|| {
        let known = "flooded, agm, gel, li-ion, nicd, nimh, .. (CiA 418 6020h)";
        unknown(name.line, "chemistry", text, known)
    })?;
    let battery = Battery {
        battery_type,
        cells: f.need("cells")?.whole("a cell count", 1.0..=200.0)? as u16,
        capacity_ah: f
            .need("capacity_ah")?
            .number("a capacity in Ah", 1.0..=10_000.0)?,
        soc_percent: f
            .need("soc")?
            .number("a state of charge in %", 0.0..=100.0)?,
        temperature_c: match f.take("temperature_c") {
            Some(t) => t.number("a temperature in degC", -60.0..=120.0)?,
            None => 25.0,
        },
    };
    // The pack model must know the chemistry.
    PackSpec::of_type(battery_type, battery.cells, battery.capacity_ah)
        .map_err(|e| ScriptError::new(name.line, format!("{text}: {e}")))?;
    f.finish()?;
    Ok(battery)
}

fn read_bus(item: &Item) -> Result<BusSetup, ScriptError> {
    let mut f = Fields::of("[bus]", item)?;
    let loss = f.take("loss").map(|i| i.number("a probability", 0.0..=1.0));
    let latency = f
        .take("latency_ms")
        .map(|i| i.number("a latency in ms", 0.0..=10_000.0));
    let seed = f.take("seed").map(|i| i.whole("a seed", 0.0..=9e15));
    f.finish()?;
    Ok(BusSetup {
        loss: loss.transpose()?.unwrap_or(0.0),
        latency: Duration::from_micros((latency.transpose()?.unwrap_or(0.0) * 1000.0) as u64),
        seed: seed
            .transpose()?
            .map_or(crate::sim::DEFAULT_SEED, |s| s as u64),
    })
}

/// `cells`: the pack's, the most a `cell-short` can short.
fn read_event(item: &Item, cells: u16) -> Result<TimedAction, ScriptError> {
    let mut f = Fields::of("[[event]]", item)?;
    let at = f.need("at")?.time()?;
    let name_item = f.need("action")?;
    let name = name_item.text("an action")?;
    let action = match name {
        "ac-off" => Action::AcOff,
        "ac-on" => Action::AcOn,
        "ac-voltage" => Action::AcVoltage(value(&mut f, "an AC voltage in V", 0.0..=400.0)?),
        "bms-silent" => Action::BmsSilent,
        "bms-back" => Action::BmsBack,
        "bus-off" => Action::BusOff(f.need("value")?.time()?),
        "bus-loss" => Action::BusLoss(value(&mut f, "a probability", 0.0..=1.0)?),
        "temperature" => {
            Action::Temperature(value(&mut f, "a temperature in degC", -60.0..=120.0)?)
        }
        "unplug" => Action::Unplug,
        "plug" => Action::Plug,
        "reverse-polarity" => Action::ReversePolarity,
        "battery-status" => {
            Action::BatteryStatus(f.need("value")?.whole("a 6000h value", 0.0..=255.0)? as u8)
        }
        "request" => {
            let current = f
                .take("current_a")
                .map(|i| i.number("a current in A", 0.0..=1000.0));
            let voltage = f
                .take("voltage_v")
                .map(|i| i.number("a voltage in V", 0.0..=1000.0));
            let (current_a, voltage_v) = (current.transpose()?, voltage.transpose()?);
            if current_a.is_none() && voltage_v.is_none() {
                return Err(ScriptError::new(
                    item.line,
                    "request: current_a or voltage_v is missing",
                ));
            }
            Action::Request {
                current_a,
                voltage_v,
            }
        }
        "ah-target" => Action::AhTarget(value(&mut f, "a charge in Ah", 0.0..=8000.0)?),
        "algorithm" => {
            Action::Algorithm(f.need("value")?.whole("an algorithm id", 0.0..=65535.0)? as u16)
        }
        "bms-emcy" => {
            let v = f.need("value")?;
            let code = v.text("an EMCY code \"0xXXXX\"")?;
            let hex = code.strip_prefix("0x").or_else(|| code.strip_prefix("0X"));
            let parsed = hex
                .filter(|h| h.len() == 4)
                .and_then(|h| u16::from_str_radix(h, 16).ok());
            Action::BmsEmcy(parsed.ok_or_else(|| {
                ScriptError::new(
                    v.line,
                    format!("expected an EMCY code \"0xXXXX\", found \"{code}\""),
                )
            })?)
        }
        "fault" => {
            let v = f.need("value")?;
            let name = v.text("a fault name")?;
            let known = "output-stage, input-stage, input-stage-2, current-measurement, relay, output-current, F-0-0-1..6";
            Action::Fault(
                StageFaults::from_label(name)
                    .ok_or_else(|| unknown(v.line, "fault", name, known))?,
            )
        }
        "cell-short" => {
            let most = f64::from(cells);
            let what = "a number of the pack's cells";
            Action::CellShort(f.need("value")?.whole(what, 1.0..=most)? as u16)
        }
        other => {
            let known = ACTIONS.join(", ");
            return Err(unknown(name_item.line, "action", other, &known));
        }
    };
    f.finish()?;
    Ok(TimedAction {
        at,
        action,
        line: item.line,
    })
}

/// The number in the event's `value`.
fn value(
    f: &mut Fields<'_>,
    what: &str,
    range: core::ops::RangeInclusive<f64>,
) -> Result<f64, ScriptError> {
    f.need("value")?.number(what, range)
}

fn codes(item: &Item) -> Result<Vec<DeltaQCode>, ScriptError> {
    item.texts("alarm codes")?
        .into_iter()
        .map(|(line, t)| {
            parse_code(t).ok_or_else(|| {
                ScriptError::new(
                    line,
                    format!("expected an alarm E-0-x-y or fault F-0-x-y, found \"{t}\""),
                )
            })
        })
        .collect()
}

fn state(line: u32, name: &str) -> Result<ChargePhase, ScriptError> {
    STATES
        .iter()
        .find(|(_, n)| *n == name)
        .map(|(p, _)| *p)
        .ok_or_else(|| {
            let known = STATES
                .iter()
                .map(|(_, n)| *n)
                .collect::<Vec<_>>()
                .join(", ");
            unknown(line, "state", name, &known)
        })
}

fn read_expect(item: &Item) -> Result<Expect, ScriptError> {
    let mut f = Fields::of("[expect]", item)?;
    let mut e = Expect::default();
    if let Some(i) = f.take("alarms") {
        e.alarms = Some(codes(i)?);
    }
    if let Some(i) = f.take("raised") {
        e.raised = codes(i)?;
    }
    if let Some(i) = f.take("not_raised") {
        e.not_raised = codes(i)?;
    }
    if let Some(i) = f.take("state") {
        e.state = Some(state(i.line, i.text("a state")?)?);
    }
    if let Some(i) = f.take("states") {
        for (line, name) in i.texts("states")? {
            e.states.push(state(line, name)?);
        }
    }
    if let Some(i) = f.take("output") {
        e.output = Some(match i.text("\"on\" or \"off\"")? {
            "on" => true,
            "off" => false,
            _ => return Err(ScriptError::new(i.line, "expected \"on\" or \"off\"")),
        });
    }
    let mut bound = |key: &str, what: &str, max: f64| {
        f.take(key).map(|i| i.number(what, 0.0..=max)).transpose()
    };
    e.ah = (
        bound("ah_min", "a charge in Ah", 1e6)?,
        bound("ah_max", "a charge in Ah", 1e6)?,
    );
    e.soc = (
        bound("soc_min", "a state of charge in %", 100.0)?,
        bound("soc_max", "a state of charge in %", 100.0)?,
    );
    e.voltage_max = bound("voltage_max", "a voltage in V", 1000.0)?;
    f.finish()?;
    Ok(e)
}
