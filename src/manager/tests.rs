//! The boot process step by step, with the frames a slave would answer.

use super::*;
use crate::abort::AbortCode;
use crate::machine::{drive_timers, Machine};
use crate::od::{Address, ConciseDcf, ConciseEntry};
use crate::sdo::AbortOrigin;
use crate::{CanFrame, NodeId, Timestamp};
use core::time::Duration;
use std::string::{String, ToString};
use std::vec::Vec;

fn t(ms: u64) -> Timestamp {
    Timestamp::from_millis(ms)
}

fn id(n: u8) -> NodeId {
    NodeId::new(n).unwrap()
}

/// Node `n`'s expedited answer to an upload of `index`:`sub`.
fn value(n: u8, index: u16, sub: u8, v: u32) -> CanFrame {
    let [lo, hi] = index.to_le_bytes();
    let [a, b, c, d] = v.to_le_bytes();
    CanFrame::standard(0x580 + u16::from(n), &[0x43, lo, hi, sub, a, b, c, d]).unwrap()
}

/// Node `n`'s abort of `index`:`sub`.
fn abort(n: u8, index: u16, sub: u8, code: u32) -> CanFrame {
    let [lo, hi] = index.to_le_bytes();
    let [a, b, c, d] = code.to_le_bytes();
    CanFrame::standard(0x580 + u16::from(n), &[0x80, lo, hi, sub, a, b, c, d]).unwrap()
}

fn beat(n: u8, state: u8) -> CanFrame {
    CanFrame::standard(0x700 + u16::from(n), &[state]).unwrap()
}

fn sent(m: &mut impl Machine) -> Vec<String> {
    core::iter::from_fn(|| m.poll_transmit())
        .map(|f| f.to_string())
        .collect()
}

fn events<M: Machine<Event = BootEvent>>(m: &mut M) -> Vec<BootEvent> {
    core::iter::from_fn(|| m.poll_event()).collect()
}

