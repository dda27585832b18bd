//! A [`Script`] run over a [`Session`]: the actions at their times, and
//! what the bench reports as it goes ([`BenchEvent`]: states, alarms, a
//! sample every simulated minute, the end [`Summary`]) and whether the
//! script's [`Expect`] held.

use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::time::Duration;

use super::script::{state_name, Action, Expect, Script};
use crate::clock::Timestamp;
use crate::deltaq::charge::{ChargePhase, AH_TARGET};
use crate::deltaq::{index, AlgorithmRequest, DeltaQCode};
use crate::sim::{PackError, PackSpec, Session, SessionConfig};

/// The physics step of a bench run (the session's default is 250 ms): a
/// second is fine enough for a charge's currents and temperatures, and
/// four times fewer steps make an 8-hour charge run in well under a
/// second.
pub const TICK: Duration = Duration::from_secs(1);

/// How often the bench reports a sample.
pub const SAMPLE_EVERY: Duration = Duration::from_secs(60);

/// What a run reports as it goes.
#[derive(Debug, Clone, PartialEq)]
pub enum BenchEvent {
    /// The charge entered a state.
    State {
        /// When, from the start.
        at: Timestamp,
        /// The state.
        state: ChargePhase,
    },
    /// An alarm or fault of the charger was raised or cleared.
    Alarm {
        /// When, from the start.
        at: Timestamp,
        /// The alarm or fault.
        code: DeltaQCode,
        /// Raised (`true`) or cleared.
        raised: bool,
    },
    /// The measurements, once a simulated minute.
    Sample {
        /// When, from the start.
        at: Timestamp,
        /// The current into the battery, A.
        current_a: f64,
        /// The battery's terminal voltage, V.
        voltage_v: f64,
        /// The battery's state of charge, %.
        soc: f64,
        /// The battery's temperature, degC.
        temperature_c: f64,
    },
    /// The run is over.
    End(Summary),
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Charge delivered into the battery, Ah.
    pub ah: f64,
    /// Energy delivered into the battery, Wh.
    pub wh: f64,
    /// The battery's state of charge at the end, %.
    pub soc: f64,
    /// The charge's state at the end.
    pub state: ChargePhase,
    /// The alarms and faults active at the end, in the order raised.
    pub alarms: Vec<DeltaQCode>,
    /// Every alarm and fault raised during the run, once each.
    pub raised: Vec<DeltaQCode>,
    /// Every state the charge entered, in order.
    pub states: Vec<ChargePhase>,
    /// The output delivers current at the end.
    pub output_on: bool,
    /// The battery's highest terminal voltage during the run, V (every
    /// simulated second).
    pub voltage_max: f64,
}

/// Seconds since the start, to the millisecond.
fn seconds(at: Timestamp) -> f64 {
    at.as_micros().div_euclid(1000) as f64 / 1000.0
}

/// `x` to `places` decimals (a finite number: JSON has no other).
fn round(x: f64, places: i32) -> f64 {
    let scale = 10f64.powi(places);
    let r = (x * scale).round() / scale;
    if r.is_finite() {
        r + 0.0
    } else {
        0.0
    }
}

fn code_list(codes: &[DeltaQCode]) -> String {
    let quoted: Vec<String> = codes.iter().map(|c| format!("\"{c}\"")).collect();
    format!("[{}]", quoted.join(", "))
}

