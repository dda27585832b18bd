//! Fuzz PDO unpacking (and re-packing) on arbitrary mappings and payloads.
//!
//! Input: up to 9 mapping entries as `(index, sub, bits)` (bits taken
//! modulo 72, so 0 and 65..=71 occur and totals above 64 are common: those
//! mappings must be rejected by `PdoMapping::new`), then a payload of any
//! length.
//!
//! Invariants: nothing panics; a payload shorter than `byte_len()` is
//! `TooShort` (8210h) and a longer one is flagged (8220h); whatever unpacks
//! re-packs with `pack_raw` to the payload's first `byte_len()` bytes with
//! the bits past `total_bits()` zeroed; the typed `pack` of the unsigned
//! views gives the same bytes with dummy fields zeroed; every typed view
//! agrees with the raw bits.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::pdo::{FieldKind, MappingEntry, PdoMapping, UnpackError, Value};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    entries: Vec<(u16, u8, u8)>,
    payload: Vec<u8>,
}

/// Bit `n` of a little-endian payload (0 past its end).
fn bit(payload: &[u8], n: u32) -> u8 {
    payload
        .get((n / 8) as usize)
        .map_or(0, |b| b >> (n % 8) & 1)
}

fuzz_target!(|input: Input| {
    let entries: Vec<MappingEntry> = input
        .entries
        .iter()
        .take(9)
        .map(|&(index, sub, bits)| MappingEntry::new(index, sub, bits % 72))
        .collect();
    let Ok(m) = PdoMapping::new(&entries) else {
        return;
    };
    assert!(m.len() <= 8 && m.total_bits() <= 64);
    let payload = &input.payload[..];
    let need = m.byte_len();

    let u = match m.unpack(payload) {
        Err(e) => {
            assert!(payload.len() < need);
            assert_eq!(
                e,
                UnpackError::TooShort {
                    need,
                    got: payload.len()
                }
            );
            assert_eq!(e.emcy_code().0, 0x8210);
            return;
        }
        Ok(u) => u,
    };
    assert!(payload.len() >= need);
    assert_eq!(u.longer_than_mapping(), payload.len() > need);
    assert_eq!(u.emcy_code().is_some(), payload.len() > need);
    assert_eq!(u.len(), m.len());

    // Raw re-pack: the payload's prefix, bits past the mapping zeroed.
    let again = m
        .pack_raw(u.raws())
        .expect("unpacked raws fit their fields");
    assert_eq!(again.len(), need);
    for n in 0..(8 * need as u32) {
        let want = if n < m.total_bits() {
            bit(payload, n)
        } else {
            0
        };
        assert_eq!(bit(again.as_slice(), n), want, "bit {n}");
    }

    // Typed re-pack: the same, with dummy fields zero.
    let mut values = Vec::new();
    let mut cleaned = Vec::new();
    for (i, (e, raw)) in u.iter().enumerate() {
        let signed = u.signed(i).expect("entry exists");
        assert_eq!(signed as u64 & low_mask(e.bits), raw);
        assert_eq!(u.value(i, FieldKind::Signed), Ok(Value::Signed(signed)));
        assert_eq!(u.boolean(i), Some(raw != 0));
        match e.bits {
            32 => assert!(u.value(i, FieldKind::Real32).is_ok()),
            64 => assert!(u.value(i, FieldKind::Real64).is_ok()),
            _ => assert!(u.value(i, FieldKind::Real32).is_err()),
        }
        // Alternate the views so both conversions are exercised.
        values.push(if i % 2 == 0 {
            Value::Unsigned(raw)
        } else {
            Value::Signed(signed)
        });
        cleaned.push(if e.is_dummy() { 0 } else { raw });
    }
    assert!(u.value(m.len(), FieldKind::Unsigned).is_err());
    let typed = m.pack(&values).expect("unpacked values fit their fields");
    assert_eq!(typed, m.pack_raw(&cleaned).expect("fits"));
});

fn low_mask(bits: u8) -> u64 {
    if bits >= 64 {
        u64::MAX
    } else {
        (1 << bits) - 1
    }
}
