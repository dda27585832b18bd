//! Layer setting services (CiA 305, "Layer setting services and protocol"):
//! the frames on 7E5h (master to slave) and 7E4h (slave to master), an LSS
//! slave state machine and an LSS master with fastscan.
//!
//! A node leaves the production line without a node-ID (255, "not
//! configured"); a service tool (the LSS master) finds its 128-bit LSS
//! address (the 1018h identity) by fastscan, gives it a node-ID and the
//! node boots up under it.
//!
//! ```
//! use canopen_codec::lss::{LssMessage, LssRequest};
//! use canopen_codec::{CanFrame, Message};
//! let f = CanFrame::standard(0x7E5, &[0x51, 0x78, 0x56, 0x34, 0x12, 31, 0, 0]).unwrap();
//! let m = Message::decode(&f).unwrap();
//! assert_eq!(m.to_string(), "LSS fastscan id 12345678 bit 31 sub 0 next 0");
//! assert!(matches!(m, Message::Lss(LssMessage::Request(LssRequest::Fastscan(_)))));
//! assert_eq!(m.encode(), f);
//! ```
//!
//! # The frames
//!
//! CiA 305 section 4 "LSS protocol descriptions": every frame is 8 bytes, byte 0
//! the command specifier (cs), bytes 1..=7 the service's data, unused bytes
//! reserved (sent as 0).
//!
//! | cs | master → slave (7E5h) | slave → master (7E4h) |
//! |----|-----------------------|-----------------------|
//! | 04h | switch state global, byte 1 mode (0 waiting, 1 configuration) | — |
//! | 11h | configure node-ID, byte 1 node-ID | error code, specific error |
//! | 13h | configure bit timing, byte 1 table selector, byte 2 table index | error code, specific error |
//! | 15h | activate bit timing, bytes 1-2 switch delay (ms) | — |
//! | 17h | store configuration | error code, specific error |
//! | 40h-43h | switch state selective: vendor-ID, product code, revision, serial (u32) | — |
//! | 44h | — | switch state selective response |
//! | 46h-4Bh | identify remote slave: vendor-ID, product code, revision low/high, serial low/high (u32) | — |
//! | 4Ch | identify non-configured remote slave | — |
//! | 4Fh | — | identify slave (also the fastscan answer) |
//! | 50h | — | identify non-configured slave |
//! | 51h | fastscan: bytes 1-4 IDNumber, byte 5 BitChecked, byte 6 LSSSub, byte 7 LSSNext | — |
//! | 5Ah-5Dh | inquire vendor-ID, product code, revision, serial | the value (u32) |
//! | 5Eh | inquire node-ID | byte 1 node-ID |
//!
//! Decoding is total and exact: a frame that is not 8 bytes long, carries a
//! command specifier this table does not list, or has a reserved byte that
//! is not zero decodes to `Other(payload)` with its bytes kept, so
//! `encode(decode(x)) == x` for every frame.

mod display;
mod master;
mod slave;
mod wire;

pub use master::{LssMaster, LssMasterError, LssMasterEvent, LssService};
pub use slave::{LssSlave, LssSlaveConfig, LssSlaveEvent, LssState, NODE_ID_UNCONFIGURED};

pub use wire::{
    Fastscan, IdentifyPart, LssAddress, LssErrorCode, LssField, LssFrame, LssInquiry, LssMessage,
    LssMode, LssRequest, LssResponse, LssStatus,
};

#[cfg(test)]
mod slave_tests;
#[cfg(test)]
mod wire_tests;