/// A manager of `nodes` (1F80h `startup`), started at 0 and past the
/// reset frames.
fn started(startup: NmtStartup, nodes: &[NodeConfig<'static>]) -> BootManager<'static, 4> {
    let config = ManagerConfig {
        startup,
        ..ManagerConfig::default()
    };
    let mut m = BootManager::new(config);
    for n in nodes {
        m.add_node(*n).unwrap();
    }
    m.start(t(0));
    let _ = sent(&mut m);
    m
}

/// Node 5 expecting device type 0x191 and vendor 0x2A.
fn node5() -> NodeConfig<'static> {
    let mut n = NodeConfig::new(id(5));
    n.expected.device_type = 0x191;
    n.expected.vendor_id = 0x2A;
    n
}

#[test]
fn an_absent_node_is_b_after_the_retries() {
    let mut m = started(NmtStartup::MASTER, &[node5()]);
    let mut frames = Vec::new();
    drive_timers(&mut m, t(5000), |at, f| {
        frames.push(std::format!("{} {f}", at.as_millis()));
    });
    // Three tries of 1000h 500 ms apart (after the 1 s boot-up wait), each
    // given up with an abort 05040000h.
    let (req, timeout) = ("605#4000100000000000", "605#8000100000000405");
    let want: Vec<String> = [
        (1000, req),
        (1500, timeout),
        (1500, req),
        (2000, timeout),
        (2000, req),
        (2500, timeout),
    ]
    .iter()
    .map(|(at, f)| std::format!("{at} {f}"))
    .collect();
    assert_eq!(frames, want);
    let code = AbortCode::SdoProtocolTimedOut;
    assert_eq!(
        events(&mut m),
        [
            BootEvent::Error {
                node: id(5),
                error: BootError::NoResponse { code }
            },
            BootEvent::NetworkStarted,
        ]
    );
    assert_eq!(m.poll_timeout(), None);
}

#[test]
fn each_identity_difference_has_its_letter() {
    let cases = [
        (0x1000, 0, 0x192, 'C'),
        (0x1018, 1, 0x2B, 'D'),
        (0x1018, 2, 8, 'M'),
        (0x1018, 3, 9, 'N'),
        (0x1018, 4, 10, 'O'),
    ];
    for (index, sub, wrong, letter) in cases {
        let mut n = node5();
        n.expected.product_code = 7;
        n.expected.revision = 8;
        n.expected.serial = 9;
        let mut m = started(NmtStartup::MASTER, &[n]);
        m.handle_frame(t(1), &beat(5, 0));
        // The right values up to the object that differs.
        let right = [
            (0x1000, 0, 0x191),
            (0x1018, 1, 0x2A),
            (0x1018, 2, 7),
            (0x1018, 3, 8),
        ];
        for (i, s, v) in right
            .into_iter()
            .take_while(|(i, s, _)| (*i, *s) != (index, sub))
        {
            assert_eq!(sent(&mut m).len(), 1);
            m.handle_frame(t(2), &value(5, i, s, v));
        }
        assert_eq!(sent(&mut m).len(), 1);
        m.handle_frame(t(3), &value(5, index, sub, wrong));
        let got = events(&mut m);
        let Some(BootEvent::Error { node, error }) = got.get(1) else {
            panic!("{got:?}")
        };
        assert_eq!((*node, error.letter()), (id(5), letter), "{error}");
        let BootError::Identity { expected, read, .. } = error else {
            panic!("{error:?}")
        };
        assert_eq!(*read, Some(wrong));
        assert_eq!(*expected, wrong - 1);
        assert_eq!(m.phase(id(5)), Some(BootPhase::Failed(*error)));
    }
}

#[test]
fn only_the_expected_identity_subs_are_read() {
    let mut n = node5();
    n.expected.serial = 0x42;
    let mut m = started(NmtStartup::MASTER, &[n]);
    m.handle_frame(t(1), &beat(5, 0));
    assert_eq!(sent(&mut m), ["605#4000100000000000"]);
    m.handle_frame(t(2), &value(5, 0x1000, 0, 0x191));
    assert_eq!(sent(&mut m), ["605#4018100100000000"]);
    m.handle_frame(t(3), &value(5, 0x1018, 1, 0x2A));
    // Product code and revision are not checked (1F86h, 1F87h = 0).
    assert_eq!(sent(&mut m), ["605#4018100400000000"]);
    m.handle_frame(t(4), &abort(5, 0x1018, 4, 0x0609_0011));
    let error = BootError::Identity {
        check: IdentityCheck::Serial,
        expected: 0x42,
        read: None,
    };
    assert_eq!(events(&mut m)[1], BootEvent::Error { node: id(5), error });
    assert_eq!(error.letter(), 'O');
}

#[test]
fn a_boot_up_starts_the_process_again_at_any_time() {
    let mut m = started(NmtStartup::MASTER, &[node5()]);
    m.handle_frame(t(1), &beat(5, 0));
    let _ = sent(&mut m);
    m.handle_frame(t(2), &value(5, 0x1000, 0, 0x191));
    assert_eq!(sent(&mut m), ["605#4018100100000000"]);
    // The node resets mid-way: the read of 1018h is dropped (no abort) and
    // 1000h read again.
    m.handle_frame(t(3), &beat(5, 0));
    assert_eq!(sent(&mut m), ["605#4000100000000000"]);
    m.handle_frame(t(4), &value(5, 0x1000, 0, 0x191));
    m.handle_frame(t(5), &value(5, 0x1018, 1, 0x2A));
    assert_eq!(sent(&mut m), ["605#4018100100000000", "000#0105"]);
    let node = id(5);
    assert_eq!(
        events(&mut m),
        [
            BootEvent::BootUp { node },
            BootEvent::BootUp { node },
            BootEvent::Identified {
                node,
                device_type: 0x191
            },
            BootEvent::Booted { node },
            BootEvent::NetworkStarted,
            BootEvent::Operational { node },
        ]
    );
    // After the start too: a boot-up begins again.
    m.handle_frame(t(6), &beat(5, 0));
    assert_eq!(sent(&mut m), ["605#4000100000000000"]);
    assert_eq!(m.phase(node), Some(BootPhase::DeviceType));
}

#[test]
fn a_boot_up_while_1000h_is_read_keeps_the_one_read() {
    let mut m = started(NmtStartup::MASTER, &[node5()]);
    m.handle_frame(t(1), &beat(5, 0));
    assert_eq!(sent(&mut m), ["605#4000100000000000"]);
    // The boot-up after the reset, the read still outstanding: one request
    // on the channel, so its one answer moves the process on.
    m.handle_frame(t(2), &beat(5, 0));
    assert_eq!(sent(&mut m), Vec::<String>::new());
    m.handle_frame(t(3), &value(5, 0x1000, 0, 0x191));
    assert_eq!(sent(&mut m), ["605#4018100100000000"]);
    m.handle_frame(t(4), &value(5, 0x1018, 1, 0x2A));
    assert_eq!(sent(&mut m), ["000#0105"]);
    let node = id(5);
    let events = events(&mut m);
    assert_eq!(
        events[..3],
        [
            BootEvent::BootUp { node },
            BootEvent::BootUp { node },
            BootEvent::Identified {
                node,
                device_type: 0x191
            },
        ]
    );
    assert!(
        events.contains(&BootEvent::Operational { node }),
        "{events:?}"
    );
}

/// Node 5 booted to the start of error control at 3 ms.
fn to_error_control(n: NodeConfig<'static>) -> BootManager<'static, 4> {
    let mut m = started(NmtStartup::MASTER, &[n]);
    m.handle_frame(t(1), &beat(5, 0));
    m.handle_frame(t(2), &value(5, 0x1000, 0, 0x191));
    m.handle_frame(t(3), &value(5, 0x1018, 1, 0x2A));
    let _ = (sent(&mut m), events(&mut m));
    assert_eq!(m.phase(id(5)), Some(BootPhase::ErrorControl));
    m
}

#[test]
fn the_heartbeat_starts_error_control_and_its_loss_is_e() {
    let mut n = node5();
    n.heartbeat = Some(Duration::from_millis(100));
    let mut m = to_error_control(n);
    // Consumer time: 150 ms + 20 ms.
    assert_eq!(m.poll_timeout(), Some(t(173)));
    m.handle_frame(t(50), &beat(5, 0x7F));
    assert_eq!(sent(&mut m), ["000#0105"]);
    let node = id(5);
    assert_eq!(events(&mut m)[0], BootEvent::Booted { node });
    m.handle_frame(t(150), &beat(5, 0x05));
    assert_eq!(m.poll_timeout(), Some(t(320)));
    m.handle_timeout(t(319));
    assert_eq!(events(&mut m), []);
    m.handle_timeout(t(320));
    m.handle_timeout(t(900));
    let error = BootError::HeartbeatLost;
    assert_eq!(events(&mut m), [BootEvent::Lost { node, error }]);
    assert_eq!(error.letter(), 'E');
    m.handle_frame(t(901), &beat(5, 0x05));
    assert_eq!(events(&mut m), [BootEvent::Restored { node }]);
    assert_eq!(m.phase(node), Some(BootPhase::Operational));
}

#[test]
fn no_heartbeat_when_error_control_starts_is_k() {
    let mut n = node5();
    n.heartbeat = Some(Duration::from_millis(100));
    let mut m = to_error_control(n);
    m.handle_timeout(t(173));
    let error = BootError::ErrorControlStart;
    assert_eq!(events(&mut m)[0], BootEvent::Error { node: id(5), error });
    assert_eq!(error.letter(), 'K');
}

#[test]
fn a_guarded_node_boots_on_its_first_reply_and_is_f_when_lost() {
    let mut n = node5();
    n.assignment = n.assignment.with_guarding(Duration::from_millis(100), 2);
    let mut m = to_error_control(n);
    // The guarding request went out with the last answer.
    m.handle_timeout(t(3));
    let guard = CanFrame::standard(0x705, &[0x7F]).unwrap();
    m.handle_frame(t(5), &guard);
    assert_eq!(sent(&mut m), ["000#0105"]);
    m.handle_timeout(t(103));
    assert_eq!(sent(&mut m), ["705#R1"]);
    // No more replies: two requests unanswered.
    for at in [203, 303] {
        m.handle_timeout(t(at));
    }
    let node = id(5);
    let error = BootError::GuardingLost;
    let got = events(&mut m);
    assert_eq!(
        got.last(),
        Some(&BootEvent::Lost { node, error }),
        "{got:?}"
    );
    assert_eq!(error.letter(), 'F');
}

#[test]
fn a_mandatory_failure_holds_start_all_and_an_optional_one_does_not() {
    let mandatory = NodeConfig {
        assignment: SlaveAssignment::BOOTED.mandatory(),
        ..node5()
    };
    let optional = NodeConfig {
        node: id(6),
        ..node5()
    };
    let startup = NmtStartup::MASTER | NmtStartup::START_ALL;
    // The optional node's wrong device type does not hold the start.
    let mut m = started(startup, &[mandatory, optional]);
    m.handle_frame(t(1), &beat(6, 0));
    m.handle_frame(t(2), &value(6, 0x1000, 0, 0x999));
    m.handle_frame(t(3), &beat(5, 0));
    m.handle_frame(t(4), &value(5, 0x1000, 0, 0x191));
    assert!(!m.network_started());
    m.handle_frame(t(5), &value(5, 0x1018, 1, 0x2A));
    assert!(sent(&mut m).contains(&"000#0100".to_string()));
    assert!(m.network_started());
    // The mandatory node's failure holds it until the node boots.
    let mut m = started(startup, &[mandatory, optional]);
    m.handle_frame(t(1), &beat(6, 0));
    m.handle_frame(t(2), &value(6, 0x1000, 0, 0x191));
    m.handle_frame(t(3), &value(6, 0x1018, 1, 0x2A));
    m.handle_frame(t(4), &beat(5, 0));
    m.handle_frame(t(5), &value(5, 0x1000, 0, 0x191));
    m.handle_frame(t(6), &value(5, 0x1018, 1, 0x2B));
    let node = id(5);
    assert!(events(&mut m).ends_with(&[BootEvent::StartHeld { node }]));
    assert!(!sent(&mut m).contains(&"000#0100".to_string()));
    m.handle_frame(t(7), &beat(5, 0));
    m.handle_frame(t(8), &value(5, 0x1000, 0, 0x191));
    m.handle_frame(t(9), &value(5, 0x1018, 1, 0x2A));
    assert!(sent(&mut m).contains(&"000#0100".to_string()));
    let got = events(&mut m);
    assert!(
        got.contains(&BootEvent::Operational { node: id(6) }),
        "{got:?}"
    );
}

#[test]
fn a_boot_up_of_a_node_not_listed_is_a() {
    let mut m = started(NmtStartup::MASTER, &[node5()]);
    m.handle_frame(t(1), &beat(9, 0));
    let error = BootError::NotListed;
    assert_eq!(events(&mut m), [BootEvent::Error { node: id(9), error }]);
    assert_eq!(error.letter(), 'A');
    assert_eq!(
        error.to_string(),
        "A: the node is not in the network list (1F81h)"
    );
}

#[test]
fn the_start_up_resets_each_slave_or_all_at_once() {
    let keep = NodeConfig {
        node: id(7),
        assignment: SlaveAssignment::BOOTED.keep_alive(),
        ..node5()
    };
    let mut m: BootManager<'_, 4> = BootManager::new(ManagerConfig::default());
    for n in [node5(), keep] {
        m.add_node(n).unwrap();
    }
    m.start(t(0));
    // The keep-alive node is not reset: its process begins at once.
    assert_eq!(sent(&mut m), ["000#8205", "607#4000100000000000"]);
    let config = ManagerConfig {
        startup: NmtStartup::MASTER | NmtStartup::RESET_ALL,
        ..ManagerConfig::default()
    };
    let mut m: BootManager<'_, 4> = BootManager::new(config);
    m.add_node(node5()).unwrap();
    assert_eq!(m.add_node(node5()), Err(ManagerError::Duplicate(id(5))));
    m.start(t(0));
    assert_eq!(sent(&mut m), ["000#8200"]);
    assert_eq!(m.add_node(keep), Err(ManagerError::Started));
}

#[test]
fn hostile_answers_never_panic_and_only_the_managers_frames_go_out() {
    let mut n = node5();
    n.heartbeat = Some(Duration::from_millis(10));
    n.expected.serial = 3;
    let mut m = started(NmtStartup::MASTER | NmtStartup::STOP_ALL, &[n]);
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut now = 0;
    for _ in 0..20_000 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let bytes = x.to_le_bytes();
        let id = [0x585, 0x705, 0x000, 0x586][(x >> 60) as usize % 4];
        let len = (bytes[7] % 9) as usize;
        if x & 1 == 0 {
            m.handle_frame(t(now), &CanFrame::standard(id, &bytes[..len]).unwrap());
        } else {
            now += x >> 58;
            m.handle_timeout(t(now));
        }
        for f in sent(&mut m) {
            assert!(
                f.starts_with("605#") || f.starts_with("000#") || f == "705#R1",
                "{f}"
            );
        }
        let _ = events(&mut m);
    }
    assert_eq!(m.frames_dropped(), 0);
}

/// 1017h = 100 ms, then 1800h:05 = 0x01F4 (two entries), leaked for the
/// manager's `'static` borrow.
fn two_entries() -> ConciseDcf<'static> {
    let entries = [
        ConciseEntry::new(Address::index(0x1017), &[100, 0]),
        ConciseEntry::new(Address::new(0x1800, 5), &[0xF4, 0x01]),
    ];
    let buf: &'static mut [u8] = std::vec![0u8; 32].leak();
    let len = ConciseDcf::encode(entries, buf).unwrap();
    ConciseDcf::new_checked(buf.get(..len).unwrap()).unwrap()
}