impl BenchEvent {
    /// The event as one line of JSON (no newline), as `canopen-bench
    /// --json` prints it: `{"t": s, "event": "state", "state": "bulk"}`,
    /// `{"t": s, "event": "alarm", "code": "E-0-0-8", "raised": true}`,
    /// `{"t": s, "event": "sample", "current_a": .., "voltage_v": ..,
    /// "soc": .., "temperature_c": ..}`, and last `{"event": "end", "ah":
    /// .., "wh": .., "soc": .., "state": .., "alarms": [..]}`.
    #[must_use]
    pub fn json(&self) -> String {
        match self {
            BenchEvent::State { at, state } => format!(
                "{{\"t\": {}, \"event\": \"state\", \"state\": \"{}\"}}",
                seconds(*at),
                state_name(*state)
            ),
            BenchEvent::Alarm { at, code, raised } => format!(
                "{{\"t\": {}, \"event\": \"alarm\", \"code\": \"{code}\", \"raised\": {raised}}}",
                seconds(*at)
            ),
            BenchEvent::Sample {
                at,
                current_a,
                voltage_v,
                soc,
                temperature_c,
            } => format!(
                "{{\"t\": {}, \"event\": \"sample\", \"current_a\": {}, \"voltage_v\": {}, \"soc\": {}, \"temperature_c\": {}}}",
                seconds(*at),
                round(*current_a, 3),
                round(*voltage_v, 3),
                round(*soc, 2),
                round(*temperature_c, 2)
            ),
            BenchEvent::End(s) => format!(
                "{{\"event\": \"end\", \"ah\": {}, \"wh\": {}, \"soc\": {}, \"state\": \"{}\", \"alarms\": {}}}",
                round(s.ah, 3),
                round(s.wh, 1),
                round(s.soc, 2),
                state_name(s.state),
                code_list(&s.alarms)
            ),
        }
    }
}

/// `h:mm:ss.mmm` since the start.
fn clock(at: Timestamp) -> String {
    let ms = at.as_micros() / 1000;
    let s = ms / 1000;
    format!(
        "{}:{:02}:{:02}.{:03}",
        s / 3600,
        s / 60 % 60,
        s % 60,
        ms % 1000
    )
}

impl BenchEvent {
    /// The event as a line of words, as `canopen-bench` prints it without
    /// `--json` (`None` for a sample: it prints none).
    #[must_use]
    pub fn words(&self) -> Option<String> {
        Some(match self {
            BenchEvent::State { at, state } => {
                format!("{} state {}", clock(*at), state_name(*state))
            }
            BenchEvent::Alarm { at, code, raised } => format!(
                "{} alarm {code} {}",
                clock(*at),
                if *raised { "raised" } else { "cleared" }
            ),
            BenchEvent::Sample { .. } => return None,
            BenchEvent::End(s) => {
                let alarms: Vec<String> = s.alarms.iter().map(|c| format!("{c}")).collect();
                format!(
                    "end: {:.3} Ah, {:.1} Wh, state of charge {:.1} %, state {}, alarms: {}",
                    s.ah,
                    s.wh,
                    s.soc,
                    state_name(s.state),
                    if alarms.is_empty() {
                        "none".into()
                    } else {
                        alarms.join(", ")
                    }
                )
            }
        })
    }
}

impl Script {
    /// The session the script starts with, not yet started.
    ///
    /// # Errors
    ///
    /// A battery the pack model cannot be (see [`PackSpec::new`]).
    pub fn session(&self) -> Result<Session, PackError> {
        let b = &self.battery;
        let pack = PackSpec {
            ambient_c: b.temperature_c,
            ..PackSpec::of_type(b.battery_type, b.cells, b.capacity_ah)?
        };
        let mut config = SessionConfig::for_pack(self.mode, pack, b.soc_percent / 100.0);
        let charge = &mut config.charger.charge;
        charge.permanent_algorithm = self.algorithm;
        charge.no_can_algorithm = self.no_can_algorithm.or(charge.no_can_algorithm);
        config.tick = TICK;
        config.bus_latency = self.bus.latency;
        config.bus_loss = self.bus.loss;
        config.bus_seed = self.bus.seed;
        Ok(Session::new(&config))
    }

