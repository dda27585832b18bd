//! One declaration per fact, measured: how many object indexes (1000h-6FFFh)
//! are written out in three or more non-test files of `src/`. An index
//! written in one place (a table row or a named constant) and named
//! everywhere else counts once; each file that writes it again as a literal
//! is one more copy a reader has to keep in step.
//!
//! What counts as a file: every `.rs` file under `src/` but the test files
//! (names ending in `tests.rs`, `test_support.rs`, anything in a `tests`
//! directory), and only up to a trailing `#[cfg(test)] mod ...` block. What
//! counts as writing an index: after `//` comments are removed, a `0xNNNN`
//! literal with NNNN in 1000h-6FFFh (`0x1017`, `0x6a00`; not `0x1017_0000`
//! nor `0x10170`), or the CiA form `NNNNh` with upper-case digits (`"1018h"`,
//! as in a message or a name).

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The most indexes that may be written out in three or more files (issue
/// 34's bound; 48 before the object tables, 3 after: 6000h, 2000h and
/// 1000h, each also an EMCY error code or a range's start).
const MOST_SHARED_INDEXES: usize = 10;

/// How many files may write an index before it counts as shared.
const SHARED_FROM_FILES: usize = 3;

fn is_word(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The part of a source file that counts: up to a `#[cfg(test)]` line that
/// starts a module (optionally with a `#[path = ...]` line between), with
/// `//` comments removed.
fn code_of(text: &str) -> String {
    let mut kept = text;
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        if let Some(rest) = line
            .starts_with("#[cfg(test)]")
            .then(|| &text[offset + "#[cfg(test)]".len()..])
        {
            let after = rest.trim_start();
            let spaces = &rest[..rest.len() - after.len()];
            let after = match after.strip_prefix("#[path") {
                Some(path) => path.split_once('\n').map_or("", |(_, r)| r.trim_start()),
                None => after,
            };
            if spaces.contains('\n') && after.starts_with("mod ") {
                kept = &text[..offset];
                break;
            }
        }
        offset += line.len();
    }
    kept.lines()
        .map(|line| line.find("//").map_or(line, |at| &line[..at]))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The object indexes (1000h-6FFFh) `code` writes out.
fn indexes_in(code: &str) -> BTreeSet<u16> {
    let chars: Vec<char> = code.chars().collect();
    let boundary = |at: usize| chars.get(at).is_none_or(|&c| !is_word(c));
    let object_digit = |c: Option<&char>| c.is_some_and(|c| ('1'..='6').contains(c));
    let mut found = BTreeSet::new();
    for at in 0..chars.len() {
        if at > 0 && !boundary(at - 1) {
            continue;
        }
        let hex = |from: usize, upper_only: bool| -> Option<u16> {
            let digits: String = chars.get(from..from + 4)?.iter().collect();
            let ok = object_digit(digits.chars().next().as_ref())
                && digits.chars().all(|c| {
                    c.is_ascii_digit()
                        || ('A'..='F').contains(&c)
                        || (!upper_only && ('a'..='f').contains(&c))
                });
            ok.then(|| u16::from_str_radix(&digits, 16).ok()).flatten()
        };
        if chars.get(at) == Some(&'0') && chars.get(at + 1) == Some(&'x') {
            if let Some(index) = hex(at + 2, false).filter(|_| boundary(at + 6)) {
                found.insert(index);
            }
        } else if let Some(index) = hex(at, true) {
            if chars.get(at + 4) == Some(&'h') && boundary(at + 5) {
                found.insert(index);
            }
        }
    }
    found
}

/// Is `path` a test file, not counted?
fn is_test_file(path: &Path) -> bool {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    name.ends_with("tests.rs")
        || name == "test_support.rs"
        || path.components().any(|c| c.as_os_str() == "tests")
}

/// For each index written in at least [`SHARED_FROM_FILES`] of `files`
/// (name, text), the names of those files.
fn shared_indexes(files: &[(String, String)]) -> BTreeMap<u16, BTreeSet<String>> {
    let mut by_index: BTreeMap<u16, BTreeSet<String>> = BTreeMap::new();
    for (name, text) in files {
        for index in indexes_in(&code_of(text)) {
            by_index.entry(index).or_default().insert(name.clone());
        }
    }
    by_index.retain(|_, files| files.len() >= SHARED_FROM_FILES);
    by_index
}

fn rs_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("a directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rs_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn few_object_indexes_are_written_in_three_or_more_files() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut paths = Vec::new();
    rs_files(&src, &mut paths);
    let files: Vec<(String, String)> = paths
        .iter()
        .filter(|p| !is_test_file(p.strip_prefix(&src).unwrap_or(p)))
        .map(|p| {
            let name = p.strip_prefix(&src).unwrap_or(p).display().to_string();
            (name, fs::read_to_string(p).expect("a source file"))
        })
        .collect();
    assert!(
        files.len() > 100,
        "only {} files read from src/",
        files.len()
    );
    let shared = shared_indexes(&files);
    let report: Vec<String> = shared
        .iter()
        .map(|(index, files)| {
            let names: Vec<&str> = files.iter().map(String::as_str).collect();
            format!("  {index:04X}h in {}: {}", files.len(), names.join(", "))
        })
        .collect();
    assert!(
        shared.len() <= MOST_SHARED_INDEXES,
        "{} object indexes are written out in {SHARED_FROM_FILES} or more non-test files \
         of src/ (at most {MOST_SHARED_INDEXES}): write each in one table row or constant \
         and name it elsewhere\n{}",
        shared.len(),
        report.join("\n")
    );
}

#[test]
fn the_counter_reads_literals_and_cia_forms_outside_comments_and_tests() {
    let file = |name: &str, text: &str| (name.to_string(), text.to_string());
    let files = [
        file(
            "a.rs",
            "const X: u16 = 0x1017; // 0x2000 in a comment\n\
             /// 0x2000 in a doc comment\n\
             fn f() -> &'static str { \"see 1018h:01\" }\n\
             const WIDE: u32 = 0x1018_0000; const LONG: u32 = 0x10180;\n\
             const LOW: u16 = 0x6a00; const OUT: [u16; 2] = [0x7000, 0x0FFF];\n\
             #[cfg(test)]\nmod tests {\n    const T: u16 = 0x2000;\n}\n",
        ),
        file(
            "b.rs",
            "match i { 0x1017 | 0x6A00 => {} _ => {} }\nlet s = \"2000h\"; let t = \"1018H\";\n",
        ),
        file(
            "c.rs",
            "#[cfg(test)]\nfn helper() -> u16 { 0x1017 }\nconst N: &str = \"6A00h, in_1018h\";\n",
        ),
    ];
    assert_eq!(
        indexes_in(&code_of(&files[0].1)),
        BTreeSet::from([0x1017, 0x1018, 0x6A00]),
    );
    assert_eq!(
        indexes_in(&code_of(&files[1].1)),
        BTreeSet::from([0x1017, 0x2000, 0x6A00]),
    );
    // A `#[cfg(test)]` item that is not a module is code.
    assert_eq!(
        indexes_in(&code_of(&files[2].1)),
        BTreeSet::from([0x1017, 0x6A00]),
    );
    let shared = shared_indexes(&files);
    let names = |names: &[&str]| names.iter().map(|n| n.to_string()).collect::<BTreeSet<_>>();
    assert_eq!(
        shared,
        BTreeMap::from([
            (0x1017, names(&["a.rs", "b.rs", "c.rs"])),
            (0x6A00, names(&["a.rs", "b.rs", "c.rs"])),
        ])
    );
    // The test module with its `#[path]` line is cut too.
    let with_path =
        "const A: u16 = 0x1400;\n#[cfg(test)]\n#[path = \"x_tests.rs\"]\nmod tests;\n0x1600";
    assert_eq!(indexes_in(&code_of(with_path)), BTreeSet::from([0x1400]));
    assert!(is_test_file(Path::new("device/objects_tests.rs")));
    assert!(is_test_file(Path::new("sdo/test_support.rs")));
    assert!(is_test_file(Path::new("log/tests/mod.rs")));
    assert!(!is_test_file(Path::new("device/objects.rs")));
}