#[test]
fn the_configuration_is_written_in_order_then_error_control_starts() {
    let n = node5().with_configuration(two_entries());
    assert_eq!(n.heartbeat, Some(Duration::from_millis(100)));
    let mut m = started(NmtStartup::MASTER, &[n]);
    m.handle_frame(t(1), &beat(5, 0));
    m.handle_frame(t(2), &value(5, 0x1000, 0, 0x191));
    m.handle_frame(t(3), &value(5, 0x1018, 1, 0x2A));
    assert_eq!(m.phase(id(5)), Some(BootPhase::Configuration(0)));
    let ack = |index: u16, sub| {
        let [lo, hi] = index.to_le_bytes();
        CanFrame::standard(0x585, &[0x60, lo, hi, sub, 0, 0, 0, 0]).unwrap()
    };
    m.handle_frame(t(4), &ack(0x1017, 0));
    m.handle_frame(t(5), &ack(0x1800, 5));
    assert_eq!(
        sent(&mut m)[2..],
        ["605#2B17100064000000", "605#2B001805F4010000"]
    );
    let node = id(5);
    assert_eq!(
        events(&mut m)[2..],
        [BootEvent::ConfigurationWritten { node, entries: 2 }]
    );
    assert_eq!(m.phase(node), Some(BootPhase::ErrorControl));
    m.handle_frame(t(6), &beat(5, 0x7F));
    assert_eq!(m.phase(node), Some(BootPhase::Operational));
}

