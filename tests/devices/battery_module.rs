//! The CiA 418 battery module (`cia418::BatteryModule`) driven through its
//! public API only, frame by frame: boot-up, heartbeat, NMT, TPDOs, RPDOs,
//! SDO and EMCY.

use crate::common;

use canopen_codec::cia418::{
    BatteryEvent, BatteryModule, BatteryModuleConfig, BatteryStatus, ChargerStatus, DeviceType,
    PackedStringObject, Temperature,
};
use canopen_codec::emcy::ErrorRegister;
use canopen_codec::machine::Machine;
use canopen_codec::nmt::NmtState;
use canopen_codec::pdo::{PdoDirection, RpdoError};
use canopen_codec::sdo::{AbortCode, AbortOrigin};
use canopen_codec::{CanFrame, NodeId, PdoNumber, Timestamp};
use common::sim::{bus, Bus, Handle};

/// A module alone on the simulated bus (`common::sim`, no latency): the
/// test is the other end. Every frame the module sends is logged as
/// `(ms, candump text)`.
struct Bench {
    sim: Bus,
    h: Handle<BatteryModule>,
    /// How much of the sim's log has been collected.
    seen: usize,
    log: Vec<(u64, String)>,
}

impl Bench {
    fn with(config: BatteryModuleConfig) -> Self {
        let mut sim = bus(0);
        let h = sim.add("Battery", BatteryModule::new(config));
        sim.set_drain_events(h, false);
        sim.with(h, |m, now| m.boot(now));
        let mut b = Bench {
            sim,
            h,
            seen: 0,
            log: Vec::new(),
        };
        b.collect();
        b
    }

    fn new() -> Self {
        Self::with(BatteryModuleConfig::new(NodeId::new(1).unwrap()))
    }

    /// The module (for its getters).
    fn m(&self) -> &BatteryModule {
        self.sim.machine(self.h).unwrap()
    }

    /// The bus's clock.
    fn now(&self) -> Timestamp {
        self.sim.now()
    }

    /// Runs a command on the module at the current time; its frames go out.
    fn run(&mut self, f: impl FnOnce(&mut BatteryModule, Timestamp)) {
        self.sim.with(self.h, f);
    }

    /// Frames the module sent since the last call.
    fn collect(&mut self) -> Vec<String> {
        let mut out = Vec::new();
        for s in self.sim.log().iter().skip(self.seen) {
            if s.from == "Battery" {
                out.push(s.frame.to_string());
                self.log.push((s.at.as_millis(), s.frame.to_string()));
            }
        }
        self.seen = self.sim.log().len();
        out
    }

    /// Advances the clock to `ms`, firing every deadline on the way.
    fn advance_to(&mut self, ms: u64) {
        self.sim.run_until(Timestamp::from_millis(ms)).unwrap();
        self.collect();
    }

    /// Delivers a frame; returns what the module sent in answer.
    fn send(&mut self, id: u16, data: &[u8]) -> Vec<String> {
        self.sim.inject(CanFrame::standard(id, data).unwrap());
        let now = self.sim.now();
        self.sim.run_until(now).unwrap();
        self.collect()
    }

    fn events(&mut self) -> Vec<BatteryEvent> {
        let h = self.h;
        std::iter::from_fn(|| self.sim.machine_mut(h).unwrap().poll_event()).collect()
    }

    fn take_log(&mut self) -> Vec<(u64, String)> {
        std::mem::take(&mut self.log)
    }

    /// Sends an SDO request to node 1 and returns the one response's data.
    fn sdo(&mut self, req: [u8; 8]) -> [u8; 8] {
        let mut resp = None;
        for f in self.send(0x601, &req) {
            if f.starts_with("581#") {
                assert!(resp.is_none(), "one response per request");
                let frame: CanFrame = canopen_codec::trace::candump::parse_frame(&f).unwrap();
                resp = Some(frame.padded_data());
            }
        }
        resp.expect("an SDO response")
    }

