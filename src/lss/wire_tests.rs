//! Byte vectors for every LSS service of CiA 305 ("Layer setting services
//! and protocol", section 4), one row per command specifier and direction.

use super::*;
use crate::bytes::Payload;
use crate::cob_id::LssDirection;
use crate::error::DecodeError;
use crate::wire::Codec;
use std::string::ToString;

/// `bytes` decode as `want` with `decode`, and `want` encodes (8 bytes,
/// every byte written) as `bytes` with `encode`.
fn round_trip<T: PartialEq + core::fmt::Debug, E: core::fmt::Debug>(
    bytes: [u8; 8],
    want: T,
    decode: fn(&[u8]) -> Result<T, E>,
    encode: fn(&T, &mut [u8; 8]) -> usize,
) {
    assert_eq!(decode(&bytes).unwrap(), want, "{bytes:02X?}");
    let mut buf = [0xAA; 8];
    assert_eq!(encode(&want, &mut buf), 8);
    assert_eq!(buf, bytes);
}

fn req(bytes: [u8; 8], want: LssRequest) {
    round_trip(bytes, want, LssRequest::parse, |r, buf| r.emit(buf));
}

fn resp(bytes: [u8; 8], want: LssResponse) {
    round_trip(bytes, want, LssResponse::parse, |r, buf| r.emit(buf));
}

#[test]
fn every_master_request() {
    use LssRequest as R;
    req(
        [0x04, 0, 0, 0, 0, 0, 0, 0],
        R::SwitchStateGlobal(LssMode::Waiting),
    );
    req(
        [0x04, 1, 0, 0, 0, 0, 0, 0],
        R::SwitchStateGlobal(LssMode::Configuration),
    );
    req(
        [0x04, 7, 0, 0, 0, 0, 0, 0],
        R::SwitchStateGlobal(LssMode::Unknown(7)),
    );
    let v = [0x9A, 0x02, 0, 0];
    for (cs, field) in [0x40, 0x41, 0x42, 0x43].into_iter().zip(LssField::ALL) {
        req(
            [cs, v[0], v[1], v[2], v[3], 0, 0, 0],
            R::SwitchStateSelective(field, 0x29A),
        );
    }
    req([0x11, 5, 0, 0, 0, 0, 0, 0], R::ConfigureNodeId(5));
    req([0x11, 0xFF, 0, 0, 0, 0, 0, 0], R::ConfigureNodeId(255));
    req(
        [0x13, 0, 3, 0, 0, 0, 0, 0],
        R::ConfigureBitTiming { table: 0, index: 3 },
    );
    req(
        [0x15, 0xE8, 0x03, 0, 0, 0, 0, 0],
        R::ActivateBitTiming { delay_ms: 1000 },
    );
    req([0x17, 0, 0, 0, 0, 0, 0, 0], R::StoreConfiguration);
    for (cs, field) in [0x5A, 0x5B, 0x5C, 0x5D].into_iter().zip(LssField::ALL) {
        req(
            [cs, 0, 0, 0, 0, 0, 0, 0],
            R::Inquire(LssInquiry::Address(field)),
        );
    }
    req([0x5E, 0, 0, 0, 0, 0, 0, 0], R::Inquire(LssInquiry::NodeId));
    for (cs, part) in (0x46..=0x4B).zip(IdentifyPart::ALL) {
        req(
            [cs, 0x78, 0x56, 0x34, 0x12, 0, 0, 0],
            R::IdentifyRemoteSlave(part, 0x1234_5678),
        );
    }
    req([0x4C, 0, 0, 0, 0, 0, 0, 0], R::IdentifyNonConfigured);
    req(
        [0x51, 0x78, 0x56, 0x34, 0x12, 31, 2, 3],
        R::Fastscan(Fastscan {
            id_number: 0x1234_5678,
            bit_checked: 31,
            sub: 2,
            next: 3,
        }),
    );
    req(
        [0x51, 0, 0, 0, 0, 0x80, 0, 0],
        R::Fastscan(Fastscan {
            id_number: 0,
            bit_checked: Fastscan::RESET,
            sub: 0,
            next: 0,
        }),
    );
}