#[test]
fn an_aborted_or_unanswered_write_is_j_with_its_object_and_code() {
    for (answer, code, origin) in [
        (
            Some(0x0609_0030),
            AbortCode::InvalidValue,
            AbortOrigin::Peer,
        ),
        (None, AbortCode::SdoProtocolTimedOut, AbortOrigin::Local),
    ] {
        let n = node5().with_configuration(two_entries());
        let mut m = started(NmtStartup::MASTER, &[n]);
        m.handle_frame(t(1), &beat(5, 0));
        m.handle_frame(t(2), &value(5, 0x1000, 0, 0x191));
        m.handle_frame(t(3), &value(5, 0x1018, 1, 0x2A));
        m.handle_frame(
            t(4),
            &CanFrame::standard(0x585, &[0x60, 0x17, 0x10, 0, 0, 0, 0, 0]).unwrap(),
        );
        match answer {
            Some(c) => m.handle_frame(t(5), &abort(5, 0x1800, 5, c)),
            None => m.handle_timeout(t(504)),
        }
        let failure = ConfigurationFailure::Aborted { code, origin };
        let error = BootError::Configuration {
            index: 0x1800,
            sub: 5,
            failure,
        };
        let got = events(&mut m);
        assert!(
            got.contains(&BootEvent::Error { node: id(5), error }),
            "{got:?}"
        );
        assert_eq!(error.letter(), 'J');
        // Not started: only the manager's own abort frame, if any, follows.
        assert!(!sent(&mut m).iter().any(|f| f.starts_with("000#01")));
    }
}

