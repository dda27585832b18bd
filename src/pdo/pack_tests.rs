//! Tests of PDO packing and unpacking: vectors P1 and P2 (from
//! python-canopen's test suite, see below), extremes of every width, length
//! rules, dummy and padding entries. (The Delta-Q charger's TPDO 3 and its
//! padding object are tested in the deltaq module.)

use super::*;
use crate::pdo::catalogue_test_support::mapping as entries;
use crate::pdo::{extract_bits, insert_bits};
use std::string::ToString;

fn mapping(widths: &[u8]) -> PdoMapping {
    let mut entries = [MappingEntry::default(); MAX_ENTRIES];
    for (i, (e, &bits)) in entries.iter_mut().zip(widths).enumerate() {
        *e = MappingEntry::new(0x2000, i as u8 + 1, bits);
    }
    PdoMapping::new(&entries[..widths.len()]).unwrap()
}

/// P1 (python-canopen test_pdo_map_bit_mapping, TPDO1): I16=-3, U8/4=0xF,
/// I8/4=-2, I32=0x01020304, BOOL=0, BOOL=1 (58 bits).
const P1: [u8; 8] = [0xFD, 0xFF, 0xEF, 0x04, 0x03, 0x02, 0x01, 0x02];
const P1_WIDTHS: [u8; 6] = [16, 4, 4, 32, 1, 1];

/// P2 (python-canopen PR #454): U8@0/4=3, I8@4/8=-2, U32@12/24=0x987654,
/// U16@36/12=0x321, I16@48/3=-1, I32@51/13=-1071 (64 bits).
const P2: [u8; 8] = [0xE3, 0x4F, 0x65, 0x87, 0x19, 0x32, 0x8F, 0xDE];
const P2_WIDTHS: [u8; 6] = [4, 8, 24, 12, 3, 13];

#[test]
fn p1_pack() {
    let m = mapping(&P1_WIDTHS);
    assert_eq!(m.total_bits(), 58);
    let values = [
        Value::Signed(-3),
        Value::Unsigned(0xF),
        Value::Signed(-2),
        Value::Signed(0x0102_0304),
        Value::Boolean(false),
        Value::Boolean(true),
    ];
    assert_eq!(m.pack(&values).unwrap().as_slice(), P1);
    let raws = [0xFFFD, 0xF, 0xE, 0x0102_0304, 0, 1];
    assert_eq!(m.pack_raw(&raws).unwrap().as_slice(), P1);
}

#[test]
fn p1_unpack() {
    let m = mapping(&P1_WIDTHS);
    let u = m.unpack(&P1).unwrap();
    assert_eq!(u.raws(), [0xFFFD, 0xF, 0xE, 0x0102_0304, 0, 1]);
    assert_eq!(u.signed(0), Some(-3));
    assert_eq!(u.unsigned(1), Some(0xF));
    assert_eq!(u.signed(2), Some(-2));
    assert_eq!(u.signed(3), Some(0x0102_0304));
    assert_eq!(u.boolean(4), Some(false));
    assert_eq!(u.boolean(5), Some(true));
    assert_eq!(u.value(0, FieldKind::Signed), Ok(Value::Signed(-3)));
    assert_eq!(u.value(5, FieldKind::Boolean), Ok(Value::Boolean(true)));
    assert!(!u.longer_than_mapping());
    assert_eq!(u.emcy_code(), None);
}

#[test]
fn p2_pack() {
    let m = mapping(&P2_WIDTHS);
    assert_eq!(m.total_bits(), 64);
    let values = [
        Value::Unsigned(3),
        Value::Signed(-2),
        Value::Unsigned(0x98_7654),
        Value::Unsigned(0x321),
        Value::Signed(-1),
        Value::Signed(-1071),
    ];
    assert_eq!(m.pack(&values).unwrap().as_slice(), P2);
}

#[test]
fn p2_unpack() {
    let m = mapping(&P2_WIDTHS);
    let u = m.unpack(&P2).unwrap();
    assert_eq!(u.raw(0), Some(3));
    assert_eq!(u.signed(1), Some(-2));
    assert_eq!(u.raw(1), Some(0xFE));
    assert_eq!(u.raw(2), Some(0x98_7654));
    assert_eq!(u.raw(3), Some(0x321));
    assert_eq!(u.signed(4), Some(-1));
    assert_eq!(u.raw(4), Some(0b111));
    assert_eq!(u.signed(5), Some(-1071));
    assert_eq!(u.value(5, FieldKind::Signed), Ok(Value::Signed(-1071)));
    assert_eq!(m.pack_raw(u.raws()).unwrap().as_slice(), P2);
}

