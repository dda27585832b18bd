//! The library's simulated bus (`canopen_codec::sim::bus`), which every
//! scenario test runs on, and the tests' shorthand for making one.

#[allow(unused_imports)]
pub use canopen_codec::sim::bus::{Bus, Fate, Handle, Sent, OUTSIDE};

/// An empty bus whose frames arrive `latency_us` microseconds after they
/// are sent.
pub fn bus(latency_us: u64) -> Bus {
    Bus::new(std::time::Duration::from_micros(latency_us))
}
