//! CAN frames and identifiers.
//!
//! [`CanFrame`] is a classic CAN 2.0 frame: an 11-bit ([`CanId::Standard`]) or
//! 29-bit ([`CanId::Extended`]) identifier, a data or remote kind, and 0..=8
//! data bytes kept inline (no allocation). Constructors validate ranges and
//! return [`FrameError`] instead of panicking.

use core::fmt;

/// The largest 11-bit identifier.
pub const MAX_STANDARD_ID: u16 = 0x7FF;
/// The largest 29-bit identifier.
pub const MAX_EXTENDED_ID: u32 = 0x1FFF_FFFF;
/// The most data bytes a classic CAN frame carries.
pub const MAX_DATA_LEN: usize = 8;

/// A CAN identifier: 11-bit (standard) or 29-bit (extended).
///
/// Build it with [`CanId::standard`] or [`CanId::extended`], which reject
/// out-of-range values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CanId {
    /// 11-bit identifier, `0..=0x7FF`. CANopen's predefined connection set uses these.
    Standard(u16),
    /// 29-bit identifier, `0..=0x1FFF_FFFF`.
    Extended(u32),
}

impl CanId {
    /// An 11-bit identifier, or `None` above `0x7FF`.
    #[must_use]
    pub const fn standard(raw: u16) -> Option<Self> {
        CanId::Standard(raw).checked()
    }

    /// A 29-bit identifier, or `None` above `0x1FFF_FFFF`.
    #[must_use]
    pub const fn extended(raw: u32) -> Option<Self> {
        CanId::Extended(raw).checked()
    }

    /// True when the value fits its format: at most [`MAX_STANDARD_ID`]
    /// for an 11-bit identifier (CAN 2.0A), [`MAX_EXTENDED_ID`] for a
    /// 29-bit one (CAN 2.0B): the check of [`CanId::standard`] and
    /// [`CanId::extended`].
    #[must_use]
    pub const fn fits(self) -> bool {
        match self {
            CanId::Standard(raw) => raw <= MAX_STANDARD_ID,
            CanId::Extended(raw) => raw <= MAX_EXTENDED_ID,
        }
    }

    /// `Some(self)` when it [`fits`](Self::fits).
    const fn checked(self) -> Option<Self> {
        if self.fits() {
            Some(self)
        } else {
            None
        }
    }

    /// The identifier's numeric value.
    #[must_use]
    pub const fn raw(self) -> u32 {
        match self {
            CanId::Standard(id) => id as u32,
            CanId::Extended(id) => id,
        }
    }

    /// True for a 29-bit identifier.
    #[must_use]
    pub const fn is_extended(self) -> bool {
        matches!(self, CanId::Extended(_))
    }
}

impl fmt::Display for CanId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CanId::Standard(id) => write!(f, "{id:03X}"),
            CanId::Extended(id) => write!(f, "{id:08X}"),
        }
    }
}

/// Why a frame could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FrameError {
    /// More than 8 data bytes (or a remote frame DLC above 8).
    #[error("CAN frame carries at most 8 data bytes, got {got}")]
    TooLong {
        /// The length asked for.
        got: usize,
    },
    /// The identifier does not fit its format.
    #[error("identifier {raw:#X} does not fit an {bits}-bit CAN identifier")]
    IdOutOfRange {
        /// The identifier asked for.
        raw: u32,
        /// 11 or 29.
        bits: u8,
    },
}

/// A classic CAN frame: identifier, data or remote, 0..=8 bytes.
///
/// The data bytes live inline; bytes past [`dlc`](Self::dlc) are always
/// zero, so two frames compare equal exactly when they mean the same frame.
///
/// ```
/// use canopen_codec::{CanFrame, CanId};
/// let f = CanFrame::new(CanId::Standard(0x70A), &[0x7F]).unwrap();
/// assert_eq!(f.data(), &[0x7F]);
/// assert!(!f.is_remote());
/// ```
///
/// It is 16 bytes: the identifier, its format and the remote flag share one
/// `u32` (an 11-bit data frame is exactly the values `0..=0x7FF`), then
/// the length and the 8 inline bytes. The length is one of nine values, so
/// `Option<CanFrame>` is 16 bytes too.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct CanFrame {
    /// Identifier bits 0..=28, [`EXTENDED_FLAG`], [`REMOTE_FLAG`].
    word: u32,
    len: Dlc,
    data: [u8; MAX_DATA_LEN],
}

