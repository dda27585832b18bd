//! Property tests for `Message` and the codecs beneath it.
//!
//! - Any classic CAN frame (11- or 29-bit, data or remote, 0..=8 bytes):
//!   `Message::decode` never panics, and whatever decodes re-encodes to the
//!   identical frame, with `kind()` matching `classify` of the id.
//! - Every typed message round-trips: `decode(encode(m)) == m`. For SDO
//!   messages built with `SdoRequest::new` / `SdoResponse::new` the `command`
//!   field is compared (the raw bytes behind it differ by construction), after
//!   [`expected_initiate`] accounts for the one documented representation
//!   change.
//!
//! Failure persistence is off, so no `proptest-regressions/` folder appears;
//! a failure prints its minimal case.

use canopen_codec::bytes::Payload;
use canopen_codec::cob_id::{classify, LssDirection};
use canopen_codec::emcy::{Emergency, ErrorCode, ErrorRegister};
use canopen_codec::lss::LssMessage;
use canopen_codec::nmt::{Heartbeat, HeartbeatFrame, NmtCommand};
use canopen_codec::sdo::{
    AbortCode, BlockDataInitiate, BlockDownloadAccept, BlockUploadInitiate, ClientBlockDownload,
    ClientBlockUpload, ClientCommand, ExpeditedData, InitiatePayload, SdoRequest, SdoResponse,
    Segment, SegmentData, ServerBlockDownload, ServerBlockUpload, ServerCommand,
};
use canopen_codec::sync::SyncMessage;
use canopen_codec::time::TimeOfDay;
use canopen_codec::{CanFrame, CanId, Codec, Message, NodeId, PdoNumber};
use proptest::prelude::*;
use proptest::test_runner::Config as ProptestConfig;

const CASES: u32 = 2048;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: CASES,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::Direct(
                "tests/proptest-regressions/message_props.txt",
            ),
        )),
        ..ProptestConfig::default()
    }
}

// ---------------------------------------------------------------------------
// Frames.

/// Identifiers of the predefined connection set, so the typed decoders are
/// hit far more often than a uniform 11-bit draw would manage.
fn interesting_standard_id() -> impl Strategy<Value = u16> {
    prop_oneof![
        Just(0x000u16),
        Just(0x080),
        Just(0x100),
        Just(0x7E4),
        Just(0x7E5),
        (
            prop::sample::select(vec![
                0x080u16, 0x180, 0x200, 0x280, 0x300, 0x380, 0x400, 0x480, 0x500, 0x580, 0x600,
                0x700,
            ]),
            0u16..=0x7F
        )
            .prop_map(|(base, node)| base + node),
    ]
}

fn can_id() -> impl Strategy<Value = CanId> {
    prop_oneof![
        2 => (0u16..=0x7FF).prop_map(CanId::Standard),
        3 => interesting_standard_id().prop_map(CanId::Standard),
        1 => (0u32..=0x1FFF_FFFF).prop_map(CanId::Extended),
    ]
}

fn can_frame() -> impl Strategy<Value = CanFrame> {
    prop_oneof![
        4 => (can_id(), prop::collection::vec(any::<u8>(), 0..=8))
            .prop_map(|(id, data)| CanFrame::new(id, &data).unwrap()),
        1 => (can_id(), 0u8..=8).prop_map(|(id, dlc)| CanFrame::remote(id, dlc).unwrap()),
    ]
}

proptest! {
    #![proptest_config(config())]

    /// (a) Total decode, exact re-encode.
    #[test]
    fn any_frame_decodes_without_panic_and_round_trips(frame in can_frame()) {
        if let Ok(msg) = Message::decode(&frame) {
            prop_assert_eq!(msg.encode(), frame, "message {:?}", msg);
            prop_assert_eq!(msg.kind(), classify(frame.id()));
            prop_assert_eq!(msg.node(), msg.kind().node());
        }
    }

    /// (a') The same, on SDO identifiers only, so every specifier and
    /// truncation of both directions is hit many times.
    #[test]
    fn any_sdo_frame_round_trips(
        response in any::<bool>(),
        node in node_id(),
        data in prop::collection::vec(any::<u8>(), 0..=8),
    ) {
        let base = if response { 0x580 } else { 0x600 };
        let frame = CanFrame::standard(base + u16::from(node.raw()), &data).unwrap();
        if let Ok(msg) = Message::decode(&frame) {
            prop_assert_eq!(msg.encode(), frame, "message {:?}", msg);
        }
        // The bare codecs agree with the message layer.
        if response {
            if let Ok(r) = SdoResponse::parse(&data) {
                let (bytes, len) = r.encode();
                prop_assert_eq!(&bytes[..len], &data[..]);
                prop_assert_eq!(r.bytes(), &data[..]);
            }
        } else if let Ok(r) = SdoRequest::parse(&data) {
            let (bytes, len) = r.encode();
            prop_assert_eq!(&bytes[..len], &data[..]);
            prop_assert_eq!(r.bytes(), &data[..]);
        }
    }
}

