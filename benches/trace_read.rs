//! Reading the same frames from a trace, per frame: as candump `-L` text
//! (`trace::LineParser`), and as Vector BLF (`trace::blf::BlfReader`) with
//! stored containers and with zlib ones (inflated with flate2, as
//! `canopen-decode` does), the file fed in 64 KiB chunks as a program
//! reads it. 20 000 frames of a CANopen mix (heartbeats, PDOs, SDO, SYNC,
//! a remote and a 29-bit frame) with varying data, times 1 ms apart,
//! containers of 128 KiB (python-can's `BLFWriter` size).
//!
//! `cargo bench --bench trace_read`. Throughput is in frames.

use std::hint::black_box;

use canopen_codec::trace::blf::{BlfEvent, BlfReader, BlfWriter, Compression, Deflate};
use canopen_codec::trace::{Format, LineParser, Record};
use canopen_codec::{CanFrame, CanId};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

const N: u64 = 20_000;
const START_US: u64 = 1_756_955_653_603_000;
const CHUNK: usize = 64 * 1024;

fn frames() -> Vec<(u64, CanFrame)> {
    (0..N)
        .map(|i| {
            let b = (i as u8).wrapping_mul(37);
            let f = match i % 8 {
                0 => CanFrame::standard(0x70A, &[0x05]),
                1 => CanFrame::standard(0x18A, &[b, 0x13, 0x45, b ^ 0x4E, 0x70, 0, 0, b]),
                2 => CanFrame::standard(0x28A, &[b, b, 1, 2]),
                3 => CanFrame::standard(0x60A, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
                4 => CanFrame::standard(0x58A, &[0x43, 0x18, 0x10, 0x01, b, 0x01, 0, 0]),
                5 => CanFrame::remote(CanId::Standard(0x70A), 1),
                6 => CanFrame::new(CanId::Extended(0x18DA_F110), &[b, 2]),
                _ => CanFrame::standard(0x080, &[]),
            };
            (i * 1000, f.unwrap())
        })
        .collect()
}

fn candump(frames: &[(u64, CanFrame)]) -> String {
    frames
        .iter()
        .map(|(us, f)| {
            let t = START_US + us;
            format!("({}.{:06}) can0 {f}\n", t / 1_000_000, t % 1_000_000)
        })
        .collect()
}

/// Reads a BLF file, counting frames (zlib containers inflated).
fn read_blf(file: &[u8], zlib: &mut flate2::Decompress, buf: &mut [u8]) -> u64 {
    let mut r = BlfReader::new();
    let mut n = 0;
    for mut chunk in file.chunks(CHUNK) {
        while let Some(e) = r.read(&mut chunk).unwrap() {
            match e {
                BlfEvent::Frame(f) => {
                    black_box(f);
                    n += 1;
                }
                BlfEvent::ContainerStart {
                    compression: Compression::Zlib,
                    ..
                } => zlib.reset(true),
                BlfEvent::Compressed(mut z) => loop {
                    let (i, o) = (zlib.total_in(), zlib.total_out());
                    let status = zlib
                        .decompress(z, buf, flate2::FlushDecompress::None)
                        .unwrap();
                    let used = (zlib.total_in() - i) as usize;
                    let made = (zlib.total_out() - o) as usize;
                    z = &z[used..];
                    let mut inflated = &buf[..made];
                    while let Some(e) = r.read_inflated(&mut inflated).unwrap() {
                        if let BlfEvent::Frame(f) = e {
                            black_box(f);
                            n += 1;
                        }
                    }
                    if status == flate2::Status::StreamEnd
                        || (used == 0 && made == 0)
                        || (z.is_empty() && made < buf.len())
                    {
                        break;
                    }
                },
                _ => {}
            }
        }
    }
    r.finish().unwrap();
    n
}

/// flate2's zlib for the writer's containers, as python-can compresses them.
struct Zlib;

impl Deflate for Zlib {
    fn deflate(&mut self, payload: &[u8], out: &mut Vec<u8>) {
        use std::io::Write;
        let mut z = flate2::write::ZlibEncoder::new(out, flate2::Compression::default());
        z.write_all(payload).unwrap();
        z.finish().unwrap();
    }
}

fn trace_read(c: &mut Criterion) {
    let frames = frames();
    let text = candump(&frames);
    let start = [2025, 9, 4, 4, 3, 14, 13, 603];
    let mut writer = BlfWriter::new(Some(start), 128 * 1024);
    for (us, f) in &frames {
        writer.push(*us, f, false);
    }
    let stored = writer.clone().finish(None);
    let packed = writer.finish(Some(&mut Zlib));
    let mut zlib = flate2::Decompress::new(true);
    let mut buf = vec![0u8; CHUNK];
    assert_eq!(read_blf(&stored, &mut zlib, &mut buf), N);
    assert_eq!(read_blf(&packed, &mut zlib, &mut buf), N);
    eprintln!(
        "trace_read: {N} frames: candump {} B, BLF stored {} B, BLF zlib {} B",
        text.len(),
        stored.len(),
        packed.len()
    );
    let mut g = c.benchmark_group("trace_read");
    g.throughput(Throughput::Elements(N));
    g.bench_function("candump_text", |b| {
        b.iter(|| {
            let mut p = LineParser::new(Format::CandumpLog);
            let mut n = 0u64;
            for line in black_box(&text).lines() {
                if let Ok(Record::Frame(f)) = p.parse(line) {
                    black_box(f);
                    n += 1;
                }
            }
            assert_eq!(n, N);
        })
    });
    g.bench_function("blf_stored", |b| {
        b.iter(|| assert_eq!(read_blf(black_box(&stored), &mut zlib, &mut buf), N))
    });
    g.bench_function("blf_zlib", |b| {
        b.iter(|| assert_eq!(read_blf(black_box(&packed), &mut zlib, &mut buf), N))
    });
    g.finish();
}

criterion_group!(benches, trace_read);
criterion_main!(benches);
