//! LSS (CiA 305, "Layer setting services and protocol") on the simulated
//! bus: an LSS master fastscans two battery modules that left production
//! without a node-ID, one after the other, gives them node-IDs 5 and 6,
//! and they boot up under them.

use crate::common;

use std::time::Duration;

use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig};
use canopen_codec::device::Identity;
use canopen_codec::lss::{
    LssAddress, LssMaster, LssMasterEvent, LssMode, LssSlave, LssSlaveConfig, LssStatus,
};
use canopen_codec::nmt::NmtState;
use canopen_codec::{NodeId, Timestamp};
use common::sim::{bus, Bus, Handle};

fn address(serial: u32) -> LssAddress {
    LssAddress {
        vendor: 0x0000_029A,
        product: 0x0418_0001,
        revision: 0x0001_0000,
        serial,
    }
}

fn module(serial: u32) -> BatteryModule {
    let a = address(serial);
    let mut config = BatteryModuleConfig::new(NodeId::MAX);
    config.identity = Identity {
        vendor_id: a.vendor,
        product_code: a.product,
        revision_number: a.revision,
        serial_number: a.serial,
    };
    BatteryModule::with_lss(config, LssSlave::new(LssSlaveConfig::new(a, None)))
}

fn master_events(sim: &mut Bus, m: Handle<LssMaster>) -> Vec<LssMasterEvent> {
    sim.take_events(m).into_iter().map(|(_, e)| e).collect()
}

fn later(sim: &Bus, ms: u64) -> Timestamp {
    sim.now().add_millis(ms)
}

#[test]
fn fastscan_two_unconfigured_modules_and_assign_5_and_6() {
    let mut sim = bus(200);
    let m = sim.add("Master", LssMaster::new(Duration::from_millis(10)));
    // Serial 2 first on the bus; serial 1 has the lower address.
    let a = sim.add("Module serial 2", module(2));
    let b = sim.add("Module serial 1", module(1));
    sim.with(a, |x, now| x.boot(now));
    sim.with(b, |x, now| x.boot(now));
    let end = later(&sim, 3000);
    sim.run_until(end).unwrap();
    assert_eq!(
        sim.log().len(),
        0,
        "no boot-up, no heartbeat without a node-ID"
    );
    assert!(!sim.machine(a).unwrap().device().is_running());

    // Node 5 step by step: fastscan, configure node-ID, switch to waiting.
    {
        let (node, serial, module) = (5u8, 1u32, b);
        sim.with(m, |x, now| x.fastscan(now).unwrap());
        let end = later(&sim, 1500);
        sim.run_until(end).unwrap();
        assert_eq!(
            master_events(&mut sim, m),
            [LssMasterEvent::FastscanFound(address(serial))],
            "exactly one end per search"
        );
        let id = NodeId::new(node).unwrap();
        sim.with(m, |x, now| x.configure_node_id(now, Some(id)).unwrap());
        let end = later(&sim, 20);
        sim.run_until(end).unwrap();
        assert_eq!(
            master_events(&mut sim, m),
            [LssMasterEvent::NodeIdConfigured(LssStatus::OK)]
        );
        assert!(
            !sim.machine(module).unwrap().device().is_running(),
            "pending until the reset"
        );
        sim.with(m, |x, now| x.switch_state_global(now, LssMode::Waiting));
        let end = later(&sim, 20);
        sim.run_until(end).unwrap();
        let dev = sim.machine(module).unwrap().device();
        assert_eq!(dev.node(), id);
        assert_eq!(dev.nmt_state(), NmtState::PreOperational);
        let bootup = sim.frames_on(0x700 + u16::from(node));
        assert_eq!(
            bootup.first().map(|(_, d)| d.clone()),
            Some(vec![0]),
            "boot-up"
        );
    }
    // Node 6 in one command.
    let six = NodeId::new(6).unwrap();
    sim.with(m, |x, now| x.fastscan_assign(now, six).unwrap());
    let end = later(&sim, 1500);
    sim.run_until(end).unwrap();
    assert_eq!(
        master_events(&mut sim, m),
        [
            LssMasterEvent::FastscanFound(address(2)),
            LssMasterEvent::NodeIdConfigured(LssStatus::OK)
        ]
    );
    assert_eq!(sim.machine(a).unwrap().device().node(), six);
    let bootup = sim.frames_on(0x706);
    assert_eq!(
        bootup.first().map(|(_, d)| d.clone()),
        Some(vec![0]),
        "boot-up"
    );
    // Both run, each under its own node-ID, heartbeating; nobody is left.
    sim.inject(common::frame(0x000, "01 00"));
    let end = later(&sim, 2500);
    sim.run_until(end).unwrap();
    for node in [5u16, 6] {
        assert!(
            sim.frames_on(0x700 + node).len() >= 3,
            "node {node} heartbeats"
        );
        // The default TPDO 1 moved to the new node-ID too.
        assert!(
            !sim.frames_on(0x180 + node).is_empty(),
            "TPDO of node {node}"
        );
    }
    assert!(
        sim.frames_on(0x77F).is_empty(),
        "the placeholder node never spoke"
    );
    sim.with(m, |x, now| x.fastscan(now).unwrap());
    let end = later(&sim, 100);
    sim.run_until(end).unwrap();
    assert_eq!(
        master_events(&mut sim, m),
        [LssMasterEvent::FastscanNotFound]
    );
}