/// A data length code 0..=8 (for a remote frame the length requested).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
enum Dlc {
    D0 = 0,
    D1 = 1,
    D2 = 2,
    D3 = 3,
    D4 = 4,
    D5 = 5,
    D6 = 6,
    D7 = 7,
    D8 = 8,
}

impl Dlc {
    /// `len`, or 8 for anything longer.
    #[inline]
    const fn clamped(len: usize) -> Dlc {
        match len {
            0 => Dlc::D0,
            1 => Dlc::D1,
            2 => Dlc::D2,
            3 => Dlc::D3,
            4 => Dlc::D4,
            5 => Dlc::D5,
            6 => Dlc::D6,
            7 => Dlc::D7,
            _ => Dlc::D8,
        }
    }

    #[inline]
    const fn get(self) -> u8 {
        self as u8
    }
}

/// Set in [`CanFrame::identity`] for a 29-bit identifier.
const EXTENDED_FLAG: u32 = 1 << 31;
/// Set in [`CanFrame::identity`] for a remote frame.
const REMOTE_FLAG: u32 = 1 << 30;

/// The identifier word of `id` (no flags but the format).
#[inline]
const fn id_word(id: CanId) -> u32 {
    match id {
        CanId::Standard(raw) => raw as u32,
        CanId::Extended(raw) => (raw & MAX_EXTENDED_ID) | EXTENDED_FLAG,
    }
}

/// The identity every data frame on `id` has (see
/// [`CanFrame::identity`]), or `u32::MAX`, which no frame has, for an
/// identifier out of range: the state machines' one-compare entry test.
#[inline]
pub(crate) const fn data_frame_identity(id: CanId) -> u32 {
    match id {
        CanId::Standard(raw) if raw <= MAX_STANDARD_ID => raw as u32,
        CanId::Extended(raw) if raw <= MAX_EXTENDED_ID => raw | EXTENDED_FLAG,
        _ => u32::MAX,
    }
}

impl CanFrame {
    /// The frame's identity: identifier bits 0..=28, the extended and the
    /// remote flag, in one word.
    /// Equal to [`data_frame_identity`] of an identifier exactly when the frame
    /// is a data frame on that identifier.
    #[inline]
    pub(crate) const fn identity(&self) -> u32 {
        self.word
    }

    /// An empty data frame on identifier 0 (a placeholder value).
    pub const EMPTY: CanFrame = CanFrame {
        word: 0,
        len: Dlc::D0,
        data: [0; MAX_DATA_LEN],
    };

    /// A data frame. Fails when `data` is longer than 8 bytes or the id is out of range.
    #[inline]
    pub fn new(id: CanId, data: &[u8]) -> Result<Self, FrameError> {
        check_id(id)?;
        if data.len() > MAX_DATA_LEN {
            return Err(FrameError::TooLong { got: data.len() });
        }
        let mut buf = [0u8; MAX_DATA_LEN];
        crate::bytes::copy_payload(&mut buf, data);
        Ok(CanFrame {
            word: id_word(id),
            len: Dlc::clamped(data.len()),
            data: buf,
        })
    }

    /// A data frame on an 11-bit identifier (convenience for CANopen's predefined set).
    pub fn standard(id: u16, data: &[u8]) -> Result<Self, FrameError> {
        let id = CanId::standard(id).ok_or(FrameError::IdOutOfRange {
            raw: u32::from(id),
            bits: 11,
        })?;
        Self::new(id, data)
    }

    /// A data frame from an inline buffer, `len` bytes long. Infallible for
    /// valid `len`; used on hot encode paths.
    #[inline]
    pub(crate) const fn from_parts(id: CanId, data: [u8; 8], len: u8) -> Self {
        Self::from_identity(id_word(id), data, len)
    }

    /// [`from_parts`](Self::from_parts) of the data frame whose
    /// identity is `identity` ([`data_frame_identity`] of an identifier in
    /// range: a caller that keeps the identity rather than the identifier).
    #[inline]
    pub(crate) const fn from_identity(identity: u32, data: [u8; 8], len: u8) -> Self {
        let len = Dlc::clamped(len as usize);
        // Zero the tail so equality is on the meaningful bytes only.
        let mut data = data;
        let mut i = len.get() as usize;
        while i < MAX_DATA_LEN {
            data[i] = 0;
            i += 1;
        }
        CanFrame {
            word: identity,
            len,
            data,
        }
    }