    /// A full SDO upload (expedited or segmented) through raw frames.
    fn upload(&mut self, index: u16, sub: u8) -> Result<Vec<u8>, u32> {
        let [lo, hi] = index.to_le_bytes();
        let r = self.sdo([0x40, lo, hi, sub, 0, 0, 0, 0]);
        match r[0] {
            0x80 => return Err(u32::from_le_bytes([r[4], r[5], r[6], r[7]])),
            cs if cs & 0xE3 == 0x43 => {
                let n = 4 - usize::from((cs >> 2) & 3);
                return Ok(r[4..4 + n].to_vec());
            }
            0x41 => {}
            other => panic!("unexpected initiate response {other:02X}"),
        }
        let size = u32::from_le_bytes([r[4], r[5], r[6], r[7]]) as usize;
        let mut data = Vec::new();
        let mut toggle = 0u8;
        loop {
            let s = self.sdo([0x60 | toggle, 0, 0, 0, 0, 0, 0, 0]);
            assert_eq!(s[0] & 0xE0, 0, "upload segment response");
            assert_eq!(s[0] & 0x10, toggle, "toggle bit");
            let n = 7 - usize::from((s[0] >> 1) & 7);
            data.extend_from_slice(&s[1..1 + n]);
            if s[0] & 1 == 1 {
                break;
            }
            toggle ^= 0x10;
        }
        assert_eq!(data.len(), size);
        Ok(data)
    }

    /// An expedited SDO download; `Err(abort code)` on an abort.
    fn download(&mut self, index: u16, sub: u8, value: &[u8]) -> Result<(), u32> {
        let [lo, hi] = index.to_le_bytes();
        let cs = 0x23 | (((4 - value.len()) as u8) << 2);
        let mut req = [cs, lo, hi, sub, 0, 0, 0, 0];
        req[4..4 + value.len()].copy_from_slice(value);
        let r = self.sdo(req);
        match r[0] {
            0x60 => Ok(()),
            0x80 => {
                assert_eq!(&r[1..4], &[lo, hi, sub], "abort names the object");
                Err(u32::from_le_bytes([r[4], r[5], r[6], r[7]]))
            }
            other => panic!("unexpected download response {other:02X}"),
        }
    }
}

fn with_id(log: &[(u64, String)], prefix: &str) -> Vec<(u64, String)> {
    log.iter()
        .filter(|(_, f)| f.starts_with(prefix))
        .cloned()
        .collect()
}

fn node1() -> BatteryModuleConfig {
    BatteryModuleConfig::new(NodeId::new(1).unwrap())
}

#[test]
fn boot_up_message_at_boot() {
    let mut b = Bench::new();
    assert_eq!(b.take_log(), vec![(0, "701#00".to_string())]);
    assert_eq!(b.m().nmt_state(), NmtState::PreOperational);
    assert_eq!(
        b.events(),
        vec![BatteryEvent::NmtStateChanged {
            from: NmtState::BootUp,
            to: NmtState::PreOperational
        }]
    );
}

#[test]
fn heartbeat_every_1017h_period() {
    let mut b = Bench::new();
    b.take_log();
    b.advance_to(3_500);
    assert_eq!(
        b.take_log(),
        vec![
            (1_000, "701#7F".to_string()),
            (2_000, "701#7F".to_string()),
            (3_000, "701#7F".to_string())
        ]
    );
    // An SDO write to 1017h changes the period at once.
    assert_eq!(b.download(0x1017, 0, &500u16.to_le_bytes()), Ok(()));
    assert_eq!(
        b.events(),
        vec![
            BatteryEvent::NmtStateChanged {
                from: NmtState::BootUp,
                to: NmtState::PreOperational
            },
            BatteryEvent::ObjectWritten {
                index: 0x1017,
                sub: 0
            }
        ]
    );
    b.advance_to(4_600);
    assert_eq!(
        with_id(&b.take_log(), "701#"),
        vec![(4_000, "701#7F".to_string()), (4_500, "701#7F".to_string())]
    );
}