    /// Runs the script: the session starts, each action happens at its
    /// time, and `report` hears every state, alarm and sample as the
    /// run goes, and the end last. Returns the session at its end (for
    /// its log) and the summary.
    ///
    /// # Errors
    ///
    /// A battery the pack model cannot be (see [`PackSpec::new`]).
    pub fn run(
        &self,
        mut report: impl FnMut(&BenchEvent),
    ) -> Result<(Session, Summary), PackError> {
        let mut s = self.session()?;
        let mut actions = self.events.iter().peekable();
        // The actions at 0:00:00 are the conditions at power-on.
        while let Some(a) = actions.next_if(|a| a.at.is_zero()) {
            apply(&mut s, a.action);
        }
        s.start();
        let end = Timestamp::ZERO.add_duration(self.until);
        let mut seen = (0, 0);
        let mut next_sample = Timestamp::ZERO.add_duration(SAMPLE_EVERY);
        let mut highest = terminal_voltage(&s);
        loop {
            let next_action = actions.peek().map(|a| Timestamp::ZERO.add_duration(a.at));
            let next = crate::clock::earliest([next_action, Some(next_sample)])
                .map_or(end, |t| t.min(end));
            s.run_while(next, |s| {
                highest = highest.max(terminal_voltage(s));
                true
            });
            highest = highest.max(terminal_voltage(&s));
            changes(&s, &mut seen, &mut report);
            while let Some(a) =
                actions.next_if(|a| next.has_reached(Timestamp::ZERO.add_duration(a.at)))
            {
                apply(&mut s, a.action);
                changes(&s, &mut seen, &mut report);
            }
            if next.has_reached(next_sample) {
                report(&sample(&s, next_sample));
                next_sample = next_sample.add_duration(SAMPLE_EVERY);
            }
            if next.has_reached(end) {
                break;
            }
        }
        let summary = summary(&s, highest);
        report(&BenchEvent::End(summary.clone()));
        Ok((s, summary))
    }
}

/// The states and alarm changes since the ones `seen`, in time order.
fn changes(s: &Session, seen: &mut (usize, usize), report: &mut impl FnMut(&BenchEvent)) {
    let phases = s.phases().get(seen.0..).unwrap_or_default();
    let alarms = s.alarm_changes().get(seen.1..).unwrap_or_default();
    seen.0 += phases.len();
    seen.1 += alarms.len();
    let mut events: Vec<BenchEvent> = phases
        .iter()
        .map(|&(at, state)| BenchEvent::State { at, state })
        .chain(alarms.iter().map(|c| BenchEvent::Alarm {
            at: c.at,
            code: c.code,
            raised: c.raised,
        }))
        .collect();
    events.sort_by_key(|e| match e {
        BenchEvent::State { at, .. } | BenchEvent::Alarm { at, .. } => *at,
        _ => Timestamp::ZERO,
    });
    events.iter().for_each(report);
}

/// The battery's terminal voltage with the current flowing now, V.
fn terminal_voltage(s: &Session) -> f64 {
    s.pack.terminal_voltage(s.stage.current_a)
}

fn sample(s: &Session, at: Timestamp) -> BenchEvent {
    BenchEvent::Sample {
        at,
        current_a: s.stage.current_a,
        voltage_v: terminal_voltage(s),
        soc: s.pack.soc() * 100.0,
        temperature_c: s.pack.temperature_c(),
    }
}

fn summary(s: &Session, voltage_max: f64) -> Summary {
    let r = s.result();
    let mut raised: Vec<DeltaQCode> = Vec::new();
    for c in s.alarm_changes() {
        if c.raised && !raised.contains(&c.code) {
            raised.push(c.code);
        }
    }
    Summary {
        ah: r.ah,
        wh: r.wh,
        soc: r.end_soc * 100.0,
        state: s.phase(),
        alarms: s.active_alarms().to_vec(),
        raised,
        states: r.phases.iter().map(|(_, p)| *p).collect(),
        output_on: s.stage.current_a > 0.01,
        voltage_max,
    }
}

