//! Checks on the repository and the test support themselves: the
//! layering rule over `src/`, how many object indexes are written out in
//! several files of `src/`, and the loader of the shared third-party test
//! data (`common::captures`) that fails in CI and skips elsewhere.

#[path = "../common/mod.rs"]
mod common;

mod imports;
mod index_literals;
mod layering;
mod shared_data;
