//! The EDS we write for our own nodes (`cia418::battery_module_eds`,
//! `deltaq::charger_eds`, the examples' `--print-eds`) read back by our own
//! parser: the dictionary built from it (`Eds::dictionary`) agrees with the
//! node's own dictionary on every object: access, length, PDO-mappable
//! flag and value.

use std::time::Duration;

use canopen_codec::cia418::{
    battery_module_eds, BatteryModule, BatteryModuleConfig, Identity, PackedStringObject,
    Temperature,
};
#[cfg(feature = "heartbeat-consumer")]
use canopen_codec::deltaq::{charger_eds, Charger, ChargerConfig};
use canopen_codec::eds::{self, DataType, Eds};
use canopen_codec::od::ObjectDictionary;
use canopen_codec::sdo::AbortCode;
use canopen_codec::{NodeId, Timestamp};
use proptest::prelude::*;

/// Every (index, sub) of `od` from 1000h up (every object of our nodes
/// has a sub-index 0).
fn entries(od: &mut dyn ObjectDictionary) -> Vec<(u16, u8)> {
    let mut out = Vec::new();
    for index in 0x1000..=0xFFFF_u16 {
        if od.info(index, 0).is_err() {
            continue;
        }
        for sub in 0..=u8::MAX {
            if od.info(index, sub).is_ok() {
                out.push((index, sub));
            }
        }
    }
    out
}

/// `text` read back by our parser agrees with `node` on every object, in
/// both directions; returns the parsed description.
fn agrees(node: &mut dyn ObjectDictionary, text: &str, id: NodeId) -> Eds {
    let eds = eds::parse(text).unwrap();
    assert_eq!(eds.warnings, [], "{text}");
    let mut back = eds.dictionary(id);
    assert_eq!(back.unserved(), [], "{text}");
    let ours = entries(node);
    assert!(ours.len() > 20);
    for &(index, sub) in &ours {
        let a = node.info(index, sub).unwrap();
        let b = back
            .info(index, sub)
            .unwrap_or_else(|e| panic!("{index:04X}h/{sub} missing from the EDS: {e:?}"));
        assert_eq!(
            (a.access, a.len, a.pdo_mappable),
            (b.access, b.len, b.pdo_mappable),
            "{index:04X}h/{sub}"
        );
        let (mut x, mut y) = ([0u8; 64], [0u8; 64]);
        let (n, m) = (
            node.read(index, sub, 0, &mut x),
            back.read(index, sub, 0, &mut y),
        );
        if n == Err(AbortCode::NoDataAvailable) {
            // An empty 1003h entry (CiA 301, 7.5.2.4) has no value to
            // write: the EDS gives none, and an EDS entry without a
            // DefaultValue reads as zero (CiA 306 has no "no data").
            assert_eq!(index, 0x1003, "{index:04X}h/{sub}");
            assert_eq!(eds.entry(index, sub).unwrap().default_value, None);
            assert_eq!(m, Ok(a.len));
            continue;
        }
        assert_eq!(n, m, "{index:04X}h/{sub}");
        assert_eq!(x, y, "{index:04X}h/{sub}");
        assert!(eds.entry(index, sub).is_some_and(|e| !e.name.is_empty()));
    }
    let described: usize = eds.objects.values().map(|o| o.subs.len().max(1)).sum();
    assert_eq!(
        described,
        ours.len(),
        "the EDS describes more than the node has"
    );
    eds
}

fn module_agrees(module: &BatteryModule) -> Eds {
    let text = eds::write(&battery_module_eds(module));
    let mut od = module.dictionary().clone();
    agrees(&mut od, &text, module.config().node)
}

#[test]
fn the_default_module_reads_back() {
    let module = BatteryModule::new(BatteryModuleConfig::default());
    let eds = module_agrees(&module);
    let t = eds.entry(0x6010, 0).unwrap();
    assert_eq!(
        (t.name.as_str(), t.data_type),
        ("Temperature", Some(DataType::Integer16))
    );
    assert_eq!(
        eds.entry(0x1000, 0).unwrap().default_value.as_deref(),
        Some("418")
    );
    assert_eq!(
        eds.device_info.product_name.as_deref(),
        Some("CiA 418 battery module")
    );
    assert_eq!(eds.device_info.nr_of_tx_pdo, Some(1));
    assert_eq!(eds.objects[&0x1003].entry.name, "Pre-defined error field");
    assert_eq!(eds.name(0x1A00, 1), Some("Application object 1"));
    assert_eq!(eds.name(0x1800, 0), Some("Highest sub-index supported"));
}

