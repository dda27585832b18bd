//! An LSS master and two non-configured LSS slaves (CiA 305) on a loopback
//! bus under an arbitrary sequence of master commands, raw frames to
//! either side, time steps and store answers. Invariants: no panic; every
//! frame sent is 8 bytes on 7E5h (master) or 7E4h (slaves); a slave's
//! node-ID only changes from a configure node-ID request with a valid
//! value (1..=127 or 255) received in configuration state, and becomes
//! exactly that value; each fastscan ends in found / not found at most
//! once, and a search no raw frame disturbed that found a slave found one
//! of the two real addresses.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::lss::{
    LssAddress, LssErrorCode, LssField, LssInquiry, LssMaster, LssMasterEvent, LssMode, LssRequest,
    LssSlave, LssSlaveConfig, LssState, LssStatus,
};
use canopen_codec::machine::Machine;
use canopen_codec::{CanFrame, Codec, NodeId, Timestamp};
use core::time::Duration;
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    Fastscan,
    FastscanAssign(u8),
    Global(bool),
    Selective(bool),
    Configure(u8),
    Store,
    Inquire(u8),
    BitTiming(u8, u8),
    Cancel,
    ToSlaves { data: [u8; 8], len: u8 },
    ToMaster { data: [u8; 8], len: u8 },
    Fastscan51 { id: u32, bit: u8, sub: u8, next: u8 },
    AnswerStore { which: bool, code: u8 },
    Reset { which: bool },
    Advance { micros: u16 },
}

const A: LssAddress = LssAddress {
    vendor: 0x29A,
    product: 0x418,
    revision: 1,
    serial: 0x8000_0001,
};
const B: LssAddress = LssAddress {
    vendor: 0x29A,
    product: 0x418,
    revision: 1,
    serial: 0x0000_0007,
};

struct Bus {
    now: Timestamp,
    master: LssMaster,
    slaves: [LssSlave; 2],
    searching: bool,
    tainted: bool,
}

impl Bus {
    fn to_slaves(&mut self, frame: &CanFrame) {
        let request = LssRequest::parse(frame.data()).ok();
        for s in &mut self.slaves {
            let before = s.pending_node_id();
            let configuring = s.state() == LssState::Configuration;
            s.handle_frame(self.now, frame);
            let after = s.pending_node_id();
            if after != before {
                let raw = match request {
                    Some(LssRequest::ConfigureNodeId(raw)) if frame.id().raw() == 0x7E5 => raw,
                    other => panic!("node-ID changed by {other:?}"),
                };
                assert!(configuring, "configured outside configuration state");
                assert!(raw == 255 || (1..=127).contains(&raw), "raw {raw}");
                assert_eq!(after, NodeId::new(raw));
            }
        }
    }

    fn settle(&mut self) {
        for _ in 0..64 {
            let mut quiet = true;
            while let Some(f) = self.master.poll_transmit() {
                quiet = false;
                assert_eq!((f.id().raw(), f.dlc()), (0x7E5, 8));
                self.to_slaves(&f);
            }
            for i in 0..2 {
                while let Some(f) = self.slaves[i].poll_transmit() {
                    quiet = false;
                    assert_eq!((f.id().raw(), f.dlc()), (0x7E4, 8));
                    self.master.handle_frame(self.now, &f);
                }
                while self.slaves[i].poll_event().is_some() {}
            }
            while let Some(e) = self.master.poll_event() {
                match e {
                    LssMasterEvent::FastscanFound(found) => {
                        assert!(self.searching, "a second end of one search");
                        self.searching = false;
                        if !self.tainted {
                            assert!(found == A || found == B, "{found:?}");
                        }
                    }
                    LssMasterEvent::FastscanNotFound => {
                        assert!(self.searching, "a second end of one search");
                        self.searching = false;
                    }
                    _ => {}
                }
            }
            if quiet {
                return;
            }
        }
    }
}

fn frame(id: u16, data: &[u8; 8], len: u8) -> CanFrame {
    CanFrame::standard(id, &data[..usize::from(len % 9)]).unwrap()
}

fuzz_target!(|ops: Vec<Op>| {
    let mut bus = Bus {
        now: Timestamp::ZERO,
        master: LssMaster::new(Duration::from_millis(1)),
        slaves: [
            LssSlave::new(LssSlaveConfig::new(A, None)),
            LssSlave::new(LssSlaveConfig::new(B, None)),
        ],
        searching: false,
        tainted: false,
    };
    for op in ops.into_iter().take(2048) {
        let now = bus.now;
        match op {
            Op::Fastscan => {
                if bus.master.fastscan(now).is_ok() {
                    assert!(!bus.searching);
                    bus.searching = true;
                    bus.tainted = false;
                }
            }
            Op::FastscanAssign(raw) => {
                if let Some(node) = NodeId::new(raw) {
                    if bus.master.fastscan_assign(now, node).is_ok() {
                        assert!(!bus.searching);
                        bus.searching = true;
                        bus.tainted = false;
                    }
                }
            }
            Op::Global(c) => bus.master.switch_state_global(
                now,
                if c {
                    LssMode::Configuration
                } else {
                    LssMode::Waiting
                },
            ),
            Op::Selective(a) => {
                let _ = bus
                    .master
                    .switch_state_selective(now, if a { A } else { B });
            }
            Op::Configure(raw) => {
                let _ = bus.master.configure_node_id(now, NodeId::new(raw));
            }
            Op::Store => {
                let _ = bus.master.store_configuration(now);
            }
            Op::Inquire(w) => {
                let what =
                    LssField::from_index(w % 5).map_or(LssInquiry::NodeId, LssInquiry::Address);
                let _ = bus.master.inquire(now, what);
            }
            Op::BitTiming(t, i) => {
                let _ = bus.master.configure_bit_timing(now, t, i);
            }
            Op::Cancel => {
                if bus.master.is_busy() {
                    bus.master.cancel();
                    bus.searching = false;
                }
            }
            Op::ToSlaves { data, len } => bus.to_slaves(&frame(0x7E5, &data, len)),
            Op::ToMaster { data, len } => {
                bus.tainted = true;
                bus.master.handle_frame(now, &frame(0x7E4, &data, len));
            }
            Op::Fastscan51 { id, bit, sub, next } => {
                let [a, b, c, d] = id.to_le_bytes();
                bus.to_slaves(&frame(0x7E5, &[0x51, a, b, c, d, bit, sub, next], 8));
            }
            Op::AnswerStore { which, code } => {
                let status = LssStatus {
                    code: LssErrorCode::from(code),
                    specific: 0,
                };
                let _ = bus.slaves[usize::from(which)].answer_store(status);
            }
            Op::Reset { which } => {
                let _ = bus.slaves[usize::from(which)].reset_communication();
            }
            Op::Advance { micros } => {
                bus.now = bus.now.add_micros(u64::from(micros));
                bus.master.handle_timeout(bus.now);
            }
        }
        bus.settle();
        // A search always has a deadline until it ends.
        if bus.searching {
            assert!(bus.master.poll_timeout().is_some());
        }
    }
    // Run the master's timers out: a running search ends exactly once.
    for _ in 0..200 {
        let Some(t) = bus.master.poll_timeout() else {
            break;
        };
        bus.now = t;
        bus.master.handle_timeout(t);
        bus.settle();
    }
    assert!(!bus.searching, "a search that never ended");
});
