//! The `canopen-decode` pipeline (trace line parse + decode + format into a
//! sink), in lines per second, on a log of 100 000 lines made by repeating
//! the real Delta-Q ICL1500 captures (read from the shared data folder
//! beside the checkout, its `spec` / `captures` folder, or
//! `$CANOPEN_SHARED_DIR`; our own recorded session when they are absent).
//!
//! - `pipeline/{words,json,csv,summary-only}`: the program's own loop
//!   (`canopen_codec::log::run`, the one `main` calls), roles given as the
//!   program is run on the captures (`--charger-node 10 --battery-node 1`),
//!   with its line cache; `*-no-cache` formats every line anew.
//! - `json_object/{ours,serde_json}`: writing the JSON object of each of
//!   the log's distinct frames: our writer (`log::json::rest`) against
//!   `serde_json::to_writer` of the same object already built as a
//!   `serde_json::Value` (so serde's figure leaves out building it: a lower
//!   bound of what JSON through serde would cost).
//! - `bus_load/{frame_bits,bus_load}`: the summary's bit count of each
//!   frame of the log (`log::bus_load::FrameBits::of`: the frame's bits
//!   laid out, its CRC-15 computed, its stuff bits counted), and the same
//!   fed to the summary's `BusLoad` (windows, shares), per frame.
//!
//! `cargo bench --features log --bench decoder_pipeline` (or `--features
//! cli`, which has `log`). The whole program
//! on a 1-million-line file is timed by `benches/decoder_program.sh`.
use canopen_codec::log::{json, pdo_learn, run, FrameLine, Notes, Options, Roles};
use canopen_codec::NodeId;

use std::collections::HashSet;
use std::hint::black_box;
use std::io;
use std::path::{Path, PathBuf};

use canopen_codec::trace::candump::{parse_line, LogLine};
use canopen_codec::Message;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

/// The real captures (third-party data: tests/data/CAPTURES.md).
const CAPTURES: [&str; 2] = ["deltaq-icl1500-startup.log", "deltaq-icl1500-charging.log"];

/// The captures' folder, as the tests find it (`tests/common/captures.rs`):
/// its captures folder under `$CANOPEN_SHARED_DIR`, else under the shared
/// data folder beside the checkout.
fn captures_dir() -> PathBuf {
    std::env::var_os("CANOPEN_SHARED_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared"))
        .join("spec")
        .join("captures")
}
const LINES: usize = 100_000;