#[test]
fn extremes_of_every_width_round_trip() {
    for bits in 1..=64u8 {
        let min = if bits == 64 {
            i64::MIN
        } else {
            -(1i64 << (bits - 1))
        };
        let max = if bits == 64 {
            i64::MAX
        } else {
            (1i64 << (bits - 1)) - 1
        };
        let umax = low_mask(bits);
        // Alone at bit 0, and after a 1-bit field so it is not aligned.
        let mut layouts = vec![mapping(&[bits])];
        if bits < 64 {
            layouts.push(mapping(&[1, bits]));
        }
        for m in &layouts {
            let last = m.len() - 1;
            let mut values = [Value::Boolean(true); 2];
            for v in [Value::Signed(min), Value::Signed(max), Value::Signed(0)] {
                values[last] = v;
                let p = m.pack(&values[..m.len()]).unwrap();
                assert_eq!(p.len(), m.byte_len());
                let u = m.unpack(p.as_slice()).unwrap();
                assert_eq!(u.value(last, FieldKind::Signed), Ok(v), "{bits} bits");
            }
            for v in [Value::Unsigned(umax), Value::Unsigned(0)] {
                values[last] = v;
                let p = m.pack(&values[..m.len()]).unwrap();
                let u = m.unpack(p.as_slice()).unwrap();
                assert_eq!(u.value(last, FieldKind::Unsigned), Ok(v), "{bits} bits");
            }
            if bits < 64 {
                let wide = PackError::ValueTooWide { entry: last, bits };
                for v in [
                    Value::Signed(min - 1),
                    Value::Signed(max + 1),
                    Value::Unsigned(umax + 1),
                ] {
                    values[last] = v;
                    assert_eq!(m.pack(&values[..m.len()]), Err(wide), "{bits} bits");
                }
                let mut raws = [1u64; 2];
                raws[last] = umax + 1;
                assert_eq!(m.pack_raw(&raws[..m.len()]), Err(wide));
            }
        }
    }
}

#[test]
fn most_negative_bit_patterns() {
    // The most negative value is the sign bit alone.
    let m = mapping(&[3, 5, 8, 16, 32]);
    let values = [-4, -16, -128, -32768, i64::from(i32::MIN)].map(Value::Signed);
    let p = m.pack(&values).unwrap();
    let u = m.unpack(p.as_slice()).unwrap();
    assert_eq!(u.raws(), [0b100, 0b1_0000, 0x80, 0x8000, 0x8000_0000]);
    for (i, v) in values.iter().enumerate() {
        assert_eq!(u.value(i, FieldKind::Signed), Ok(*v));
    }
}

#[test]
fn short_payload_of_a_bit_mapping() {
    // 58 bits need 8 bytes; 7 is not enough even though 56 of them fit.
    let m = mapping(&P1_WIDTHS);
    assert_eq!(
        m.unpack(&P1[..7]),
        Err(UnpackError::TooShort { need: 8, got: 7 })
    );
    // A 9-bit mapping needs 2 bytes.
    let m = mapping(&[9]);
    assert_eq!(
        m.unpack(&[0xFF]),
        Err(UnpackError::TooShort { need: 2, got: 1 })
    );
    assert_eq!(m.unpack(&[0xFF, 0xFF]).unwrap().raw(0), Some(0x1FF));
}

#[test]
fn longer_than_eight_bytes_is_decoded_and_flagged() {
    let m = mapping(&[8, 8]);
    let u = m.unpack(&[1, 2, 3, 4, 5, 6, 7, 8, 9, 10]).unwrap();
    assert_eq!(u.raws(), [1, 2]);
    assert!(u.longer_than_mapping());
}

