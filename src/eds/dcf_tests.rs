//! A hand-written DCF and its concise DCF checked byte by byte (CiA 302-3
//! section 4), the choice of values (writable, with a `ParameterValue`),
//! the PDO order, and a DCF written from an EDS read back.

use super::*;
use crate::eds::{parse, write, ValueError};

/// Node 5: identity (read-only, never written), a heartbeat time, RPDO 1
/// (COB-ID `$NODEID+0x200`, type FEh, one mapping entry), a string, a
/// value with only a default, an empty `ParameterValue=` and a constant.
const DCF: &str = "\
[DeviceComissioning]
NodeID=5
Baudrate=250

[1000]
ParameterName=Device type
DataType=0x0007
AccessType=ro
DefaultValue=0x00010192
ParameterValue=0x00010192

[1017]
ParameterName=Producer heartbeat time
DataType=0x0006
AccessType=rw
DefaultValue=0
ParameterValue=500

[1400]
ParameterName=RPDO1 communication parameter
ObjectType=0x9
SubNumber=3

[1400sub0]
ParameterName=Highest sub-index
DataType=0x0005
AccessType=ro
DefaultValue=2
ParameterValue=2

[1400sub1]
ParameterName=COB-ID
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x200
ParameterValue=$NODEID+0x200

[1400sub2]
ParameterName=Transmission type
DataType=0x0005
AccessType=rw
DefaultValue=255
ParameterValue=0xFE

[1600]
ParameterName=RPDO1 mapping parameter
ObjectType=0x9
SubNumber=2

[1600sub0]
ParameterName=Number of entries
DataType=0x0005
AccessType=rw
ParameterValue=1

[1600sub1]
ParameterName=Entry 1
DataType=0x0007
AccessType=rw
ParameterValue=0x60000108

[2000]
ParameterName=Name
DataType=0x0009
AccessType=rw
ParameterValue=left

[2001]
ParameterName=Default only
DataType=0x0005
AccessType=rw
DefaultValue=3

[2002]
ParameterName=Empty parameter value
DataType=0x0006
AccessType=rw
DefaultValue=7
ParameterValue=

[2003]
ParameterName=Constant
DataType=0x0003
AccessType=const
ParameterValue=1
";

#[test]
fn concise_form_of_a_hand_written_dcf_byte_by_byte() {
    let dcf = parse(DCF).unwrap();
    assert_eq!(dcf.node_id(), NodeId::new(5));
    #[rustfmt::skip]
    let expected: &[u8] = &[
        8, 0, 0, 0,
        0x17, 0x10, 0, 2, 0, 0, 0, 0xF4, 0x01, // 1017h = 500
        0x00, 0x14, 1, 4, 0, 0, 0, 0x05, 0x02, 0, 0x80, // 1400h:1 disabled
        0x00, 0x14, 2, 1, 0, 0, 0, 0xFE, // 1400h:2 = FEh
        0x00, 0x16, 0, 1, 0, 0, 0, 0, // 1600h:0 = 0
        0x00, 0x16, 1, 4, 0, 0, 0, 0x08, 0x01, 0x00, 0x60, // 1600h:1
        0x00, 0x16, 0, 1, 0, 0, 0, 1, // 1600h:0 = 1
        0x00, 0x14, 1, 4, 0, 0, 0, 0x05, 0x02, 0, 0, // 1400h:1 = 205h
        0x00, 0x20, 0, 4, 0, 0, 0, b'l', b'e', b'f', b't', // 2000h
    ];
    assert_eq!(dcf.to_concise_dcf().unwrap(), expected);
}

#[test]
fn configured_values_are_the_writable_parameter_values() {
    let dcf = parse(DCF).unwrap();
    let addrs: Vec<Address> = dcf
        .configured_values()
        .unwrap()
        .into_iter()
        .map(|(a, _)| a)
        .collect();
    assert_eq!(
        addrs,
        [
            Address::new(0x1017, 0),
            Address::new(0x1400, 1),
            Address::new(0x1400, 2),
            Address::new(0x1600, 0),
            Address::new(0x1600, 1),
            Address::new(0x2000, 0),
        ]
    );
}

#[test]
fn a_value_that_does_not_encode_is_a_typed_error() {
    // (what the DCF gets wrong, the edit that makes it so, the entry that
    // cannot be encoded and why)
    let cases = [
        (
            "no NodeID for a $NODEID value",
            ("NodeID=5\n", ""),
            Address::new(0x1400, 1),
            ValueError::NoNodeId,
        ),
        (
            "a value wider than its type",
            ("ParameterValue=0xFE", "ParameterValue=0x1FE"),
            Address::new(0x1400, 2),
            ValueError::OutOfRange,
        ),
    ];
    for (what, (from, to), addr, error) in cases {
        let text = DCF.replace(from, to);
        assert_eq!(
            parse(&text).unwrap().to_concise_dcf(),
            Err(DcfError::Value {
                addr,
                reason: UnservedReason::Value(error)
            }),
            "{what}"
        );
    }
}

