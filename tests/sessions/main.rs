//! Whole sessions in simulated time: the simulated bus itself
//! (`canopen_codec::sim::bus`), every charge scenario of `sim::Scenario`, and the
//! recorded virtual session (`tests/data/virtual-session.log`).

#[path = "../common/mod.rs"]
mod common;

#[cfg(feature = "sim")]
mod bus_faults;
#[cfg(feature = "sim")]
mod bus_observe;
#[cfg(feature = "sim")]
mod charge_sessions;
#[cfg(feature = "sim")]
mod sim;
#[cfg(feature = "sim")]
mod virtual_session;
