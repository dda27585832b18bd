use super::*;
use crate::emcy::ErrorCode;
use crate::nmt::{NmtCommandSpecifier, NmtState, NmtTarget};
use crate::sdo::{ClientCommand, ServerCommand};

use crate::frame::standard_frame as f;

/// `check` for every first byte at every length 0..=8 (the other bytes a
/// fixed filler), with the first byte beside the data.
fn every_payload(mut check: impl FnMut(u8, &[u8])) {
    for b0 in 0..=255u8 {
        let data = [b0, 0xA1, 0xB2, 0xC3, 0xD4, 0xE5, 0xF6, 0x17];
        for len in 0..=8 {
            check(b0, &data[..len]);
        }
    }
}

use crate::cob_id::test_node as n;

fn round_trip(frame: CanFrame) -> Message {
    let m = Message::decode(&frame).unwrap();
    assert_eq!(m.encode(), frame, "{m:?}");
    m
}

#[test]
fn capture_frames_decode() {
    assert_eq!(
        round_trip(f(0x000, &[0x01, 0x0A])),
        Message::Nmt(NmtCommand {
            command: NmtCommandSpecifier::Start,
            target: NmtTarget::Node(n(10)),
        })
    );
    assert_eq!(
        round_trip(f(0x70A, &[0x7F])),
        Message::Heartbeat {
            node: n(10),
            heartbeat: Heartbeat::new(NmtState::PreOperational)
        }
    );
    let Message::Emcy { node, emcy } =
        round_trip(f(0x08A, &[0x30, 0x81, 0x01, 0x1E, 0x80, 0, 0, 0]))
    else {
        panic!()
    };
    assert_eq!(node, n(10));
    assert_eq!(emcy.code, ErrorCode::HEARTBEAT);
    let Message::Tpdo { pdo, node, payload } =
        round_trip(f(0x18A, &[0x74, 0x13, 0x45, 0x4E, 0x70, 0, 0, 0]))
    else {
        panic!()
    };
    assert_eq!((pdo, node), (PdoNumber::P0, n(10)));
    assert_eq!(payload.as_slice(), &[0x74, 0x13, 0x45, 0x4E, 0x70, 0, 0, 0]);
    let Message::Rpdo { pdo, .. } = round_trip(f(0x30A, &[0, 0, 0, 0x0A, 0, 0x52, 0x30, 0x02]))
    else {
        panic!()
    };
    assert_eq!(pdo, PdoNumber::P1);
}

#[test]
fn sdo_both_directions() {
    let Message::SdoRequest { node, sdo } =
        round_trip(f(0x602, &[0x40, 0x18, 0x10, 1, 0, 0, 0, 0]))
    else {
        panic!()
    };
    assert_eq!(node, n(2));
    assert_eq!(
        sdo.command,
        ClientCommand::InitiateUpload {
            index: 0x1018,
            sub: 1
        }
    );
    let Message::SdoResponse { sdo, .. } = round_trip(f(0x582, &[0x60, 0x17, 0x10, 0, 0, 0, 0, 0]))
    else {
        panic!()
    };
    assert_eq!(
        sdo.command,
        ServerCommand::InitiateDownload {
            index: 0x1017,
            sub: 0
        }
    );
}

#[test]
fn remote_frames() {
    let guard = CanFrame::remote(CanId::Standard(0x701), 1).unwrap();
    assert_eq!(
        round_trip(guard),
        Message::NodeGuardRequest { node: n(1), dlc: 1 }
    );
    let rtr = CanFrame::remote(CanId::Standard(0x281), 8).unwrap();
    assert_eq!(
        round_trip(rtr),
        Message::TpdoRequest {
            pdo: PdoNumber::P1,
            node: n(1),
            dlc: 8
        }
    );
    let odd = CanFrame::remote(CanId::Standard(0x123), 0).unwrap();
    assert_eq!(round_trip(odd), Message::Unknown(odd));
    for id in [0x000u16, 0x080, 0x081, 0x100, 0x201, 0x581, 0x601, 0x7E5] {
        let r = CanFrame::remote(CanId::Standard(id), 0).unwrap();
        assert_eq!(
            Message::decode(&r),
            Err(DecodeError::UnexpectedRemote),
            "{id:X}"
        );
    }
}

#[test]
fn others() {
    assert_eq!(
        round_trip(f(0x080, &[])),
        Message::Sync(SyncMessage { counter: None })
    );
    assert_eq!(
        round_trip(f(0x080, &[3])),
        Message::Sync(SyncMessage { counter: Some(3) })
    );
    assert!(matches!(
        round_trip(f(0x100, &[1, 2, 3, 4, 5, 6])),
        Message::Time(_)
    ));
    assert!(matches!(
        round_trip(f(0x7E5, &[0x04, 1, 0, 0, 0, 0, 0, 0])),
        Message::Lss(crate::lss::LssMessage::Request(
            crate::lss::LssRequest::SwitchStateGlobal(crate::lss::LssMode::Configuration)
        ))
    ));
    let ext = CanFrame::new(CanId::Extended(0x18A), &[1, 2]).unwrap();
    assert_eq!(round_trip(ext), Message::Unknown(ext));
    assert_eq!(round_trip(f(0x700, &[5])), Message::Unknown(f(0x700, &[5])));
}

