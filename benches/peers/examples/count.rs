//! One adapter over one stream, many times: for instruction counts under
//! `valgrind --tool=callgrind --toggle-collect='*peers*ADAPTER*'`.
//!
//! `cargo run --release --example count -- ADAPTER STREAM [PASSES]` with
//! ADAPTER one of copy, ours, canopen_rs, zencan, oze, ours_pdo,
//! canopen_rs_pdo and STREAM one of mixed, sdo_upload, heartbeats. Prints
//! the frames decoded and the type sizes involved.

use std::hint::black_box;

use canopen_codec_peers as peers;

fn main() {
    let mut args = std::env::args().skip(1);
    let adapter = args.next().unwrap_or_else(|| "ours".into());
    let stream = args.next().unwrap_or_else(|| "mixed".into());
    let passes: usize = args.next().and_then(|p| p.parse().ok()).unwrap_or(100);
    let all = peers::Streams::load();
    let s = match stream.as_str() {
        "mixed" => &all.mixed,
        "sdo_upload" => &all.sdo_upload,
        "heartbeats" => &all.heartbeats,
        other => panic!("unknown stream {other}"),
    };
    let ours_m = peers::OurMappings::new();
    let mut theirs = peers::CanopenRsPdo::new();
    let mut ok = 0usize;
    for _ in 0..passes {
        match adapter.as_str() {
            "copy" => s.ours.iter().for_each(|f| {
                black_box(peers::copy(black_box(f)));
            }),
            "ours" => {
                ok += s
                    .ours
                    .iter()
                    .filter(|f| black_box(peers::ours(f)).is_ok())
                    .count()
            }
            "canopen_rs" => {
                ok += s
                    .canopen_rs
                    .iter()
                    .filter(|f| black_box(peers::canopen_rs(f)).is_ok())
                    .count()
            }
            "zencan" => {
                ok += s
                    .zencan
                    .iter()
                    .filter(|f| black_box(peers::zencan(f)).is_ok())
                    .count()
            }
            "oze" => {
                ok += s
                    .oze
                    .iter()
                    .filter(|f| black_box(peers::oze(f)).is_ok())
                    .count()
            }
            "ours_pdo" => s.ours.iter().for_each(|f| {
                black_box(peers::ours_pdo(&ours_m, f));
            }),
            "canopen_rs_pdo" => s.canopen_rs.iter().for_each(|f| {
                black_box(peers::canopen_rs_pdo(&mut theirs, f));
            }),
            other => panic!("unknown adapter {other}"),
        }
    }
    println!(
        "{adapter} on {stream}: {} frames x {passes} passes, {ok} decoded; sizes: CanFrame {}, Message {}, Result<Message> {}, DecodeError {}, SdoRequest {}, SdoResponse {}",
        s.len(),
        size_of::<canopen_codec::CanFrame>(),
        size_of::<canopen_codec::Message>(),
        size_of::<Result<canopen_codec::Message, canopen_codec::DecodeError>>(),
        size_of::<canopen_codec::DecodeError>(),
        size_of::<canopen_codec::sdo::SdoRequest>(),
        size_of::<canopen_codec::sdo::SdoResponse>(),
    );
}
