//! `canopen-decode --signals FILE.csv`: every PDO field of the log as a
//! signal column, checked cell by cell against the `--json` output of the
//! same run, on the bundled session and on the real Delta-Q captures.

use crate::common;
use crate::decoder_support;

use std::collections::HashMap;
use std::path::PathBuf;

use decoder_support::*;
use serde_json::Value;

/// A fresh path in the temporary folder for this test.
fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("canopen-signals-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// What the CSV cell of a JSON field must be: the value (number, words),
/// the raw integer for an object with no name, empty for null.
fn want_cell(field: &Value) -> Option<String> {
    match (&field["value"], field["kind"].as_str()) {
        (Value::Null, Some("raw" | "wrong_width")) => Some(field["raw"].to_string()),
        (Value::Null, _) => None,
        (Value::String(s), _) => Some(s.clone()),
        (v, _) => Some(v.to_string()),
    }
}

/// Runs the decoder with `args` twice (`--json`, and `--signals`), checks
/// that the CSV has a row per PDO frame with fields, in order, every row
/// as wide as the header, and every cell equal to the JSON field's value.
/// Returns the header and the number of rows.
fn check(args: &[&str], name: &str) -> (Vec<String>, usize) {
    let csv_path = temp(name);
    let csv_arg = csv_path.display().to_string();
    let mut with_signals = args.to_vec();
    with_signals.extend(["--signals", &csv_arg]);
    let o = run(&with_signals, None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut with_json = args.to_vec();
    with_json.push("--json");
    let j = run(&with_json, None);
    assert!(j.status.success());
    let frames: Vec<Value> = json_lines(&j)
        .into_iter()
        .filter(|v| v["fields"].is_array())
        .collect();
    let csv = std::fs::read_to_string(&csv_path).unwrap();
    assert!(
        !PathBuf::from(format!("{csv_arg}.rows")).exists(),
        "the rows file is left behind"
    );
    let mut lines = csv.lines();
    let header = csv_row(lines.next().unwrap());
    assert_eq!(header[..2], ["time".to_string(), "cob_id".to_string()]);
    let rows: Vec<Vec<String>> = lines.map(csv_row).collect();
    assert_eq!(rows.len(), frames.len(), "a row per PDO frame with fields");
    // The column of each signal (COB-ID, index, sub): found by its header,
    // `name [unit]`, with the COB-ID after it where two share a name.
    let mut column: HashMap<(u64, u64, u64), usize> = HashMap::new();
    for (row, frame) in rows.iter().zip(&frames) {
        assert_eq!(row.len(), header.len(), "row {row:?}");
        let id = frame["id"].as_u64().unwrap();
        assert_eq!(row[1], format!("{id:03X}"));
        match frame["t"].as_f64() {
            Some(t) => assert_eq!(row[0].parse::<f64>().unwrap(), t),
            None => assert_eq!(row[0], ""),
        }
        let mut filled = vec![false; header.len()];
        for f in frame["fields"].as_array().unwrap() {
            if f["kind"] == "padding" {
                continue;
            }
            let key = (id, f["index"].as_u64().unwrap(), f["sub"].as_u64().unwrap());
            let c = *column.entry(key).or_insert_with(|| {
                let name = f["name"].as_str().unwrap();
                let suffix = format!(" ({id:03X}h)");
                // A field without a value (invalid) has no unit in JSON:
                // then any unit in the header fits.
                let fits = |h: &str| {
                    let h = h.strip_suffix(&suffix).unwrap_or(h);
                    match (name, f["unit"].as_str()) {
                        ("unknown object", _) => h == format!("{:04X}h:{:02X} raw", key.1, key.2),
                        (n, Some(u)) => h == format!("{n} [{u}]"),
                        (n, None) => {
                            h == n
                                || h.strip_prefix(n)
                                    .is_some_and(|r| r.starts_with(" [") && r.ends_with(']'))
                        }
                    }
                };
                let found: Vec<usize> = (2..header.len()).filter(|&i| fits(&header[i])).collect();
                let own: Vec<usize> = found
                    .iter()
                    .copied()
                    .filter(|&i| header[i].ends_with(&suffix))
                    .collect();
                match (&found[..], &own[..]) {
                    (_, [one]) | ([one], []) => *one,
                    _ => panic!("no single column for {name} on {id:03X}h in {header:?}"),
                }
            });
            filled[c] = true;
            match want_cell(f) {
                Some(want) if f["value"].is_number() => {
                    let got: f64 = row[c].parse().unwrap();
                    assert_eq!(got, f["value"].as_f64().unwrap(), "{want} in {row:?}");
                }
                Some(want) => assert_eq!(row[c], want),
                None => assert_eq!(row[c], "", "{f}"),
            }
        }
        for (c, cell) in row.iter().enumerate().skip(2) {
            assert!(filled[c] || cell.is_empty(), "column {} filled", header[c]);
        }
    }
    // Every column belongs to a signal the log showed.
    assert_eq!(column.len(), header.len() - 2);
    (header, rows.len())
}

#[test]
fn bundled_session_signals_equal_the_json_values() {
    let (header, rows) = check(&["--bundled", "session"], "session.csv");
    assert_eq!(rows, 91);
    assert_eq!(
        header[2..],
        ["charger status", "temperature [degC]", "battery status"].map(String::from)
    );
}

#[test]
fn capture_signals_equal_the_json_values() {
    for (name, rows) in [
        (common::captures::CHARGING, 449),
        (common::captures::STARTUP, 738),
    ] {
        let Some(path) = capture(name) else {
            continue;
        };
        let (header, n) = check(&["--pdo-capture-mapping", &path], &format!("{name}.csv"));
        assert_eq!(n, rows);
        // The charger's and the battery's charging current: one name, two
        // signals, told apart by their COB-IDs.
        assert!(header.contains(&"charging current [A] (18Ah)".to_string()));
        assert!(header.contains(&"charging current [A] (30Ah)".to_string()));
    }
}

/// A mapping learned from SDO writes in the log (node 5, no role: its
/// objects are unnamed, their cells the raw integers), then moved to another
/// COB-ID: the frames there get columns of their own, and the rows before
/// them are padded to the full width.
#[test]
fn mapping_learned_in_the_log_adds_columns() {
    let log = temp("remap.log");
    std::fs::write(
        &log,
        "285#1122334455\n\
605#2F011A0000000000\n585#60011A0000000000\n\
605#23011A0108000060\n585#60011A0100000000\n\
605#23011A0210001060\n585#60011A0200000000\n\
605#2F011A0002000000\n585#60011A0000000000\n\
285#2A3412\n\
605#23011801A5020000\n585#6001180100000000\n\
2A5#2B7856\n",
    )
    .unwrap();
    let (header, rows) = check(&[&log.display().to_string()], "remap.csv");
    assert_eq!(rows, 2);
    assert_eq!(
        header[2..],
        [
            "6000h:00 raw (285h)",
            "6010h:00 raw (285h)",
            "6000h:00 raw (2A5h)",
            "6010h:00 raw (2A5h)"
        ]
        .map(String::from)
    );
    let csv = std::fs::read_to_string(temp("remap.csv")).unwrap();
    assert_eq!(csv.lines().nth(1), Some(",285,42,4660,,"));
}

#[test]
fn unwritable_signals_path_is_an_error() {
    let o = run(
        &[
            "--bundled",
            "session",
            "--signals",
            "/nonexistent-dir/x.csv",
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--signals"));
    // A folder cannot be the output: the error comes at the end, and the
    // rows file written meanwhile is removed.
    let dir = temp("a-folder");
    std::fs::create_dir_all(&dir).unwrap();
    let arg = dir.display().to_string();
    let o = run(&["--bundled", "session", "--signals", &arg], None);
    assert_eq!(o.status.code(), Some(2));
    assert!(!PathBuf::from(format!("{arg}.rows")).exists());
}

/// `--signals` and `--dbc`, like `--report`, make their file the output:
/// the frames go to stdout only when `--json` or `--output` asks, and
/// `--summary` still prints the summary.
#[test]
fn signals_and_dbc_print_frames_only_when_asked() {
    let csv = temp("quiet.csv").display().to_string();
    let dbc = temp("quiet.dbc").display().to_string();
    let plain = run(&["--bundled", "session"], None);
    let frames = text(&plain).lines().count();
    assert!(frames > 100);
    for file in [["--signals", &csv], ["--dbc", &dbc]] {
        let o = run(&["--bundled", "session", file[0], file[1]], None);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(text(&o), "", "{}", file[0]);
        assert!(std::fs::metadata(file[1]).unwrap().len() > 0);
        let o = run(&["--bundled", "session", file[0], file[1], "--json"], None);
        assert_eq!(json_lines(&o).len(), frames, "{}", file[0]);
        let o = run(
            &[
                "--bundled",
                "session",
                file[0],
                file[1],
                "--output",
                "words",
            ],
            None,
        );
        assert_eq!(text(&o), text(&plain), "{}", file[0]);
        let o = run(
            &["--bundled", "session", file[0], file[1], "--summary"],
            None,
        );
        let out = text(&o);
        assert!(
            out.contains("summary") && out.lines().count() < frames,
            "{out}"
        );
    }
}

/// Several logs in one run: one dataset partitioned by log, each part the
/// file a run on that log alone writes.
#[test]
fn several_logs_make_one_dataset_partitioned_by_log() {
    let (Some(startup), Some(charging)) = (
        capture(common::captures::STARTUP),
        capture(common::captures::CHARGING),
    ) else {
        return;
    };
    let root = temp("fleet");
    let root_arg = root.display().to_string();
    let o = run(
        &[
            "--pdo-capture-mapping",
            "--signals",
            &root_arg,
            &startup,
            &charging,
        ],
        None,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for (log, name) in [
        (&startup, "deltaq-icl1500-startup"),
        (&charging, "deltaq-icl1500-charging"),
    ] {
        let part = root.join(format!("log={name}")).join("part-0.csv");
        let alone = temp(&format!("{name}-alone.csv"));
        let alone_arg = alone.display().to_string();
        let one = run(
            &["--pdo-capture-mapping", "--signals", &alone_arg, log],
            None,
        );
        assert!(one.status.success());
        assert_eq!(
            std::fs::read_to_string(&part).unwrap(),
            std::fs::read_to_string(&alone).unwrap(),
            "{name}"
        );
    }
    // Two logs of one name cannot share a partition.
    let o = run(&["--signals", &root_arg, &startup, &startup], None);
    assert_eq!(o.status.code(), Some(2));
}

/// `--dataset` makes a dataset of one log; a folder of logs is a dataset
/// of its files; either's parts are what a run on that log alone writes.
#[test]
fn dataset_option_and_folder_of_logs() {
    let Some(startup) = capture(common::captures::STARTUP) else {
        return;
    };
    let alone = temp("startup-alone.csv");
    let alone_arg = alone.display().to_string();
    let one = run(
        &["--pdo-capture-mapping", "--signals", &alone_arg, &startup],
        None,
    );
    assert!(one.status.success());
    let want = std::fs::read_to_string(&alone).unwrap();

    let root = temp("one-log-dataset");
    let root_arg = root.display().to_string();
    let args = [
        "--pdo-capture-mapping",
        "--dataset",
        "csv",
        "--signals",
        &root_arg,
        &startup,
    ];
    let o = run(&args, None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let part = root.join("log=deltaq-icl1500-startup/part-0.csv");
    assert_eq!(std::fs::read_to_string(part).unwrap(), want);

    // A folder holding two logs (copies of the capture): two partitions.
    let logs = temp("logs");
    std::fs::create_dir_all(&logs).unwrap();
    for name in ["bus-a.log", "bus-b.log"] {
        std::fs::copy(&startup, logs.join(name)).unwrap();
    }
    let fleet = temp("fleet-of-folder");
    let fleet_arg = fleet.display().to_string();
    let logs_arg = logs.display().to_string();
    let o = run(
        &["--pdo-capture-mapping", "--signals", &fleet_arg, &logs_arg],
        None,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for name in ["bus-a", "bus-b"] {
        let part = fleet.join(format!("log={name}")).join("part-0.csv");
        assert_eq!(std::fs::read_to_string(part).unwrap(), want, "{name}");
    }
    // An empty folder or a glob matching nothing is a usage error.
    let glob = format!("{logs_arg}/*.trc");
    let o = run(&["--signals", &fleet_arg, &glob], None);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no log there"));
}

/// A Parquet path in a decoder built without the `parquet` feature is a
/// usage error, before the log is read.
#[cfg(not(feature = "parquet"))]
#[test]
fn parquet_needs_its_feature() {
    let o = run(&["--bundled", "session", "--signals", "x.parquet"], None);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("`parquet` feature"));
}

/// `--signals FILE.parquet` read back with the parquet crate's reader: the
/// same cells as the CSV of the same run (checked against `--json` above),
/// typed, in more than one row group for a log longer than one group.
#[cfg(feature = "parquet")]
#[test]
fn parquet_holds_the_csv_cells_typed_in_row_groups() {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::Field;
    // The bundled session repeated with shifted times: more PDO rows than
    // one row group holds.
    let session = std::fs::read_to_string("tests/data/virtual-session.log").unwrap();
    let mut long = String::new();
    for copy in 0..1200u64 {
        for line in session.lines() {
            let (time, rest) = line[1..].split_once(')').unwrap();
            let (secs, micros) = time.split_once('.').unwrap();
            let secs: u64 = secs.parse().unwrap();
            long.push_str(&format!("({}.{micros}){rest}\n", secs + 13 * copy));
        }
    }
    let log = temp("long.log");
    std::fs::write(&log, long).unwrap();
    let log_arg = log.display().to_string();
    let (csv, pq) = (temp("long.csv"), temp("long.parquet"));
    for out in [&csv, &pq] {
        let o = run(
            &[
                "--battery-node",
                "1",
                "--summary-only",
                "--signals",
                &out.display().to_string(),
                &log_arg,
            ],
            None,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let csv = std::fs::read_to_string(&csv).unwrap();
    let mut csv_lines = csv.lines();
    let header = csv_row(csv_lines.next().unwrap());
    let reader = SerializedFileReader::try_from(std::fs::File::open(&pq).unwrap()).unwrap();
    assert!(reader.metadata().num_row_groups() >= 2);
    let mut n = 0;
    for (row, line) in reader.get_row_iter(None).unwrap().zip(csv_lines) {
        let row = row.unwrap();
        let cells = csv_row(line);
        for (i, ((name, field), cell)) in row.get_column_iter().zip(&cells).enumerate() {
            assert_eq!(name, &header[i]);
            match field {
                Field::Null => assert_eq!(cell, ""),
                Field::Int(id) if i == 1 => assert_eq!(format!("{id:03X}"), *cell),
                Field::Double(v) => assert_eq!(*v, cell.parse::<f64>().unwrap(), "{name}"),
                Field::Str(s) => assert_eq!(s, cell),
                other => panic!("{name}: {other:?}"),
            }
        }
        n += 1;
    }
    assert_eq!(n, csv.lines().count() - 1);
    assert!(n > 65_536, "{n} rows");
}