#[test]
fn dummy_entries() {
    // UNSIGNED8 dummy (0005h/8) between two fields.
    let m = entries(&[(0x2000, 1, 4), (0x0005, 0, 8), (0x2000, 2, 16)]);
    // The dummy's value is ignored, whatever it is.
    for dummy in [
        Value::Unsigned(0xAB),
        Value::Unsigned(u64::MAX),
        Value::Real64(1.5),
    ] {
        let p = m
            .pack(&[Value::Unsigned(0x9), dummy, Value::Unsigned(0x1234)])
            .unwrap();
        assert_eq!(p.as_slice(), [0x09, 0x40, 0x23, 0x01]);
    }
    // Received dummy bits are skipped by the fields after it, and kept raw.
    let u = m.unpack(&[0xF9, 0x4F, 0x23, 0x01]).unwrap();
    assert_eq!(u.raws(), [0x9, 0xFF, 0x1234]);
    // pack_raw is verbatim, so it gives the payload back.
    assert_eq!(
        m.pack_raw(u.raws()).unwrap().as_slice(),
        [0xF9, 0x4F, 0x23, 0x01]
    );
}

#[test]
fn field_spilling_across_bytes() {
    // A 12-bit field at bit 6 covers bytes 0, 1 and 2.
    let m = mapping(&[6, 12, 6]);
    let p = m
        .pack(&[
            Value::Unsigned(0),
            Value::Unsigned(0xFFF),
            Value::Unsigned(0),
        ])
        .unwrap();
    assert_eq!(p.as_slice(), [0xC0, 0xFF, 0x03]);
    let u = m.unpack(&[0x40, 0x8D, 0x02]).unwrap();
    // bits 6..18 of 0x028D40 = 0xA35.
    assert_eq!(u.raws(), [0, 0xA35, 0]);
    assert_eq!(u.signed(1), Some(0xA35 - 0x1000));
    // A 63-bit field after one bit: spans all 8 bytes.
    let m = mapping(&[1, 63]);
    let p = m
        .pack(&[Value::Boolean(false), Value::Signed(-(1 << 62))])
        .unwrap();
    assert_eq!(p.as_slice(), [0, 0, 0, 0, 0, 0, 0, 0x80]);
    assert_eq!(m.unpack(p.as_slice()).unwrap().signed(1), Some(-(1 << 62)));
}

#[test]
fn reals() {
    let m = mapping(&[32, 32]);
    let p = m.pack(&[Value::Real32(1.5), Value::Real32(-0.0)]).unwrap();
    assert_eq!(p.as_slice(), [0, 0, 0xC0, 0x3F, 0, 0, 0, 0x80]);
    let u = m.unpack(p.as_slice()).unwrap();
    assert_eq!(u.value(0, FieldKind::Real32), Ok(Value::Real32(1.5)));
    assert_eq!(
        u.value(1, FieldKind::Real64),
        Err(FieldError::KindWidth {
            entry: 1,
            kind: FieldKind::Real64,
            bits: 32
        })
    );
    let m = mapping(&[64]);
    let p = m.pack(&[Value::Real64(-2.25)]).unwrap();
    assert_eq!(p.as_slice(), (-2.25f64).to_le_bytes());
    let u = m.unpack(p.as_slice()).unwrap();
    assert_eq!(u.value(0, FieldKind::Real64), Ok(Value::Real64(-2.25)));
    assert!(u.value(0, FieldKind::Real32).is_err());
    // A REAL in a field of the wrong width does not pack.
    assert_eq!(
        mapping(&[16]).pack(&[Value::Real32(1.0)]),
        Err(PackError::KindWidth {
            entry: 0,
            kind: FieldKind::Real32,
            bits: 16
        })
    );
    assert_eq!(
        mapping(&[32]).pack(&[Value::Real64(1.0)]),
        Err(PackError::KindWidth {
            entry: 0,
            kind: FieldKind::Real64,
            bits: 32
        })
    );
}

#[test]
fn booleans_and_kinds() {
    let m = mapping(&[1, 8]);
    let p = m
        .pack(&[Value::Boolean(true), Value::Boolean(true)])
        .unwrap();
    assert_eq!(p.as_slice(), [0x03, 0x00]);
    let u = m.unpack(&[0xFE, 0x01]).unwrap();
    assert_eq!(u.boolean(0), Some(false));
    assert_eq!(u.boolean(1), Some(true)); // any set bit
    assert_eq!(u.raw(1), Some(0xFF)); // kept raw
    for kind in [
        FieldKind::Unsigned,
        FieldKind::Signed,
        FieldKind::Boolean,
        FieldKind::Real32,
        FieldKind::Real64,
    ] {
        assert_eq!(kind.fits_width(32), kind != FieldKind::Real64);
        assert_eq!(kind.fits_width(64), kind != FieldKind::Real32);
    }
    assert_eq!(Value::Real32(0.0).kind(), FieldKind::Real32);
}