    /// A remote (RTR) frame asking for `dlc` bytes. Fails when `dlc > 8`.
    pub fn remote(id: CanId, dlc: u8) -> Result<Self, FrameError> {
        check_id(id)?;
        if usize::from(dlc) > MAX_DATA_LEN {
            return Err(FrameError::TooLong {
                got: usize::from(dlc),
            });
        }
        Ok(CanFrame {
            word: id_word(id) | REMOTE_FLAG,
            len: Dlc::clamped(dlc as usize),
            data: [0; MAX_DATA_LEN],
        })
    }

    /// The identifier.
    #[must_use]
    #[inline]
    pub const fn id(&self) -> CanId {
        if self.word & EXTENDED_FLAG != 0 {
            CanId::Extended(self.word & MAX_EXTENDED_ID)
        } else {
            CanId::Standard((self.word & MAX_EXTENDED_ID) as u16)
        }
    }

    /// The identifier of an 11-bit data frame; `None` for a remote frame or
    /// a 29-bit identifier.
    #[must_use]
    #[inline]
    pub(crate) const fn standard_data_id(&self) -> Option<u16> {
        if self.word <= MAX_STANDARD_ID as u32 {
            Some(self.word as u16)
        } else {
            None
        }
    }

    /// True for a remote (RTR) frame.
    #[must_use]
    #[inline]
    pub const fn is_remote(&self) -> bool {
        self.word & REMOTE_FLAG != 0
    }

    /// The data length code: the number of data bytes, or for a remote frame
    /// the number requested.
    #[must_use]
    #[inline]
    pub const fn dlc(&self) -> u8 {
        self.len.get()
    }

    /// The data bytes (empty for a remote frame).
    #[must_use]
    #[inline]
    pub fn data(&self) -> &[u8] {
        if self.is_remote() {
            &[]
        } else {
            // The length is at most 8: the `min` lets the compiler drop
            // the fallback at every use.
            self.data
                .get(..usize::from(self.len.get()).min(MAX_DATA_LEN))
                .unwrap_or(&[])
        }
    }

    /// The 8-byte inline buffer, zero past the data length.
    #[must_use]
    #[inline]
    pub const fn padded_data(&self) -> [u8; 8] {
        self.data
    }
}

pub(crate) fn check_id(id: CanId) -> Result<(), FrameError> {
    match id {
        CanId::Standard(raw) if raw > MAX_STANDARD_ID => Err(FrameError::IdOutOfRange {
            raw: u32::from(raw),
            bits: 11,
        }),
        CanId::Extended(raw) if raw > MAX_EXTENDED_ID => {
            Err(FrameError::IdOutOfRange { raw, bits: 29 })
        }
        _ => Ok(()),
    }
}

impl fmt::Debug for CanFrame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

/// Formats as candump does: `70A#7F`, `12345678#0102`, `701#R` (remote, DLC 0)
/// or `701#R1` (remote, DLC 1).
impl fmt::Display for CanFrame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}#", self.id())?;
        if self.is_remote() {
            f.write_str("R")?;
            if self.len.get() > 0 {
                write!(f, "{}", self.len.get())?;
            }
            return Ok(());
        }
        for b in self.data() {
            write!(f, "{b:02X}")?;
        }
        Ok(())
    }
}

#[cfg(feature = "embedded-can")]
mod embedded {
    //! Conversions to and from any [`embedded_can::Frame`] implementor.
    use super::{CanFrame, CanId};

    impl From<CanId> for embedded_can::Id {
        fn from(id: CanId) -> Self {
            match id {
                // Both constructors accept every value our CanId admits; the
                // fallbacks are unreachable for a validly built CanId.
                CanId::Standard(raw) => embedded_can::StandardId::new(raw)
                    .map(embedded_can::Id::Standard)
                    .unwrap_or(embedded_can::Id::Standard(embedded_can::StandardId::MAX)),
                CanId::Extended(raw) => embedded_can::ExtendedId::new(raw)
                    .map(embedded_can::Id::Extended)
                    .unwrap_or(embedded_can::Id::Extended(embedded_can::ExtendedId::MAX)),
            }
        }
    }

