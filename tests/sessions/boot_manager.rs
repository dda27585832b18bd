//! Our own nodes booted by the CiA 302-2 boot-up manager
//! (`manager::BootManager`) on the simulated bus, each configured from a
//! DCF of its own EDS (issue 36, item 4): the CiA 418 battery module with
//! a faster heartbeat, and the Delta-Q charger with its start-up
//! configuration written by the manager instead of by the charger itself
//! (`ChargerConfig::configure_cob_ids` off): its heartbeat, the heartbeat
//! consumer of the module (1016h) and each of its PDOs paired with the
//! module's (CiA 419 section 7.2, `cia419::PDO_PAIRS`: the module's
//! COB-ID from the module's EDS). The DCFs are turned into concise DCFs
//! (CiA 302-3 section 4) by `Eds::to_concise_dcf`. Both nodes boot, are
//! checked against the identity their EDS gives, configured and started;
//! the new heartbeats and the paired PDOs show on the bus; a module that
//! goes away after the boot is reported with CiA 302-2's letter E.

use canopen_codec::cia418::{battery_module_eds, BatteryModule, BatteryModuleConfig};
use canopen_codec::cia419::PDO_PAIRS;
use canopen_codec::deltaq::{charger_eds, Charger, ChargerConfig};
use canopen_codec::eds::{eval_int, Eds};
use canopen_codec::manager::{
    BootEvent, BootManager, ExpectedIdentity, ManagerConfig, NodeConfig, SlaveAssignment,
};
use canopen_codec::od::{Address, ConciseDcf};
use canopen_codec::pdo::PdoDirection;
use canopen_codec::{CanId, NodeId};

use crate::common::ms;
use crate::common::sim::bus;

/// The value an EDS gives `index`/`sub` for `node`, as a number.
fn default_of(eds: &Eds, index: u16, sub: u8, node: NodeId) -> u32 {
    let text = eds.entry(index, sub).unwrap().value().unwrap();
    u32::try_from(eval_int(text, Some(node.raw())).unwrap()).unwrap()
}

/// A mandatory slave checked against its EDS (1000h, 1018h sub 1 and 2)
/// and configured by the concise DCF of `eds` configured with `values`.
fn slave(eds: &Eds, node: NodeId, values: &[(Address, &str)]) -> (NodeConfig<'static>, u32) {
    let dcf = eds.to_dcf(node, values.iter().copied()).unwrap();
    let bytes: &'static [u8] = Vec::leak(dcf.to_concise_dcf().unwrap());
    let concise = ConciseDcf::new_checked(bytes).unwrap();
    let mut config = NodeConfig::new(node).with_configuration(concise);
    config.assignment = SlaveAssignment::BOOTED.mandatory();
    config.expected = ExpectedIdentity {
        device_type: default_of(eds, 0x1000, 0, node),
        vendor_id: default_of(eds, 0x1018, 1, node),
        product_code: default_of(eds, 0x1018, 2, node),
        ..ExpectedIdentity::default()
    };
    (config, concise.len())
}

