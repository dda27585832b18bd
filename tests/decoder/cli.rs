//! The `canopen-decode` program run on the real captures (read from the
//! shared data folder beside the checkout: `common::captures`) and on our
//! own logs: the trace formats, bad lines, usage, roles, guarding,
//! deviations, CSV, the summary, LSS and the line cache. Cargo builds the
//! program for these tests (feature `cli`); SDO and PDO options are in
//! `decoder_sdo.rs` and `decoder_pdo.rs`.

use crate::common;
use crate::decoder_support;

use std::process::{Command, Stdio};

use decoder_support::*;
use serde_json::Value;

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

/// A line that is not UTF-8 or longer than 64 KiB is one bad line: the
/// run reports it with its number and goes on.
#[test]
fn lines_not_text_or_too_long_are_bad_lines() {
    let mut input = b"(1.000000) can0 701#05\n(1.5) can0 \xFF\xFE701#05\n".to_vec();
    input.extend(std::iter::repeat_n(b'x', 70_000));
    input.extend(b"\r\n(2.000000) can0 701#7F\r\n(3.000000) can0 701#05");
    let dir = std::env::temp_dir().join(format!("canopen-decode-bytes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.log");
    std::fs::write(&path, &input).unwrap();
    let o = run(&[path.to_str().unwrap()], None);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8(o.stderr.clone()).unwrap();
    assert!(err.contains("line 2: not UTF-8 text"), "{err}");
    assert!(err.contains("line 3: longer than 65536 bytes"), "{err}");
    assert!(err.contains("2 bad line(s)"), "{err}");
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[0].contains("heartbeat node 1: operational"), "{out}");
    assert!(lines[1].starts_with("         2.000000"), "{out}");
    assert!(
        lines[1].contains("heartbeat node 1: pre-operational"),
        "{out}"
    );
    assert!(lines[2].contains("heartbeat node 1: operational"), "{out}");
}

