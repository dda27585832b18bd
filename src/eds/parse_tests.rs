//! Hand-written descriptions, one per quirk real files have (CiA 306,
//! "Electronic data sheet specification for CANopen").

use alloc::string::ToString;
use alloc::vec::Vec;

use super::*;
use crate::od::{Access, ObjectDictionary, SizeRule};
use crate::pdo::{MappingEntry, PdoDirection};
use crate::NodeId;

fn ok(text: &str) -> Eds {
    match parse(text) {
        Ok(eds) => eds,
        Err(e) => panic!("{e}"),
    }
}

fn kinds(eds: &Eds) -> Vec<WarningKind> {
    eds.warnings.iter().map(|w| w.kind).collect()
}

const NODE: NodeId = match NodeId::new(10) {
    Some(n) => n,
    None => NodeId::MIN,
};

#[test]
fn sections_and_indexes_in_any_case_without_padding() {
    let eds = ok(
        "[fileinfo]\nFileName=x.eds\n[1a00]\nParameterName=m\nObjectType=9\n\
                  [1A00SUB0]\nParameterName=n\nDataType=5\n[1a00sub1]\nParameterName=e\n\
                  [1A00sub0A]\nParameterName=ten\n[100]\nParameterName=short\n",
    );
    assert_eq!(eds.file_info.file_name.as_deref(), Some("x.eds"));
    let o = &eds.objects[&0x1A00];
    assert_eq!(o.subs.keys().copied().collect::<Vec<_>>(), [0, 1, 10]);
    assert_eq!(eds.name(0x1A00, 10), Some("ten"));
    assert_eq!(eds.name(0x0100, 0), Some("short"));
    assert_eq!(o.entry.object_type, ObjectType::Record);
}

#[test]
fn object_type_defaults_to_var_and_codes_are_read() {
    let eds = ok(
        "[2000]\nDataType=7\n[2001]\nObjectType=0x2\n[2002]\nObjectType=5\n\
                  [2003]\nObjectType=6\n[2004]\nObjectType=0x8\n[2005]\nObjectType=0x09\n",
    );
    let t = |i| eds.objects[&i].entry.object_type;
    assert_eq!(t(0x2000), ObjectType::Var);
    assert_eq!(t(0x2001), ObjectType::Domain);
    assert_eq!(t(0x2002), ObjectType::DefType);
    assert_eq!(t(0x2003), ObjectType::DefStruct);
    assert_eq!(t(0x2004), ObjectType::Array);
    assert_eq!(t(0x2005), ObjectType::Record);
}

#[test]
fn data_type_hex_or_decimal_and_unknown_kept() {
    let eds = ok(
        "[2000]\nDataType=0x0007\n[2001]\nDataType=5\n[2002]\nDataType=16\n\
                  [2003]\nDataType=0x40\n",
    );
    let t = |i| eds.objects[&i].entry.data_type;
    assert_eq!(t(0x2000), Some(DataType::Unsigned32));
    assert_eq!(t(0x2001), Some(DataType::Unsigned8));
    assert_eq!(t(0x2002), Some(DataType::Integer24));
    assert_eq!(t(0x2003), Some(DataType::Other(0x40)));
}

#[test]
fn access_types_in_any_case() {
    let eds = ok(
        "[1]\nAccessType=RO\n[2]\nAccessType=wo\n[3]\nAccessType=Rw\n\
                  [4]\nAccessType=rwr\n[5]\nAccessType=RWW\n[6]\nAccessType=CONST\n\
                  [7]\nAccessType=readonly\n",
    );
    let a = |i| eds.objects[&i].entry.access;
    assert_eq!(a(1), Some(AccessType::ReadOnly));
    assert_eq!(a(2), Some(AccessType::WriteOnly));
    assert_eq!(a(3), Some(AccessType::ReadWrite));
    assert_eq!(a(4), Some(AccessType::ReadWriteRead));
    assert_eq!(a(5), Some(AccessType::ReadWriteWrite));
    assert_eq!(a(6), Some(AccessType::Const));
    assert_eq!(a(7), None);
    assert_eq!(
        eds.warnings,
        [Warning {
            line: 14,
            kind: WarningKind::UnknownAccessType
        }]
    );
}

