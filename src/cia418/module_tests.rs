use super::*;
use crate::machine::Machine;
use crate::nmt::NmtState;
use core::mem::MaybeUninit;

use crate::{CanFrame, PdoNumber};

fn module() -> BatteryModule {
    BatteryModule::new(BatteryModuleConfig::default())
}

fn drain(m: &mut BatteryModule) -> std::vec::Vec<CanFrame> {
    core::iter::from_fn(|| m.poll_transmit()).collect()
}

/// A module whose 1000h says it has the optional 2nd and 3rd RPDO and
/// TPDO (bits 16-19, CiA 418 section 6.2.1).
fn with_every_pdo() -> BatteryModule {
    BatteryModule::new(BatteryModuleConfig {
        device_type: DeviceType::cia418(0xF_0000),
        ..BatteryModuleConfig::default()
    })
}

#[test]
fn nothing_happens_before_boot() {
    let mut m = module();
    assert_eq!(m.poll_timeout(), None);
    m.handle_frame(
        Timestamp::ZERO,
        &CanFrame::standard(0x000, &[0x01, 0x00]).unwrap(),
    );
    m.handle_timeout(Timestamp::MAX);
    assert_eq!(m.nmt_state(), NmtState::BootUp);
    assert!(drain(&mut m).is_empty());
    assert_eq!(m.poll_event(), None);
}

#[test]
fn default_pdo_set_follows_the_device_type() {
    let mut config = BatteryModuleConfig::default();
    let mut pdos = PdoConfig::new();
    default_pdo_config(
        &BatteryModulePowerOn::from(config),
        config.device_type,
        &mut pdos,
    );
    assert!(pdos
        .get(PdoDirection::Transmit, PdoNumber::P0)
        .unwrap()
        .is_valid());
    assert!(pdos.get(PdoDirection::Transmit, PdoNumber::P1).is_none());
    assert!(pdos
        .get(PdoDirection::Receive, PdoNumber::P0)
        .unwrap()
        .is_valid());
    config.enable_tpdos = false;
    config.device_type = DeviceType::cia418(DeviceType::TPDO_2ND | DeviceType::RPDO_3RD);
    let mut pdos = PdoConfig::new();
    default_pdo_config(
        &BatteryModulePowerOn::from(config),
        config.device_type,
        &mut pdos,
    );
    let t1 = pdos.get(PdoDirection::Transmit, PdoNumber::P1).unwrap();
    assert_eq!(t1.comm.cob_id.to_u32(), 0x8000_0281);
    assert_eq!(t1.count(), 3);
    assert!(pdos.get(PdoDirection::Receive, PdoNumber::P2).is_some());
    assert!(pdos.get(PdoDirection::Receive, PdoNumber::P1).is_none());
}

#[test]
fn hostile_frames_and_times_never_panic() {
    let mut m = with_every_pdo();
    m.boot(Timestamp::MAX);
    let ids = [
        0x000u16, 0x080, 0x081, 0x181, 0x201, 0x301, 0x401, 0x601, 0x701, 0x7FF,
    ];
    let mut t = 0u64;
    for (i, id) in ids.iter().cycle().take(2_000).enumerate() {
        let len = i % 9;
        let data: std::vec::Vec<u8> = (0..len).map(|k| (i * 31 + k * 7) as u8).collect();
        let frame = CanFrame::standard(*id, &data).unwrap();
        t = t.wrapping_mul(6364136223846793005).wrapping_add(i as u64);
        let now = Timestamp::from_micros(t);
        m.handle_frame(now, &frame);
        m.handle_timeout(now);
        let _ = drain(&mut m);
        while m.poll_event().is_some() {}
        let _ = m.poll_timeout();
    }
}

