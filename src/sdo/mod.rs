//! Service data objects (SDO), CiA 301: abort codes and the frame codec.
//!
//! The stateful client and server build on these types.

mod abort;
mod data;
mod wire;

pub use abort::{AbortCode, ALL_ABORT_CODES};
pub use data::{ExpeditedData, InitiatePayload, InlineData, Segment, SegmentData};
pub use wire::{
    abort_code_of, ClientBlockDownload, ClientBlockUpload, ClientCommand, SdoRequest, SdoResponse,
    ServerBlockDownload, ServerBlockUpload, ServerCommand,
};