#[test]
fn configured_module_changes_node_id_at_reset_communication() {
    let mut sim = bus(200);
    let m = sim.add("Master", LssMaster::new(Duration::from_millis(10)));
    let a = address(9);
    let mut config = BatteryModuleConfig::new(NodeId::new(3).unwrap());
    config.heartbeat = Duration::from_millis(100);
    let lss = LssSlave::new(LssSlaveConfig::new(a, NodeId::new(3)));
    let x = sim.add("Module", BatteryModule::with_lss(config, lss));
    sim.with(x, |x, now| x.boot(now));
    sim.with(m, |mm, now| mm.switch_state_selective(now, a).unwrap());
    let end = later(&sim, 50);
    sim.run_until(end).unwrap();
    assert_eq!(
        master_events(&mut sim, m),
        [LssMasterEvent::SwitchedSelective]
    );
    sim.with(m, |mm, now| {
        mm.configure_node_id(now, NodeId::new(12)).unwrap();
    });
    let end = later(&sim, 50);
    sim.run_until(end).unwrap();
    sim.with(m, |mm, now| mm.switch_state_global(now, LssMode::Waiting));
    let end = later(&sim, 300);
    sim.run_until(end).unwrap();
    assert_eq!(
        sim.machine(x).unwrap().device().node(),
        NodeId::new(3).unwrap()
    );
    assert!(
        sim.frames_on(0x70C).is_empty(),
        "a configured node waits for NMT"
    );
    // NMT reset communication to node 3.
    sim.inject(common::frame(0x000, "82 03"));
    let end = later(&sim, 300);
    sim.run_until(end).unwrap();
    assert_eq!(
        sim.machine(x).unwrap().device().node(),
        NodeId::new(12).unwrap()
    );
    let f = sim.frames_on(0x70C);
    assert_eq!(f.first().map(|(_, d)| d.clone()), Some(vec![0]));
}

/// A module whose LSS slave already has a node-ID (5) boots up under it,
/// and its CiA 418 default PDOs are the predefined connection set's for
/// node 5 (TPDO 0 on 185h, RPDO 0 on 205h), whatever node its
/// configuration was made for: the module's DeviceConfig is rebuilt from
/// its configuration, which follows the LSS node-ID (CiA 301 section
/// 7.3.5, predefined connection set).
#[test]
fn a_module_with_a_stored_lss_node_id_uses_its_pdo_cob_ids() {
    use canopen_codec::cob_id::PdoNumber;
    use canopen_codec::machine::Machine;
    use canopen_codec::pdo::PdoDirection;
    let five = NodeId::new(5).unwrap();
    let lss = LssSlave::new(LssSlaveConfig::new(address(7), Some(five)));
    let mut m = BatteryModule::with_lss(BatteryModuleConfig::new(NodeId::MIN), lss);
    m.boot(Timestamp::ZERO);
    assert_eq!(m.poll_transmit().unwrap().to_string(), "705#00");
    assert_eq!((m.node(), m.config().node), (five, five));
    let cob = |dir| {
        m.pdo_config()
            .get(dir, PdoNumber::new(0).unwrap())
            .map(|slot| slot.comm.cob_id.id_bits())
    };
    assert_eq!(cob(PdoDirection::Transmit), Some(0x185));
    assert_eq!(cob(PdoDirection::Receive), Some(0x205));
}