    impl From<embedded_can::Id> for CanId {
        fn from(id: embedded_can::Id) -> Self {
            match id {
                embedded_can::Id::Standard(s) => CanId::Standard(s.as_raw()),
                embedded_can::Id::Extended(e) => CanId::Extended(e.as_raw()),
            }
        }
    }

    impl CanFrame {
        /// Converts any `embedded_can::Frame` into a `CanFrame`. Returns `None`
        /// if the source frame reports more than 8 data bytes.
        pub fn from_embedded<F: embedded_can::Frame>(frame: &F) -> Option<Self> {
            let id = CanId::from(frame.id());
            if frame.is_remote_frame() {
                u8::try_from(frame.dlc())
                    .ok()
                    .and_then(|dlc| CanFrame::remote(id, dlc).ok())
            } else {
                CanFrame::new(id, frame.data()).ok()
            }
        }

        /// Builds an `embedded_can::Frame` of the caller's type from this frame.
        /// Returns `None` if the target type refuses it.
        pub fn to_embedded<F: embedded_can::Frame>(&self) -> Option<F> {
            let id = embedded_can::Id::from(self.id());
            if self.is_remote() {
                F::new_remote(id, usize::from(self.dlc()))
            } else {
                F::new(id, self.data())
            }
        }
    }
}

#[cfg(all(test, feature = "embedded-can"))]
mod embedded_tests {
    use super::*;

    /// A minimal foreign frame type, as a HAL would provide.
    #[derive(Debug, PartialEq)]
    struct HalFrame {
        id: embedded_can::Id,
        remote: bool,
        dlc: usize,
        data: [u8; 8],
    }

    impl embedded_can::Frame for HalFrame {
        #[inline]
        fn new(id: impl Into<embedded_can::Id>, data: &[u8]) -> Option<Self> {
            let mut buf = [0; 8];
            buf.get_mut(..data.len())?.copy_from_slice(data);
            Some(HalFrame {
                id: id.into(),
                remote: false,
                dlc: data.len(),
                data: buf,
            })
        }
        fn new_remote(id: impl Into<embedded_can::Id>, dlc: usize) -> Option<Self> {
            (dlc <= 8).then(|| HalFrame {
                id: id.into(),
                remote: true,
                dlc,
                data: [0; 8],
            })
        }
        fn is_extended(&self) -> bool {
            matches!(self.id, embedded_can::Id::Extended(_))
        }
        fn is_remote_frame(&self) -> bool {
            self.remote
        }
        #[inline]
        fn id(&self) -> embedded_can::Id {
            self.id
        }
        #[inline]
        fn dlc(&self) -> usize {
            self.dlc
        }
        #[inline]
        fn data(&self) -> &[u8] {
            &self.data[..if self.remote { 0 } else { self.dlc }]
        }
    }

    #[test]
    fn converts_both_ways() {
        for ours in [
            CanFrame::standard(0x18A, &[0x74, 0x13, 0x45]).unwrap(),
            CanFrame::new(CanId::Extended(0x1FFF_FFFF), &[]).unwrap(),
            CanFrame::remote(CanId::Standard(0x701), 1).unwrap(),
        ] {
            let hal: HalFrame = ours.to_embedded().unwrap();
            assert_eq!(CanId::from(hal.id), ours.id());
            assert_eq!(CanFrame::from_embedded(&hal), Some(ours));
        }
    }
}

