//! The `canopen-replay` program against the virtual devices of
//! `examples/`: the real Delta-Q ICL1500 startup capture played both ways
//! (and from a BLF copy), a deliberately wrong charger, the stdin/stdout
//! mode, every trace format, usage errors and a device that dies.

use crate::blf_support;
use crate::common;
use crate::trace_writers;

use std::io::{Read, Write};
use std::path::PathBuf;
use std::process::{Command, Stdio};

use canopen_codec::CanFrame;
use serde_json::Value;
use trace_writers::{every_format, frames_of, BLF_START};

fn replay(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_canopen-replay"))
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code().unwrap(),
        String::from_utf8(o.stdout).unwrap(),
        String::from_utf8(o.stderr).unwrap(),
    )
}

/// The startup capture's path; absent: skipped, or a failure under CI.
fn startup() -> Option<String> {
    let p = common::captures::path(common::captures::STARTUP);
    if p.is_none() && std::env::var("CI").as_deref() == Ok("true") {
        panic!("the real capture is missing under CI");
    }
    p.map(|p| p.display().to_string())
}

fn virtual_session() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/virtual-session.log")
        .display()
        .to_string()
}

/// The differences of a JSON report as (kind, COB-ID) pairs.
fn differences(report: &Value) -> Vec<(String, String)> {
    report["differences"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| {
            (
                d["kind"].as_str().unwrap().to_string(),
                d["cob_id"].as_str().unwrap_or("-").to_string(),
            )
        })
        .collect()
}

fn pairs(list: &[(&str, &str)]) -> Vec<(String, String)> {
    list.iter()
        .map(|(k, c)| (k.to_string(), c.to_string()))
        .collect()
}

fn period(report: &Value, side: &str, cob: &str) -> f64 {
    report[side]["traffic"][cob]["period_ms"].as_f64().unwrap()
}

fn emcy_times(report: &Value, side: &str, name: &str) -> Vec<f64> {
    report[side]["emcys"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["name"].as_str().unwrap().ends_with(name))
        .map(|e| e["t_ms"].as_f64().unwrap())
        .collect()
}

/// The charger the capture shows, as far as the virtual one goes: default
/// COB-IDs, 340 ms battery heartbeat consumer time (the capture's E-0-3-2
/// comes 342 ms after the last battery heartbeat; the specification's
/// recommended 2000 ms does not reproduce it: see
/// `the_specifications_consumer_time_does_not_reproduce_the_captures_e_0_3_2`), the capture's TPDO
/// event timers (200 ms, 1000 ms, 1000 ms, the fourth off); its power
/// stage and battery are the models.
const CAPTURE_CHARGER: [&str; 6] = [
    "--no-configure",
    "--battery-timeout-ms",
    "340",
    "--tpdo-ms",
    "200,1000,1000,0",
    "--linger-ms",
];

