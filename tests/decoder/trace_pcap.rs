//! pcap, pcapng and gzip input of the `canopen-decode` program: the real
//! captures rewritten as pcap (either byte order, micro- and nanosecond
//! times) and as pcapng (two interfaces, nanosecond resolution, a block
//! of another type between the packets), and gzip-compressed candump and
//! BLF files, decode to exactly what the candump original decodes to;
//! packets of another link type and CAN FD packets are reported, and a
//! capture with no CAN frame fails.

use std::io::Write;
use std::process::{Command, Output};

use canopen_codec::trace::{LineParser, Record};
use canopen_codec::CanFrame;

use crate::blf_support;
use crate::common::captures::{self, CHARGING, STARTUP};

pub(crate) fn decode(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_canopen-decode"))
        .args(args)
        .output()
        .unwrap()
}

pub(crate) fn tmp(name: &str, bytes: &[u8]) -> String {
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, bytes).unwrap();
    path.display().to_string()
}

/// A SocketCAN packet (`LINKTYPE_CAN_SOCKETCAN`): identifier word in
/// network byte order, length, FD flags, reserved, data padded to 8.
fn socketcan(f: &CanFrame) -> Vec<u8> {
    let mut word = f.id().raw();
    if f.id().is_extended() {
        word |= 0x8000_0000;
    }
    if f.is_remote() {
        word |= 0x4000_0000;
    }
    let mut p = word.to_be_bytes().to_vec();
    p.extend([f.dlc(), 0, 0, 0]);
    p.extend(f.padded_data());
    p
}

/// Fields in one byte order.
fn put(out: &mut Vec<u8>, big: bool, v: u32) {
    out.extend(if big {
        v.to_be_bytes()
    } else {
        v.to_le_bytes()
    });
}

/// A pcap file of `frames` (UNIX microseconds, frame), link type 227.
pub(crate) fn pcap(frames: &[(u64, CanFrame)], big: bool, nanos: bool) -> Vec<u8> {
    let mut f = Vec::new();
    put(&mut f, big, if nanos { 0xA1B2_3C4D } else { 0xA1B2_C3D4 });
    let version = if big { [0, 2, 0, 4] } else { [2, 0, 4, 0] };
    f.extend(version);
    for v in [0, 0, 65_535, 227] {
        put(&mut f, big, v);
    }
    for (us, frame) in frames {
        let frac = us % 1_000_000;
        put(&mut f, big, (us / 1_000_000) as u32);
        put(
            &mut f,
            big,
            if nanos {
                frac as u32 * 1000
            } else {
                frac as u32
            },
        );
        put(&mut f, big, 16);
        put(&mut f, big, 16);
        f.extend(socketcan(frame));
    }
    f
}

/// A little-endian pcapng block.
fn block(out: &mut Vec<u8>, block_type: u32, body: &[u8]) {
    let length = 12 + body.len() as u32;
    put(out, false, block_type);
    put(out, false, length);
    out.extend(body);
    put(out, false, length);
}

/// A pcapng file of `frames`, alternately on two SocketCAN interfaces
/// with nanosecond times, a Name Resolution Block after the first packet.
pub(crate) fn pcapng(frames: &[(u64, CanFrame)]) -> Vec<u8> {
    let mut f = Vec::new();
    let mut shb = 0x1A2B_3C4Du32.to_le_bytes().to_vec();
    shb.extend([1, 0, 0, 0]);
    shb.extend([0xFF; 8]);
    block(&mut f, 0x0A0D_0D0A, &shb);
    // Link type 227, snap length 0, if_tsresol 9, end of options.
    let idb = [227, 0, 0, 0, 0, 0, 0, 0, 9, 0, 1, 0, 9, 0, 0, 0, 0, 0, 0, 0];
    block(&mut f, 1, &idb);
    block(&mut f, 1, &idb);
    for (i, (us, frame)) in frames.iter().enumerate() {
        let ns = us * 1000;
        let mut epb = Vec::new();
        put(&mut epb, false, (i % 2) as u32);
        put(&mut epb, false, (ns >> 32) as u32);
        put(&mut epb, false, ns as u32);
        put(&mut epb, false, 16);
        put(&mut epb, false, 16);
        epb.extend(socketcan(frame));
        block(&mut f, 6, &epb);
        if i == 0 {
            block(&mut f, 4, &[0; 4]);
        }
    }
    f
}

pub(crate) fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

/// The frames of a candump log, with their UNIX microseconds.
fn frames_of(log: &str) -> Vec<(u64, CanFrame)> {
    let mut p = LineParser::auto();
    log.lines()
        .filter_map(|l| match p.parse(l) {
            Ok(Record::Frame(f)) => Some((f.timestamp.unwrap().as_micros(), f.frame)),
            _ => None,
        })
        .collect()
}