#[test]
fn nmt_start_sends_tpdo0_every_200ms_with_application_values() {
    let mut b = Bench::new();
    b.run(|m, now| m.set_temperature(now, Temperature::from_celsius(25).unwrap()));
    b.run(|m, now| m.set_battery_status(now, BatteryStatus::READY_TO_CHARGE));
    b.take_log();
    b.events();
    assert_eq!(b.send(0x000, &[0x01, 0x01]), vec!["181#C80001"]);
    assert_eq!(b.m().nmt_state(), NmtState::Operational);
    assert_eq!(
        b.events(),
        vec![BatteryEvent::NmtStateChanged {
            from: NmtState::PreOperational,
            to: NmtState::Operational
        }]
    );
    b.advance_to(650);
    let tpdos = with_id(&b.take_log(), "181#");
    assert_eq!(
        tpdos,
        vec![
            (0, "181#C80001".to_string()),
            (200, "181#C80001".to_string()),
            (400, "181#C80001".to_string()),
            (600, "181#C80001".to_string())
        ]
    );
    // A changed mapped value is an event: sent at once, timer restarted.
    b.advance_to(700);
    b.run(|m, now| m.set_temperature(now, Temperature::from_raw(-80)));
    assert_eq!(b.collect(), vec!["181#B0FF01"]);
    b.advance_to(899);
    assert!(with_id(&b.take_log(), "181#").len() == 1);
    b.advance_to(900);
    assert_eq!(b.take_log(), vec![(900, "181#B0FF01".to_string())]);
    // Heartbeat reports operational.
    b.advance_to(1_000);
    assert_eq!(
        with_id(&b.take_log(), "701#"),
        vec![(1_000, "701#05".to_string())]
    );
}

#[test]
fn no_tpdos_before_start_nor_after_stop() {
    let mut b = Bench::new();
    b.advance_to(1_100);
    assert!(with_id(&b.take_log(), "181#").is_empty());
    b.send(0x000, &[0x01, 0x00]); // start all
    b.advance_to(1_500);
    assert_eq!(with_id(&b.take_log(), "181#").len(), 3); // 1100, 1300, 1500
    b.send(0x000, &[0x02, 0x01]);
    assert_eq!(b.m().nmt_state(), NmtState::Stopped);
    b.advance_to(3_000);
    let log = b.take_log();
    assert!(with_id(&log, "181#").is_empty());
    assert_eq!(
        with_id(&log, "701#"),
        vec![(2_000, "701#04".to_string()), (3_000, "701#04".to_string())]
    );
    // No SDO in stopped.
    assert!(b.send(0x601, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]).is_empty());
    // Pre-operational again: SDO yes, TPDO no.
    b.send(0x000, &[0x80, 0x01]);
    assert_eq!(b.m().nmt_state(), NmtState::PreOperational);
    assert_eq!(b.upload(0x1000, 0), Ok(vec![0xA2, 0x01, 0x00, 0x00]));
    b.advance_to(3_900);
    assert!(with_id(&b.take_log(), "181#").is_empty());
}

