//! Service data objects (SDO), CiA 301: abort codes and the frame codec.
//!
//! [`Client`] and [`Server`] are the sans-IO state machines for expedited
//! and segmented transfers; both implement the state-machine contract of
//! [`crate::machine`].

mod abort;
mod client;
#[cfg(feature = "alloc")]
mod collect;
mod data;
mod server;
mod wire;

pub use abort::{AbortCode, ALL_ABORT_CODES};
pub use client::{Client, ClientConfig, ClientError, ClientEvent};
#[cfg(feature = "alloc")]
pub use collect::{Collected, UploadBuffer};
pub use data::{ExpeditedData, InitiatePayload, InlineData, Segment, SegmentData};
pub use server::{AbortOrigin, Server, ServerConfig, ServerEvent, DEFAULT_TIMEOUT};
pub use wire::{
    abort_code_of, ClientBlockDownload, ClientBlockUpload, ClientCommand, SdoRequest, SdoResponse,
    ServerBlockDownload, ServerBlockUpload, ServerCommand,
};

#[cfg(test)]
mod machine_tests;