#[test]
fn comments_blank_lines_trailing_spaces_crlf_and_bom() {
    let text = "\u{FEFF}; a header comment\r\n\r\n[2000]   \r\n  ; indented comment\r\n\
                ParameterName=Charger status  ; what it is\r\nDataType=0x0005 \t\r\n\
                DefaultValue=0x10;no space, so part of the value\r\n  \r\n";
    let eds = ok(text);
    let e = &eds.objects[&0x2000].entry;
    assert_eq!(e.name, "Charger status");
    assert_eq!(e.data_type, Some(DataType::Unsigned8));
    assert_eq!(
        e.default_value.as_deref(),
        Some("0x10;no space, so part of the value")
    );
    assert!(eds.warnings.is_empty());
}

#[test]
fn non_utf8_bytes_in_names() {
    let bytes = b"\xEF\xBB\xBF[2000]\r\nParameterName=Temp\xE9rature\r\nDataType=3\r\n";
    let eds = parse_bytes(bytes).unwrap();
    assert_eq!(eds.objects[&0x2000].entry.name, "Temp\u{FFFD}rature");
    assert_eq!(
        eds.objects[&0x2000].entry.data_type,
        Some(DataType::Integer16)
    );
    assert_eq!(
        eds.warnings,
        [Warning {
            line: 2,
            kind: WarningKind::NotUtf8
        }]
    );
}

#[test]
fn node_id_sums_in_every_form() {
    let eds = ok(
        "[1800]\nObjectType=9\nSubNumber=3\n[1800sub0]\nDataType=5\nDefaultValue=2\n\
                  [1800sub1]\nDataType=7\nDefaultValue=$NODEID+0x180\n\
                  [1800sub2]\nDataType=5\nDefaultValue=254\n\
                  [1801]\nObjectType=9\n[1801sub1]\nDataType=7\nDefaultValue=0x280+$NODEID\n\
                  [1400]\nObjectType=9\n[1400sub1]\nDataType=7\nDefaultValue= $NodeID + 0x200 \n\
                  [1401]\nObjectType=9\n[1401sub1]\nDataType=7\nDefaultValue=$nodeid+0x80000300\n",
    );
    let pdos = eds.pdos(NODE);
    let cob = |d, n: u16| {
        let p = pdos
            .iter()
            .find(|p| p.direction == d && p.number == n)
            .unwrap();
        p.cob_id.unwrap().to_u32()
    };
    assert_eq!(cob(PdoDirection::Transmit, 0), 0x18A);
    assert_eq!(cob(PdoDirection::Transmit, 1), 0x28A);
    assert_eq!(cob(PdoDirection::Receive, 0), 0x20A);
    assert_eq!(cob(PdoDirection::Receive, 1), 0x8000_030A);
    assert_eq!(pdos[2].transmission_type, Some(254));
    // The text is kept as written; the node id is applied when building.
    let raw = eds.objects[&0x1400].subs[&1].default_value.as_deref();
    assert_eq!(raw, Some("$NodeID + 0x200"));
}

#[test]
fn limits_decimal_hex_leading_zeros_negative() {
    let eds = ok(
        "[2000]\nLowLimit=-100\nHighLimit=0x7F\n[2001]\nLowLimit=0010\nHighLimit=0X00FF\n\
                  [2002]\nLowLimit=4.5\nHighLimit=\n[2003]\nLowLimit=ten\n",
    );
    let lim = |i: u16| {
        let e = &eds.objects[&i].entry;
        (
            e.low_limit.as_deref().map(|s| eval_int(s, None)),
            e.high_limit.as_deref().map(|s| eval_int(s, None)),
        )
    };
    assert_eq!(lim(0x2000), (Some(Ok(-100)), Some(Ok(0x7F))));
    assert_eq!(lim(0x2001), (Some(Ok(10)), Some(Ok(0xFF))));
    assert_eq!(eds.objects[&0x2002].entry.low_limit.as_deref(), Some("4.5"));
    assert_eq!(eds.objects[&0x2002].entry.high_limit, None);
    assert_eq!(kinds(&eds), [WarningKind::InvalidLimit]);
}

