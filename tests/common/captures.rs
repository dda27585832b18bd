//! The real Delta-Q captures. They are third-party data (from the public
//! repository I-am-Invictus/honda-cb550, Apache-2.0; provenance and PDO
//! mapping in tests/data/CAPTURES.md), so they are not in this repository:
//! tests read them from the project's shared data folder beside the
//! checkout (`../shared`, the `spec` / `captures` folder inside it), or from
//! `$CANOPEN_SHARED_DIR` when set. When they are absent a test fails in CI
//! (`CI=true`) and elsewhere says on stderr that it skipped.

use std::path::{Path, PathBuf};

/// The startup capture: boot-up, NMT start, heartbeat loss, E-0-3-2, E-0-3-0.
pub const STARTUP: &str = "deltaq-icl1500-startup.log";
/// The charging capture: a steady charge at about 19.5 A.
pub const CHARGING: &str = "deltaq-icl1500-charging.log";

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

/// `path` when it is a file; otherwise, with `CI=true`, the test fails
/// (nothing passes silently in CI), and outside CI it says on stderr that
/// it skipped and gives `None`.
pub fn shared_file(what: &str, path: PathBuf) -> Option<PathBuf> {
    if path.is_file() {
        return Some(path);
    }
    let note = format!(
        "{what} is not at {} (set CANOPEN_SHARED_DIR)",
        path.display()
    );
    assert!(std::env::var("CI").as_deref() != Ok("true"), "{note}");
    eprintln!("skipped: {note}");
    None
}

/// The path of capture `name`, or `None` (with a note on stderr) when absent
/// outside CI; in CI an absent capture fails the test.
pub fn path(name: &str) -> Option<PathBuf> {
    shared_file(&format!("the real capture {name}"), dir().join(name))
}

/// The path of the real EDS file `name` (in `../shared/eds`, or in
/// `$CANOPEN_EDS_DIR` when set); absent: see [`shared_file`].
pub fn eds_path(name: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("CANOPEN_EDS_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| shared_dir().join("eds"));
    shared_file(&format!("the real EDS file {name}"), dir.join(name))
}

/// The text of capture `name`, or `None` (with a note on stderr) when absent.
pub fn text(name: &str) -> Option<String> {
    std::fs::read_to_string(path(name)?).ok()
}
