//! The LSS slave and master against each other and against hostile
//! sequences (CiA 305 "LSS protocol descriptions").

use core::time::Duration;
use std::string::ToString;
use std::vec::Vec;

use super::*;
use crate::clock::Timestamp;
use crate::cob_id::NodeId;
use crate::frame::CanFrame;
use crate::machine::{assert_quiet_until, Machine};
use crate::wire::Codec;

const A: LssAddress = LssAddress {
    vendor: 0x0000_029A,
    product: 0x0001_0203,
    revision: 0x0000_0102,
    serial: 0x8000_0001,
};

fn slave() -> LssSlave {
    LssSlave::new(LssSlaveConfig::new(A, None))
}

fn req(r: LssRequest) -> CanFrame {
    let mut buf = [0; 8];
    let n = r.emit(&mut buf);
    CanFrame::standard(0x7E5, &buf[..n]).unwrap()
}

fn answers(s: &mut LssSlave, r: LssRequest) -> Vec<LssResponse> {
    s.handle_frame(Timestamp::ZERO, &req(r));
    let mut out = Vec::new();
    while let Some(f) = s.poll_transmit() {
        assert_eq!(f.id().raw(), 0x7E4);
        out.push(LssResponse::parse(f.data()).unwrap());
    }
    out
}

fn scan(id_number: u32, bit_checked: u8, sub: u8, next: u8) -> LssRequest {
    LssRequest::Fastscan(Fastscan {
        id_number,
        bit_checked,
        sub,
        next,
    })
}

#[test]
fn selective_switch_needs_all_four_parts_in_order() {
    let mut s = slave();
    use LssField::*;
    for f in [Vendor, Product, Revision] {
        assert!(answers(&mut s, LssRequest::SwitchStateSelective(f, A.get(f))).is_empty());
    }
    // A wrong serial: no answer, still waiting.
    assert!(answers(&mut s, LssRequest::SwitchStateSelective(Serial, 0)).is_empty());
    assert_eq!(s.state(), LssState::Waiting);
    // Serial alone after the failure: the sequence restarted.
    assert!(answers(&mut s, LssRequest::SwitchStateSelective(Serial, A.serial)).is_empty());
    for f in LssField::ALL {
        let got = answers(&mut s, LssRequest::SwitchStateSelective(f, A.get(f)));
        assert_eq!(got.is_empty(), f != Serial);
    }
    assert_eq!(s.state(), LssState::Configuration);
}

#[test]
fn configuration_services_only_in_configuration_state() {
    let mut s = slave();
    let inquire = LssRequest::Inquire(LssInquiry::NodeId);
    assert!(answers(&mut s, inquire).is_empty());
    assert!(answers(&mut s, LssRequest::ConfigureNodeId(5)).is_empty());
    assert!(answers(&mut s, LssRequest::StoreConfiguration).is_empty());
    answers(
        &mut s,
        LssRequest::SwitchStateGlobal(LssMode::Configuration),
    );
    assert_eq!(answers(&mut s, inquire), [LssResponse::NodeId(0xFF)]);
    for f in LssField::ALL {
        let got = answers(&mut s, LssRequest::Inquire(LssInquiry::Address(f)));
        assert_eq!(got, [LssResponse::Address(f, A.get(f))]);
    }
    let refused = LssResponse::ConfigureNodeId(LssStatus::new(LssErrorCode::Refused));
    for bad in [0u8, 128, 200, 254] {
        assert_eq!(answers(&mut s, LssRequest::ConfigureNodeId(bad)), [refused]);
        assert_eq!(s.pending_node_id(), None);
    }
    let ok = LssResponse::ConfigureNodeId(LssStatus::OK);
    assert_eq!(answers(&mut s, LssRequest::ConfigureNodeId(127)), [ok]);
    assert_eq!(s.pending_node_id(), NodeId::new(127));
    assert_eq!(s.node_id(), None, "pending until reset communication");
    assert_eq!(answers(&mut s, LssRequest::ConfigureNodeId(255)), [ok]);
    assert_eq!(s.pending_node_id(), None);
    assert_eq!(answers(&mut s, LssRequest::ConfigureNodeId(9)), [ok]);
    // Store: an event the application answers.
    assert!(answers(&mut s, LssRequest::StoreConfiguration).is_empty());
    let mut stored = None;
    while let Some(e) = s.poll_event() {
        if let LssSlaveEvent::StoreRequested { node_id, .. } = e {
            stored = Some(node_id);
        }
    }
    assert_eq!(stored, Some(NodeId::new(9)));
    assert!(s.answer_store(LssStatus::OK));
    assert!(!s.answer_store(LssStatus::OK), "one answer per request");
    assert_eq!(
        LssResponse::parse(s.poll_transmit().unwrap().data()).unwrap(),
        LssResponse::StoreConfiguration(LssStatus::OK)
    );
    // Bit timing is refused by default.
    let bt = LssRequest::ConfigureBitTiming { table: 0, index: 3 };
    assert_eq!(
        answers(&mut s, bt),
        [LssResponse::ConfigureBitTiming(LssStatus::new(
            LssErrorCode::Refused
        ))]
    );
    // Back to waiting: the unconfigured slave asks for a reset.
    answers(&mut s, LssRequest::SwitchStateGlobal(LssMode::Waiting));
    let mut events = Vec::new();
    while let Some(e) = s.poll_event() {
        events.push(e);
    }
    assert_eq!(
        events.last(),
        Some(&LssSlaveEvent::ResetCommunication),
        "{events:?}"
    );
    assert_eq!(s.reset_communication(), NodeId::new(9));
}

