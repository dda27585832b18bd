//! Whole sessions in simulated time: the simulated bus itself
//! (`common::sim::Sim`), every charge scenario of `sim::Scenario`, and the
//! recorded virtual session (`tests/data/virtual-session.log`).

#[path = "../common/mod.rs"]
mod common;

#[cfg(feature = "sim")]
mod charge_sessions;
mod sim;
#[cfg(feature = "heartbeat-consumer")]
mod virtual_session;
