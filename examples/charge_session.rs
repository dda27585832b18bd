//! A whole charge session in simulated time: the Delta-Q charger and the
//! CiA 418 battery module on a simulated bus (`canopen_codec::sim`), a use
//! case of the Delta-Q specification's section 7 scripted on it. Writes the
//! session as a candump log and prints a one-screen result.
//!
//! ```text
//! cargo run --release --features sim --example charge_session -- --scenario normal-local --soc 20 --ah 100
//! canopen-decode --summary normal-local.log
//! ```
//!
//! Options: `--scenario NAME` (normal-local; `--list` names them all),
//! `--mode local|remote|local-override|monitoring` (the scenario's own),
//! `--soc PERCENT` (20), `--ah CAPACITY` (100), `--chemistry
//! lead-acid|lithium-ion` (lead-acid), `--log FILE` (NAME.log),
//! `--interface NAME` (vcan0, the candump interface column).

use std::fmt::Write as _;
use std::io::Write as _;
use std::process::ExitCode;
use std::time::Instant;

use canopen_codec::cia418::Chemistry;
use canopen_codec::deltaq::OperatingMode;
use canopen_codec::sim::{Scenario, ScenarioOptions, Session};
use canopen_codec::Timestamp;

const USAGE: &str =
    "usage: charge_session [--scenario NAME] [--mode local|remote|local-override|monitoring]
                      [--soc PERCENT] [--ah CAPACITY] [--chemistry lead-acid|lithium-ion]
                      [--log FILE] [--interface NAME] [--list]";

struct Options {
    scenario: Scenario,
    run: ScenarioOptions,
    log: Option<String>,
    interface: String,
}

fn parse_args(args: &[String]) -> Result<Option<Options>, String> {
    let mut o = Options {
        scenario: Scenario::NormalLocal,
        run: ScenarioOptions::default(),
        log: None,
        interface: "vcan0".into(),
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        let number = |v: &String| {
            v.parse::<f64>()
                .ok()
                .filter(|n| n.is_finite())
                .ok_or(format!("{a}: '{v}' is not a number"))
        };
        match a.as_str() {
            "-h" | "--help" => return Ok(None),
            "--list" => {
                for s in Scenario::ALL {
                    println!("{:<24} {} mode", s.name(), s.default_mode());
                }
                std::process::exit(0);
            }
            "--scenario" => {
                let v = value()?;
                o.scenario = Scenario::from_name(v).ok_or(format!(
                    "--scenario: unknown scenario '{v}' (--list names them)"
                ))?;
            }
            "--mode" => {
                o.run.mode = Some(match value()?.as_str() {
                    "local" => OperatingMode::Local,
                    "remote" => OperatingMode::Remote,
                    "local-override" => OperatingMode::LocalOverride,
                    "monitoring" => OperatingMode::MonitoringOnly,
                    other => return Err(format!("--mode: unknown mode '{other}'")),
                })
            }
            "--soc" => {
                let soc = number(value()?)?;
                if !(0.0..=100.0).contains(&soc) {
                    return Err("--soc must be 0..=100 (percent)".into());
                }
                o.run.soc = soc / 100.0;
            }
            "--ah" => {
                let ah = number(value()?)?;
                if !(1.0..=2000.0).contains(&ah) {
                    return Err("--ah must be 1..=2000".into());
                }
                o.run.capacity_ah = ah;
            }
            "--chemistry" => {
                o.run.chemistry = match value()?.as_str() {
                    "lead-acid" => Chemistry::LeadAcid,
                    "lithium-ion" => Chemistry::LithiumIon,
                    other => {
                        return Err(format!(
                    "--chemistry: '{other}' has no charge algorithm here (lead-acid, lithium-ion)"
                ))
                    }
                }
            }
            "--log" => o.log = Some(value()?.clone()),
            "--interface" => o.interface = value()?.clone(),
            other => return Err(format!("unknown option '{other}'")),
        }
    }
    Ok(Some(o))
}

fn write_log(path: &str, interface: &str, session: &Session) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    for line in session.candump(interface) {
        writeln!(out, "{line}")?;
    }
    out.flush()
}

fn clock(t: Timestamp) -> String {
    let s = t.as_millis() / 1000;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

fn result_text(o: &Options, session: &Session, wall_ms: u128) -> String {
    let r = session.result();
    let mut t = String::new();
    let mode = o.run.mode.unwrap_or(o.scenario.default_mode());
    let _ = writeln!(
        t,
        "scenario {} ({mode} mode), {:?} {} Ah, {} frames, {} simulated in {wall_ms} ms",
        o.scenario,
        o.run.chemistry,
        o.run.capacity_ah,
        session.log().len(),
        clock(session.now()),
    );
    let _ = writeln!(
        t,
        "state of charge {:.1} % -> {:.1} %; {:.2} Ah and {:.0} Wh into the pack; pack at most {:.1} degC",
        r.start_soc * 100.0,
        r.end_soc * 100.0,
        r.ah,
        r.wh,
        r.max_pack_temperature_c
    );
    let _ = writeln!(t, "phases:");
    for (i, (at, phase)) in r.phases.iter().enumerate() {
        let until = r.phases.get(i + 1).map_or(session.now(), |n| n.0);
        if until == *at && i + 1 < r.phases.len() {
            continue; // passed through at the same instant
        }
        let _ = writeln!(
            t,
            "  {} {:<30} for {}",
            clock(*at),
            phase.name(),
            clock(Timestamp::from_micros(until.saturating_micros_since(*at)))
        );
    }
    if r.errors.is_empty() {
        let _ = writeln!(t, "errors raised: none");
    } else {
        let _ = writeln!(t, "errors raised:");
        for (at, code) in &r.errors {
            let what = code.description().unwrap_or("(not in the table)");
            let _ = writeln!(t, "  {} {code} {what}", clock(*at));
        }
    }
    let status = session
        .charger()
        .expect("the session's charger")
        .charge_control()
        .status();
    let _ = writeln!(
        t,
        "charger now: 2006h = {:04X}h, 6001h = {:02X}h, 6052h = {} (Q3 Ah), 6080h = {}",
        status.extended.to_u16(),
        status.charger_status,
        status.ah_returned,
        status.charger_soc
    );
    t
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let o = match parse_args(&args) {
        Ok(Some(o)) => o,
        Ok(None) => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("charge_session: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let started = Instant::now();
    let session = match o.scenario.run(&o.run) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("charge_session: {e}");
            return ExitCode::from(2);
        }
    };
    let wall = started.elapsed().as_millis();
    let path = o.log.clone().unwrap_or(format!("{}.log", o.scenario));
    if let Err(e) = write_log(&path, &o.interface, &session) {
        eprintln!("charge_session: cannot write {path}: {e}");
        return ExitCode::from(1);
    }
    print!("{}", result_text(&o, &session, wall));
    println!("log: {path}");
    ExitCode::SUCCESS
}
