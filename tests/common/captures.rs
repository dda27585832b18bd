//! The real Delta-Q captures and the real EDS files. They are third-party
//! data (the captures from the public repository I-am-Invictus/honda-cb550,
//! Apache-2.0; provenance and PDO mapping in tests/data/CAPTURES.md), so
//! they are not in this repository: tests read them from the project's
//! shared data folder beside the checkout (`../shared`, the `spec` /
//! `captures` and `eds` folders inside it), or from `$CANOPEN_SHARED_DIR`
//! (and `$CANOPEN_EDS_DIR` for the EDS files) when set.
//!
//! A file that is absent or unreadable fails the test in CI (`CI=true`,
//! which `.ci/run` exports): a test must never pass because its data is
//! missing. Elsewhere the test says on stderr that it skipped and passes
//! without asserting. Every message starts with [`MISSING`].

use std::path::{Path, PathBuf};

/// The startup capture: boot-up, NMT start, heartbeat loss, E-0-3-2, E-0-3-0.
pub const STARTUP: &str = "deltaq-icl1500-startup.log";
/// The charging capture: a steady charge at about 19.5 A.
pub const CHARGING: &str = "deltaq-icl1500-charging.log";

/// The first words of every note (and of every failure under CI) about a
/// shared file that is absent or unreadable (`.ci/run` greps for them).
pub const MISSING: &str = "shared test data missing or unreadable";

/// Whether the tests run in CI (`CI=true`): absent data then fails.
pub fn in_ci() -> bool {
    std::env::var("CI").as_deref() == Ok("true")
}

/// The project's shared data folder beside the checkout, or
/// `$CANOPEN_SHARED_DIR` when set (it may not exist).
pub fn shared_dir() -> PathBuf {
    std::env::var_os("CANOPEN_SHARED_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared"))
}

/// The folder the captures are in (it may not exist).
pub fn dir() -> PathBuf {
    shared_dir().join("spec/captures")
}

/// The folder the real EDS files are in: `$CANOPEN_EDS_DIR`, else the
/// shared folder's `eds` (it may not exist).
pub fn eds_dir() -> PathBuf {
    std::env::var_os("CANOPEN_EDS_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| shared_dir().join("eds"))
}

/// `path` when it is a file that opens for reading; otherwise, with
/// `CI=true`, the test fails (nothing passes silently in CI), and outside
/// CI it says on stderr that it skipped and gives `None`.
pub fn shared_file(what: &str, path: PathBuf) -> Option<PathBuf> {
    shared_file_in(what, path, in_ci())
}

/// [`shared_file`] with the CI flag given (`ci`: fail instead of skip).
pub fn shared_file_in(what: &str, path: PathBuf, ci: bool) -> Option<PathBuf> {
    let problem = if path.is_file() {
        match std::fs::File::open(&path) {
            Ok(_) => return Some(path),
            Err(e) => format!("cannot be opened ({e})"),
        }
    } else if path.exists() {
        "is not a file".to_string()
    } else {
        "does not exist".to_string()
    };
    absent(format!("{what}: {} {problem}", path.display()), ci)
}

/// The text of the shared file `path` (UTF-8), or, when it is absent or
/// cannot be read as text, a failure with `ci` and a skip note and `None`
/// without.
pub fn shared_text_in(what: &str, path: PathBuf, ci: bool) -> Option<String> {
    let path = shared_file_in(what, path, ci)?;
    match std::fs::read_to_string(&path) {
        Ok(text) => Some(text),
        Err(e) => absent(
            format!("{what}: {} cannot be read as text ({e})", path.display()),
            ci,
        ),
    }
}

/// Fails with `note` under CI; outside it prints that the test skipped.
fn absent<T>(note: String, ci: bool) -> Option<T> {
    let note = format!("{MISSING}: {note} (set CANOPEN_SHARED_DIR or CANOPEN_EDS_DIR)");
    assert!(!ci, "{note}");
    eprintln!("skipped: {note}");
    None
}

/// The path of capture `name`, or `None` (with a note on stderr) when absent
/// or unreadable outside CI; in CI that fails the test.
pub fn path(name: &str) -> Option<PathBuf> {
    shared_file(&format!("the real capture {name}"), dir().join(name))
}

/// The path of the real EDS file `name` (in `../shared/eds`, or in
/// `$CANOPEN_EDS_DIR` when set); absent or unreadable: see [`shared_file`].
pub fn eds_path(name: &str) -> Option<PathBuf> {
    shared_file(&format!("the real EDS file {name}"), eds_dir().join(name))
}

/// The text of capture `name`, or `None` (with a note on stderr) when it is
/// absent or cannot be read outside CI; in CI either fails the test.
pub fn text(name: &str) -> Option<String> {
    shared_text_in(
        &format!("the real capture {name}"),
        dir().join(name),
        in_ci(),
    )
}
