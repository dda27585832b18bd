//! The CRC of SDO block transfer: CRC-16/CCITT with polynomial 1021h and
//! initial value 0 (also known as CRC-16/XMODEM), no reflection, no final
//! XOR, computed over all data bytes of the transfer (CiA 301 section
//! 7.2.4.3, SDO protocols: SDO block download / block upload, "CRC").

/// The CRC register after each byte value from a zero register (256
/// entries of polynomial 1021h, built at compile time): one lookup per data
/// byte.
const TABLE: [u16; 256] = msb_first_table(16, 0x1021);

/// The byte table of a CRC of `width` bits (9 to 16) with polynomial
/// `poly`, shifted most significant bit first with no reflection: entry
/// `i` is the register after the 8 bits of `i` entered a register of `i`
/// in its top 8 bits. One algorithm for the two CRCs of this crate: SDO
/// block transfer's CRC-16/CCITT (width 16, 1021h; CiA 301 section
/// 7.2.4.3) and the CRC-15 of a CAN frame that the log's bus load counts
/// the stuff bits over (width 15, 4599h; ISO 11898-1 section 10.4.2.6).
/// Evaluated at compile time.
pub(crate) const fn msb_first_table(width: u32, poly: u16) -> [u16; 256] {
    let top = 1u16 << (width - 1);
    let mask = u16::MAX >> (16 - width);
    let mut table = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut crc = (i as u16) << (width - 8);
        let mut bit = 0;
        while bit < 8 {
            crc = if crc & top != 0 {
                (crc << 1) ^ poly
            } else {
                crc << 1
            } & mask;
            bit += 1;
        }
        table[i] = crc;
        i += 1;
    }
    table
}

/// Continues a CRC-16/CCITT (polynomial 1021h) over `data`, starting from
/// `crc` (0 for a new transfer): feeding a value in pieces gives the same
/// CRC as feeding it whole (a block transfer feeds it 7 bytes a segment).
///
/// ```
/// use canopen_codec::sdo::{crc16, crc16_update};
/// assert_eq!(crc16_update(crc16_update(0, b"1234"), b"56789"), crc16(b"123456789"));
/// ```
#[must_use]
pub fn crc16_update(crc: u16, data: &[u8]) -> u16 {
    data.iter().fold(crc, |crc, &b| {
        (crc << 8) ^ TABLE[usize::from((crc >> 8) as u8 ^ b)]
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
}