#[test]
fn the_battery_module_and_the_charger_boot_from_dcfs_of_their_own_eds() {
    let battery_node = NodeId::new(1).unwrap();
    let charger_node = NodeId::new(10).unwrap();
    let module = BatteryModule::new(BatteryModuleConfig::default());
    let mut charger_config = ChargerConfig::new(charger_node, battery_node);
    charger_config.configure_cob_ids = false;
    let charger = Charger::new(charger_config);
    let module_eds = battery_module_eds(&module);
    let charger_eds = charger_eds(&charger);

    // The module: heartbeat every 250 ms (its default is 1000 ms).
    let (module_slave, module_entries) = slave(
        &module_eds,
        battery_node,
        &[(Address::new(0x1017, 0), "250")],
    );
    // The charger: heartbeat every 500 ms, the module's heartbeat consumed
    // within 1500 ms (1016h sub 1: node 1 in bits 16-23, the time in ms),
    // and each PDO that pairs with one of the module's on the module's
    // identifier (written by the PDO procedure: disabled, then enabled).
    let mut values = vec![
        (Address::new(0x1017, 0), "500".to_string()),
        (Address::new(0x1016, 1), "0x000105DC".to_string()),
    ];
    let mut paired = Vec::new();
    for pair in PDO_PAIRS {
        let own = pair.charger_direction.comm_index(pair.charger_pdo);
        if module_eds.entry(pair.module_comm_index, 1).is_none()
            || charger_eds.entry(own, 1).is_none()
        {
            continue;
        }
        let id = default_of(&module_eds, pair.module_comm_index, 1, battery_node) & 0x7FF;
        values.push((Address::new(own, 1), format!("0x{id:X}")));
        paired.push((pair.charger_direction, id));
    }
    let values: Vec<(Address, &str)> = values.iter().map(|(a, v)| (*a, v.as_str())).collect();
    let (charger_slave, charger_entries) = slave(&charger_eds, charger_node, &values);
    assert_eq!(module_entries, 1);
    // 1016h:1, 1017h, and two writes (disable, enable) per paired PDO.
    assert_eq!(charger_entries as usize, 2 + 2 * paired.len());
    assert!(paired.len() >= 2, "{paired:?}");

    let mut sim = bus(500);
    let b = sim.add("Battery", module);
    let c = sim.add("Charger", charger);
    let mut manager: BootManager<'static, 4> = BootManager::new(ManagerConfig::default());
    manager.add_node(module_slave).unwrap();
    manager.add_node(charger_slave).unwrap();
    let m = sim.add("Manager", manager);
    sim.with(b, |d, now| d.boot(now));
    sim.with(c, |d, now| d.boot(now));
    sim.run_until(ms(10)).unwrap();
    sim.with(m, |d, now| d.start(now));
    sim.run_until(ms(3000)).unwrap();

    let events = sim.event_list(m);
    for (node, entries) in [
        (battery_node, module_entries),
        (charger_node, charger_entries),
    ] {
        assert!(
            events.contains(&BootEvent::ConfigurationWritten { node, entries }),
            "{events:?}"
        );
        assert!(events.contains(&BootEvent::Booted { node }), "{events:?}");
        assert!(
            events.contains(&BootEvent::Operational { node }),
            "{events:?}"
        );
    }
    assert!(events.contains(&BootEvent::NetworkStarted));
    assert!(
        !events
            .iter()
            .any(|e| matches!(e, BootEvent::Error { .. } | BootEvent::Lost { .. })),
        "{events:?}"
    );

    // The configured heartbeats, operational (05h), in the last second.
    let in_last_second = |from: &'static str, id: u32| -> Vec<(u64, u8)> {
        sim.sent_by(from)
            .filter(|s| s.frame.id() == CanId::Standard(id as u16) && s.at >= ms(2000))
            .map(|s| {
                (
                    s.at.as_micros(),
                    s.frame.data().first().copied().unwrap_or(0),
                )
            })
            .collect()
    };
    for (from, id, period_ms) in [("Battery", 0x701, 250), ("Charger", 0x70A, 500)] {
        let beats = in_last_second(from, id);
        assert!(beats.len() >= 2, "{from}: {beats:?}");
        assert!(
            beats.iter().all(|(_, state)| *state == 0x05),
            "{from}: {beats:?}"
        );
        for pair in beats.windows(2) {
            assert_eq!(pair[1].0 - pair[0].0, period_ms * 1000, "{from}: {beats:?}");
        }
    }
    // The charger's TPDOs go out on the identifiers of the module's RPDOs.
    for (direction, id) in &paired {
        if *direction == PdoDirection::Transmit {
            assert!(!in_last_second("Charger", *id).is_empty(), "{id:03X}h");
        }
    }

    // The module goes away: the manager reports heartbeat event E once.
    sim.unplug(b);
    sim.run_until(ms(5000)).unwrap();
    let lost: Vec<char> = sim
        .event_list(m)
        .iter()
        .filter_map(|e| match e {
            BootEvent::Lost { node, error } if *node == battery_node => Some(error.letter()),
            _ => None,
        })
        .collect();
    assert_eq!(lost, ['E']);
}
