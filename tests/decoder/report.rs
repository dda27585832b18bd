//! `canopen-decode --report FILE.html`: the page is self-contained, its
//! data says what the log holds (compared with `--json`), the frames are
//! not printed unless asked for, and a long log's page stays small (the
//! plots decimated, every sample counted). The page rendered in a real
//! browser is checked by tests/interop/report_browser.py in CI.

use crate::common;
use crate::decoder_support;

use decoder_support::*;
use serde_json::Value;

/// Runs the decoder with `--report` on `args` and returns the page's
/// text, its embedded data and the program's stdout.
fn report(args: &[&str], stdin: Option<&str>, name: &str) -> (String, Value, String) {
    let path =
        std::env::temp_dir().join(format!("canopen-report-{}-{name}.html", std::process::id()));
    let path_text = path.to_str().unwrap().to_string();
    let mut all = args.to_vec();
    all.extend(["--report", &path_text]);
    let o = run(&all, stdin);
    assert!(
        o.status.code().is_some_and(|c| c <= 1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let page = std::fs::read_to_string(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    let start = page.find("id=\"report-data\">").unwrap() + "id=\"report-data\">".len();
    let end = start + page[start..].find("</script>").unwrap();
    let data: Value = serde_json::from_str(&page[start..end].replace("<\\/", "</")).unwrap();
    (page, data, text(&o))
}

fn self_contained(page: &str) {
    for bad in ["http://", "https://", "<link", " src="] {
        assert!(!page.contains(bad), "the page refers outside itself: {bad}");
    }
}

#[test]
fn bundled_session_report_shows_what_the_log_holds() {
    let (page, data, stdout) = report(&["--bundled", "session"], None, "bundled");
    self_contained(&page);
    // --report alone prints no frame lines.
    assert_eq!(stdout, "");
    assert!(page.contains("summary:") && page.contains("Delta-Q E-0-3-2 heartbeat lost"));
    // One series per named field of the session's PDOs, every sample kept.
    let labels: Vec<&str> = data["series"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["label"].as_str().unwrap())
        .collect();
    assert_eq!(
        labels,
        [
            "181h 6000h battery status [raw]",
            "181h 6010h temperature [degC]",
            "201h 6001h charger status [raw]"
        ]
    );
    for s in data["series"].as_array().unwrap() {
        assert_eq!(s["exact"], true);
        assert_eq!(
            s["t"].as_array().unwrap().len() as u64,
            s["samples"].as_u64().unwrap()
        );
    }
    // The temperature samples equal --json's values.
    let o = run(&["--bundled", "session", "--json"], None);
    let want: Vec<f64> = json_lines(&o)
        .iter()
        .filter(|l| l["id"] == 0x181)
        .flat_map(|l| l["fields"].as_array().cloned().unwrap_or_default())
        .filter(|f| f["index"] == 0x6010)
        .map(|f| f["value"].as_f64().unwrap())
        .collect();
    let temp = &data["series"][1];
    let got: Vec<f64> = temp["v"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    // Equal values in a row may be one point: the drawn points are a
    // subsequence with the same values.
    assert_eq!(got.len(), want.len());
    assert_eq!(got, want);
    // The timeline: the battery's silence 5 s to 9 s, the charger's EMCY
    // and its reset, two NMT starts on the bus row.
    let rows = data["rows"].as_array().unwrap();
    let battery = rows.iter().find(|r| r["node"] == 1).unwrap();
    assert_eq!(battery["silences"], serde_json::json!([[5.0, 9.0]]));
    let charger = rows.iter().find(|r| r["node"] == 10).unwrap();
    let kinds: Vec<&str> = charger["marks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m[1].as_str().unwrap())
        .collect();
    // E-0-3-2 at the loss, E-0-3-0 when the module is gone, the reset.
    assert_eq!(kinds, ["boot-up", "emcy", "emcy", "emcy-reset"]);
    let bus = rows.iter().find(|r| r["node"] == 0).unwrap();
    assert_eq!(bus["marks"].as_array().unwrap().len(), 2);
    assert_eq!(data["marks"], 15);
}

#[test]
fn report_with_json_still_prints_the_frames() {
    let (_, _, stdout) = report(&["--bundled", "session", "--json"], None, "json");
    let plain = run(&["--bundled", "session", "--json"], None);
    assert_eq!(stdout, text(&plain));
    assert!(stdout.lines().count() > 100);
}

#[test]
fn startup_capture_report() {
    let Some(startup) = capture(common::captures::STARTUP) else {
        return;
    };
    let (page, data, _) = report(&["--pdo-capture-mapping", &startup], None, "startup");
    self_contained(&page);
    let charger = data["rows"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["node"] == 10)
        .unwrap();
    let emcys: Vec<&str> = charger["marks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m[1] == "emcy")
        .map(|m| m[2].as_str().unwrap())
        .collect();
    assert_eq!(emcys.len(), 2);
    assert!(
        emcys[0].contains("E-0-3-2") && emcys[1].contains("E-0-3-0"),
        "{emcys:?}"
    );
    assert_eq!(data["series"].as_array().unwrap().len(), 14);
}

#[test]
fn a_long_log_gives_a_small_page_with_every_sample_counted() {
    // The bundled session repeated with its times shifted: 300 copies,
    // about 42 000 lines, 12 000 temperature samples.
    let session = std::fs::read_to_string("tests/data/virtual-session.log").unwrap();
    let mut log = String::new();
    let copies = 300u64;
    for k in 0..copies {
        for line in session.lines() {
            let Some(rest) = line.strip_prefix('(') else {
                continue;
            };
            let (t, tail) = rest.split_once(')').unwrap();
            let (s, us) = t.split_once('.').unwrap();
            let s: u64 = s.parse::<u64>().unwrap() + 13 * k;
            log.push_str(&format!("({s}.{us}){tail}\n"));
        }
    }
    let args = ["--charger-node", "10", "--battery-node", "1", "-"];
    let (page, data, _) = report(&args, Some(&log), "long");
    let temp = &data["series"][1];
    assert_eq!(temp["samples"], 40 * copies);
    assert_eq!(temp["exact"], false);
    let points = temp["t"].as_array().unwrap().len();
    // Between half the bucket cap and two points per bucket.
    assert!((1200..=2 * 2400).contains(&points), "{points} points");
    // 2 boot-ups per copy on node 1: all drawn (under the mark cap).
    let battery = data["rows"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["node"] == 1)
        .unwrap();
    let boot_ups = battery["marks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m[1] == "boot-up")
        .count();
    assert_eq!(boot_ups as u64, 2 * copies);
    assert!(page.len() < 1_500_000, "{} bytes", page.len());
}

/// A foreign trace (no role, no mapping): the report plots the bus load
/// per 1-second window, each node's frames per second and the raw bytes
/// of the PDO no mapping names; a node only addressed by NMT has no row.
#[test]
fn a_foreign_trace_plots_its_traffic_and_lists_only_nodes_heard() {
    // NMT resets node 5, which never sends; node 6 sends TPDO1 (no
    // mapping) and a heartbeat.
    let log = "(1.000000) can0 000#8105\n(1.100000) can0 186#0102\n(1.500000) can0 186#0304\n\
               (2.200000) can0 186#05\n(2.300000) can0 706#05\n";
    let (_, data, _) = report(&[], Some(log), "foreign");
    let rows: Vec<(&str, usize)> = data["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            (
                r["label"].as_str().unwrap(),
                r["marks"].as_array().unwrap().len(),
            )
        })
        .collect();
    // The reset of node 5 is drawn on the bus row.
    assert_eq!(rows, [("bus (NMT)", 1), ("node 6", 0)]);
    let plots = data["plots"].as_array().unwrap();
    let labels: Vec<&str> = plots.iter().map(|p| p["label"].as_str().unwrap()).collect();
    assert_eq!(
        labels,
        [
            "bus load per 1-second window (aligned to the first frame) at 250000 bit/s [%]",
            "frames of no node (NMT, SYNC, TIME, other identifiers) per second (1 in all)",
            "node 6 frames per second (4 in all)",
            "186h byte 0 (no mapping) [raw]",
            "186h byte 1 (no mapping) [raw]",
        ]
    );
    let points = |i: usize| -> Vec<(f64, f64)> {
        let p = &plots[i];
        let t = p["t"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap());
        let v = p["v"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap());
        t.zip(v).collect()
    };
    assert_eq!(points(1), [(0.0, 1.0)]);
    assert_eq!(points(2), [(0.0, 2.0), (1.0, 2.0)]);
    assert_eq!(points(3), [(0.1, 1.0), (0.5, 3.0), (1.2, 5.0)]);
    assert_eq!(points(4), [(0.1, 2.0), (0.5, 4.0)]);
    // The bus load plot holds every frame's bits: as many as the summary
    // counts, and its busiest window is the summary's peak.
    let o = run(&["--summary-only", "--json"], Some(log));
    let lines = json_lines(&o);
    let bus = &lines.iter().find(|l| l["kind"] == "summary").unwrap()["bus_load"];
    let bits: u64 = bus["cob_ids"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["bits"].as_u64().unwrap())
        .sum();
    let load = points(0);
    assert_eq!(load.len(), 2);
    let plotted: f64 = load.iter().map(|(_, v)| v * 250_000.0 / 100.0).sum();
    assert!((plotted - bits as f64).abs() < 1e-6, "{plotted} {bits}");
    let peak = load.iter().map(|(_, v)| *v).fold(0.0, f64::max);
    let want = bus["peak_window"]["bus_load_percent"].as_f64().unwrap();
    assert!((peak - want).abs() < 1e-9, "{peak} {want}");
}