#[test]
fn battery_side_of_the_startup_capture_into_the_virtual_charger() {
    let Some(capture) = startup() else { return };
    let charger = common::example("charger");
    let mut args = vec![&capture[..], "--play", "1", "--speed", "0", "--json"];
    args.extend(["--pdo-capture-mapping", "--", &charger]);
    args.extend(CAPTURE_CHARGER);
    args.push("0");
    let (code, out, err) = replay(&args);
    let report: Value = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}{err}"));
    // Reproduced: the 70Ah state changes to operational and back to
    // pre-operational (within one heartbeat period), the rates of 70Ah,
    // 18Ah, 28Ah and 38Ah, E-0-3-2 at the heartbeat loss and E-0-3-0 when
    // the module is gone, each within 100 ms.
    for cob in ["70A", "18A", "28A", "38A"] {
        let (r, d) = (
            period(&report, "recording", cob),
            period(&report, "device", cob),
        );
        assert!(
            (r - d).abs() <= r * 0.1,
            "{cob}: {r} ms recorded, {d} ms from the device"
        );
    }
    let nmt = &report["device"]["nmt"][0];
    assert_eq!(
        (nmt["from"].as_u64(), nmt["to"].as_u64()),
        (Some(0x7F), Some(0x05))
    );
    let recorded_start = report["recording"]["nmt"][0]["t_ms"].as_f64().unwrap();
    assert!((nmt["t_ms"].as_f64().unwrap() - recorded_start).abs() <= 1000.0);
    let back = &report["device"]["nmt"][1];
    assert_eq!(
        (back["from"].as_u64(), back["to"].as_u64()),
        (Some(0x05), Some(0x7F))
    );
    let recorded_back = report["recording"]["nmt"][1]["t_ms"].as_f64().unwrap();
    assert!((back["t_ms"].as_f64().unwrap() - recorded_back).abs() <= 1000.0);
    for alarm in ["E-0-3-2", "E-0-3-0"] {
        let (r, d) = (
            emcy_times(&report, "recording", alarm),
            emcy_times(&report, "device", alarm),
        );
        assert_eq!((r.len(), d.len()), (1, 1), "{alarm}");
        assert!(
            (r[0] - d[0]).abs() <= 100.0,
            "{alarm} at {} ms, recorded {} ms",
            d[0],
            r[0]
        );
    }
    // Not reproduced, each named (docs/REPLAY.md says why): the 48Ah TPDO
    // the virtual charger sends once on start, the two error-reset EMCYs
    // after the NMT start, and the integrator's PDO layouts of 18Ah and
    // 38Ah (the virtual charger has the Delta-Q defaults).
    assert_eq!(
        differences(&report),
        pairs(&[
            ("unexpected", "48A"),
            ("emcy missing", "08A"),
            ("emcy missing", "08A"),
            ("pdo length", "18A"),
            ("pdo length", "38A"),
        ])
    );
    let words: Vec<&str> = report["differences"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["words"].as_str().unwrap())
        .collect();
    assert!(words[1].contains("EEC 0000h"), "{words:?}");
    assert_eq!(code, 4);
}

#[test]
fn charger_side_of_the_startup_capture_into_the_virtual_battery_module() {
    let Some(capture) = startup() else { return };
    let module = common::example("battery_module");
    let (code, out, err) = replay(&[
        &capture,
        "--play",
        "10",
        "--speed",
        "0",
        "--json",
        "--",
        &module,
        "--heartbeat-ms",
        "100",
        "--linger-ms",
        "0",
    ]);
    let report: Value = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}{err}"));
    let (r, d) = (
        period(&report, "recording", "701"),
        period(&report, "device", "701"),
    );
    assert!(
        (r - d).abs() <= r * 0.1,
        "701h: {r} ms recorded, {d} ms from the device"
    );
    // The capture's battery controller is the NMT master and sends the
    // integrator's RPDOs 20Ah and 30Ah; the virtual module does neither.
    assert_eq!(
        differences(&report),
        pairs(&[("missing", "000"), ("missing", "20A"), ("missing", "30A")])
    );
    assert_eq!(code, 4);
}

