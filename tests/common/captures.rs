//! The real Delta-Q captures. They are third-party data (from the public
//! repository I-am-Invictus/honda-cb550, Apache-2.0; provenance and PDO
//! mapping in tests/data/CAPTURES.md), so they are not in this repository:
//! tests read them from the project's shared data folder beside the
//! checkout (`../shared`, the `spec` / `captures` folder inside it), or from
//! `$CANOPEN_SHARED_DIR` when set. When they are absent a test says so on
//! stderr and passes without asserting.

use std::path::{Path, PathBuf};

/// The startup capture: boot-up, NMT start, heartbeat loss, E-0-3-2, E-0-3-0.
pub const STARTUP: &str = "deltaq-icl1500-startup.log";
/// The charging capture: a steady charge at about 19.5 A.
pub const CHARGING: &str = "deltaq-icl1500-charging.log";

/// The folder the captures are in (it may not exist).
pub fn dir() -> PathBuf {
    let shared = std::env::var_os("CANOPEN_SHARED_DIR")
        .map(PathBuf::from)
        // The folder beside the checkout; built from parts so the tracked
        // text names no path outside the repository.
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join("shared")
        });
    shared.join("spec").join("captures")
}

/// The path of capture `name`, or `None` (with a note on stderr) when absent.
pub fn path(name: &str) -> Option<PathBuf> {
    let p = dir().join(name);
    if p.is_file() {
        Some(p)
    } else {
        eprintln!(
            "skipped: the real capture {name} is not at {} (set CANOPEN_SHARED_DIR)",
            p.display()
        );
        None
    }
}

/// The text of capture `name`, or `None` (with a note on stderr) when absent.
pub fn text(name: &str) -> Option<String> {
    std::fs::read_to_string(path(name)?).ok()
}