#[test]
fn every_slave_response() {
    use LssResponse as R;
    resp([0x44, 0, 0, 0, 0, 0, 0, 0], R::SwitchStateSelective);
    resp(
        [0x11, 0, 0, 0, 0, 0, 0, 0],
        R::ConfigureNodeId(LssStatus::OK),
    );
    resp(
        [0x11, 1, 0, 0, 0, 0, 0, 0],
        R::ConfigureNodeId(LssStatus::new(LssErrorCode::Refused)),
    );
    resp(
        [0x11, 0xFF, 0x2A, 0, 0, 0, 0, 0],
        R::ConfigureNodeId(LssStatus {
            code: LssErrorCode::ImplementationSpecific,
            specific: 0x2A,
        }),
    );
    resp(
        [0x13, 1, 0, 0, 0, 0, 0, 0],
        R::ConfigureBitTiming(LssStatus::new(LssErrorCode::Refused)),
    );
    resp(
        [0x17, 2, 0, 0, 0, 0, 0, 0],
        R::StoreConfiguration(LssStatus::new(LssErrorCode::StorageAccess)),
    );
    resp(
        [0x17, 9, 0, 0, 0, 0, 0, 0],
        R::StoreConfiguration(LssStatus::new(LssErrorCode::Reserved(9))),
    );
    for (cs, field) in [0x5A, 0x5B, 0x5C, 0x5D].into_iter().zip(LssField::ALL) {
        resp(
            [cs, 0x78, 0x56, 0x34, 0x12, 0, 0, 0],
            R::Address(field, 0x1234_5678),
        );
    }
    resp([0x5E, 5, 0, 0, 0, 0, 0, 0], R::NodeId(5));
    resp([0x4F, 0, 0, 0, 0, 0, 0, 0], R::IdentifySlave);
    resp([0x50, 0, 0, 0, 0, 0, 0, 0], R::IdentifyNonConfigured);
}

#[test]
fn error_codes_round_trip_every_byte() {
    for raw in 0..=255u8 {
        assert_eq!(u8::from(LssErrorCode::from(raw)), raw);
        assert_eq!(u8::from(LssMode::from(raw)), raw);
    }
    assert_eq!(LssErrorCode::from(0), LssErrorCode::Success);
    assert_eq!(LssErrorCode::from(1), LssErrorCode::Refused);
    assert_eq!(LssErrorCode::from(2), LssErrorCode::StorageAccess);
    assert_eq!(
        LssErrorCode::from(255),
        LssErrorCode::ImplementationSpecific
    );
}

#[test]
fn unlisted_short_and_nonzero_reserved_frames_are_kept_raw() {
    let cases: [&[u8]; 6] = [
        &[0x99, 1, 2, 3, 4, 5, 6, 7],    // unknown cs
        &[0x04, 1],                      // short
        &[],                             // empty
        &[0x04, 1, 0, 0, 0, 0, 0, 9],    // reserved byte set
        &[0x17, 0, 0, 0, 0, 0, 0, 1],    // reserved byte set
        &[0x44, 0, 0, 0, 0, 0, 0, 0xFF], // a response cs on the request id
    ];
    for bytes in cases {
        let r = LssRequest::parse(bytes).unwrap();
        assert_eq!(r, LssRequest::Other(Payload::new(bytes).unwrap()));
        let mut buf = [0; 8];
        let n = r.emit(&mut buf);
        assert_eq!(&buf[..n], bytes);
        assert_eq!(r.buffer_len(), bytes.len());
        let s = LssResponse::parse(bytes).unwrap();
        let n = s.emit(&mut buf);
        assert_eq!(&buf[..n], bytes);
        assert_eq!(s.buffer_len(), bytes.len());
    }
    // A request cs on the response id is not a response.
    assert!(matches!(
        LssResponse::parse(&[0x51, 0, 0, 0, 0, 0x80, 0, 0]).unwrap(),
        LssResponse::Other(_)
    ));
    assert!(LssRequest::parse(&[0; 9]).is_err());
}

