//! Reading the same frames from a trace, per frame, through each format's
//! public reader: candump `-L` text (`trace::LineParser`), Vector BLF
//! (`trace::blf::BlfReader`) with stored containers and with zlib ones,
//! pcapng (`trace::pcap::PcapReader`: the SocketCAN link type, one
//! Enhanced Packet Block a frame, as dumpcap writes it) and ASAM MDF 4 bus
//! logging (`trace::mf4::Mf4Reader`) as python-can's `MF4Writer` writes
//! it, uncompressed (`##DT`) and in transposed deflate `##DZ` blocks (zlib
//! inflated with flate2, as `canopen-decode` does). Files are fed in 64 KiB
//! chunks, as a program reads them. Beside them the copy baseline: a
//! memcpy of the candump text, the largest of the inputs.
//!
//! 100 000 frames of a CANopen mix (heartbeats, PDOs, SDO, SYNC, a remote
//! and a 29-bit frame) with varying data, times 1 ms apart. BLF is written
//! by the library's `BlfWriter` (containers of 128 KiB, python-can's
//! `BLFWriter` size), pcapng by the lines below (PCAP Next Generation
//! Dump File Format, sections 4.1 to 4.3), the MF4 files by python-can
//! (`python3` with python-can and asammdf, run in the setup; without them
//! the MF4 rows are left out and the bench says so).
//!
//! `cargo bench --bench trace_read`. Throughput is in frames.

use std::hint::black_box;

use canopen_codec::trace::blf::{BlfEvent, BlfReader, BlfWriter, Compression, Deflate};
use canopen_codec::trace::inflate;
use canopen_codec::trace::mf4::{Mf4Event, Mf4Reader};
use canopen_codec::trace::pcap::{PcapEvent, PcapReader};
use canopen_codec::trace::{Format, LineParser, Record};
use canopen_codec::{CanFrame, CanId};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

const N: u64 = 100_000;
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

/// A pcapng file of the frames: a Section Header Block, one Interface
/// Description Block (link type 227, SocketCAN; microsecond times), one
/// Enhanced Packet Block a frame (the identifier word in network byte
/// order with the EFF and RTR flags, the length, three bytes, the data
/// padded to 8).
fn pcapng(frames: &[(u64, CanFrame)]) -> Vec<u8> {
    fn block(out: &mut Vec<u8>, kind: u32, body: &[u8]) {
        let padded = body.len().div_ceil(4) * 4;
        let length = (12 + padded) as u32;
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(&length.to_le_bytes());
        out.extend_from_slice(body);
        out.resize(out.len() + padded - body.len(), 0);
        out.extend_from_slice(&length.to_le_bytes());
    }
    let mut out = Vec::new();
    let mut shb = 0x1A2B_3C4Du32.to_le_bytes().to_vec();
    shb.extend_from_slice(&[1, 0, 0, 0]);
    shb.extend_from_slice(&[0xFF; 8]);
    block(&mut out, 0x0A0D_0D0A, &shb);
    let mut idb = 227u16.to_le_bytes().to_vec();
    idb.extend_from_slice(&[0, 0]);
    idb.extend_from_slice(&0u32.to_le_bytes());
    block(&mut out, 1, &idb);
    for (us, f) in frames {
        let t = START_US + us;
        let (raw, eff) = match f.id() {
            CanId::Standard(id) => (u32::from(id), 0),
            CanId::Extended(id) => (id, 0x8000_0000),
        };
        let rtr = if f.is_remote() { 0x4000_0000 } else { 0 };
        let mut packet = (raw | eff | rtr).to_be_bytes().to_vec();
        packet.extend_from_slice(&[f.dlc(), 0, 0, 0]);
        packet.extend_from_slice(f.data());
        packet.resize(16, 0);
        let mut epb = 0u32.to_le_bytes().to_vec();
        epb.extend_from_slice(&((t >> 32) as u32).to_le_bytes());
        epb.extend_from_slice(&(t as u32).to_le_bytes());
        epb.extend_from_slice(&16u32.to_le_bytes());
        epb.extend_from_slice(&16u32.to_le_bytes());
        epb.extend_from_slice(&packet);
        block(&mut out, 6, &epb);
    }
    out
}

