//! Whole SDO transfers through an in-memory client/server pair: a 1000-byte
//! segmented upload and download (143 segments each), with a fixed-buffer
//! object dictionary (no allocation anywhere in the loop); and block versus
//! segmented transfer of 1000 bytes and 64 KiB, per byte (block transfer
//! sends about half the frames: no request per segment).
//!
//! cargo bench --bench sdo
//!
//! The pairs are `common/sdo_pair.rs` (client and server on the library's
//! simulated bus), shared with the `sdo_count` harness that callgrind
//! counts instructions per segment with.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

mod common;
use common::sdo_pair;

use sdo_pair::{download, pair, upload, DomainOd, Pair, LEN, SEGMENTS};

const BIG: usize = 64 * 1024;
static BIG_DATA: [u8; BIG] = [0xA5; BIG];

/// A pair over one domain at 2000h:00 of up to 64 KiB (allocated once,
/// before the loop), `len` bytes of it set.
fn big_pair(len: usize) -> Pair<Vec<u8>> {
    Pair::new(DomainOd::new(vec![0x5A; BIG], len))
}

fn block_vs_segmented(c: &mut Criterion) {
    for (name, len) in [("1000_bytes", LEN), ("64_KiB", BIG)] {
        let mut g = c.benchmark_group(format!("sdo_per_byte_{name}"));
        g.throughput(Throughput::Elements(len as u64));
        g.sample_size(20);
        g.measurement_time(Duration::from_secs(3));
        let data = &BIG_DATA[..len];
        g.bench_function("segmented_upload", |b| {
            let mut p = big_pair(len);
            b.iter(|| {
                p.start(|c, now| c.start_upload(now, 0x2000, 0)).unwrap();
                assert_eq!(p.run(), len);
            })
        });
        g.bench_function("block_upload", |b| {
            let mut p = big_pair(len);
            b.iter(|| {
                p.start(|c, now| c.start_block_upload(now, 0x2000, 0))
                    .unwrap();
                assert_eq!(p.run(), len);
            })
        });
        g.bench_function("segmented_download", |b| {
            let mut p = big_pair(len);
            b.iter(|| {
                p.start(|c, now| c.start_download(now, 0x2000, 0, data))
                    .unwrap();
                p.run();
                assert_eq!(p.od().len, len);
            })
        });
        g.bench_function("block_download", |b| {
            let mut p = big_pair(len);
            b.iter(|| {
                p.start(|c, now| c.start_block_download(now, 0x2000, 0, data))
                    .unwrap();
                p.run();
                assert_eq!(p.od().len, len);
            })
        });
        g.finish();
    }
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("sdo_1000_bytes");
    g.throughput(Throughput::Elements(SEGMENTS));
    g.bench_function("upload", |b| {
        let mut p = pair();
        b.iter(|| upload(&mut p))
    });
    g.bench_function("download", |b| {
        let mut p = pair();
        b.iter(|| download(&mut p))
    });
    g.finish();
}

criterion_group!(benches, bench, block_vs_segmented);
criterion_main!(benches);
