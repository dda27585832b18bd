//! PDO packing and unpacking.
//!
//! Run with `cargo bench --bench pdo`. Groups:
//!
//! - `pdo/copy_baseline`: copy an 8-byte payload into a black-boxed sink,
//!   the machine's floor for touching a PDO at all;
//! - `pdo/pack_8x8`, `pdo/unpack_8x8`: an 8-entry, 64-bit mapping
//!   (widths 4, 12, 1, 7, 16, 3, 13, 8: fields spill across bytes), typed
//!   values in, raw bits out;
//! - `pdo/deltaq_tpdo3_typed`: the Delta-Q charger TPDO 3 (2002h/16,
//!   2100h/16, 2006h/16) unpacked into `ChargingCurrent`,
//!   `BatteryVoltageLegacy` and `ExtendedChargeStatus`.
//!
//! Throughput is in PDOs (elements).

use std::hint::black_box;

use canopen_codec::pdo::{MappingEntry, PdoMapping, Value};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

mod common;
use common::tpdo3;

const WIDTHS: [u8; 8] = [4, 12, 1, 7, 16, 3, 13, 8];

fn mapping_8x8() -> PdoMapping {
    let mut entries = [MappingEntry::default(); 8];
    for (i, (e, bits)) in entries.iter_mut().zip(WIDTHS).enumerate() {
        *e = MappingEntry::new(0x2000, i as u8 + 1, bits);
    }
    PdoMapping::new(&entries).expect("64-bit mapping")
}

fn pdo(c: &mut Criterion) {
    let m8 = mapping_8x8();
    let values = [
        Value::Unsigned(3),
        Value::Signed(-1071),
        Value::Boolean(true),
        Value::Signed(-64),
        Value::Unsigned(0xBEEF),
        Value::Signed(-4),
        Value::Unsigned(0x1ABC),
        Value::Unsigned(0xFF),
    ];
    let packed = m8.pack(&values).expect("values fit");
    let tpdo3 = tpdo3::mapping();
    let frame = tpdo3::FRAME;
    assert!(tpdo3::decode(&tpdo3, &frame).is_some());

    let mut g = c.benchmark_group("pdo");
    g.throughput(Throughput::Elements(1));
    g.bench_function("copy_baseline", |b| {
        b.iter(|| {
            let mut out = [0u8; 8];
            out.copy_from_slice(black_box(packed.as_slice()));
            black_box(out)
        })
    });
    g.bench_function("pack_8x8", |b| {
        b.iter(|| black_box(black_box(&m8).pack(black_box(&values))))
    });
    g.bench_function("unpack_8x8", |b| {
        b.iter(|| {
            let u = black_box(&m8).unpack(black_box(packed.as_slice()));
            black_box(u.map(|u| u.signed(7)))
        })
    });
    g.bench_function("deltaq_tpdo3_typed", |b| {
        b.iter(|| black_box(tpdo3::decode(black_box(&tpdo3), black_box(&frame))))
    });
    g.finish();
}

criterion_group!(benches, pdo);
criterion_main!(benches);
