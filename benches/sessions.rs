//! Whole charge sessions per second: the scenario bench (`sim::bench`)
//! running an 8-hour charge of a 100 Ah flooded lead-acid pack from 20 %
//! in local mode (the Delta-Q charger, the CiA 418 battery module, the
//! BMS, about 960 000 frames on the simulated bus, the physics every
//! simulated second), and a 30-minute remote charge on a bus losing 5 % of
//! its frames. Criterion's throughput is in sessions (elements) per second.
//!
//! cargo bench --features sim --bench sessions

use std::time::Duration;

use canopen_codec::cia418::BatteryType;
use canopen_codec::deltaq::OperatingMode;
use canopen_codec::sim::bench::{Battery, BusSetup, Expect, Script};
use canopen_codec::sim::DEFAULT_SEED;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn script(mode: OperatingMode, hours: f64, loss: f64) -> Script {
    Script {
        mode,
        algorithm: None,
        no_can_algorithm: None,
        battery: Battery {
            battery_type: BatteryType::from_name("flooded").unwrap(),
            cells: 24,
            capacity_ah: 100.0,
            soc_percent: 20.0,
            temperature_c: 25.0,
        },
        bus: BusSetup {
            loss,
            latency: Duration::ZERO,
            seed: DEFAULT_SEED,
        },
        events: Vec::new(),
        until: Duration::from_secs_f64(hours * 3600.0),
        expect: Expect::default(),
    }
}

fn sessions(c: &mut Criterion) {
    let mut g = c.benchmark_group("session");
    g.throughput(Throughput::Elements(1));
    g.sample_size(10);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(10));
    let whole = script(OperatingMode::Local, 8.0, 0.0);
    g.bench_function("8-hour local charge", |b| {
        b.iter(|| {
            let (_, summary) = whole.run(|_| {}).unwrap();
            assert!(summary.soc > 95.0, "{summary:?}");
        });
    });
    let lossy = script(OperatingMode::Remote, 0.5, 0.05);
    g.bench_function("30-minute remote charge, 5 % loss", |b| {
        b.iter(|| lossy.run(|_| {}).unwrap().1.ah);
    });
    g.finish();
}

criterion_group!(benches, sessions);
criterion_main!(benches);
