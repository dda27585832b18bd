//! Hostile files given to `canopen-decode` on its command line, for every
//! binary reader (pcap, pcapng, Vector BLF, ASAM MDF 4) and the line
//! reader: a valid file cut inside its last record, its first 16 bytes
//! alone, gzip-compressed and cut, random bytes, an empty file, a folder
//! with no log, a `.gz` that is not gzip and a path that does not exist.
//! Each ends in an error that says what is wrong and the documented exit
//! status (1 bad input or no frame, an empty input included: a file read
//! as nothing is an error; 2 an I/O or usage error), never a panic; control characters in what is echoed
//! (escape sequences in a bad line, NULs in a block) are escaped.

use std::process::Output;

use canopen_codec::CanFrame;

use crate::blf_support;
use crate::trace_pcap::{decode, gzip, pcap, pcapng, tmp};

/// A file python-can's `MF4Writer` wrote (transposed deflate).
const MF4: &[u8] = include_bytes!("../data/python-can-mf4writer.mf4");

/// The exit status and stderr, after checking that nothing panicked.
fn status(name: &str, o: &Output) -> (Option<i32>, String) {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(
        !err.contains("panicked") && o.status.code() != Some(101),
        "{name}: {err}"
    );
    (o.status.code(), err)
}

/// Deterministic noise (xorshift), so a failure can be replayed.
fn noise(n: usize) -> Vec<u8> {
    let mut x = 0x9E37_79B9_7F4A_7C15u64;
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x as u8
        })
        .collect()
}

#[test]
fn hostile_files_end_in_a_clear_error_never_a_panic() {
    let frames: Vec<(u64, CanFrame)> = (0..200u64)
        .map(|i| {
            let f = if i % 2 == 0 {
                CanFrame::standard(0x70A, &[5]).unwrap()
            } else {
                CanFrame::standard(0x18A, &[1, 2, 3, 4, 5, 6, 7, 8]).unwrap()
            };
            (1_757_000_000_000_000 + i * 1500, f)
        })
        .collect();
    let start = [2025, 9, 4, 4, 3, 14, 13, 603];
    let readers = [
        ("pcap", pcap(&frames, false, false)),
        ("pcapng", pcapng(&frames)),
        (
            "blf",
            blf_support::file(start, &blf_support::can_objects(&frames), 2000, true),
        ),
        ("mf4", MF4.to_vec()),
    ];
    for (format, good) in &readers {
        let o = decode(&[&tmp(&format!("hostile-good.{format}"), good)]);
        assert_eq!(status(format, &o).0, Some(0), "{format}: the valid file");
        // Cut inside its last record or block: the structure error is
        // said ("after packet N: ...") and the status is 1.
        let name = format!("hostile-cut.{format}");
        let (code, err) = status(&name, &decode(&[&tmp(&name, &good[..good.len() - 5])]));
        assert_eq!(code, Some(1), "{name}: {err}");
        assert!(err.contains("after "), "{name}: {err}");
        // Its head alone: no frame, status 1, the format named.
        let name = format!("hostile-head.{format}");
        let (code, err) = status(&name, &decode(&[&tmp(&name, &good[..16])]));
        assert_eq!(code, Some(1), "{name}: {err}");
        assert!(err.contains("is a CAN frame (read as"), "{name}: {err}");
        // gzip-compressed, then cut: an error of the input, status 2.
        let zipped = gzip(good);
        let name = format!("hostile-cut.{format}.gz");
        let (code, err) = status(&name, &decode(&[&tmp(&name, &zipped[..zipped.len() / 2])]));
        assert_eq!(code, Some(2), "{name}: {err}");
        assert!(err.contains("gzip-compressed input: "), "{name}: {err}");
    }
    let cases: [(&str, Vec<u8>, i32, &str); 3] = [
        ("hostile-noise", noise(5000), 1, "no format detected"),
        ("hostile-empty.log", Vec::new(), 1, "the input is empty"),
        (
            "hostile-not.gz",
            [&[0x1F, 0x8B][..], &noise(300)].concat(),
            2,
            "gzip-compressed input: ",
        ),
    ];
    for (name, bytes, want, says) in cases {
        let o = decode(&["--summary", &tmp(name, &bytes)]);
        let (code, err) = status(name, &o);
        assert_eq!(code, Some(want), "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
    }
    // Control characters in what is echoed (a bad line's escape sequences,
    // an MF4 block's NUL bytes) are escaped: they never reach the terminal.
    let mut mf4 = vec![0u8; 4096];
    mf4[..28].copy_from_slice(b"MDF     4.10    hostile\0\0\0\0\0");
    mf4[28..30].copy_from_slice(&410u16.to_le_bytes());
    let cases: [(&str, Vec<u8>, &str); 2] = [
        (
            "hostile-escapes.log",
            b"(1.000000) can0 70A#05\n(2.000000) can0 70A#05\x1b[31mRED\n\x1b]0;t\x07\n".to_vec(),
            "70A#05\\u{1b}[31mRED",
        ),
        ("hostile-nul.mf4", mf4, "is \\u{0}\\u{0}\\u{0}\\u{0}, not"),
    ];
    for (name, bytes, says) in cases {
        let (code, err) = status(name, &decode(&[&tmp(name, &bytes)]));
        assert_eq!(code, Some(1), "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
        assert!(!err.contains(['\x1b', '\x07', '\0']), "{name}: {err:?}");
    }
    let folder = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("hostile-folder");
    std::fs::create_dir_all(&folder).unwrap();
    let missing = folder.join("no-such.log");
    for (path, says) in [(&folder, "no log there"), (&missing, "No such file")] {
        let path = path.display().to_string();
        let (code, err) = status(&path, &decode(&[&path]));
        assert_eq!(code, Some(2), "{path}: {err}");
        assert!(err.contains(says), "{path}: {err}");
    }
}
