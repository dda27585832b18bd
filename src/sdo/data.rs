//! Inline data carriers of SDO frames: up to 4 expedited bytes, up to 7
//! segment bytes, and the initiate payload forms.

pub use crate::bytes::InlineData;

/// The data of an expedited initiate frame: 0..=4 bytes.
pub type ExpeditedData = InlineData<4>;
/// The data of a segment: 0..=7 bytes.
pub type SegmentData = InlineData<7>;

/// What an initiate-download request or initiate-upload response carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InitiatePayload {
    /// e = 1: the value itself. With `size_indicated` (s = 1) the n field
    /// gives the exact length, 1..=4 bytes (an empty `data` cannot be
    /// expressed and encodes as 4 zero bytes; [`InitiatePayload::expedited`]
    /// refuses it); without it (s = 0) the value is "up to 4 bytes" and
    /// `data` holds every data byte the frame carried.
    Expedited {
        /// The data bytes.
        data: ExpeditedData,
        /// The s bit.
        size_indicated: bool,
    },
    /// e = 0: a segmented transfer follows, with its total size when s = 1.
    Segmented {
        /// Total size in bytes (bytes 4-7) when indicated.
        size: Option<u32>,
    },
}

impl InitiatePayload {
    /// An expedited payload with its size indicated: 1..=4 bytes. `None`
    /// for an empty value (the n field cannot say 0 bytes: CiA 301 sends it
    /// segmented) and above 4 bytes.
    #[must_use]
    pub fn expedited(data: &[u8]) -> Option<Self> {
        if data.is_empty() {
            return None;
        }
        Some(InitiatePayload::Expedited {
            data: ExpeditedData::new(data)?,
            size_indicated: true,
        })
    }
}

/// One segment of a segmented transfer (download request or upload response).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Segment {
    /// The t bit.
    pub toggle: bool,
    /// The c bit: no more segments follow.
    pub last: bool,
    /// 0..=7 data bytes (7 - n).
    pub data: SegmentData,
}