#[test]
fn the_checked_view_splits_service_frames_only() {
    let f = LssFrame::new_checked(&[0x51, 1, 2, 3, 4, 31, 2, 3]).unwrap();
    assert_eq!(f.service(), Some((0x51, [1, 2, 3, 4, 31, 2, 3])));
    assert_eq!(f.as_bytes(), &[0x51, 1, 2, 3, 4, 31, 2, 3]);
    for len in 0..8usize {
        let f = LssFrame::new_checked(&[0x5E; 8][..len]).unwrap();
        assert_eq!(f.service(), None, "{len} bytes");
        assert_eq!(f.as_bytes().len(), len);
    }
    assert_eq!(
        LssFrame::new_checked(&[0; 9]),
        Err(DecodeError::TooLong { max: 8, got: 9 })
    );
    // Typed services are 8 bytes, and the request round-trips through
    // the frame it builds.
    let r = LssRequest::SwitchStateGlobal(LssMode::Configuration);
    assert_eq!(r.buffer_len(), 8);
    assert_eq!(LssRequest::of_frame(&r.to_frame()), Some(r));
    let s = LssResponse::NodeId(5);
    assert_eq!(LssResponse::parse_frame(&s.to_frame()), Ok(s));
}

/// Frames in words: the direction, the data and what they say.
const WORDS: &[(LssDirection, &[u8], &str)] = {
    use LssDirection::{MasterToSlave as M, SlaveToMaster as S};
    &[
        (
            M,
            &[0x40, 0x9A, 0x02, 0, 0, 0, 0, 0],
            "LSS master: switch state selective vendor 0000029Ah",
        ),
        (
            M,
            &[0x51, 0x78, 0x56, 0x34, 0x12, 31, 0, 0],
            "LSS fastscan id 12345678 bit 31 sub 0 next 0",
        ),
        (S, &[0x4F, 0, 0, 0, 0, 0, 0, 0], "LSS slave: identify slave"),
        (
            M,
            &[0x04, 1, 0, 0, 0, 0, 0, 0],
            "LSS master: switch state global configuration",
        ),
        (
            M,
            &[0x11, 5, 0, 0, 0, 0, 0, 0],
            "LSS master: configure node-ID 5",
        ),
        (
            S,
            &[0x11, 1, 0, 0, 0, 0, 0, 0],
            "LSS slave: configure node-ID error 1 (refused)",
        ),
        (S, &[0x5E, 5, 0, 0, 0, 0, 0, 0], "LSS slave: node-ID 5"),
        (M, &[0x99], "LSS master: unknown [99]"),
    ]
};

#[test]
fn words() {
    for &(direction, data, words) in WORDS {
        let message = LssMessage::parse(direction, data).unwrap();
        assert_eq!(message.to_string(), words, "{data:02X?}");
    }
}

#[test]
fn address_fields() {
    let mut a = LssAddress::default();
    for (i, f) in LssField::ALL.into_iter().enumerate() {
        assert_eq!(f.index() as usize, i);
        assert_eq!(LssField::from_index(f.index()), Some(f));
        a.set(f, i as u32 + 10);
        assert_eq!(a.get(f), i as u32 + 10);
    }
    assert_eq!(LssField::from_index(4), None);
}

/// A message travels in the frame of its direction: `to_frame` makes it,
/// `of_frame` reads it back; the other direction's identifier and a remote
/// frame give none.
#[test]
fn messages_in_their_frames() {
    use crate::frame::{CanFrame, CanId};
    let request = LssRequest::SwitchStateGlobal(LssMode::Configuration);
    let frame = request.to_frame();
    assert_eq!(frame.to_string(), "7E5#0401000000000000");
    assert_eq!(LssRequest::of_frame(&frame), Some(request));
    assert_eq!(LssResponse::of_frame(&frame), None);
    let response = LssResponse::ConfigureNodeId(LssStatus::OK);
    let frame = response.to_frame();
    assert_eq!(frame.to_string(), "7E4#1100000000000000");
    assert_eq!(LssResponse::of_frame(&frame), Some(response));
    assert_eq!(LssRequest::of_frame(&frame), None);
    let remote = CanFrame::remote(CanId::Standard(0x7E5), 8).unwrap();
    assert_eq!(LssRequest::of_frame(&remote), None);
}
