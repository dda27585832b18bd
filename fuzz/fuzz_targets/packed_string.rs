//! Fuzz the CiA 418 packed-string codec (6030h, 6031h, 6040h, 6041h).
//!
//! Input: byte 0 selects the object (bits 0-1) and the element count
//! (bits 2-7, so 0..=63, mostly invalid); the rest is read twice, as
//! little-endian Unsigned32 elements and as a string.
//!
//! Invariants: decoding and encoding never panic; whatever decodes keeps its
//! count and elements, has a valid text, and re-encodes with the same count to
//! exactly the same elements (the minimal encoding is a prefix, the rest zero);
//! whatever encodes decodes back to the same value and text.
#![no_main]

use canopen_codec::cia418::{PackedString, PackedStringObject};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&selector, rest)) = data.split_first() else {
        return;
    };
    let object = PackedStringObject::ALL[usize::from(selector & 3)];
    let count = selector >> 2;

    // As elements + count.
    let words: Vec<u32> = rest
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    if let Ok(p) = PackedString::decode(object, count, &words) {
        assert_eq!(p.object(), object);
        assert_eq!(p.count(), count);
        assert_eq!(p.words(), &words[..usize::from(count)]);
        let text = p.text();
        assert!(text.len() <= object.max_chars());
        assert!(text.as_bytes().iter().all(|&b| (0x01..0x80).contains(&b)));
        assert_eq!(
            PackedString::encode_with_count(object, text.as_str(), count),
            Ok(p)
        );
        let minimal = PackedString::encode(object, text.as_str()).expect("decoded text encodes");
        let n = minimal.words().len();
        assert!(n <= p.words().len());
        assert_eq!(minimal.words(), &p.words()[..n]);
        assert!(p.words()[n..].iter().all(|&w| w == 0));
    }

    // As a string.
    if let Ok(s) = core::str::from_utf8(rest) {
        if let Ok(p) = PackedString::encode(object, s) {
            assert_eq!(p.text().as_str(), s);
            assert_eq!(PackedString::decode(object, p.count(), p.words()), Ok(p));
        }
    }
});
