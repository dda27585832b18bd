//! SDO (CiA 301 section 7.2.4): the client and the server byte-exact
//! against the public vectors, every abort path, segment and block transfers on
//! the simulated bus (`common::sim`, `common::sdo::SdoPair`), the passive
//! observer beside them under faults, and the back-pressure rule.
//!
//! `SDO_BLOCK_PROPS_CASES` and `SDO_OBSERVER_PROPS_CASES` raise the property
//! cases (`.ci/run --long`: `cargo test --all-features --test sdo observer_props::`
//! and `--release ... block_props::`).

#[path = "../common/mod.rs"]
mod common;

#[cfg(feature = "alloc")]
mod aborts;
#[cfg(all(feature = "alloc", feature = "sdo-client-segmented"))]
mod backpressure;
#[cfg(all(feature = "sim", feature = "sdo-block"))]
mod block_props;
#[cfg(all(feature = "sim", feature = "sdo-block"))]
mod observer_props;
#[cfg(all(feature = "sim", feature = "sdo-client-segmented"))]
mod pair;
#[cfg(all(feature = "alloc", feature = "sdo-client-segmented"))]
mod segment_paths;
#[cfg(feature = "alloc")]
mod vectors;