#[test]
fn reset_communication_sends_boot_up_and_restores_pdo_defaults() {
    let mut b = Bench::new();
    assert_eq!(b.download(0x1017, 0, &500u16.to_le_bytes()), Ok(()));
    // Disable TPDO 0 and change its event timer by SDO.
    assert_eq!(b.download(0x1800, 1, &0x8000_0181u32.to_le_bytes()), Ok(()));
    assert_eq!(b.download(0x1800, 5, &500u16.to_le_bytes()), Ok(()));
    let t0 = *b
        .m()
        .pdo_config()
        .get(PdoDirection::Transmit, PdoNumber::P0)
        .unwrap();
    assert!(!t0.is_valid());
    assert_eq!(t0.comm.event_timer_ms, 500);
    b.send(0x000, &[0x01, 0x01]);
    b.advance_to(1_100);
    let log = b.take_log();
    assert!(with_id(&log, "181#").is_empty(), "disabled");
    assert_eq!(
        with_id(&log, "701#"),
        vec![
            (0, "701#00".to_string()),
            (500, "701#05".to_string()),
            (1_000, "701#05".to_string())
        ]
    );
    b.events();

    assert_eq!(b.send(0x000, &[0x82, 0x01]), vec!["701#00"]);
    assert_eq!(b.m().nmt_state(), NmtState::PreOperational);
    assert_eq!(
        b.events(),
        vec![
            BatteryEvent::Reset { node: false },
            BatteryEvent::NmtStateChanged {
                from: NmtState::Operational,
                to: NmtState::PreOperational
            }
        ]
    );
    let t0 = *b
        .m()
        .pdo_config()
        .get(PdoDirection::Transmit, PdoNumber::P0)
        .unwrap();
    assert!(t0.is_valid());
    assert_eq!(t0.comm.cob_id.to_u32(), 0x181);
    assert_eq!(t0.comm.event_timer_ms, 200);
    assert_eq!(b.upload(0x1800, 1), Ok(vec![0x81, 0x01, 0, 0]));
    assert_eq!(b.upload(0x1017, 0), Ok(vec![0xE8, 0x03]));
    // The heartbeat restarts from the reset with the default period.
    b.advance_to(2_100);
    assert_eq!(
        with_id(&b.take_log(), "701#"),
        vec![(1_100, "701#00".to_string()), (2_100, "701#7F".to_string())]
    );
    // Started again, TPDO 0 is back at 200 ms.
    b.send(0x000, &[0x01, 0x01]);
    b.advance_to(2_500);
    assert_eq!(with_id(&b.take_log(), "181#").len(), 3);
    // Reset node also boots again.
    assert_eq!(b.send(0x000, &[0x81, 0x00]), vec!["701#00"]);
    assert!(b.events().contains(&BatteryEvent::Reset { node: true }));
}

#[test]
fn tpdos_stay_disabled_without_enable_tpdos() {
    let mut b = Bench::with(BatteryModuleConfig {
        enable_tpdos: false,
        ..node1()
    });
    b.send(0x000, &[0x01, 0x01]);
    b.advance_to(1_000);
    assert!(with_id(&b.take_log(), "181#").is_empty());
    assert_eq!(b.upload(0x1800, 1), Ok(vec![0x81, 0x01, 0, 0x80]));
    // Enabling by SDO starts it at once.
    assert_eq!(b.download(0x1800, 1, &0x181u32.to_le_bytes()), Ok(()));
    b.advance_to(1_200);
    assert_eq!(with_id(&b.take_log(), "181#").len(), 2);
}

#[test]
fn sdo_upload_of_1008h_segmented_and_6030h_sub_1() {
    let mut b = Bench::with(BatteryModuleConfig {
        device_name: "Lead-acid BMS 48V",
        ..node1()
    });
    assert_eq!(b.upload(0x1008, 0), Ok(b"Lead-acid BMS 48V".to_vec()));
    b.run(|m, _| {
        m.set_text(PackedStringObject::BatterySerialNumber, "BATTERY")
            .unwrap()
    });
    assert_eq!(b.upload(0x6030, 0), Ok(vec![2]));
    assert_eq!(b.upload(0x6030, 1), Ok(vec![0x42, 0x41, 0x54, 0x54]));
    assert_eq!(b.upload(0x6030, 2), Ok(vec![0x45, 0x52, 0x59, 0x00]));
    assert_eq!(b.upload(0x6030, 3), Err(0x0609_0011));
    assert_eq!(b.upload(0x6099, 0), Err(0x0602_0000));
    assert_eq!(b.upload(0x1200, 1), Ok(vec![0x01, 0x06, 0, 0]));
    assert_eq!(b.upload(0x1200, 2), Ok(vec![0x81, 0x05, 0, 0]));
}