#[test]
fn store_unsupported_and_bit_timing_supported() {
    let mut c = LssSlaveConfig::new(A, NodeId::new(3));
    c.store_supported = false;
    c.bit_timing_supported = true;
    let mut s = LssSlave::new(c);
    answers(
        &mut s,
        LssRequest::SwitchStateGlobal(LssMode::Configuration),
    );
    assert_eq!(
        answers(&mut s, LssRequest::StoreConfiguration),
        [LssResponse::StoreConfiguration(LssStatus::new(
            LssErrorCode::Refused
        ))]
    );
    for (table, index, good) in [(0, 0, true), (0, 8, true), (0, 9, false), (1, 0, false)] {
        let got = answers(&mut s, LssRequest::ConfigureBitTiming { table, index });
        assert_eq!(got.len(), 1);
        assert_eq!(
            got.first(),
            Some(&LssResponse::ConfigureBitTiming(if good {
                LssStatus::OK
            } else {
                LssStatus::new(LssErrorCode::Refused)
            }))
        );
    }
    // A configured slave takes no part in fastscan or identify non-configured.
    answers(&mut s, LssRequest::SwitchStateGlobal(LssMode::Waiting));
    assert!(answers(&mut s, scan(0, 0x80, 0, 0)).is_empty());
    assert!(answers(&mut s, LssRequest::IdentifyNonConfigured).is_empty());
    while let Some(e) = s.poll_event() {
        assert_ne!(
            e,
            LssSlaveEvent::ResetCommunication,
            "a configured slave is reset by NMT"
        );
    }
}

#[test]
fn identify_remote_slave_ranges() {
    let mut s = slave();
    let send = |s: &mut LssSlave, parts: [u32; 6]| {
        let mut got = Vec::new();
        for (p, v) in IdentifyPart::ALL.into_iter().zip(parts) {
            got.extend(answers(s, LssRequest::IdentifyRemoteSlave(p, v)));
        }
        got
    };
    let yes = [LssResponse::IdentifySlave];
    assert_eq!(
        send(&mut s, [A.vendor, A.product, 0, u32::MAX, 0, u32::MAX]),
        yes
    );
    assert_eq!(
        send(
            &mut s,
            [A.vendor, A.product, A.revision, A.revision, A.serial, A.serial]
        ),
        yes
    );
    assert!(send(
        &mut s,
        [A.vendor, A.product, 0, u32::MAX, A.serial + 1, u32::MAX]
    )
    .is_empty());
    assert!(send(&mut s, [A.vendor + 1, A.product, 0, u32::MAX, 0, u32::MAX]).is_empty());
    assert!(send(
        &mut s,
        [A.vendor, A.product, A.revision + 1, u32::MAX, 0, u32::MAX]
    )
    .is_empty());
    assert_eq!(
        answers(&mut s, LssRequest::IdentifyNonConfigured),
        [LssResponse::IdentifyNonConfigured]
    );
}

