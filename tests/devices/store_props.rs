//! Property tests of store / restore (1010h, CiA 301 section 7.5.2.13) on
//! the battery module: any bytes stored as any group's record are loaded or
//! ignored at boot and reset node, never a panic, and an ignored record
//! leaves the defaults; one flipped bit of a good record is always caught
//! (the CRC-16); what 1010h stores (heartbeat, a TPDO's COB-ID and event
//! timer, an application parameter) comes back in a new module on the same
//! storage.

use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig};
use canopen_codec::cob_id::PdoNumber;
use canopen_codec::device::{
    DeviceEvent, ParameterGroup, ParameterStorage, RamStorage, StorageEvent,
};
use canopen_codec::machine::Machine;
use canopen_codec::pdo::{PdoCobId, PdoDirection};
use canopen_codec::{CanFrame, NodeId, Timestamp};
use proptest::prelude::*;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 512,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::Direct(
                "tests/proptest-regressions/store_props.txt",
            ),
        )),
        ..ProptestConfig::default()
    }
}

const GROUPS: [ParameterGroup; 3] = [
    ParameterGroup::Communication,
    ParameterGroup::Application,
    ParameterGroup::Lss,
];

fn module(storage: RamStorage) -> BatteryModule {
    let mut m = BatteryModule::new(BatteryModuleConfig::new(NodeId::new(1).unwrap()));
    m.device_mut().set_storage(Box::leak(Box::new(storage)));
    m.boot(Timestamp::ZERO);
    m
}

fn drain(m: &mut BatteryModule) -> Vec<StorageEvent> {
    while m.poll_transmit().is_some() {}
    std::iter::from_fn(|| m.poll_event())
        .filter_map(|e| match e {
            DeviceEvent::Storage(s) => Some(s),
            _ => None,
        })
        .collect()
}

/// What the tests compare: 1017h, TPDO 1's COB-ID and event timer, 6080h.
fn observed(m: &BatteryModule) -> (u16, u32, u16, u8) {
    let slot = m
        .pdo_config()
        .get(PdoDirection::Transmit, PdoNumber::P0)
        .unwrap();
    (
        m.comm().heartbeat_ms,
        slot.comm.cob_id.to_u32(),
        slot.comm.event_timer_ms,
        m.objects().charger_state_of_charge.raw(),
    )
}

fn defaults() -> (u16, u32, u16, u8) {
    observed(&module(RamStorage::new()))
}

fn save_all(m: &mut BatteryModule) {
    let request = [0x23, 0x10, 0x10, 1, 0x73, 0x61, 0x76, 0x65];
    m.handle_frame(
        Timestamp::ZERO,
        &CanFrame::standard(0x601, &request).unwrap(),
    );
}

/// A module's stored records, copied into a storage of one's own.
fn records(m: &mut BatteryModule) -> RamStorage {
    let storage = m.device_mut().take_storage().unwrap();
    let mut copy = RamStorage::new();
    let mut buf = [0u8; 512];
    for group in GROUPS {
        let n = storage.load(group, &mut buf).unwrap();
        if n > 0 {
            copy.save(group, &buf[..n]).unwrap();
        }
    }
    copy
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn any_record_is_loaded_or_ignored(
        comm in proptest::collection::vec(any::<u8>(), 0..512),
        app in proptest::collection::vec(any::<u8>(), 0..64),
        lss in proptest::collection::vec(any::<u8>(), 0..32),
    ) {
        let mut storage = RamStorage::new();
        for (group, bytes) in GROUPS.into_iter().zip([&comm, &app, &lss]) {
            storage.save(group, bytes).unwrap();
        }
        let mut m = module(storage);
        let events = drain(&mut m);
        for e in &events {
            prop_assert!(matches!(e, StorageEvent::Ignored { .. }), "{e:?}");
        }
        prop_assert_eq!(observed(&m), defaults());
        m.handle_frame(Timestamp::ZERO, &CanFrame::standard(0, &[0x81, 1]).unwrap());
        let _ = drain(&mut m);
        prop_assert_eq!(observed(&m), defaults());
    }

    #[test]
    fn a_flipped_bit_is_always_caught(group in 0usize..2, bit in 0usize..(12 * 8)) {
        let mut m = module(RamStorage::new());
        m.update_comm(Timestamp::ZERO, |c| c.heartbeat_ms = 321);
        m.update(Timestamp::ZERO, |o| o.charger_state_of_charge = canopen_codec::cia418::StateOfCharge::from_raw(9));
        save_all(&mut m);
        let mut storage = records(&mut m);
        let record = storage.record_mut(GROUPS[group]);
        let bit = bit % (record.len() * 8);
        record[bit / 8] ^= 1 << (bit % 8);
        let mut m = module(storage);
        let events = drain(&mut m);
        prop_assert!(
            events.iter().any(|e| matches!(e, StorageEvent::Ignored { group: g, .. } if *g == GROUPS[group])),
            "{events:?}"
        );
    }

    #[test]
    fn what_is_stored_comes_back(
        heartbeat in any::<u16>(),
        id in 0x181u16..0x1FF,
        timer in any::<u16>(),
        soc in 0u8..=100,
    ) {
        let mut m = module(RamStorage::new());
        m.update_comm(Timestamp::ZERO, |c| c.heartbeat_ms = heartbeat);
        m.update_pdos(Timestamp::ZERO, |p| {
            let slot = p.get_mut(PdoDirection::Transmit, PdoNumber::P0).unwrap();
            slot.comm.cob_id = PdoCobId::standard(id);
            slot.comm.event_timer_ms = timer;
        });
        m.update(Timestamp::ZERO, |o| o.charger_state_of_charge = canopen_codec::cia418::StateOfCharge::from_raw(soc));
        let _ = drain(&mut m);
        save_all(&mut m);
        let stored = observed(&m);
        prop_assert_eq!(stored, (heartbeat, u32::from(id), timer, soc));
        let mut again = module(records(&mut m));
        prop_assert_eq!(
            drain(&mut again),
            vec![
                StorageEvent::Loaded(ParameterGroup::Communication),
                StorageEvent::Loaded(ParameterGroup::Application)
            ]
        );
        prop_assert_eq!(observed(&again), stored);
    }
}
