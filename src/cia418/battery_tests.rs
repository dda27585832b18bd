//! Battery type and battery parameters: table tests with literal bytes.

use super::*;
use crate::error::DecodeError;

/// CiA 418 v1.0.1, 7.3.4 (battery type): flooded, normal gravity, flat
/// plate lead acid is 0b0001_0000.
#[test]
fn flooded_lead_acid_example() {
    let t = BatteryType::from(0b0001_0000);
    assert_eq!(
        t,
        BatteryType::LeadAcid {
            kind: LeadAcid::Flooded {
                gravity: Gravity::Normal,
                plate: Plate::Flat
            },
            reserved: 0
        }
    );
    assert_eq!(t.encode(), [0x10]);
    assert_eq!(BatteryType::decode(&[0x10]), Ok(t));
}

/// Every chemistry row of CiA 418's battery-type table (v1.0.1, 7.3.4), with
/// its code.
#[test]
fn chemistry_rows() {
    let rows: [(u8, Chemistry); 16] = [
        (0b0000, Chemistry::Unknown(0)),
        (0b0001, Chemistry::LeadAcid),
        (0b0010, Chemistry::NickelCadmium),
        (0b0011, Chemistry::NickelZinc),
        (0b0100, Chemistry::Unknown(4)),
        (0b0101, Chemistry::NickelIron),
        (0b0110, Chemistry::SilverOxide),
        (0b0111, Chemistry::NickelHydrogen),
        (0b1000, Chemistry::NickelMetalHydride),
        (0b1001, Chemistry::ZincAlkalineManganeseDioxide),
        (0b1010, Chemistry::LithiumIon),
        (0b1011, Chemistry::ZincBromine),
        (0b1100, Chemistry::MetalAir),
        (0b1101, Chemistry::LithiumIronSulfide),
        (0b1110, Chemistry::SodiumBeta),
        (0b1111, Chemistry::Unknown(15)),
    ];
    for (code, chemistry) in rows {
        assert_eq!(Chemistry::from_code(code), chemistry);
        assert_eq!(chemistry.code(), code);
        assert_eq!(BatteryType::from(code << 4).chemistry(), chemistry);
    }
    let plain: [(u8, BatteryType); 9] = [
        (0x30, BatteryType::NickelZinc { reserved: 0 }),
        (0x50, BatteryType::NickelIron { reserved: 0 }),
        (0x70, BatteryType::NickelHydrogen { reserved: 0 }),
        (0x80, BatteryType::NickelMetalHydride { reserved: 0 }),
        (
            0x90,
            BatteryType::ZincAlkalineManganeseDioxide { reserved: 0 },
        ),
        (0xA0, BatteryType::LithiumIon { reserved: 0 }),
        (0xB0, BatteryType::ZincBromine { reserved: 0 }),
        (0xC0, BatteryType::MetalAir { reserved: 0 }),
        (0xD0, BatteryType::LithiumIronSulfide { reserved: 0 }),
    ];
    for (byte, t) in plain {
        assert_eq!(BatteryType::from(byte), t);
        assert_eq!(u8::from(t), byte);
    }
    assert_eq!(
        BatteryType::from(0xE5),
        BatteryType::SodiumBeta { reserved: 0x5 }
    );
    for byte in [0x00, 0x0F, 0x40, 0x4A, 0xF0, 0xFF] {
        assert_eq!(BatteryType::from(byte), BatteryType::Unknown(byte));
    }
}

#[test]
fn lead_acid_sub_types() {
    let la = |kind, reserved| BatteryType::LeadAcid { kind, reserved };
    let fl = |gravity, plate| LeadAcid::Flooded { gravity, plate };
    let rows: [(u8, BatteryType); 9] = [
        (0x10, la(fl(Gravity::Normal, Plate::Flat), 0)),
        (0x11, la(fl(Gravity::Normal, Plate::Tubular), 0)),
        (0x12, la(fl(Gravity::High, Plate::Flat), 0)),
        (0x13, la(fl(Gravity::High, Plate::Tubular), 0)),
        (0x18, la(LeadAcid::MaintenanceFree(MaintenanceFree::Agm), 0)),
        (0x19, la(LeadAcid::MaintenanceFree(MaintenanceFree::Gel), 0)),
        (
            0x1A,
            la(LeadAcid::MaintenanceFree(MaintenanceFree::Hybrid), 0),
        ),
        (
            0x1B,
            la(LeadAcid::MaintenanceFree(MaintenanceFree::Unused), 0),
        ),
        // Reserved bit x kept.
        (
            0x1D,
            la(LeadAcid::MaintenanceFree(MaintenanceFree::Gel), 0x04),
        ),
    ];
    for (byte, t) in rows {
        assert_eq!(BatteryType::from(byte), t, "{byte:#04x}");
        assert_eq!(u8::from(t), byte);
    }
}

