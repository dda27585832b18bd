//! Packed strings: the profile's example, limits, NUL handling, errors.

use super::*;

const SERIAL: PackedStringObject = PackedStringObject::BatterySerialNumber;

/// CiA 418 section 7.3.5: "BATTERY" packs to sub0 = 2, sub1 = 54544142h,
/// sub2 = 00595245h.
#[test]
fn battery_example() {
    let p = PackedString::encode(SERIAL, "BATTERY").unwrap();
    assert_eq!(p.count(), 2);
    assert_eq!(p.words(), &[0x5454_4142, 0x0059_5245]);
    assert_eq!(p.word(0), None);
    assert_eq!(p.word(1), Some(0x5454_4142));
    assert_eq!(p.word(2), Some(0x0059_5245));
    assert_eq!(p.word(3), None);
    // On the wire (SDO, little-endian): the characters in order.
    assert_eq!(p.word(1).unwrap().to_le_bytes(), *b"BATT");
    assert_eq!(p.word(2).unwrap().to_le_bytes(), [0x45, 0x52, 0x59, 0x00]);

    let back = PackedString::decode(SERIAL, 2, &[0x5454_4142, 0x0059_5245]).unwrap();
    assert_eq!(back, p);
    assert_eq!(back.text().as_str(), "BATTERY");
    assert_eq!(back.text().len(), 7);
}

#[test]
fn object_limits() {
    let rows: [(PackedStringObject, u16, usize, u8); 4] = [
        (PackedStringObject::BatterySerialNumber, 0x6030, 10, 3),
        (PackedStringObject::BatteryId, 0x6031, 20, 5),
        (PackedStringObject::VehicleSerialNumber, 0x6040, 20, 5),
        (PackedStringObject::VehicleId, 0x6041, 20, 5),
    ];
    for (object, index, chars, elements) in rows {
        assert_eq!(object.index(), index);
        assert_eq!(object.max_chars(), chars);
        assert_eq!(object.max_elements(), elements);
        assert_eq!(PackedStringObject::from_index(index), Some(object));
    }
    assert_eq!(PackedStringObject::from_index(0x6000), None);
}

#[test]
fn empty_string_is_one_zero_element() {
    let p = PackedString::encode(SERIAL, "").unwrap();
    assert_eq!(p.count(), 1);
    assert_eq!(p.words(), &[0]);
    assert!(p.text().is_empty());
    assert_eq!(PackedString::decode(SERIAL, 1, &[0]), Ok(p));
}

#[test]
fn full_length_strings() {
    let p = PackedString::encode(SERIAL, "0123456789").unwrap();
    assert_eq!(p.words(), &[0x3332_3130, 0x3736_3534, 0x0000_3938]);
    let id = PackedString::encode(PackedStringObject::VehicleId, "ABCDEFGHIJKLMNOPQRST").unwrap();
    assert_eq!(id.count(), 5);
    assert_eq!(id.word(5), Some(u32::from_le_bytes(*b"QRST")));
    assert_eq!(id.text().as_str(), "ABCDEFGHIJKLMNOPQRST");
    assert_eq!(
        PackedString::decode(PackedStringObject::VehicleId, 5, id.words()),
        Ok(id)
    );
}

#[test]
fn encode_errors() {
    assert_eq!(
        PackedString::encode(SERIAL, "0123456789A"),
        Err(PackedStringError::TooLong { max: 10, got: 11 })
    );
    assert_eq!(
        PackedString::encode(PackedStringObject::BatteryId, "012345678901234567890"),
        Err(PackedStringError::TooLong { max: 20, got: 21 })
    );
    assert_eq!(
        PackedString::encode(SERIAL, "AB\u{e9}"),
        Err(PackedStringError::NonAscii {
            position: 2,
            byte: 0xC3
        })
    );
    assert_eq!(
        PackedString::encode(SERIAL, "AB\0C"),
        Err(PackedStringError::Nul { position: 2 })
    );
    assert_eq!(
        PackedString::encode(SERIAL, "\0"),
        Err(PackedStringError::Nul { position: 0 })
    );
    // 7-bit control characters are ISO 646 and accepted.
    assert!(PackedString::encode(SERIAL, "\x01\x7F").is_ok());
}

