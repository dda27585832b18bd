use super::*;
use crate::frame::CanId;
use std::vec::Vec;

fn node() -> NodeId {
    NodeId::new(10).unwrap()
}

fn request() -> CanFrame {
    CanFrame::remote(CanId::Standard(0x70A), 1).unwrap()
}

fn reply(byte: u8) -> CanFrame {
    CanFrame::standard(0x70A, &[byte]).unwrap()
}

fn ms(v: u64) -> Timestamp {
    Timestamp::from_millis(v)
}

#[test]
fn slave_replies_with_state_and_alternating_toggle() {
    let mut s = GuardingSlave::new(node());
    let mut bytes = Vec::new();
    for (i, state) in [
        NmtState::PreOperational,
        NmtState::PreOperational,
        NmtState::Operational,
        NmtState::Operational,
        NmtState::Stopped,
        NmtState::Stopped,
    ]
    .into_iter()
    .enumerate()
    {
        s.set_state(state);
        s.handle_frame(ms(i as u64 * 10), &request());
        let f = s.poll_transmit().unwrap();
        assert_eq!(f.id(), CanId::Standard(0x70A));
        assert!(!f.is_remote());
        bytes.extend_from_slice(f.data());
        assert_eq!(s.poll_transmit(), None);
    }
    // CiA 301: toggle 0 first, then alternating; state in bits 6-0.
    assert_eq!(bytes, [0x7F, 0xFF, 0x05, 0x85, 0x04, 0x84]);
    // Reset communication: toggle back to 0.
    s.reset();
    s.handle_frame(ms(100), &request());
    assert_eq!(s.poll_transmit().unwrap().data(), &[0x04]);
}

#[test]
fn slave_ignores_other_frames() {
    let mut s = GuardingSlave::new(node());
    s.set_state(NmtState::Operational);
    for f in [
        CanFrame::remote(CanId::Standard(0x70B), 1).unwrap(),
        reply(0x05),
        CanFrame::remote(CanId::Extended(0x70A), 1).unwrap(),
        CanFrame::standard(0x000, &[0x01, 0x0A]).unwrap(),
    ] {
        s.handle_frame(ms(0), &f);
        assert_eq!(s.poll_transmit(), None, "{f}");
    }
    // Any DLC of the remote request is answered.
    s.handle_frame(ms(0), &CanFrame::remote(CanId::Standard(0x70A), 0).unwrap());
    assert_eq!(s.poll_transmit().unwrap().data(), &[0x05]);
}

#[test]
fn life_guarding_needs_a_request_and_both_objects() {
    let mut s = GuardingSlave::new(node());
    s.set_life_guarding(ms(0), Duration::from_millis(100), 3);
    // No request yet: no supervision.
    assert!(!s.life_guarding_active());
    assert_eq!(s.poll_timeout(), None);
    s.handle_frame(ms(50), &request());
    let _ = s.poll_transmit();
    assert!(s.life_guarding_active());
    assert_eq!(s.poll_timeout(), Some(ms(350)));
    s.handle_timeout(ms(349));
    assert_eq!(s.poll_event(), None);
    s.handle_timeout(ms(350));
    assert_eq!(s.poll_event(), Some(SlaveGuardingEvent::LifeGuardingLost));
    assert!(s.is_master_lost());
    // Reported once.
    assert_eq!(s.poll_timeout(), None);
    s.handle_timeout(ms(10_000));
    assert_eq!(s.poll_event(), None);
    s.handle_frame(ms(10_000), &request());
    assert_eq!(
        s.poll_event(),
        Some(SlaveGuardingEvent::LifeGuardingResumed)
    );
    assert_eq!(s.poll_timeout(), Some(ms(10_300)));
    // Factor 0 or guard time 0: off.
    for (guard, factor) in [(0, 3), (100, 0)] {
        s.set_life_guarding(ms(10_000), Duration::from_millis(guard), factor);
        assert!(!s.life_guarding_active());
        assert_eq!(s.poll_timeout(), None);
    }
}

#[test]
fn heartbeat_disables_guarding() {
    let mut s = GuardingSlave::new(node());
    s.set_state(NmtState::Operational);
    s.set_life_guarding(ms(0), Duration::from_millis(100), 2);
    s.handle_frame(ms(0), &request());
    assert_eq!(s.poll_transmit().unwrap().data(), &[0x05]);
    s.set_heartbeat_active(ms(10), true);
    assert_eq!(s.poll_timeout(), None);
    s.handle_frame(ms(20), &request());
    assert_eq!(s.poll_transmit(), None);
    s.handle_timeout(ms(1000));
    assert_eq!(s.poll_event(), None);
    s.set_heartbeat_active(ms(1000), false);
    assert_eq!(s.poll_timeout(), Some(ms(1200)));
    s.handle_frame(ms(1010), &request());
    assert_eq!(s.poll_transmit().unwrap().data(), &[0x85]);
}

