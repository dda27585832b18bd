//! The scenario files of `scenarios/` (the use cases of "Delta-Q IC Series
//! CANopen interface specification rev 2.0", section 7, in each operating
//! mode): every one is read with the bench program's TOML reading and run
//! through the library, and its `[expect]` must hold; bad files name their
//! line; a lossy bus still charges and bus-off raises the charger's CAN bus
//! error; the program itself exits 0, 4 and 2 and prints the JSON lines.

use std::path::PathBuf;

use canopen_codec::deltaq::DeltaQCode;
use canopen_codec::sim::bench::{BenchEvent, Script, ScriptError};

#[path = "../../src/bin/canopen-bench/toml_tree.rs"]
mod toml_tree;

fn scenarios() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenarios")
}

pub(crate) fn script(text: &str) -> Result<Script, ScriptError> {
    Script::from_document(&toml_tree::read(text)?)
}

#[test]
fn every_scenario_file_holds_its_expectations() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenarios())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 30, "{} scenario files", files.len());
    let mut failed = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        assert!(text.starts_with("# "), "{}: no comment", file.display());
        let script = script(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let (_, summary) = script.run(|_| {}).unwrap();
        for f in script.expect.check(&summary) {
            failed.push(format!("{}: {f}", file.display()));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

const BASE: &str = "[charger]\nmode = \"remote\"\n[battery]\nchemistry = \"li-ion\"\ncells = 13\ncapacity_ah = 100\nsoc = 20\n";

#[test]
fn unknown_keys_and_bad_values_name_their_line() {
    let cases = [
        ("[run]\nuntil = \"0:01:00\"\ncolour = 3\n", 10, "unknown key colour in [run]"),
        ("[run]\nuntil = \"0:61:00\"\n", 9, "expected a time h:mm:ss"),
        (
            "[[event]]\nat = \"0:00:10\"\naction = \"explode\"\n[run]\nuntil = \"0:01:00\"\n",
            10,
            "unknown action \"explode\"",
        ),
        (
            "[[event]]\nat = \"0:00:10\"\naction = \"bus-loss\"\nvalue = 2\n[run]\nuntil = \"0:01:00\"\n",
            11,
            "expected a probability from 0 to 1, found 2",
        ),
        (
            "[run]\nuntil = \"0:01:00\"\n[expect]\nalarms = [\"E-0-0-1\", \"E-9\"]\n",
            11,
            "found \"E-9\"",
        ),
        ("[run]\nuntil = \"0:01:00\"\n[expect]\nstate = \"charging\"\n", 11, "unknown state"),
    ];
    for (tail, line, words) in cases {
        let e = script(&format!("{BASE}{tail}")).unwrap_err();
        assert_eq!(e.line, line, "{tail}: {e}");
        assert!(e.message.contains(words), "{tail}: {e}");
    }
    let e = script(&BASE.replace("li-ion", "unobtainium")).unwrap_err();
    assert_eq!(e.line, 4, "{e}");
    let e = script("[charger\n").unwrap_err();
    assert!(e.message.contains("line 1"), "{e}");
}

#[test]
fn the_charger_chooses_from_6020h_unless_the_file_sets_its_algorithms() {
    let active = |text: &str| {
        let (s, summary) = script(text).unwrap().run(|_| {}).unwrap();
        let c = s.charger().unwrap().charge_control();
        (c.active_algorithm(), c.permanent_algorithm(), summary)
    };
    let minute = "[run]\nuntil = \"0:01:00\"\n";
    // Remote, no permanent algorithm: the module's 13 li-ion cells choose
    // 11 (its thresholds), the BMS's 25 A flow meanwhile.
    let (id, permanent, summary) = active(&format!("{BASE}{minute}"));
    assert_eq!((id, permanent), (Some(11), None));
    assert!(summary.output_on);
    // A permanent algorithm is kept whatever the module says.
    let set = BASE.replace("mode = \"remote\"\n", "mode = \"remote\"\nalgorithm = 13\n");
    assert_eq!(active(&format!("{set}{minute}")).0, Some(13));
    // Local without CAN: after the hold-off the file's default, 12 A.
    let alone = BASE.replace(
        "mode = \"remote\"\n",
        "mode = \"local\"\nno_can_algorithm = 13\n",
    );
    let silent = "[[event]]\nat = \"0:00:00\"\naction = \"bms-silent\"\n";
    let (id, _, summary) = active(&format!("{alone}{silent}{minute}"));
    assert_eq!(id, Some(13));
    assert_eq!(
        summary.state,
        canopen_codec::deltaq::charge::ChargePhase::Bulk
    );
    assert!(summary.ah > 12.0 * 50.0 / 3600.0 * 0.95 && summary.ah < 12.0 * 50.0 / 3600.0 * 1.05);
    // An id the charger does not have names its line.
    let bad = BASE.replace("mode = \"remote\"\n", "mode = \"remote\"\nalgorithm = 99\n");
    let e = script(&format!("{bad}{minute}")).unwrap_err();
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("unknown algorithm \"99\""), "{e}");
}

/// The run of `script` with the JSON lines it reports.
fn run(text: &str) -> (Vec<String>, canopen_codec::sim::bench::Summary) {
    let mut lines = Vec::new();
    let (_, summary) = script(text).unwrap().run(|e| lines.push(e.json())).unwrap();
    (lines, summary)
}

#[test]
fn a_session_with_five_percent_loss_still_charges() {
    let lossy = format!("{BASE}[bus]\nloss = 0.05\nseed = 7\n[run]\nuntil = \"0:30:00\"\n");
    let (lines, summary) = run(&lossy);
    // 25 A for 30 min, a BMS request lost now and then changes nothing.
    assert!(summary.ah > 12.0, "{summary:?}");
    assert!(summary.output_on);
    // The same seed loses the same frames: the same run.
    assert_eq!(run(&lossy).0, lines);
    let other = lossy.replace("seed = 7", "seed = 8");
    assert_ne!(run(&other).0, lines);
}

#[test]
fn bus_off_raises_the_can_bus_error_and_frames_are_lost() {
    let text = format!(
        "{BASE}[[event]]\nat = \"0:01:00\"\naction = \"bus-off\"\nvalue = \"0:00:30\"\n[run]\nuntil = \"0:03:00\"\n"
    );
    let mut events = Vec::new();
    let (s, _) = script(&text)
        .unwrap()
        .run(|e| events.push(e.clone()))
        .unwrap();
    let raised = |code: DeltaQCode, raised: bool| {
        events.iter().find_map(|e| match e {
            BenchEvent::Alarm {
                at,
                code: c,
                raised: r,
            } if *c == code && *r == raised => Some(at.as_millis()),
            _ => None,
        })
    };
    // Raised at the charger's first frame in the window (its controller
    // goes bus-off), cleared once it has recovered: 128 x 11 bits at
    // 125 kbit/s after the bus is back.
    let up = raised(DeltaQCode::CAN_BUS_COMMUNICATION, true).unwrap();
    assert!((60_000..61_000).contains(&up), "{up}");
    assert_eq!(
        raised(DeltaQCode::CAN_BUS_COMMUNICATION, false),
        Some(90_011)
    );
    assert!(
        s.bus().lost_to_bus_off() > 100,
        "{}",
        s.bus().lost_to_bus_off()
    );
    // Nothing reached the bus while it was off.
    assert!(!s
        .log()
        .iter()
        .any(|l| (60_001..90_000).contains(&l.at.as_millis())));
}

#[test]
fn a_heavy_loss_takes_the_charger_error_passive_and_frames_are_missing() {
    // 30 % of the frames lost from 0:01 to 0:02: the charger's transmit
    // error counter climbs (8 per lost frame, 1 off per good one) past 127,
    // its controller is error passive or bus-off and reports E-0-2-9; once
    // the loss is over the counter comes down and the alarm clears.
    let text = format!(
        "{BASE}[[event]]\nat = \"0:01:00\"\naction = \"bus-loss\"\nvalue = 0.3\n[[event]]\nat = \"0:02:00\"\naction = \"bus-loss\"\nvalue = 0\n[run]\nuntil = \"0:04:00\"\n"
    );
    let mut events = Vec::new();
    let (s, _) = script(&text)
        .unwrap()
        .run(|e| events.push(e.clone()))
        .unwrap();
    let changes: Vec<(u64, bool)> = events
        .iter()
        .filter_map(|e| match e {
            BenchEvent::Alarm { at, code, raised }
                if *code == DeltaQCode::CAN_BUS_COMMUNICATION =>
            {
                Some((at.as_millis(), *raised))
            }
            _ => None,
        })
        .collect();
    assert!(!changes.is_empty(), "no E-0-2-9");
    assert!(
        changes.iter().all(|c| (60_000..125_000).contains(&c.0)),
        "{changes:?}"
    );
    assert!(changes.first().is_some_and(|c| c.1), "{changes:?}");
    assert!(changes.last().is_some_and(|c| !c.1), "{changes:?}");
    // The charger's TPDO 3 every second: a minute without loss logs all
    // of them, the lossy minute far fewer.
    let count = |from: u64, to: u64| {
        s.log()
            .iter()
            .filter(|l| l.frame.id().raw() == 0x48A && (from..to).contains(&l.at.as_millis()))
            .count()
    };
    let (before, lossy) = (count(0, 60_000), count(60_000, 120_000));
    assert!(lossy * 10 < before * 8, "{lossy} of {before} in a minute");
}

#[test]
fn json_lines_are_the_issues() {
    let text = format!(
        "{BASE}[[event]]\nat = \"0:01:30\"\naction = \"bms-silent\"\n[run]\nuntil = \"0:02:00\"\n"
    );
    let (lines, _) = run(&text);
    let expected = [
        r#"{"t": 0, "event": "state", "state": "idle"}"#,
        r#"{"t": 0.02, "event": "state", "state": "remote"}"#,
    ];
    assert_eq!(lines[..2], expected);
    let sample: serde_json::Value = serde_json::from_str(&lines[2]).unwrap();
    assert_eq!(sample["t"], 60);
    assert_eq!(sample["event"], "sample");
    assert_eq!(sample["current_a"], 25.0);
    for key in ["voltage_v", "soc", "temperature_c"] {
        assert!(sample[key].is_f64(), "{key}: {sample}");
    }
    assert!(
        lines.contains(
            &r#"{"t": 92, "event": "alarm", "code": "E-0-3-2", "raised": true}"#.to_string()
        ),
        "{lines:#?}"
    );
    let end: serde_json::Value = serde_json::from_str(lines.last().unwrap()).unwrap();
    assert_eq!(end["event"], "end");
    assert_eq!(end["state"], "idle");
    assert_eq!(end["alarms"], serde_json::json!(["E-0-3-2", "E-0-3-0"]));
    assert!(end["ah"].as_f64().unwrap() > 0.6);
}

#[cfg(feature = "cli")]
mod program {
    use std::process::Command;

    fn bench(args: &[&str]) -> (i32, String, String) {
        let out = Command::new(env!("CARGO_BIN_EXE_canopen-bench"))
            .args(args)
            .output()
            .unwrap();
        let text = |b: Vec<u8>| String::from_utf8(b).unwrap();
        (
            out.status.code().unwrap(),
            text(out.stdout),
            text(out.stderr),
        )
    }

    #[test]
    fn exit_codes_json_lines_log_and_report() {
        let dir = std::env::temp_dir().join(format!("canopen-bench-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = super::scenarios().join("04-terminate-via-6000h-remote.toml");
        let file = file.to_str().unwrap();
        let log = dir.join("bus.log");
        let report = dir.join("report.html");
        let (code, out, _) = bench(&[
            "run",
            file,
            "--json",
            "--log",
            log.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ]);
        assert_eq!(code, 0);
        let last: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
        assert_eq!(last["state"], "idle");
        let log = std::fs::read_to_string(&log).unwrap();
        assert!(
            log.lines()
                .next()
                .unwrap()
                .starts_with("(1767225600.000000) can0 70A#00"),
            "{log:.200}"
        );
        assert!(std::fs::read_to_string(&report).unwrap().contains("<html"));
        // The same file expecting the output on: 4, and says why.
        let wrong = dir.join("wrong.toml");
        let text = std::fs::read_to_string(file)
            .unwrap()
            .replace("output = \"off\"", "output = \"on\"");
        std::fs::write(&wrong, text).unwrap();
        let (code, _, err) = bench(&["run", wrong.to_str().unwrap()]);
        assert_eq!(code, 4);
        assert!(
            err.contains("output at the end: expected on, found off"),
            "{err}"
        );
        // A bad value: 2, naming the line.
        std::fs::write(&wrong, "[charger]\nmode = \"turbo\"\n").unwrap();
        let (code, _, err) = bench(&["run", wrong.to_str().unwrap()]);
        assert_eq!(code, 2);
        assert!(err.contains("line 2: unknown mode \"turbo\""), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn voltage_max_bounds_the_highest_battery_voltage_of_the_run() {
    let text = format!("{BASE}[run]\nuntil = \"0:30:00\"\n");
    let mut samples = Vec::new();
    let (_, summary) = script(&text)
        .unwrap()
        .run(|e| {
            if let BenchEvent::Sample { voltage_v, .. } = e {
                samples.push(*voltage_v);
            }
        })
        .unwrap();
    let sampled = samples.iter().copied().fold(f64::MIN, f64::max);
    // Charging at 25 A the voltage rises: the highest of every step is at
    // least every minute's sample, and below the algorithm's 13 x 4.25 V.
    assert!(sampled > samples[0], "{samples:?}");
    assert!(summary.voltage_max >= sampled, "{summary:?}");
    assert!(summary.voltage_max < 13.0 * 4.25, "{summary:?}");
    let check = |v: f64| {
        script(&format!("{text}[expect]\nvoltage_max = {v}\n"))
            .unwrap()
            .expect
            .check(&summary)
    };
    assert!(check(summary.voltage_max + 0.01).is_empty());
    let failed = check(sampled - 0.01);
    assert_eq!(failed.len(), 1, "{failed:?}");
    assert!(failed[0].contains("highest battery voltage"), "{failed:?}");
}