#[test]
fn a_configured_module_reads_back() {
    let mut config = BatteryModuleConfig::new(NodeId::new(5).unwrap());
    config.device_type = canopen_codec::cia418::DeviceType::cia418(0x000F_0000);
    config.identity = Identity {
        vendor_id: 0x110,
        product_code: 7,
        revision_number: 0x0003_0100,
        serial_number: 0xDEAD_BEEF,
    };
    config.heartbeat = Duration::ZERO;
    config.enable_tpdos = false;
    let mut module = BatteryModule::new(config);
    module
        .set_text(PackedStringObject::BatterySerialNumber, "SN-0042")
        .unwrap();
    module.update(Timestamp::ZERO, |o| {
        o.temperature = Temperature::from_raw(-321);
    });
    let eds = module_agrees(&module);
    assert_eq!(eds.device_info.vendor_number, Some(0x110));
    assert_eq!(eds.device_info.revision_number, Some(0x0003_0100));
    let mut od = module.dictionary().clone();
    let tpdos = (0x1800..=0x19FF_u16)
        .filter(|&i| od.info(i, 0).is_ok())
        .count();
    assert!(tpdos > 1);
    assert_eq!(eds.device_info.nr_of_tx_pdo, Some(tpdos as u16));
    assert!(od.read(0x1800, 1, 0, &mut [0; 4]).is_ok());
    assert_eq!(
        eds.entry(0x6010, 0).unwrap().default_value.as_deref(),
        Some("-321")
    );
}

#[cfg(feature = "heartbeat-consumer")]
#[test]
fn the_charger_reads_back() {
    let config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::MIN);
    let charger = Charger::new(config);
    let text = eds::write(&charger_eds(&charger));
    let mut od = charger.dictionary().clone();
    let eds = agrees(&mut od, &text, config.node);
    assert_eq!(
        eds.entry(0x1000, 0).unwrap().default_value.as_deref(),
        Some("419")
    );
    assert_eq!(eds.name(0x2FFA, 2), Some("ZeroTxFilling"));
    assert_eq!(eds.name(0x4201, 0), Some("External Override"));
    assert_eq!(eds.name(0x1016, 1), Some("Consumer heartbeat time 1"));
    assert_eq!(
        eds.device_info.vendor_name.as_deref(),
        Some("Delta-Q Technologies")
    );
    assert!(eds.manufacturer.contains(&0x2002));
}

#[cfg(all(
    feature = "sim",
    feature = "lss",
    feature = "guarding",
    feature = "sync-time",
    feature = "store"
))]
fn print_eds(name: &str, args: &[&str]) -> Eds {
    let out = std::process::Command::new(crate::common::example(name))
        .args(args)
        .arg("--print-eds")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let eds = eds::parse_bytes(&out.stdout).unwrap();
    assert_eq!(eds.warnings, []);
    assert_eq!(eds.dictionary(NodeId::MIN).unserved(), []);
    eds
}

/// Needs the examples' features (`battery_module` and `charger` run the
/// simulation models).
#[cfg(all(
    feature = "sim",
    feature = "lss",
    feature = "guarding",
    feature = "sync-time",
    feature = "store"
))]
#[test]
fn the_examples_print_their_eds() {
    let eds = print_eds(
        "battery_module",
        &[
            "--device-name",
            "bench module",
            "--heartbeat-ms",
            "250",
            "--identity",
            "110,2,3,4",
            "--temperature",
            "-10",
            "--device-type",
            "0x000301A2",
        ],
    );
    let value = |i, s| eds.entry(i, s).unwrap().default_value.clone().unwrap();
    assert_eq!(value(0x1008, 0), "bench module");
    assert_eq!(value(0x1017, 0), "250");
    assert_eq!(value(0x1018, 1), "272");
    assert_eq!(value(0x1000, 0), format!("{}", 0x0003_01A2));
    assert_eq!(value(0x6010, 0), "-80");
    assert_eq!(
        eds.device_info.product_name.as_deref(),
        Some("bench module")
    );
    {
        let eds = print_eds("charger", &["--node-id", "12", "--current", "2.5"]);
        let value = |i, s| eds.entry(i, s).unwrap().default_value.clone().unwrap();
        assert_eq!(value(0x1000, 0), "419");
        assert_eq!(value(0x2002, 0), "640");
        assert_eq!(value(0x1200, 2), format!("{}", 0x580 + 12));
    }
}

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 96,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::Direct(
                "tests/proptest-regressions/eds_export.txt",
            ),
        )),
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config())]

    /// Any battery-module configuration: its EDS reads back to a
    /// dictionary that agrees with the module's on every object.
    #[test]
    fn any_module_configuration_reads_back(
        node in 1u8..=127,
        pdo_bits in 0u32..16,
        heartbeat in any::<u16>(),
        identity in any::<[u32; 4]>(),
        name in "[A-Za-z0-9]([A-Za-z0-9 _.,-]{0,30}[A-Za-z0-9])?",
        enable_tpdos in any::<bool>(),
        temperature in any::<i16>(),
    ) {
        let mut config = BatteryModuleConfig::new(NodeId::new(node).unwrap());
        config.device_type = canopen_codec::cia418::DeviceType::cia418(pdo_bits << 16);
        config.heartbeat = Duration::from_millis(u64::from(heartbeat));
        let [vendor_id, product_code, revision_number, serial_number] = identity;
        config.identity = Identity { vendor_id, product_code, revision_number, serial_number };
        config.device_name = Box::leak(name.clone().into_boxed_str());
        config.enable_tpdos = enable_tpdos;
        let mut module = BatteryModule::new(config);
        module.update(Timestamp::ZERO, |o| o.temperature = Temperature::from_raw(temperature));
        let eds = module_agrees(&module);
        prop_assert_eq!(eds.device_info.product_name.as_deref(), Some(name.as_str()));
        prop_assert_eq!(eds.device_info.vendor_number, Some(vendor_id));
    }
}
