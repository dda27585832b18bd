//! ASAM MDF 4 through the public API and the `canopen-decode` program: a
//! file python-can's `MF4Writer` wrote (tests/data/python-can-mf4writer.mf4:
//! transposed deflate, its data frames, a remote frame and an error frame
//! in three data groups) reads as the candump log of the same frames, by
//! detection and with `--format mf4`, on stdin and gzip-compressed as by
//! its path; truncated and wrongly named files exit non-zero with the
//! error of the file's structure.

use canopen_codec::log::input::{frames, Binary, How, Kind, NoInflate, Zlib};

const FILE: &[u8] = include_bytes!("../data/python-can-mf4writer.mf4");

/// The frames python-can wrote, as candump lines, received (` R`, as the
/// MF4's `Dir` 0 says; the error frame at 0.2535 s is not a line).
const LOG: &str = "\
(1757000000.250000) can1 70A#05 R
(1757000000.251000) can1 18A#7413454E70000000 R
(1757000000.252000) can1 60A#4018100100000000 R
(1757000000.253000) can1 58A#4318100110010000 R
(1757000000.254000) can1 70A#R1 R
(1757000000.255000) can1 18DAF110#0102 R
(1757000000.256000) can1 080# R
(1757000000.350000) can1 70A#05 R
";

#[test]
fn the_library_reads_python_cans_file_as_the_candump_log() {
    let mf4 = frames(FILE, How::default(), &mut Zlib::default()).unwrap();
    let log = frames(LOG.as_bytes(), How::default(), &mut NoInflate).unwrap();
    assert_eq!(
        mf4.totals.kind,
        Kind::Binary {
            binary: Binary::Mf4,
            objects: 9,
            skipped: 0
        }
    );
    assert_eq!((mf4.totals.unsupported, mf4.totals.bad), (1, 0));
    let key = |f: &canopen_codec::log::input::Timed| (f.timestamp, f.frame);
    assert_eq!(
        mf4.frames.iter().map(key).collect::<Vec<_>>(),
        log.frames.iter().map(key).collect::<Vec<_>>()
    );
    // The compressed blocks need an inflater.
    let none = frames(FILE, How::default(), &mut NoInflate).unwrap();
    assert_eq!(none.frames.len(), 0);
    assert!(
        none.first_bad
            .as_deref()
            .unwrap()
            .contains("does not inflate"),
        "{:?}",
        none.first_bad
    );
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
        let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
        std::fs::write(&path, bytes).unwrap();
        path.display().to_string()
    }

    #[test]
    fn mf4_decodes_as_the_candump_log_of_the_same_frames() {
        let want = decode(&["--json", &tmp("mf4-same-frames.log", LOG.as_bytes())]);
        assert!(want.status.success());
        let mf4 = tmp("python-can.mf4", FILE);
        for args in [
            vec!["--json", &mf4],
            vec!["--json", "--format", "mf4", &mf4],
        ] {
            let got = decode(&args);
            let err = String::from_utf8_lossy(&got.stderr);
            assert!(got.status.success(), "{err}");
            assert!(
                err.contains("record 5: ErrorFrame not decoded: MF4 bus-logging record"),
                "{err}"
            );
            assert!(err.contains("0 CAN FD frame(s), 1 error frame(s)"), "{err}");
            assert_eq!(
                String::from_utf8_lossy(&got.stdout),
                String::from_utf8_lossy(&want.stdout)
            );
        }
    }

    /// The program's output with `input` on its stdin.
    fn decode_stdin(args: &[&str], input: &[u8]) -> std::process::Output {
        use std::io::Write;
        use std::process::Stdio;
        let mut child = Command::new(env!("CARGO_BIN_EXE_canopen-decode"))
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        let input = input.to_vec();
        // Written beside the reading, so a full pipe cannot stall either.
        let writer = std::thread::spawn(move || stdin.write_all(&input));
        let out = child.wait_with_output().unwrap();
        writer.join().unwrap().unwrap();
        out
    }

    #[test]
    fn mf4_on_stdin_and_gzipped_decodes_as_the_file_by_its_path() {
        use std::io::Write;
        let want = decode(&["--json", &tmp("python-can-by-path.mf4", FILE)]);
        assert!(want.status.success());
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        e.write_all(FILE).unwrap();
        let gz = e.finish().unwrap();
        let by_path = decode(&["--json", &tmp("python-can.mf4.gz", &gz)]);
        for got in [
            decode_stdin(&["--json", "-"], FILE),
            decode_stdin(&["--json", "-"], &gz),
            by_path,
        ] {
            let err = String::from_utf8_lossy(&got.stderr);
            assert!(got.status.success(), "{err}");
            assert!(err.contains("0 CAN FD frame(s), 1 error frame(s)"), "{err}");
            assert_eq!(
                String::from_utf8_lossy(&got.stdout),
                String::from_utf8_lossy(&want.stdout)
            );
        }
    }

    #[test]
    fn truncated_and_misnamed_files_exit_non_zero() {
        let o = decode(&[&tmp("truncated.mf4", &FILE[..FILE.len() / 2])]);
        assert_eq!(o.status.code(), Some(1));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("past the end of the file: the rest is not read"),
            "{err}"
        );
        let o = decode(&["--format", "mf4", &tmp("text-as-mf4.log", LOG.as_bytes())]);
        assert_eq!(o.status.code(), Some(1));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("after record 0: not an MDF file"), "{err}");
        assert!(
            err.contains("none of the 0 record(s) is a CAN frame (read as mf4)"),
            "{err}"
        );
        // A line format given reads the file as lines.
        let o = decode(&["--format", "candump", &tmp("mf4-as-text.mf4", FILE)]);
        assert_eq!(o.status.code(), Some(1));
    }
}
