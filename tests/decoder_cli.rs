//! The `decode` example run as a program on the real captures.
#![cfg(feature = "std")]

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

use serde_json::Value;

/// `target/<profile>/examples/decode`, built by `cargo test` before the tests run.
fn decoder() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().unwrap().parent().unwrap();
    let path = dir
        .join("examples")
        .join(format!("decode{}", std::env::consts::EXE_SUFFIX));
    assert!(path.exists(), "{} not built", path.display());
    path
}

fn run(args: &[&str], stdin: Option<&str>) -> Output {
    let mut child = Command::new(decoder())
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut pipe = child.stdin.take().unwrap();
    pipe.write_all(stdin.unwrap_or("").as_bytes()).unwrap();
    drop(pipe);
    child.wait_with_output().unwrap()
}

const STARTUP: &str = "tests/data/deltaq-icl1500-startup.log";
const CHARGING: &str = "tests/data/deltaq-icl1500-charging.log";

fn text(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

#[test]
fn startup_capture_in_words() {
    let o = run(&[STARTUP], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    assert_eq!(out.lines().count(), 1387);
    let emcy: Vec<&str> = out.lines().filter(|l| l.contains("EMCY")).collect();
    assert_eq!(emcy.len(), 4, "{emcy:#?}");
    assert!(out.contains(
        "08A  charger  EMCY node 10: 8130h life guard error or heartbeat error, reg 01h, mfr 20 80 00 00 00, Delta-Q E-0-3-2 heartbeat lost"
    ), "{emcy:#?}");
    assert!(out.contains(
        "EMCY node 10: 8130h life guard error or heartbeat error, reg 01h, mfr 1E 80 00 00 00, Delta-Q E-0-3-0 battery module communication error"
    ), "{emcy:#?}");
    assert!(out.contains("1756955653.603308       000  -        NMT start, node 10"));
    assert!(out.contains("701  battery  heartbeat node 1: operational"));
    assert!(out.contains("70A  charger  heartbeat node 10: pre-operational"));
    assert!(out.contains("18A  charger  TPDO0 node 10: 7C 13 46 4E 70 00 00 00"));
}

#[test]
fn both_captures_as_json() {
    for (file, lines, emcys) in [(STARTUP, 1387, 4), (CHARGING, 848, 1)] {
        let o = run(&["--json", file], None);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let out = text(&o);
        let values: Vec<Value> = out
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(values.len(), lines);
        let mut seen_emcy = 0;
        for v in &values {
            assert!(v["t"].is_f64(), "{v}");
            let id = v["id"].as_u64().unwrap();
            let kind = v["kind"].as_str().unwrap();
            let want = match id {
                0x000 => "nmt",
                0x08A => "emcy",
                0x18A | 0x28A | 0x38A => "tpdo",
                0x20A | 0x30A => "rpdo",
                0x701 | 0x70A => "heartbeat",
                other => panic!("unexpected id {other:#x}"),
            };
            assert_eq!(kind, want);
            if kind == "nmt" {
                assert!(v["node"].is_null());
            } else {
                assert_eq!(v["node"].as_u64().unwrap(), id & 0x7F);
            }
            if kind == "heartbeat" {
                assert!(["operational", "pre-operational"].contains(&v["state"].as_str().unwrap()));
            }
            if kind == "emcy" {
                seen_emcy += 1;
                let code = v["code"].as_u64().unwrap();
                let mfr = v["mfr"].as_str().unwrap();
                match (code, mfr) {
                    (0, "0000000000") => assert!(v["deltaq"].is_null()),
                    (0x8130, "2080000000") => {
                        assert_eq!(v["register"], 1);
                        assert_eq!(v["deltaq"]["label"], "E-0-3-2");
                        assert_eq!(v["deltaq"]["description"], "heartbeat lost");
                    }
                    (0x8130, "1e80000000") => {
                        assert_eq!(v["deltaq"]["label"], "E-0-3-0");
                        assert_eq!(
                            v["deltaq"]["description"],
                            "battery module communication error"
                        );
                    }
                    other => panic!("unexpected EMCY {other:?}"),
                }
            }
        }
        assert_eq!(seen_emcy, emcys, "{file}");
    }
}

#[test]
fn bad_lines_are_reported_and_skipped() {
    let input =
        "(1.000000) can0 701#05\nnot a frame\n(2.000000) can0 08A#3081\n701#R1\n(3.5) can0 7FF#\n";
    let o = run(&["-"], Some(input));
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8(o.stderr).unwrap();
    assert!(err.contains("line 2: no ID#DATA field"), "{err}");
    assert!(
        err.contains("line 3: frame 08A#3081 does not decode: truncated: need 8 bytes, got 2"),
        "{err}"
    );
    assert!(err.contains("2 bad line(s)"), "{err}");
    let out = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 4, "{out}");
    assert!(lines[0].contains("heartbeat node 1: operational"));
    assert!(lines[1].contains("malformed"));
    assert!(lines[2].contains("node guarding request node 1, DLC 1"));
    assert!(lines[3].contains("unknown 7FF#"));
}

#[test]
fn sdo_and_options_in_json() {
    let input =
        "602#4018100100000000\n582#43181001040000000\n582#4318100104000000\n5FF#8018100111000906\n";
    let o = run(
        &["--json", "--charger-node", "2", "--battery-node", "127"],
        Some(input),
    );
    assert_eq!(o.status.code(), Some(1)); // line 2 has an odd digit count
    let out = text(&o);
    let v: Vec<Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(v.len(), 3);
    assert_eq!(v[0]["kind"], "sdo_rx");
    assert_eq!(v[0]["role"], "charger");
    assert_eq!(v[0]["command"], "initiate_upload");
    assert_eq!(v[0]["index"], 0x1018);
    assert!(v[0]["t"].is_null());
    assert_eq!(v[1]["kind"], "sdo_tx");
    assert_eq!(v[1]["bytes"], "04000000");
    assert_eq!(v[2]["role"], "battery");
    assert_eq!(v[2]["abort_code"], 0x0609_0011);
    assert_eq!(v[2]["abort_meaning"], "Sub-index does not exist");
}

#[test]
fn usage_errors() {
    assert_eq!(run(&["--charger-node", "0"], None).status.code(), Some(2));
    assert_eq!(run(&["--bogus"], None).status.code(), Some(2));
    assert_eq!(run(&["/nonexistent/file.log"], None).status.code(), Some(2));
}

#[test]
fn terminal_stdin_decodes_the_bundled_capture() {
    // `script` gives the decoder a pseudo-terminal on stdin.
    let o = Command::new("script")
        .args(["-qec", &decoder().display().to_string(), "/dev/null"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::null())
        .output()
        .expect("`script` (util-linux) is needed for this test");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    assert!(out.contains("decoding tests/data/deltaq-icl1500-startup.log (bundled real capture)"));
    assert!(out.contains("Delta-Q E-0-3-2 heartbeat lost"));
    assert_eq!(
        out.lines().filter(|l| l.contains(" 701  battery")).count(),
        525
    );
}
