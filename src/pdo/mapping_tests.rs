use super::*;
use crate::od::{Access, ObjectInfo};

/// A dictionary with a few objects for entry checks.
struct Od;

impl ObjectDictionary for Od {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        match (index, sub) {
            (0x6010, 0) => Ok(ObjectInfo::fixed(Access::ReadOnly, 2).mappable()),
            (0x6000, 0) => Ok(ObjectInfo::fixed(Access::ReadOnly, 1).mappable()),
            (0x1008, 0) => Ok(ObjectInfo::fixed(Access::Const, 8)),
            (0x6020, 9) => Err(AbortCode::SubIndexDoesNotExist),
            (0x6020, _) => Ok(ObjectInfo::fixed(Access::ReadOnly, 2).mappable()),
            (0x7000, 0) => Err(AbortCode::HardwareError),
            _ => Err(AbortCode::ObjectDoesNotExist),
        }
    }
    fn read(&mut self, _: u16, _: u8, _: usize, _: &mut [u8]) -> Result<usize, AbortCode> {
        Ok(0)
    }
    fn write(&mut self, _: u16, _: u8, _: usize, _: &[u8]) -> Result<(), AbortCode> {
        Ok(())
    }
}

#[test]
fn entry_u32_round_trip() {
    for raw in [
        0u32,
        0x6010_0010,
        0x6000_0008,
        0x6060_0020,
        0x2FFA_0108,
        u32::MAX,
    ] {
        assert_eq!(MappingEntry::from_u32(raw).to_u32(), raw);
    }
    assert!(MappingEntry::from_u32(0).is_empty());
    assert_eq!(
        format!("{}", MappingEntry::new(0x6010, 0, 16)),
        "6010h:00/16"
    );
}

#[test]
fn entry_checks_against_the_dictionary() {
    let e = |i, s, b| MappingEntry::new(i, s, b);
    assert_eq!(
        e(0x6010, 0, 17).check(&Od),
        Err(MappingError::LongerThanObject {
            entry: e(0x6010, 0, 17),
            object_bits: 16
        })
    );
    // (index, sub, bits, the abort code of a refusal)
    let cases = [
        (0x6010, 0, 16, None),
        (0x6010, 0, 8, None),
        (0x1008, 0, 8, Some(AbortCode::ObjectCannotBeMapped)),
        (0x6020, 9, 8, Some(AbortCode::SubIndexDoesNotExist)),
        (0x5000, 0, 8, Some(AbortCode::ObjectDoesNotExist)),
        (0x7000, 0, 8, Some(AbortCode::HardwareError)),
        (0x6010, 0, 0, Some(AbortCode::InvalidValue)),
        // Dummy entries: standard types of their exact width.
        (0x0005, 0, 8, None),
        (0x0001, 0, 1, None),
        (0x001B, 0, 64, None),
        (0x0005, 0, 16, Some(AbortCode::ObjectCannotBeMapped)),
        (0x0009, 0, 8, Some(AbortCode::ObjectCannotBeMapped)),
    ];
    for (index, sub, bits, refused) in cases {
        assert_eq!(
            e(index, sub, bits).check(&Od).map_err(|x| x.abort_code()),
            refused.map_or(Ok(()), Err),
            "{index:04X}h sub {sub}, {bits} bits"
        );
    }
}

#[test]
fn mapping_limits() {
    let e8 = MappingEntry::new(0x6000, 0, 8);
    assert!(PdoMapping::new(&[e8; 8]).is_ok());
    assert_eq!(
        PdoMapping::new(&[e8; 9]),
        Err(MappingError::TooManyEntries { got: 9 })
    );
    let e33 = MappingEntry::new(0x6060, 0, 33);
    assert_eq!(
        PdoMapping::new(&[e33, e33]),
        Err(MappingError::TooManyBits { got: 66 })
    );
    assert_eq!(
        PdoMapping::new(&[e8, MappingEntry::default()]),
        Err(MappingError::EmptyEntry {
            entry: MappingEntry::default()
        })
    );
    assert_eq!(
        MappingError::TooManyBits { got: 66 }.abort_code(),
        AbortCode::PdoLengthExceeded
    );
    assert_eq!(
        MappingError::TooManyEntries { got: 9 }.abort_code(),
        AbortCode::PdoLengthExceeded
    );
    let m = PdoMapping::from_u32s(&[0x6010_0010, 0x6000_0008]).unwrap();
    assert_eq!(m.len(), 2);
    assert_eq!(m.total_bits(), 24);
    assert_eq!(m.byte_len(), 3);
    assert_eq!(m.check(&Od), Ok(()));
    assert!(PdoMapping::EMPTY.is_empty());
}

#[test]
fn bit_helpers() {
    let mut p = [0u8; 8];
    insert_bits(&mut p, 4, 8, 0xFE);
    assert_eq!(p[..2], [0xE0, 0x0F]);
    assert_eq!(extract_bits(&p, 4, 8), 0xFE);
    insert_bits(&mut p, 0, 64, u64::MAX);
    assert_eq!(p, [0xFF; 8]);
    assert_eq!(extract_bits(&p, 0, 64), u64::MAX);
    assert_eq!(extract_bits(&p, 60, 8), 0xF);
    assert_eq!(extract_bits(&p, 64, 8), 0);
    assert_eq!(extract_bits(&[0xFF], 4, 8), 0x0F);
    insert_bits(&mut p, 70, 8, 0);
    assert_eq!(p, [0xFF; 8]);
    assert_eq!(sign_extend(0b111, 3), -1);
    assert_eq!(sign_extend(0b100, 3), -4);
    assert_eq!(sign_extend(0x7F, 8), 127);
}

/// The device's mapping writes answer with `check_abort`: the same code as
/// `check` gives through `abort_code`, for every entry kind (objects
/// present, missing, with a missing sub-index, a dictionary error, not
/// mappable, too long; dummy entries of every index 0..=0x20, exact or
/// not; the empty entry and zero bits).
#[test]
fn check_abort_is_check_as_an_abort_code() {
    let objects = [0x6010u16, 0x6000, 0x1008, 0x6020, 0x7000, 0x5000];
    let dummies = 0..=0x20u16;
    let mut seen = 0;
    for index in objects.into_iter().chain(dummies) {
        for sub in [0u8, 1, 9] {
            for bits in [0u8, 1, 8, 16, 17, 32, 64, 65, 255] {
                let e = MappingEntry::new(index, sub, bits);
                let want = e.check(&Od).map_err(MappingError::abort_code);
                assert_eq!(e.check_abort(&Od), want, "{e}");
                seen += usize::from(want.is_ok());
            }
        }
    }
    assert!(seen > 10, "some entries are accepted ({seen})");
    let empty = MappingEntry::from_u32(0);
    assert_eq!(empty.check_abort(&Od), Err(AbortCode::InvalidValue));
}