#[test]
fn compact_sub_obj_with_names_and_values() {
    let eds = ok(
        "[3004]\nParameterName=Sensor\nObjectType=8\nCompactSubObj=3\nDataType=6\n\
                  AccessType=rw\nDefaultValue=7\nPDOMapping=1\n\
                  [3004Name]\nNrOfEntries=2\n1=Left\n3=Right\n\
                  [3004value]\nNrOfEntries=1\n2=0x99\n\
                  [3004Denotation]\n1=front left\n",
    );
    let o = &eds.objects[&0x3004];
    let names: Vec<_> = o.subs.values().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["NrOfObjects", "Left", "Sensor2", "Right"]);
    assert_eq!(o.subs[&0].default_value.as_deref(), Some("3"));
    assert_eq!(o.subs[&2].parameter_value.as_deref(), Some("0x99"));
    assert_eq!(o.subs[&1].denotation.as_deref(), Some("front left"));
    let mut od = eds.dictionary(NODE);
    let mut buf = [0u8; 2];
    od.read(0x3004, 2, 0, &mut buf).unwrap();
    assert_eq!(buf, [0x99, 0]);
    od.read(0x3004, 3, 0, &mut buf).unwrap();
    assert_eq!(buf, [7, 0]);
    assert!(od.info(0x3004, 1).unwrap().pdo_mappable);
    assert!(!od.info(0x3004, 0).unwrap().pdo_mappable);
    assert!(eds.warnings.is_empty());
}

#[test]
fn sub_number_and_obj_flags() {
    let eds = ok(
        "[1018]\nObjectType=9\nSubNumber=3\nObjFlags=0x1\n[1018sub0]\nDataType=5\n\
                  [1018sub1]\nDataType=7\n",
    );
    let o = &eds.objects[&0x1018];
    assert_eq!((o.entry.sub_number, o.entry.obj_flags), (Some(3), Some(1)));
    assert_eq!(
        eds.warnings,
        [Warning {
            line: 1,
            kind: WarningKind::SubNumberMismatch {
                index: 0x1018,
                declared: 3,
                found: 2
            }
        }]
    );
}

#[test]
fn commissioning_both_spellings_decimal_or_hex() {
    let a = ok("[DeviceComissioning]\nNodeID=0x10\nBaudrate=500\nNodeName=left\n");
    let b = ok("[devicecommissioning]\nNodeID=16\nBaudrate=250\n");
    let ca = a.commissioning.unwrap();
    let cb = b.commissioning.unwrap();
    assert_eq!((ca.node_id, ca.baudrate), (Some(16), Some(500)));
    assert_eq!(ca.node_name.as_deref(), Some("left"));
    assert_eq!((cb.node_id, cb.baudrate), (Some(16), Some(250)));
}

#[test]
fn dcf_parameter_value_wins_over_default() {
    let eds = ok(
        "[1017]\nDataType=6\nAccessType=rw\nDefaultValue=0\nParameterValue=500\n\
                  Denotation=heartbeat\n",
    );
    let e = &eds.objects[&0x1017].entry;
    assert_eq!(e.value(), Some("500"));
    assert_eq!(e.denotation.as_deref(), Some("heartbeat"));
    let mut od = eds.dictionary(NODE);
    let mut buf = [0u8; 2];
    od.read(0x1017, 0, 0, &mut buf).unwrap();
    assert_eq!(u16::from_le_bytes(buf), 500);
}

#[test]
fn lists_device_info_dummies_and_comments() {
    let eds = ok(
        "[DeviceInfo]\nVendorName=Acme\nVendorNumber=0x110\nBaudRate_250=1\n\
                  BaudRate_125=1\nBaudRate_1000=0\nNrOfTXPDO=8\nLSS_Supported=1\n\
                  [MandatoryObjects]\nSupportedObjects=2\n1=0x1000\n2=0x1001\n\
                  [OptionalObjects]\nSupportedObjects=1\n1=0x1017\n\
                  [ManufacturerObjects]\nSupportedObjects=1\n1=8192\n\
                  [DummyUsage]\nDummy0005=1\nDummy0002=0\n\
                  [Comments]\nLines=2\nLine2=second\nLine1=first\n\
                  [1000]\n[1001]\n[1017]\n",
    );
    let d = &eds.device_info;
    assert_eq!(
        (d.vendor_name.as_deref(), d.vendor_number),
        (Some("Acme"), Some(0x110))
    );
    assert_eq!(d.baud_rates, [125, 250]);
    assert_eq!((d.nr_of_tx_pdo, d.lss_supported), (Some(8), true));
    assert_eq!(eds.mandatory, [0x1000, 0x1001]);
    assert_eq!(eds.optional, [0x1017]);
    assert_eq!(eds.manufacturer, [0x2000]);
    assert_eq!(eds.dummy_usage.get(&5), Some(&true));
    assert_eq!(eds.dummy_usage.get(&2), Some(&false));
    assert_eq!(eds.comments, ["first", "second"]);
    assert_eq!(
        kinds(&eds),
        [WarningKind::ListedObjectMissing { index: 0x2000 }]
    );
}

