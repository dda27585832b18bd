//! Test support shared by the integration tests (public API only).
#![allow(dead_code)]

pub mod captures;
#[cfg(feature = "sim")]
pub mod devices;
#[cfg(feature = "sim")]
pub mod observe;
#[cfg(feature = "sim")]
pub mod sdo;
#[cfg(feature = "sim")]
pub mod sim;

use canopen_codec::{CanFrame, CanId, Timestamp};

/// The time `n` milliseconds after `Timestamp::ZERO`.
pub fn ms(n: u64) -> Timestamp {
    Timestamp::from_millis(n)
}

/// A standard frame from an id and a hex string with optional spaces.
pub fn frame(id: u16, hex: &str) -> CanFrame {
    let digits: Vec<u8> = hex.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    let bytes: Vec<u8> = digits
        .chunks(2)
        .map(|p| u8::from_str_radix(std::str::from_utf8(p).unwrap(), 16).unwrap())
        .collect();
    CanFrame::new(CanId::Standard(id), &bytes).unwrap()
}

/// `target/<profile>/examples/NAME`, which `cargo test` builds before the
/// tests run, as a path string (for `Command::new` and argument lists).
pub fn example(name: &str) -> String {
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().unwrap().parent().unwrap();
    let path = dir
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(path.exists(), "{} not built", path.display());
    path.display().to_string()
}
