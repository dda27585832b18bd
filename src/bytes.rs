//! Small inline byte carriers (no allocation).

/// Up to `N` data bytes kept inline (no allocation).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct InlineData<const N: usize> {
    len: u8,
    bytes: [u8; N],
}

/// The payload of a PDO or LSS frame: 0..=8 bytes.
pub type Payload = InlineData<8>;

impl<const N: usize> Default for InlineData<N> {
    fn default() -> Self {
        InlineData {
            len: 0,
            bytes: [0; N],
        }
    }
}

impl<const N: usize> InlineData<N> {
    /// The largest number of bytes this carrier holds.
    pub const CAPACITY: usize = N;

    /// Copies `data`; `None` if it is longer than `N`.
    #[must_use]
    pub fn new(data: &[u8]) -> Option<Self> {
        let mut bytes = [0u8; N];
        bytes.get_mut(..data.len())?.copy_from_slice(data);
        Some(InlineData {
            len: data.len() as u8,
            bytes,
        })
    }

    /// The bytes.
    #[must_use]
    pub fn as_slice(&self) -> &[u8] {
        self.bytes.get(..usize::from(self.len)).unwrap_or(&[])
    }

    /// Number of bytes.
    #[must_use]
    pub const fn len(&self) -> usize {
        self.len as usize
    }

    /// True when no bytes are held.
    #[must_use]
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