// ---------------------------------------------------------------------------
// Typed values.

fn node_id() -> impl Strategy<Value = NodeId> {
    (1u8..=127).prop_map(|n| NodeId::new(n).unwrap())
}

fn pdo_number() -> impl Strategy<Value = PdoNumber> {
    (0u8..=3).prop_map(|n| PdoNumber::new(n).unwrap())
}

fn payload() -> impl Strategy<Value = Payload> {
    prop::collection::vec(any::<u8>(), 0..=8).prop_map(|v| Payload::new(&v).unwrap())
}

fn expedited_data(len: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = ExpeditedData> {
    prop::collection::vec(any::<u8>(), len).prop_map(|v| ExpeditedData::new(&v).unwrap())
}

fn segment() -> impl Strategy<Value = Segment> {
    (
        any::<bool>(),
        any::<bool>(),
        prop::collection::vec(any::<u8>(), 0..=7),
    )
        .prop_map(|(toggle, last, data)| Segment {
            toggle,
            last,
            data: SegmentData::new(&data).unwrap(),
        })
}

/// An initiate payload. Expedited with the size indicated carries 1..=4
/// bytes: the 2-bit n field cannot say 0 (`InitiatePayload::expedited(&[])`
/// refuses to build such a value).
fn initiate_payload() -> impl Strategy<Value = InitiatePayload> {
    prop_oneof![
        expedited_data(1..=4).prop_map(|data| InitiatePayload::Expedited {
            data,
            size_indicated: true
        }),
        expedited_data(0..=4).prop_map(|data| InitiatePayload::Expedited {
            data,
            size_indicated: false
        }),
        any::<Option<u32>>().prop_map(|size| InitiatePayload::Segmented { size }),
    ]
}

/// Abort codes as the wire produces them (`From<u32>` is canonical: a listed
/// value never comes back as `Other`).
fn abort_code() -> impl Strategy<Value = AbortCode> {
    prop_oneof![
        prop::sample::select(canopen_codec::sdo::ALL_ABORT_CODES.to_vec()),
        any::<u32>().prop_map(AbortCode::from),
    ]
}

fn client_command() -> impl Strategy<Value = ClientCommand> {
    let mux = (any::<u16>(), any::<u8>());
    prop_oneof![
        segment().prop_map(ClientCommand::DownloadSegment),
        (mux, initiate_payload()).prop_map(|((index, sub), payload)| {
            ClientCommand::InitiateDownload {
                index,
                sub,
                payload,
            }
        }),
        mux.prop_map(|(index, sub)| ClientCommand::InitiateUpload { index, sub }),
        any::<bool>().prop_map(|toggle| ClientCommand::UploadSegment { toggle }),
        (mux, abort_code()).prop_map(|((index, sub), code)| ClientCommand::Abort {
            index,
            sub,
            code
        }),
        prop_oneof![
            (mux, any::<bool>(), any::<u8>(), any::<u8>()).prop_map(
                |((index, sub), crc, blksize, pst)| ClientBlockUpload::Initiate(
                    BlockUploadInitiate {
                        index,
                        sub,
                        crc,
                        blksize,
                        pst
                    }
                )
            ),
            Just(ClientBlockUpload::Start),
            (any::<u8>(), any::<u8>())
                .prop_map(|(ackseq, blksize)| ClientBlockUpload::Ack { ackseq, blksize }),
            Just(ClientBlockUpload::End),
        ]
        .prop_map(ClientCommand::BlockUpload),
        prop_oneof![
            (mux, any::<bool>(), any::<Option<u32>>()).prop_map(|((index, sub), crc, size)| {
                ClientBlockDownload::Initiate(BlockDataInitiate {
                    index,
                    sub,
                    crc,
                    size,
                })
            }),
            (0u8..=7, any::<u16>())
                .prop_map(|(unused, crc)| ClientBlockDownload::End { unused, crc }),
        ]
        .prop_map(ClientCommand::BlockDownload),
        // ccs = 7: what decodes to Unknown.
        (0xE0u8..=0xFF).prop_map(ClientCommand::Unknown),
    ]
}

fn server_command() -> impl Strategy<Value = ServerCommand> {
    let mux = (any::<u16>(), any::<u8>());
    prop_oneof![
        segment().prop_map(ServerCommand::UploadSegment),
        any::<bool>().prop_map(|toggle| ServerCommand::DownloadSegment { toggle }),
        (mux, initiate_payload()).prop_map(|((index, sub), payload)| {
            ServerCommand::InitiateUpload {
                index,
                sub,
                payload,
            }
        }),
        mux.prop_map(|(index, sub)| ServerCommand::InitiateDownload { index, sub }),
        (mux, abort_code()).prop_map(|((index, sub), code)| ServerCommand::Abort {
            index,
            sub,
            code
        }),
        prop_oneof![
            (mux, any::<bool>(), any::<u8>()).prop_map(|((index, sub), crc, blksize)| {
                ServerBlockDownload::Initiate(BlockDownloadAccept {
                    index,
                    sub,
                    crc,
                    blksize,
                })
            }),
            (any::<u8>(), any::<u8>())
                .prop_map(|(ackseq, blksize)| ServerBlockDownload::Ack { ackseq, blksize }),
            Just(ServerBlockDownload::End),
        ]
        .prop_map(ServerCommand::BlockDownload),
        prop_oneof![
            (mux, any::<bool>(), any::<Option<u32>>()).prop_map(|((index, sub), crc, size)| {
                ServerBlockUpload::Initiate(BlockDataInitiate {
                    index,
                    sub,
                    crc,
                    size,
                })
            }),
            (0u8..=7, any::<u16>())
                .prop_map(|(unused, crc)| ServerBlockUpload::End { unused, crc }),
        ]
        .prop_map(ServerCommand::BlockUpload),
        // scs = 7, or scs = 5 with ss = 3: what decodes to Unknown.
        prop_oneof![0xE0u8..=0xFF, (0u8..8).prop_map(|x| 0xA3 | x << 2)]
            .prop_map(ServerCommand::Unknown),
    ]
}

/// The one representation change of a `new`-built SDO frame: expedited data
/// without a size indication is "up to 4 bytes"; `new` sends DLC 8, so the
/// decoder sees all 4 data bytes (the value zero-padded).
fn expected_initiate(payload: InitiatePayload) -> InitiatePayload {
    match payload {
        InitiatePayload::Expedited {
            data,
            size_indicated: false,
        } => {
            let mut four = [0u8; 4];
            four[..data.len()].copy_from_slice(data.as_slice());
            InitiatePayload::Expedited {
                data: ExpeditedData::new(&four).unwrap(),
                size_indicated: false,
            }
        }
        other => other,
    }
}

fn expected_client(cmd: ClientCommand) -> ClientCommand {
    match cmd {
        ClientCommand::InitiateDownload {
            index,
            sub,
            payload,
        } => ClientCommand::InitiateDownload {
            index,
            sub,
            payload: expected_initiate(payload),
        },
        other => other,
    }
}

fn expected_server(cmd: ServerCommand) -> ServerCommand {
    match cmd {
        ServerCommand::InitiateUpload {
            index,
            sub,
            payload,
        } => ServerCommand::InitiateUpload {
            index,
            sub,
            payload: expected_initiate(payload),
        },
        other => other,
    }
}

/// Every typed message except SDO (compared by `==` directly).
fn plain_message() -> impl Strategy<Value = Message> {
    prop_oneof![
        (any::<u8>(), any::<u8>()).prop_map(|(cs, target)| Message::Nmt(NmtCommand {
            command: cs.into(),
            target: target.into(),
        })),
        (node_id(), any::<u8>()).prop_map(|(node, b)| Message::Heartbeat {
            node,
            heartbeat: Heartbeat::from_view(&HeartbeatFrame::from_byte(b)),
        }),
        (node_id(), 0u8..=8).prop_map(|(node, dlc)| Message::NodeGuardRequest { node, dlc }),
        (node_id(), any::<u16>(), any::<u8>(), any::<[u8; 5]>()).prop_map(
            |(node, code, reg, manufacturer)| Message::Emcy {
                node,
                emcy: Emergency {
                    code: ErrorCode(code),
                    register: ErrorRegister::from_bits_retain(reg),
                    manufacturer,
                },
            }
        ),
        any::<Option<u8>>().prop_map(|counter| Message::Sync(SyncMessage { counter })),
        (0u32..=0x0FFF_FFFF, any::<u16>(), 0u8..=0x0F).prop_map(|(millis, days, reserved)| {
            Message::Time(TimeOfDay {
                millis,
                days,
                reserved,
            })
        }),
        (pdo_number(), node_id(), payload()).prop_map(|(pdo, node, payload)| Message::Tpdo {
            pdo,
            node,
            payload
        }),
        (pdo_number(), node_id(), 0u8..=8).prop_map(|(pdo, node, dlc)| Message::TpdoRequest {
            pdo,
            node,
            dlc
        }),
        (pdo_number(), node_id(), payload()).prop_map(|(pdo, node, payload)| Message::Rpdo {
            pdo,
            node,
            payload
        }),
        (
            prop_oneof![
                Just(LssDirection::MasterToSlave),
                Just(LssDirection::SlaveToMaster)
            ],
            payload()
        )
            .prop_map(|(direction, payload)| {
                Message::Lss(
                    LssMessage::parse(direction, payload.as_slice()).expect("0..=8 bytes decode"),
                )
            }),
    ]
}

proptest! {
    #![proptest_config(config())]

    /// (b) Typed NMT, heartbeat, guarding, EMCY, SYNC, TIME, PDO and LSS
    /// messages: `decode(encode(m)) == m`.
    #[test]
    fn typed_messages_round_trip(m in plain_message()) {
        let frame = m.encode();
        prop_assert_eq!(Message::decode(&frame), Ok(m), "frame {}", frame);
    }

    /// (b) SDO requests built from typed `ClientCommand`s.
    #[test]
    fn typed_sdo_requests_round_trip(node in node_id(), cmd in client_command()) {
        let sent = Message::SdoRequest { node, sdo: SdoRequest::new(cmd) };
        let frame = sent.encode();
        prop_assert_eq!(frame.dlc(), 8, "new() sends DLC 8");
        let got = Message::decode(&frame);
        let Ok(Message::SdoRequest { node: got_node, sdo }) = got else {
            return Err(TestCaseError::fail(format!("{frame} decoded to {got:?}")));
        };
        prop_assert_eq!(got_node, node);
        prop_assert_eq!(sdo.command, expected_client(cmd), "frame {}", frame);
        // And the decoded form is a fixed point.
        prop_assert_eq!(Message::SdoRequest { node, sdo }.encode(), frame);
    }

    /// (b) SDO responses built from typed `ServerCommand`s.
    #[test]
    fn typed_sdo_responses_round_trip(node in node_id(), cmd in server_command()) {
        let sent = Message::SdoResponse { node, sdo: SdoResponse::new(cmd) };
        let frame = sent.encode();
        prop_assert_eq!(frame.dlc(), 8, "new() sends DLC 8");
        let got = Message::decode(&frame);
        let Ok(Message::SdoResponse { node: got_node, sdo }) = got else {
            return Err(TestCaseError::fail(format!("{frame} decoded to {got:?}")));
        };
        prop_assert_eq!(got_node, node);
        prop_assert_eq!(sdo.command, expected_server(cmd), "frame {}", frame);
        prop_assert_eq!(Message::SdoResponse { node, sdo }.encode(), frame);
    }

    /// Abort codes: `u32 -> AbortCode -> u32` is lossless for every value.
    #[test]
    fn abort_code_u32_is_lossless(raw in any::<u32>()) {
        prop_assert_eq!(u32::from(AbortCode::from(raw)), raw);
    }
}
