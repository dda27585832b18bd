//! The CiA 302-2 boot-up manager ([`BootManager`]) on the simulated bus,
//! with plain CiA 301 devices as its slaves: a matching node checked,
//! configured (the values arrive in its dictionary) and started; wrong
//! identities refused with their letters; an absent node; a refused
//! configuration; the software check (G, H); a keep-alive slave found
//! running (L) or reset; a heartbeat lost after the boot; a node that
//! resets mid-run; a mandatory failure holding the start of all nodes
//! while an optional one does not; the application starting the slaves
//! (1F80h bit 3); the boot time (1F89h); an absent slave retried (CiA
//! 302-2 "Network management", sections 4.3 and 4.4).

use crate::common;

use core::time::Duration;

use crate::common::ms;
use canopen_codec::device::{Cia301Device, DeviceConfig, Identity};
use canopen_codec::machine::Machine;
use canopen_codec::manager::{
    BootError, BootEvent, BootManager, BootPhase, ManagerConfig, ManagerError, NmtStartup,
    NodeConfig, SlaveAssignment, SoftwareCheck,
};
use canopen_codec::nmt::{NmtCommand, NmtCommandSpecifier, NmtState, NmtTarget};
use canopen_codec::od::{Access, Address, ConciseDcf, ConciseEntry, MemoryDictionary};
use canopen_codec::NodeId;
use common::sim::{Bus, Handle};

type Slave = Cia301Device<MemoryDictionary>;
type Manager = BootManager<'static, 4>;

const DEVICE_TYPE: u32 = 0x0001_0191;
const IDENTITY: Identity = Identity {
    vendor_id: 0x0000_02A0,
    product_code: 0x0000_0418,
    revision_number: 0x0001_0000,
    serial_number: 0x1234,
};
/// The application object the configuration writes.
const SETTING: Address = Address::new(0x2000, 0);

fn id(n: u8) -> NodeId {
    NodeId::new(n).unwrap()
}

/// A plain device: no heartbeat until configured, `SETTING` = 0 (rw).
fn slave(node: u8, device_type: u32, identity: Identity) -> Slave {
    let config = DeviceConfig {
        device_type,
        identity,
        heartbeat: Duration::ZERO,
        ..DeviceConfig::new(id(node))
    };
    let mut app = MemoryDictionary::new();
    app.insert(SETTING.index, SETTING.sub, Access::ReadWrite, &[0; 4]);
    Slave::plain(config, app)
}

