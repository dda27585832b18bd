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
    // The bundled capture is decoded with its integrator's PDO mapping.
    assert!(out.contains("with its integrator's PDO mapping"), "{out}");
    assert!(
        out.contains("2002h charging current 19.48 A; 2101h battery voltage 78.27 V"),
        "{out}"
    );
    assert_eq!(
        out.lines().filter(|l| l.contains(" 701  battery")).count(),
        525
    );
}

/// The capture README's mapping, as `--pdo` arguments (padding the README
/// leaves unnamed as CiA 301 dummy entries 0005h / 0006h).
const CAPTURE_PDO_ARGS: [&str; 9] = [
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
    let mut args = CAPTURE_PDO_ARGS.to_vec();
    args.push(CHARGING);
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
    let short = run(&["--pdo-capture-mapping", CHARGING], None);
    assert_eq!(text(&short), out);

    // The startup capture's BMS reports no current yet.
    let startup = text(&run(&["--pdo-capture-mapping", STARTUP], None));
    assert!(startup.contains(
        "30A  charger  RPDO1 node 10: 00 00 00 00 00 4E 30 02 = 2002h charging current 0 A; \
         2101h battery voltage 78 V; 6010h temperature 70 degC"
    ));
}

#[test]
fn capture_mapping_in_json() {
    let o = run(&["--json", "--pdo-capture-mapping", CHARGING], None);
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
    let o = run(&["-"], Some(input));
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

    let o = run(&["--json", "-"], Some(input));
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
    let o = run(&["--no-default-pdos", "-"], Some(input));
    assert!(!text(&o).contains(" = "));

    // A given mapping on the battery node reads CiA 418 objects only; a
    // short frame marks the missing field.
    let o = run(&["--pdo=181=2002:0:16,6081:0:8", "-"], Some("181#7413\n"));
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
        (&["--pdo"][..], "--pdo needs"),
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
        assert!(err.contains("usage: decode"), "{err}");
    }
}