/// Reads a pcap or pcapng file, counting frames.
fn read_pcap(file: &[u8]) -> u64 {
    let mut r = PcapReader::new();
    let mut n = 0;
    for mut chunk in file.chunks(CHUNK) {
        while let Some(e) = r.read(&mut chunk).unwrap() {
            if let PcapEvent::Frame(f) = e {
                black_box(f);
                n += 1;
            }
        }
    }
    r.finish().unwrap();
    n
}

/// python-can's `MF4Writer` (through asammdf) writing the candump log
/// `argv[1]` to `argv[2]` with compression level `argv[3]`.
const MF4_WRITER: &str = "
import sys, can
with can.MF4Writer(sys.argv[2], compression_level=int(sys.argv[3])) as w:
    for m in can.CanutilsLogReader(sys.argv[1]):
        w.on_message_received(m)
";

/// The frames as MF4 files written by python-can, uncompressed and in
/// transposed deflate blocks; `None` (said on stderr) without python-can.
fn mf4_files(text: &str) -> Option<(Vec<u8>, Vec<u8>)> {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let log = dir.join("trace_read.log");
    std::fs::write(&log, text).ok()?;
    let mut files = Vec::new();
    for level in ["0", "2"] {
        let out = dir.join(format!("trace_read-{level}.mf4"));
        let status = std::process::Command::new("python3")
            .args(["-c", MF4_WRITER])
            .arg(&log)
            .arg(&out)
            .arg(level)
            .status();
        if !status.is_ok_and(|s| s.success()) {
            eprintln!("trace_read: python-can's MF4Writer did not run: no MF4 rows");
            return None;
        }
        files.push(std::fs::read(&out).ok()?);
    }
    let packed = files.pop()?;
    Some((files.pop()?, packed))
}

/// Reads an MF4 file, counting frames.
fn read_mf4(file: &[u8], zlib: &mut inflate::Zlib) -> u64 {
    let mut r = Mf4Reader::new(file).unwrap();
    let mut n = 0;
    while let Some(e) = r.next(zlib).unwrap() {
        if let Mf4Event::Frame(f) = e {
            black_box(f);
            n += 1;
        }
    }
    n
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
    let ng = pcapng(&frames);
    assert_eq!(read_pcap(&ng), N);
    let mut inflater = inflate::Zlib::default();
    let mf4 = mf4_files(&text);
    if let Some((dt, dz)) = &mf4 {
        assert_eq!(read_mf4(dt, &mut inflater), N);
        assert_eq!(read_mf4(dz, &mut inflater), N);
    }
    eprintln!(
        "trace_read: {N} frames: candump {} B, BLF stored {} B, BLF zlib {} B, pcapng {} B, \
         MF4 {:?} B",
        text.len(),
        stored.len(),
        packed.len(),
        ng.len(),
        mf4.as_ref().map(|(dt, dz)| (dt.len(), dz.len()))
    );
    let mut copy = vec![0u8; text.len()];
    let mut g = c.benchmark_group("trace_read");
    g.throughput(Throughput::Elements(N));
    g.bench_function("copy_candump_bytes", |b| {
        b.iter(|| {
            copy.copy_from_slice(black_box(text.as_bytes()));
            black_box(&mut copy);
        })
    });
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
    g.bench_function("pcapng", |b| {
        b.iter(|| assert_eq!(read_pcap(black_box(&ng)), N))
    });
    if let Some((dt, dz)) = &mf4 {
        g.bench_function("mf4_stored", |b| {
            b.iter(|| assert_eq!(read_mf4(black_box(dt), &mut inflater), N))
        });
        g.bench_function("mf4_transposed_deflate", |b| {
            b.iter(|| assert_eq!(read_mf4(black_box(dz), &mut inflater), N))
        });
    }
    g.finish();
}

criterion_group!(benches, trace_read);
criterion_main!(benches);
