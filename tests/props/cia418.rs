//! Property tests for the CiA 418 codecs, through the public API only.

use canopen_codec::cia418::{
    BatteryType, BatteryVoltage, CalendarDateTime, ChargeCurrentRequested, DeviceType,
    EighthAmpHours, EqualizationDate, PackedString, PackedStringObject, StateOfCharge, Temperature,
};
use canopen_codec::PdoNumber;
use proptest::prelude::*;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 512,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::Direct(
                "tests/proptest-regressions/cia418_props.txt",
            ),
        )),
        ..ProptestConfig::default()
    }
}

fn object() -> impl Strategy<Value = PackedStringObject> {
    prop::sample::select(PackedStringObject::ALL.to_vec())
}

/// A valid string (7-bit, no NUL, 0..=max characters) for its object.
fn valid_string() -> impl Strategy<Value = (PackedStringObject, String)> {
    object().prop_flat_map(|o| {
        (
            Just(o),
            prop::collection::vec(1u8..=0x7F, 0..=o.max_chars())
                .prop_map(|b| String::from_utf8(b).expect("7-bit bytes are UTF-8")),
        )
    })
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn packed_string_round_trips((o, s) in valid_string()) {
        let p = PackedString::encode(o, &s).unwrap();
        prop_assert_eq!(usize::from(p.count()), s.len().div_ceil(4).max(1));
        prop_assert_eq!(p.object(), o);
        let text = p.text();
        prop_assert_eq!(text.as_str(), s.as_str());
        let back = PackedString::decode(o, p.count(), p.words()).unwrap();
        prop_assert_eq!(back, p);
        let back_text = back.text();
        prop_assert_eq!(back_text.as_str(), s.as_str());
        // The bytes on the wire are the characters, zero padded.
        let bytes: Vec<u8> = p.words().iter().flat_map(|w| w.to_le_bytes()).collect();
        prop_assert_eq!(&bytes[..s.len()], s.as_bytes());
        prop_assert!(bytes[s.len()..].iter().all(|&b| b == 0));
    }

    #[test]
    fn packed_string_padded_round_trips((o, s) in valid_string(), extra in 0u8..5) {
        let min = s.len().div_ceil(4).max(1) as u8;
        let count = min.saturating_add(extra);
        match PackedString::encode_with_count(o, &s, count) {
            Ok(p) => {
                prop_assert!(count <= o.max_elements());
                prop_assert_eq!(PackedString::decode(o, count, p.words()), Ok(p));
                let text = p.text();
        prop_assert_eq!(text.as_str(), s.as_str());
            }
            Err(_) => prop_assert!(count > o.max_elements()),
        }
    }

    #[test]
    fn packed_string_decode_is_total(
        o in object(),
        count in any::<u8>(),
        words in prop::collection::vec(any::<u32>(), 0..7),
    ) {
        if let Ok(p) = PackedString::decode(o, count, &words) {
            // Whatever decodes re-encodes to exactly the same elements.
            prop_assert_eq!(p.count(), count);
            prop_assert_eq!(p.words(), &words[..usize::from(count)]);
            let text = p.text();
            prop_assert!(text.len() <= o.max_chars());
            prop_assert_eq!(PackedString::encode_with_count(o, text.as_str(), count), Ok(p));
            let minimal = PackedString::encode(o, text.as_str()).unwrap();
            let n = minimal.words().len();
            prop_assert_eq!(minimal.words(), &p.words()[..n]);
            prop_assert!(p.words()[n..].iter().all(|&w| w == 0));
        }
    }

    #[test]
    fn packed_string_words_near_valid_are_total(
        o in object(),
        count in 1u8..=5,
        bytes in prop::collection::vec(prop::sample::select(vec![0u8, 0x41, 0x7F, 0x80, 0xFF]), 20),
    ) {
        let words: Vec<u32> = bytes
            .chunks(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        if let Ok(p) = PackedString::decode(o, count, &words) {
            prop_assert_eq!(PackedString::encode_with_count(o, p.text().as_str(), count), Ok(p));
        }
    }

    #[test]
    fn packed_string_encode_is_total(o in object(), s in any::<String>()) {
        if let Ok(p) = PackedString::encode(o, &s) {
            let text = p.text();
        prop_assert_eq!(text.as_str(), s.as_str());
        }
    }

    #[test]
    fn date_round_trips_every_raw_day(days in any::<u16>(), minutes in 0u16..1440) {
        let eq = EqualizationDate { minutes, days };
        let c = eq.to_calendar().unwrap();
        let again = CalendarDateTime::new(c.year(), c.month(), c.day(), c.hour(), c.minute());
        prop_assert_eq!(again, Ok(c));
        prop_assert_eq!(EqualizationDate::from(c), eq);
    }

    #[test]
    fn date_round_trips_every_valid_date(
        year in 1980u16..2170,
        month in 0u8..14,
        day in 0u8..33,
        hour in 0u8..25,
        minute in 0u8..61,
    ) {
        if let Ok(c) = CalendarDateTime::new(year, month, day, hour, minute) {
            prop_assert_eq!(EqualizationDate::from(c).to_calendar(), Ok(c));
        }
    }

    #[test]
    fn date_minutes_beyond_a_day_are_errors(days in any::<u16>(), minutes in 1440u16..) {
        let eq = EqualizationDate { minutes, days };
        prop_assert!(eq.to_calendar().is_err());
    }

    #[test]
    fn temperature_round_trips(raw in any::<i16>()) {
        let t = Temperature::from_raw(raw);
        prop_assert_eq!(Temperature::from_millidegrees_c(t.millidegrees_c()), Some(t));
        prop_assert_eq!(Temperature::decode(&t.encode()), Ok(t));
        prop_assert_eq!(t.as_celsius_f32() * 1000.0, t.millidegrees_c() as f32);
    }

    #[test]
    fn eighth_amp_hours_round_trip(raw in any::<u16>()) {
        let a = EighthAmpHours::from_raw(raw);
        prop_assert_eq!(EighthAmpHours::from_milliamp_hours(a.milliamp_hours()), Some(a));
        prop_assert_eq!(EighthAmpHours::decode(&a.encode()), Ok(a));
    }

    #[test]
    fn voltage_round_trips(raw in any::<u32>()) {
        let v = BatteryVoltage::from_raw(raw);
        prop_assert_eq!(BatteryVoltage::from_picovolts(v.picovolts()), Some(v));
        prop_assert_eq!(BatteryVoltage::decode(&v.encode()), Ok(v));
        prop_assert_eq!(v.as_volts_f64() * 1024.0, f64::from(raw));
    }

    #[test]
    fn charge_current_round_trips(raw in any::<u16>()) {
        let i = ChargeCurrentRequested::from_raw(raw);
        prop_assert_eq!(ChargeCurrentRequested::decode(&i.encode()), Ok(i));
        match i.microamps() {
            Some(ua) => prop_assert_eq!(ChargeCurrentRequested::from_microamps(ua), Some(i)),
            None => prop_assert_eq!(raw, 0xFFFF),
        }
    }

    #[test]
    fn soc_and_battery_type_round_trip(raw in any::<u8>()) {
        let s = StateOfCharge::decode(&[raw]).unwrap();
        prop_assert_eq!(s.encode(), [raw]);
        prop_assert_eq!(s.percent().is_some(), raw <= 100);
        let t = BatteryType::from(raw);
        prop_assert_eq!(u8::from(t), raw);
        prop_assert_eq!(BatteryType::from(u8::from(t)), t);
    }

    #[test]
    fn device_type_round_trips(raw in any::<u32>()) {
        let d = DeviceType::decode(&raw.to_le_bytes()).unwrap();
        prop_assert_eq!(d.raw(), raw);
        prop_assert_eq!(d.encode(), raw.to_le_bytes());
        prop_assert!(d.rpdos().contains(PdoNumber::P0));
        prop_assert!(d.tpdos().contains(PdoNumber::P0));
        prop_assert_eq!(d.rpdos().contains(PdoNumber::P1), raw & (1 << 16) != 0);
        prop_assert_eq!(d.tpdos().contains(PdoNumber::P2), raw & (1 << 19) != 0);
        prop_assert!(!d.tpdos().contains(PdoNumber::P3));
    }
}