#[test]
fn unknown_sections_and_keys_are_kept() {
    let eds = ok(
        "[Tools]\nItems=1\n[2000]\nStorageLocation=RAM\nParameterName=x\n\
                  [FileInfo]\nVendorSpecific=yes\n[2001sub1]\nParameterName=orphan\n",
    );
    assert_eq!(eds.other_sections.len(), 2);
    assert_eq!(eds.other_sections[0].name, "Tools");
    assert_eq!(eds.other_sections[0].keys.get("items"), Some("1"));
    assert_eq!(
        eds.objects[&0x2000].entry.other.get("StorageLocation"),
        Some("RAM")
    );
    assert_eq!(eds.file_info.keys.get("VendorSpecific"), Some("yes"));
    assert_eq!(
        kinds(&eds),
        [WarningKind::OrphanSubObject { index: 0x2001 }]
    );
}

#[test]
fn duplicates_and_keys_outside_sections_are_warnings() {
    let eds = ok("Orphan=1\n[2000]\nDataType=5\nDataType=6\n[2000]\nParameterName=again\n");
    assert_eq!(
        kinds(&eds),
        [
            WarningKind::KeyOutsideSection,
            WarningKind::DuplicateKey,
            WarningKind::DuplicateSection
        ]
    );
    let e = &eds.objects[&0x2000].entry;
    assert_eq!(
        (e.data_type, e.name.as_str()),
        (Some(DataType::Unsigned16), "again")
    );
}

#[test]
fn errors_name_the_line() {
    assert_eq!(
        parse("[2000]\n[2001\n"),
        Err(Error::UnterminatedSection { line: 2 })
    );
    assert_eq!(
        parse("[2000]\n\njunk\n"),
        Err(Error::NotAKeyValue { line: 3 })
    );
    assert_eq!(parse("[2000]\n=5\n"), Err(Error::NotAKeyValue { line: 2 }));
    let bad = |key: &str, line| {
        let text = alloc::format!("[2000]\nParameterName=x\n{key}=zz\n");
        assert_eq!(
            parse(&text),
            Err(Error::InvalidNumber { line: 3, key: line })
        );
    };
    bad("ObjectType", Key::ObjectType);
    bad("DataType", Key::DataType);
    bad("PDOMapping", Key::PdoMapping);
    bad("SubNumber", Key::SubNumber);
    bad("CompactSubObj", Key::CompactSubObj);
    bad("ObjFlags", Key::ObjFlags);
    assert_eq!(
        parse("[OptionalObjects]\n1=0x10000\n"),
        Err(Error::InvalidNumber {
            line: 2,
            key: Key::ListEntry
        })
    );
}

#[test]
fn dictionary_sizes_access_strings_and_domains() {
    let eds = ok("[1008]\nDataType=9\nAccessType=const\nDefaultValue=IC650\n\
                  [1F50]\nObjectType=2\nAccessType=wo\n\
                  [2000]\nDataType=4\nAccessType=rww\nDefaultValue=-2\n\
                  [2001]\nDataType=5\nAccessType=ro\nDefaultValue=\n\
                  [0005]\nObjectType=5\nDataType=7\n");
    let mut od = eds.dictionary(NODE);
    let s = od.info(0x1008, 0).unwrap();
    assert_eq!((s.access, s.len), (Access::Const, 5));
    assert_eq!(
        s.size,
        SizeRule::Variable {
            max: MAX_VARIABLE_LEN
        }
    );
    let mut buf = [0u8; 8];
    assert_eq!(od.read(0x1008, 0, 0, &mut buf), Ok(5));
    assert_eq!(&buf[..5], b"IC650");
    let d = od.info(0x1F50, 0).unwrap();
    assert_eq!((d.access, d.len), (Access::WriteOnly, 0));
    let i = od.info(0x2000, 0).unwrap();
    assert_eq!((i.access, i.size), (Access::ReadWrite, SizeRule::Fixed(4)));
    od.read(0x2000, 0, 0, &mut buf).unwrap();
    assert_eq!(&buf[..4], &(-2i32).to_le_bytes());
    assert_eq!(od.read(0x2001, 0, 0, &mut buf), Ok(1));
    assert_eq!(buf[0], 0);
    assert!(od.info(0x0005, 0).is_err(), "DEFTYPE is not a value");
}

