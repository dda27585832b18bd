//! Byte vectors of the NMT wire layer: parse, emit, round trip, lengths.

use super::*;
use crate::wire::assert_round_trip;
use std::string::ToString;

fn n(raw: u8) -> NodeId {
    NodeId::new(raw).unwrap()
}

#[test]
fn public_vectors_n1_n2_n3() {
    let n1 = n(1);
    // [N1] start node 1, then operational heartbeat.
    let start = NmtCommand::parse(&[0x01, 0x01]).unwrap();
    assert_eq!(start.command, NmtCommandSpecifier::Start);
    assert_eq!(start.target, NmtTarget::Node(n1));
    assert_eq!(
        Heartbeat::parse(&[0x05]).unwrap().state,
        NmtState::Operational
    );
    // [N2] reset communication node 1, boot-up.
    let rc = NmtCommand::parse(&[0x82, 0x01]).unwrap();
    assert_eq!(rc.command, NmtCommandSpecifier::ResetCommunication);
    assert!(Heartbeat::parse(&[0x00]).unwrap().is_boot_up());
    // [N3] all nodes pre-operational.
    let pre = NmtCommand::parse(&[0x80, 0x00]).unwrap();
    assert_eq!(pre.command, NmtCommandSpecifier::EnterPreOperational);
    assert_eq!(pre.target, NmtTarget::All);
    assert!(pre.target.addresses(n1));
}

#[test]
fn nmt_command_emits_its_two_bytes() {
    let cmd = NmtCommand {
        command: NmtCommandSpecifier::ResetNode,
        target: NmtTarget::Node(n(10)),
    };
    let mut buf = [0xEE; 8];
    assert_eq!(cmd.emit(&mut buf), 2);
    assert_eq!(buf, [0x81, 0x0A, 0xEE, 0xEE, 0xEE, 0xEE, 0xEE, 0xEE]);
    assert_eq!(cmd.buffer_len(), 2);
    assert_eq!(
        cmd.to_frame_on(CanId::Standard(0)),
        CanFrame::standard(0, &[0x81, 0x0A]).unwrap()
    );
}

#[test]
fn every_command_and_target_byte_round_trips() {
    for cs in 0..=255u8 {
        for node in [0u8, 1, 10, 127, 128, 255] {
            assert!(assert_round_trip::<NmtCommand>(&[cs, node]).is_some());
        }
    }
    assert_eq!(
        NmtCommandSpecifier::from(0x81),
        NmtCommandSpecifier::ResetNode
    );
    assert_eq!(
        NmtCommandSpecifier::from(0x03),
        NmtCommandSpecifier::Unknown(0x03)
    );
    assert_eq!(NmtTarget::from(200), NmtTarget::Invalid(200));
    assert!(!NmtTarget::Invalid(200).addresses(NodeId::MIN));
}

#[test]
fn every_heartbeat_byte_round_trips() {
    for b in 0..=255u8 {
        let hb = assert_round_trip::<Heartbeat>(&[b]).unwrap();
        assert_eq!(hb.byte(), b);
        assert_eq!(hb.toggle, b & 0x80 != 0);
    }
    assert_eq!(Heartbeat::parse(&[0x04]).unwrap().state, NmtState::Stopped);
    assert_eq!(
        Heartbeat::parse(&[0x06]).unwrap().state,
        NmtState::Unknown(0x06)
    );
}

#[test]
fn lengths() {
    crate::error::assert_exact_length(NmtCommand::parse, 2);
    crate::error::assert_exact_length(NmtFrame::new_checked, 2);
    crate::error::assert_exact_length(Heartbeat::parse, 1);
    crate::error::assert_exact_length(HeartbeatFrame::new_checked, 1);
}

#[test]
fn heartbeat_of_a_frame_agrees_with_parse_of_its_bytes() {
    for len in 0..=8usize {
        for b0 in [0x00, 0x05, 0x7F, 0x85, 0xFF] {
            let bytes = [b0, 1, 2, 3, 4, 5, 6, 7];
            let frame = CanFrame::standard(0x70A, &bytes[..len]).unwrap();
            assert_eq!(
                Heartbeat::parse_frame(&frame),
                Heartbeat::parse(&bytes[..len]),
                "{frame}"
            );
        }
    }
    let remote = guard_request(n(10));
    assert_eq!(
        Heartbeat::parse_frame(&remote),
        Err(DecodeError::UnexpectedRemote)
    );
}

#[test]
fn heartbeat_frames_and_guard_requests() {
    let node = n(10);
    let reply = Heartbeat {
        state: NmtState::Operational,
        toggle: true,
    };
    assert_eq!(reply.to_frame(node).to_string(), "70A#85");
    assert_eq!(Heartbeat::BOOT_UP.to_frame(node).to_string(), "70A#00");
    let request = guard_request(node);
    assert!(request.is_remote());
    assert_eq!(request.dlc(), 1);
    assert_eq!(request.id(), CanId::Standard(0x70A));
    assert!(is_guard_request(&request, node));
    assert!(!is_guard_request(&request, n(11)));
    assert!(!is_guard_request(&reply.to_frame(node), node));
    // Any DLC is a request.
    let long = CanFrame::remote(CanId::Standard(0x70A), 8).unwrap();
    assert!(is_guard_request(&long, node));
}