/// Sequences that crashed another Rust LSS stack end cleanly here: BitChecked
/// 32..=127 and 81h..=FFh, LSSSub and LSSNext above 3, every shift.
#[test]
fn hostile_fastscan_values_are_ignored() {
    let mut s = slave();
    assert_eq!(
        answers(&mut s, scan(0, 0x80, 0, 0)),
        [LssResponse::IdentifySlave]
    );
    for bit in (32..=0x7F).chain(0x81..=0xFF) {
        assert!(
            answers(&mut s, scan(A.vendor, bit, 0, 0)).is_empty(),
            "bit {bit}"
        );
    }
    for (sub, next) in [(4, 0), (0, 4), (255, 255), (3, 200), (200, 3)] {
        for bit in [0, 1, 31] {
            assert!(answers(&mut s, scan(A.vendor, bit, sub, next)).is_empty());
        }
    }
    // Every shift of the mask, matching and not matching.
    for bit in 0..=31u8 {
        assert_eq!(
            answers(&mut s, scan(A.vendor, bit, 0, 0)).len(),
            1,
            "bit {bit}"
        );
        let flipped = A.vendor ^ (1u32 << bit);
        assert!(
            answers(&mut s, scan(flipped, bit, 0, 0)).is_empty(),
            "bit {bit}"
        );
    }
    // The search goes on normally afterwards.
    assert_eq!(s.state(), LssState::Waiting);
    let mut m = LssMaster::new(Duration::from_millis(5));
    assert_eq!(
        run_scan(&mut m, &mut [&mut s]),
        LssMasterEvent::FastscanFound(A)
    );
    assert_eq!(s.state(), LssState::Configuration);
}

fn run_scan(m: &mut LssMaster, slaves: &mut [&mut LssSlave]) -> LssMasterEvent {
    let mut now = Timestamp::ZERO;
    m.fastscan(now).unwrap();
    let mut result = None;
    for _ in 0..200 {
        while let Some(f) = m.poll_transmit() {
            for s in slaves.iter_mut() {
                s.handle_frame(now, &f);
            }
        }
        for s in slaves.iter_mut() {
            while let Some(f) = s.poll_transmit() {
                m.handle_frame(now, &f);
            }
        }
        while let Some(e) = m.poll_event() {
            assert!(result.is_none(), "one end per search");
            result = Some(e);
        }
        let Some(t) = m.poll_timeout() else { break };
        now = t;
        m.handle_timeout(now);
    }
    assert!(!m.is_busy());
    result.expect("the search ended")
}

/// The slave in configuration gets node-ID `node`, is switched to waiting
/// and resets communication: it has a node-ID and takes no part in the
/// next Fastscan.
fn configure_and_leave(slave: &mut LssSlave, node: u8) {
    slave.handle_frame(Timestamp::ZERO, &req(LssRequest::ConfigureNodeId(node)));
    let waiting = req(LssRequest::SwitchStateGlobal(LssMode::Waiting));
    slave.handle_frame(Timestamp::ZERO, &waiting);
    slave.reset_communication();
    while slave.poll_transmit().is_some() {}
}

