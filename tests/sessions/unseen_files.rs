//! Scenario files written apart from the charger (`tests/sessions/unseen/`):
//! each file's comment gives the outcome the Delta-Q IC Series CANopen
//! interface specification (section 7's use cases, section 4.4 alarms and
//! EMCY policy) and battery physics predict, written before the file was
//! first run, and its `[expect]` is that prediction (alarms, output, charge
//! delivered within the chemistry's efficiency bounds). Hostile values
//! (fractional counts, more shorted cells than the pack has, a run of
//! months) are errors naming their line.

use std::path::PathBuf;

use super::scenario_files::script;

#[test]
fn every_unseen_file_holds_its_prediction() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/sessions/unseen");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 20, "{} unseen files", files.len());
    let mut failed = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        assert!(
            text.contains("Prediction"),
            "{}: no prediction",
            file.display()
        );
        let script = script(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        assert_ne!(script.expect, Default::default(), "{}", file.display());
        let (_, summary) = script.run(|_| {}).unwrap();
        for f in script.expect.check(&summary) {
            failed.push(format!("{}: {f}", file.display()));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

const BASE: &str = "[charger]\nmode = \"local\"\n[battery]\nchemistry = \"flooded\"\ncells = 24\ncapacity_ah = 100\nsoc = 50\n";

#[test]
fn hostile_counts_and_runs_are_errors_naming_their_line() {
    let event = |action: &str, value: &str| {
        format!("[[event]]\nat = \"0:10:00\"\naction = \"{action}\"\nvalue = {value}\n[run]\nuntil = \"1:00:00\"\n")
    };
    let cases = [
        (
            BASE.replace("cells = 24", "cells = 24.5"),
            5,
            "a cell count (a whole number)",
        ),
        (
            format!("{BASE}{}", event("cell-short", "25")),
            11,
            "from 1 to 24, found 25",
        ),
        (
            format!("{BASE}{}", event("cell-short", "1.5")),
            11,
            "(a whole number)",
        ),
        (
            format!("{BASE}{}", event("algorithm", "2.5")),
            11,
            "(a whole number)",
        ),
        (
            format!("{BASE}{}", event("battery-status", "0.5")),
            11,
            "(a whole number)",
        ),
        (
            format!("{BASE}[run]\nuntil = \"9999:00:00\"\n"),
            9,
            "a time h:mm:ss up to 72:00:00",
        ),
        (
            format!("{BASE}[bus]\nseed = 0.5\n[run]\nuntil = \"1:00:00\"\n"),
            9,
            "(a whole number)",
        ),
    ];
    for (text, line, words) in cases {
        let e = script(&text).unwrap_err();
        assert_eq!(e.line, line, "{text}: {e}");
        assert!(e.message.contains(words), "{text}: {e}");
    }
    // The longest run allowed, and shorting every cell, are still runs.
    assert!(script(&format!("{BASE}[run]\nuntil = \"72:00:00\"\n")).is_ok());
    assert!(script(&format!("{BASE}{}", event("cell-short", "24"))).is_ok());
}
