//! `canopen-decode --bitrate`: the summary's bus load, in words and JSON,
//! checked against bit counts worked out by hand (the table in the
//! library's `log::bus_load` documentation): `000#` is 53 bits with its
//! stuff bits (47 without, 55 at most), `000#R` 50.

use crate::decoder_support::*;
use serde_json::Value;

/// The JSON summary of `log` decoded with `args`.
fn summary(log: &str, args: &[&str]) -> Value {
    let mut all = vec!["--summary-only", "--json"];
    all.extend(args);
    let o = run(&all, Some(log));
    assert!(
        o.status.code().is_some_and(|c| c <= 1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let lines = json_lines(&o);
    let s = lines
        .iter()
        .find(|l| l["kind"] == "summary")
        .expect("a summary");
    s.clone()
}

fn close(got: &Value, want: f64) {
    let got = got.as_f64().unwrap();
    assert!((got - want).abs() < 1e-9, "{got} != {want}");
}

#[test]
fn two_hand_counted_frames_at_a_given_bit_rate() {
    // Two NMT-identifier frames of 0 bytes, 1 s apart, at 1000 bit/s: 53
    // bits each; the log lasts 1 s plus the first frame's 53 ms.
    let log = "(1.000000) can0 000#\n(2.000000) can0 000#\n";
    let s = summary(log, &["--bitrate", "1000"]);
    let b = &s["bus_load"];
    assert_eq!(b["bitrate"], 1000);
    assert_eq!(b["bitrate_assumed"], false);
    assert_eq!(b["frames"], 2);
    close(&b["duration_s"], 1.053);
    let mean = 2.0 * 53.0 * 100.0 / (1000.0 * 1.053);
    close(&s["bus_load_percent"], mean);
    close(&b["bus_load_percent"], mean);
    close(&b["unstuffed_percent"], 2.0 * 47.0 * 100.0 / 1053.0);
    close(&b["worst_case_percent"], 2.0 * 55.0 * 100.0 / 1053.0);
    // Each frame in its own aligned window: the first is the peak.
    let p = &b["peak_window"];
    assert_eq!(
        (p["aligned"].as_bool(), p["frames"].as_u64()),
        (Some(true), Some(1))
    );
    close(&p["start"], 1.0);
    close(&p["bus_load_percent"], 5.3);
    close(&p["unstuffed_percent"], 4.7);
    close(&p["worst_case_percent"], 5.5);
    // NMT's identifier belongs to no node.
    assert_eq!(b["nodes"][0]["node"], Value::Null);
    close(&b["nodes"][0]["share_percent"], 100.0);
    assert_eq!(b["cob_ids"][0]["cob_id"], 0);
    assert_eq!(b["cob_ids"][0]["bits"], 106);
}

#[test]
fn the_load_lies_between_the_unstuffed_and_worst_case_loads() {
    for (log, args) in [
        (None, vec!["--bundled", "session"]),
        (
            Some("(1.000000) can0 000#R\n(1.000100) can0 7FF#FFFFFFFFFFFFFFFF\n(1.000300) can0 1FFFFFFF#0000000000000000\n(1.5) can0 181#55AA\n"),
            vec![],
        ),
    ] {
        let s = summary(log.unwrap_or(""), &args);
        let b = &s["bus_load"];
        let (lo, mid, hi) = (
            b["unstuffed_percent"].as_f64().unwrap(),
            b["bus_load_percent"].as_f64().unwrap(),
            b["worst_case_percent"].as_f64().unwrap(),
        );
        assert!(lo < mid && mid < hi, "{args:?}: {lo} {mid} {hi}");
        assert_eq!(b["bitrate"], 250_000);
        assert_eq!(b["bitrate_assumed"], true);
        // The shares add up to every frame's bits.
        let shares: f64 = b["cob_ids"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["share_percent"].as_f64().unwrap())
            .sum();
        assert!((shares - 100.0).abs() < 1e-6, "{shares}");
    }
}

#[test]
fn the_words_say_the_rate_is_assumed_and_count_error_frames() {
    let asc = "date Tue Dec 01 09:11:16.935 2026\nbase hex  timestamps absolute\nBegin Triggerblock\n\
               \x20  1.000000 1  70A             Rx   d 1 05\n\
               \x20  1.150000 1  ErrorFrame\n   1.200000 1  0               Tx   d 2 01 0A\nEnd TriggerBlock\n";
    let o = run(&["--summary-only"], Some(asc));
    let t = text(&o);
    assert!(
        t.contains("bus load at 250000 bit/s (assumed: --bitrate gives it): "),
        "{t}"
    );
    // 17 bits of 57 + 17 + 67: 70A#05 is 55 bits and 2 stuff bits,
    // 000#010A 63 and 4 (counted bit by bit, CRC-15 included).
    assert!(
        t.contains("error frames: 1 (12.06% of the bus time: 17 bits each, 23 with superposed error flags)"),
        "{t}"
    );
    assert!(!t.contains("CAN FD frames"), "{t}");
    assert!(
        t.contains("by node: no node ") && t.contains(", node 10 "),
        "{t}"
    );
    let o = run(&["--summary-only", "--bitrate", "500000"], Some(asc));
    let t = text(&o);
    assert!(t.contains("bus load at 500000 bit/s: "), "{t}");
    assert_eq!(
        summary(asc, &[])["bus_load"]["error_frames"],
        1,
        "the JSON counts it too"
    );
    // Not a bit rate.
    for bad in ["0", "-1", "fast", "4294967296"] {
        let o = run(&["--bitrate", bad, "--summary-only"], Some(asc));
        assert_eq!(o.status.code(), Some(2), "--bitrate {bad}");
    }
}

#[test]
fn nodes_only_addressed_are_not_listed() {
    // NMT resets node 5 and node 6; only node 6 answers (a boot-up).
    let log = "(1.0) can0 000#8105\n(1.1) can0 000#8106\n(1.2) can0 706#00\n";
    let o = run(&["--summary-only"], Some(log));
    let t = text(&o);
    assert!(!t.contains("node 5"), "{t}");
    assert!(t.contains("  node 6:\n    heartbeats: 1"), "{t}");
    assert!(t.contains("boot-up at 1.200000 (after reset node)"), "{t}");
    let s = summary(log, &[]);
    let nodes: Vec<u64> = s["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["node"].as_u64().unwrap())
        .collect();
    assert_eq!(nodes, [6]);
}

#[test]
fn fd_and_error_frames_of_a_candump_log_are_in_the_load() {
    // At 500 kbit/s (2 µs a bit) and 2 Mbit/s (0.5 µs), the bits counted
    // by hand in the library's `log::bus_load` tests (unstuffed, exact,
    // worst case; nominal and data phase):
    // 000#: 47, 53, 55 nominal: 94, 106, 110 µs
    // 123##1 + 64 FFh: 30, 30, 34 nominal; 549, 652, 678 data:
    //   334.5, 386, 407 µs
    // an error frame: 17, 17, 23 nominal: 34, 34, 46 µs
    // 12345678##1 + 12 zero bytes: 49, 49, 57 nominal; 128, 147, 154 data:
    //   162, 171.5, 191 µs
    let log = format!(
        "(1.000000) can0 000#\n(1.100000) can0 123##1{}\n(1.200000) can0 20000004#0004000000000000\n(2.000000) can0 12345678##1{}\n",
        "FF".repeat(64),
        "00".repeat(12)
    );
    let args = ["--bitrate", "500000", "--data-bitrate", "2000000"];
    let s = summary(&log, &args);
    let b = &s["bus_load"];
    assert_eq!(
        (b["frames"].as_u64(), b["error_frames"].as_u64()),
        (Some(4), Some(1))
    );
    assert_eq!(
        (b["fd_frames"].as_u64(), b["fd_brs_frames"].as_u64()),
        (Some(2), Some(2))
    );
    assert_eq!(b["data_bitrate"], 2_000_000);
    assert_eq!(b["data_bitrate_assumed"], false);
    // From the start of the first frame (its 106 µs) to the last.
    close(&b["duration_s"], 1.000_106);
    let load = |us: f64| us * 1e-6 / 1.000_106 * 100.0;
    let (lo, hi) = (
        load(94.0 + 334.5 + 34.0 + 162.0),
        load(110.0 + 407.0 + 46.0 + 191.0),
    );
    close(&b["unstuffed_percent"], lo);
    close(&b["worst_case_percent"], hi);
    close(&s["bus_load_percent"], load(106.0 + 386.0 + 34.0 + 171.5));
    let mid = s["bus_load_percent"].as_f64().unwrap();
    assert!(lo < mid && mid < hi, "{lo} {mid} {hi}");
    // The FD frames have their COB-IDs' shares; the error frame none.
    let share = |id: u64| {
        b["cob_ids"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["cob_id"] == id)
            .map(|c| c["share_percent"].as_f64().unwrap())
    };
    let all = 106.0 + 386.0 + 34.0 + 171.5;
    assert!((share(0x123).unwrap() - 386.0 * 100.0 / all).abs() < 1e-9);
    assert!((share(0x1234_5678).unwrap() - 171.5 * 100.0 / all).abs() < 1e-9);
    close(&b["error_frames_share_percent"], 34.0 * 100.0 / all);
    let o = run(&["--summary-only", "--bitrate", "500000"], Some(&log));
    let t = text(&o);
    assert!(
        t.contains("CAN FD frames: 2 in the load (2 with BRS, their data phase at 2000000 bit/s (assumed: --data-bitrate gives it))"),
        "{t}"
    );
    for bad in ["0", "fast"] {
        let o = run(&["--data-bitrate", bad, "--summary-only"], Some(&log));
        assert_eq!(o.status.code(), Some(2), "--data-bitrate {bad}");
    }
}