#[test]
fn a_full_event_queue_drops_the_oldest() {
    let mut m = module();
    for sub in 0..20u8 {
        m.device_mut()
            .push_event(BatteryEvent::ObjectWritten { index: 0x6001, sub });
    }
    let subs: std::vec::Vec<u8> = core::iter::from_fn(|| m.poll_event())
        .map(|e| match e {
            BatteryEvent::ObjectWritten { sub, .. } => sub,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(subs, (4..20).collect::<std::vec::Vec<u8>>());
    assert_eq!(m.events_dropped(), 4);
}

/// The module's PDO configuration has room for its 3 TPDOs and 3 RPDOs
/// only: a fourth given by the application is ignored, and its objects stay
/// absent over SDO (06020000h) while the third's are served.
#[test]
fn a_fourth_pdo_has_no_room() {
    use crate::od::ObjectDictionary;
    use crate::pdo::{PdoCobId, PdoCommParams, PdoMapping, PdoSlot};
    let mut m = with_every_pdo();
    m.boot(Timestamp::ZERO);
    let slot = PdoSlot::new(
        PdoCommParams::event_driven(PdoCobId::standard(0x481), 0),
        &PdoMapping::EMPTY,
    );
    m.update_pdos(Timestamp::ZERO, |c| {
        for dir in [PdoDirection::Transmit, PdoDirection::Receive] {
            c.insert(dir, PdoNumber::P3, slot);
            c.insert(dir, PdoNumber::P2, slot);
        }
    });
    let mut od = m.dictionary().clone();
    for dir in [PdoDirection::Transmit, PdoDirection::Receive] {
        assert_eq!(m.pdo_config().get(dir, PdoNumber::P2), Some(&slot));
        assert_eq!(m.pdo_config().get(dir, PdoNumber::P3), None);
        let mut buf = [0u8; 4];
        let (third, fourth) = (dir.comm_index(PdoNumber::P2), dir.comm_index(PdoNumber::P3));
        assert_eq!(od.read(third, 1, 0, &mut buf), Ok(4));
        assert_eq!(buf, [0x81, 0x04, 0, 0]);
        assert_eq!(
            od.read(fourth, 1, 0, &mut buf),
            Err(crate::abort::AbortCode::ObjectDoesNotExist)
        );
    }
}

/// Over SDO: an upload of 1802h:01 (the 3rd TPDO's COB-ID) is answered,
/// one of 1803h:01 or 1A03h:00 is aborted with 06020000h.
#[test]
fn sdo_sees_three_tpdos() {
    let mut m = with_every_pdo();
    m.boot(Timestamp::ZERO);
    drain(&mut m);
    let mut upload = |index: u16, sub: u8| {
        let [lo, hi] = index.to_le_bytes();
        let req = CanFrame::standard(0x601, &[0x40, lo, hi, sub, 0, 0, 0, 0]).unwrap();
        m.handle_frame(Timestamp::ZERO, &req);
        drain(&mut m)
            .iter()
            .map(|f| std::format!("{f}"))
            .collect::<std::vec::Vec<_>>()
    };
    assert_eq!(upload(0x1802, 1), ["581#4302180181030000"]);
    assert_eq!(upload(0x1803, 1), ["581#8003180100000206"]);
    assert_eq!(upload(0x1A03, 0), ["581#80031A0000000206"]);
    assert_eq!(upload(0x1402, 1), ["581#4302140101040000"]);
    assert_eq!(upload(0x1403, 1), ["581#8003140100000206"]);
}

#[test]
fn new_in_builds_what_new_builds() {
    let config = BatteryModuleConfig {
        device_type: DeviceType::cia418(
            DeviceType::RPDO_2ND | DeviceType::RPDO_3RD | DeviceType::TPDO_3RD,
        ),
        device_name: "BM-5",
        identity: crate::device::Identity {
            vendor_id: 7,
            serial_number: 42,
            ..crate::device::Identity::ZERO
        },
        ..BatteryModuleConfig::new(NodeId::new(5).unwrap())
    };
    let mut slot = MaybeUninit::<BatteryModule<4>>::uninit();
    let built_in = BatteryModule::new_in(&mut slot, config);
    let mut built = BatteryModule::<4>::with_queue_capacity(config);
    assert_eq!(built_in.config(), built.config());
    assert_eq!(built_in.comm(), built.comm());
    // 1000h, 1008h and 1018h are the configuration's in both.
    assert_eq!(
        (built_in.comm().device_type, built_in.comm().device_name),
        (config.device_type.raw(), "BM-5")
    );
    assert_eq!(built_in.comm().identity, config.identity);
    assert_eq!(built_in.pdo_config(), built.pdo_config());
    assert_eq!(built_in.poll_timeout(), None);
    for m in [&mut *built_in, &mut built] {
        m.boot(Timestamp::ZERO);
        m.handle_frame(
            Timestamp::ZERO,
            &CanFrame::standard(0x000, &[0x01, 0x05]).unwrap(),
        );
    }
    let frames = |m: &mut BatteryModule<4>| {
        core::iter::from_fn(|| m.poll_transmit()).collect::<std::vec::Vec<_>>()
    };
    let expected = frames(&mut built);
    assert_eq!(
        expected
            .first()
            .map(std::string::ToString::to_string)
            .as_deref(),
        Some("705#00")
    );
    assert_eq!(frames(built_in), expected);
    assert_eq!(built_in.poll_timeout(), built.poll_timeout());
}
