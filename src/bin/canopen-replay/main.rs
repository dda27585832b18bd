//! `canopen-replay`: plays one side of a CANopen recording into a device
//! under test and diffs what the device sends against what the recording
//! shows for it. See docs/REPLAY.md.

mod diff;
mod link;
#[path = "../common/pdo_syntax.rs"]
mod pdo_syntax;
mod player;
mod recording;
mod report;

use std::collections::BTreeSet;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;

use diff::Tolerances;
use link::Link;

const EXIT_CODES: &str = "Exit status: 0 the device matches the recording within tolerance; \
4 it differs; 2 usage error (bad option, unreadable trace); 3 the device could not be \
started or stopped/died before the recording ended.";

/// Replays the frames of the --play nodes from a recording (any trace
/// format canopen-decode reads) into a device under test and diffs what the
/// device sends against the recording. The device is the program after
/// `--` on a candump-line pipe, or, without `--`, the replay's own stdout
/// (frames to the device) and stdin (frames from it).
#[derive(Parser)]
#[command(name = "canopen-replay", after_help = EXIT_CODES)]
struct Args {
    /// The recording.
    trace: std::path::PathBuf,
    /// The nodes whose frames the replay sends (decimal or 0x hex), comma-separated.
    #[arg(long, value_delimiter = ',', required = true)]
    play: Vec<String>,
    /// Time scale: 2 plays twice as fast; 0 as fast as the device answers.
    #[arg(long, default_value_t = 1.0)]
    speed: f64,
    /// How many raw units a PDO field may differ from the recording.
    #[arg(long, default_value_t = 0)]
    tolerance: u64,
    /// How much a COB-ID's period may differ, in percent.
    #[arg(long, default_value_t = 10.0)]
    period_tolerance: f64,
    /// How far an EMCY (and an NMT state change beyond one heartbeat
    /// period) may be from its recorded time, in ms.
    #[arg(long, default_value_t = 100)]
    time_tolerance_ms: u64,
    /// How long to wait for the device's SDO answer, in ms.
    #[arg(long, default_value_t = 1000)]
    sdo_timeout_ms: u64,
    /// The longest to listen after the last played frame, in ms (the rest
    /// of the recording, up to this).
    #[arg(long, default_value_t = 60_000)]
    tail_limit_ms: u64,
    /// A PDO mapping whose field values are compared: COBID=INDEX:SUB:BITS,...
    #[arg(long)]
    pdo: Vec<String>,
    /// The real Delta-Q ICL1500 capture's PDO mapping (see canopen-decode).
    #[arg(long)]
    pdo_capture_mapping: bool,
    /// The report as one JSON object.
    #[arg(long)]
    json: bool,
    /// The device under test and its arguments.
    #[arg(last = true)]
    device: Vec<String>,
}

fn node(s: &str) -> Result<u8, String> {
    let v = match s.trim().strip_prefix("0x") {
        Some(h) => u8::from_str_radix(h, 16).ok(),
        None => s.trim().parse().ok(),
    };
    v.filter(|n| (1..=127).contains(n))
        .ok_or(format!("--play: '{s}' is not a node id 1..=127"))
}

fn usage(e: &str) -> ExitCode {
    eprintln!("canopen-replay: {e}");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let args = match Args::try_parse() {
        Ok(a) => a,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    let play: BTreeSet<u8> = match args.play.iter().map(|s| node(s)).collect() {
        Ok(p) => p,
        Err(e) => return usage(&e),
    };
    let number = |v: f64| v.is_finite() && v >= 0.0;
    if !number(args.speed) || !number(args.period_tolerance) {
        return usage("--speed and --period-tolerance must be numbers >= 0");
    }
    let mut pdos = Vec::new();
    let capture = args.pdo_capture_mapping.then_some(pdo_syntax::CAPTURE_PDOS);
    for a in args
        .pdo
        .iter()
        .map(String::as_str)
        .chain(capture.into_iter().flatten())
    {
        match pdo_syntax::parse_pdo(a) {
            Ok(m) => pdos.push(m),
            Err(e) => return usage(&e),
        }
    }
    let text = match std::fs::read(&args.trace) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) => return usage(&format!("{}: {e}", args.trace.display())),
    };
    let rec = match recording::read(&text, &play) {
        Ok(r) => r,
        Err(e) => return usage(&format!("{}: {e}", args.trace.display())),
    };
    let sent_by_played = |r: &recording::Recorded| matches!(recording::addressing(&r.frame), Some((n, false)) if play.contains(&n));
    if !rec.played.iter().any(sent_by_played) {
        return usage("the recording has no frame of the --play nodes");
    }
    let mut link = match args.device.split_first() {
        Some((program, rest)) => match Link::spawn(program, rest) {
            Ok(l) => l,
            Err(e) => {
                eprintln!("canopen-replay: {e}");
                return ExitCode::from(3);
            }
        },
        None => Link::stdio(),
    };
    let options = player::Options {
        speed: args.speed,
        sdo_timeout: Duration::from_millis(args.sdo_timeout_ms),
        tail_limit: Duration::from_millis(args.tail_limit_ms),
    };
    let played = match player::play(&rec, &mut link, &options) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("canopen-replay: {e}");
            link.close(Duration::ZERO);
            return ExitCode::from(3);
        }
    };
    link.close(Duration::from_millis(100));
    let tol = Tolerances {
        value: args.tolerance,
        period: args.period_tolerance / 100.0,
        time: args.time_tolerance_ms * 1000,
    };
    let recorded = diff::side(&rec.expected, &rec.played);
    let mut device = diff::side(&played.heard, &rec.played);
    for id in &played.boot_ups_at_start {
        if let Some(t) = device.traffic.get_mut(id) {
            t.kinds.remove("boot-up");
            t.count -= 1;
            if t.count == 0 {
                device.traffic.remove(id);
            }
        }
    }
    let mut differences = diff::compare(
        &recorded,
        &device,
        &rec.expected,
        &played.heard,
        &pdos,
        &tol,
    );
    for (t, id) in &played.unanswered_sdo {
        differences.push(diff::Difference {
            kind: "sdo unanswered",
            cob_id: Some(*id),
            words: format!(
                "the SDO request at {:.1} ms got no answer on {id:03X}h",
                *t as f64 / 1000.0
            ),
        });
    }
    let report = report::Report {
        recording: &recorded,
        device: &device,
        played: &played,
        sent: rec.played.len(),
        differences: &differences,
    };
    // In stdin/stdout mode stdout is the bus: the report goes to stderr.
    let text = if args.json {
        format!("{}\n", report.json())
    } else {
        report.words()
    };
    if args.device.is_empty() {
        eprint!("{text}");
    } else {
        print!("{text}");
    }
    if differences.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(4)
    }
}
