//! Property tests for PDO packing and unpacking, through the public API
//! only: random mappings (1..=64-bit fields, at most 64 bits and 8 entries,
//! dummy entries included) and random values or payloads, checked against a
//! naive bit-by-bit reference written here.

use canopen_codec::pdo::{FieldKind, MappingEntry, PdoMapping, UnpackError, Value};
use proptest::prelude::*;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 1024,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::Direct(
                "tests/proptest-regressions/pdo_props.txt",
            ),
        )),
        ..ProptestConfig::default()
    }
}

/// One mapped field: its entry and the kind its value is given as.
#[derive(Debug, Clone, Copy)]
struct Field {
    entry: MappingEntry,
    kind: FieldKind,
}

/// Entries of random widths (small ones likelier, so that up to 8 fit),
/// cut to a random budget of at most 64 bits; some are dummy entries
/// (0005h UNSIGNED8 index with any width: `PdoMapping::new` does not check
/// dummy widths), some are 32 or 64 bits read as REALs.
fn fields() -> impl Strategy<Value = Vec<Field>> {
    let width = prop_oneof![1u8..=8, 1u8..=16, 1u8..=64, Just(32u8), Just(64u8)];
    let index = prop_oneof![6 => 0x2000u16..=0x2FFF, 1 => Just(0x0005u16)];
    let field = (width, index, any::<u8>(), 0u8..5);
    (
        prop::collection::vec(field, 0..=8),
        prop_oneof![Just(64u32), 1u32..=64],
    )
        .prop_map(|(raw, budget)| {
            let mut out = Vec::new();
            let mut total = 0u32;
            for (bits, index, sub, kind) in raw {
                let bits = u32::from(bits).min(budget - total);
                if bits == 0 {
                    break;
                }
                total += bits;
                let bits = bits as u8;
                let kind = match kind {
                    0 => FieldKind::Unsigned,
                    1 => FieldKind::Signed,
                    2 => FieldKind::Boolean,
                    _ if bits == 32 => FieldKind::Real32,
                    _ if bits == 64 => FieldKind::Real64,
                    3 => FieldKind::Signed,
                    _ => FieldKind::Unsigned,
                };
                out.push(Field {
                    entry: MappingEntry::new(index, sub, bits),
                    kind,
                });
            }
            out
        })
}

fn mapping_of(fields: &[Field]) -> PdoMapping {
    let entries: Vec<MappingEntry> = fields.iter().map(|f| f.entry).collect();
    PdoMapping::new(&entries).expect("strategy builds valid mappings")
}

/// A seed for a value, biased to the edges (0, all ones, one bit, the sign
/// bit of the field after masking).
fn seed() -> impl Strategy<Value = u64> {
    prop_oneof![
        3 => any::<u64>(),
        1 => Just(0u64),
        1 => Just(u64::MAX),
        1 => (0u32..64).prop_map(|b| 1u64 << b),
        1 => (0u32..64).prop_map(|b| !(1u64 << b)),
    ]
}

// ---------------------------------------------------------------------------
// The naive reference: one bit at a time.

/// Bit `n` of a little-endian payload (0 past its end).
fn bit(payload: &[u8], n: u32) -> u64 {
    payload
        .get((n / 8) as usize)
        .map_or(0, |b| u64::from(b >> (n % 8) & 1))
}

/// Every field's raw bits, bit by bit, and the payload length needed.
fn reference_unpack(entries: &[MappingEntry], payload: &[u8]) -> (Vec<u64>, usize) {
    let mut at = 0u32;
    let mut raws = Vec::new();
    for e in entries {
        let mut raw = 0u64;
        for k in 0..u32::from(e.bits) {
            raw |= bit(payload, at + k) << k;
        }
        raws.push(raw);
        at += u32::from(e.bits);
    }
    (raws, (at as usize).div_ceil(8))
}

/// Two's complement of the low `bits` bits, by copying the top bit upward.
fn reference_signed(raw: u64, bits: u8) -> i64 {
    let mut v = raw;
    if raw >> (bits - 1) & 1 == 1 {
        for k in bits..64 {
            v |= 1 << k;
        }
    }
    v as i64
}

/// The low `bits` bits of `seed`, one bit at a time.
fn low_bits(seed: u64, bits: u8) -> u64 {
    (0..bits).fold(0, |acc, k| acc | (seed & (1 << k)))
}

/// The value a field of kind `kind` and `bits` bits gets from `seed`, and
/// its raw bits.
fn value_of(kind: FieldKind, bits: u8, seed: u64) -> (Value, u64) {
    let raw = low_bits(seed, bits);
    match kind {
        FieldKind::Unsigned => (Value::Unsigned(raw), raw),
        FieldKind::Signed => (Value::Signed(reference_signed(raw, bits)), raw),
        FieldKind::Boolean => (Value::Boolean(seed & 1 == 1), seed & 1),
        FieldKind::Real32 => (Value::Real32(f32::from_bits(raw as u32)), raw),
        FieldKind::Real64 => (Value::Real64(f64::from_bits(raw)), raw),
        _ => unreachable!("no other kind is generated"),
    }
}