#[test]
fn counts_and_positions() {
    let m = mapping(&[8, 8]);
    assert_eq!(
        m.pack(&[Value::Unsigned(1)]),
        Err(PackError::CountMismatch {
            entries: 2,
            values: 1
        })
    );
    assert_eq!(
        m.pack_raw(&[1, 2, 3]),
        Err(PackError::CountMismatch {
            entries: 2,
            values: 3
        })
    );
    let u = m.unpack(&[1, 2]).unwrap();
    assert_eq!((u.len(), u.is_empty()), (2, false));
    assert_eq!(u.mapping(), &m);
    assert_eq!(u.raw(2), None);
    assert_eq!(u.signed(2), None);
    assert_eq!(u.boolean(8), None);
    assert_eq!(
        u.value(2, FieldKind::Unsigned),
        Err(FieldError::NoSuchEntry { entry: 2, count: 2 })
    );
}

#[test]
fn empty_mapping() {
    let m = PdoMapping::EMPTY;
    assert!(m.pack(&[]).unwrap().is_empty());
    let u = m.unpack(&[]).unwrap();
    assert!(u.is_empty() && u.raws().is_empty());
    assert!(m.unpack(&[0]).unwrap().longer_than_mapping());
}

#[test]
fn error_messages() {
    assert_eq!(
        PackError::ValueTooWide { entry: 2, bits: 4 }.to_string(),
        "value of entry 2 does not fit in 4 bits"
    );
    assert_eq!(
        PackError::KindWidth {
            entry: 0,
            kind: FieldKind::Real32,
            bits: 16
        }
        .to_string(),
        "REAL32 value for entry 0 of 16 bits"
    );
    assert_eq!(
        UnpackError::TooShort { need: 6, got: 4 }.to_string(),
        "PDO of 4 bytes, the mapping needs 6"
    );
    assert_eq!(FieldKind::Signed.to_string(), "INTEGER");
}

/// The running shift in `unpack` and the OR in `pack` give the same bits as
/// the mapping module's `extract_bits` / `insert_bits` at each offset.
#[test]
fn agrees_with_mapping_helpers() {
    for widths in [
        &P1_WIDTHS[..],
        &P2_WIDTHS,
        &[64],
        &[1, 63],
        &[7, 9, 13, 3, 32],
    ] {
        let m = mapping(widths);
        for payload in [P1, P2, [0xA5; 8], [0xFF; 8]] {
            let u = m.unpack(&payload).unwrap();
            let mut word = [0u8; 8];
            for ((raw, offset), e) in u.raws().iter().zip(m.offsets()).zip(m.entries()) {
                let bits = u32::from(e.bits);
                assert_eq!(*raw, extract_bits(&payload, offset, bits));
                insert_bits(&mut word, offset, bits, *raw);
            }
            let p = m.pack_raw(u.raws()).unwrap();
            assert_eq!(p.as_slice(), &word[..m.byte_len()]);
        }
    }
}

#[test]
fn le_word_of_every_length_is_the_zero_padded_word() {
    let bytes = [0x11u8, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x99];
    for n in 0..=bytes.len() {
        let mut padded = [0u8; 8];
        for (d, s) in padded.iter_mut().zip(&bytes[..n]) {
            *d = *s;
        }
        assert_eq!(
            super::le_word(&bytes[..n]),
            u64::from_le_bytes(padded),
            "{n} bytes"
        );
    }
}

#[test]
fn slots_past_the_count_are_empty() {
    for count in 0..=8 {
        let m = mapping(&[8, 8, 8, 8, 8, 8, 8, 8][..count]);
        assert!(
            m.slots()[count..].iter().all(|e| e.bits == 0),
            "{count} entries"
        );
        let mut raw = [0u32; MAX_ENTRIES];
        for (r, e) in raw.iter_mut().zip(m.entries()) {
            *r = e.to_u32();
        }
        let back = PdoMapping::from_u32s(&raw[..count]).unwrap();
        assert!(back.slots()[count..].iter().all(|e| e.bits == 0));
    }
}
