//! The layering rule, checked: the CiA 301 layers (frame, message, NMT,
//! heartbeat, EMCY, SDO, PDO, object dictionary, COB-IDs, SYNC, TIME and the
//! device core) never name a device profile. Profiles (`cia418`, `cia419`,
//! `deltaq`) sit on top and may use anything below them. The log analysis
//! (`log`) sits at the programs' level, with `sim` and `bin`: it may use
//! everything, and nothing but the programs uses it.
//!
//! Every `.rs` file under `src/` is read; all of them except `lib.rs` and
//! the profile directories are CiA 301 layers. A profile counts as named
//! when it appears as a path: `crate::cia418`, `super::super::deltaq::X`,
//! `cia419::Charger`, a `use crate::{.., deltaq, ..}` group (over several
//! lines too), a doc link ``[`crate::deltaq::index`]``, or a file path such
//! as `#[path = "../deltaq/pdo.rs"]`. Prose that mentions "CiA 418" or
//! "Delta-Q", and identifiers such as `deltaq_tpdo3`, are not paths.

use std::fs;
use std::path::{Path, PathBuf};

/// The profile modules no CiA 301 layer may name.
const PROFILES: [&str; 3] = ["cia418", "cia419", "deltaq"];

/// Directories under `src/` that are profiles (allowed to name each other
/// and everything below them).
// `bin` holds the programs, `log` the log analysis they are made of and
// `sim` the simulation models and sessions, which sit on top of every layer.
const PROFILE_DIRS: [&str; 6] = ["cia418", "cia419", "deltaq", "sim", "bin", "log"];

/// Files under `src/` that are not a layer: the crate root declares every
/// module, profiles included.
const NOT_A_LAYER: [&str; 1] = ["lib.rs"];

fn is_ident(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// Every mention of a profile as a path in `text`, as (line number from 1,
/// profile name).
fn profile_paths(text: &str) -> Vec<(usize, &'static str)> {
    let bytes = text.as_bytes();
    let mut hits = Vec::new();
    for profile in PROFILES {
        let mut from = 0;
        while let Some(found) = text[from..].find(profile) {
            let at = from + found;
            let end = at + profile.len();
            from = end;
            let before = at.checked_sub(1).map(|i| bytes[i]);
            let after = bytes.get(end).copied();
            // Whole words only: `deltaq_tpdo3` and `my_cia418` are not it.
            if before.is_some_and(is_ident) || after.is_some_and(is_ident) {
                continue;
            }
            let path_before = text[..at].ends_with("::") || before == Some(b'/');
            let path_after = text[end..].starts_with("::") || after == Some(b'/');
            if path_before || path_after || in_use_statement(&text[..at]) {
                let line = text[..at].matches('\n').count() + 1;
                hits.push((line, profile));
            }
        }
    }
    hits.sort_unstable();
    hits
}

/// True if `before` (the text up to a word) ends inside an unfinished `use`
/// statement: the last `use` keyword at the start of a line (after
/// whitespace and `pub`/`pub(crate)`) has no `;` after it yet.
fn in_use_statement(before: &str) -> bool {
    let mut start_of_use = None;
    let mut offset = 0;
    for line in before.split_inclusive('\n') {
        let trimmed = line.trim_start();
        let rest = trimmed
            .strip_prefix("pub(crate) ")
            .or_else(|| trimmed.strip_prefix("pub(super) "))
            .or_else(|| trimmed.strip_prefix("pub "))
            .unwrap_or(trimmed);
        if rest.starts_with("use ") {
            start_of_use = Some(offset + (line.len() - rest.len()));
        }
        offset += line.len();
    }
    match start_of_use {
        Some(start) => !before[start..].contains(';'),
        None => false,
    }
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries = fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// True if `rel` (a path relative to `src/`) is a CiA 301 layer.
fn is_cia301_layer(rel: &Path) -> bool {
    let mut parts = rel.components().map(|c| c.as_os_str().to_string_lossy());
    let Some(first) = parts.next() else {
        return false;
    };
    let top_level_file = parts.next().is_none();
    if top_level_file {
        !NOT_A_LAYER.contains(&first.as_ref())
    } else {
        !PROFILE_DIRS.contains(&first.as_ref())
    }
}

#[test]
fn cia301_layers_never_name_a_profile() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut checked = 0;
    let mut problems = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&src).expect("under src");
        if !is_cia301_layer(rel) {
            continue;
        }
        checked += 1;
        let text = fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        for (line, profile) in profile_paths(&text) {
            let shown = text.lines().nth(line - 1).unwrap_or("").trim();
            problems.push(format!(
                "src/{}:{line}: names the profile `{profile}`: {shown}",
                rel.display()
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "CiA 301 layers must not import device profiles (DESIGN.md, layering \
         rule):\n{}",
        problems.join("\n")
    );
    // The layers exist and were read (a wrong root would check nothing).
    assert!(checked >= 40, "only {checked} CiA 301 files found");
    for must in [
        "frame.rs",
        "sdo/server/mod.rs",
        "pdo/defaults.rs",
        "pdo/catalogue/mod.rs",
    ] {
        assert!(
            files.iter().any(|f| f.ends_with(must)),
            "src/{must} not found"
        );
    }
}

#[test]
fn which_files_are_layers() {
    for layer in [
        "frame.rs",
        "message_tests.rs",
        "display.rs",
        "pdo/defaults.rs",
        "pdo/catalogue/tests.rs",
        "sdo/server/mod.rs",
        "od/index.rs",
    ] {
        assert!(is_cia301_layer(Path::new(layer)), "{layer}");
    }
    for not in [
        "lib.rs",
        "cia418/pdo.rs",
        "cia419/charger.rs",
        "deltaq/catalogue.rs",
        "sim/session.rs",
        "bin/canopen-decode/main.rs",
        "log/pipeline.rs",
        "log/input/blf.rs",
    ] {
        assert!(!is_cia301_layer(Path::new(not)), "{not}");
    }
}

/// Every line of `text` that names the log module as a path
/// (`crate::log`, `super::log::X`, `canopen_codec::log`), by number from 1.
fn log_paths(text: &str) -> Vec<usize> {
    let mut hits = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut from = 0;
        while let Some(found) = line[from..].find("::log") {
            let end = from + found + "::log".len();
            from = end;
            let after = line.as_bytes().get(end).copied();
            let before = &line[..end - "::log".len()];
            let root = ["crate", "super", "canopen_codec"]
                .iter()
                .any(|r| before.ends_with(r));
            if root && !after.is_some_and(is_ident) {
                hits.push(i + 1);
                break;
            }
        }
    }
    hits
}

#[test]
fn only_the_programs_use_the_log_module() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut problems = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&src).expect("under src");
        let top = rel
            .components()
            .next()
            .map(|c| c.as_os_str().to_string_lossy());
        if matches!(top.as_deref(), Some("log" | "bin" | "lib.rs")) {
            continue;
        }
        let text = fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        for line in log_paths(&text) {
            problems.push(format!("src/{}:{line}", rel.display()));
        }
    }
    assert!(
        problems.is_empty(),
        "only src/bin and src/log may name the log module:\n{}",
        problems.join("\n")
    );
    assert_eq!(
        log_paths("use crate::log::input;\nlet x = super::log;\n"),
        [1, 2]
    );
    assert!(log_paths("fn logs() { a::login(); a::log_level(); }").is_empty());
    assert!(log_paths("kept in [`Session::log`]").is_empty());
}

