//! The CiA 418 battery module under arbitrary frames and time steps.
//! Invariants: no panic; every frame it sends is its own (heartbeat 701h,
//! EMCY 81h, SDO response 581h) or one of its valid TPDO COB-IDs, and TPDOs
//! only in NMT operational; a twin module whose events are never read sends
//! exactly the same frames and has the same deadlines (back-pressure).
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig, DeviceType};
use canopen_codec::machine::Machine;
use canopen_codec::nmt::NmtState;
use canopen_codec::pdo::PdoDirection;
use canopen_codec::{CanFrame, CanId, NodeId, PdoNumber, Timestamp};
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    Frame { id_sel: u8, raw_id: u16, data: [u8; 8], len: u8 },
    Advance { micros: u32, backwards: bool },
    Fault(bool),
}

const IDS: [u16; 8] = [0x000, 0x601, 0x201, 0x301, 0x401, 0x080, 0x70A, 0x18A];

fuzz_target!(|input: (u8, Vec<Op>)| {
    let (bits, ops) = input;
    let mut config = BatteryModuleConfig::new(NodeId::new(1).unwrap());
    config.device_type = DeviceType::cia418(u32::from(bits & 0x1F) << 16);
    let mut m = BatteryModule::new(config);
    // A twin whose events are never read: the back-pressure rule says it
    // sends exactly the same frames at the same deadlines.
    let mut twin = BatteryModule::new(config);
    let mut now = Timestamp::from_millis(1);
    m.boot(now);
    twin.boot(now);
    for op in ops.into_iter().take(300) {
        match op {
            Op::Frame { id_sel, raw_id, data, len } => {
                let id = IDS.get(usize::from(id_sel)).copied().unwrap_or(raw_id & 0x7FF);
                let len = usize::from(len % 9);
                let f = CanFrame::new(CanId::Standard(id), &data[..len]).unwrap();
                m.handle_frame(now, &f);
                twin.handle_frame(now, &f);
            }
            Op::Advance { micros, backwards } => {
                now = if backwards {
                    Timestamp::from_micros(now.as_micros().saturating_sub(u64::from(micros)))
                } else {
                    now.add_micros(u64::from(micros) * 8)
                };
                m.handle_timeout(now);
                twin.handle_timeout(now);
            }
            Op::Fault(on) => {
                m.set_temperature_sensor_fault(now, on);
                twin.set_temperature_sensor_fault(now, on);
            }
        }
        assert_eq!(m.poll_timeout(), twin.poll_timeout(), "deadlines differ when undrained");
        while let Some(f) = m.poll_transmit() {
            assert_eq!(twin.poll_transmit(), Some(f), "undrained twin sent otherwise");
            let CanId::Standard(id) = f.id() else { panic!("29-bit frame sent: {f}") };
            if [0x701, 0x081, 0x581].contains(&id) {
                continue;
            }
            let pdos = m.pdo_config();
            let is_tpdo = [PdoNumber::P0, PdoNumber::P1, PdoNumber::P2, PdoNumber::P3].iter().any(|n| {
                pdos.get(PdoDirection::Transmit, *n)
                    .is_some_and(|s| s.is_valid() && s.comm.cob_id.can_id() == Some(f.id()))
            });
            assert!(is_tpdo, "frame for another node's COB-ID: {f}");
            assert_eq!(m.nmt_state(), NmtState::Operational, "TPDO outside operational: {f}");
        }
        assert_eq!(twin.poll_transmit(), None, "undrained twin sent more");
        while m.poll_event().is_some() {}
        assert_eq!(m.events_dropped(), 0, "drained after every step: nothing dropped");
    }
});