#[test]
fn encode_with_count() {
    let p = PackedString::encode_with_count(SERIAL, "BATTERY", 3).unwrap();
    assert_eq!(p.count(), 3);
    assert_eq!(p.words(), &[0x5454_4142, 0x0059_5245, 0]);
    assert_eq!(p.text().as_str(), "BATTERY");
    assert_eq!(
        PackedString::encode_with_count(SERIAL, "BATTERY", 1),
        Err(PackedStringError::BadCount {
            min: 2,
            max: 3,
            got: 1
        })
    );
    assert_eq!(
        PackedString::encode_with_count(SERIAL, "", 4),
        Err(PackedStringError::BadCount {
            min: 1,
            max: 3,
            got: 4
        })
    );
    assert_eq!(
        PackedString::encode_with_count(SERIAL, "", 0),
        Err(PackedStringError::BadCount {
            min: 1,
            max: 3,
            got: 0
        })
    );
}

#[test]
fn decode_count_and_words() {
    assert_eq!(
        PackedString::decode(SERIAL, 0, &[0]),
        Err(PackedStringError::BadCount {
            min: 1,
            max: 3,
            got: 0
        })
    );
    assert_eq!(
        PackedString::decode(SERIAL, 4, &[0; 5]),
        Err(PackedStringError::BadCount {
            min: 1,
            max: 3,
            got: 4
        })
    );
    assert_eq!(
        PackedString::decode(PackedStringObject::BatteryId, 6, &[0; 6]),
        Err(PackedStringError::BadCount {
            min: 1,
            max: 5,
            got: 6
        })
    );
    assert_eq!(
        PackedString::decode(SERIAL, 2, &[0x4141_4141]),
        Err(PackedStringError::MissingWords { need: 2, got: 1 })
    );
    // Words past the count are ignored (a fixed buffer works).
    let p = PackedString::decode(SERIAL, 1, &[0x0000_4241, 0xFFFF_FFFF, 7]).unwrap();
    assert_eq!(p.text().as_str(), "AB");
    assert_eq!(p.words(), &[0x0000_4241]);
}

#[test]
fn decode_padding_rules() {
    // Trailing all-zero elements are accepted and kept.
    let p = PackedString::decode(SERIAL, 3, &[0x5454_4142, 0x0059_5245, 0]).unwrap();
    assert_eq!(p.text().as_str(), "BATTERY");
    assert_eq!(p.count(), 3);
    assert_eq!(PackedString::encode_with_count(SERIAL, "BATTERY", 3), Ok(p));
    // A leading NUL is the empty string.
    let e = PackedString::decode(SERIAL, 2, &[0, 0]).unwrap();
    assert!(e.text().is_empty());
    // A non-NUL byte after the first NUL is rejected.
    assert_eq!(
        PackedString::decode(SERIAL, 1, &[0x4100_0041]),
        Err(PackedStringError::DataAfterNul {
            position: 3,
            byte: 0x41
        })
    );
    assert_eq!(
        PackedString::decode(SERIAL, 2, &[0x0000_0041, 0x0000_0100]),
        Err(PackedStringError::DataAfterNul {
            position: 5,
            byte: 0x01
        })
    );
}

#[test]
fn decode_character_and_length_errors() {
    assert_eq!(
        PackedString::decode(SERIAL, 1, &[0x0000_8041]),
        Err(PackedStringError::NonAscii {
            position: 1,
            byte: 0x80
        })
    );
    // 6030h: 3 elements hold 12 bytes, but only 10 characters are allowed.
    assert_eq!(
        PackedString::decode(SERIAL, 3, &[0x4141_4141, 0x4141_4141, 0x0041_4141]),
        Err(PackedStringError::TooLong { max: 10, got: 11 })
    );
    assert_eq!(
        PackedString::decode(SERIAL, 3, &[0x4141_4141, 0x4141_4141, 0x4141_4141]),
        Err(PackedStringError::TooLong { max: 10, got: 12 })
    );
    assert!(PackedString::decode(SERIAL, 3, &[0x4141_4141, 0x4141_4141, 0x0000_4141]).is_ok());
}

#[test]
fn text_formats() {
    let t = PackedString::encode(SERIAL, "SN-42").unwrap().text();
    assert_eq!(format!("{t}"), "SN-42");
    assert_eq!(format!("{t:?}"), "\"SN-42\"");
    assert_eq!(t.as_bytes(), b"SN-42");
}

#[test]
fn errors_display() {
    let e = PackedStringError::BadCount {
        min: 1,
        max: 3,
        got: 0,
    };
    assert_eq!(format!("{e}"), "element count 0 outside 1..=3");
}
