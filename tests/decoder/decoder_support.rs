//! What the program test files share: running `canopen-decode` and
//! `canopen-boot` (built by cargo for the test crate, feature `cli`),
//! reading their output, and a scratch folder for their files.
#![allow(dead_code)]

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

use serde_json::Value;

/// The program, built by cargo for this test crate.
pub fn decoder() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_canopen-decode"))
}

/// `canopen-boot` with `args`, to be run (`output()`) or spawned with
/// pipes.
pub fn canopen_boot(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_canopen-boot"));
    c.args(args);
    c
}

/// A fresh folder for one test's files (emptied if it exists).
pub fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("canopen-boot-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn run(args: &[&str], stdin: Option<&str>) -> Output {
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

/// A real capture's path as an argument, or `None` when it is absent or
/// unreadable outside CI (the test then says it skipped and passes without
/// asserting); under `CI=true` that fails the test (`common::captures`).
pub fn capture(name: &str) -> Option<String> {
    crate::common::captures::path(name).map(|p| p.display().to_string())
}

pub fn text(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

pub const SDO_SAMPLE: &str = "tests/data/sdo-sample.log";

/// The transfer lines (words) of a run, without the timestamp and role columns.
pub fn transfers(out: &str) -> Vec<String> {
    out.lines()
        .filter_map(|l| l.split_once("  transfer  "))
        .map(|(_, rest)| rest.get(9..).unwrap_or("").to_string())
        .collect()
}

pub fn json_lines(o: &Output) -> Vec<Value> {
    text(o)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

pub fn json_transfers(o: &Output) -> Vec<Value> {
    json_lines(o)
        .into_iter()
        .filter(|v| v["kind"] == "sdo_transfer")
        .collect()
}

/// Splits one RFC 4180 row.
pub fn csv_row(line: &str) -> Vec<String> {
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
