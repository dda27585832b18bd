//! A dictionary built from an EDS (CiA 306), served by the SDO server to a
//! client on the simulated bus: values with `$NODEID` resolved, strings,
//! access rules and sizes from the description.

use crate::common;

use canopen_codec::eds::{parse, EdsDictionary};
use canopen_codec::sdo::{AbortCode, ClientEvent, TransferEnd};
use canopen_codec::NodeId;
use common::sdo::SdoPair;

const EDS: &str = "\
[1008]\r\nParameterName=Manufacturer Device Name\r\nDataType=0x0009\r\nAccessType=const\r\n\
DefaultValue=IC650 charger with a long name\r\n\
[1017]\r\nParameterName=Producer heartbeat time\r\nDataType=6\r\nAccessType=rw\r\nDefaultValue=0\r\n\
[1800]\r\nParameterName=TPDO 0\r\nObjectType=9\r\nSubNumber=2\r\n\
[1800sub0]\r\nParameterName=Highest sub-index\r\nDataType=5\r\nAccessType=ro\r\nDefaultValue=1\r\n\
[1800sub1]\r\nParameterName=COB-ID\r\nDataType=7\r\nAccessType=rw\r\nDefaultValue=$NODEID+0x180\r\n";

fn pair() -> SdoPair<EdsDictionary> {
    let eds = parse(EDS).unwrap();
    SdoPair::new(10, eds.dictionary(NodeId::new(10).unwrap()))
}

#[cfg(feature = "sdo-client-segmented")]
fn upload(p: &mut SdoPair<EdsDictionary>, index: u16, sub: u8) -> Vec<u8> {
    p.clear_events();
    p.with_client(|c, now| c.start_upload(now, index, sub))
        .unwrap();
    p.drive_bounded(10_000).unwrap();
    p.uploaded()
}

fn download(p: &mut SdoPair<EdsDictionary>, index: u16, sub: u8, value: &[u8]) -> ClientEvent {
    p.clear_events();
    p.with_client(|c, now| c.start_download(now, index, sub, value.to_vec()))
        .unwrap();
    p.drive_bounded(10_000).unwrap();
    p.client_events().pop().unwrap()
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn serves_values_with_node_id_resolved() {
    let mut p = pair();
    assert_eq!(upload(&mut p, 0x1800, 1), 0x18Au32.to_le_bytes());
    // A segmented upload of a string default.
    assert_eq!(upload(&mut p, 0x1008, 0), b"IC650 charger with a long name");
}

#[test]
fn access_and_size_come_from_the_description() {
    let mut p = pair();
    let aborted = |e: ClientEvent| match e {
        ClientEvent::Ended(TransferEnd::Aborted { code, .. }) => Some(code),
        _ => None,
    };
    assert_eq!(
        aborted(download(&mut p, 0x1008, 0, b"x")),
        Some(AbortCode::WriteOfReadOnlyObject)
    );
    assert_eq!(
        aborted(download(&mut p, 0x1017, 0, &[1, 2, 3])),
        Some(AbortCode::DataTypeLengthTooHigh)
    );
    assert_eq!(
        download(&mut p, 0x1017, 0, &[0xE8, 0x03]),
        ClientEvent::Ended(TransferEnd::Downloaded {
            index: 0x1017,
            sub: 0,
            len: 2
        })
    );
    assert_eq!(p.od().values().get(0x1017, 0), Some(&[0xE8, 0x03][..]));
    assert_eq!(
        aborted(download(&mut p, 0x1800, 2, &[1])),
        Some(AbortCode::SubIndexDoesNotExist)
    );
}
