//! TIME (identifier 0x100), CiA 301: a TIME_OF_DAY value, 6 bytes:
//! bits 0-27 milliseconds after midnight, bits 28-31 reserved, then a u16 of
//! days since 1984-01-01. The TIME producer and consumer follow 1012h
//! COB-ID TIME ([`TimeCobId`], [`TimeProducer`], [`TimeConsumer`]).
//!
//! The frame is read and written in one place, the TIME wire layer
//! ([`TimeFrame`] / [`TimeOfDay`], the crate's
//! [`Codec`](crate::wire::Codec) shape).

mod consumer;
mod producer;
mod wire;
pub use consumer::{TimeConsumer, TimeEvent};
pub use producer::{TimeCobId, TimeProducer};
pub use wire::{TimeFrame, TimeOfDay, MS_PER_DAY};
