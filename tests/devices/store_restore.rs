//! Store parameters (1010h) and restore default parameters (1011h), CiA 301
//! sections 7.5.2.13/7.5.2.14, on the CiA 418 battery module through its
//! public API and the bus only: a TPDO remapped by SDO (the CiA 301 mapping
//! procedure) and a parameter written, "save" to 1010h sub 1; a new module
//! on the same storage (a power cycle) has the remap and the parameter and
//! sends the remapped TPDO; "load" to 1011h sub 1 and reset node give the
//! defaults back, in that module and in the next one.

use crate::common::ms;
use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig};
use canopen_codec::device::{
    DeviceEvent, ParameterGroup, ParameterStorage, RamStorage, StorageEvent,
};
use canopen_codec::machine::Machine;
use canopen_codec::{CanFrame, NodeId};

const SDO_REQUEST: u16 = 0x601;

fn sent(m: &mut impl Machine) -> Vec<String> {
    std::iter::from_fn(|| m.poll_transmit())
        .map(|f| f.to_string())
        .collect()
}

/// An expedited download of `data` (1..=4 bytes); the module's answer.
fn download(m: &mut BatteryModule, index: u16, sub: u8, data: &[u8]) -> String {
    let cs = 0x23 | ((4 - data.len() as u8) << 2);
    let [lo, hi] = index.to_le_bytes();
    let mut bytes = [cs, lo, hi, sub, 0, 0, 0, 0];
    bytes[4..4 + data.len()].copy_from_slice(data);
    m.handle_frame(ms(1), &CanFrame::standard(SDO_REQUEST, &bytes).unwrap());
    sent(m).join(" ")
}

/// An expedited upload; the value's bytes (4, little-endian, as answered).
fn upload(m: &mut BatteryModule, index: u16, sub: u8) -> String {
    let [lo, hi] = index.to_le_bytes();
    let bytes = [0x40, lo, hi, sub, 0, 0, 0, 0];
    m.handle_frame(ms(1), &CanFrame::standard(SDO_REQUEST, &bytes).unwrap());
    let answer = sent(m).join(" ");
    answer.get(12..).unwrap_or(&answer).to_string()
}

fn ok(index: u16, sub: u8) -> String {
    let [lo, hi] = index.to_le_bytes();
    format!("581#60{lo:02X}{hi:02X}{sub:02X}00000000")
}

/// A module on `storage`, booted, its boot frames drained.
fn module(storage: &'static mut dyn ParameterStorage) -> BatteryModule {
    let mut m = BatteryModule::new(BatteryModuleConfig::new(NodeId::new(1).unwrap()));
    m.device_mut().set_storage(storage);
    m.boot(ms(0));
    let _ = sent(&mut m);
    m
}

fn storage_events(m: &mut BatteryModule) -> Vec<StorageEvent> {
    std::iter::from_fn(|| m.poll_event())
        .filter_map(|e| match e {
            DeviceEvent::Storage(s) => Some(s),
            _ => None,
        })
        .collect()
}

/// The 1st TPDO's COB-ID and mapping as read by SDO.
fn tpdo1(m: &mut BatteryModule) -> Vec<String> {
    let mut read = vec![upload(m, 0x1800, 1), upload(m, 0x1A00, 0)];
    read.extend((1..=3).map(|sub| upload(m, 0x1A00, sub)));
    read
}

#[test]
fn stored_remap_survives_a_power_cycle_and_restore_brings_the_defaults_back() {
    let storage: &'static mut RamStorage = Box::leak(Box::new(RamStorage::new()));
    let mut m = module(storage);
    let defaults = tpdo1(&mut m);
    let default_6080 = upload(&mut m, 0x6080, 0);
    // The CiA 301 mapping procedure: disable, clear, map, count, enable.
    for (index, sub, data) in [
        (0x1800, 1, &0x8000_0181u32.to_le_bytes()[..]),
        (0x1A00, 0, &[0][..]),
        (0x1A00, 1, &0x6060_0020u32.to_le_bytes()[..]),
        (0x1A00, 2, &0x6081_0008u32.to_le_bytes()[..]),
        (0x1A00, 0, &[2][..]),
        (0x1800, 1, &0x0000_01F1u32.to_le_bytes()[..]),
        (0x6080, 0, &[80][..]),
    ] {
        assert_eq!(
            download(&mut m, index, sub, data),
            ok(index, sub),
            "{index:04X}h:{sub}"
        );
    }
    let remapped = tpdo1(&mut m);
    assert_eq!(&remapped[..3], ["F1010000", "02000000", "20006060"]);
    assert_eq!(download(&mut m, 0x1010, 1, b"save"), ok(0x1010, 1));
    assert_eq!(
        storage_events(&mut m),
        [
            StorageEvent::Stored(ParameterGroup::Communication),
            StorageEvent::Stored(ParameterGroup::Application)
        ]
    );

    // Power cycle: a new module on the same storage.
    let mut m = module(m.device_mut().take_storage().unwrap());
    assert_eq!(tpdo1(&mut m), remapped);
    assert_eq!(upload(&mut m, 0x6080, 0), "50000000");
    m.update(ms(2), |o| {
        o.battery_state_of_charge = canopen_codec::cia418::StateOfCharge::from_raw(73)
    });
    m.handle_frame(ms(3), &CanFrame::standard(0, &[0x01, 1]).unwrap());
    m.handle_timeout(ms(4));
    let frames = sent(&mut m);
    assert!(
        frames
            .iter()
            .any(|f| f.starts_with("1F1#") && f.len() == "1F1#".len() + 10 && f.ends_with("49")),
        "the remapped TPDO (6060h U32, 6081h 73) on 1F1h: {frames:?}"
    );
    assert!(!frames.iter().any(|f| f.starts_with("181#")), "{frames:?}");

    // Restore: nothing changes before the reset; reset node gives the defaults.
    m.handle_frame(ms(5), &CanFrame::standard(0, &[0x80, 1]).unwrap());
    let _ = sent(&mut m);
    assert_eq!(download(&mut m, 0x1011, 1, b"load"), ok(0x1011, 1));
    assert_eq!(tpdo1(&mut m), remapped);
    m.handle_frame(ms(6), &CanFrame::standard(0, &[0x81, 1]).unwrap());
    let _ = sent(&mut m);
    assert_eq!(tpdo1(&mut m), defaults);
    assert_eq!(upload(&mut m, 0x6080, 0), default_6080);

    // And in the next power cycle.
    let mut m = module(m.device_mut().take_storage().unwrap());
    assert_eq!(tpdo1(&mut m), defaults);
    assert_eq!(storage_events(&mut m), []);
}