#[test]
fn sdo_download_to_6001h_and_read_only_6000h() {
    let mut b = Bench::new();
    b.events();
    assert_eq!(b.download(0x6001, 0, &[0x01]), Ok(()));
    assert_eq!(b.m().charger_status(), ChargerStatus::ENABLED);
    assert_eq!(
        b.events(),
        vec![BatteryEvent::ObjectWritten {
            index: 0x6001,
            sub: 0
        }]
    );
    assert_eq!(b.download(0x6000, 0, &[0x01]), Err(0x0601_0002));
    assert_eq!(
        b.events(),
        vec![BatteryEvent::SdoAborted {
            index: 0x6000,
            sub: 0,
            code: AbortCode::WriteOfReadOnlyObject,
            origin: AbortOrigin::Local
        }]
    );
    assert_eq!(b.download(0x6080, 0, &[55]), Ok(()));
    assert_eq!(b.m().charger_state_of_charge().percent(), Some(55));
    assert_eq!(b.download(0x6052, 0, &[0x10, 0x02]), Ok(()));
    assert_eq!(b.m().ah_returned_during_last_charge().raw(), 0x0210);
}

#[test]
fn charger_rpdo_writes_6001h_only_while_operational() {
    let mut b = Bench::new();
    b.events();
    b.send(0x201, &[0x01]);
    assert_eq!(
        b.m().charger_status(),
        ChargerStatus::empty(),
        "pre-operational"
    );
    assert!(b.events().is_empty());
    b.send(0x000, &[0x01, 0x01]);
    b.events();
    b.send(0x201, &[0x01]);
    assert_eq!(b.m().charger_status(), ChargerStatus::ENABLED);
    assert_eq!(
        b.events(),
        vec![BatteryEvent::RpdoReceived { pdo: PdoNumber::P0 }]
    );
    assert_eq!(b.upload(0x6001, 0), Ok(vec![0x01]));
}

/// Back-to-back RPDOs, delivered before anyone reads the module's events:
/// the device drains its RPDO receiver after every frame, so each one is
/// applied and reported, none lost (the receiver holds one event: a frame
/// is at most one RPDO).
#[test]
fn back_to_back_rpdos_are_each_applied() {
    let mut b = Bench::with(BatteryModuleConfig {
        device_type: DeviceType::cia418(DeviceType::RPDO_2ND),
        ..node1()
    });
    b.send(0x000, &[0x01, 0x01]);
    b.events();
    b.sim.inject(CanFrame::standard(0x201, &[0x01]).unwrap());
    b.sim
        .inject(CanFrame::standard(0x301, &[0x00, 0x34, 0x12]).unwrap());
    b.sim.inject(CanFrame::standard(0x201, &[0x01]).unwrap());
    b.sim
        .inject(CanFrame::standard(0x301, &[0x01, 0x10, 0x02]).unwrap());
    let now = b.now();
    b.sim.run_until(now).unwrap();
    let pdos = [PdoNumber::P0, PdoNumber::P1, PdoNumber::P0, PdoNumber::P1];
    assert_eq!(
        b.events(),
        pdos.map(|pdo| BatteryEvent::RpdoReceived { pdo }).to_vec()
    );
    assert_eq!(b.m().events_dropped(), 0);
    assert_eq!(b.m().charger_status(), ChargerStatus::ENABLED);
    assert_eq!(b.m().ah_returned_during_last_charge().raw(), 0x0210);
}