/// 1017h = 100 ms and `SETTING` = 0x12345678, plus `extra` entries.
fn configuration(extra: &[ConciseEntry<'static>]) -> ConciseDcf<'static> {
    let mut entries = vec![
        ConciseEntry::new(Address::index(0x1017), &[100, 0]),
        ConciseEntry::new(SETTING, &[0x78, 0x56, 0x34, 0x12]),
    ];
    entries.extend_from_slice(extra);
    let bytes = ConciseDcf::encode_vec(entries).unwrap().leak();
    ConciseDcf::new_checked(bytes).unwrap()
}

/// Node `node` expected with the right identity and configured.
fn expected(node: u8) -> NodeConfig<'static> {
    let mut n = NodeConfig::new(id(node)).with_configuration(configuration(&[]));
    n.expected.device_type = DEVICE_TYPE;
    n.expected.vendor_id = IDENTITY.vendor_id;
    n.expected.product_code = IDENTITY.product_code;
    n.expected.revision = IDENTITY.revision_number;
    n.expected.serial = IDENTITY.serial_number;
    n
}

/// The slaves booted at 0 ms, the manager of `nodes` (retries 2, SDO
/// timeout 100 ms) started at 1 ms.
fn network(
    startup: NmtStartup,
    slaves: Vec<Slave>,
    nodes: &[NodeConfig<'static>],
) -> (Bus, Vec<Handle<Slave>>, Handle<Manager>) {
    let config = ManagerConfig {
        startup,
        sdo_timeout: Duration::from_millis(100),
        ..ManagerConfig::default()
    };
    network_with(config, slaves, nodes)
}

/// [`network`] with the manager's whole configuration.
fn network_with(
    config: ManagerConfig,
    slaves: Vec<Slave>,
    nodes: &[NodeConfig<'static>],
) -> (Bus, Vec<Handle<Slave>>, Handle<Manager>) {
    let mut sim = common::sim::bus(200);
    let handles: Vec<_> = slaves
        .into_iter()
        .map(|s| {
            let h = sim.add("Slave", s);
            sim.with(h, |d, now| d.boot(now));
            h
        })
        .collect();
    let mut manager = Manager::new(config);
    for n in nodes {
        manager.add_node(*n).unwrap();
    }
    let m = sim.add("Manager", manager);
    sim.run_until(ms(1)).unwrap();
    sim.with(m, |m, now| m.start(now));
    (sim, handles, m)
}

/// The error events of the manager.
fn errors(sim: &Bus, m: Handle<Manager>) -> Vec<(u8, char)> {
    sim.event_list(m)
        .into_iter()
        .filter_map(|e| match e {
            BootEvent::Error { node, error } => Some((node.raw(), error.letter())),
            _ => None,
        })
        .collect()
}

#[test]
fn a_matching_node_is_checked_configured_and_started() {
    let (mut sim, s, m) = network(
        NmtStartup::MASTER,
        vec![slave(5, DEVICE_TYPE, IDENTITY)],
        &[expected(5)],
    );
    sim.run_until(ms(500)).unwrap();
    let node = id(5);
    assert_eq!(
        sim.event_list(m),
        [
            BootEvent::BootUp { node },
            BootEvent::Identified {
                node,
                device_type: DEVICE_TYPE
            },
            BootEvent::ConfigurationWritten { node, entries: 2 },
            BootEvent::Booted { node },
            BootEvent::NetworkStarted,
            BootEvent::Operational { node },
        ]
    );
    let device = sim.machine(s[0]).unwrap();
    assert_eq!(device.nmt_state(), NmtState::Operational);
    assert_eq!(
        device.objects().get(SETTING.index, SETTING.sub),
        Some(&[0x78, 0x56, 0x34, 0x12][..])
    );
    // Its heartbeat, configured to 100 ms, goes on without a loss.
    assert!(sim.frames_on(0x705).len() >= 4);
    assert_eq!(
        sim.machine(m).unwrap().phase(node),
        Some(BootPhase::Operational)
    );
}

#[test]
fn wrong_identities_are_refused_with_their_letters() {
    let wrong_vendor = Identity {
        vendor_id: 0x99,
        ..IDENTITY
    };
    let wrong_product = Identity {
        product_code: 0x419,
        ..IDENTITY
    };
    let (mut sim, s, m) = network(
        NmtStartup::MASTER,
        vec![
            slave(5, 0x0002_0191, IDENTITY),
            slave(6, DEVICE_TYPE, wrong_vendor),
            slave(7, DEVICE_TYPE, wrong_product),
        ],
        &[expected(5), expected(6), expected(7)],
    );
    sim.run_until(ms(500)).unwrap();
    let mut got = errors(&sim, m);
    got.sort_unstable();
    assert_eq!(got, [(5, 'C'), (6, 'D'), (7, 'M')]);
    // None configured, none started.
    for h in s {
        let device = sim.machine(h).unwrap();
        assert_eq!(device.nmt_state(), NmtState::PreOperational);
        assert_eq!(device.objects().get(0x2000, 0), Some(&[0u8; 4][..]));
    }
}

#[test]
fn an_absent_node_is_b_after_the_retries() {
    let (mut sim, _, m) = network(NmtStartup::MASTER, vec![], &[expected(9)]);
    // Boot-up wait 1 s, then three reads 100 ms apart.
    sim.run_until(ms(1300)).unwrap();
    assert_eq!(errors(&sim, m), []);
    sim.run_until(ms(1302)).unwrap();
    assert_eq!(errors(&sim, m), [(9, 'B')]);
    let requests = sim
        .frames_on(0x609)
        .iter()
        .filter(|(_, d)| d[0] == 0x40)
        .count();
    assert_eq!(requests, 3);
}

#[test]
fn a_refused_configuration_is_j_and_the_node_is_not_started() {
    // 1000h is read-only: the device aborts the write (06010002h).
    let mut n = expected(5);
    n = n.with_configuration(configuration(&[ConciseEntry::new(
        Address::index(0x1000),
        &[1, 2, 3, 4],
    )]));
    let (mut sim, s, m) = network(
        NmtStartup::MASTER,
        vec![slave(5, DEVICE_TYPE, IDENTITY)],
        &[n],
    );
    sim.run_until(ms(500)).unwrap();
    let error = sim.event_list(m).into_iter().find_map(|e| match e {
        BootEvent::Error { error, .. } => Some(error),
        _ => None,
    });
    let Some(BootError::Configuration { index, sub, .. }) = error else {
        panic!("{error:?}")
    };
    assert_eq!((index, sub, error.unwrap().letter()), (0x1000, 0, 'J'));
    assert_eq!(
        sim.machine(s[0]).unwrap().nmt_state(),
        NmtState::PreOperational
    );
}

#[test]
fn a_heartbeat_lost_after_the_boot_is_e_and_a_reset_boots_the_node_again() {
    let (mut sim, s, m) = network(
        NmtStartup::MASTER,
        vec![slave(5, DEVICE_TYPE, IDENTITY)],
        &[expected(5)],
    );
    sim.run_until(ms(500)).unwrap();
    sim.clear_events();
    // The node goes off the bus: 170 ms later, E.
    sim.set_connected(s[0], false);
    sim.run_until(ms(800)).unwrap();
    let node = id(5);
    let error = BootError::HeartbeatLost;
    assert_eq!(sim.event_list(m), [BootEvent::Lost { node, error }]);
    // Back on the bus after a power cycle: its boot-up starts the process
    // again, and it is configured and started once more.
    sim.clear_events();
    sim.set_connected(s[0], true);
    sim.with(s[0], |d, now| d.boot(now));
    sim.run_until(ms(1200)).unwrap();
    let got = sim.event_list(m);
    assert_eq!(got.first(), Some(&BootEvent::BootUp { node }));
    assert_eq!(
        got.last(),
        Some(&BootEvent::Operational { node }),
        "{got:?}"
    );
    assert_eq!(
        sim.machine(s[0]).unwrap().nmt_state(),
        NmtState::Operational
    );
}

#[test]
fn a_mandatory_failure_holds_start_all_and_an_optional_failure_does_not() {
    let startup = NmtStartup::MASTER | NmtStartup::START_ALL;
    let mandatory = NodeConfig {
        assignment: SlaveAssignment::BOOTED.mandatory(),
        ..expected(5)
    };
    // The optional node 6 has the wrong device type: the network starts.
    let (mut sim, s, m) = network(
        startup,
        vec![
            slave(5, DEVICE_TYPE, IDENTITY),
            slave(6, 0x0002_0191, IDENTITY),
        ],
        &[mandatory, expected(6)],
    );
    sim.run_until(ms(500)).unwrap();
    assert_eq!(errors(&sim, m), [(6, 'C')]);
    assert!(sim.machine(m).unwrap().network_started());
    // Start all: node 6, refused, is started too (CiA 302-2's NMT start
    // to all nodes).
    assert_eq!(
        sim.machine(s[0]).unwrap().nmt_state(),
        NmtState::Operational
    );
    assert!(sim.frames_on(0x000).iter().any(|(_, d)| d == &[1, 0]));

    // The mandatory node 5 has the wrong vendor: nothing is started.
    let wrong_vendor = Identity {
        vendor_id: 0x99,
        ..IDENTITY
    };
    let (mut sim, s, m) = network(
        startup,
        vec![
            slave(5, DEVICE_TYPE, wrong_vendor),
            slave(6, DEVICE_TYPE, IDENTITY),
        ],
        &[mandatory, expected(6)],
    );
    sim.run_until(ms(500)).unwrap();
    let events = sim.event_list(m);
    assert!(events.contains(&BootEvent::StartHeld { node: id(5) }));
    assert!(events.contains(&BootEvent::Booted { node: id(6) }));
    assert!(!sim.machine(m).unwrap().network_started());
    for h in s {
        assert_eq!(
            sim.machine(h).unwrap().nmt_state(),
            NmtState::PreOperational
        );
    }
}

/// The program software identification a slave serves in 1F56h sub 1
/// (CiA 302-3 "Configuration and program download", section 4).
const SOFTWARE: u32 = 0x2026_0107;

#[test]
fn the_software_check_reads_1f56h_and_refuses_with_g_or_h() {
    struct Case {
        name: &'static str,
        /// 1F56h sub 1 of the slave (`None`: it has no 1F56h).
        serves: Option<u32>,
        /// 1F55h for the slave.
        expected: u32,
        /// The error letter, or `None`: verified, configured and started.
        letter: Option<char>,
        /// Whether the manager reads 1F56h sub 1.
        reads: bool,
    }
    let cases = [
        Case {
            name: "the same identification",
            serves: Some(SOFTWARE),
            expected: SOFTWARE,
            letter: None,
            reads: true,
        },
        Case {
            name: "another identification",
            serves: Some(SOFTWARE + 1),
            expected: SOFTWARE,
            letter: Some('H'),
            reads: true,
        },
        Case {
            name: "1F55h not configured",
            serves: Some(SOFTWARE),
            expected: 0,
            letter: Some('G'),
            reads: false,
        },
        Case {
            name: "no 1F56h on the slave",
            serves: None,
            expected: SOFTWARE,
            letter: Some('G'),
            reads: true,
        },
    ];
    for case in cases {
        let mut device = slave(5, DEVICE_TYPE, IDENTITY);
        if let Some(value) = case.serves {
            let od = device.objects_mut();
            od.insert(0x1F56, 1, Access::ReadOnly, &value.to_le_bytes());
        }
        let mut node = expected(5);
        node.assignment = SlaveAssignment::BOOTED.verify_software();
        node.expected.software = case.expected;
        let (mut sim, s, m) = network(NmtStartup::MASTER, vec![device], &[node]);
        sim.run_until(ms(500)).unwrap();
        let name = case.name;
        let read_1f56 = sim
            .frames_on(0x605)
            .iter()
            .any(|(_, d)| d[..4] == [0x40, 0x56, 0x1F, 1]);
        assert_eq!(read_1f56, case.reads, "{name}: read of 1F56h:01");
        let events = sim.event_list(m);
        let configured = sim.machine(s[0]).unwrap().objects().get(0x2000, 0)
            == Some(&[0x78, 0x56, 0x34, 0x12][..]);
        let state = sim.machine(s[0]).unwrap().nmt_state();
        match case.letter {
            None => {
                let verified = BootEvent::SoftwareVerified {
                    node: id(5),
                    check: SoftwareCheck::Identification,
                    value: SOFTWARE,
                };
                assert!(events.contains(&verified), "{name}: {events:?}");
                assert!(configured, "{name}: configured");
                assert_eq!(state, NmtState::Operational, "{name}");
            }
            Some(letter) => {
                assert_eq!(errors(&sim, m), [(5, letter)], "{name}");
                assert!(!configured, "{name}: not configured");
                assert_eq!(state, NmtState::PreOperational, "{name}");
            }
        }
    }
}

#[test]
fn a_keep_alive_slave_running_already_is_l_and_is_neither_reset_nor_configured() {
    let node = id(5);
    // Node 5 produces a 100 ms heartbeat; `running`: it was started before
    // the manager comes up.
    for running in [true, false] {
        let mut sim = common::sim::bus(200);
        let config = DeviceConfig {
            device_type: DEVICE_TYPE,
            identity: IDENTITY,
            heartbeat: Duration::from_millis(100),
            ..DeviceConfig::new(node)
        };
        let mut app = MemoryDictionary::new();
        app.insert(SETTING.index, SETTING.sub, Access::ReadWrite, &[0; 4]);
        let s = sim.add("Slave", Slave::plain(config, app));
        sim.with(s, |d, now| {
            d.boot(now);
            if running {
                let start = NmtCommand::new(NmtCommandSpecifier::Start, NmtTarget::Node(node));
                d.handle_frame(now, &start.to_frame());
            }
        });
        let mut manager = Manager::new(ManagerConfig::default());
        let mut slave = expected(5);
        slave.assignment = SlaveAssignment::BOOTED.keep_alive();
        manager.add_node(slave).unwrap();
        let m = sim.add("Manager", manager);
        sim.run_until(ms(1)).unwrap();
        sim.with(m, |m, now| m.start(now));
        sim.run_until(ms(600)).unwrap();
        let events = sim.event_list(m);
        let nmt = sim.frames_on(0x000);
        let reset = nmt.iter().any(|(_, d)| d == &[0x82, 5]);
        let configured =
            sim.machine(s).unwrap().objects().get(0x2000, 0) == Some(&[0x78, 0x56, 0x34, 0x12][..]);
        assert_eq!(
            sim.machine(s).unwrap().nmt_state(),
            NmtState::Operational,
            "running {running}"
        );
        if running {
            let identified = BootEvent::Identified {
                node,
                device_type: DEVICE_TYPE,
            };
            assert_eq!(
                events,
                [
                    identified,
                    BootEvent::InitiallyOperational { node },
                    BootEvent::Booted { node },
                    BootEvent::NetworkStarted,
                    BootEvent::Operational { node },
                ]
            );
            assert!(!reset && !configured, "not reset, not configured");
            assert!(!nmt.iter().any(|(_, d)| d == &[1, 5]), "not started again");
        } else {
            assert!(reset, "a pre-operational keep-alive slave is reset");
            assert!(events.contains(&BootEvent::BootUp { node }), "{events:?}");
            assert!(!events.contains(&BootEvent::InitiallyOperational { node }));
            assert_eq!(events.last(), Some(&BootEvent::Operational { node }));
            assert!(configured, "configured after its reset");
        }
    }
}

#[test]
fn with_1f80h_bit_3_the_application_starts_the_slaves() {
    let startup = NmtStartup::MASTER | NmtStartup::NO_SLAVE_START;
    let (mut sim, s, m) = network(
        startup,
        vec![
            slave(5, DEVICE_TYPE, IDENTITY),
            slave(6, DEVICE_TYPE, IDENTITY),
        ],
        &[expected(5), expected(6)],
    );
    sim.run_until(ms(500)).unwrap();
    // Both booted, neither started by the manager.
    let state = |sim: &Bus, i: usize| sim.machine(s[i]).unwrap().nmt_state();
    assert_eq!(
        sim.machine(m).unwrap().phase(id(5)),
        Some(BootPhase::Booted)
    );
    assert!(!sim.machine(m).unwrap().network_started());
    assert_eq!(state(&sim, 0), NmtState::PreOperational);
    // The application starts node 5 alone.
    let started = sim.with(m, |m, now| m.start_node(now, id(5)));
    assert_eq!(started, Some(Ok(())));
    sim.run_until(ms(510)).unwrap();
    assert_eq!(state(&sim, 0), NmtState::Operational);
    assert_eq!(state(&sim, 1), NmtState::PreOperational);
    assert!(sim
        .event_list(m)
        .contains(&BootEvent::Operational { node: id(5) }));
    // Started already; not managed.
    let again = sim.with(m, |m, now| m.start_node(now, id(5)));
    assert_eq!(again, Some(Err(ManagerError::NotBooted(id(5)))));
    let unknown = sim.with(m, |m, now| m.start_node(now, id(9)));
    assert_eq!(unknown, Some(Err(ManagerError::NotManaged(id(9)))));
    // Then the network: node 6 is started too, node 5 not a second time.
    sim.with(m, |m, now| m.start_network(now));
    sim.run_until(ms(520)).unwrap();
    assert_eq!(state(&sim, 1), NmtState::Operational);
    assert!(sim.machine(m).unwrap().network_started());
    let starts: Vec<_> = sim
        .frames_on(0x000)
        .into_iter()
        .filter(|(_, d)| d[0] == 1)
        .map(|(_, d)| d[1])
        .collect();
    assert_eq!(starts, [5, 6]);
}

#[test]
fn the_boot_time_reports_each_missing_mandatory_slave_once() {
    let config = ManagerConfig {
        boot_time: Duration::from_millis(700),
        sdo_timeout: Duration::from_millis(100),
        ..ManagerConfig::default()
    };
    let mandatory = |n| NodeConfig {
        assignment: SlaveAssignment::BOOTED.mandatory(),
        ..expected(n)
    };
    // 5 boots; mandatory 9 and optional 8 are absent.
    let nodes = [mandatory(5), mandatory(9), expected(8)];
    let (mut sim, _, m) = network_with(config, vec![slave(5, DEVICE_TYPE, IDENTITY)], &nodes);
    let elapsed = |sim: &Bus| {
        sim.event_list(m)
            .into_iter()
            .filter_map(|e| match e {
                BootEvent::BootTimeElapsed { node } => Some(node.raw()),
                _ => None,
            })
            .collect::<Vec<_>>()
    };
    sim.run_until(ms(700)).unwrap();
    assert_eq!(elapsed(&sim), Vec::<u8>::new(), "before 1 + 700 ms");
    sim.run_until(ms(3000)).unwrap();
    assert_eq!(elapsed(&sim), [9]);
    assert!(!sim.machine(m).unwrap().network_started());
}

#[test]
fn an_absent_slave_is_retried_at_the_interval_and_boots_when_it_answers() {
    let config = ManagerConfig {
        retry_interval: Duration::from_millis(1000),
        sdo_timeout: Duration::from_millis(100),
        ..ManagerConfig::default()
    };
    // Node 9 is off the bus when it boots: the manager never sees its
    // boot-up, and reads 1000h in vain (B at 1302 ms).
    let mut sim = common::sim::bus(200);
    let s = sim.add("Slave", slave(9, DEVICE_TYPE, IDENTITY));
    sim.set_connected(s, false);
    sim.with(s, |d, now| d.boot(now));
    let mut manager = Manager::new(config);
    manager.add_node(expected(9)).unwrap();
    let m = sim.add("Manager", manager);
    sim.run_until(ms(1)).unwrap();
    sim.with(m, |m, now| m.start(now));
    sim.run_until(ms(1400)).unwrap();
    assert_eq!(errors(&sim, m), [(9, 'B')]);
    let reads = |sim: &Bus| {
        sim.frames_on(0x609)
            .iter()
            .filter(|(_, d)| d[..3] == [0x40, 0x00, 0x10])
            .count()
    };
    assert_eq!(reads(&sim), 3);
    // Still absent at the first retry (2302 ms): B again.
    sim.run_until(ms(2700)).unwrap();
    assert_eq!(errors(&sim, m), [(9, 'B'), (9, 'B')]);
    assert_eq!(reads(&sim), 6);
    // On the bus before the second retry (3602 ms): booted and started.
    sim.set_connected(s, true);
    sim.run_until(ms(4000)).unwrap();
    assert_eq!(errors(&sim, m).len(), 2);
    assert_eq!(
        sim.event_list(m).last(),
        Some(&BootEvent::Operational { node: id(9) })
    );
    assert_eq!(sim.machine(s).unwrap().nmt_state(), NmtState::Operational);
}
