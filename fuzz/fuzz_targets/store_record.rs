//! Fuzz the stored-parameter records of 1010h (CiA 301 section 7.5.2.13):
//! what a battery module loads at boot and at reset node from its
//! `ParameterStorage`.
//!
//! Input: byte 0 picks the group (bits 0-1: communication, application,
//! LSS) and, with bit 7, a valid record of the module's (its heartbeat
//! period from bytes 1-2) that the rest of the input is XORed into; without
//! bit 7 the rest is the record as it is.
//!
//! Invariants: boot and reset node never panic; each record gives at most
//! one event, `Loaded` or `Ignored`; an ignored communication record leaves
//! the defaults; whatever loads, stored again ("save" to 1010h) and loaded
//! by a new module, gives the same objects (load is the inverse of store).
#![no_main]

use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig};
use canopen_codec::device::{
    DeviceEvent, ParameterGroup, ParameterStorage, RamStorage, StorageEvent,
};
use canopen_codec::lss::{LssAddress, LssSlave, LssSlaveConfig};
use canopen_codec::machine::Machine;
use canopen_codec::{CanFrame, NodeId, Timestamp};
use libfuzzer_sys::fuzz_target;

const GROUPS: [ParameterGroup; 3] = [
    ParameterGroup::Communication,
    ParameterGroup::Application,
    ParameterGroup::Lss,
];

fn module(storage: RamStorage) -> BatteryModule {
    let lss = LssSlave::new(LssSlaveConfig::new(LssAddress::default(), NodeId::new(1)));
    let config = BatteryModuleConfig::new(NodeId::new(1).unwrap());
    let mut m = BatteryModule::with_lss(config, lss);
    m.device_mut().set_storage(Box::leak(Box::new(storage)));
    m.boot(Timestamp::ZERO);
    m
}

fn storage_events(m: &mut BatteryModule) -> Vec<StorageEvent> {
    while m.poll_transmit().is_some() {}
    std::iter::from_fn(|| m.poll_event())
        .filter_map(|e| match e {
            DeviceEvent::Storage(s) => Some(s),
            _ => None,
        })
        .collect()
}

fn save_all(m: &mut BatteryModule) {
    let request = [0x23, 0x10, 0x10, 1, 0x73, 0x61, 0x76, 0x65];
    m.handle_frame(
        Timestamp::ZERO,
        &CanFrame::standard(0x601, &request).unwrap(),
    );
}

/// The module's storage back as the box `module` leaked it from (so that
/// the leak sanitizer sees nothing leaked).
fn reclaim(m: &mut BatteryModule) -> Box<dyn ParameterStorage> {
    let storage: *mut dyn ParameterStorage = m.device_mut().take_storage().unwrap();
    // SAFETY: every storage a module has was made by `Box::leak` in
    // `module`, and `take_storage` hands it back once.
    unsafe { Box::from_raw(storage) }
}

/// A module's records copied into a storage of one's own.
fn records(m: &mut BatteryModule) -> RamStorage {
    let mut storage = reclaim(m);
    let mut copy = RamStorage::new();
    let mut buf = [0u8; 512];
    for group in GROUPS {
        let n = storage.load(group, &mut buf).unwrap();
        copy.save(group, &buf[..n]).unwrap();
    }
    copy
}

fn objects(m: &BatteryModule) -> String {
    format!("{:?} {:?} {:?}", m.comm(), m.pdo_config(), m.objects())
}

fuzz_target!(|data: &[u8]| {
    let Some((&selector, rest)) = data.split_first() else {
        return;
    };
    let group = GROUPS[usize::from(selector & 3) % 3];
    let record: Vec<u8> = if selector & 0x80 != 0 {
        let [a, b, mutation @ ..] = rest else { return };
        let mut m = module(RamStorage::new());
        m.update_comm(Timestamp::ZERO, |c| {
            c.heartbeat_ms = u16::from_le_bytes([*a, *b])
        });
        save_all(&mut m);
        let mut storage = records(&mut m);
        let mut valid = storage.record_mut(group).to_vec();
        for (byte, x) in valid.iter_mut().zip(mutation) {
            *byte ^= x;
        }
        valid
    } else {
        rest.iter().copied().take(512).collect()
    };
    let mut storage = RamStorage::new();
    storage.save(group, &record).unwrap();
    let mut fresh = module(RamStorage::new());
    let defaults = objects(&fresh);
    drop(reclaim(&mut fresh));

    let mut m = module(storage);
    for _ in 0..2 {
        let events = storage_events(&mut m);
        assert!(events.len() <= 2, "{events:?}");
        for e in &events {
            assert!(
                matches!(e, StorageEvent::Loaded(g) | StorageEvent::Ignored { group: g, .. } if *g == group),
                "{e:?}"
            );
        }
        let loaded = events.iter().any(|e| matches!(e, StorageEvent::Loaded(_)));
        if group == ParameterGroup::Communication && !loaded && !events.is_empty() {
            assert_eq!(objects(&m), defaults);
        }
        // Reset node loads again.
        m.handle_frame(Timestamp::ZERO, &CanFrame::standard(0, &[0x81, 1]).unwrap());
    }
    let _ = storage_events(&mut m);
    let before = objects(&m);
    save_all(&mut m);
    let mut again = module(records(&mut m));
    assert_eq!(objects(&again), before, "load is the inverse of store");
    let _ = storage_events(&mut again);
    drop(reclaim(&mut again));
});
