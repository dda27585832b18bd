//! Whole sessions in simulated time: the simulated bus itself
//! (`canopen_codec::sim::bus`), every charge scenario of `sim::Scenario`,
//! every file of `scenarios/` (`sim::bench`), generated ones and the
//! unseen ones written apart from the charger (`tests/sessions/unseen/`),
//! the recorded virtual session (`tests/data/virtual-session.log`), and
//! our own nodes booted by the CiA 302-2 boot-up manager from DCFs of
//! their EDS.

#[path = "../common/mod.rs"]
mod common;

#[cfg(feature = "sim")]
mod battery_type;
#[cfg(feature = "sim")]
mod boot_manager;
#[cfg(feature = "sim")]
mod bus_faults;
#[cfg(feature = "sim")]
mod bus_observe;
#[cfg(feature = "sim")]
mod charge_sessions;
#[cfg(feature = "sim")]
mod chemistries;
#[cfg(feature = "sim")]
mod generated_scenarios;
#[cfg(feature = "sim")]
mod protections;
#[cfg(feature = "sim")]
mod scenario_files;
#[cfg(feature = "sim")]
mod sim;
#[cfg(feature = "sim")]
mod unseen_files;
#[cfg(feature = "sim")]
mod virtual_session;
