//! SYNC (identifier 0x080), CiA 301: no data, or one counter byte; the
//! SYNC producer and consumer with 1005h COB-ID SYNC ([`SyncCobId`]), 1006h
//! communication cycle period, 1007h synchronous window length and 1019h
//! synchronous counter overflow value ([`SyncProducer`], [`SyncConsumer`]).
//!
//! The frame is read and written in one place, the SYNC wire layer
//! ([`SyncFrame`] / [`SyncMessage`], the crate's
//! [`Codec`](crate::wire::Codec) shape).

mod consumer;
mod producer;
mod wire;
pub use consumer::{SyncConsumer, SyncEvent};
pub use producer::{valid_counter_overflow, SyncCobId, SyncProducer};
pub use wire::{SyncFrame, SyncMessage};