/// The log: the captures (or our session) repeated to [`LINES`] lines.
fn log() -> String {
    let dir = captures_dir();
    let mut paths: Vec<PathBuf> = CAPTURES.iter().map(|n| dir.join(n)).collect();
    if !paths.iter().all(|p| p.is_file()) {
        eprintln!(
            "decoder_pipeline bench: the real captures are not in {}; using tests/data/virtual-session.log",
            dir.display()
        );
        paths = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/virtual-session.log")];
    }
    let mut one = Vec::new();
    for path in &paths {
        let text = std::fs::read_to_string(path)
            .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
        one.extend(
            text.lines()
                .filter(|l| !l.trim().is_empty())
                .map(str::to_string),
        );
    }
    let mut out = String::new();
    for line in one.iter().cycle().take(LINES) {
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// The options of `canopen-decode --charger-node 10 --battery-node 1` and
/// `extra`, with the program's line search (memchr).
fn options(extra: &[&str]) -> Options {
    let mut o = Options {
        find_newline: Some(|bytes| memchr::memchr(b'\n', bytes)),
        roles: Roles {
            charger: NodeId::new(10),
            battery: NodeId::new(1),
            deltaq: NodeId::new(10),
        },
        ..Options::default()
    };
    for e in extra {
        match *e {
            "--json" => o.json = true,
            "csv" => o.csv = true,
            "--summary-only" => (o.summary, o.frames) = (true, false),
            "--no-cache" => o.no_cache = true,
            _ => {}
        }
    }
    o
}

fn pipeline(c: &mut Criterion) {
    let log = log();
    let mut g = c.benchmark_group("pipeline");
    g.throughput(Throughput::Elements(LINES as u64));
    g.sample_size(20);
    for (name, extra) in [
        ("words", &[][..]),
        ("json", &["--json"][..]),
        ("csv", &["--output", "csv"][..]),
        ("summary-only", &["--summary-only"][..]),
        ("words-no-cache", &["--no-cache"][..]),
        ("json-no-cache", &["--json", "--no-cache"][..]),
    ] {
        let opts = options(extra);
        g.bench_function(name, |b| {
            b.iter(|| {
                let r = run(
                    black_box(log.as_bytes()),
                    &mut io::sink(),
                    &mut io::sink(),
                    &opts,
                );
                black_box(r.expect("the pipeline runs"))
            })
        });
    }
    g.finish();
}

fn json_object(c: &mut Criterion) {
    let log = log();
    let opts = options(&["--json"]);
    let roles = opts.roles;
    let learned = pdo_learn::Learned::default();
    // The distinct frames of the log, decoded, with the object we write.
    let mut seen = HashSet::new();
    let lines: Vec<LogLine<'_>> = log
        .lines()
        .filter_map(|l| parse_line(l).ok())
        .filter(|l| seen.insert((l.frame.id().raw(), l.frame.data().to_vec())))
        .collect();
    let decoded: Vec<_> = lines
        .iter()
        .map(|l| {
            let m = Message::decode(&l.frame);
            let fields = m
                .as_ref()
                .ok()
                .and_then(|m| opts.pdos.fields(&l.frame, m, &roles, &learned));
            (m, fields)
        })
        .collect();
    let notes = Notes::default();
    let write_ours = |out: &mut String| {
        for (l, (m, fields)) in lines.iter().zip(&decoded) {
            out.clear();
            let line = FrameLine {
                log: l,
                decoded: m,
                roles: &roles,
                fields: fields.as_ref(),
                notes: &notes,
            };
            json::rest(out, &line);
            black_box(out.len());
        }
    };
    let values: Vec<serde_json::Value> = lines
        .iter()
        .zip(&decoded)
        .map(|(l, (m, fields))| {
            let mut text = String::from("{\"t\":0");
            let line = FrameLine {
                log: l,
                decoded: m,
                roles: &roles,
                fields: fields.as_ref(),
                notes: &notes,
            };
            json::rest(&mut text, &line);
            serde_json::from_str(&text).expect("our JSON parses")
        })
        .collect();
    let mut g = c.benchmark_group("json_object");
    g.throughput(Throughput::Elements(lines.len() as u64));
    g.bench_function("ours", |b| {
        let mut out = String::new();
        b.iter(|| write_ours(&mut out))
    });
    g.bench_function("serde_json", |b| {
        let mut out: Vec<u8> = Vec::new();
        b.iter(|| {
            for v in &values {
                out.clear();
                serde_json::to_writer(&mut out, v).expect("writes");
                black_box(out.len());
            }
        })
    });
    g.finish();
}

fn bus_load(c: &mut Criterion) {
    use canopen_codec::log::bus_load::{BusLoad, FrameBits};
    let log = log();
    let frames: Vec<LogLine<'_>> = log.lines().filter_map(|l| parse_line(l).ok()).collect();
    let mut g = c.benchmark_group("bus_load");
    g.throughput(Throughput::Elements(frames.len() as u64));
    g.sample_size(20);
    g.bench_function("frame_bits", |b| {
        b.iter(|| {
            frames
                .iter()
                .map(|l| u64::from(FrameBits::of(black_box(&l.frame)).nominal.stuffed))
                .sum::<u64>()
        })
    });
    g.bench_function("bus_load", |b| {
        b.iter(|| {
            let mut load = BusLoad::new(None);
            for l in &frames {
                load.frame(l.timestamp, black_box(&l.frame));
            }
            black_box(load.mean_percent())
        })
    });
    g.finish();
}

criterion_group!(benches, pipeline, json_object, bus_load);
criterion_main!(benches);
