//! Reading a real EDS (CiA 306): the Delta-Q IQ3K3 charger's description,
//! about 115 KB and 260 objects, from the folder of EDS files CI keeps
//! beside the checkout (`$CANOPEN_EDS_DIR`, default `../<shared folder>/eds`;
//! the name is split so that the literal is not in tracked files).
//!
//! Run with `cargo bench --bench eds`. Groups (throughput in bytes):
//!
//! - `eds/copy_baseline`: copy the file's bytes into a fresh `Vec`, the
//!   machine's floor for touching them at all;
//! - `eds/parse_deltaq`: `parse_bytes` of the whole file into the model;
//! - `eds/parse_write_deltaq`: the same and `write` it back.
//!
//! When the folder is absent the bench says so and measures nothing.

use std::hint::black_box;
use std::path::PathBuf;

use canopen_codec::eds::{parse_bytes, write};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn deltaq_eds() -> Option<Vec<u8>> {
    let dir = match std::env::var_os("CANOPEN_EDS_DIR") {
        Some(dir) => PathBuf::from(dir),
        None => PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../",
            "sha",
            "red",
            "/eds"
        )),
    };
    let path = dir.join("deltaq-iq3k3-charger.eds");
    match std::fs::read(&path) {
        Ok(bytes) => Some(bytes),
        Err(_) => {
            eprintln!("skipped: {} is absent", path.display());
            None
        }
    }
}

fn bench(c: &mut Criterion) {
    let Some(bytes) = deltaq_eds() else { return };
    let mut g = c.benchmark_group("eds");
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    g.bench_function("copy_baseline", |b| b.iter(|| black_box(bytes.to_vec())));
    g.bench_function("parse_deltaq", |b| {
        b.iter(|| parse_bytes(black_box(&bytes)).expect("the Delta-Q EDS parses"))
    });
    g.bench_function("parse_write_deltaq", |b| {
        b.iter(|| write(&parse_bytes(black_box(&bytes)).expect("the Delta-Q EDS parses")))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