fn assert_same(name: &str, got: &Output, want: &Output) {
    assert_eq!(
        got.status.code(),
        want.status.code(),
        "{name}: {}",
        String::from_utf8_lossy(&got.stderr)
    );
    assert!(
        got.stdout == want.stdout,
        "{name}: the decode differs from the candump original's"
    );
}

#[test]
fn the_real_captures_as_pcap_pcapng_and_gzip_decode_as_the_candump_originals() {
    for capture in [STARTUP, CHARGING] {
        let Some(path) = captures::path(capture) else {
            continue;
        };
        let log = std::fs::read_to_string(&path).unwrap();
        let frames = frames_of(&log);
        assert!(frames.len() > 800, "{capture}");
        let original = path.display().to_string();
        let want = decode(&["--json", "--pdo-capture-mapping", &original]);
        assert!(want.status.success());
        let files = [
            ("le-us.pcap", pcap(&frames, false, false), Some("pcap")),
            ("be-us.pcap", pcap(&frames, true, false), Some("pcap")),
            ("le-ns.pcap", pcap(&frames, false, true), None),
            ("be-ns.pcap", pcap(&frames, true, true), None),
            ("two.pcapng", pcapng(&frames), Some("pcapng")),
            ("two.pcapng.gz", gzip(&pcapng(&frames)), None),
            ("log.gz", gzip(log.as_bytes()), Some("candump")),
        ];
        for (name, bytes, format) in files {
            let file = tmp(&format!("{capture}.{name}"), &bytes);
            let got = decode(&["--json", "--pdo-capture-mapping", &file]);
            assert_same(name, &got, &want);
            if let Some(format) = format {
                let got = decode(&["--json", "--pdo-capture-mapping", "--format", format, &file]);
                assert_same(name, &got, &want);
            }
        }
    }
}

#[test]
fn a_gzip_compressed_blf_decodes_as_the_blf() {
    let frames: Vec<(u64, CanFrame)> = (0..300u64)
        .map(|i| (i * 1500, CanFrame::standard(0x70A, &[5]).unwrap()))
        .collect();
    let start = [2025, 9, 4, 4, 3, 14, 13, 603];
    let blf = blf_support::file(start, &blf_support::can_objects(&frames), 2000, true);
    let want = decode(&["--json", &tmp("plain.blf", &blf)]);
    assert!(want.status.success());
    assert_eq!(String::from_utf8_lossy(&want.stdout).lines().count(), 300);
    let got = decode(&["--json", &tmp("plain.blf.gz", &gzip(&blf))]);
    assert_same("blf.gz", &got, &want);
}

#[test]
fn other_link_types_and_fd_frames_are_reported_and_no_frame_fails() {
    let hb = CanFrame::standard(0x70A, &[5]).unwrap();
    let mut file = pcap(&[(1_000_000, hb)], false, false);
    // A CAN FD packet (FDF set, 72 bytes) after the heartbeat.
    file.extend([0, 0, 0, 0, 0, 0, 0, 0, 72, 0, 0, 0, 72, 0, 0, 0]);
    file.extend([0, 0, 0x01, 0x23, 12, 0x04, 0, 0]);
    file.extend([0; 64]);
    let o = decode(&[&tmp("fd.pcap", &file)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("packet 2: CanFd not decoded: link type 227"),
        "{err}"
    );
    assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 1);
    // Ethernet: every packet reported, and no frame is a failure.
    let mut eth = pcap(&[], true, false);
    let at = eth.len() - 4;
    eth[at..].copy_from_slice(&1u32.to_be_bytes());
    for _ in 0..2 {
        eth.extend([0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 14, 0, 0, 0, 14]);
        eth.extend([0xFF; 14]);
    }
    let o = decode(&[&tmp("ethernet.pcap", &eth)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("packet 2: LinkType not decoded: link type 1"),
        "{err}"
    );
    assert!(
        err.contains("2 packet(s) of another link type than SocketCAN"),
        "{err}"
    );
    assert!(
        err.contains("none of the 2 packet(s) is a CAN frame (read as pcap)"),
        "{err}"
    );
    // Cut inside a packet: said, and the frames before it decoded.
    let good = pcap(&[(1_000_000, hb), (2_000_000, hb)], false, false);
    let o = decode(&[&tmp("cut.pcap", &good[..good.len() - 3])]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("after packet 1: the file ends inside a packet record"),
        "{err}"
    );
    assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 1);
}
