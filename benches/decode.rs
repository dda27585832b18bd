//! The hot decode path on the real Delta-Q ICL1500 captures (2235 frames).
//! They are third-party data, not in this repository: the bench reads them
//! from the shared data folder beside the checkout (its `spec` / `captures`
//! folder) or `$CANOPEN_SHARED_DIR`, and falls back to our own recorded
//! session (tests/data/virtual-session.log) when they are absent, saying so.
//!
//! Run with `cargo bench --bench decode`. Groups:
//!
//! - `stream/copy_baseline`: copy every frame of both captures into a
//!   black-boxed sink: the machine's floor for touching the stream at all;
//! - `stream/message_decode`: `Message::decode` on every frame;
//! - `stream/message_encode`: `Message::encode` of the pre-decoded messages;
//! - `single/*`: decode of one frame of each common kind.
//!
//! Throughput is in frames (elements), so criterion prints frames/s; read
//! `message_decode` as a ratio to `copy_baseline`.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use canopen_codec::{CanFrame, CanId, Message};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

const CAPTURES: [&str; 2] = ["deltaq-icl1500-startup.log", "deltaq-icl1500-charging.log"];

/// The captures' folder (see the module docs).
fn captures_dir() -> PathBuf {
    std::env::var_os("CANOPEN_SHARED_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join("shared")
        })
        .join("spec")
        .join("captures")
}

/// Parses one candump log line: `(1756955646.068614) can1 70A#7F`,
/// `12345678#0102` (29-bit), `701#R` / `701#R1` (remote). `None` for blank
/// lines, comments and anything else (CAN FD, error frames).
fn parse_candump_line(line: &str) -> Option<CanFrame> {
    let field = line.split_whitespace().nth(2)?;
    let (id, data) = field.split_once('#')?;
    let raw = u32::from_str_radix(id, 16).ok()?;
    let id = match id.len() {
        3 => CanId::standard(u16::try_from(raw).ok()?)?,
        8 => CanId::extended(raw)?,
        _ => return None,
    };
    if let Some(dlc) = data.strip_prefix('R') {
        let dlc = if dlc.is_empty() { 0 } else { dlc.parse().ok()? };
        return CanFrame::remote(id, dlc).ok();
    }
    if data.len() % 2 != 0 || data.len() > 16 {
        return None;
    }
    let mut bytes = [0u8; 8];
    let n = data.len() / 2;
    for (i, b) in bytes.iter_mut().take(n).enumerate() {
        *b = u8::from_str_radix(data.get(2 * i..2 * i + 2)?, 16).ok()?;
    }
    CanFrame::new(id, &bytes[..n]).ok()
}

fn load_captures() -> Vec<CanFrame> {
    let dir = captures_dir();
    let mut paths: Vec<PathBuf> = CAPTURES.iter().map(|n| dir.join(n)).collect();
    if !paths.iter().all(|p| p.is_file()) {
        eprintln!(
            "decode bench: the real captures are not in {}; using tests/data/virtual-session.log",
            dir.display()
        );
        paths = vec![Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests")
            .join("data")
            .join("virtual-session.log")];
    }
    let mut frames = Vec::new();
    for path in paths {
        let text = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
        let before = frames.len();
        frames.extend(text.lines().filter_map(parse_candump_line));
        assert!(
            frames.len() > before,
            "no frames parsed from {}",
            path.display()
        );
    }
    frames
}

fn frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::standard(id, data).expect("valid bench frame")
}

fn stream(c: &mut Criterion) {
    let frames = load_captures();
    let messages: Vec<Message> = frames
        .iter()
        .map(|f| Message::decode(f).unwrap_or_else(|e| panic!("capture frame {f}: {e}")))
        .collect();
    let mut g = c.benchmark_group("stream");
    g.throughput(Throughput::Elements(frames.len() as u64));
    g.bench_function("copy_baseline", |b| {
        b.iter(|| {
            for f in &frames {
                black_box(*black_box(f));
            }
        })
    });
    g.bench_function("message_decode", |b| {
        b.iter(|| {
            for f in &frames {
                let _ = black_box(Message::decode(black_box(f)));
            }
        })
    });
    g.bench_function("message_encode", |b| {
        b.iter(|| {
            for m in &messages {
                black_box(black_box(m).encode());
            }
        })
    });
    g.finish();
}

fn single(c: &mut Criterion) {
    let cases: [(&str, CanFrame); 6] = [
        ("heartbeat", frame(0x70A, &[0x7F])),
        (
            "tpdo",
            frame(0x18A, &[0x74, 0x13, 0x45, 0x4E, 0x70, 0, 0, 0]),
        ),
        (
            "emcy",
            frame(0x08A, &[0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0]),
        ),
        (
            "sdo_expedited_request",
            frame(0x60A, &[0x23, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0]),
        ),
        (
            "sdo_expedited_response",
            frame(0x58A, &[0x43, 0x18, 0x10, 0x01, 0x5A, 0x03, 0, 0]),
        ),
        (
            "sdo_segment",
            frame(0x58A, &[0x10, b'I', b'C', b'L', b'1', b'5', b'0', b'0']),
        ),
    ];
    let mut g = c.benchmark_group("single");
    g.throughput(Throughput::Elements(1));
    for (name, f) in &cases {
        let m = Message::decode(f).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(m.encode(), *f, "{name} must round-trip");
        g.bench_function(format!("decode/{name}"), |b| {
            b.iter(|| Message::decode(black_box(f)))
        });
        g.bench_function(format!("encode/{name}"), |b| {
            b.iter(|| black_box(&m).encode())
        });
    }
    g.finish();
}

criterion_group!(benches, stream, single);
criterion_main!(benches);