/// For the crate's tests: the 11-bit data frame on `id` carrying `data`
/// (the caller's literals are in range: `id` at most 7FFh, at most 8
/// bytes).
#[cfg(test)]
pub(crate) fn standard_frame(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::standard(id, data).expect("an 11-bit identifier and at most 8 bytes")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_long_data_and_bad_ids() {
        assert_eq!(
            CanFrame::standard(0x123, &[0; 9]),
            Err(FrameError::TooLong { got: 9 })
        );
        assert_eq!(
            CanFrame::standard(0x800, &[]),
            Err(FrameError::IdOutOfRange {
                raw: 0x800,
                bits: 11
            })
        );
        assert_eq!(
            CanFrame::new(CanId::Extended(0x2000_0000), &[]),
            Err(FrameError::IdOutOfRange {
                raw: 0x2000_0000,
                bits: 29
            })
        );
        assert_eq!(
            CanFrame::remote(CanId::Standard(1), 9),
            Err(FrameError::TooLong { got: 9 })
        );
        assert!(CanId::standard(0x7FF).is_some());
        assert!(CanId::standard(0x800).is_none());
        assert!(CanId::extended(0x1FFF_FFFF).is_some());
        assert!(CanId::extended(0x2000_0000).is_none());
        // The range each format allows, at its edges.
        assert!(CanId::Standard(0x7FF).fits() && !CanId::Standard(0x800).fits());
        assert!(CanId::Extended(0x1FFF_FFFF).fits() && !CanId::Extended(0x2000_0000).fits());
    }

    #[test]
    fn data_and_display() {
        let f = CanFrame::standard(0x18A, &[0x74, 0x13, 0x45, 0x4E]).unwrap();
        assert_eq!(f.data(), &[0x74, 0x13, 0x45, 0x4E]);
        assert_eq!(f.dlc(), 4);
        assert_eq!(f.padded_data(), [0x74, 0x13, 0x45, 0x4E, 0, 0, 0, 0]);
        assert_eq!(format!("{f}"), "18A#7413454E");
        let r = CanFrame::remote(CanId::Standard(0x701), 1).unwrap();
        assert_eq!(r.data(), &[] as &[u8]);
        assert_eq!(format!("{r}"), "701#R1");
        let e = CanFrame::new(CanId::Extended(0x18FF_0001), &[1]).unwrap();
        assert_eq!(format!("{e}"), "18FF0001#01");
    }

    #[test]
    fn sixteen_bytes_and_flags_kept_apart() {
        assert_eq!(core::mem::size_of::<CanFrame>(), 16);
        let e = CanFrame::new(CanId::Extended(0x7FF), &[1]).unwrap();
        assert_eq!(e.id(), CanId::Extended(0x7FF));
        assert!(!e.is_remote());
        let r = CanFrame::remote(CanId::Extended(MAX_EXTENDED_ID), 8).unwrap();
        assert_eq!(
            (r.id(), r.is_remote()),
            (CanId::Extended(MAX_EXTENDED_ID), true)
        );
        let s = CanFrame::remote(CanId::Standard(0x7FF), 0).unwrap();
        assert_eq!((s.id(), s.is_remote()), (CanId::Standard(0x7FF), true));
        let d = CanFrame::standard(0x7FF, &[]).unwrap();
        assert!(!d.is_remote());
        assert_ne!(d, s);
        assert_ne!(
            CanFrame::standard(0x7FF, &[]).unwrap(),
            CanFrame::new(CanId::Extended(0x7FF), &[]).unwrap()
        );
    }

    #[test]
    fn data_frame_identity_matches_data_frames_only() {
        let std = CanFrame::standard(0x601, &[0x40]).unwrap();
        let ext = CanFrame::new(CanId::Extended(0x601), &[0x40]).unwrap();
        let rtr = CanFrame::remote(CanId::Standard(0x601), 0).unwrap();
        let w = data_frame_identity(CanId::Standard(0x601));
        assert_eq!(
            (
                std.identity() == w,
                ext.identity() == w,
                rtr.identity() == w
            ),
            (true, false, false)
        );
        assert_eq!(ext.identity(), data_frame_identity(CanId::Extended(0x601)));
        // Out of range: a word no frame has.
        assert_eq!(data_frame_identity(CanId::Standard(0x800)), u32::MAX);
        assert_eq!(data_frame_identity(CanId::Extended(1 << 29)), u32::MAX);
        let top = CanFrame::remote(CanId::Extended(MAX_EXTENDED_ID), 8).unwrap();
        assert_ne!(top.identity(), u32::MAX);
    }

    #[test]
    fn sixteen_bytes_with_or_without_option() {
        assert_eq!(core::mem::size_of::<CanFrame>(), 16);
        assert_eq!(core::mem::size_of::<Option<CanFrame>>(), 16);
        let f = CanFrame::from_parts(CanId::Standard(1), [9; 8], 200);
        assert_eq!(f.dlc(), 8);
        for len in 0..=8u8 {
            assert_eq!(
                CanFrame::from_parts(CanId::Standard(1), [9; 8], len).dlc(),
                len
            );
        }
    }

    #[test]
    fn from_parts_zeroes_tail() {
        let f = CanFrame::from_parts(CanId::Standard(1), [9; 8], 2);
        assert_eq!(f, CanFrame::standard(1, &[9, 9]).unwrap());
    }
}
