//! SYNC (identifier 0x080), CiA 301: no data, or one counter byte; the
//! SYNC producer and consumer with 1005h COB-ID SYNC ([`SyncCobId`]), 1006h
//! communication cycle period, 1007h synchronous window length and 1019h
//! synchronous counter overflow value ([`SyncProducer`], [`SyncConsumer`]).

use crate::error::DecodeError;

/// A SYNC message with its optional counter (1..=240 when the producer's
/// 1019h is set; any byte is kept as received).
///
/// ```
/// use canopen_codec::sync::SyncFrame;
/// assert_eq!(SyncFrame::decode(&[]).unwrap(), SyncFrame { counter: None });
/// assert_eq!(SyncFrame::decode(&[7]).unwrap().counter, Some(7));
/// assert!(SyncFrame::decode(&[1, 2]).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct SyncFrame {
    /// The counter byte, if the frame carries one.
    pub counter: Option<u8>,
}

impl SyncFrame {
    /// Decodes 0 or 1 data bytes.
    #[inline]
    pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
        match *data {
            [] => Ok(SyncFrame { counter: None }),
            [c] => Ok(SyncFrame { counter: Some(c) }),
            _ => Err(DecodeError::TooLong {
                max: 1,
                got: data.len(),
            }),
        }
    }

    /// The data bytes (`len` is 0 or 1) in an 8-byte buffer.
    #[must_use]
    #[inline]
    pub fn encode(&self) -> ([u8; 1], usize) {
        match self.counter {
            Some(c) => ([c], 1),
            None => ([0], 0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        for c in 0..=255u8 {
            let s = SyncFrame::decode(&[c]).unwrap();
            let (buf, len) = s.encode();
            assert_eq!(&buf[..len], &[c]);
        }
        let (_, len) = SyncFrame::default().encode();
        assert_eq!(len, 0);
    }
}

mod consumer;
mod producer;
pub use consumer::{SyncConsumer, SyncEvent};
pub use producer::{valid_counter_overflow, SyncCobId, SyncProducer};
