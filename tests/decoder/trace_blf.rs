//! Vector BLF through the public API: files with stored and zlib
//! containers (flate2 as the inflater, as the decoder program does) read
//! in any chunks, against the same frames as candump lines; and the
//! `canopen-decode` program on BLF files (feature `cli`): the same
//! decoded lines as for the candump log of the same frames, detection by
//! the LOGG signature, truncated files and files with no frame.

use crate::blf_support;

use blf_support::*;
use canopen_codec::trace::blf::{BlfError, BlfEvent, BlfReader, Compression};
use canopen_codec::trace::RxTx;
use canopen_codec::{CanFrame, CanId, Timestamp};

const START: [u16; 8] = [2025, 9, 4, 4, 3, 14, 13, 603];
const START_US: u64 = 1_756_955_653_603_000;

/// A realistic mix: heartbeats, PDOs, an SDO exchange, a remote frame, a
/// 29-bit frame, at times 0, 1 ms, 2 ms, ...
fn frames() -> Vec<(u64, CanFrame)> {
    let std = |id, d: &[u8]| CanFrame::standard(id, d).unwrap();
    let base = [
        std(0x70A, &[0x05]),
        std(0x18A, &[0x74, 0x13, 0x45, 0x4E, 0x70, 0, 0, 0]),
        std(0x60A, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
        std(0x58A, &[0x43, 0x18, 0x10, 0x01, 0x10, 0x01, 0, 0]),
        CanFrame::remote(CanId::Standard(0x70A), 1).unwrap(),
        CanFrame::new(CanId::Extended(0x18DA_F110), &[1, 2]).unwrap(),
        std(0x080, &[]),
    ];
    (0..700u64)
        .map(|i| (i * 1000, base[(i % 7) as usize]))
        .collect()
}

/// A frame read: its time, direction and frame.
type Read = (Option<Timestamp>, RxTx, CanFrame);

/// Reads `file` in chunks of `chunk` bytes, inflating zlib containers.
fn read(file: &[u8], chunk: usize) -> (Vec<Read>, Result<(), BlfError>) {
    let mut r = BlfReader::new();
    let mut z = flate2::Decompress::new(true);
    let mut out = Vec::new();
    let mut buf = vec![0u8; 4096];
    for mut piece in file.chunks(chunk) {
        while let Some(e) = match r.read(&mut piece) {
            Ok(e) => e,
            Err(e) => return (out, Err(e)),
        } {
            match e {
                BlfEvent::ContainerStart {
                    compression: Compression::Zlib,
                    ..
                } => z.reset(true),
                BlfEvent::Compressed(mut c) => loop {
                    let (i, o) = (z.total_in(), z.total_out());
                    let status = z
                        .decompress(c, &mut buf, flate2::FlushDecompress::None)
                        .unwrap();
                    let used = (z.total_in() - i) as usize;
                    let made = (z.total_out() - o) as usize;
                    c = &c[used..];
                    let mut inflated = &buf[..made];
                    while let Some(e) = match r.read_inflated(&mut inflated) {
                        Ok(e) => e,
                        Err(e) => return (out, Err(e)),
                    } {
                        if let BlfEvent::Frame(f) = e {
                            out.push((f.timestamp, f.direction, f.frame));
                        }
                    }
                    if status == flate2::Status::StreamEnd
                        || (used == 0 && made == 0)
                        || (c.is_empty() && made < buf.len())
                    {
                        break;
                    }
                },
                BlfEvent::Frame(f) => out.push((f.timestamp, f.direction, f.frame)),
                _ => {}
            }
        }
    }
    let end = r.finish();
    (out, end)
}

#[test]
fn stored_and_zlib_files_read_the_frames_written_whatever_the_chunks() {
    let frames = frames();
    let objects = can_objects(&frames);
    for zlib in [false, true] {
        // Containers of 1000 bytes: CAN objects of 48 bytes straddle them.
        let file = file(START, &objects, 1000, zlib);
        for chunk in [1, 17, 4096, file.len()] {
            let (got, end) = read(&file, chunk);
            assert_eq!(end, Ok(()), "zlib {zlib} chunk {chunk}");
            assert_eq!(got.len(), frames.len());
            for ((t, dir, f), (us, want)) in got.iter().zip(&frames) {
                assert_eq!(
                    (*t, *dir, f),
                    (Some(Timestamp::from_micros(START_US + us)), RxTx::Rx, want)
                );
            }
        }
    }
}

#[test]
fn v2_objects_and_ten_microsecond_times_in_zlib_containers() {
    let f = CanFrame::standard(0x70A, &[0x7F]).unwrap();
    let mut objects = object(
        2,
        86,
        TEN_US,
        250,
        &[can_body(&f, true), vec![0; 8]].concat(),
    );
    objects.extend(object(2, 1, NS, 3_000_400, &can_body(&f, false)));
    let file = file([0; 8], &objects, 50, true);
    let (got, end) = read(&file, 7);
    assert_eq!(end, Ok(()));
    assert_eq!(
        got,
        [
            (Some(Timestamp::from_micros(2500)), RxTx::Tx, f),
            (Some(Timestamp::from_micros(3000)), RxTx::Rx, f)
        ]
    );
}

#[test]
fn lying_zlib_sizes_and_truncated_files_are_errors() {
    let objects = can_objects(&frames()[..10]);
    let good = file(START, &objects, 10_000, true);
    // The first container's declared uncompressed size (bytes 168..172:
    // after the file header and the container's base header and method)
    // one more, one less than the truth.
    for delta in [1i64, -1] {
        let mut bad = good.clone();
        let declared = u32::from_le_bytes(bad[168..172].try_into().unwrap()) as i64 + delta;
        bad[168..172].copy_from_slice(&(declared as u32).to_le_bytes());
        let (_, end) = read(&bad, 64);
        assert!(
            matches!(end, Err(BlfError::InflatedSizeMismatch { .. })),
            "{delta}: {end:?}"
        );
    }
    // The last cut is inside the last container whatever its padding (at
    // most 3 bytes, which may end a file).
    for cut in [100, 150, 170, good.len() - 4] {
        let (_, end) = read(&good[..cut], 64);
        assert!(
            matches!(end, Err(BlfError::Truncated(_))),
            "cut {cut}: {end:?}"
        );
    }
}

#[cfg(feature = "cli")]
mod program {
    use super::*;
    use std::process::Command;

    fn decode(args: &[&str]) -> std::process::Output {
        Command::new(env!("CARGO_BIN_EXE_canopen-decode"))
            .args(args)
            .output()
            .unwrap()
    }

    fn tmp(name: &str, bytes: &[u8]) -> String {
        let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        path.display().to_string()
    }

    /// The same frames as a BLF (stored, zlib) and as a candump log decode
    /// to the same JSON lines (the BLF's frames are received: the log says
    /// so with python-can's ` R` flag, and both give `"rxtx":"rx"`).
    #[test]
    fn blf_decodes_as_the_candump_log_of_the_same_frames() {
        let frames = frames();
        let log: String = frames
            .iter()
            .map(|(us, f)| {
                let t = START_US + us;
                format!("({}.{:06}) can0 {f} R\n", t / 1_000_000, t % 1_000_000)
            })
            .collect();
        let text = tmp("same-frames.log", log.as_bytes());
        let want = decode(&["--json", "--charger-node", "10", &text]);
        assert!(want.status.success());
        let objects = can_objects(&frames);
        for (name, zlib) in [("stored.blf", false), ("zlib.blf", true)] {
            let blf = tmp(name, &file(START, &objects, 2000, zlib));
            for args in [
                vec!["--json", "--charger-node", "10", &blf],
                vec!["--json", "--charger-node", "10", "--format", "blf", &blf],
            ] {
                let got = decode(&args);
                assert!(
                    got.status.success(),
                    "{}",
                    String::from_utf8_lossy(&got.stderr)
                );
                assert_eq!(
                    String::from_utf8_lossy(&got.stdout),
                    String::from_utf8_lossy(&want.stdout),
                    "{name}"
                );
            }
        }
    }

    #[test]
    fn fd_error_and_unknown_objects_are_reported_and_counted() {
        let f = CanFrame::standard(0x70A, &[0x05]).unwrap();
        let mut objects = object(1, 100, NS, 1, &[0; 84]);
        objects.extend(object(1, 73, NS, 2, &[0; 32]));
        objects.extend(object(1, 65, NS, 3, b"text"));
        objects.extend(object(1, 1, NS, 4, &can_body(&f, false)));
        let o = decode(&[&tmp("mixed.blf", &file(START, &objects, 64, true))]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        assert!(
            err.contains("object 1: CanFd not decoded: object type 100"),
            "{err}"
        );
        assert!(
            err.contains("object 2: ErrorFrame not decoded: object type 73"),
            "{err}"
        );
        assert!(err.contains("1 CAN FD frame(s), 1 error frame(s)"), "{err}");
        assert!(err.contains("1 other BLF object(s) skipped"), "{err}");
        assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 1);
        // The bus load: the error object's 17 bits beside 70A#05's 57 (55
        // and 2 stuff bits); the FD object, whose frame the reader does not
        // give, counted beside the load.
        let blf = tmp("mixed-load.blf", &file(START, &objects, 64, true));
        let o = decode(&["--json", "--summary-only", &blf]);
        let out = String::from_utf8_lossy(&o.stdout);
        let summary: serde_json::Value = out
            .lines()
            .filter_map(|l| serde_json::from_str(l).ok())
            .find(|v: &serde_json::Value| v["kind"] == "summary")
            .expect("a summary");
        let b = &summary["bus_load"];
        assert_eq!(
            (b["frames"].as_u64(), b["error_frames"].as_u64()),
            (Some(2), Some(1))
        );
        assert_eq!(
            (b["fd_frames"].as_u64(), b["fd_frames_not_in_load"].as_u64()),
            (Some(0), Some(1))
        );
        let share = b["error_frames_share_percent"].as_f64().unwrap();
        assert!((share - 17.0 * 100.0 / 74.0).abs() < 1e-9, "{share}");
    }

    #[test]
    fn no_frame_truncated_and_not_blf_files_exit_non_zero() {
        let objects = object(1, 65, NS, 3, b"text");
        let o = decode(&[&tmp("no-frame.blf", &file(START, &objects, 64, false))]);
        assert_eq!(o.status.code(), Some(1));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("none of the 1 object(s) is a CAN frame (read as blf)"),
            "{err}"
        );
        let good = file(START, &can_objects(&frames()[..3]), 64, true);
        let o = decode(&[&tmp("truncated.blf", &good[..good.len() - 5])]);
        assert_eq!(o.status.code(), Some(1));
        assert!(String::from_utf8_lossy(&o.stderr).contains("the file ends inside"));
        let o = decode(&["--format", "blf", &tmp("text.log", b"(1.0) can0 70A#05\n")]);
        assert_eq!(o.status.code(), Some(1));
        assert!(String::from_utf8_lossy(&o.stderr).contains("not a BLF file"));
    }
}
