//! The charger session under arbitrary frames and time steps. Invariants:
//! no panic; every frame it sends is its own (heartbeat 70Ah, EMCY 8Ah, SDO
//! response 58Ah, SDO request to the battery 601h) or one of its valid TPDO
//! COB-IDs; no TPDO before the PDO pairing is configured, outside NMT
//! operational, or on a not-valid COB-ID; a twin charger whose events are
//! never read sends exactly the same frames and has the same deadlines
//! (back-pressure).
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::deltaq::{Charger, ChargerConfig};
use canopen_codec::machine::Machine;
use canopen_codec::nmt::NmtState;
use canopen_codec::pdo::PdoDirection;
use canopen_codec::{CanFrame, CanId, NodeId, PdoNumber, Timestamp};
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    /// A frame; `id_sel` picks from ids that matter to the charger, or any.
    Frame { id_sel: u8, raw_id: u16, data: [u8; 8], len: u8 },
    Advance { micros: u32, backwards: bool },
}

const IDS: [u16; 10] = [0x000, 0x701, 0x581, 0x60A, 0x081, 0x181, 0x281, 0x381, 0x20A, 0x080];

fuzz_target!(|input: (bool, Vec<Op>)| {
    let (configure, ops) = input;
    let mut config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::new(1).unwrap());
    config.configure_cob_ids = configure;
    let mut c = Charger::new(config);
    // A twin whose events are never read: the back-pressure rule says it
    // sends exactly the same frames at the same deadlines.
    let mut twin = Charger::new(config);
    let mut now = Timestamp::from_millis(1);
    c.boot(now);
    twin.boot(now);
    for op in ops.into_iter().take(300) {
        match op {
            Op::Frame { id_sel, raw_id, data, len } => {
                let id = IDS.get(usize::from(id_sel)).copied().unwrap_or(raw_id & 0x7FF);
                let len = usize::from(len % 9);
                let f = CanFrame::new(CanId::Standard(id), &data[..len]).unwrap();
                c.handle_frame(now, &f);
                twin.handle_frame(now, &f);
            }
            Op::Advance { micros, backwards } => {
                now = if backwards {
                    Timestamp::from_micros(now.as_micros().saturating_sub(u64::from(micros)))
                } else {
                    now.add_micros(u64::from(micros) * 8)
                };
                c.handle_timeout(now);
                twin.handle_timeout(now);
            }
        }
        assert_eq!(c.poll_timeout(), twin.poll_timeout(), "deadlines differ when undrained");
        while let Some(f) = c.poll_transmit() {
            assert_eq!(twin.poll_transmit(), Some(f), "undrained twin sent otherwise");
            let CanId::Standard(id) = f.id() else { panic!("29-bit frame sent: {f}") };
            if [0x70A, 0x08A, 0x58A, 0x601].contains(&id) {
                continue;
            }
            // Anything else must be one of the charger's valid TPDOs, sent
            // while configured and operational.
            let pdos = c.pdo_config();
            let is_tpdo = [PdoNumber::P0, PdoNumber::P1, PdoNumber::P2, PdoNumber::P3].iter().any(|n| {
                pdos.get(PdoDirection::Transmit, *n)
                    .is_some_and(|s| s.is_valid() && s.comm.cob_id.can_id() == Some(f.id()))
            });
            assert!(is_tpdo, "frame for another node's COB-ID: {f}");
            assert!(c.is_configured(), "TPDO before configuration: {f}");
            assert_eq!(c.nmt_state(), NmtState::Operational, "TPDO outside operational: {f}");
        }
        assert_eq!(twin.poll_transmit(), None, "undrained twin sent more");
        while c.poll_event().is_some() {}
        assert_eq!(c.events_dropped(), 0, "drained after every step: nothing dropped");
    }
});
