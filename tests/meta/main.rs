//! Checks on the repository and the test support themselves: the
//! layering rule over `src/`, and the loader of the shared third-party test
//! data (`common::captures`) that fails in CI and skips elsewhere.

#[path = "../common/mod.rs"]
mod common;

mod layering;
mod shared_data;