#[test]
fn detects_every_form_of_path() {
    let cases: &[(&str, &[(usize, &str)])] = &[
        ("use crate::cia418::DeviceType;", &[(1, "cia418")]),
        ("use super::super::deltaq;", &[(1, "deltaq")]),
        (
            "pub use crate::deltaq::{index, ChargingCurrent};",
            &[(1, "deltaq")],
        ),
        ("use crate::{emcy, deltaq};", &[(1, "deltaq")]),
        ("use crate::{cia419::Charger, nmt};", &[(1, "cia419")]),
        (
            "use crate::{\n    emcy::ErrorCode,\n    cia418,\n    deltaq::index,\n};",
            &[(3, "cia418"), (4, "deltaq")],
        ),
        (
            "//! and the CiA 418 set ([`crate::cia418::DEFAULT_PDOS`]) as",
            &[(1, "cia418")],
        ),
        ("/// [words](crate::deltaq::index)", &[(1, "deltaq")]),
        ("    let x = cia418::BATTERY_STATUS;", &[(1, "cia418")]),
        (
            "    let x = canopen_codec::deltaq::index::PADDING;",
            &[(1, "deltaq")],
        ),
        ("#[path = \"../deltaq/pdo.rs\"]", &[(1, "deltaq")]),
        (
            "use crate::cia418::{BatteryStatus};\nuse crate::deltaq::{\n    ChargeType,\n};",
            &[(1, "cia418"), (2, "deltaq")],
        ),
    ];
    for (text, want) in cases {
        assert_eq!(profile_paths(text), *want, "{text}");
    }
}

#[test]
fn prose_and_identifiers_are_not_paths() {
    for text in [
        "//! The CiA 418 battery module and the Delta-Q charger (cia418, deltaq).",
        "fn deltaq_tpdo3() {}",
        "fn battery_defaults_from_cia418() {}",
        "const DELTAQ_OBJECTS: u8 = 0;",
        "let deltaq = 1;",
        "use crate::pdo::MappingEntry;\nlet deltaq = 2; // after the use statement",
        "// the deltaq profile, see DESIGN.md",
        "use crate::pdo::{\n    deltaq_name,\n};",
    ] {
        assert_eq!(profile_paths(text), [], "{text}");
    }
}

/// On the tree before the profiles were moved out of `pdo`, the check
/// fails: these lines are from that tree's `src/pdo/`.
#[test]
fn the_old_pdo_imports_are_caught() {
    let old = "\
//! and the battery module's CiA 418 set ([`crate::cia418::DEFAULT_PDOS`]) as
//! use canopen_codec::cia418::PdoDirection;
use crate::cia418::{PdoDirection, DEFAULT_PDOS};
use crate::cob_id::{classify_standard, CobKind, NodeId, PdoNumber};
use crate::cia418::{BatteryStatus, BatteryType, ChargerStatus, WaterLevelStatus};
use crate::deltaq::{
    AlgorithmRequest, ChargeIndication, ChargeStatusFlags, ChargeType, DerateReasons,
};
";
    let lines: Vec<usize> = profile_paths(old).iter().map(|&(l, _)| l).collect();
    assert_eq!(lines, [1, 2, 3, 5, 6]);
}