#[test]
fn a_pdo_mapping_alone_is_written_count_zero_entries_count() {
    let text = "[DeviceComissioning]\nNodeID=1\n\
        [1A00]\nObjectType=0x9\n\
        [1A00sub0]\nDataType=0x0005\nAccessType=rw\nParameterValue=2\n\
        [1A00sub1]\nDataType=0x0007\nAccessType=rw\nParameterValue=0x60000108\n\
        [1A00sub2]\nDataType=0x0007\nAccessType=rw\nParameterValue=0x60010110\n";
    let bytes = parse(text).unwrap().to_concise_dcf().unwrap();
    let dcf = ConciseDcf::new_checked(&bytes).unwrap();
    let steps: Vec<(u16, u8, &[u8])> = dcf
        .iter()
        .map(|e| (e.addr.index, e.addr.sub, e.data))
        .collect();
    assert_eq!(
        steps,
        [
            (0x1A00, 0, &[0][..]),
            (0x1A00, 1, &[0x08, 0x01, 0x00, 0x60][..]),
            (0x1A00, 2, &[0x10, 0x01, 0x01, 0x60][..]),
            (0x1A00, 0, &[2][..]),
        ]
    );
}

fn eds() -> Eds {
    // The DCF's objects without its commissioning section nor its values.
    let mut eds = parse(DCF).unwrap();
    eds.commissioning = None;
    for o in eds.objects.values_mut() {
        o.entry.parameter_value = None;
        for e in o.subs.values_mut() {
            e.parameter_value = None;
        }
    }
    eds
}

#[test]
fn a_dcf_written_from_an_eds_reads_back_with_its_values() {
    let node = NodeId::new(9).unwrap();
    let eds = eds();
    assert_eq!(eds.to_concise_dcf().unwrap(), [0, 0, 0, 0]);
    let dcf = eds
        .to_dcf(
            node,
            [
                (Address::new(0x1017, 0), "250"),
                (Address::new(0x1400, 1), "$NODEID+0x200"),
                (Address::new(0x2000, 0), "right"),
            ],
        )
        .unwrap();
    let text = write(&dcf);
    assert!(text.contains("[DeviceComissioning]\nNodeID=9\n"), "{text}");
    let again = parse(&text).unwrap();
    assert_eq!(again.node_id(), Some(node));
    assert_eq!(
        again.configured_values().unwrap(),
        [
            (Address::new(0x1017, 0), alloc::vec![0xFA, 0]),
            (Address::new(0x1400, 1), alloc::vec![0x09, 0x02, 0, 0]),
            (Address::new(0x2000, 0), b"right".to_vec()),
        ]
    );
    // Everything else as in the EDS: the objects differ only in those values.
    let mut back = again.clone();
    back.commissioning = None;
    for (index, sub) in [(0x1017, 0), (0x1400, 1), (0x2000, 0)] {
        back.entry_mut(Address::new(index, sub))
            .unwrap()
            .parameter_value = None;
    }
    let mut expected = eds.clone();
    back.clear_positions();
    expected.clear_positions();
    assert_eq!(back.objects, expected.objects);
}

#[test]
fn to_dcf_refuses_what_a_node_cannot_be_configured_with() {
    let eds = eds();
    let node = NodeId::new(9).unwrap();
    /// The refusal for an entry, which names it.
    type Refusal = fn(Address) -> DcfError;
    let not_a_number: Refusal = |addr| DcfError::Value {
        addr,
        reason: UnservedReason::Value(ValueError::NotANumber),
    };
    // (what is wrong, the entry and value asked for, the refusal)
    let cases: [(_, _, _, Refusal); 5] = [
        (
            "read-only",
            Address::new(0x1000, 0),
            "1",
            DcfError::NotWritable,
        ),
        ("const", Address::new(0x2003, 0), "1", DcfError::NotWritable),
        (
            "no such object",
            Address::new(0x3000, 0),
            "1",
            DcfError::NoEntry,
        ),
        (
            "no such sub-index",
            Address::new(0x1017, 1),
            "1",
            DcfError::NoEntry,
        ),
        ("not a number", Address::new(0x1017, 0), "x", not_a_number),
    ];
    for (what, addr, text, refusal) in cases {
        assert_eq!(
            eds.to_dcf(node, [(addr, text)]),
            Err(refusal(addr)),
            "{what}"
        );
    }
    // Existing commissioning keys are kept, NodeID replaced.
    let mut with_rate = eds.clone();
    with_rate.commissioning = parse("[DeviceComissioning]\nnodeid=3\nBaudrate=500\n")
        .unwrap()
        .commissioning;
    let dcf = with_rate.to_dcf(node, []).unwrap();
    let c = dcf.commissioning.unwrap();
    assert_eq!(c.keys.get("Baudrate"), Some("500"));
    assert_eq!(c.keys.get("NodeID"), Some("9"));
    assert_eq!(c.keys.len(), 2);
}