/// Why the reproduction runs the charger with 340 ms: with the Delta-Q
/// specification's recommended heartbeat consumer time (2000 ms, the
/// charger's default) E-0-3-2 comes 2000 ms after the last battery
/// heartbeat, together with E-0-3-0, where the capture's came at 342 ms.
#[test]
fn the_specifications_consumer_time_does_not_reproduce_the_captures_e_0_3_2() {
    let Some(capture) = startup() else { return };
    let charger = common::example("charger");
    let mut args = vec![&capture[..], "--play", "1", "--speed", "0", "--json"];
    args.extend(["--pdo-capture-mapping", "--", &charger]);
    args.extend(
        CAPTURE_CHARGER
            .iter()
            .filter(|a| !["--battery-timeout-ms", "340"].contains(a)),
    );
    args.push("0");
    let (code, out, err) = replay(&args);
    let report: Value = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}{err}"));
    let after_cause = |name: &str| -> Vec<f64> {
        report["device"]["emcys"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|e| e["name"].as_str().unwrap().ends_with(name))
            .map(|e| e["after_cause_ms"].as_f64().unwrap())
            .collect()
    };
    // At the 2000 ms (the device's frames are timed by its clock on the
    // replay's: a few ms of scheduling at most).
    for name in ["E-0-3-2", "E-0-3-0"] {
        let t = after_cause(name);
        assert!(
            t.len() == 1 && (2000.0..2050.0).contains(&t[0]),
            "{name}: {t:?}"
        );
    }
    let late: Vec<&str> = report["differences"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["kind"] == "emcy time")
        .map(|d| d["words"].as_str().unwrap())
        .collect();
    assert_eq!(late.len(), 1, "{late:?}");
    assert!(late[0].contains("E-0-3-2"), "{late:?}");
    // 2000 ms where the capture has 342.1 ms.
    let off: f64 = late[0]
        .strip_suffix(" ms off")
        .and_then(|w| w.rsplit_once("the device's +"))
        .and_then(|(_, ms)| ms.parse().ok())
        .unwrap_or_else(|| panic!("{late:?}"));
    assert!((1657.0..1710.0).contains(&off), "{late:?}");
    assert_eq!(code, 4);
}

#[test]
fn a_wrong_charger_is_named_difference_by_difference() {
    let Some(capture) = startup() else { return };
    let charger = common::example("charger");
    // A 500 ms heartbeat instead of 1000 ms, and a consumer time so long
    // that E-0-3-2 never comes within the recording.
    let (code, out, _) = replay(&[
        &capture,
        "--play",
        "1",
        "--speed",
        "0",
        "--",
        &charger,
        "--no-configure",
        "--tpdo-ms",
        "200,1000,1000,0",
        "--heartbeat-ms",
        "500",
        "--battery-timeout-ms",
        "30000",
        "--linger-ms",
        "0",
    ]);
    assert_eq!(code, 4, "{out}");
    assert!(
        out.contains("period: 70Ah: period 1000.1 ms in the recording, 500.0 ms from the device"),
        "{out}"
    );
    assert!(
        out.contains("emcy missing: 08Ah: EMCY EEC 8130h reg 01h E-0-3-2 at 60292.6 ms is missing"),
        "{out}"
    );
}

#[test]
fn the_bundled_session_matches_the_virtual_charger_and_waits_for_sdo_answers() {
    let charger = common::example("charger");
    let module = common::example("battery_module");
    let session = virtual_session();
    // The module's side played into the charger, as fast as it answers
    // and at 20 times the recorded pace: the charger's SDO requests to the
    // module are answered by the played side.
    for speed in ["0", "20"] {
        let (code, out, _) = replay(&[
            &session,
            "--play",
            "1",
            "--speed",
            speed,
            "--",
            &charger,
            "--linger-ms",
            "0",
        ]);
        assert!(
            out.ends_with("the device matches the recording within tolerance\n"),
            "speed {speed}: {out}"
        );
        assert_eq!(code, 0);
    }
    // The charger's side played into the module: each SDO request waits for
    // the module's answer; all six are answered.
    let (code, out, _) = replay(&[
        &session,
        "--play",
        "10",
        "--speed",
        "0",
        "--json",
        "--",
        &module,
        "--linger-ms",
        "0",
    ]);
    let report: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(report["unanswered_sdo"].as_array().unwrap().len(), 0);
    assert_eq!(report["device"]["traffic"]["581"]["count"], 6);
    // The recorded module restarts at 9 s (its NMT state changes twice);
    // the virtual one, never reset, once.
    assert_eq!(differences(&report), pairs(&[("nmt", "701")]));
    assert_eq!(code, 4);
}

