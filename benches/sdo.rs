//! Whole SDO transfers through an in-memory client/server pair: a 1000-byte
//! segmented upload and download (143 segments each), with a fixed-buffer
//! object dictionary (no allocation anywhere in the loop); and block versus
//! segmented transfer of 1000 bytes and 64 KiB, per byte (block transfer
//! sends about half the frames: no request per segment).
//!
//! cargo bench --bench sdo
//!
//! The 1000-byte pair is `common/sdo_pair.rs`, shared with the `sdo_count`
//! harness that callgrind counts instructions per segment with.

use std::hint::black_box;
use std::time::Duration;

use canopen_codec::machine::Machine;
use canopen_codec::sdo::{Client, ClientConfig, ClientEvent, Server, ServerConfig};
use canopen_codec::{NodeId, Timestamp};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

mod common;
use common::sdo_pair;

use sdo_pair::{download, pair, upload, DomainOd, LEN, SEGMENTS};

const BIG: usize = 64 * 1024;
static BIG_DATA: [u8; BIG] = [0xA5; BIG];

/// One domain at 2000h:00 of up to 64 KiB (allocated once, before the loop).
type BigOd = DomainOd<Vec<u8>>;

type BigPair = (Client<&'static [u8]>, Server<BigOd>);

fn big_pair(len: usize) -> BigPair {
    let node = NodeId::new(1).unwrap();
    (
        Client::new(ClientConfig::for_server(node)),
        Server::new(
            ServerConfig::for_node(node),
            DomainOd::new(vec![0x5A; BIG], len),
        ),
    )
}

/// Runs the started transfer to its end, delivering every frame as soon
/// as it is sent (a block sender sends a whole sub-block per drain);
/// returns the bytes uploaded.
fn run_any((client, server): &mut BigPair) -> usize {
    let now = Timestamp::ZERO;
    let mut got = 0;
    let mut take = |client: &mut Client<&'static [u8]>| {
        while let Some(e) = client.poll_event() {
            if let ClientEvent::UploadData { data, .. } = e {
                got += black_box(data.as_slice()).len();
            }
        }
    };
    loop {
        let mut moved = false;
        while let Some(req) = client.poll_transmit() {
            moved = true;
            server.handle_frame(now, &req);
            while server.poll_event().is_some() {}
            while let Some(resp) = server.poll_transmit() {
                client.handle_frame(now, &resp);
                take(client);
            }
        }
        while let Some(resp) = server.poll_transmit() {
            moved = true;
            client.handle_frame(now, &resp);
            take(client);
        }
        if !moved {
            break;
        }
    }
    got
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
                p.0.start_upload(Timestamp::ZERO, 0x2000, 0).unwrap();
                assert_eq!(run_any(&mut p), len);
            })
        });
        g.bench_function("block_upload", |b| {
            let mut p = big_pair(len);
            b.iter(|| {
                p.0.start_block_upload(Timestamp::ZERO, 0x2000, 0).unwrap();
                assert_eq!(run_any(&mut p), len);
            })
        });
        g.bench_function("segmented_download", |b| {
            let mut p = big_pair(len);
            b.iter(|| {
                p.0.start_download(Timestamp::ZERO, 0x2000, 0, data)
                    .unwrap();
                run_any(&mut p);
                assert_eq!(p.1.od().len, len);
            })
        });
        g.bench_function("block_download", |b| {
            let mut p = big_pair(len);
            b.iter(|| {
                p.0.start_block_download(Timestamp::ZERO, 0x2000, 0, data)
                    .unwrap();
                run_any(&mut p);
                assert_eq!(p.1.od().len, len);
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
