//! A DCF served whole: tests/data/sixteen-tpdo-node.dcf (written for these
//! tests; its `[Comments]` say what it holds) has 16 TPDOs, its own COB-ID
//! SYNC (1005h), store/restore (1010h/1011h), error behaviour (1029h),
//! server and client SDO parameters (1200h, 1280h), `ParameterValue`s that
//! differ from the defaults and empty `ParameterValue=` lines. The
//! dictionary built from it holds every value of the file with the file's
//! value: the `ParameterValue`, or the `DefaultValue` where the
//! `ParameterValue` of a number is empty (as python-canopen reads it).

use crate::common;

use canopen_codec::eds::{parse_bytes, Eds, ObjectType};
use canopen_codec::od::{Access, ObjectDictionary};
use canopen_codec::NodeId;
use common::sdo::SdoPair;

const DCF: &[u8] = include_bytes!("../data/sixteen-tpdo-node.dcf");

fn node() -> NodeId {
    NodeId::new(10).unwrap()
}

fn eds() -> Eds {
    parse_bytes(DCF).unwrap()
}

fn value(od: &mut impl ObjectDictionary, index: u16, sub: u8) -> Vec<u8> {
    let info = od.info(index, sub).unwrap();
    let mut buf = vec![0; info.len];
    assert_eq!(od.read(index, sub, 0, &mut buf), Ok(info.len));
    buf
}

fn u32_at(od: &mut impl ObjectDictionary, index: u16, sub: u8) -> u32 {
    let v = value(od, index, sub);
    u32::from_le_bytes(v.try_into().unwrap())
}

#[test]
fn every_value_of_the_file_is_served() {
    let eds = eds();
    let od = eds.dictionary(node());
    assert_eq!(od.unserved(), []);
    assert!(eds.unserved(node()).is_empty());
    let mut values = 0;
    for o in eds.objects.values() {
        let entries: Vec<(u8, _)> = if o.subs.is_empty() {
            vec![(0, &o.entry)]
        } else {
            o.subs.iter().map(|(s, e)| (*s, e)).collect()
        };
        for (sub, e) in entries {
            if matches!(e.object_type, ObjectType::DefType | ObjectType::DefStruct) {
                continue;
            }
            assert!(
                od.info(o.index, sub).is_ok(),
                "{:04X}h:{sub:02X} {} is not served",
                o.index,
                e.name
            );
            values += 1;
        }
    }
    assert_eq!(values, 332);
    assert_eq!(od.values().len(), values);
    // 16 TPDOs (communication and mapping), 4 RPDOs.
    let pdos = eds.pdos(node());
    assert_eq!(pdos.len(), 20);
}

#[test]
fn communication_objects_have_the_files_values() {
    let mut od = eds().dictionary(node());
    // Its own COB-ID SYNC: a producer on 081h (ParameterValue).
    assert_eq!(u32_at(&mut od, 0x1005, 0), 0x4000_0081);
    assert_eq!(u32_at(&mut od, 0x1006, 0), 10_000);
    // Store: sub 1 from its ParameterValue, subs 2-4 from DefaultValue
    // (empty ParameterValue); restore likewise.
    assert_eq!(u32_at(&mut od, 0x1010, 1), 3);
    assert_eq!(u32_at(&mut od, 0x1010, 4), 1);
    assert_eq!(u32_at(&mut od, 0x1011, 1), 1);
    assert_eq!(od.info(0x1010, 1).unwrap().access, Access::ReadWrite);
    assert_eq!(value(&mut od, 0x1029, 1), [1]);
    assert_eq!(value(&mut od, 0x1029, 2), [0]);
    // $NODEID resolved in a DefaultValue reached through an empty
    // ParameterValue.
    assert_eq!(u32_at(&mut od, 0x1014, 0), 0x8A);
    assert_eq!(u32_at(&mut od, 0x1200, 1), 0x60A);
    assert_eq!(u32_at(&mut od, 0x1280, 1), 0x641);
    // TPDO 16 (1800h + 15): its COB-ID, inhibit time, event timer, mapping.
    assert_eq!(u32_at(&mut od, 0x180F, 1), 0x4000_028F);
    assert_eq!(value(&mut od, 0x180F, 3), 150u16.to_le_bytes());
    assert_eq!(value(&mut od, 0x180F, 5), 1500u16.to_le_bytes());
    assert_eq!(value(&mut od, 0x1A0F, 0), [2]);
    assert_eq!(u32_at(&mut od, 0x1A0F, 1), 0x2002_0010);
    assert_eq!(u32_at(&mut od, 0x1A0F, 3), 0);
    // An empty ParameterValue of a string is the empty string.
    assert_eq!(value(&mut od, 0x1008, 0), b"");
    // Numbers: ParameterValue, or DefaultValue behind an empty (or blank) one.
    assert_eq!(value(&mut od, 0x2000, 2), [0x55]);
    assert_eq!(value(&mut od, 0x2001, 0), (-100i16).to_le_bytes());
    assert_eq!(value(&mut od, 0x2003, 0), [0xFE]);
    assert_eq!(u32_at(&mut od, 0x1018, 4), 0xBEEF);
}

#[test]
fn the_sdo_server_serves_them() {
    let od = eds().dictionary(node());
    let mut p = SdoPair::new(10, od);
    for (index, sub, want) in [
        (0x1005u16, 0u8, 0x4000_0081u32.to_le_bytes().to_vec()),
        (0x180F, 1, 0x4000_028Fu32.to_le_bytes().to_vec()),
        (0x1029, 1, vec![1]),
    ] {
        p.clear_events();
        p.with_client(|c, now| c.start_upload(now, index, sub))
            .unwrap();
        p.drive_bounded(10_000).unwrap();
        assert_eq!(p.uploaded(), want, "{index:04X}h:{sub:02X}");
    }
}

#[test]
fn five_hundred_and_twelve_tpdos_are_served() {
    // 1800h-19FFh, every TPDO's COB-ID: its own value in the dictionary.
    let mut text = String::new();
    for n in 0..512u32 {
        let index = 0x1800 + n;
        text.push_str(&format!(
            "[{index:04X}]\nObjectType=0x9\nSubNumber=2\n\
             [{index:04X}sub0]\nDataType=5\nAccessType=const\nDefaultValue=1\n\
             [{index:04X}sub1]\nDataType=7\nAccessType=rw\nDefaultValue=0\nParameterValue=0x{:08X}\n",
            0x8000_0000u32 + n
        ));
    }
    let eds = canopen_codec::eds::parse(&text).unwrap();
    let mut od = eds.dictionary(node());
    assert_eq!(od.values().len(), 1024);
    for n in 0..512u16 {
        assert_eq!(u32_at(&mut od, 0x1800 + n, 1), 0x8000_0000 + u32::from(n));
    }
    assert_eq!(eds.pdos(node()).len(), 512);
}