#[test]
fn stdin_stdout_mode_talks_to_a_device_on_the_other_end_of_the_pipes() {
    let mut replay = Command::new(env!("CARGO_BIN_EXE_canopen-replay"))
        .args([&virtual_session()[..], "--play", "1", "--speed", "0"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut charger = Command::new(common::example("charger"))
        .args(["--linger-ms", "0"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let (mut to_charger, mut from_charger) = (
        charger.stdin.take().unwrap(),
        charger.stdout.take().unwrap(),
    );
    let (mut to_replay, mut from_replay) =
        (replay.stdin.take().unwrap(), replay.stdout.take().unwrap());
    let a = std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n @ 1..) = from_replay.read(&mut buf) {
            if to_charger.write_all(&buf[..n]).is_err() {
                break;
            }
        }
    });
    let b = std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n @ 1..) = from_charger.read(&mut buf) {
            if to_replay.write_all(&buf[..n]).is_err() {
                break;
            }
        }
    });
    let mut report = String::new();
    replay
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut report)
        .unwrap();
    let status = replay.wait().unwrap();
    a.join().unwrap();
    let _ = charger.kill();
    let _ = charger.wait();
    b.join().unwrap();
    assert!(
        report.ends_with("the device matches the recording within tolerance\n"),
        "{report}"
    );
    assert_eq!(status.code(), Some(0));
}

