//! Property tests of the LSS codec (CiA 305): every payload of 0..=8 bytes
//! decodes in both directions and encodes back to the same bytes; every
//! typed message encodes to 8 bytes that decode to the same message; the
//! same holds through `Message` on 7E4h / 7E5h.

use canopen_codec::cob_id::LssDirection;
use canopen_codec::lss::{
    Fastscan, IdentifyPart, LssErrorCode, LssField, LssInquiry, LssMessage, LssMode, LssRequest,
    LssResponse, LssStatus,
};
use canopen_codec::{CanFrame, Codec, Message};
use proptest::prelude::*;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 2048,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::Direct(
                "tests/proptest-regressions/lss_props.txt",
            ),
        )),
        ..ProptestConfig::default()
    }
}

fn field() -> impl Strategy<Value = LssField> {
    (0u8..4).prop_map(|i| LssField::from_index(i).unwrap())
}

fn part() -> impl Strategy<Value = IdentifyPart> {
    (0usize..6).prop_map(|i| IdentifyPart::ALL[i])
}

fn status() -> impl Strategy<Value = LssStatus> {
    (any::<u8>(), any::<u8>()).prop_map(|(c, specific)| LssStatus {
        code: LssErrorCode::from(c),
        specific,
    })
}

fn request() -> impl Strategy<Value = LssRequest> {
    prop_oneof![
        any::<u8>().prop_map(|m| LssRequest::SwitchStateGlobal(LssMode::from(m))),
        (field(), any::<u32>()).prop_map(|(f, v)| LssRequest::SwitchStateSelective(f, v)),
        any::<u8>().prop_map(LssRequest::ConfigureNodeId),
        (any::<u8>(), any::<u8>())
            .prop_map(|(table, index)| LssRequest::ConfigureBitTiming { table, index }),
        any::<u16>().prop_map(|delay_ms| LssRequest::ActivateBitTiming { delay_ms }),
        Just(LssRequest::StoreConfiguration),
        field().prop_map(|f| LssRequest::Inquire(LssInquiry::Address(f))),
        Just(LssRequest::Inquire(LssInquiry::NodeId)),
        (part(), any::<u32>()).prop_map(|(p, v)| LssRequest::IdentifyRemoteSlave(p, v)),
        Just(LssRequest::IdentifyNonConfigured),
        (any::<u32>(), any::<u8>(), any::<u8>(), any::<u8>()).prop_map(
            |(id_number, bit_checked, sub, next)| LssRequest::Fastscan(Fastscan {
                id_number,
                bit_checked,
                sub,
                next
            })
        ),
    ]
}

fn response() -> impl Strategy<Value = LssResponse> {
    prop_oneof![
        Just(LssResponse::SwitchStateSelective),
        status().prop_map(LssResponse::ConfigureNodeId),
        status().prop_map(LssResponse::ConfigureBitTiming),
        status().prop_map(LssResponse::StoreConfiguration),
        (field(), any::<u32>()).prop_map(|(f, v)| LssResponse::Address(f, v)),
        any::<u8>().prop_map(LssResponse::NodeId),
        Just(LssResponse::IdentifySlave),
        Just(LssResponse::IdentifyNonConfigured),
    ]
}

proptest! {
    #![proptest_config(config())]

    /// Any bytes: decode then encode gives them back, both directions.
    #[test]
    fn bytes_round_trip(data in proptest::collection::vec(any::<u8>(), 0..=8)) {
        for dir in [LssDirection::MasterToSlave, LssDirection::SlaveToMaster] {
            let m = LssMessage::parse(dir, &data).unwrap();
            let mut buf = [0; 8];
            let n = m.emit(&mut buf);
            prop_assert_eq!(&buf[..n], &data[..]);
            let id = if dir == LssDirection::MasterToSlave { 0x7E5 } else { 0x7E4 };
            let f = CanFrame::standard(id, &data).unwrap();
            let msg = Message::decode(&f).unwrap();
            prop_assert_eq!(msg, Message::Lss(m));
            prop_assert_eq!(msg.encode(), f);
        }
    }

    /// Typed requests: 8 bytes that decode to the same request.
    #[test]
    fn requests_round_trip(r in request()) {
        let mut buf = [0; 8];
        prop_assert_eq!(r.emit(&mut buf), 8);
        prop_assert_eq!(LssRequest::parse(&buf).unwrap(), r);
    }

    /// Typed responses: 8 bytes that decode to the same response.
    #[test]
    fn responses_round_trip(r in response()) {
        let mut buf = [0; 8];
        prop_assert_eq!(r.emit(&mut buf), 8);
        prop_assert_eq!(LssResponse::parse(&buf).unwrap(), r);
    }
}
