//! # canopen-codec
//!
//! A pure, sans-IO CANopen codec for the battery-charging world: CiA 301
//! (NMT, heartbeat, SYNC, TIME, EMCY, SDO, PDO), the CiA 418 battery-module
//! profile, the CiA 419 charger side and the Delta-Q IC Series charger.
//!
//! The caller hands it frames (and, for the state machines, timestamps); it
//! hands back typed messages. It never opens a socket, never reads a clock
//! and never allocates on its decode path, so it runs in `no_std` firmware,
//! in desktop tools and under a fuzzer.
//!
//! ```
//! use canopen_codec::{CanFrame, Message};
//! use canopen_codec::emcy::ErrorCode;
//!
//! // The real Delta-Q charger's "heartbeat lost" emergency.
//! let frame = CanFrame::standard(0x08A, &[0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0]).unwrap();
//! let msg = Message::decode(&frame).unwrap();
//! let Message::Emcy { node, emcy } = msg else { panic!("not an EMCY") };
//! assert_eq!(node.raw(), 10);
//! assert_eq!(emcy.code, ErrorCode::HEARTBEAT);
//! assert_eq!(msg.encode(), frame); // exact round trip
//! ```
//!
//! ## Features
//!
//! - `std` (default): `std::error::Error` for the error types; implies `alloc`.
//! - `alloc`: heap conveniences (none on the decode path).
//! - `embedded-can`: conversions between [`CanFrame`] and any
//!   `embedded_can::Frame` implementor.
//!
//! ## PDO numbering
//!
//! PDOs are numbered from 0, as Delta-Q and the communication parameter
//! indexes do (TPDO n at 1800h + n); see [`cob_id`].
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
#![cfg_attr(docsrs, feature(doc_cfg))]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(test)]
#[macro_use]
extern crate std;
#[cfg(all(feature = "std", not(test)))]
extern crate std;

pub mod bytes;
pub mod cia418;
pub mod cia419;
pub mod clock;
pub mod cob_id;
pub mod deltaq;
pub mod device;
#[cfg(feature = "alloc")]
pub mod eds;
pub mod emcy;
pub mod error;
pub mod frame;
pub mod lss;
pub mod machine;
pub mod message;
pub mod nmt;
pub mod od;
pub mod pdo;
mod queue;
pub mod sdo;
pub mod sync;
pub mod time;
pub mod trace;

pub use clock::Timestamp;
pub use cob_id::{CobKind, NodeId, PdoNumber};
pub use error::DecodeError;
pub use frame::{CanFrame, CanId, FrameError};
pub use message::Message;

/// The README's examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