#[test]
fn master_requests_every_guard_time() {
    let mut m = GuardingMaster::new(node(), Duration::from_millis(100), 3);
    assert_eq!(m.node_life_time(), Duration::from_millis(300));
    assert_eq!(m.poll_timeout(), None);
    m.start(ms(0));
    assert_eq!(m.poll_transmit(), Some(request()));
    let mut at = Vec::new();
    crate::machine::drive_timers(&mut m, ms(350), |t, f| {
        assert!(f.is_remote());
        assert_eq!(f.id(), CanId::Standard(0x70A));
        at.push(t.as_millis());
    });
    assert_eq!(at, [100, 200, 300]);
    m.stop();
    assert_eq!(m.poll_timeout(), None);
    // Guard time 0: no requests.
    let mut z = GuardingMaster::new(node(), Duration::ZERO, 3);
    z.start(ms(0));
    assert_eq!((z.poll_transmit(), z.poll_timeout()), (None, None));
}

#[test]
fn master_lost_restored_toggle_and_state() {
    let n = node();
    let mut m = GuardingMaster::new(n, Duration::from_millis(100), 2);
    m.set_expected_state(Some(NmtState::Operational));
    m.start(ms(0));
    let _ = m.poll_transmit();
    m.handle_frame(ms(1), &reply(0x05));
    assert_eq!(m.state(), Some(NmtState::Operational));
    assert_eq!(m.poll_event(), None);
    // A reply without a request is ignored.
    m.handle_frame(ms(2), &reply(0x85));
    m.handle_timeout(ms(100));
    // Repeated toggle 0: a toggle error, not a reply.
    m.handle_frame(ms(101), &reply(0x05));
    assert_eq!(
        m.poll_event(),
        Some(MasterGuardingEvent::ToggleError {
            node: n,
            toggle: false
        })
    );
    m.handle_timeout(ms(200));
    assert_eq!(m.poll_event(), None);
    m.handle_timeout(ms(300));
    assert_eq!(m.poll_event(), Some(MasterGuardingEvent::Lost(n)));
    assert!(m.is_lost());
    // After the toggle error the master expects toggle 1.
    m.handle_frame(ms(301), &reply(0x85));
    assert_eq!(
        m.poll_event(),
        Some(MasterGuardingEvent::Restored {
            node: n,
            state: NmtState::Operational
        })
    );
    // The node reports pre-operational: one mismatch, not one per reply.
    m.handle_timeout(ms(400));
    m.handle_frame(ms(401), &reply(0x7F));
    m.handle_timeout(ms(500));
    m.handle_frame(ms(501), &reply(0xFF));
    assert_eq!(
        m.poll_event(),
        Some(MasterGuardingEvent::StateMismatch {
            node: n,
            expected: NmtState::Operational,
            reported: NmtState::PreOperational
        })
    );
    assert_eq!(m.poll_event(), None);
    // Boot-up: the next reply must have toggle 0.
    m.handle_frame(ms(550), &reply(0x00));
    assert_eq!(m.poll_event(), Some(MasterGuardingEvent::BootUp(n)));
    m.handle_timeout(ms(600));
    m.handle_frame(ms(601), &reply(0xFF));
    assert!(matches!(
        m.poll_event(),
        Some(MasterGuardingEvent::ToggleError { toggle: true, .. })
    ));
    assert_eq!(m.events_dropped(), 0);
}

#[test]
fn master_factor_zero_counts_as_one_and_late_calls_do_not_drift() {
    let n = node();
    let mut m = GuardingMaster::new(n, Duration::from_millis(100), 0);
    assert_eq!(m.node_life_time(), Duration::from_millis(100));
    m.start(ms(0));
    m.handle_timeout(ms(150));
    assert_eq!(m.poll_event(), Some(MasterGuardingEvent::Lost(n)));
    assert_eq!(m.poll_timeout(), Some(ms(200)));
    // A call far too late: the next request one guard time from then.
    m.handle_timeout(ms(1000));
    assert_eq!(m.poll_timeout(), Some(ms(1100)));
    // The end of the clock: expired once, not re-armed in the past.
    m.handle_timeout(Timestamp::MAX);
    assert_eq!(m.poll_timeout(), None);
}