/// Makes `action` happen on the session now.
pub fn apply(s: &mut Session, action: Action) {
    match action {
        Action::AcOff => s.set_ac(false),
        Action::AcOn => s.set_ac(true),
        Action::AcVoltage(v) => s.set_ac_voltage(v),
        Action::BmsSilent => s.set_module_on_can(false),
        Action::BmsBack => s.set_module_on_can(true),
        Action::BusOff(d) => s.bus_off(d),
        Action::BusLoss(p) => s.set_loss(p),
        Action::Temperature(t) => s.pack.set_temperature_c(t),
        Action::CellShort(n) => s.pack.short_cells(n),
        Action::ReversePolarity => {
            s.set_battery_connected(true);
            s.set_reverse_polarity(true);
        }
        Action::Fault(fault) => s.inject_fault(fault, true),
        Action::Unplug => s.set_battery_connected(false),
        Action::Plug => {
            s.set_reverse_polarity(false);
            s.set_battery_connected(true);
        }
        Action::BatteryStatus(v) => s.bms.hold = v & 1 == 0,
        Action::Request {
            current_a,
            voltage_v,
        } => {
            if let Some(a) = current_a {
                s.bms.current_limit_a = None;
                s.bms.max_current_a = a;
            }
            if let Some(v) = voltage_v {
                s.bms.cv_volts = v;
                // 2271h: 1/1024 V.
                let q10 = (v * 1024.0).round().clamp(0.0, f64::from(u32::MAX)) as u32;
                s.write_charger(index::VOLTAGE_REQUEST, 0, &q10.to_le_bytes());
            }
        }
        Action::AhTarget(ah) => {
            // 2250h (ours): 1/8 Ah.
            let q3 = (ah * 8.0).round().clamp(0.0, 65534.0) as u16;
            s.write_charger(AH_TARGET, 0, &q3.to_le_bytes());
        }
        Action::Algorithm(id) => {
            let value = AlgorithmRequest::new(id).to_u32().to_le_bytes();
            s.write_charger(index::ALGORITHM_REQUEST, 0, &value);
        }
        Action::BmsEmcy(code) => s.module_emcy(code),
    }
}

impl Expect {
    /// What of the expectations `summary` fails, one sentence each (none:
    /// it holds).
    #[must_use]
    pub fn check(&self, summary: &Summary) -> Vec<String> {
        let mut failed = Vec::new();
        if let Some(alarms) = &self.alarms {
            let same = alarms.len() == summary.alarms.len()
                && alarms.iter().all(|a| summary.alarms.contains(a));
            if !same {
                failed.push(format!(
                    "alarms at the end: expected {}, found {}",
                    code_list(alarms),
                    code_list(&summary.alarms)
                ));
            }
        }
        for code in &self.raised {
            if !summary.raised.contains(code) {
                failed.push(format!("{code} was never raised"));
            }
        }
        for code in &self.not_raised {
            if summary.raised.contains(code) {
                failed.push(format!("{code} was raised"));
            }
        }
        if let Some(state) = self.state.filter(|s| *s != summary.state) {
            failed.push(format!(
                "state at the end: expected {}, found {}",
                state_name(state),
                state_name(summary.state)
            ));
        }
        let mut entered = summary.states.iter();
        for state in &self.states {
            if !entered.any(|s| s == state) {
                failed.push(format!(
                    "the charge did not enter {} (in the order of states)",
                    state_name(*state)
                ));
                break;
            }
        }
        if let Some(on) = self.output.filter(|on| *on != summary.output_on) {
            let word = |on: bool| if on { "on" } else { "off" };
            failed.push(format!(
                "output at the end: expected {}, found {}",
                word(on),
                word(!on)
            ));
        }
        for (what, unit, (min, max), got) in [
            ("charge delivered", "Ah", self.ah, summary.ah),
            ("state of charge at the end", "%", self.soc, summary.soc),
            (
                "highest battery voltage",
                "V",
                (None, self.voltage_max),
                summary.voltage_max,
            ),
        ] {
            if min.is_some_and(|m| got < m) || max.is_some_and(|m| got > m) {
                let bound = |b: Option<f64>| b.map_or("-".into(), |b| format!("{b}"));
                failed.push(format!(
                    "{what}: {got:.3} {unit}, expected from {} to {}",
                    bound(min),
                    bound(max)
                ));
            }
        }
        failed
    }
}