#[test]
fn usage_errors_exit_2() {
    let session = virtual_session();
    let empty = std::env::temp_dir().join(format!("replay-empty-{}.log", std::process::id()));
    std::fs::write(&empty, "no frame here\n").unwrap();
    let empty = empty.display().to_string();
    for args in [
        vec![&session[..]],
        vec![&session, "--play", "200"],
        vec![&session, "--play", "1", "--speed", "-1"],
        vec![&session, "--play", "1", "--pdo", "18A=nonsense"],
        vec!["/nonexistent/trace.log", "--play", "1"],
        vec![&empty, "--play", "1"],
        vec![&session, "--play", "99"],
    ] {
        let (code, _, err) = replay(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(!err.is_empty(), "{args:?}");
    }
    let _ = std::fs::remove_file(&empty);
    // A BLF file without a frame, and a text one: each says how it was read.
    let blf = tmp("no-frame.blf", &blf_support::header(BLF_START));
    let (code, _, err) = replay(&[&blf, "--play", "1"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("the trace has no frames (0 unreadable object(s), read as blf)"),
        "{err}"
    );
    let text = tmp("no-frame.trc", b";$FILEVERSION=1.1\nnonsense\n");
    let (code, _, err) = replay(&[&text, "--play", "1"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("(1 unreadable line(s), read as trc; --format names one; the first: line 2: "),
        "{err}"
    );
}

#[test]
fn a_device_that_cannot_run_or_dies_exits_3() {
    let session = virtual_session();
    for device in [
        vec!["/nonexistent/device"],
        vec!["sh", "-c", "exit 1"],
        vec!["sh", "-c", "read line; exit 0"],
    ] {
        let mut args = vec![&session[..], "--play", "1", "--speed", "0", "--"];
        args.extend(&device);
        let (code, _, err) = replay(&args);
        assert_eq!(code, 3, "{device:?}: {err}");
        assert!(err.contains("canopen-replay:"), "{err}");
    }
}

#[test]
fn a_long_tail_is_cut_at_the_limit_and_said_so() {
    let Some(capture) = startup() else { return };
    let charger = common::example("charger");
    let started = std::time::Instant::now();
    let (code, out, _) = replay(&[
        &capture,
        "--play",
        "1",
        "--speed",
        "0",
        "--tail-limit-ms",
        "200",
        "--",
        &charger,
        "--no-configure",
        "--battery-timeout-ms",
        "340",
        "--linger-ms",
        "0",
    ]);
    assert!(started.elapsed() < std::time::Duration::from_secs(3));
    assert!(
        out.contains("the recording's tail after the last played frame was cut at --tail-limit-ms"),
        "{out}"
    );
    // The heartbeat loss comes 340 ms after the last played frame: cut off.
    assert!(out.contains("E-0-3-2 at 60292.6 ms is missing"), "{out}");
    assert_eq!(code, 4);
}

/// Writes `bytes` to a file of the test's own and gives its path.
fn tmp(name: &str, bytes: &[u8]) -> String {
    let safe: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("replay-{safe}"));
    std::fs::write(&path, bytes).unwrap();
    path.display().to_string()
}

/// What a replay report says about the recording alone (the same for the
/// same frames whatever the format) and its verdict.
fn recording_and_verdict(report: &Value) -> (Value, Value, Value, Value) {
    (
        report["recording"].clone(),
        report["played"].clone(),
        report["matches"].clone(),
        Value::from(
            differences(report)
                .iter()
                .map(|(k, c)| format!("{k} {c}"))
                .collect::<Vec<_>>(),
        ),
    )
}

/// The bundled session (times cut to whole milliseconds, which every
/// format carries exactly) written in every trace format the decoder
/// reads: each replays into the virtual charger as its candump log does,
/// the recording's figures the same to the microsecond and the device a
/// match (exit 0).
#[test]
fn every_trace_format_replays_as_the_candump_log_of_the_same_frames() {
    let log = std::fs::read_to_string(virtual_session()).unwrap();
    let frames: Vec<(u64, CanFrame)> = frames_of(&log)
        .into_iter()
        .map(|(us, f)| (us / 1000 * 1000, f))
        .collect();
    let charger = common::example("charger");
    let run = |path: &str, format: Option<&str>| {
        let mut args = vec![path, "--play", "1", "--speed", "0", "--json"];
        if let Some(f) = format {
            args.extend(["--format", f]);
        }
        args.extend(["--", &charger, "--linger-ms", "0"]);
        let (code, out, err) = replay(&args);
        let report: Value =
            serde_json::from_str(&out).unwrap_or_else(|e| panic!("{path}: {e}: {out}{err}"));
        (code, recording_and_verdict(&report), err)
    };
    let formats = every_format(&frames);
    let original = tmp("session.log", &formats[0].2);
    let (code, want, _) = run(&original, None);
    assert_eq!(code, 0, "{want:?}");
    assert_eq!(want.1, Value::from(58), "{want:?}");
    for (name, format, bytes) in &formats {
        let path = tmp(name, bytes);
        let (got_code, got, err) = run(&path, *format);
        assert_eq!(got, want, "{name}: {err}");
        assert_eq!(got_code, code, "{name}: {err}");
        assert!(!err.contains("unreadable"), "{name}: {err}");
    }
}

/// The real startup capture as a BLF file (zlib containers) replays as
/// its candump original does: the same recording, the same differences.
#[test]
fn a_blf_copy_of_the_startup_capture_replays_as_the_original() {
    let Some(capture) = startup() else { return };
    let frames = frames_of(&std::fs::read_to_string(&capture).unwrap());
    let blf = tmp(
        "startup.blf",
        &blf_support::file(
            BLF_START,
            &blf_support::can_objects(&frames),
            64 * 1024,
            true,
        ),
    );
    let charger = common::example("charger");
    let run = |path: &str| {
        let mut args = vec![path, "--play", "1", "--speed", "0", "--json"];
        args.extend(["--pdo-capture-mapping", "--", &charger]);
        args.extend(CAPTURE_CHARGER);
        args.push("0");
        let (code, out, err) = replay(&args);
        let report: Value =
            serde_json::from_str(&out).unwrap_or_else(|e| panic!("{path}: {e}: {out}{err}"));
        (code, recording_and_verdict(&report))
    };
    let (want_code, want) = run(&capture);
    let (code, got) = run(&blf);
    assert_eq!(got, want);
    assert_eq!(code, want_code);
    assert_eq!(code, 4);
}