#[test]
fn an_empty_parameter_value_of_a_number_falls_back_to_the_default() {
    let eds = ok(
        "[1017]\nDataType=6\nAccessType=rw\nDefaultValue=500\nParameterValue=\n\
                  [1008]\nDataType=9\nAccessType=const\nDefaultValue=name\nParameterValue=\n",
    );
    let mut od = eds.dictionary(NODE);
    let mut buf = [0; 4];
    assert_eq!(od.read(0x1017, 0, 0, &mut buf), Ok(2));
    assert_eq!(buf[..2], 500u16.to_le_bytes());
    assert_eq!(od.info(0x1008, 0).unwrap().len, 0);
}

#[test]
fn pdo_mapping_entries() {
    let eds = ok(
        "[1A00]\nObjectType=9\n[1A00sub0]\nDataType=5\nDefaultValue=2\n\
                  [1A00sub1]\nDataType=7\nDefaultValue=0x60010008\n\
                  [1A00sub2]\nDataType=7\nDefaultValue=0x60520010\n\
                  [1A00sub3]\nDataType=7\nDefaultValue=0x60600020\n\
                  [1800]\nObjectType=9\n[1800sub1]\nDataType=7\nDefaultValue=$NODEID+0x180\n",
    );
    let pdos = eds.pdos(NODE);
    assert_eq!(pdos.len(), 1);
    let m = pdos[0].mapping().unwrap();
    assert_eq!(
        m.entries(),
        [
            MappingEntry::new(0x6001, 0, 8),
            MappingEntry::new(0x6052, 0, 16)
        ]
    );
    assert_eq!(m.total_bits(), 24);
}

/// Found by the `eds_parse` fuzz target in CI: text that starts with two
/// byte order marks read differently through `parse` and `parse_bytes`
/// (each skipped one, `parse_bytes` before handing the rest to `parse`).
#[test]
fn parse_and_parse_bytes_agree_on_byte_order_marks() {
    for text in [
        "\u{feff}\u{feff}",
        "\u{feff}",
        "\u{feff}\u{feff}[FileInfo]\nFileName=x.eds\n",
        "\u{feff}[FileInfo]\nFileName=x.eds\n",
    ] {
        assert_eq!(parse(text), parse_bytes(text.as_bytes()), "{text:?}");
    }
    assert_eq!(
        parse("\u{feff}[FileInfo]\nFileName=x.eds\n").map(|e| e.file_info.file_name),
        parse("[FileInfo]\nFileName=x.eds\n").map(|e| e.file_info.file_name)
    );
}

#[test]
fn warnings_say_the_line_and_the_deviation_in_words() {
    let eds = ok("[ManufacturerObjects]\nSupportedObjects=2\n1=0x2000\n\
                  [2000]\nObjectType=9\nSubNumber=3\n[2000sub0]\nDataType=5\n\
                  [2001sub1]\nDataType=5\n[2002]\nAccessType=rx\n");
    let said: Vec<_> = eds.warnings.iter().map(ToString::to_string).collect();
    assert_eq!(
        said,
        [
            "line 1: the object list says SupportedObjects=2 but has 1 entry",
            "line 12: AccessType is none of const, ro, wo, rw, rwr, rww (left unset)",
            "line 9: a sub-object of 2001h, which has no [2001] section (kept as an unknown section)",
            "line 4: 2000h has SubNumber=3 but 1 sub-object is described",
        ]
    );
    let missing = Warning {
        line: 0,
        kind: WarningKind::ListedObjectMissing { index: 0x1018 },
    };
    assert_eq!(
        missing.to_string(),
        "1018h is in an object list but has no section"
    );
}
