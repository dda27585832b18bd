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

mod display;
mod master;
mod slave;
mod wire;

pub use master::{LssMaster, LssMasterError, LssMasterEvent, LssService};
pub use slave::{LssSlave, LssSlaveConfig, LssSlaveEvent, LssState, NODE_ID_UNCONFIGURED};

pub use wire::{
    Fastscan, IdentifyPart, LssAddress, LssErrorCode, LssField, LssInquiry, LssMessage, LssMode,
    LssRequest, LssResponse, LssStatus,
};

#[cfg(test)]
mod slave_tests;
#[cfg(test)]
mod wire_tests;
