//! canopen-codec beside canopen-rs 0.6.1, zencan-common 0.0.5 and
//! oze-canopen 0.1.0 on the same frames (see the package's src/lib.rs for
//! the streams and adapters).
//!
//! `cargo bench` in benches/peers. Criterion times one pass over each
//! stream per crate; at the end a table gives ns per frame (criterion's
//! median over the stream's frame count) and the ratio to the copy
//! baseline. Each result is left in place and its address handed to
//! `black_box` (`black_box(&result)`): passing the value itself would copy
//! it out in 16-byte loads right after the decoder's stores, a
//! store-forwarding stall that measures the harness, not the decoder, and
//! weighs on each crate by how its compiler happened to split the stores.
//! The `*_by_value` groups time the same streams with each result
//! returned by value into `black_box` (`black_box(result)`), which is how a
//! caller uses a decoder, stall and all.
//! Short runs while iterating:
//! `cargo bench -- --warm-up-time 1 --measurement-time 2`.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use canopen_codec_peers as peers;
use criterion::{Criterion, Throughput};
use peers::{Stream, Streams};

const CRATES: [&str; 5] = [
    "copy",
    "canopen-codec",
    "canopen-rs",
    "zencan-common",
    "oze-canopen",
];

fn out_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("target")
        .join("criterion")
}

/// Hands a decoder's result to the optimiser's barrier: its address
/// (`BY_VALUE` false, the result left in place) or the value itself.
#[inline(always)]
fn sink<const BY_VALUE: bool, T>(result: T) {
    if BY_VALUE {
        black_box(result);
    } else {
        black_box(&result);
    }
}

fn bench_stream<const BY_VALUE: bool>(c: &mut Criterion, name: &str, s: &Stream) {
    let mut g = c.benchmark_group(name);
    g.throughput(Throughput::Elements(s.len() as u64));
    g.bench_function("copy", |b| {
        b.iter(|| {
            for f in &s.ours {
                sink::<BY_VALUE, _>(peers::copy(black_box(f)));
            }
        })
    });
    g.bench_function("canopen-codec", |b| {
        b.iter(|| {
            for f in &s.ours {
                sink::<BY_VALUE, _>(peers::ours(black_box(f)));
            }
        })
    });
    g.bench_function("canopen-rs", |b| {
        b.iter(|| {
            for f in &s.canopen_rs {
                sink::<BY_VALUE, _>(peers::canopen_rs(black_box(f)));
            }
        })
    });
    g.bench_function("zencan-common", |b| {
        b.iter(|| {
            for f in &s.zencan {
                sink::<BY_VALUE, _>(peers::zencan(black_box(f)));
            }
        })
    });
    g.bench_function("oze-canopen", |b| {
        b.iter(|| {
            for f in &s.oze {
                sink::<BY_VALUE, _>(peers::oze(black_box(f)));
            }
        })
    });
    g.finish();
}

fn bench_pdo(c: &mut Criterion, s: &Stream) {
    let ours = peers::OurMappings::new();
    let mut theirs = peers::CanopenRsPdo::new();
    let mut g = c.benchmark_group("pdo_unpack");
    g.throughput(Throughput::Elements(s.len() as u64));
    g.bench_function("canopen-codec", |b| {
        b.iter(|| {
            for f in &s.ours {
                black_box(peers::ours_pdo(&ours, black_box(f)));
            }
        })
    });
    g.bench_function("canopen-rs", |b| {
        b.iter(|| {
            for f in &s.canopen_rs {
                black_box(peers::canopen_rs_pdo(&mut theirs, black_box(f)));
            }
        })
    });
    g.finish();
}

/// Criterion's median for one bench, in ns per iteration.
fn median_ns(group: &str, bench: &str) -> Option<f64> {
    let path = out_dir()
        .join(group)
        .join(bench)
        .join("new")
        .join("estimates.json");
    let text = std::fs::read_to_string(path).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    v.get("median")?.get("point_estimate")?.as_f64()
}

fn main() {
    let streams = Streams::load();
    if !streams.real {
        eprintln!(
            "peers bench: the real capture {} is not in {}; the mixed and heartbeat \
             streams are our own recorded session (tests/data/virtual-session.log)",
            peers::CAPTURE,
            peers::captures_dir().display()
        );
    }
    let rows: [(&str, &str, &Stream); 7] = [
        ("mixed", "real capture, mixed", &streams.mixed),
        ("sdo_upload", "1000-byte SDO upload", &streams.sdo_upload),
        ("heartbeats", "heartbeats only", &streams.heartbeats),
        ("mixed_by_value", "mixed, result by value", &streams.mixed),
        (
            "sdo_upload_by_value",
            "SDO upload, result by value",
            &streams.sdo_upload,
        ),
        (
            "heartbeats_by_value",
            "heartbeats, result by value",
            &streams.heartbeats,
        ),
        ("pdo_unpack", "decode + unpack PDOs", &streams.mixed),
    ];
    let mut c = Criterion::default()
        .output_directory(&out_dir())
        .configure_from_args();
    for (name, _, s) in &rows[..3] {
        bench_stream::<false>(&mut c, name, s);
    }
    for (name, _, s) in &rows[3..6] {
        bench_stream::<true>(&mut c, name, s);
    }
    bench_pdo(&mut c, &streams.mixed);
    c.final_summary();

    // The table: ns per frame, and (x) the ratio to the copy baseline.
    println!();
    println!(
        "ns per frame (criterion median / frames); (x) = ratio to the copy baseline{}",
        if streams.real {
            ""
        } else {
            " [fallback: our own session, not the real capture]"
        }
    );
    print!("| {:<34} |", "stream");
    for k in CRATES {
        print!(" {k:>15} |");
    }
    println!();
    print!("|{}|", "-".repeat(36));
    for _ in CRATES {
        print!("{}|", "-".repeat(17));
    }
    println!();
    for (group, label, s) in rows {
        let n = s.len() as f64;
        let per = |k: &str| median_ns(group, k).map(|t| t / n);
        let floor = per("copy");
        print!("| {:<34} |", format!("{label}, {} frames", s.len()));
        for k in CRATES {
            let cell = match (per(k), floor) {
                (Some(t), Some(f)) if k != "copy" => format!("{t:.2} ({:.1}x)", t / f),
                (Some(t), _) => format!("{t:.2}"),
                (None, _) => "-".to_string(),
            };
            print!(" {cell:>15} |");
        }
        println!();
    }
}