#[test]
fn malformed_known_objects_are_errors() {
    // (identifier, data, the error): an EMCY, NMT, heartbeat, SYNC and SDO
    // frame each shorter or longer than its object.
    #[rustfmt::skip]
    let cases: [(u16, &[u8], DecodeError); 6] = [
        (0x08A, &[0x30, 0x81], DecodeError::Truncated { need: 8, got: 2 }),
        (0x000, &[1], DecodeError::Truncated { need: 2, got: 1 }),
        (0x701, &[], DecodeError::Truncated { need: 1, got: 0 }),
        (0x080, &[1, 2], DecodeError::TooLong { max: 1, got: 2 }),
        (0x601, &[], DecodeError::Truncated { need: 1, got: 0 }),
        (0x601, &[0x40, 0x00], DecodeError::Truncated { need: 4, got: 2 }),
    ];
    for (id, data, error) in cases {
        assert_eq!(
            Message::decode(&f(id, data)),
            Err(error),
            "{id:03X}h {data:02X?}"
        );
    }
}

#[test]
fn kind_and_node() {
    let m = Message::decode(&f(0x28A, &[])).unwrap();
    assert_eq!(m.kind(), CobKind::Tpdo(PdoNumber::P1, n(10)));
    assert_eq!(m.node(), Some(n(10)));
    assert_eq!(Message::decode(&f(0x080, &[])).unwrap().node(), None);
}

/// The out-of-line SDO segment decoders give exactly what the general SDO
/// decoders give, for every command byte and length, on both directions.
#[test]
fn sdo_fast_paths_match_the_general_decoders() {
    use crate::sdo::{SdoRequest, SdoResponse};
    let node = n(5);
    every_payload(|_, data| {
        let resp = f(0x585, data);
        let want = SdoResponse::parse(data).map(|sdo| Message::SdoResponse { node, sdo });
        assert_eq!(Message::decode(&resp), want, "response {resp}");
        let req = f(0x605, data);
        let want = SdoRequest::parse(data).map(|sdo| Message::SdoRequest { node, sdo });
        assert_eq!(Message::decode(&req), want, "request {req}");
        assert_eq!(SdoRequest::decode_frame(&req), SdoRequest::parse(data));
        assert_eq!(SdoResponse::decode_frame(&resp), SdoResponse::parse(data));
        if let Ok(m) = Message::decode(&req) {
            assert_eq!(m.encode(), req);
        }
        if let Ok(m) = Message::decode(&resp) {
            assert_eq!(m.encode(), resp);
        }
    });
}

/// The heartbeat arm gives what `Heartbeat::parse` gives, for every byte
/// and length; every 7-bit state reads back to its bits.
#[test]
fn heartbeat_arm_matches_heartbeat_decode() {
    let node = n(5);
    every_payload(|b, data| {
        let want = Heartbeat::parse(data).map(|heartbeat| Message::Heartbeat { node, heartbeat });
        assert_eq!(Message::decode(&f(0x705, data)), want, "{data:02X?}");
        assert_eq!(NmtState::from_bits(b).bits(), b & 0x7F);
    });
    assert_eq!(NmtState::from_bits(0x85), NmtState::Operational);
    assert_eq!(NmtState::from_bits(0x04), NmtState::Stopped);
    assert_eq!(NmtState::from_bits(0xFF), NmtState::PreOperational);
    assert_eq!(NmtState::from_bits(0x80), NmtState::BootUp);
    assert_eq!(NmtState::from_bits(0x7E), NmtState::Unknown(0x7E));
}

/// Any classic CAN frame: 11- or 29-bit, data or remote, 0..=8 bytes, with
/// the identifiers of the predefined connection set well represented.
fn any_frame() -> impl proptest::strategy::Strategy<Value = CanFrame> {
    use proptest::prelude::*;
    let standard = prop_oneof![
        0u16..=0x7FF,
        (0u16..16, 0u16..128).prop_map(|(f, n)| (f << 7) | n),
        Just(0x7E4u16),
        Just(0x7E5u16),
    ];
    (
        standard,
        0u32..=0x1FFF_FFFF,
        any::<bool>(),
        any::<bool>(),
        proptest::collection::vec(any::<u8>(), 0..=8),
    )
        .prop_map(|(std_id, ext_id, extended, remote, data)| {
            let id = if extended {
                CanId::Extended(ext_id)
            } else {
                CanId::Standard(std_id)
            };
            if remote {
                CanFrame::remote(id, data.len() as u8).unwrap()
            } else {
                CanFrame::new(id, &data).unwrap()
            }
        })
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 4096,
        ..crate::testing::proptest_config("tests/proptest-regressions/src-message-tests.txt")
    })]

    /// The hot path of `Message::decode` (the objects of a node, straight
    /// from the function code) gives what the full classification gives,
    /// errors included, on every frame.
    #[test]
    fn decode_agrees_with_the_classification(frame in any_frame()) {
        proptest::prop_assert_eq!(Message::decode(&frame), Message::decode_classified(&frame));
    }
}

/// Every 11-bit identifier with every length, as data and as remote frame:
/// the hot path and the full classification agree.
#[test]
fn decode_agrees_with_the_classification_on_every_identifier() {
    for raw in 0..=0x7FFu16 {
        for len in 0..=8u8 {
            let bytes = [0x43, 0x00, 0x10, 0x00, 0x05, 0x7F, 0x81, 0xFF];
            let data = CanFrame::standard(raw, &bytes[..usize::from(len)]).unwrap();
            let remote = CanFrame::remote(CanId::Standard(raw), len).unwrap();
            for frame in [data, remote] {
                assert_eq!(
                    Message::decode(&frame),
                    Message::decode_classified(&frame),
                    "{frame}"
                );
            }
        }
    }
}
