//! The `canopen-decode` program run on the real captures (read from the
//! shared data folder beside the checkout: `common::captures`) and on our
//! own logs. Cargo builds the program for these tests (feature `cli`).
#![cfg(feature = "cli")]

mod common;

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

use serde_json::Value;

/// The program, built by cargo for this test crate.
fn decoder() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_canopen-decode"))
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
    // Written from a thread: a large input with a large output would
    // otherwise fill both pipes and deadlock.
    let mut pipe = child.stdin.take().unwrap();
    let input = stdin.unwrap_or("").to_string();
    let writer = std::thread::spawn(move || {
        // The decoder may exit before reading everything (usage errors).
        let _ = pipe.write_all(input.as_bytes());
    });
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap();
    out
}

/// A real capture's path as an argument, or `None` when it is absent (the
/// test then passes without asserting).
fn capture(name: &str) -> Option<String> {
    common::captures::path(name).map(|p| p.display().to_string())
}

fn text(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

#[test]
fn startup_capture_in_words() {
    let Some(startup) = capture(common::captures::STARTUP) else {
        return;
    };
    let o = run(
        &["--charger-node", "10", "--battery-node", "1", &startup],
        None,
    );
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
    let (Some(startup), Some(charging)) = (
        capture(common::captures::STARTUP),
        capture(common::captures::CHARGING),
    ) else {
        return;
    };
    for (file, lines, emcys) in [(&startup, 1387, 4), (&charging, 848, 1)] {
        let o = run(
            &[
                "--charger-node",
                "10",
                "--battery-node",
                "1",
                "--json",
                file,
            ],
            None,
        );
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
    // Lenient (the default): the 2-byte EMCY is read and flagged.
    let o = run(
        &["--charger-node", "10", "--battery-node", "1", "-"],
        Some(input),
    );
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8(o.stderr.clone()).unwrap();
    assert!(err.contains("1 bad line(s)"), "{err}");
    assert!(text(&o).contains(
        "EMCY node 10: 8130h life guard error or heartbeat error, reg 00h, mfr 00 00 00 00 00, \
         Delta-Q 0x0000 unknown Delta-Q code [deviates: 2 bytes where CiA 301 has 8 (the missing ones read as 0)]"
    ), "{}", text(&o));
    // --strict: a deviation is a malformed frame.
    let o = run(
        &[
            "--charger-node",
            "10",
            "--battery-node",
            "1",
            "--strict",
            "-",
        ],
        Some(input),
    );
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
    // The three frames, and after the response the transfer it completed.
    assert_eq!(v.len(), 4);
    assert_eq!(v[0]["kind"], "sdo_rx");
    assert_eq!(v[0]["role"], "charger");
    assert_eq!(v[0]["command"], "initiate_upload");
    assert_eq!(v[0]["index"], 0x1018);
    assert!(v[0]["t"].is_null());
    assert_eq!(v[1]["kind"], "sdo_tx");
    assert_eq!(v[1]["bytes"], "04000000");
    assert_eq!(v[2]["kind"], "sdo_transfer");
    assert_eq!(v[2]["role"], "charger");
    assert_eq!(v[2]["value"], 4);
    // An abort with no transfer open on its channel ends nothing.
    assert_eq!(v[3]["role"], "battery");
    assert_eq!(v[3]["abort_code"], 0x0609_0011);
    assert_eq!(v[3]["abort_meaning"], "Sub-index does not exist");
}

#[test]
fn usage_errors() {
    assert_eq!(run(&["--charger-node", "0"], None).status.code(), Some(2));
    assert_eq!(run(&["--bogus"], None).status.code(), Some(2));
    assert_eq!(run(&["/nonexistent/file.log"], None).status.code(), Some(2));
}

#[test]
fn terminal_stdin_decodes_the_bundled_session() {
    // `script` gives the decoder a pseudo-terminal on stdin.
    let o = Command::new("script")
        .args(["-qec", &decoder().display().to_string(), "/dev/null"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::null())
        .output()
        .expect("`script` (util-linux) is needed for this test");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    assert!(
        out.contains("no input given; decoding tests/data/virtual-session.log"),
        "{out}"
    );
    assert!(out.contains("Delta-Q E-0-3-2 heartbeat lost"), "{out}");
    assert!(out.contains("SDO upload 1000h:00 from node 1"), "{out}");
    assert_eq!(
        out.lines()
            .filter(|l| l.contains(" 701  battery  heartbeat"))
            .count(),
        8,
        "{out}"
    );
}

/// The capture README's mapping, as `--pdo` arguments (padding the README
/// leaves unnamed as CiA 301 dummy entries 0005h / 0006h).
const CAPTURE_PDO_ARGS: [&str; 13] = [
    "--charger-node",
    "10",
    "--battery-node",
    "1",
    "--no-default-pdos",
    "--pdo",
    "18A=2002:0:16,2101:0:16,2006:0:16,6:0:16",
    "--pdo",
    "0x38A=2060:00:32,2200:00:16,6080:00:8,5:0:8",
    "--pdo",
    "20A=2FFA:1:8,6081:0:8,4201:0:8,2276:0:16,6070:0:16,6000:0:8",
    "--pdo",
    "30a=0x2ffa:1:8,2FFA:01:8,2002:0:16,2101:0:16,6010:0:16",
];

#[test]
fn capture_mapping_in_words() {
    let (Some(startup), Some(charging)) = (
        capture(common::captures::STARTUP),
        capture(common::captures::CHARGING),
    ) else {
        return;
    };
    let mut args = CAPTURE_PDO_ARGS.to_vec();
    args.push(&charging);
    let o = run(&args, None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    assert_eq!(out.lines().count(), 848);
    // Numbers in words: rounded to at most 2 decimals, trailing zeros dropped.
    for want in [
        "1757032317.008242       18A  charger  TPDO0 node 10: 74 13 45 4E 70 00 00 00 = \
         2002h charging current 19.45 A; 2101h battery voltage 78.27 V; \
         2006h extended charge status: AC present, charger enabled, override external (BMS)",
        "38A  charger  TPDO2 node 10: 00 00 00 00 BA 07 FF 00 = 2060h displayed error: none; \
         2200h AC voltage 123.63 V; 6080h charger state of charge: invalid (raw FFh)",
        "20A  charger  RPDO0 node 10: 00 4C 01 00 52 A0 00 01 = 6081h battery state of charge 76 %; \
         4201h external override: equalize; 2276h voltage request 82 V; \
         6070h charge current requested 10 A; 6000h battery status: ready to charge",
        "30A  charger  RPDO1 node 10: 00 00 00 0A 00 52 30 02 = 2002h charging current 10 A; \
         2101h battery voltage 82 V; 6010h temperature 70 degC",
    ] {
        assert!(out.contains(want), "missing {want}");
    }
    for l in out.lines() {
        let mapped = [" 18A ", " 38A ", " 20A ", " 30A "]
            .iter()
            .any(|id| l.contains(id));
        assert_eq!(l.contains(" = "), mapped, "{l}");
        assert!(!l.contains("default"), "{l}");
    }
    // 0x28A has no published layout: raw, as before.
    assert!(out.contains("28A  charger  TPDO1 node 10: 00 00 00 00 00 00 00 00\n"));

    // --pdo-capture-mapping is the same thing in one flag.
    let short = run(&["--pdo-capture-mapping", &charging], None);
    assert_eq!(text(&short), out);

    // The startup capture's BMS reports no current yet.
    let startup = text(&run(&["--pdo-capture-mapping", &startup], None));
    assert!(startup.contains(
        "30A  charger  RPDO1 node 10: 00 00 00 00 00 4E 30 02 = 2002h charging current 0 A; \
         2101h battery voltage 78 V; 6010h temperature 70 degC"
    ));
}

#[test]
fn capture_mapping_in_json() {
    let Some(charging) = capture(common::captures::CHARGING) else {
        return;
    };
    let o = run(&["--json", "--pdo-capture-mapping", &charging], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let values: Vec<Value> = text(&o)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let mut seen = std::collections::BTreeSet::new();
    for v in &values {
        let id = v["id"].as_u64().unwrap();
        let mapped = matches!(id, 0x18A | 0x38A | 0x20A | 0x30A);
        assert_eq!(v["fields"].is_array(), mapped, "{v}");
        if !mapped {
            continue;
        }
        assert_eq!(v["mapping"], "given");
        assert_eq!(v["unmapped_bytes"], 0);
        for f in v["fields"].as_array().unwrap() {
            for k in [
                "index", "sub", "bits", "name", "raw", "kind", "value", "text",
            ] {
                assert!(f.get(k).is_some(), "{k} in {f}");
            }
            assert_eq!(
                f["kind"] == "scaled",
                f["value"].is_f64() || f["value"].is_u64()
            );
            assert_eq!(f.get("unit").is_some(), f["kind"] == "scaled", "{f}");
        }
        seen.insert((id, v["data"].as_str().unwrap().to_string()));
        let fields = v["fields"].as_array().unwrap();
        let field = |i: usize| &fields[i];
        match (id, v["data"].as_str().unwrap()) {
            (0x18A, "7413454e70000000") => {
                assert_eq!(field(0)["index"], 0x2002);
                assert_eq!(field(0)["name"], "charging current");
                assert_eq!(field(0)["raw"], 0x1374);
                assert_eq!(field(0)["value"], 19.453125); // exact in JSON
                assert_eq!(field(0)["unit"], "A");
                assert_eq!(field(1)["index"], 0x2101);
                assert_eq!(field(1)["value"], 78.26953125);
                assert_eq!(field(1)["unit"], "V");
                assert_eq!(field(2)["index"], 0x2006);
                assert_eq!(field(2)["raw"], 0x70);
                assert_eq!(field(2)["kind"], "flags");
                assert_eq!(
                    field(2)["value"],
                    "AC present, charger enabled, override external (BMS)"
                );
                assert_eq!(field(3)["kind"], "padding");
                assert_eq!(field(3)["index"], 6);
            }
            (0x38A, "00000000ba07ff00") => {
                assert_eq!(field(0)["index"], 0x2060);
                assert_eq!(field(0)["kind"], "error");
                assert_eq!(field(0)["value"], "none");
                assert_eq!(field(1)["value"], 123.625);
                assert_eq!(field(1)["unit"], "V");
                assert_eq!(field(2)["index"], 0x6080);
                assert_eq!(field(2)["raw"], 255);
                assert_eq!(field(2)["kind"], "invalid");
                assert!(field(2)["value"].is_null());
            }
            (0x20A, "004c010052a00001") => {
                assert_eq!(field(0)["index"], 0x2FFA);
                assert_eq!(field(0)["sub"], 1);
                assert_eq!(field(1)["name"], "battery state of charge");
                assert_eq!(field(1)["value"], 76);
                assert_eq!(field(1)["unit"], "%");
                assert_eq!(field(2)["value"], "equalize");
                assert_eq!(field(3)["index"], 0x2276);
                assert_eq!(field(3)["value"], 82);
                assert_eq!(field(4)["index"], 0x6070);
                assert_eq!(field(4)["value"], 10);
                assert_eq!(field(4)["unit"], "A");
                assert_eq!(field(5)["value"], "ready to charge");
            }
            (0x30A, "0000000a00523002") => {
                assert_eq!(field(2)["value"], 10);
                assert_eq!(field(3)["value"], 82);
                assert_eq!(field(4)["name"], "temperature");
                assert_eq!(field(4)["raw"], 0x230);
                assert_eq!(field(4)["value"], 70);
                assert_eq!(field(4)["unit"], "degC");
            }
            _ => {}
        }
    }
    for (id, data) in [
        (0x18A, "7413454e70000000"),
        (0x38A, "00000000ba07ff00"),
        (0x20A, "004c010052a00001"),
        (0x30A, "0000000a00523002"),
    ] {
        assert!(seen.contains(&(id, data.to_string())), "{id:x} {data}");
    }
}

#[test]
fn default_mappings_apply_without_pdo() {
    // Charger TPDO 3 (2002h, 2100h Q10, 2006h), charger RPDO 0 (6010h,
    // 6000h), battery TPDO 0 (the same, CiA 418), charger RPDO 3 (no
    // published mapping: raw), another node (no mapping: raw).
    let input = "48A#7413003070000000\n20A#300201\n181#C0FE00\n50A#01\n182#01\n";
    let o = run(
        &["--charger-node", "10", "--battery-node", "1", "-"],
        Some(input),
    );
    assert!(o.status.success());
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].ends_with(
            "= [charger default] 2002h charging current 19.45 A; \
             2100h battery voltage (legacy) 12 V; \
             2006h extended charge status: AC present, charger enabled, override external (BMS) \
             (+2 unmapped bytes)"
        ),
        "{out}"
    );
    assert!(
        lines[1].ends_with(
            "= [charger default] 6010h temperature 70 degC; 6000h battery status: ready to charge"
        ),
        "{out}"
    );
    assert!(
        lines[2].ends_with(
            "= [battery default] 6010h temperature -40 degC; \
             6000h battery status: not ready to charge"
        ),
        "{out}"
    );
    assert!(!lines[3].contains(" = "), "{out}");
    assert!(!lines[4].contains(" = "), "{out}");

    let o = run(
        &["--charger-node", "10", "--battery-node", "1", "--json", "-"],
        Some(input),
    );
    let v: Vec<Value> = text(&o)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(v[0]["mapping"], "charger default");
    assert_eq!(v[0]["unmapped_bytes"], 2);
    assert_eq!(v[0]["fields"][1]["value"], 12);
    assert_eq!(v[2]["mapping"], "battery default");
    assert_eq!(v[2]["fields"][0]["value"], -40);
    assert!(v[3].get("fields").is_none());

    // --no-default-pdos: everything raw.
    let o = run(
        &[
            "--charger-node",
            "10",
            "--battery-node",
            "1",
            "--no-default-pdos",
            "-",
        ],
        Some(input),
    );
    assert!(!text(&o).contains(" = "));

    // A given mapping on the battery node reads CiA 418 objects only; a
    // short frame marks the missing field.
    let o = run(
        &[
            "--charger-node",
            "10",
            "--battery-node",
            "1",
            "--pdo=181=2002:0:16,6081:0:8",
            "-",
        ],
        Some("181#7413\n"),
    );
    assert!(
        text(&o).contains(
            "= 2002h unknown object: raw 1374h (16 bits); \
             6081h battery state of charge: missing (past the end of the frame)"
        ),
        "{}",
        text(&o)
    );
}

#[test]
fn bad_pdo_values_exit_2() {
    for (args, why) in [
        (&["--pdo"][..], "a value is required for '--pdo"),
        (&["--pdo", "18A"], "expected COBID=INDEX:SUB:BITS"),
        (&["--pdo", "18A="], "is not INDEX:SUB:BITS"),
        (&["--pdo", "18A=2002:0"], "is not INDEX:SUB:BITS"),
        (&["--pdo", "18A=2002:0:16:1"], "is not INDEX:SUB:BITS"),
        (
            &["--pdo", "800=2002:0:16"],
            "COB-ID '800' is not hex 0..=7FF",
        ),
        (&["--pdo", "XYZ=2002:0:16"], "COB-ID 'XYZ'"),
        (&["--pdo", "18A=20021:0:16"], "index '20021'"),
        (&["--pdo", "18A=2002:100:16"], "sub-index '100'"),
        (
            &["--pdo", "18A=2002:0:0"],
            "bits '0' is not a decimal 1..=64",
        ),
        (&["--pdo", "18A=2002:0:65"], "bits '65'"),
        (&["--pdo", "18A=2002:0:0x10"], "bits '0x10'"),
        (
            &["--pdo", "18A=6060:0:32,6060:0:32,6001:0:8"],
            "mapping of 72 bits, at most 64",
        ),
        (
            &[
                "--pdo",
                "18A=5:0:8,5:0:8,5:0:8,5:0:8,5:0:8,5:0:8,5:0:8,5:0:8,5:0:8",
            ],
            "9 entries, at most 8",
        ),
        (
            &["--pdo", "18A=6001:0:8", "--pdo", "0x18a=6001:0:8"],
            "COB-ID 18A given twice",
        ),
    ] {
        let o = run(args, None);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(why), "{args:?}: {err}");
        // clap's errors point to --help; the program's own show the usage.
        assert!(
            err.contains("Usage: canopen-decode") || err.contains("try '--help'"),
            "{err}"
        );
    }
}

const SDO_SAMPLE: &str = "tests/data/sdo-sample.log";

/// The transfer lines (words) of a run, without the timestamp and role columns.
fn transfers(out: &str) -> Vec<String> {
    out.lines()
        .filter_map(|l| l.split_once("  transfer  "))
        .map(|(_, rest)| rest.get(9..).unwrap_or("").to_string())
        .collect()
}

fn json_lines(o: &Output) -> Vec<Value> {
    text(o)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn json_transfers(o: &Output) -> Vec<Value> {
    json_lines(o)
        .into_iter()
        .filter(|v| v["kind"] == "sdo_transfer")
        .collect()
}

#[test]
fn sdo_sample_transfers_in_words() {
    let o = run(&[SDO_SAMPLE], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    // 26 frames, each on its line as before, and 6 transfers.
    assert_eq!(out.lines().count(), 32);
    let lines: Vec<&str> = out.lines().filter(|l| l.contains(" transfer ")).collect();
    assert_eq!(
        lines,
        [
            "1757100000.001350  transfer  -        SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)",
            "1757100000.101350  transfer  -        SDO download 1017h:00 to node 2: A0 0F (producer heartbeat time: 4000 ms)",
            "1757100000.207750  transfer  -        SDO upload 1008h:00 from node 2: 26 bytes \"Tiny Node - Mega Domains !\" (manufacturer device name)",
            "1757100000.304550  transfer  -        SDO download 2000h:00 to node 2: 13 bytes 41 20 6C 6F 6E 67 20 73 74 72 69 6E 67",
            "1757100000.402950  transfer  -        SDO download 2000h:00 to node 2: 0 bytes",
            "1757100000.501350  transfer  -        SDO upload 1018h:01 from node 2 aborted: 06090011h Sub-index does not exist",
        ]
    );
    // Each transfer line follows the frame that ended it.
    let all: Vec<&str> = out.lines().collect();
    for (i, l) in all
        .iter()
        .enumerate()
        .filter(|(_, l)| l.contains(" transfer "))
    {
        assert!(all[i - 1].contains("582  -        SDO response"), "{l}");
        assert_eq!(all[i - 1].get(..17), l.get(..17));
    }
}

#[test]
fn sdo_sample_transfers_in_json() {
    let o = run(&["--json", SDO_SAMPLE], None);
    assert!(o.status.success());
    let all = json_lines(&o);
    assert_eq!(all.len(), 32);
    let t = json_transfers(&o);
    // The timestamp as serde_json reads the decoder's `1757100000.001350`.
    let base = |t: &str, dir: &str, index: u16, sub: u8| {
        serde_json::json!({
            "t": t.parse::<f64>().unwrap(), "kind": "sdo_transfer", "node": 2, "role": null, "direction": dir,
            "index": index, "sub": sub, "status": "complete", "indicated_size": null,
            "block": false, "crc_checked": false,
            "size_indicated": true, "size_mismatch": false, "truncated": false,
            "unit": null, "meaning": null, "value": null, "name": null,
        })
    };
    let with = |mut v: Value, extra: Value| {
        for (k, x) in extra.as_object().unwrap() {
            v[k] = x.clone();
        }
        v
    };
    let want = [
        with(
            base("1757100000.001350", "upload", 0x1018, 1),
            serde_json::json!({"size": 4, "indicated_size": 4, "bytes": "04000000", "name": "identity vendor-ID",
                "value": 4, "meaning": "00000004h",
                "text": "SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)"}),
        ),
        with(
            base("1757100000.101350", "download", 0x1017, 0),
            serde_json::json!({"size": 2, "indicated_size": 2, "bytes": "a00f", "name": "producer heartbeat time",
                "value": 4000, "unit": "ms", "meaning": "4000 ms",
                "text": "SDO download 1017h:00 to node 2: A0 0F (producer heartbeat time: 4000 ms)"}),
        ),
        with(
            base("1757100000.207750", "upload", 0x1008, 0),
            serde_json::json!({"size": 26, "indicated_size": 26,
                "bytes": "54696e79204e6f6465202d204d65676120446f6d61696e732021",
                "name": "manufacturer device name", "value": "Tiny Node - Mega Domains !",
                "text": "SDO upload 1008h:00 from node 2: 26 bytes \"Tiny Node - Mega Domains !\" (manufacturer device name)"}),
        ),
        with(
            base("1757100000.304550", "download", 0x2000, 0),
            serde_json::json!({"size": 13, "indicated_size": 13, "bytes": "41206c6f6e6720737472696e67",
                "text": "SDO download 2000h:00 to node 2: 13 bytes 41 20 6C 6F 6E 67 20 73 74 72 69 6E 67"}),
        ),
        with(
            base("1757100000.402950", "download", 0x2000, 0),
            serde_json::json!({"size": 0, "indicated_size": 0, "bytes": "",
                "text": "SDO download 2000h:00 to node 2: 0 bytes"}),
        ),
        with(
            base("1757100000.501350", "upload", 0x1018, 1),
            serde_json::json!({"status": "aborted", "size": 0, "bytes": "", "name": "identity vendor-ID",
                "abort": {"code": 0x0609_0011, "meaning": "Sub-index does not exist", "by": "server"},
                "text": "SDO upload 1018h:01 from node 2 aborted: 06090011h Sub-index does not exist"}),
        ),
    ];
    assert_eq!(t.len(), want.len());
    for (got, want) in t.iter().zip(&want) {
        assert_eq!(got, want);
    }
}

#[test]
fn sdo_objects_named_by_role() {
    // Battery node 1, charger node 10 (the defaults); node 4 has no role.
    let input = "\
601#2F01600001000000\n581#6001600000000000\n\
601#4000100000000000\n581#43001000A2010900\n\
60A#4001100000000000\n58A#4F01100081000000\n\
60A#4003100100000000\n58A#4303100100908001\n\
604#2300140104020080\n584#6000140100000000\n\
604#23161002F0000100\n584#6016100200000000\n\
601#40001A0100000000\n581#43001A0110000160\n\
601#4030600100000000\n581#4330600141424344\n\
601#4060600000000000\n581#4360600000480100\n\
601#4081600000000000\n581#4F816000FF000000\n\
601#4017100000000000\n581#4317100010270000\n\
602#4000140200000000\n582#42001402FE000000\n";
    let o = run(
        &["--charger-node", "10", "--battery-node", "1", "-"],
        Some(input),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        transfers(&text(&o)),
        [
            "SDO download 6001h:00 to node 1: 01 (charger status: enabled)",
            "SDO upload 1000h:00 from node 1: A2 01 09 00 (device type: CiA 418 battery module, RPDOs 0/1, TPDOs 0/2)",
            "SDO upload 1001h:00 from node 10: 81 (error register: generic, manufacturer)",
            "SDO upload 1003h:01 from node 10: 00 90 80 01 (pre-defined error field: 9000h external error, \
             information 0180h, Delta-Q E-0-0-1 battery high voltage (threshold from the algorithm))",
            "SDO download 1400h:01 to node 4: 04 02 00 80 (RPDO0 communication: COB-ID: 204h, invalid) \
             [RPDO0 of node 4 is not valid (COB-ID bit 31 set)]",
            "SDO download 1016h:02 to node 4: F0 00 01 00 (consumer heartbeat time: node 1, 240 ms)",
            "SDO upload 1A00h:01 from node 1: 10 00 01 60 (TPDO0 mapping: entry 1: 6001h:00/16 charger status)",
            "SDO upload 6030h:01 from node 1: 41 42 43 44 (battery serial number: \"ABCD\")",
            "SDO upload 6060h:00 from node 1: 00 48 01 00 (battery voltage: 82 V)",
            "SDO upload 6081h:00 from node 1: FF (battery state of charge: invalid (raw FFh))",
            "SDO upload 1017h:00 from node 1: 10 27 00 00 (producer heartbeat time: 4 bytes, the object has 2)",
            "SDO upload 1400h:02 from node 2: FE 00 00 00 (RPDO0 communication: transmission type: \
             event-driven (manufacturer-specific)) [size not indicated]",
        ]
    );
    let v = json_transfers(&run(
        &["--charger-node", "10", "--battery-node", "1", "--json", "-"],
        Some(input),
    ));
    assert_eq!(v[0]["role"], "battery");
    assert_eq!(v[0]["value"], "enabled");
    assert_eq!(v[6]["value"], 0x6001_0010);
    assert_eq!(v[7]["value"], "ABCD");
    assert_eq!(v[8]["value"], 82);
    assert_eq!(v[8]["unit"], "V");
    assert!(v[9]["value"].is_null());
    assert!(v[10]["value"].is_null());
    assert_eq!(v[11]["size_indicated"], false);
    assert_eq!(v[11]["value"], 254);
}

const V8_START: &str =
    "602#4008100000000000\n582#410810001A000000\n602#6000000000000000\n582#0054696E79204E6F\n";

#[test]
fn sdo_stray_segments_end_nothing() {
    // Segments and acknowledgements with no transfer open, then V1.
    let input = "582#0054696E79204E6F\n602#6000000000000000\n602#0041206C6F6E6720\n\
582#2000200000000000\n582#15696E7320210000\n602#4018100100000000\n582#4318100104000000\n";
    let o = run(&["-"], Some(input));
    assert!(o.status.success());
    assert_eq!(
        transfers(&text(&o)),
        ["SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)"]
    );
    // A stray segment inside a download breaks it off, once.
    let o = run(
        &["-"],
        Some("602#210020000D000000\n582#6000200000000000\n582#15696E7320210000\n582#15696E7320210000\n"),
    );
    assert_eq!(
        transfers(&text(&o)),
        [
            "SDO download 2000h:00 to node 2 incomplete: the server's upload segment t=1, 5 bytes: \
             69 6E 73 20 21, last breaks CiA 301 (the client should abort with 05040001h \
             Client/server command specifier not valid or unknown), and no abort followed \
             (0 bytes transferred of 13 indicated)"
        ]
    );
}

#[test]
fn sdo_new_initiate_breaks_off_the_transfer() {
    let input = format!("{V8_START}602#4018100100000000\n582#4318100104000000\n");
    let o = run(&["-"], Some(&input));
    assert!(o.status.success());
    let out = text(&o);
    assert_eq!(
        transfers(&out),
        [
            "SDO upload 1008h:00 from node 2 incomplete: new initiate upload 1018h:01 \
             (7 bytes transferred of 26 indicated)",
            "SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)",
        ]
    );
    // The report follows the initiate that broke the transfer off.
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[4].contains("initiate upload 1018h sub 1"));
    assert!(lines[5].contains("incomplete"));
    let v = json_transfers(&run(&["--json", "-"], Some(&input)));
    assert_eq!(v[0]["status"], "incomplete");
    assert_eq!(v[0]["incomplete"], "new initiate upload 1018h:01");
    assert_eq!(v[0]["bytes"], "54696e79204e6f");
    assert!(v[0]["value"].is_null());
    assert_eq!(v[1]["status"], "complete");
}

#[test]
fn sdo_toggle_error_is_reported_once() {
    // V8 whose second segment repeats toggle 0; the rest is then stray.
    let input = format!(
        "{V8_START}602#7000000000000000\n582#006465202D204D65\n\
602#6000000000000000\n582#00676120446F6D61\n602#7000000000000000\n582#15696E7320210000\n"
    );
    let o = run(&["-"], Some(&input));
    assert!(o.status.success());
    assert_eq!(
        transfers(&text(&o)),
        [
            "SDO upload 1008h:00 from node 2 incomplete: the server's upload segment t=0, 7 bytes: \
             64 65 20 2D 20 4D 65 breaks CiA 301 (the client should abort with 05030000h Toggle \
             bit not alternated), and no abort followed (7 bytes transferred of 26 indicated)"
        ]
    );
    // A client request with the wrong toggle, a download ack with the wrong
    // toggle, and a client abort (V16, index not filled in).
    let input = format!(
        "{V8_START}602#6000000000000000\n\
602#210020000D000000\n582#6000200000000000\n602#0041206C6F6E6720\n582#3000200000000000\n\
602#4008100000000000\n582#410810001A000000\n602#8000000000000405\n"
    );
    assert_eq!(
        transfers(&text(&run(&["-"], Some(&input)))),
        [
            "SDO upload 1008h:00 from node 2 incomplete: the client's upload segment request t=0 \
             breaks CiA 301 (the server should abort with 05030000h Toggle bit not alternated), \
             and no abort followed (7 bytes transferred of 26 indicated)",
            "SDO download 2000h:00 to node 2 incomplete: the server's download segment ack t=1 \
             breaks CiA 301 (the client should abort with 05030000h Toggle bit not alternated), \
             and no abort followed (7 bytes transferred of 13 indicated)",
            "SDO upload 1008h:00 from node 2 aborted by the client: 05040000h SDO protocol timed out",
        ]
    );
}

#[test]
fn sdo_size_mismatch_truncation_and_log_end_are_reported() {
    // V9: more data than indicated; V10: less; then a transfer the log cuts.
    let input = format!(
        "602#4008100000000000\n582#4108100004000000\n602#6000000000000000\n582#0554696E79200000\n\
602#401B200000000000\n582#411B2000FEFDFCFB\n602#6000000000000000\n582#00B2012002911203\n\
602#7000000000000000\n582#1D192170FEFDFCFB\n{V8_START}"
    );
    let o = run(&["-"], Some(&input));
    assert!(o.status.success());
    assert_eq!(
        transfers(&text(&o)),
        [
            "SDO upload 1008h:00 from node 2: 5 bytes \"Tiny \" (manufacturer device name) \
             [size mismatch: 4 bytes indicated, 5 transferred]",
            "SDO upload 201Bh:00 from node 2: B2 01 20 02 91 12 03 19 \
             [size mismatch: 4227661310 bytes indicated, 8 transferred]",
            "SDO upload 1008h:00 from node 2 incomplete: the log ends (7 bytes transferred of 26 indicated)",
        ]
    );
    let v = json_transfers(&run(&["--json", "-"], Some(&input)));
    assert_eq!(v[0]["size_mismatch"], true);
    assert_eq!(v[0]["indicated_size"], 4);
    assert_eq!(v[0]["size"], 5);
    assert_eq!(v[2]["incomplete"], "the log ends");
    assert!(v[2]["t"].is_null()); // the log has no timestamps

    // 70000 bytes: the first 64 KiB are kept, the total is counted.
    let mut big = String::from("602#4000200000000000\n582#4100200070110100\n");
    for i in 0..10_000u32 {
        let t = if i % 2 == 0 { "" } else { "1" };
        let last = i == 9_999;
        let cmd = if t.is_empty() { 0u8 } else { 0x10 } | u8::from(last);
        big.push_str(&format!(
            "602#{}000000000000000\n",
            if t.is_empty() { "6" } else { "7" }
        ));
        big.push_str(&format!("582#{cmd:02X}41414141414141\n"));
    }
    let v = json_transfers(&run(&["--json", "-"], Some(&big)));
    assert_eq!(v.len(), 1);
    assert_eq!(v[0]["status"], "complete");
    assert_eq!(v[0]["size"], 70_000);
    assert_eq!(v[0]["truncated"], true);
    assert_eq!(v[0]["bytes"].as_str().unwrap().len(), 2 * 65_536);
    assert!(v[0]["text"]
        .as_str()
        .unwrap()
        .ends_with("[truncated: the first 65536 of 70000 bytes kept]"));
}

#[test]
fn sdo_block_transfers_are_reassembled_and_their_segments_named() {
    // V17 and V18 (block download and upload, CRC on both), then V1.
    let input = "\
602#C60020001E000000\n582#A40020007F000000\n602#014120726561 6C6C\n602#027920726561 6C6C\n\
602#03792 06C6F6E6720\n602#0473747269 6E672E\n602#852E2E0000000000\n582#A2057F0000000000\n\
602#D545690000000000\n582#A100000000000000\n\
602#A40810007F000000\n582#C60810001A000000\n602#A300000000000000\n582#0154696E79204E6F\n\
582#026465202D204D65\n582#0367612044 6F6D61\n582#8469 6E73202100 00\n602#A2047F0000000000\n\
582#C940E10000000000\n602#A100000000000000\n\
602#4018100100000000\n582#4318100104000000\n";
    let input = input.replace(' ', "");
    let o = run(&["-"], Some(&input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    assert_eq!(
        transfers(&out),
        [
            "SDO block download 2000h:00 to node 2: 30 bytes 41 20 72 65 61 6C 6C 79 20 72 65 61 \
             6C 6C 79 20 6C 6F 6E 67 20 73 74 72 69 6E 67 2E 2E 2E [CRC checked]",
            "SDO block upload 1008h:00 from node 2: 26 bytes \"Tiny Node - Mega Domains !\" \
             (manufacturer device name) [CRC checked]",
            "SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)"
        ]
    );
    // Sub-block segments are named as such, not read as commands.
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[2].ends_with("SDO block segment seq 1 to node 2: 41 20 72 65 61 6C 6C"),
        "{}",
        lines[2]
    );
    assert!(
        lines[6].ends_with("SDO block segment seq 5, last to node 2: 2E 2E 00 00 00 00 00"),
        "{}",
        lines[6]
    );
    assert!(
        lines[14].ends_with("SDO block segment seq 1 from node 2: 54 69 6E 79 20 4E 6F"),
        "{}",
        lines[14]
    );
    assert_eq!(out.matches("block segment").count(), 9);
    let v = json_lines(&run(&["--json", "-"], Some(&input)));
    assert_eq!(v[2]["command"], "block segment");
    assert_eq!(v[2]["seqno"], 1);
    assert_eq!(v[2]["last"], false);
    assert_eq!(v[6]["seqno"], 5);
    assert_eq!(v[6]["last"], true);
    assert_eq!(v[6]["segment_data"], "2e2e0000000000");
    let block: Vec<&Value> = v.iter().filter(|x| x["kind"] == "sdo_transfer").collect();
    assert_eq!(block[0]["block"], true);
    assert_eq!(block[0]["crc_checked"], true);
    assert_eq!(block[1]["size"], 26);
}

#[test]
fn sdo_garbage_never_panics() {
    // A deterministic stream of random SDO frames (any length 0..=8) on two
    // channels, with malformed and short frames among them.
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let mut input = String::new();
    for _ in 0..20_000 {
        let r = next();
        let id = [0x602, 0x582, 0x603, 0x583][(r & 3) as usize];
        let len = ((r >> 2) % 9) as usize;
        // Bias byte 0 towards real command specifiers and small toggles.
        let mut bytes: Vec<u8> = (0..len).map(|i| (next() >> (i * 3)) as u8).collect();
        if let Some(b) = bytes.first_mut() {
            *b = [
                0x00, 0x10, 0x01, 0x40, 0x41, 0x60, 0x70, 0x20, 0x21, 0x23, 0x30, 0x80, 0x43,
            ][(r >> 8) as usize % 13]
                | (*b & 0x01);
        }
        let hex: String = bytes.iter().map(|b| format!("{b:02X}")).collect();
        input.push_str(&format!("{id:03X}#{hex}\n"));
    }
    for args in [&["-"][..], &["--json", "-"]] {
        let o = run(args, Some(&input));
        let code = o.status.code();
        assert!(
            matches!(code, Some(0) | Some(1)),
            "{code:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(!String::from_utf8_lossy(&o.stderr).contains("panicked"));
        if args.len() == 2 {
            let v = json_lines(&o);
            assert!(v.len() >= 20_000);
            let transfers = v.iter().filter(|v| v["kind"] == "sdo_transfer").count();
            assert!(transfers > 0);
        }
    }
}

#[test]
fn bundled_session_shows_configuration_loss_and_recovery() {
    let o = run(&["--bundled", "session"], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    // The charger's configuration reads, reassembled and explained, twice.
    assert_eq!(
        out.matches("transfer  battery  SDO upload 1000h:00 from node 1: A2 01 00 00 (device type: CiA 418 battery module").count(),
        2
    );
    assert!(out.contains(
        "SDO upload 1800h:01 from node 1: 81 01 00 00 (TPDO0 communication: COB-ID: 181h, valid)"
    ));
    assert!(out.contains("1763800007.000500       08A  charger  EMCY node 10: 8130h life guard error or heartbeat error, reg 01h, mfr 20 80 00 00 00, Delta-Q E-0-3-2 heartbeat lost"));
    assert!(out.contains("08A  charger  EMCY node 10: 0000h error reset or no error"));
    let o = run(&["--json", "--bundled", "session"], None);
    let transfers: Vec<Value> = text(&o)
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .filter(|v| v["kind"] == "sdo_transfer")
        .collect();
    assert_eq!(transfers.len(), 6);
    assert!(transfers
        .iter()
        .all(|v| v["status"] == "complete" && v["node"] == 1));
    assert_eq!(run(&["--bundled", "other"], None).status.code(), Some(2));
    assert_eq!(
        run(&["--bundled", "session", "tests/data/sdo-sample.log"], None)
            .status
            .code(),
        Some(2)
    );
}

/// The same four frames in every trace format the decoder reads (as
/// python-can 4.6's writers and PCAN-View / candump write them) give the
/// same decoded frames.
#[test]
fn every_trace_format_decodes_the_same_frames() {
    let traces: [(&str, &str); 6] = [
        (
            "candump",
            "(1.000000) can0 70A#05\n(1.100000) can0 18A#7413454E70000000\n(1.200000) can0 000#010A\n",
        ),
        (
            "candump-screen",
            "(1.000000)  can0  70A   [1]  05\n(1.100000)  can0  18A   [8]  74 13 45 4E 70 00 00 00\n\
             (1.200000)  can0  000   [2]  01 0A\n",
        ),
        (
            "trc",
            ";$FILEVERSION=1.1\n;   comment\n     1)      1000.0  Rx         070A  1  05\n\
             \x20    2)      1100.0  Rx         018A  8  74 13 45 4E 70 00 00 00\n\
             \x20    3)      1200.0  Tx         0000  2  01 0A\n",
        ),
        (
            "trc",
            ";$FILEVERSION=2.1\n;$COLUMNS=N,O,T,B,I,d,R,L,D\n      1      1000.000 DT  1     070A Rx -  1    05\n\
             \x20     2      1100.000 DT  1     018A Rx -  8    74 13 45 4E 70 00 00 00\n\
             \x20     3      1200.000 DT  1     0000 Tx -  2    01 0A\n",
        ),
        (
            "asc",
            "date Tue Dec 01 09:11:16.935 2026\nbase hex  timestamps absolute\nBegin Triggerblock\n\
             \x20  1.000000 1  70A             Rx   d 1 05\n   1.100000 1  18A             Rx   d 8 74 13 45 4E 70 00 00 00\n\
             \x20  1.150000 1  ErrorFrame\n   1.200000 1  0               Tx   d 2 01 0A\nEnd TriggerBlock\n",
        ),
        (
            "csv",
            "timestamp,arbitration_id,extended,remote,error,dlc,data\n1.0,0x70a,0,0,0,1,BQ==\n\
             1.1,0x18a,0,0,0,8,dBNFTnAAAAA=\n1.2,0x0,0,0,0,2,AQo=\n",
        ),
    ];
    let mut decoded = Vec::new();
    for (name, trace) in traces {
        for args in [vec!["--json"], vec!["--json", "--format", name]] {
            let o = run(&args, Some(trace));
            assert!(
                o.status.success(),
                "{name} {args:?}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            let frames: Vec<(String, String)> = text(&o)
                .lines()
                .map(|l| {
                    let v: Value = serde_json::from_str(l).unwrap();
                    (v["id"].to_string(), v["text"].to_string())
                })
                .collect();
            assert_eq!(frames.len(), 3, "{name} {args:?}: {frames:?}");
            decoded.push((name, frames));
        }
    }
    for (name, frames) in &decoded {
        assert_eq!(frames, &decoded[0].1, "{name}");
    }
    // An error frame is reported, not a bad line; a line no format reads is.
    let o = run(&[], Some("hello\n(1.0) can0 70A#05\n"));
    assert_eq!(o.status.code(), Some(1));
}

/// CiA 301 node guarding: the reply to a remote request on 700h + node is a
/// guarding reply whatever its toggle (the first reply has toggle 0); a
/// frame there without a request is a heartbeat.
#[test]
fn guarding_replies_follow_their_request() {
    let log = "(1.0) can0 70A#R1\n(1.001) can0 70A#05\n(1.5) can0 70A#05\n\
               (2.0) can0 70A#R1\n(2.001) can0 70A#85\n(2.5) can0 70A#85\n";
    let o = run(&["--charger-node", "10"], Some(log));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let words: Vec<String> = text(&o)
        .lines()
        .map(|l| l.split("charger  ").nth(1).unwrap().to_string())
        .collect();
    assert_eq!(
        words,
        [
            "node guarding request node 10, DLC 1",
            "node guarding reply node 10: operational, toggle 0",
            "heartbeat node 10: operational",
            "node guarding request node 10, DLC 1",
            "node guarding reply node 10: operational, toggle 1",
            // Toggle 1 without a request: the library's reading stands.
            "node guarding reply node 10: operational, toggle 1",
        ]
    );
    let o = run(&["--charger-node", "10", "--json"], Some(log));
    let replies: Vec<bool> = text(&o)
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap()["guard_reply"] == true)
        .collect();
    assert_eq!(replies, [false, true, false, false, true, false]);
}

/// Frames real devices send that deviate from CiA 301 harmlessly are read
/// and flagged (words and JSON), never counted as malformed unless
/// `--strict`.
#[test]
fn deviating_frames_are_read_and_flagged() {
    let log = "(1.0) can0 000#01\n(1.1) can0 100#0000000010270000\n(1.2) can0 08A#\n\
               (1.3) can0 080#0102\n(1.4) can0 70A#05FF\n";
    let o = run(&["--json"], Some(log));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let deviations: Vec<String> = text(&o)
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap()["deviation"].to_string())
        .collect();
    assert_eq!(
        deviations,
        [
            "\"1 bytes where CiA 301 has 2 (the missing ones read as 0)\"",
            "\"8 bytes where CiA 301 has at most 6 (the extra ones ignored)\"",
            "\"0 bytes where CiA 301 has 8 (the missing ones read as 0)\"",
            "\"2 bytes where CiA 301 has at most 1 (the extra ones ignored)\"",
            "\"2 bytes where CiA 301 has at most 1 (the extra ones ignored)\"",
        ]
    );
    let o = run(&["--strict"], Some(log));
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("5 bad line(s)"));
}

/// No node has a role without evidence: an I/O module at node 10 is not a
/// charger (its PDOs print raw), and a node becomes the battery module once
/// the log shows its 1000h naming profile 418 (then the CiA 418 defaults
/// apply to its PDOs).
#[test]
fn roles_only_from_evidence() {
    // Node 10 sends a TPDO; nobody says what it is.
    let o = run(
        &[],
        Some("(1.0) can0 18A#C80001\n(1.1) can0 08A#3081012080000000\n"),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    assert!(
        out.contains("18A  -        TPDO0 node 10: C8 00 01\n"),
        "{out}"
    );
    assert!(
        !out.contains("Delta-Q"),
        "no Delta-Q label without a charger: {out}"
    );
    // Node 1's device type read by SDO: profile 418, a battery module.
    let log = "(1.0) can0 181#C80001\n(1.1) can0 601#4000100000000000\n\
               (1.2) can0 581#43001000A2010000\n(1.3) can0 181#C80001\n";
    let o = run(&[], Some(log));
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].contains("181  -        TPDO0 node 1: C8 00 01"),
        "{out}"
    );
    assert!(
        out.contains("node 1 is the battery (its device type, 1000h, says so)"),
        "{out}"
    );
    assert!(
        lines.last().unwrap().contains(
            "181  battery  TPDO0 node 1: C8 00 01 = [battery default] 6010h temperature 25 degC; 6000h battery status: ready to charge"
        ),
        "{out}"
    );
    let o = run(&["--json"], Some(log));
    assert!(text(&o).contains("{\"kind\":\"role\",\"node\":1,\"role\":\"battery\"}"));
}

/// Splits one RFC 4180 row.
fn csv_row(line: &str) -> Vec<String> {
    let (mut fields, mut cur, mut quoted, mut chars) =
        (Vec::new(), String::new(), false, line.chars().peekable());
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(std::mem::take(&mut cur)),
            (c, _) => cur.push(c),
        }
    }
    fields.push(cur);
    fields
}

/// `--output csv`: a header and one row of 12 documented columns per frame,
/// quoted where a field holds a comma; no transfer rows.
#[test]
fn csv_output_one_row_per_frame() {
    let log = "(1.0) can0 000#01\n(1.1) can0 70A#05\n(1.2) can0 18A#7413454E70000000\n\
               (1.3) can0 601#4000100000000000\n(1.4) can0 581#43001000A2010000\n\
               (1.5) can0 08A#3081\n";
    let o = run(&["--output", "csv", "--charger-node", "10"], Some(log));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    let rows: Vec<Vec<String>> = out.lines().map(csv_row).collect();
    assert_eq!(
        rows[0].join(","),
        "time,id,extended,remote,dlc,data,kind,node,role,text,deviation,error"
    );
    assert_eq!(rows.len(), 7, "{out}");
    assert!(rows.iter().all(|r| r.len() == 12), "{out}");
    assert_eq!(
        rows[1][..9],
        ["1.000000", "000", "0", "0", "1", "01", "nmt", "", ""]
    );
    assert_eq!(rows[1][9], "NMT start, all nodes");
    assert!(rows[1][10].starts_with("1 bytes where CiA 301 has 2"));
    assert_eq!(
        rows[2][6..10],
        [
            "heartbeat",
            "10",
            "charger",
            "heartbeat node 10: operational"
        ]
    );
    assert_eq!(rows[3][5], "7413454E70000000");
    assert!(
        rows[5][9].starts_with("SDO response from node 1"),
        "{:?}",
        rows[5]
    );
    assert!(rows[6][9].contains("Delta-Q"), "{:?}", rows[6]);
    // The same frames under --strict: the short EMCY is an error row.
    let o = run(&["--output", "csv", "--strict"], Some(log));
    let last = csv_row(text(&o).lines().last().unwrap());
    assert_eq!(last[9], "");
    assert_eq!(last[11], "truncated: need 8 bytes, got 2");
    assert_eq!(run(&["--output", "xml"], None).status.code(), Some(2));
}

/// `--summary-only` on our recorded session: node 1's heartbeat silence
/// while unplugged, its second boot-up, the charger's E-0-3-2 cleared by
/// the error reset after recovery; nothing open, so `--check` exits 0.
#[test]
fn summary_of_the_bundled_session() {
    let o = run(&["--bundled", "session", "--summary-only", "--check"], None);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let out = text(&o);
    for want in [
        "  node 1 (battery):\n    heartbeats: 10, period 1000 ms, largest gap 4000 ms\n",
        "    boot-up at 1763800009.000000 (not preceded by an NMT reset)\n",
        "    silent from 1763800005.000000 (+5.000 s) to 1763800009.000000 (+9.000 s)\n",
        "    SDO transfers: 6, aborted: 0\n",
        "  node 10 (charger):\n",
        "    EMCY at 1763800007.000500 (+7.000 s): 8130h life guard error or heartbeat error, \
         Delta-Q E-0-3-2 heartbeat lost (cleared by an error reset)\n",
        "  PDO 181h: 40 frames",
        "  open problems at the end: none\n",
    ] {
        assert!(out.contains(want), "missing {want:?} in\n{out}");
    }
    assert!(!out.contains("TPDO0"), "--summary-only prints no frames");
    let o = run(&["--bundled", "session", "--summary-only", "--json"], None);
    let v: Value = serde_json::from_str(text(&o).trim()).unwrap();
    assert_eq!(v["kind"], "summary");
    assert_eq!(v["open_problems"], false);
    assert_eq!(
        v["nodes"][0]["silences"][0]["to"].as_f64(),
        Some(1_763_800_009.0)
    );
    assert_eq!(v["nodes"][1]["emcys"][0]["cleared"], true);
}

/// The real startup capture: node 1's heartbeat stops and never returns,
/// the charger raised E-0-3-2 then E-0-3-0 and cleared neither: `--check`
/// exits 3.
#[test]
fn summary_of_the_real_startup_capture() {
    let Some(startup) = capture(common::captures::STARTUP) else {
        return;
    };
    let o = run(
        &[
            "--summary-only",
            "--check",
            "--pdo-capture-mapping",
            &startup,
        ],
        None,
    );
    assert_eq!(
        o.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let out = text(&o);
    let node1 = out.split("  node 10").next().unwrap();
    assert!(
        node1.contains("silent from 1756955706.019119 (+59.950 s, its last heartbeat) until the end of the log"),
        "{out}"
    );
    let e032 = out
        .find("Delta-Q E-0-3-2 heartbeat lost (not cleared)")
        .expect("E-0-3-2");
    let e030 = out
        .find("Delta-Q E-0-3-0 battery module communication error (not cleared)")
        .expect("E-0-3-0");
    assert!(e032 < e030, "{out}");
    assert!(out.contains("  open problems at the end: yes"));
}

/// LSS (CiA 305) services in words, JSON fields, CSV text and the summary.
#[test]
fn lss_services_in_words_json_csv_and_summary() {
    let log = "(1.000) can0 7E5#5100000000800000\n(1.001) can0 7E4#4F00000000000000\n\
               (1.010) can0 7E5#51785634121F0000\n(1.020) can0 7E5#409A020000000000\n\
               (1.030) can0 7E5#1105000000000000\n(1.031) can0 7E4#1100000000000000\n\
               (1.040) can0 7E5#1700000000000000\n(1.041) can0 7E4#1702000000000000\n\
               (1.050) can0 7E5#5E00000000000000\n(1.051) can0 7E4#5EFF000000000000\n\
               (1.060) can0 7E5#0400000000000000\n(1.061) can0 705#00\n\
               (1.070) can0 7E5#9901020304050607\n";
    let o = run(&["--summary"], Some(log));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    for want in [
        "LSS fastscan id 00000000 bit 128 sub 0 next 0",
        "LSS slave: identify slave",
        "LSS fastscan id 12345678 bit 31 sub 0 next 0",
        "LSS master: switch state selective vendor 0000029Ah",
        "LSS master: configure node-ID 5",
        "LSS slave: configure node-ID ok",
        "LSS master: store configuration",
        "LSS slave: store configuration error 2 (storage media access error)",
        "LSS master: inquire node-ID",
        "LSS slave: node-ID 255",
        "LSS master: switch state global waiting",
        "LSS master: unknown [99 01 02 03 04 05 06 07]",
        "LSS: 12 frames, 1 fastscans, node-IDs configured: 5",
    ] {
        assert!(out.contains(want), "{want:?} missing in:\n{out}");
    }
    let o = run(&["--json"], Some(log));
    let rows: Vec<Value> = text(&o)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let scan = &rows[2];
    assert_eq!(scan["kind"], "lss");
    assert_eq!(scan["direction"], "master_to_slave");
    assert_eq!(scan["service"], "fastscan");
    assert_eq!(scan["id_number"], 0x1234_5678);
    assert_eq!(scan["bit_checked"], 31);
    assert_eq!(
        (&scan["lss_sub"], &scan["lss_next"]),
        (&0.into(), &0.into())
    );
    assert_eq!(rows[3]["service"], "switch_state_selective");
    assert_eq!(
        (&rows[3]["field"], &rows[3]["value"]),
        (&"vendor".into(), &0x29A.into())
    );
    assert_eq!(rows[5]["service"], "configure_node_id_response");
    assert_eq!(rows[5]["error_code"], 0);
    assert_eq!(rows[7]["error_code"], 2);
    assert_eq!(rows[9]["direction"], "slave_to_master");
    assert_eq!(
        (&rows[9]["field"], &rows[9]["value"]),
        (&"node_id".into(), &255.into())
    );
    assert_eq!(rows[12]["service"], "unknown");
    // A short LSS frame with a listed command specifier: read, flagged.
    let o = run(&["--json"], Some("(2.0) can0 7E5#0401\n"));
    let v: Value = serde_json::from_str(text(&o).trim()).unwrap();
    assert_eq!(v["service"], "switch_state_global");
    assert_eq!(v["mode"], 1);
    assert!(v["deviation"]
        .as_str()
        .unwrap()
        .starts_with("2 bytes where"));
    let o = run(&["--output", "csv"], Some(log));
    let csv = text(&o);
    assert!(
        csv.lines()
            .any(|l| l.ends_with(",lss,,,LSS slave: identify slave,,")),
        "{csv}"
    );
}

#[test]
fn sdo_channels_on_other_cob_ids_are_declared_with_sdo() {
    // An SDO server on 241h/1C1h (node 65): an expedited upload of 1008h,
    // then a block upload cut off by the end of the log.
    let input = "241#4008100000000000\n1C1#4F08100041000000\n\
241#A40810007F000000\n1C1#C60810001A000000\n241#A300000000000000\n1C1#0154696E79204E6F\n";
    let o = run(&["--sdo", "65=241,1C1", "-"], Some(input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    assert!(
        out.contains("SDO request to node 65: initiate upload 1008h sub 0"),
        "{out}"
    );
    assert!(
        out.contains("SDO block segment seq 1 from node 65: 54 69 6E 79 20 4E 6F"),
        "{out}"
    );
    assert_eq!(
        transfers(&out),
        [
            "SDO upload 1008h:00 from node 65: 1 bytes \"A\" (manufacturer device name)",
            "SDO block upload 1008h:00 from node 65 incomplete: the log ends \
             (7 bytes transferred of 26 indicated)",
        ]
    );
    // The open transfer is reported once, in JSON too.
    let v = json_transfers(&run(
        &["--json", "--sdo", "65=0x241,0x1C1", "-"],
        Some(input),
    ));
    assert_eq!(v.len(), 2);
    assert_eq!(v[1]["status"], "incomplete");
    assert_eq!(v[1]["block"], true);
    // Undeclared, the same frames are PDOs.
    let out = text(&run(&["-"], Some(input)));
    assert!(transfers(&out).is_empty());
    assert!(out.contains("RPDO"), "{out}");
    // A malformed declaration is a usage error.
    for bad in [
        "65=241",
        "x=241,1C1",
        "65=241,241",
        "65=zz,1C1",
        "200=241,1C1",
    ] {
        let o = run(&["--sdo", bad, "-"], Some(input));
        assert_eq!(o.status.code(), Some(2), "--sdo {bad}");
    }
}

#[test]
fn pdo_mappings_written_by_sdo_apply_to_the_pdos_that_follow() {
    // Node 5 (no role): TPDO 1 (1801h/1A01h) remapped by the CiA 301
    // procedure (0 entries, the entries, then their number), then moved to
    // 2A5h; its frames decode by the mapping from then on.
    let input = "\
285#1122334455\n\
605#2F011A0000000000\n585#60011A0000000000\n\
605#23011A0108000060\n585#60011A0100000000\n\
605#23011A0210001060\n585#60011A0200000000\n\
605#2F011A0002000000\n585#60011A0000000000\n\
285#2A3412\n\
605#23011801A5020000\n585#6001180100000000\n\
2A5#2B7856\n";
    let o = run(&["-"], Some(input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    // Before the remap the frame is raw.
    assert!(
        lines[0].ends_with("TPDO1 node 5: 11 22 33 44 55"),
        "{}",
        lines[0]
    );
    let remap = lines
        .iter()
        .find(|l| l.contains("SDO download 1A01h:00") && l.contains("02"))
        .unwrap();
    assert!(
        remap.ends_with(
            "[TPDO1 of node 5 maps 6000h:00/8, 6010h:00/16; applied to the frames on 285h that follow]"
        ),
        "{remap}"
    );
    let pdo = lines
        .iter()
        .find(|l| l.contains("  285  ") && l.contains("2A 34 12"))
        .unwrap();
    assert!(pdo.contains("[from SDO in the log]"), "{pdo}");
    assert!(
        pdo.contains("6000h unknown object: raw 2Ah")
            && pdo.contains("6010h unknown object: raw 1234h"),
        "{pdo}"
    );
    let moved = lines
        .iter()
        .find(|l| l.contains("SDO download 1801h:01"))
        .unwrap();
    assert!(
        moved.ends_with("[TPDO1 of node 5 now on 2A5h; its mapping applies there]"),
        "{moved}"
    );
    let last = lines.last().unwrap();
    assert!(last.contains("[from SDO in the log]"), "{last}");
    // In JSON the transfer carries the note and the PDO its fields.
    let v = json_lines(&run(&["--json", "-"], Some(input)));
    let notes: Vec<&str> = v.iter().filter_map(|x| x["pdo_config"].as_str()).collect();
    assert_eq!(notes.len(), 3, "{notes:?}");
    assert_eq!(notes[0], "TPDO1 of node 5: mapping cleared (0 entries)");
    assert!(notes[1].starts_with("TPDO1 of node 5 maps"), "{}", notes[1]);
    let fields = v.last().unwrap()["fields"].as_array().unwrap().len();
    assert_eq!(fields, 2);
}

/// A small device description of our own, for `--eds`: a pump controller
/// (CiA 401 device type) whose TPDO0 carries its speed (2000h sub 0,
/// UNSIGNED16) and temperature (2001h, INTEGER8), and whose SDO server is
/// not on the default COB-IDs: 640h/5C0h + $NODEID (643h/5C3h for node 3).
const PUMP_EDS: &str = "[FileInfo]\nFileName=pump.eds\n\n[DeviceInfo]\nVendorName=Us\nProductName=Pump\n\n\
[MandatoryObjects]\nSupportedObjects=1\n1=0x1000\n\n\
[1000]\nParameterName=Device type\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=0x00000191\nPDOMapping=0\n\n\
[OptionalObjects]\nSupportedObjects=4\n1=0x1200\n2=0x1800\n3=0x1A00\n4=0x2000\n\n\
[1200]\nParameterName=Server SDO parameter\nObjectType=0x9\nSubNumber=3\n\n\
[1200sub0]\nParameterName=Highest sub-index\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=2\nPDOMapping=0\n\n\
[1200sub1]\nParameterName=COB-ID client to server\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=$NODEID+0x640\nPDOMapping=0\n\n\
[1200sub2]\nParameterName=COB-ID server to client\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=$NODEID+0x5C0\nPDOMapping=0\n\n\
[1800]\nParameterName=TPDO0 communication\nObjectType=0x9\nSubNumber=2\n\n\
[1800sub0]\nParameterName=Highest sub-index\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=1\nPDOMapping=0\n\n\
[1800sub1]\nParameterName=COB-ID\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID+0x180\nPDOMapping=0\n\n\
[1A00]\nParameterName=TPDO0 mapping\nObjectType=0x9\nSubNumber=3\n\n\
[1A00sub0]\nParameterName=Number of entries\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\nDefaultValue=2\nPDOMapping=0\n\n\
[1A00sub1]\nParameterName=Entry 1\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0x20000010\nPDOMapping=0\n\n\
[1A00sub2]\nParameterName=Entry 2\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0x20010008\nPDOMapping=0\n\n\
[2000]\nParameterName=Pump\nObjectType=0x9\nSubNumber=2\n\n\
[2000sub0]\nParameterName=Speed\nObjectType=0x7\nDataType=0x0006\nAccessType=ro\nDefaultValue=0\nPDOMapping=1\n\n\
[2000sub1]\nParameterName=Unused\nObjectType=0x7\nDataType=0x0006\nAccessType=ro\nDefaultValue=0\nPDOMapping=1\n\n\
[2001]\nParameterName=Temperature\nObjectType=0x7\nDataType=0x0002\nAccessType=ro\nDefaultValue=0\nPDOMapping=1\n";

#[test]
fn eds_gives_pdo_mappings_sdo_channels_and_names() {
    let dir = std::env::temp_dir().join(format!("canopen-decode-eds-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("pump.eds");
    std::fs::write(&path, PUMP_EDS).unwrap();
    let arg = format!("3={}", path.display());
    let input = "183#3412F6\n643#4001200000000000\n5C3#4F012000F6000000\n";
    let o = run(&["--eds", &arg, "-"], Some(input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("node 3 from"), "{err}");
    assert!(err.contains("device type 00000191h (profile 401)"), "{err}");
    assert!(err.contains("PDOs mapped: TPDO0 on 183h"), "{err}");
    assert!(err.contains("SDO on 643h/5C3h"), "{err}");
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].ends_with("= [from the EDS] 2000h Pump: Speed 4660; 2001h Temperature -10"),
        "{}",
        lines[0]
    );
    assert!(
        lines[1].contains("SDO request to node 3: initiate upload 2001h sub 0"),
        "{}",
        lines[1]
    );
    assert_eq!(transfers(&out), ["SDO upload 2001h:00 from node 3: F6"]);
    // A file that is not there, or not an EDS, is a usage error.
    let o = run(&["--eds", "3=/nonexistent/pump.eds", "-"], Some(input));
    assert_eq!(o.status.code(), Some(2));
    let o = run(&["--eds", "pump.eds", "-"], Some(input));
    assert_eq!(o.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}
