//! The SYNC wire layer, CiA 301 section 7.2.5.3 (SYNC protocol): the one
//! place where the bytes of a SYNC frame are read and written. A SYNC
//! carries no data, or one byte, the counter (1..=240 when the producer's
//! 1019h synchronous counter overflow value is set; any byte is kept as
//! received).

use crate::error::DecodeError;
use crate::wire::{parse_through_view, Codec};

/// The checked view of a SYNC frame's data: 0 or 1 byte.
///
/// ```
/// use canopen_codec::sync::SyncFrame;
/// assert_eq!(SyncFrame::new_checked(&[]).unwrap().counter(), None);
/// assert_eq!(SyncFrame::new_checked(&[7]).unwrap().counter(), Some(7));
/// assert!(SyncFrame::new_checked(&[1, 2]).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SyncFrame {
    counter: Option<u8>,
}

impl SyncFrame {
    /// The view of `data`: [`DecodeError::TooLong`] above 1 byte.
    #[inline]
    pub fn new_checked(data: &[u8]) -> Result<Self, DecodeError> {
        match *data {
            [] => Ok(SyncFrame { counter: None }),
            [c] => Ok(SyncFrame { counter: Some(c) }),
            _ => Err(DecodeError::TooLong {
                max: 1,
                got: data.len(),
            }),
        }
    }

    /// Byte 0, the counter, when the frame has one.
    #[must_use]
    #[inline]
    pub const fn counter(&self) -> Option<u8> {
        self.counter
    }
}

/// A SYNC message with its optional counter.
///
/// ```
/// use canopen_codec::sync::SyncMessage;
/// use canopen_codec::wire::Codec;
/// assert_eq!(SyncMessage::parse(&[]).unwrap(), SyncMessage { counter: None });
/// let counted = SyncMessage::parse(&[7]).unwrap();
/// assert_eq!(counted.counter, Some(7));
/// let mut buf = [0; 8];
/// assert_eq!(counted.emit(&mut buf), 1);
/// assert_eq!(buf[0], 7);
/// assert!(SyncMessage::parse(&[1, 2]).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct SyncMessage {
    /// The counter byte, if the frame carries one.
    pub counter: Option<u8>,
}

impl SyncMessage {
    /// The SYNC a checked frame carries.
    #[must_use]
    #[inline]
    pub const fn from_view(frame: &SyncFrame) -> Self {
        SyncMessage {
            counter: frame.counter(),
        }
    }
}

impl Codec for SyncMessage {
    parse_through_view!(SyncFrame);

    #[inline]
    fn emit(&self, buf: &mut [u8; 8]) -> usize {
        let [b0, ..] = buf;
        match self.counter {
            Some(c) => {
                *b0 = c;
                1
            }
            None => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::assert_round_trip;

    #[test]
    fn every_counter_round_trips() {
        for c in 0..=255u8 {
            let s = assert_round_trip::<SyncMessage>(&[c]).unwrap();
            assert_eq!(s.counter, Some(c));
        }
        let none = assert_round_trip::<SyncMessage>(&[]).unwrap();
        assert_eq!(none, SyncMessage::default());
        assert_eq!(none.buffer_len(), 0);
    }

    #[test]
    fn more_than_one_byte_is_too_long() {
        for len in 2..=8usize {
            let data = [1u8; 8];
            assert_eq!(
                SyncMessage::parse(&data[..len]),
                Err(DecodeError::TooLong { max: 1, got: len })
            );
        }
    }
}
