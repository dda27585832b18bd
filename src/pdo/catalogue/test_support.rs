//! Checks every catalogue's tests share: rows in words, a table's
//! consistency, short and long frames, and totality. The mechanism's own
//! tests and each profile's catalogue tests call them with their rows.

use std::string::ToString;
use std::vec::Vec;

use proptest::prelude::*;

use super::{Catalogue, FieldValue, Fixed, MappingEntry, ObjectRow, PdoMapping};

/// One catalogue row read in words: `(mapping entry, raw, words)`, the
/// entry as a PDO mapping parameter holds it (CiA 301, 7.5.2.36: index,
/// sub-index, length in bits, so 6020_0108h is 6020h:01, 8 bits).
pub(crate) type WordsCase = (u32, u64, &'static str);

/// Every case reads as its words in `cat`.
pub(crate) fn assert_words(cat: Catalogue, cases: &[WordsCase]) {
    for &(entry, raw, words) in cases {
        let field = cat.interpret(MappingEntry::from_u32(entry), raw);
        assert_eq!(field.to_string(), words, "{entry:08X}h raw {raw:X}h");
    }
}

/// Every case of a vector file reads as its words in `cat`. A case is a
/// line `IIII:SS/BITS RAW WORDS` (index and sub-index in hex, the mapped
/// width in bits, the raw value in hex, then the words); `#` lines and
/// blank lines are comments. A file without a case, or a line that is not
/// one, fails the test.
pub(crate) fn assert_vectors(cat: Catalogue, vectors: &'static str) {
    let mut cases = 0;
    for line in vectors.lines() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (entry, rest) = line.split_once(' ').expect(line);
        let (raw, words) = rest.trim_start().split_once(' ').expect(line);
        let (mux, bits) = entry.split_once('/').expect(line);
        let (index, sub) = mux.split_once(':').expect(line);
        let index = u16::from_str_radix(index, 16).expect(line);
        let sub = u8::from_str_radix(sub, 16).expect(line);
        let bits: u8 = bits.parse().expect(line);
        let raw = u64::from_str_radix(raw, 16).expect(line);
        let entry = MappingEntry::new(index, sub, bits).to_u32();
        assert_words(cat, &[(entry, raw, words.trim_start())]);
        cases += 1;
    }
    assert!(cases > 0, "no case in the vector file");
}

/// A mapping of `(index, sub, bits)` entries.
pub(crate) fn mapping(entries: &[(u16, u8, u8)]) -> PdoMapping {
    let e: Vec<MappingEntry> = entries
        .iter()
        .map(|&(i, s, b)| MappingEntry::new(i, s, b))
        .collect();
    PdoMapping::new(&e).unwrap()
}

/// No row of `table` overlaps another, every width is a CiA 301 basic
/// type's (1 to 32 bits), and every index of `complete` has a row.
pub(crate) fn assert_table_consistent(table: &[ObjectRow], complete: &[u16]) {
    for (i, a) in table.iter().enumerate() {
        assert!(
            a.address.sub <= a.last_sub && (1..=32).contains(&a.bits()),
            "{a:?}"
        );
        for b in &table[i + 1..] {
            let overlap = a.address.index == b.address.index
                && a.address.sub <= b.last_sub
                && b.address.sub <= a.last_sub;
            assert!(!overlap, "{a:?} overlaps {b:?}");
        }
    }
    for &index in complete {
        assert!(
            table.iter().any(|e| e.address.index == index),
            "{index:04X}h"
        );
    }
}

/// A frame one byte short of `three` (16, 8 and 32 bits, the first a
/// signed 1/8 object): the first reads 0230h, the second 1, the third is
/// missing, in words `missing`; a frame two bytes longer than the one-byte
/// mapping `one`, in words `one_words`; and the empty mapping.
pub(crate) fn assert_short_and_long_frames(
    (cat, three, missing): (Catalogue, [(u16, u8, u8); 3], &str),
    (one_cat, one, one_words): (Catalogue, (u16, u8, u8), &str),
) {
    let fields = cat.decode(&mapping(&three), &[0x30, 0x02, 0x01, 0x00]);
    assert_eq!(fields.len(), 3);
    let s = fields.as_slice();
    assert_eq!(s[0].value.number(), Some(Fixed::new(0x230, 3)));
    assert_eq!(s[1].raw, 1);
    assert_eq!(s[2].value, FieldValue::Missing);
    assert_eq!(s[2].raw, 0);
    assert_eq!(s[2].to_string(), missing);
    assert_eq!(fields.unmapped_bytes(), 0);

    let fields = one_cat.decode(&mapping(&[one]), &[1, 2, 3]);
    assert_eq!(fields.unmapped_bytes(), 2);
    assert_eq!(fields.to_string(), one_words);

    let empty = one_cat.decode(&PdoMapping::EMPTY, &[1]);
    assert!(empty.is_empty());
    assert_eq!(empty.to_string(), "");
}

/// Any PDO a decoder may meet: up to 8 raw mapping entries, a payload of
/// up to 10 bytes (longer than any classic frame) and a display precision.
pub(crate) fn any_pdo() -> impl Strategy<Value = (Vec<u32>, Vec<u8>, Option<usize>)> {
    (
        proptest::collection::vec(any::<u32>(), 0..=8),
        proptest::collection::vec(any::<u8>(), 0..=10),
        proptest::option::of(0usize..25),
    )
}

/// Decoding is total and displays without panicking, in every catalogue of
/// `cats`, for any mapping the raw entries make and any payload.
pub(crate) fn assert_decode_total(
    cats: &[Catalogue],
    raw_entries: &[u32],
    payload: &[u8],
    precision: Option<usize>,
) -> Result<(), TestCaseError> {
    let Ok(m) = PdoMapping::from_u32s(raw_entries) else {
        return Ok(());
    };
    for cat in cats {
        let fields = cat.decode(&m, payload);
        prop_assert_eq!(fields.len(), m.len());
        let _ = match precision {
            Some(p) => format!("{fields:.p$}"),
            None => fields.to_string(),
        };
    }
    Ok(())
}
