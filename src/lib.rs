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
//! ## Where do I look for X
//!
//! | I want to ... | Look in |
//! |---|---|
//! | decode or encode any frame | [`Message`] ([`message`]); logs with deviations: [`message::lenient`]; words: [`message::display`] |
//! | parse or emit one protocol's payload | [`wire`] (the [`Codec`] trait: `parse` / `emit` / `buffer_len`, and each protocol's checked view) |
//! | know which object an identifier is | [`cob_id`] ([`CobKind`], [`NodeId`], the predefined connection set) |
//! | build or inspect a frame | [`frame`] ([`CanFrame`], [`CanId`]) |
//! | drive any state machine | [`machine`] (the [`Machine`](machine::Machine) contract and back-pressure rule) |
//! | give the machines time | [`clock`] ([`Timestamp`], the timer table) |
//! | NMT commands, a node's state, heartbeat, node guarding | [`nmt`], [`nmt::heartbeat`], [`nmt::guarding`] |
//! | emergencies and their codes | [`emcy`] |
//! | SYNC and TIME | [`sync`] ([`sync::SyncMessage`], producer, consumer), [`time`] ([`time::TimeOfDay`], producer, consumer) |
//! | read or write objects over SDO, or follow transfers on a bus | [`sdo`] (client, server, observer; the wire layer in [`sdo::ClientCommand`] / [`sdo::ServerCommand`]) |
//! | SDO abort codes (also why the object dictionary refused an access) | [`abort`] ([`abort::AbortCode`], re-exported as [`sdo::AbortCode`]) |
//! | PDO mapping, packing, producers and receivers | [`pdo`] |
//! | layer setting services (CiA 305) | [`lss`] |
//! | an object dictionary for a server or a device | [`od`] |
//! | a whole CiA 301 device (NMT slave, heartbeat, EMCY, SDO server, PDOs) | [`device`] |
//! | boot a network as its NMT master: check, configure and start each slave (CiA 302-2) | [`manager`] ([`manager::BootManager`], the error status letters in [`manager::BootError`]) |
//! | program download (CiA 302-3: 1F50h-1F57h) | [`program`] (the objects, the store trait, the codes), `device::ProgramObjects` (feature `program-download`), [`sdo::ProgramDownload`] (the master) |
//! | EDS and DCF files (CiA 306) | `eds` (feature `alloc`) |
//! | read candump, PCAN, Vector ASC, CSV and BLF traces | [`trace`] ([`trace::candump`] for candump lines, [`trace::blf`] for BLF) |
//! | the CiA 418 battery module | [`cia418`] |
//! | CiA 419 charger objects | [`cia419`] |
//! | the Delta-Q IC Series charger and its error codes | [`deltaq`] |
//! | the charger's own charge logic (modes, algorithms, set points, status) | [`deltaq::charge`] |
//! | a simulated bus for any set of machines (latency, faults, loss, bus-off) | `sim::bus` (feature `sim`) |
//! | a battery pack, a power stage and whole charge sessions in simulated time | `sim` (feature `sim`) |
//! | read a CAN log, reassemble SDO, name the objects, summarise a bus | `log` (feature `log`: what the programs do, as a library) |
//! | the common imports in one line | [`prelude`] |
//!
//! The modules are layered; each imports only from the layers below it
//! (and, where marked, from its own), and no modules import each other in
//! a circle, at any level (`tests/meta/layering.rs` checks both on the
//! real import graph):
//!
//! 1. the base, each other's peers: [`abort`], [`bytes`], [`clock`],
//!    [`cob_id`], [`error`], [`frame`], [`machine`], [`wire`];
//! 2. [`od`] and [`program`];
//! 3. the protocols, each other's peers: [`emcy`], [`lss`], [`nmt`],
//!    [`pdo`], [`sdo`], [`sync`], [`time`], [`trace`];
//! 4. [`message`] and the [`prelude`];
//! 5. the CiA 302-2 boot-up manager, [`manager`];
//! 6. the device core, [`device`];
//! 7. `eds` (describes a device);
//! 8. the profiles, in order: [`cia418`], [`cia419`], [`deltaq`];
//! 9. `sim`, then `log`, then the programs.
//!
//! The CiA 301 layers (1 to 7) never name a profile, `sim` or `log`.
//!
//! ## Features
//!
//! - `std` (default): `std::error::Error` for the error types; implies `alloc`.
//! - `alloc`: heap conveniences (none on the decode path).
//! - `embedded-can`: conversions between [`CanFrame`] and any
//!   `embedded_can::Frame` implementor.
//! - Device services a firmware node can leave out (all default on; each
//!   removes code inside the one engine that serves it, and what it
//!   removes is refused on the bus with the CiA 301 abort code):
//!   `lss` (the LSS slave in the device core), `guarding` (node and life
//!   guarding in the device core), `sync-time` (the device's SYNC producer
//!   and TIME), `sdo-block` (SDO block transfer in the client and the
//!   server), `sdo-client-segmented` (segmented transfers in the SDO
//!   client), `heartbeat-consumer` (1016h in the device core and the
//!   Delta-Q charger), `program-download` (1F50h-1F57h served over a
//!   `program::ProgramStore`). Their firmware cost is in `Cargo.toml` and
//!   `docs/FIRMWARE.md`.
//! - `sim` (not default): the simulated bus (`sim::bus::Bus`) every test,
//!   bench, session and fuzz target runs on, the simulation models and
//!   whole charge sessions (`sim`).
//! - `log`: log analysis (trace reading, SDO reassembly, naming, PDO
//!   learning, summary, signals, DBC, report), no dependency of its own;
//!   implies `std` and every device service.
//! - `cli`: the `canopen-decode` and `canopen-replay` programs (`log` plus
//!   their own dependencies, which never reach the library).
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
// The log module formats text: `format!` and `vec!` from std.
#[cfg(any(test, feature = "log"))]
#[macro_use]
extern crate std;
#[cfg(all(feature = "std", not(any(test, feature = "log"))))]
extern crate std;

pub mod abort;
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
#[cfg(feature = "log")]
pub mod log;
pub mod lss;
pub mod machine;
pub mod manager;
pub mod message;
pub mod nmt;
pub mod od;
pub mod pdo;
pub mod prelude;
pub mod program;
mod queue;
pub mod sdo;
#[cfg(feature = "sim")]
pub mod sim;
pub mod sync;
pub mod time;
pub mod trace;
pub mod wire;

#[cfg(test)]
mod testing;

pub use clock::Timestamp;
pub use cob_id::{CobKind, NodeId, PdoNumber};
pub use error::DecodeError;
pub use frame::{CanFrame, CanId, FrameError};
pub use message::Message;
pub use wire::Codec;

/// The README's examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

/// The examples of docs/LIBRARY.md (LSS, EDS), compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../docs/LIBRARY.md")]
pub struct LibraryDoctests;
