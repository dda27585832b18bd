//! The example programs run as a user runs them (built by `cargo test`,
//! found with `common::example`): the battery module on candump scripts, and
//! the charger and the battery module charging in real time on a pipe pair,
//! and the two booted by `canopen-boot` on a three-program bus.

#[path = "../common/mod.rs"]
mod common;

#[cfg(all(
    feature = "sim",
    feature = "lss",
    feature = "guarding",
    feature = "sync-time",
    feature = "store"
))]
mod battery_module_cli;
#[cfg(all(
    feature = "sim",
    feature = "lss",
    feature = "guarding",
    feature = "sync-time",
    feature = "store"
))]
mod realtime_charge;
// It runs `canopen-boot` (feature `cli`) as the two programs' NMT master.
#[cfg(all(
    feature = "cli",
    feature = "sim",
    feature = "lss",
    feature = "guarding",
    feature = "sync-time",
    feature = "store"
))]
mod boot_programs;