#[test]
fn fastscan_finds_the_lowest_address_then_the_next() {
    let b = LssAddress {
        serial: A.serial - 1,
        ..A
    };
    let mut s1 = slave();
    let mut s2 = LssSlave::new(LssSlaveConfig::new(b, None));
    let mut m = LssMaster::new(Duration::from_millis(5));
    assert_eq!(
        run_scan(&mut m, &mut [&mut s1, &mut s2]),
        LssMasterEvent::FastscanFound(b)
    );
    assert_eq!(s2.state(), LssState::Configuration);
    assert_eq!(s1.state(), LssState::Waiting);
    // s2 gets a node-ID; after switching to waiting it resets and is out.
    configure_and_leave(&mut s2, 6);
    assert_eq!(
        run_scan(&mut m, &mut [&mut s1, &mut s2]),
        LssMasterEvent::FastscanFound(A)
    );
    // Nobody left: not found, once.
    configure_and_leave(&mut s1, 5);
    assert_eq!(
        run_scan(&mut m, &mut [&mut s1, &mut s2]),
        LssMasterEvent::FastscanNotFound
    );
    assert_eq!(run_scan(&mut m, &mut []), LssMasterEvent::FastscanNotFound);
}

#[test]
fn master_confirmed_services_and_timeouts() {
    let mut m = LssMaster::new(Duration::from_millis(10));
    let t = Timestamp::ZERO;
    m.configure_node_id(t, NodeId::new(5)).unwrap();
    assert_eq!(m.configure_node_id(t, None), Err(LssMasterError::Busy));
    assert_eq!(m.fastscan(t), Err(LssMasterError::Busy));
    assert_eq!(
        m.poll_transmit().unwrap().to_string(),
        "7E5#1105000000000000"
    );
    assert_quiet_until(&mut m, Timestamp::from_millis(10));
    assert_eq!(m.poll_event(), None);
    m.handle_timeout(Timestamp::from_millis(10));
    assert_eq!(
        m.poll_event(),
        Some(LssMasterEvent::NoResponse(LssService::ConfigureNodeId))
    );
    assert_eq!(m.poll_timeout(), None);
    // Against a slave.
    let mut s = slave();
    let exchange = |m: &mut LssMaster, s: &mut LssSlave| {
        while let Some(f) = m.poll_transmit() {
            s.handle_frame(t, &f);
        }
        while let Some(f) = s.poll_transmit() {
            m.handle_frame(t, &f);
        }
        m.poll_event()
    };
    // Each service against the slave and the event it ends in.
    type Service = fn(&mut LssMaster, Timestamp) -> Result<(), LssMasterError>;
    let services: [(Service, LssMasterEvent); 5] = [
        (
            |m, t| m.switch_state_selective(t, A),
            LssMasterEvent::SwitchedSelective,
        ),
        (
            |m, t| m.inquire(t, LssInquiry::Address(LssField::Serial)),
            LssMasterEvent::Address(LssField::Serial, A.serial),
        ),
        (
            |m, t| m.inquire(t, LssInquiry::NodeId),
            LssMasterEvent::NodeId(None),
        ),
        (
            |m, t| m.configure_node_id(t, NodeId::new(5)),
            LssMasterEvent::NodeIdConfigured(LssStatus::OK),
        ),
        (
            |m, t| m.configure_bit_timing(t, 0, 2),
            LssMasterEvent::BitTimingConfigured(LssStatus::new(LssErrorCode::Refused)),
        ),
    ];
    for (service, want) in services {
        service(&mut m, t).unwrap();
        assert_eq!(exchange(&mut m, &mut s), Some(want));
    }
    m.store_configuration(t).unwrap();
    assert_eq!(exchange(&mut m, &mut s), None);
    assert!(s.answer_store(LssStatus::new(LssErrorCode::StorageAccess)));
    assert_eq!(
        exchange(&mut m, &mut s),
        Some(LssMasterEvent::Stored(LssStatus::new(
            LssErrorCode::StorageAccess
        )))
    );
    m.identify_non_configured(t).unwrap();
    // A pending node-ID counts as configured: no answer.
    assert_eq!(exchange(&mut m, &mut s), None);
    m.handle_timeout(Timestamp::from_millis(10));
    assert_eq!(
        m.poll_event(),
        Some(LssMasterEvent::NoResponse(
            LssService::IdentifyNonConfigured
        ))
    );
    let mut fresh = slave();
    m.identify_non_configured(t).unwrap();
    assert_eq!(
        exchange(&mut m, &mut fresh),
        Some(LssMasterEvent::NonConfiguredPresent)
    );
}
