//! The wire-decoding error shared by every stateless codec.

/// Why bytes did not decode. `Copy`, no heap, names the field at fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum DecodeError {
    /// Fewer bytes than the message needs.
    #[error("truncated: need {need} bytes, got {got}")]
    Truncated {
        /// Bytes the message needs.
        need: usize,
        /// Bytes present.
        got: usize,
    },
    /// More bytes than the message may carry.
    #[error("too long: at most {max} bytes, got {got}")]
    TooLong {
        /// Bytes the message may carry.
        max: usize,
        /// Bytes present.
        got: usize,
    },
    /// A remote (RTR) frame where CiA 301 defines only data frames.
    #[error("remote frame where only data frames are defined")]
    UnexpectedRemote,
}

/// Checks that `data` is exactly `n` bytes long.
#[inline]
pub(crate) const fn exact_len(data: &[u8], n: usize) -> Result<(), DecodeError> {
    if data.len() < n {
        Err(DecodeError::Truncated {
            need: n,
            got: data.len(),
        })
    } else if data.len() > n {
        Err(DecodeError::TooLong {
            max: n,
            got: data.len(),
        })
    } else {
        Ok(())
    }
}

/// For the crate's tests: `decode` reads a value of exactly `len` bytes.
/// Every shorter input is [`DecodeError::Truncated`], every longer one (up
/// to 8 bytes more) [`DecodeError::TooLong`], and `len` bytes are no
/// length error.
#[cfg(test)]
pub(crate) fn assert_exact_length<T: core::fmt::Debug>(
    decode: impl Fn(&[u8]) -> Result<T, DecodeError>,
    len: usize,
) {
    use core::cmp::Ordering;
    let data = [0u8; 24];
    for got in 0..=len + 8 {
        let result = decode(data.get(..got).expect("lengths up to 16 bytes"));
        match got.cmp(&len) {
            Ordering::Less => {
                assert_eq!(
                    result.err(),
                    Some(DecodeError::Truncated { need: len, got })
                );
            }
            Ordering::Greater => {
                assert_eq!(result.err(), Some(DecodeError::TooLong { max: len, got }));
            }
            Ordering::Equal => assert!(
                !matches!(
                    result,
                    Err(DecodeError::Truncated { .. } | DecodeError::TooLong { .. })
                ),
                "{len} bytes: {result:?}"
            ),
        }
    }
}
