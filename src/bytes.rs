//! Small inline byte carriers (no allocation).

/// Copies the first `min(dst.len(), src.len())` bytes of a CAN payload
/// (at most 8 in every caller).
#[inline]
pub(crate) fn copy_payload(dst: &mut [u8], src: &[u8]) {
    let n = dst.len().min(src.len());
    if let (Some(d), Some(s)) = (dst.get_mut(..n), src.get(..n)) {
        d.copy_from_slice(s);
    }
}

/// Up to `N` data bytes kept inline (no allocation).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct InlineData<const N: usize> {
    len: u8,
    bytes: [u8; N],
}

/// The payload of a PDO or LSS frame: 0..=8 bytes.
pub type Payload = InlineData<8>;

impl InlineData<8> {
    /// The payload of a zero-padded 8-byte buffer holding `len` bytes (a
    /// checked view's buffer: the bytes past `len` are zero, as
    /// [`InlineData::new`] leaves them).
    #[inline]
    pub(crate) const fn from_padded(bytes: [u8; 8], len: u8) -> Self {
        InlineData {
            len: if len > 8 { 8 } else { len },
            bytes,
        }
    }

    /// The zero-padded 8-byte buffer and the length (0..=8): what a CAN
    /// frame carries.
    #[inline]
    pub(crate) const fn padded(&self) -> ([u8; 8], u8) {
        (self.bytes, self.len)
    }
}

impl<const N: usize> InlineData<N> {
    /// `len` bytes (at most `N`) of a little-endian word: byte `i` of the
    /// data is bits `8 i .. 8 i + 8` of `word`. Bytes past `len` come out
    /// zero, as [`InlineData::new`] leaves them (the SDO segment and
    /// expedited paths).
    #[inline]
    pub(crate) fn from_le_word(word: u64, len: usize) -> Self {
        let len = if len > N { N } else { len };
        let mask = if len >= 8 {
            u64::MAX
        } else {
            (1u64 << (8 * len)) - 1
        };
        let all = (word & mask).to_le_bytes();
        let mut bytes = [0u8; N];
        let n = if N < 8 { N } else { 8 };
        if let (Some(d), Some(s)) = (bytes.get_mut(..n), all.get(..n)) {
            d.copy_from_slice(s);
        }
        InlineData {
            len: len as u8,
            bytes,
        }
    }
}

impl InlineData<4> {
    /// One byte.
    #[must_use]
    pub const fn le_u8(v: u8) -> Self {
        InlineData {
            len: 1,
            bytes: [v, 0, 0, 0],
        }
    }

    /// A `u16`, little-endian (CANopen's byte order).
    #[must_use]
    pub const fn le_u16(v: u16) -> Self {
        let [a, b] = v.to_le_bytes();
        InlineData {
            len: 2,
            bytes: [a, b, 0, 0],
        }
    }

    /// A `u32`, little-endian (CANopen's byte order).
    #[must_use]
    pub const fn le_u32(v: u32) -> Self {
        InlineData {
            len: 4,
            bytes: v.to_le_bytes(),
        }
    }
}

impl<const N: usize> Default for InlineData<N> {
    fn default() -> Self {
        InlineData {
            len: 0,
            bytes: [0; N],
        }
    }
}

impl<const N: usize> AsRef<[u8]> for InlineData<N> {
    fn as_ref(&self) -> &[u8] {
        self.as_slice()
    }
}

impl<const N: usize> InlineData<N> {
    /// No bytes.
    pub const EMPTY: Self = InlineData {
        len: 0,
        bytes: [0; N],
    };

    /// The largest number of bytes this carrier holds.
    pub const CAPACITY: usize = N;

    /// Copies `data`; `None` if it is longer than `N`.
    #[must_use]
    #[inline]
    pub fn new(data: &[u8]) -> Option<Self> {
        if data.len() > N {
            return None;
        }
        let mut bytes = [0u8; N];
        copy_payload(&mut bytes, data);
        Some(InlineData {
            len: data.len() as u8,
            bytes,
        })
    }

    /// The bytes.
    #[must_use]
    #[inline]
    pub fn as_slice(&self) -> &[u8] {
        // `len` is at most `N`; the `min` says so to the compiler, which
        // then drops the fallback (a select at every use, on 32-bit
        // targets some 10 bytes each).
        self.bytes
            .get(..usize::from(self.len).min(N))
            .unwrap_or(&[])
    }

    /// Number of bytes.
    #[must_use]
    #[inline]
    pub const fn len(&self) -> usize {
        self.len as usize
    }

    /// True when no bytes are held.
    #[must_use]
    #[inline]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl<const N: usize> core::fmt::Debug for InlineData<N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("[")?;
        for (i, b) in self.as_slice().iter().enumerate() {
            if i > 0 {
                f.write_str(" ")?;
            }
            write!(f, "{b:02X}")?;
        }
        f.write_str("]")
    }
}

/// The two `From` conversions between a code or value type and the raw
/// word the bus carries it in: `raw_word!(AbortCode: u32, AbortCode::from_u32,
/// AbortCode::to_u32)` gives `From<u32> for AbortCode` and
/// `From<AbortCode> for u32` through the type's own named conversions.
macro_rules! raw_word {
    ($ty:ident : $raw:ty, $from:expr, $to:expr) => {
        impl From<$raw> for $ty {
            #[inline]
            fn from(raw: $raw) -> Self {
                $from(raw)
            }
        }

        impl From<$ty> for $raw {
            #[inline]
            fn from(value: $ty) -> $raw {
                $to(value)
            }
        }
    };
}
pub(crate) use raw_word;
