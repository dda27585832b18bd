//! The CRC of SDO block transfer: CRC-16/CCITT with polynomial 1021h and
//! initial value 0 (also known as CRC-16/XMODEM), no reflection, no final
//! XOR, computed over all data bytes of the transfer (CiA 301 section
//! 7.2.4.3, SDO protocols: SDO block download / block upload, "CRC").

/// Slicing tables of polynomial 1021h, built at compile time (8 x 256
/// entries, 4 KiB): `TABLES[k][x]` is the CRC register after byte `x`
/// followed by `k` zero bytes, from a zero register. CRC is linear, so the
/// CRC of up to 8 bytes is the XOR of one independent lookup per byte
/// (the register's two bytes folded into the first two), instead of a
/// chain of 8 dependent ones.
const TABLES: [[u16; 256]; 8] = {
    let mut tables = [[0u16; 256]; 8];
    let mut i = 0;
    while i < 256 {
        let mut crc = (i as u16) << 8;
        let mut bit = 0;
        while bit < 8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x1021
            } else {
                crc << 1
            };
            bit += 1;
        }
        tables[0][i] = crc;
        i += 1;
    }
    let mut k = 1;
    while k < 8 {
        let mut i = 0;
        while i < 256 {
            let prev = tables[k - 1][i];
            tables[k][i] = (prev << 8) ^ tables[0][(prev >> 8) as usize];
            i += 1;
        }
        k += 1;
    }
    tables
};

/// The CRC register after `bytes` (2..=8 of them), from `crc`.
#[inline(always)]
fn fold<const N: usize>(crc: u16, bytes: &[u8; N]) -> u16 {
    let [hi, lo] = crc.to_be_bytes();
    let mut acc = 0u16;
    // N is 2..=8 and i < N: every index is a constant in bounds.
    for (i, &b) in bytes.iter().enumerate() {
        let x = match i {
            0 => b ^ hi,
            1 => b ^ lo,
            _ => b,
        };
        acc ^= TABLES[N - 1 - i][usize::from(x)];
    }
    acc
}

/// One step over at most 8 bytes.
#[inline]
fn step(crc: u16, chunk: &[u8]) -> u16 {
    macro_rules! by {
        ($($n:literal)*) => {
            match chunk.len() {
                $($n => match <&[u8; $n]>::try_from(chunk) {
                    Ok(bytes) => fold(crc, bytes),
                    Err(_) => crc,
                },)*
                1 => match chunk.first() {
                    Some(&b) => (crc << 8) ^ TABLES[0][usize::from((crc >> 8) as u8 ^ b)],
                    None => crc,
                },
                _ => crc,
            }
        };
    }
    by!(2 3 4 5 6 7 8)
}

/// Continues a CRC-16/CCITT (polynomial 1021h) over `data`, starting from
/// `crc` (0 for a new transfer): feeding a value in pieces gives the same
/// CRC as feeding it whole.
///
/// ```
/// use canopen_codec::sdo::{crc16, crc16_update};
/// assert_eq!(crc16_update(crc16_update(0, b"1234"), b"56789"), crc16(b"123456789"));
/// ```
///
/// On 64-bit targets it runs eight bytes at a time over 4 KiB of slicing
/// tables; elsewhere (32-bit microcontrollers, where flash is the scarce
/// resource) one byte at a time over the first 512-byte table alone. Both
/// give the same CRC.
#[must_use]
pub fn crc16_update(crc: u16, data: &[u8]) -> u16 {
    if cfg!(target_pointer_width = "64") {
        sliced(crc, data)
    } else {
        bytewise(crc, data)
    }
}

/// [`crc16_update`] eight bytes at a time (the slicing tables).
fn sliced(crc: u16, data: &[u8]) -> u16 {
    let mut chunks = data.chunks_exact(8);
    let mut crc = crc;
    for chunk in &mut chunks {
        crc = step(crc, chunk);
    }
    step(crc, chunks.remainder())
}

/// The table of one byte (the first slicing table), 512 bytes.
const BYTE_TABLE: [u16; 256] = TABLES[0];

/// [`crc16_update`] one byte at a time over [`BYTE_TABLE`] alone.
fn bytewise(crc: u16, data: &[u8]) -> u16 {
    data.iter().fold(crc, |crc, &b| {
        (crc << 8) ^ BYTE_TABLE[usize::from((crc >> 8) as u8 ^ b)]
    })
}

/// The CRC of SDO block transfer over `data`: CRC-16/CCITT, polynomial
/// 1021h, initial value 0 (CiA 301 section 7.2.4.3, SDO block download /
/// upload).
///
/// ```
/// use canopen_codec::sdo::crc16;
/// assert_eq!(crc16(b"123456789"), 0x31C3);
/// assert_eq!(crc16(b""), 0);
/// ```
#[must_use]
pub fn crc16(data: &[u8]) -> u16 {
    crc16_update(0, data)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bit-at-a-time reference, straight from the polynomial.
    fn reference(data: &[u8]) -> u16 {
        let mut crc = 0u16;
        for &b in data {
            crc ^= u16::from(b) << 8;
            for _ in 0..8 {
                crc = if crc & 0x8000 != 0 {
                    (crc << 1) ^ 0x1021
                } else {
                    crc << 1
                };
            }
        }
        crc
    }

    #[test]
    fn known_vectors() {
        // CRC-16/XMODEM check value.
        assert_eq!(crc16(b"123456789"), 0x31C3);
        assert_eq!(crc16(&[]), 0x0000);
        assert_eq!(crc16(&[0x00]), 0x0000);
        assert_eq!(crc16(b"A"), 0x58E5);
        // python-canopen's block download test value (30 bytes).
        assert_eq!(crc16(b"A really really long string..."), 0x6945);
        // python-canopen's block upload test value (26 bytes).
        assert_eq!(crc16(b"Tiny Node - Mega Domains !"), 0xE140);
    }

    #[test]
    fn table_matches_reference_and_pieces_compose() {
        let data: [u8; 300] = core::array::from_fn(|i| (i * 37 + 11) as u8);
        assert_eq!(crc16(&data), reference(&data));
        for split in [0, 1, 7, 150, 299, 300] {
            let (a, b) = data.split_at(split);
            assert_eq!(crc16_update(crc16(a), b), crc16(&data));
        }
        // Every length of every remainder path, from a non-zero register.
        for len in 0..=40 {
            let piece = &data[3..3 + len];
            let mut crc = 0x1D0F;
            for &b in piece {
                crc = crc16_update(crc, &[b]);
            }
            assert_eq!(crc16_update(0x1D0F, piece), crc, "len {len}");
            assert_eq!(crc16(piece), reference(piece), "len {len}");
        }
    }

    #[test]
    fn both_table_paths_agree_with_the_reference() {
        let data: [u8; 300] = core::array::from_fn(|i| (i * 53 + 7) as u8);
        for len in [0, 1, 2, 7, 8, 9, 16, 63, 300] {
            let piece = &data[..len];
            for start in [0, 0x1D0F, 0xFFFF] {
                assert_eq!(sliced(start, piece), bytewise(start, piece), "len {len}");
            }
            assert_eq!(bytewise(0, piece), reference(piece), "len {len}");
        }
        assert_eq!(bytewise(0, b"123456789"), 0x31C3);
    }
}