#[test]
fn a_second_start_waits_for_every_first_boot_again() {
    // Start all: the network starts once the node's first boot has ended,
    // after the first start and after the second alike.
    let mut m = started(NmtStartup::MASTER | NmtStartup::START_ALL, &[node5()]);
    assert!(!m.network_started());
    for at in [0, 10] {
        if at > 0 {
            m.start(t(at));
            assert!(!m.network_started());
        }
        m.handle_frame(t(at + 1), &beat(5, 0));
        m.handle_frame(t(at + 2), &value(5, 0x1000, 0, 0x191));
        m.handle_frame(t(at + 3), &value(5, 0x1018, 1, 0x2A));
        assert!(m.network_started());
        let frames = sent(&mut m);
        assert!(frames.contains(&"000#0100".to_string()), "{frames:?}");
        assert!(!frames.contains(&"000#0105".to_string()), "{frames:?}");
    }
}

#[test]
fn a_lost_mandatory_slave_stops_all_nodes_when_1f80h_says_so() {
    for (startup, stop) in [
        (NmtStartup::MASTER | NmtStartup::STOP_ALL, true),
        (NmtStartup::MASTER, false),
    ] {
        let n = NodeConfig {
            assignment: SlaveAssignment::BOOTED.mandatory(),
            heartbeat: Some(Duration::from_millis(100)),
            ..node5()
        };
        let mut m = started(startup, &[n]);
        m.handle_frame(t(1), &beat(5, 0));
        m.handle_frame(t(2), &value(5, 0x1000, 0, 0x191));
        m.handle_frame(t(3), &value(5, 0x1018, 1, 0x2A));
        m.handle_frame(t(4), &beat(5, 0x7F));
        let _ = sent(&mut m);
        m.handle_timeout(t(500));
        let expected: &[&str] = if stop { &["000#0200"] } else { &[] };
        assert_eq!(sent(&mut m), expected);
    }
}
