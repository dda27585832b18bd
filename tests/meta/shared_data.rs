//! The loader of the third-party test data (`common::captures`): in CI a
//! file that is absent, not a file, or not readable as text fails the test
//! that wanted it, with a message that says so; outside CI the test skips
//! (`None`). `.ci/run` also runs the whole suite under `CI=true` with the
//! shared folder pointed at an empty one and checks that it fails so.

use crate::common;

use std::path::PathBuf;

use common::captures::{shared_file_in, shared_text_in, MISSING};

/// A fresh folder of this test's own under the system's temporary one.
fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("canopen-shared-data-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The panic message of `f`, which must panic.
fn panic_message(f: impl FnOnce() + std::panic::UnwindSafe) -> String {
    let err = std::panic::catch_unwind(f).expect_err("it did not fail");
    err.downcast_ref::<String>()
        .cloned()
        .or_else(|| err.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default()
}

#[test]
fn an_absent_file_fails_in_ci_and_skips_elsewhere() {
    let path = scratch("absent").join("deltaq-icl1500-startup.log");
    let shown = path.display().to_string();
    let p = path.clone();
    let msg = panic_message(move || {
        shared_file_in("the real capture", p, true);
    });
    assert!(msg.starts_with(MISSING), "{msg}");
    assert!(
        msg.contains(&shown) && msg.contains("does not exist"),
        "{msg}"
    );
    assert_eq!(
        shared_file_in("the real capture", path.clone(), false),
        None
    );
    assert_eq!(shared_text_in("the real capture", path, false), None);
}

#[test]
fn a_folder_in_place_of_the_file_fails_in_ci() {
    let path = scratch("folder").join("sample.eds");
    std::fs::create_dir_all(&path).unwrap();
    let p = path.clone();
    let msg = panic_message(move || {
        shared_file_in("the real EDS file", p, true);
    });
    assert!(msg.starts_with(MISSING), "{msg}");
    assert!(msg.contains("is not a file"), "{msg}");
    assert_eq!(shared_file_in("the real EDS file", path, false), None);
}

/// A capture that is there but cannot be read as text (not UTF-8) was
/// once skipped even in CI (the text was read with `.ok()`).
#[test]
fn a_capture_that_cannot_be_read_as_text_fails_in_ci() {
    let path = scratch("binary").join("deltaq-icl1500-charging.log");
    std::fs::write(&path, [0x28, 0xff, 0xfe, 0x29]).unwrap();
    // It is a readable file: the path is given.
    assert_eq!(shared_file_in("x", path.clone(), true), Some(path.clone()));
    let p = path.clone();
    let msg = panic_message(move || {
        shared_text_in("the real capture", p, true);
    });
    assert!(msg.starts_with(MISSING), "{msg}");
    assert!(msg.contains("cannot be read as text"), "{msg}");
    assert_eq!(shared_text_in("the real capture", path, false), None);
}

#[test]
fn a_readable_file_is_given_in_ci_and_elsewhere() {
    let path = scratch("present").join("deltaq-icl1500-startup.log");
    std::fs::write(&path, "(1.000000) can0 701#05\n").unwrap();
    for ci in [true, false] {
        assert_eq!(shared_file_in("x", path.clone(), ci), Some(path.clone()));
        assert_eq!(
            shared_text_in("x", path.clone(), ci).as_deref(),
            Some("(1.000000) can0 701#05\n")
        );
    }
}
