//! Collecting an upload into a `Vec` (`alloc` feature).

use alloc::vec::Vec;

use super::client::ClientEvent;
use super::end::AbortOrigin;
use super::end::TransferEnd;
use crate::abort::AbortCode;

/// How a collected transfer ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Collected {
    /// The upload completed with this value.
    Value(Vec<u8>),
    /// A download completed with this many bytes written.
    Written(usize),
    /// The transfer was aborted.
    Aborted {
        /// The abort code.
        code: AbortCode,
        /// Who aborted.
        origin: AbortOrigin,
    },
}

/// Gathers [`ClientEvent`]s into whole values.
///
/// ```
/// use canopen_codec::sdo::{ClientEvent, Collected, SegmentData, TransferEnd, UploadBuffer};
/// let mut buf = UploadBuffer::new();
/// let piece = |offset, b: &[u8]| ClientEvent::UploadData { index: 0x1008, sub: 0, offset, data: SegmentData::new(b).unwrap() };
/// assert_eq!(buf.push(&piece(0, b"Tiny No")), None);
/// assert_eq!(buf.push(&piece(7, b"de")), None);
/// let done = ClientEvent::Ended(TransferEnd::Uploaded { index: 0x1008, sub: 0, len: 9 });
/// assert_eq!(buf.push(&done), Some(Collected::Value(b"Tiny Node".to_vec())));
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct UploadBuffer {
    data: Vec<u8>,
}

impl UploadBuffer {
    /// An empty buffer.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Feeds one event; returns the outcome when the event ends the transfer.
    pub fn push(&mut self, event: &ClientEvent) -> Option<Collected> {
        match *event {
            ClientEvent::UploadData { offset, data, .. } => {
                // Events arrive in order; an offset that does not follow is
                // impossible from one client, and is placed where it says.
                if offset != self.data.len() {
                    self.data.resize(offset, 0);
                }
                self.data.extend_from_slice(data.as_slice());
                None
            }
            ClientEvent::Ended(TransferEnd::Uploaded { .. }) => {
                Some(Collected::Value(core::mem::take(&mut self.data)))
            }
            ClientEvent::Ended(TransferEnd::Downloaded { len, .. }) => {
                self.data.clear();
                Some(Collected::Written(len))
            }
            ClientEvent::Ended(TransferEnd::Aborted { code, origin, .. }) => {
                self.data.clear();
                Some(Collected::Aborted { code, origin })
            }
        }
    }
}