#[test]
fn short_rpdo_raises_emcy_8210h() {
    let mut b = Bench::with(BatteryModuleConfig {
        device_type: DeviceType::cia418(DeviceType::RPDO_2ND),
        ..node1()
    });
    b.send(0x000, &[0x01, 0x01]);
    b.events();
    // 2nd RPDO maps 6001h/8 + 6052h/16: 3 bytes; 2 arrive.
    let out = b.send(0x301, &[0x01, 0x10]);
    assert_eq!(out, vec!["081#1082110000000000"]);
    assert_eq!(
        b.events(),
        vec![BatteryEvent::RpdoRefused {
            pdo: PdoNumber::P1,
            error: RpdoError::TooShort { need: 3, got: 2 }
        }]
    );
    assert_eq!(
        b.m().charger_status(),
        ChargerStatus::empty(),
        "refused whole"
    );
    // The full length is accepted.
    assert!(b.send(0x301, &[0x01, 0x10, 0x02]).is_empty());
    assert_eq!(b.m().charger_status(), ChargerStatus::ENABLED);
    assert_eq!(b.m().ah_returned_during_last_charge().raw(), 0x0210);
    // An empty 1st RPDO is short too.
    assert_eq!(b.send(0x201, &[]), vec!["081#1082110000000000"]);
}

#[test]
fn temperature_sensor_fault_emcy_bytes() {
    let mut b = Bench::new();
    b.take_log();
    b.run(|m, now| m.set_temperature_sensor_fault(now, true));
    assert_eq!(b.collect(), vec!["081#1050210000000000"]);
    assert_eq!(
        b.m().error_register(),
        ErrorRegister::GENERIC | ErrorRegister::DEVICE_PROFILE
    );
    assert_eq!(b.upload(0x1001, 0), Ok(vec![0x21]));
    b.run(|m, now| m.set_temperature_sensor_fault(now, true));
    assert!(b.collect().is_empty(), "no repeat");
    b.run(|m, now| m.set_temperature_sensor_fault(now, false));
    assert_eq!(b.collect(), vec!["081#0000000000000000"]);
    assert_eq!(b.m().error_register(), ErrorRegister::empty());
    // Stopped: the register changes, no EMCY is sent.
    b.send(0x000, &[0x02, 0x01]);
    b.run(|m, now| m.set_temperature_sensor_fault(now, true));
    assert!(b.collect().is_empty());
    assert_eq!(b.m().error_register().bits(), 0x21);
}

#[test]
fn frames_for_other_nodes_are_ignored() {
    let mut b = Bench::new();
    b.take_log();
    b.events();
    assert!(b.send(0x000, &[0x01, 0x02]).is_empty());
    assert!(b.send(0x000, &[0x82, 0x02]).is_empty());
    assert!(b.send(0x000, &[0x01, 0x80]).is_empty());
    assert!(b.send(0x000, &[0x01]).is_empty());
    assert_eq!(b.m().nmt_state(), NmtState::PreOperational);
    assert!(b.send(0x602, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]).is_empty());
    b.send(0x000, &[0x01, 0x01]);
    b.take_log();
    b.events();
    b.send(0x202, &[0x01]);
    b.send(0x182, &[0x01, 0x02, 0x03]);
    b.send(0x702, &[0x05]);
    assert_eq!(b.m().charger_status(), ChargerStatus::empty());
    assert!(b.events().is_empty());
    assert!(b.take_log().is_empty());
}