/// Equality that compares REALs by their bits (NaN payloads included).
fn same(a: Value, b: Value) -> bool {
    match (a, b) {
        (Value::Real32(x), Value::Real32(y)) => x.to_bits() == y.to_bits(),
        (Value::Real64(x), Value::Real64(y)) => x.to_bits() == y.to_bits(),
        _ => a == b,
    }
}

proptest! {
    #![proptest_config(config())]

    /// pack then unpack gives every value back (dummy fields read as zero),
    /// the payload has `byte_len()` bytes, and it matches the reference.
    #[test]
    fn pack_unpack_is_identity(
        fields in fields(),
        seeds in prop::collection::vec(seed(), 8),
    ) {
        let m = mapping_of(&fields);
        let (values, raws): (Vec<Value>, Vec<u64>) = fields
            .iter()
            .zip(&seeds)
            .map(|(f, &s)| value_of(f.kind, f.entry.bits, s))
            .unzip();
        let p = m.pack(&values).unwrap();
        prop_assert_eq!(p.len(), m.byte_len());
        let (reference, need) = reference_unpack(m.entries(), p.as_slice());
        prop_assert_eq!(need, p.len());
        // Bits past the mapping are zero.
        for n in m.total_bits()..(8 * p.len() as u32) {
            prop_assert_eq!(bit(p.as_slice(), n), 0);
        }

        let u = m.unpack(p.as_slice()).unwrap();
        prop_assert!(!u.longer_than_mapping());
        prop_assert_eq!(u.raws(), &reference[..]);
        for (i, (f, (v, raw))) in fields.iter().zip(values.iter().zip(&raws)).enumerate() {
            if f.entry.is_dummy() {
                prop_assert_eq!(u.raw(i), Some(0));
                continue;
            }
            prop_assert_eq!(u.raw(i), Some(*raw));
            let back = u.value(i, f.kind).unwrap();
            prop_assert!(same(back, *v), "entry {}: {:?} != {:?}", i, back, v);
        }

        // The raw variant gives the same payload for the same bits.
        let raw_in: Vec<u64> = fields
            .iter()
            .zip(&raws)
            .map(|(f, &r)| if f.entry.is_dummy() { 0 } else { r })
            .collect();
        prop_assert_eq!(m.pack_raw(&raw_in).unwrap(), p);
    }

    /// A value one past its field's range never packs.
    #[test]
    fn too_wide_never_packs(fields in fields(), pick in any::<prop::sample::Index>()) {
        prop_assume!(!fields.is_empty());
        let i = pick.index(fields.len());
        let bits = fields[i].entry.bits;
        prop_assume!(bits < 64 && !fields[i].entry.is_dummy());
        let m = mapping_of(&fields);
        let mut values: Vec<Value> = fields.iter().map(|_| Value::Boolean(false)).collect();
        for v in [
            Value::Unsigned(1 << bits),
            Value::Signed(1 << (bits - 1)),
            Value::Signed(-(1 << (bits - 1)) - 1),
        ] {
            values[i] = v;
            let err = m.pack(&values).unwrap_err();
            prop_assert_eq!(err, canopen_codec::pdo::PackError::ValueTooWide { entry: i, bits });
        }
    }

    /// unpack on any payload (0..=10 bytes) never panics and agrees with
    /// the reference: too short is 8210h, longer is decoded and flagged,
    /// signed reads sign-extend, and re-packing the raw bits gives the
    /// payload's first `byte_len()` bytes with the bits past the mapping
    /// zero.
    #[test]
    fn unpack_agrees_with_reference(
        fields in fields(),
        payload in prop::collection::vec(any::<u8>(), 0..=10),
    ) {
        let m = mapping_of(&fields);
        let (reference, need) = reference_unpack(m.entries(), &payload);
        prop_assert_eq!(need, m.byte_len());
        match m.unpack(&payload) {
            Err(e) => {
                prop_assert!(payload.len() < need);
                prop_assert_eq!(e, UnpackError::TooShort { need, got: payload.len() });
                prop_assert_eq!(e.emcy_code().0, 0x8210);
            }
            Ok(u) => {
                prop_assert!(payload.len() >= need);
                prop_assert_eq!(u.longer_than_mapping(), payload.len() > need);
                prop_assert_eq!(u.emcy_code().map(|c| c.0), (payload.len() > need).then_some(0x8220));
                prop_assert_eq!(u.raws(), &reference[..]);
                prop_assert_eq!(u.len(), fields.len());
                for (i, (e, raw)) in u.iter().enumerate() {
                    prop_assert_eq!(e, fields[i].entry);
                    prop_assert_eq!(raw, reference[i]);
                    prop_assert_eq!(u.signed(i), Some(reference_signed(raw, e.bits)));
                    prop_assert_eq!(u.boolean(i), Some(raw != 0));
                }
                prop_assert_eq!(u.raw(fields.len()), None);

                let again = m.pack_raw(u.raws()).unwrap();
                prop_assert_eq!(again.len(), need);
                for n in 0..(8 * need as u32) {
                    let want = if n < m.total_bits() { bit(&payload, n) } else { 0 };
                    prop_assert_eq!(bit(again.as_slice(), n), want, "bit {}", n);
                }
            }
        }
    }
}