/// Heartbeats whose period is near the largest time a trace can give
/// (three periods do not fit in 64 bits of microseconds): the summary
/// still reads them (found by the `decoder_run` fuzz target).
#[test]
fn summary_of_heartbeats_days_apart_at_the_end_of_time() {
    let input = "(1.000000) can0 701#05\n(7000000000000.000000) can0 701#05\n\
                 (14000000000000.000000) can0 701#05\n(18000000000000.000000) can0 701#05\n\
                 (18446744073709.551615) can0 701#05\n";
    for (output, expect) in [
        (
            "words",
            "heartbeats: 5, period 6999999999999000 ms, largest gap 7000000000000000 ms",
        ),
        ("json", "\"heartbeats\":5,\"period_ms\":6999999999999000"),
    ] {
        let o = run(&["--summary-only", "--output", output, "-"], Some(input));
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(text(&o).contains(expect), "{}", text(&o));
    }
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

/// `rxtx` says which way a frame went where the trace tells (candump lines
/// with python-can's `R` / `T` flag, `.trc` 1.1, ASC), also for the same
/// frame seen both ways (its text comes from the line cache); a trace that
/// does not tell gives no `rxtx`.
#[test]
fn json_rxtx_where_the_trace_says() {
    let traces = [
        "(1.0) can0 70A#05 R\n(1.1) can0 70A#05 T\n(1.2) can0 70A#05 R\n",
        ";$FILEVERSION=1.1\n     1)      1000.0  Rx         070A  1  05\n\
         \x20    2)      1100.0  Tx         070A  1  05\n     3)      1200.0  Rx         070A  1  05\n",
        "base hex  timestamps absolute\n   1.000000 1  70A             Rx   d 1 05\n\
         \x20  1.100000 2  70A             Tx   d 1 05\n   1.200000 1  70A             Rx   d 1 05\n",
    ];
    for trace in traces {
        let o = run(&["--json"], Some(trace));
        assert!(o.status.success(), "{trace}");
        let rxtx: Vec<String> = text(&o)
            .lines()
            .map(|l| serde_json::from_str::<Value>(l).unwrap()["rxtx"].to_string())
            .collect();
        assert_eq!(rxtx, ["\"rx\"", "\"tx\"", "\"rx\""], "{trace}");
    }
    let o = run(&["--json"], Some("(1.0) can0 70A#05\n"));
    let v: Value = serde_json::from_str(text(&o).trim()).unwrap();
    assert!(v.get("rxtx").is_none(), "{v}");
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
    assert!(
        text(&o).contains("{\"kind\":\"role\",\"node\":1,\"role\":\"battery\",\"deltaq\":false,")
    );
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
fn the_line_cache_never_changes_the_output() {
    // Every output of every log we have, with and without the cache that
    // repeats the text of a frame equal to the last on its identifier; the
    // PDO-remapping log changes mappings midway (the cache is cleared).
    let remap = "285#2A3412\n605#2F011A0000000000\n585#60011A0000000000\n\
605#23011A0108000060\n585#60011A0100000000\n605#2F011A0001000000\n585#60011A0000000000\n\
285#2A3412\n285#2A3412\n701#7F\n701#05\n701#05\n";
    let dir = std::env::temp_dir().join(format!("canopen-decode-cache-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let remap_path = dir.join("remap.log");
    std::fs::write(&remap_path, remap).unwrap();
    let mut logs = vec![
        "tests/data/virtual-session.log".to_string(),
        SDO_SAMPLE.to_string(),
        remap_path.display().to_string(),
    ];
    logs.extend(capture(common::captures::STARTUP));
    logs.extend(capture(common::captures::CHARGING));
    for log in &logs {
        for output in ["words", "json", "csv"] {
            let args = [
                "--charger-node",
                "10",
                "--battery-node",
                "1",
                "--summary",
                "--output",
                output,
            ];
            let mut with: Vec<&str> = args.to_vec();
            with.push(log);
            let mut without = with.clone();
            without.insert(0, "--no-cache");
            let (a, b) = (run(&with, None), run(&without, None));
            assert_eq!(a.status.code(), b.status.code(), "{log} {output}");
            assert!(
                a.stdout == b.stdout,
                "{log} {output}: the cached output differs"
            );
        }
    }
    // The remapped PDO changed its text after the remap, though the frame
    // is the same.
    let out = text(&run(&[remap_path.to_str().unwrap()], None));
    let pdo: Vec<&str> = out.lines().filter(|l| l.contains("  285  ")).collect();
    assert_eq!(pdo.len(), 3);
    assert!(!pdo[0].contains("from SDO"), "{}", pdo[0]);
    assert!(
        pdo[1].contains("from SDO") && pdo[2].contains("from SDO"),
        "{pdo:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
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

/// A PCAN-View 1.0 trace (no `;$FILEVERSION` line) is read as 1.0, as
/// PEAK and python-can read it: every line a frame, exit 0.
#[test]
fn header_less_pcan_trace_is_read_as_1_0() {
    let log =
        "     1)      1841  070A  1  05\n     2)      1941  018A  8  7C 13 46 4E 70 00 00 00\n";
    let o = run(&["--format", "trc", "-"], Some(log));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    assert_eq!(out.lines().count(), 2, "{out}");
    assert!(out.contains("heartbeat node 10: operational"), "{out}");
}

/// A file of which no line is a frame is an error that names the format
/// tried (here a 1.0 trace wrongly declared 1.1: every line an event).
#[test]
fn a_log_without_frames_exits_1_naming_the_format() {
    let log = ";$FILEVERSION=1.1\n     1)      1841  070A  1  05\n";
    no_frame_in_a_trc(log);
}

/// `log` (two lines, read as `.trc`) exits 1 saying no line is a frame;
/// returns the stderr.
fn no_frame_in_a_trc(log: &str) -> String {
    let o = run(&["-"], Some(log));
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(
        err.contains("none of the 2 line(s) is a CAN frame (read as trc"),
        "{err}"
    );
    err
}

/// A trace of headers alone has no bad line: the exit status is 1 for the
/// missing frames, and the message does not count a bad line that is not.
#[test]
fn a_log_of_headers_alone_counts_no_bad_line() {
    let log = ";$FILEVERSION=2.1\n;$COLUMNS=N,O,T,B,I,d,R,L,D\n";
    let err = no_frame_in_a_trc(log);
    assert!(!err.contains("bad line"), "{err}");
}