/// CiA 418 v1.0.1, 7.3.1-7.3.18 (each object's type and access), row by
/// row, through the module's SDO frames: upload
/// length, and a download of that length accepted (rw) or refused with
/// 06010002h (ro, const).
#[test]
fn every_profile_object_through_sdo() {
    let rows: &[(u16, u8, bool, usize)] = &[
        (0x6000, 0, false, 1),
        (0x6001, 0, true, 1),
        (0x6010, 0, false, 2),
        (0x6020, 0, false, 1),
        (0x6020, 1, false, 1),
        (0x6020, 2, false, 2),
        (0x6020, 3, false, 2),
        (0x6020, 4, false, 2),
        (0x6030, 0, false, 1),
        (0x6030, 1, false, 4),
        (0x6031, 0, false, 1),
        (0x6031, 1, false, 4),
        (0x6040, 0, false, 1),
        (0x6040, 1, false, 4),
        (0x6041, 0, false, 1),
        (0x6041, 1, false, 4),
        (0x6050, 0, false, 4),
        (0x6051, 0, false, 2),
        (0x6052, 0, true, 2),
        (0x6053, 0, true, 2),
        (0x6054, 0, false, 1),
        (0x6054, 1, true, 2),
        (0x6054, 2, true, 2),
        (0x6060, 0, false, 4),
        (0x6070, 0, false, 2),
        (0x6080, 0, true, 1),
        (0x6081, 0, false, 1),
        (0x6090, 0, false, 1),
        (0x1000, 0, false, 4),
        (0x1001, 0, false, 1),
        (0x1017, 0, true, 2),
        (0x1018, 4, false, 4),
        (0x1200, 2, false, 4),
    ];
    let mut b = Bench::with(BatteryModuleConfig {
        device_type: DeviceType::cia418(0xF_0000),
        ..node1()
    });
    assert_eq!(b.upload(0x1000, 0), Ok(vec![0xA2, 0x01, 0x0F, 0x00]));
    for &(index, sub, writable, len) in rows {
        let value = b.upload(index, sub).unwrap();
        assert_eq!(value.len(), len, "{index:04X}h:{sub}");
        let got = b.download(index, sub, &vec![0x01; len]);
        if writable {
            assert_eq!(got, Ok(()), "{index:04X}h:{sub}");
            assert_eq!(b.upload(index, sub), Ok(vec![0x01; len]));
        } else {
            assert_eq!(got, Err(0x0601_0002), "{index:04X}h:{sub}");
        }
    }
    // All six default PDOs exist with the optional bits set.
    for n in [PdoNumber::P0, PdoNumber::P1, PdoNumber::P2] {
        assert!(b.m().pdo_config().get(PdoDirection::Receive, n).is_some());
        assert!(b.m().pdo_config().get(PdoDirection::Transmit, n).is_some());
    }
    assert_eq!(b.upload(0x1A01, 0), Ok(vec![3]));
    assert_eq!(b.upload(0x1A01, 3), Ok(vec![0x20, 0x00, 0x60, 0x60]));
}

#[test]
fn optional_pdos_declared_by_the_device_type() {
    use canopen_codec::cia418::{BatteryVoltage, ChargeCurrentRequested, StateOfCharge};
    let mut b = Bench::with(BatteryModuleConfig {
        device_type: DeviceType::cia418(0xF_0000),
        ..node1()
    });
    let now = b.now();
    b.run(|m, _| m.set_temperature(now, Temperature::from_celsius(25).unwrap()));
    b.run(|m, _| m.set_battery_status(now, BatteryStatus::READY_TO_CHARGE));
    b.run(|m, _| m.set_battery_voltage(now, BatteryVoltage::from_volts(48).unwrap()));
    b.run(|m, _| {
        m.set_charge_current_requested(now, ChargeCurrentRequested::from_amps(10).unwrap())
    });
    b.run(|m, _| m.set_battery_state_of_charge(now, StateOfCharge::new(80).unwrap()));
    let mut out = b.send(0x000, &[0x01, 0x00]);
    out.sort();
    assert_eq!(out, vec!["181#C80001", "281#C8000100C00000", "381#A00050"]);
    // 3rd RPDO: 6001h, 6052h, 6080h.
    assert!(b.send(0x401, &[0x01, 0x10, 0x02, 0x37]).is_empty());
    assert_eq!(b.m().charger_status(), ChargerStatus::ENABLED);
    assert_eq!(b.m().ah_returned_during_last_charge().raw(), 0x0210);
    assert_eq!(b.m().charger_state_of_charge().percent(), Some(55));
    b.take_log();
    b.advance_to(200);
    assert_eq!(b.take_log().len(), 3);
}
