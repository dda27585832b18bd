//! The devices on the CiA 301 device core: the CiA 418 battery module
//! and the Delta-Q charger (NMT, resets, queues at the firmware's capacities,
//! scenarios on the simulated bus), and the device services one by one (store /
//! restore, node guarding, LSS, SYNC and TIME, program download, PDO
//! reconfiguration), the end of the clock and the frame back-pressure rule.

#[path = "../common/mod.rs"]
mod common;

#[cfg(feature = "sim")]
mod battery_module;
#[cfg(feature = "sim")]
mod boot_manager;
#[cfg(all(feature = "sim", feature = "program-download"))]
mod boot_software;
#[cfg(feature = "heartbeat-consumer")]
mod charger_nmt;
#[cfg(feature = "heartbeat-consumer")]
mod charger_queue_capacity;
#[cfg(feature = "sim")]
mod charger_scenarios;
mod end_of_time;
mod event_capacity;
mod frame_backpressure;
#[cfg(all(feature = "sim", feature = "guarding"))]
mod guarding;
#[cfg(all(feature = "sim", feature = "lss"))]
mod lss_scenarios;
mod module_queue_capacity;
#[cfg(feature = "sim")]
mod pdo_reconfig;
#[cfg(all(feature = "sim", feature = "program-download"))]
mod program_download;
mod resets;
#[cfg(feature = "store")]
mod store_props;
#[cfg(feature = "store")]
mod store_restore;
#[cfg(all(feature = "sim", feature = "sync-time"))]
mod sync_time;
