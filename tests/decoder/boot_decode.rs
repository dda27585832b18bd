//! `canopen-decode` names the traffic of a CiA 302-2 boot session in words:
//! a configuration tool setting up the manager's own objects (1F80h-1F89h,
//! 1F55h and a concise DCF in 1F22h, CiA 302-2 "Network management"
//! section 4.2 and CiA 302-3 "Configuration and program download" section
//! 4), then the frames `manager::BootManager` and a CiA 301 slave exchange
//! on the simulated bus (its identity, its 1F56h program software
//! identification, its configuration).

use crate::common;
use crate::decoder_support::*;

use core::time::Duration;

use canopen_codec::device::{Cia301Device, DeviceConfig, Identity};
use canopen_codec::manager::{BootEvent, BootManager, ManagerConfig, NodeConfig, SlaveAssignment};
use canopen_codec::od::{Access, Address, ConciseDcf, ConciseEntry, MemoryDictionary};
use canopen_codec::NodeId;

/// A tool writes the manager's (node 1) CiA 302-2 objects for slave 5:
/// 1F80h, 1F81h:05, 1F84h:05-1F88h:05, 1F89h, 1F55h:05 expedited, and
/// 1F22h:05 (its 13-byte concise DCF: 1017h = 100 ms) segmented.
const TOOL: &str = "\
601#23801F0001000000\n581#60801F0000000000\n\
601#23811F052D000000\n581#60811F0500000000\n\
601#23841F0591010100\n581#60841F0500000000\n\
601#23851F05A0020000\n581#60851F0500000000\n\
601#23861F0518040000\n581#60861F0500000000\n\
601#23871F0500000100\n581#60871F0500000000\n\
601#23881F0534120000\n581#60881F0500000000\n\
601#23891F00B80B0000\n581#60891F0000000000\n\
601#23551F0507012620\n581#60551F0500000000\n\
601#21221F050D000000\n581#60221F0500000000\n\
601#0001000000171000\n581#2000000000000000\n\
601#1302000000640000\n581#3000000000000000\n";

#[test]
fn a_boot_session_is_named_in_words() {
    let node = NodeId::new(5).unwrap();
    let identity = Identity {
        vendor_id: 0x2A0,
        product_code: 0x418,
        revision_number: 0x0001_0000,
        serial_number: 0x1234,
    };
    let config = DeviceConfig {
        device_type: 0x0001_0191,
        identity,
        heartbeat: Duration::ZERO,
        ..DeviceConfig::new(node)
    };
    let mut app = MemoryDictionary::new();
    app.insert(0x1F56, 1, Access::ReadOnly, &0x2026_0107u32.to_le_bytes());
    app.insert(0x2000, 0, Access::ReadWrite, &[0; 4]);
    let slave: Cia301Device<MemoryDictionary> = Cia301Device::plain(config, app);

    let entries = [
        ConciseEntry::new(Address::index(0x1017), &[100, 0]),
        ConciseEntry::new(Address::index(0x2000), &[0x78, 0x56, 0x34, 0x12]),
    ];
    let bytes = ConciseDcf::encode_vec(entries).unwrap().leak();
    let mut expected =
        NodeConfig::new(node).with_configuration(ConciseDcf::new_checked(bytes).unwrap());
    expected.assignment = SlaveAssignment::BOOTED.mandatory().verify_software();
    expected.expected.device_type = 0x0001_0191;
    expected.expected.vendor_id = 0x2A0;
    expected.expected.product_code = 0x418;
    expected.expected.revision = 0x0001_0000;
    expected.expected.serial = 0x1234;
    expected.expected.software = 0x2026_0107;
    let mut manager: BootManager<'static, 2> = BootManager::new(ManagerConfig::default());
    manager.add_node(expected).unwrap();

    let mut sim = common::sim::bus(200);
    let s = sim.add("Slave", slave);
    let m = sim.add("Manager", manager);
    sim.with(m, |m, now| m.start(now));
    sim.run_until(common::ms(1)).unwrap();
    sim.with(s, |d, now| d.boot(now));
    sim.run_until(common::ms(300)).unwrap();
    assert_eq!(
        sim.event_list(m).last(),
        Some(&BootEvent::Operational { node }),
        "the session boots node 5"
    );
    let mut input = String::from(TOOL);
    for sent in sim.log() {
        input.push_str(&format!("{}\n", sent.frame));
    }

    let o = run(&["-"], Some(&input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    let lines = transfers(&out);
    assert_eq!(
        lines,
        [
            // The manager's own objects, written by the tool.
            "SDO download 1F80h:00 to node 1: 01 00 00 00 (NMT start-up: NMT master)",
            "SDO download 1F81h:05 to node 1: 2D 00 00 00 (NMT slave assignment of node 5: 0000002Dh)",
            "SDO download 1F84h:05 to node 1: 91 01 01 00 (device type identification of node 5: 00010191h)",
            "SDO download 1F85h:05 to node 1: A0 02 00 00 (vendor identification of node 5: 000002A0h)",
            "SDO download 1F86h:05 to node 1: 18 04 00 00 (product code of node 5: 00000418h)",
            "SDO download 1F87h:05 to node 1: 00 00 01 00 (revision number of node 5: 00010000h)",
            "SDO download 1F88h:05 to node 1: 34 12 00 00 (serial number of node 5: 00001234h)",
            "SDO download 1F89h:00 to node 1: B8 0B 00 00 (boot time: 3000 ms)",
            "SDO download 1F55h:05 to node 1: 07 01 26 20 (expected software identification of node 5: 20260107h)",
            "SDO download 1F22h:05 to node 1: 13 bytes 01 00 00 00 17 10 00 02 00 00 00 64 00 (concise DCF 5)",
            // The boot of node 5: its identity, its software, its configuration.
            "SDO upload 1000h:00 from node 5: 91 01 01 00 (device type: profile 401, additional information 0001h)",
            "SDO upload 1018h:01 from node 5: A0 02 00 00 (identity vendor-ID: 000002A0h)",
            "SDO upload 1018h:02 from node 5: 18 04 00 00 (identity product code: 00000418h)",
            "SDO upload 1018h:03 from node 5: 00 00 01 00 (identity revision number: 00010000h)",
            "SDO upload 1018h:04 from node 5: 34 12 00 00 (identity serial number: 00001234h)",
            "SDO upload 1F56h:01 from node 5: 07 01 26 20 (program software identification 1: 20260107h)",
            "SDO download 1017h:00 to node 5: 64 00 (producer heartbeat time: 100 ms)",
            // An application object: bytes only (no EDS given).
            "SDO download 2000h:00 to node 5: 78 56 34 12",
        ]
    );
    // The NMT commands, the boot-up and the heartbeats in words too.
    for words in [
        "NMT reset communication, node 5",
        "boot-up node 5",
        "heartbeat node 5: pre-operational",
        "NMT start, node 5",
        "heartbeat node 5: operational",
    ] {
        assert!(
            out.lines().any(|l| l.ends_with(words)),
            "{words:?} in:\n{out}"
        );
    }
}
