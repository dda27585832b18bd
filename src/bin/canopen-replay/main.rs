//! `canopen-replay`: plays one side of a CANopen recording into a device
//! under test and diffs what the device sends against what the recording
//! shows for it. See docs/REPLAY.md.

mod link;
mod report;

use std::collections::BTreeSet;
use std::process::ExitCode;
use std::time::Duration;

use canopen_codec::log::replay::{self as recording, diff, player};
use canopen_codec::log::{input, pdo_syntax};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::Parser;

use diff::Tolerances;
use link::Link;

/// `--format`: the names of [`input::FORMAT_NAMES`], each with its help
/// (as `canopen-decode`'s).
fn format_names() -> impl TypedValueParser<Value = input::How> {
    let names = input::FORMAT_NAMES.map(|f| PossibleValue::new(f.name).help(f.help));
    PossibleValuesParser::new(names).map(|name| input::How::named(&name).unwrap_or_default())
}

const EXIT_CODES: &str = "Exit status: 0 the device matches the recording within tolerance; \
4 it differs; 2 usage error (bad option, unreadable trace); 3 the device could not be \
started or stopped/died before the recording ended.";

/// The slowest `--speed` but 0 (a minute of recording takes 17 hours).
const MIN_SPEED: f64 = 0.001;
/// The fastest `--speed`, as the examples' (`charger`, `battery_module`):
/// a heartbeat consumer time of a second or two stays tens of wall
/// milliseconds above the scheduler's jitter.
const MAX_SPEED: f64 = 1000.0;
/// The widest `--period-tolerance`, in percent.
const MAX_PERCENT: f64 = 1000.0;
/// The largest value of each `*-ms` option: 2^32 - 1 ms (49.7 days).
const MAX_MS: u64 = u32::MAX as u64;

/// Replays the frames of the --play nodes from a recording (any trace
/// format canopen-decode reads: candump log or screen, PCAN .trc, Vector
/// ASC or BLF, python-can CSV) into a device under test and diffs what the
/// device sends against the recording. The device is the program after
/// `--` on a candump-line pipe, or, without `--`, the replay's own stdout
/// (frames to the device) and stdin (frames from it).
#[derive(Parser)]
#[command(name = "canopen-replay", after_help = EXIT_CODES)]
struct Args {
    /// The recording.
    trace: std::path::PathBuf,
    /// The recording's format (detected from its content when not given;
    /// candump-screen-delta, for candump -t d, has to be given).
    #[arg(long, value_parser = format_names())]
    format: Option<input::How>,
    /// The nodes whose frames the replay sends (1..=127, decimal or 0x
    /// hex), comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        value_parser = node,
        allow_hyphen_values = true
    )]
    play: Vec<u8>,
    /// Time scale: 2 plays twice as fast; 0 as fast as the device answers
    /// (0, or 0.001 to 1000).
    #[arg(long, default_value_t = 1.0, value_parser = speed, allow_hyphen_values = true)]
    speed: f64,
    /// How many raw units a PDO field may differ from the recording.
    #[arg(long, default_value_t = 0, allow_hyphen_values = true)]
    tolerance: u64,
    /// How much a COB-ID's period may differ, in percent (0 to 1000).
    #[arg(long, default_value_t = 10.0, value_parser = percent, allow_hyphen_values = true)]
    period_tolerance: f64,
    /// How far an EMCY (and an NMT state change beyond one heartbeat
    /// period) may be from its recorded time, in ms (0 to 4294967295).
    #[arg(long, default_value_t = 100, value_parser = ms(), allow_hyphen_values = true)]
    time_tolerance_ms: u64,
    /// How long to wait for the device's SDO answer, in ms (0 to
    /// 4294967295).
    #[arg(long, default_value_t = 1000, value_parser = ms(), allow_hyphen_values = true)]
    sdo_timeout_ms: u64,
    /// The longest to listen after the last played frame, in ms (the rest
    /// of the recording, up to this; 0 to 4294967295).
    #[arg(long, default_value_t = 60_000, value_parser = ms(), allow_hyphen_values = true)]
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

/// A node id 1..=127, decimal or `0x` hex.
fn node(s: &str) -> Result<u8, String> {
    let t = s.trim();
    let v = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(h) => u8::from_str_radix(h, 16).ok(),
        None => t.parse().ok(),
    };
    v.filter(|n| (1..=127).contains(n))
        .ok_or(format!("'{s}' is not a node id 1..=127"))
}

/// A finite decimal number.
fn finite(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or(format!("'{s}' is not a finite number"))
}

/// `--speed`: 0, or [`MIN_SPEED`] to [`MAX_SPEED`].
fn speed(s: &str) -> Result<f64, String> {
    let v = finite(s)?;
    if v == 0.0 || (MIN_SPEED..=MAX_SPEED).contains(&v) {
        Ok(v.abs())
    } else {
        Err(format!(
            "'{s}' is neither 0 (as fast as the device answers) nor {MIN_SPEED} to {MAX_SPEED}"
        ))
    }
}

/// `--period-tolerance`: 0 to [`MAX_PERCENT`].
fn percent(s: &str) -> Result<f64, String> {
    let v = finite(s)?;
    if (0.0..=MAX_PERCENT).contains(&v) {
        Ok(v.abs())
    } else {
        Err(format!("'{s}' is not 0 to {MAX_PERCENT} percent"))
    }
}

/// A `*-ms` option: 0 to [`MAX_MS`].
fn ms() -> clap::builder::RangedU64ValueParser<u64> {
    clap::value_parser!(u64).range(0..=MAX_MS)
}

fn usage(e: &str) -> ExitCode {
    eprintln!("canopen-replay: {e}");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    // clap prints --help (exit 0) or a usage error (exit 2), as
    // canopen-decode does.
    let args = Args::parse();
    let play: BTreeSet<u8> = args.play.iter().copied().collect();
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
    let read = std::fs::File::open(&args.trace).and_then(|f| {
        let mut zlib = input::Zlib::default();
        let how = input::How {
            // memchr's SIMD search for line ends, as canopen-decode's.
            find_newline: Some(|bytes| memchr::memchr(b'\n', bytes)),
            ..args.format.unwrap_or_default()
        };
        input::frames(f, how, &mut zlib)
    });
    let frames = match read {
        Ok(f) => f,
        Err(e) => return usage(&format!("{}: {e}", args.trace.display())),
    };
    let rec = match recording::of(&frames, &play) {
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
    let played = match link::play(&rec, &mut link, &options) {
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
        time: args.time_tolerance_ms.saturating_mul(1000),
    };
    let player::Comparison {
        recording: recorded,
        device,
        differences,
    } = played.compare(&rec, &pdos, &tol);
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