#[test]
fn nickel_cadmium_and_silver_oxide() {
    let nicd = |cell, plate, reserved| BatteryType::NickelCadmium {
        cell,
        plate,
        reserved,
    };
    let rows: [(u8, BatteryType); 5] = [
        (
            0x20,
            nicd(NickelCadmiumCell::Vented, NickelCadmiumPlate::Pocket, 0),
        ),
        (
            0x21,
            nicd(NickelCadmiumCell::Vented, NickelCadmiumPlate::Sintered, 0),
        ),
        (
            0x28,
            nicd(NickelCadmiumCell::Sealed, NickelCadmiumPlate::Pocket, 0),
        ),
        (
            0x29,
            nicd(NickelCadmiumCell::Sealed, NickelCadmiumPlate::Sintered, 0),
        ),
        (
            0x2E,
            nicd(NickelCadmiumCell::Sealed, NickelCadmiumPlate::Pocket, 0x06),
        ),
    ];
    for (byte, t) in rows {
        assert_eq!(BatteryType::from(byte), t, "{byte:#04x}");
        assert_eq!(u8::from(t), byte);
    }
    let ag = |couple, reserved| BatteryType::SilverOxide { couple, reserved };
    let rows: [(u8, BatteryType); 5] = [
        (0x60, ag(SilverOxide::AgZn, 0)),
        (0x61, ag(SilverOxide::AgCd, 0)),
        (0x62, ag(SilverOxide::AgFe, 0)),
        (0x63, ag(SilverOxide::Unused, 0)),
        (0x6D, ag(SilverOxide::AgCd, 0x0C)),
    ];
    for (byte, t) in rows {
        assert_eq!(BatteryType::from(byte), t, "{byte:#04x}");
        assert_eq!(u8::from(t), byte);
    }
}

#[test]
fn every_byte_round_trips() {
    for byte in 0..=u8::MAX {
        let t = BatteryType::from(byte);
        assert_eq!(u8::from(t), byte);
        assert_eq!(BatteryType::from(u8::from(t)), t);
        assert_eq!(t.chemistry().code(), byte >> 4);
    }
}

#[test]
fn encoding_masks_stray_reserved_bits() {
    let t = BatteryType::LeadAcid {
        kind: LeadAcid::MaintenanceFree(MaintenanceFree::Agm),
        reserved: 0xFF,
    };
    assert_eq!(u8::from(t), 0x1C);
    assert_eq!(u8::from(BatteryType::LithiumIon { reserved: 0xF3 }), 0xA3);
}

#[test]
fn battery_parameter_subs() {
    let mut p = BatteryParameters::default();
    p.decode_sub(1, &[0x10]).unwrap();
    p.decode_sub(2, &[0xE8, 0x03]).unwrap();
    p.decode_sub(3, &[0x96, 0x00]).unwrap();
    p.decode_sub(4, &[0x18, 0x00]).unwrap();
    p.decode_sub(0, &[0x04]).unwrap();
    assert_eq!(
        p,
        BatteryParameters {
            battery_type: BatteryType::from(0x10),
            ah_capacity: 1000,
            max_charge_current: 150,
            number_of_cells: 24,
        }
    );
    let expected: [&[u8]; 5] = [
        &[0x04],
        &[0x10],
        &[0xE8, 0x03],
        &[0x96, 0x00],
        &[0x18, 0x00],
    ];
    for (sub, bytes) in (0u8..).zip(expected) {
        assert_eq!(p.encode_sub(sub).unwrap().as_slice(), bytes, "sub {sub}");
        let v = BatteryParameterValue::decode(sub, bytes).unwrap();
        assert_eq!(v.sub_index(), sub);
        assert_eq!(p.get(sub), Some(v));
    }
    assert_eq!(p.encode_sub(5), None);
    assert!(!p.set(BatteryParameterValue::HighestSubIndex(9)));
    assert!(p.set(BatteryParameterValue::NumberOfCells(12)));
    assert_eq!(p.number_of_cells, 12);
}

#[test]
fn battery_parameter_errors() {
    assert_eq!(
        BatteryParameterValue::decode(5, &[0]),
        Err(ObjectError::NoSuchSubIndex {
            index: 0x6020,
            sub: 5
        })
    );
    assert_eq!(
        BatteryParameterValue::decode(2, &[0]),
        Err(ObjectError::Decode(DecodeError::Truncated {
            need: 2,
            got: 1
        }))
    );
    assert_eq!(
        BatteryParameterValue::decode(1, &[0, 0]),
        Err(ObjectError::Decode(DecodeError::TooLong { max: 1, got: 2 }))
    );
    let mut p = BatteryParameters::default();
    assert!(p.decode_sub(4, &[]).is_err());
    assert_eq!(p, BatteryParameters::default());
}
