//! The log tools: the trace readers through the public API (Vector BLF),
//! the log analysis library's hand-written JSON (feature `log`),
//! and the programs `canopen-decode`, `canopen-replay` and `canopen-boot`
//! (feature `cli`, run from `env!("CARGO_BIN_EXE_...")`) on our logs, on
//! every trace format and on the real captures.

// BLF files are written by the library's writer (feature `alloc`).
#[cfg(feature = "alloc")]
mod blf_support;
#[path = "../common/mod.rs"]
mod common;
#[cfg(feature = "cli")]
mod decoder_support;
#[cfg(feature = "cli")]
mod trace_writers;

#[cfg(feature = "cli")]
mod boot_cli;
// It runs the boot-up manager on the simulated bus (feature `sim`).
#[cfg(all(feature = "cli", feature = "sim"))]
mod boot_decode;
#[cfg(feature = "cli")]
mod boot_master_cli;
#[cfg(feature = "cli")]
mod bus_load;
#[cfg(feature = "cli")]
mod cli;
#[cfg(feature = "cli")]
mod dbc;
#[cfg(feature = "cli")]
mod hostile_files;
#[cfg(feature = "log")]
mod log_json;
#[cfg(feature = "cli")]
mod naming;
#[cfg(feature = "cli")]
mod pdo;
#[cfg(feature = "cli")]
mod program_options;
// It runs the `charger` and `battery_module` examples (feature `sim`).
#[cfg(all(feature = "cli", feature = "sim"))]
mod replay_cli;
#[cfg(feature = "cli")]
mod report;
#[cfg(feature = "cli")]
mod sdo;
#[cfg(feature = "cli")]
mod signals;
#[cfg(feature = "alloc")]
mod trace_blf;
#[cfg(feature = "zlib")]
mod trace_mf4;
#[cfg(feature = "cli")]
mod trace_pcap;
