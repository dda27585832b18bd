//! The PDO wire layer, CiA 301 section 7.2.2 (Process data object): the one
//! place where a PDO frame's bytes are read and written. A PDO carries
//! 0..=8 data bytes with no framing of its own: what they mean is its
//! mapping's ([`PdoMapping`](crate::pdo::PdoMapping) packs and unpacks
//! them), so the representation is the bytes themselves, a
//! [`Payload`]. A remote frame on a TPDO identifier (a request for that
//! TPDO) carries no data and is not a PDO frame here.

use crate::bytes::{InlineData, Payload};
use crate::error::DecodeError;
use crate::frame::CanFrame;
use crate::wire::{put, Codec};

/// The checked view of a PDO frame's data: 0..=8 bytes, held padded to 8
/// with zeros (bytes past the length read as zero): the [`Payload`] it
/// carries, with the PDO's own readings of it.
///
/// ```
/// use canopen_codec::pdo::PdoFrame;
/// let f = PdoFrame::new_checked(&[0x74, 0x13]).unwrap();
/// assert_eq!((f.as_bytes().len(), f.word()), (2, 0x1374));
/// assert!(PdoFrame::new_checked(&[0; 9]).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PdoFrame(Payload);

impl PdoFrame {
    /// The view of `data`: [`DecodeError::TooLong`] above 8 bytes.
    #[inline]
    pub fn new_checked(data: &[u8]) -> Result<Self, DecodeError> {
        Payload::new(data)
            .map(PdoFrame)
            .ok_or(DecodeError::TooLong {
                max: Payload::CAPACITY,
                got: data.len(),
            })
    }

    /// The view of a data frame's bytes straight from its padded buffer
    /// (the hot path: no copy loop); a remote frame is
    /// [`DecodeError::UnexpectedRemote`].
    #[inline]
    pub fn of_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
        if frame.is_remote() {
            return Err(DecodeError::UnexpectedRemote);
        }
        Ok(PdoFrame(InlineData::from_padded(
            frame.padded_data(),
            frame.dlc(),
        )))
    }

    /// The data bytes.
    #[must_use]
    #[inline]
    pub fn as_bytes(&self) -> &[u8] {
        self.0.as_slice()
    }

    /// The frame of `len` (at most 8) little-endian bytes of `word`, bytes
    /// past `len` zero: a TPDO's payload as its mapping packed it.
    #[must_use]
    #[inline]
    pub(crate) const fn from_word(word: u64, len: u8) -> Self {
        let len = if len > 8 { 8 } else { len };
        let mask = if len >= 8 {
            u64::MAX
        } else {
            (1u64 << (8 * len as u32)) - 1
        };
        PdoFrame(InlineData::from_padded((word & mask).to_le_bytes(), len))
    }

    /// The data frame carrying these bytes on the identifier whose word is
    /// `identity` ([`data_frame_identity`](crate::frame::data_frame_identity)
    /// of an identifier in range: a producer that keeps the word, not the
    /// identifier).
    #[must_use]
    #[inline]
    pub(crate) const fn frame_on_identity(&self, identity: u32) -> CanFrame {
        let (bytes, len) = self.0.padded();
        CanFrame::from_identity(identity, bytes, len)
    }

    /// The data as one little-endian word (byte `i` is bits `8 i .. 8 i +
    /// 8`; zero past the length), the form the mapping packs and unpacks.
    #[must_use]
    #[inline]
    pub const fn word(&self) -> u64 {
        u64::from_le_bytes(self.0.padded().0)
    }

    /// The payload the frame carries.
    #[must_use]
    #[inline]
    pub const fn payload(&self) -> Payload {
        self.0
    }
}

impl Codec for Payload {
    /// Reads a PDO's (or any raw frame's) 0..=8 data bytes.
    #[inline]
    fn parse(data: &[u8]) -> Result<Self, DecodeError> {
        PdoFrame::new_checked(data).map(|f| f.payload())
    }

    /// [`PdoFrame::of_frame`]: no copy loop on the hot path.
    #[inline]
    fn parse_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
        PdoFrame::of_frame(frame).map(|f| f.payload())
    }

    #[inline]
    fn emit(&self, buf: &mut [u8; 8]) -> usize {
        put(buf, self.as_slice())
    }

    #[inline]
    fn buffer_len(&self) -> usize {
        self.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::CanId;
    use crate::wire::assert_round_trip;

    #[test]
    fn every_length_round_trips() {
        let bytes = [0x74, 0x13, 0x45, 0x4E, 0x00, 0xFF, 0x80, 0x01];
        for len in 0..=8usize {
            let p = assert_round_trip::<Payload>(&bytes[..len]).unwrap();
            assert_eq!(p.as_slice(), &bytes[..len]);
            let frame = CanFrame::standard(0x18A, &bytes[..len]).unwrap();
            assert_eq!(Payload::parse_frame(&frame), Ok(p));
            assert_eq!(p.to_frame_on(CanId::Standard(0x18A)), frame);
        }
        assert_eq!(
            Payload::parse(&[0; 9]),
            Err(DecodeError::TooLong { max: 8, got: 9 })
        );
    }

    #[test]
    fn a_packed_word_is_the_frame_of_its_bytes() {
        let f = PdoFrame::from_word(0x1122_3344_5566_7788, 3);
        assert_eq!(f.as_bytes(), &[0x88, 0x77, 0x66]);
        assert_eq!(f.word(), 0x66_7788);
        assert_eq!(PdoFrame::from_word(u64::MAX, 8).as_bytes(), &[0xFF; 8]);
        assert_eq!(PdoFrame::from_word(u64::MAX, 0).word(), 0);
        let identity = crate::frame::data_frame_identity(CanId::Standard(0x18A));
        assert_eq!(
            f.frame_on_identity(identity),
            CanFrame::standard(0x18A, &[0x88, 0x77, 0x66]).unwrap()
        );
    }

    #[test]
    fn the_view_reads_the_word_and_refuses_remote_frames() {
        let f = PdoFrame::new_checked(&[1, 2, 3]).unwrap();
        assert_eq!(f.word(), 0x03_02_01);
        assert_eq!(f.as_bytes(), &[1, 2, 3]);
        assert_eq!(f.payload().len(), 3);
        assert!(PdoFrame::new_checked(&[]).unwrap().as_bytes().is_empty());
        let remote = CanFrame::remote(CanId::Standard(0x18A), 2).unwrap();
        assert_eq!(
            PdoFrame::of_frame(&remote),
            Err(DecodeError::UnexpectedRemote)
        );
    }
}
