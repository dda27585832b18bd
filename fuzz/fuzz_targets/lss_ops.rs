//! An LSS master and two non-configured LSS slaves (CiA 305) on the
//! simulated bus (`canopen_codec::sim::bus`) under an arbitrary sequence of
//! master commands, raw frames put on the bus, time steps and store
//! answers. Every frame reaches every other machine, so the slaves also
//! hear each other's answers. Invariants, checked around every single
//! delivery through the bus's observer: no panic; every frame sent is 8
//! bytes on 7E5h (master) or 7E4h (slaves); a slave's node-ID only changes
//! from a configure node-ID request from the master (7E5h) with a valid
//! value (1..=127 or 255) received in configuration state, and becomes
//! exactly that value; each fastscan ends in found / not found at most
//! once, and a search no raw frame to the master disturbed that found a
//! slave found one of the two real addresses.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::lss::{
    LssAddress, LssErrorCode, LssField, LssInquiry, LssMaster, LssMasterEvent, LssMode, LssRequest,
    LssSlave, LssSlaveConfig, LssState, LssStatus,
};
use canopen_codec::machine::Machine;
use canopen_codec::sim::bus::{Bus, Delivery, Handle, OUTSIDE};
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

const MASTER: &str = "Master";
const SLAVES: [&str; 2] = ["A", "B"];

/// What the checks remember between two looks at the bus.
struct Checks {
    master: Handle<LssMaster>,
    slaves: [Handle<LssSlave>; 2],
    searching: bool,
    tainted: bool,
    /// Log entries and master events already checked.
    frames: usize,
    events: usize,
    /// The receiving slave's node-ID and whether it was in configuration
    /// state, just before the delivery being observed.
    before: (Option<NodeId>, bool),
}

impl Checks {
    fn slave<'a>(&self, bus: &'a Bus, name: &str) -> Option<&'a LssSlave> {
        let i = SLAVES.iter().position(|s| *s == name)?;
        bus.machine(*self.slaves.get(i)?)
    }

    /// Around each delivery: a slave's node-ID changes only as configured.
    fn delivery(&mut self, d: &Delivery, bus: &Bus) {
        if let Some(s) = self.slave(bus, d.to) {
            let now = (s.pending_node_id(), s.state() == LssState::Configuration);
            if !d.handled {
                self.before = now;
            } else if now.0 != self.before.0 {
                let raw = match LssRequest::parse(d.frame.data()).ok() {
                    Some(LssRequest::ConfigureNodeId(raw)) if d.frame.id().raw() == 0x7E5 => raw,
                    other => panic!("node-ID changed by {other:?} from {}", d.from),
                };
                assert!(self.before.1, "configured outside configuration state");
                assert!(raw == 255 || (1..=127).contains(&raw), "raw {raw}");
                assert_eq!(now.0, NodeId::new(raw));
            }
        }
        if d.handled {
            self.look(bus);
        }
    }

    /// The frames sent and the master's events since the last look.
    fn look(&mut self, bus: &Bus) {
        for s in bus.log().get(self.frames..).unwrap_or_default() {
            let id = match s.from {
                MASTER => 0x7E5,
                OUTSIDE => continue,
                _ => 0x7E4,
            };
            assert_eq!((s.frame.id().raw(), s.frame.dlc()), (id, 8), "from {}", s.from);
        }
        self.frames = bus.log().len();
        let events = bus.events(self.master);
        for (_, e) in events.get(self.events..).unwrap_or_default() {
            match e {
                LssMasterEvent::FastscanFound(found) => {
                    assert!(self.searching, "a second end of one search");
                    self.searching = false;
                    if !self.tainted {
                        assert!(*found == A || *found == B, "{found:?}");
                    }
                }
                LssMasterEvent::FastscanNotFound => {
                    assert!(self.searching, "a second end of one search");
                    self.searching = false;
                }
                _ => {}
            }
        }
        self.events = events.len();
    }
}

/// Runs everything due by `to`, checking around every delivery.
fn settle(bus: &mut Bus, checks: &mut Checks, to: Timestamp) {
    checks.look(bus);
    let run = bus.run_until_observed(to, &mut |d, bus| checks.delivery(d, bus));
    assert!(run.is_ok(), "{run:?}");
    checks.look(bus);
}

fn frame(id: u16, data: &[u8; 8], len: u8) -> CanFrame {
    CanFrame::standard(id, &data[..usize::from(len % 9)]).unwrap()
}

fuzz_target!(|ops: Vec<Op>| {
    let mut bus = Bus::new(Duration::ZERO);
    let master = bus.add(MASTER, LssMaster::new(Duration::from_millis(1)));
    let slaves = [
        bus.add(SLAVES[0], LssSlave::new(LssSlaveConfig::new(A, None))),
        bus.add(SLAVES[1], LssSlave::new(LssSlaveConfig::new(B, None))),
    ];
    let mut checks = Checks {
        master,
        slaves,
        searching: false,
        tainted: false,
        frames: 0,
        events: 0,
        before: (None, false),
    };
    for op in ops.into_iter().take(2048) {
        match op {
            Op::Fastscan => {
                if bus.with(master, |m, now| m.fastscan(now)).is_some_and(|r| r.is_ok()) {
                    assert!(!checks.searching);
                    checks.searching = true;
                    checks.tainted = false;
                }
            }
            Op::FastscanAssign(raw) => {
                if let Some(node) = NodeId::new(raw) {
                    let r = bus.with(master, |m, now| m.fastscan_assign(now, node));
                    if r.is_some_and(|r| r.is_ok()) {
                        assert!(!checks.searching);
                        checks.searching = true;
                        checks.tainted = false;
                    }
                }
            }
            Op::Global(c) => {
                let mode = if c { LssMode::Configuration } else { LssMode::Waiting };
                bus.with(master, |m, now| m.switch_state_global(now, mode));
            }
            Op::Selective(a) => {
                bus.with(master, |m, now| {
                    let _ = m.switch_state_selective(now, if a { A } else { B });
                });
            }
            Op::Configure(raw) => {
                bus.with(master, |m, now| {
                    let _ = m.configure_node_id(now, NodeId::new(raw));
                });
            }
            Op::Store => {
                bus.with(master, |m, now| {
                    let _ = m.store_configuration(now);
                });
            }
            Op::Inquire(w) => {
                let what =
                    LssField::from_index(w % 5).map_or(LssInquiry::NodeId, LssInquiry::Address);
                bus.with(master, |m, now| {
                    let _ = m.inquire(now, what);
                });
            }
            Op::BitTiming(t, i) => {
                bus.with(master, |m, now| {
                    let _ = m.configure_bit_timing(now, t, i);
                });
            }
            Op::Cancel => {
                let busy = bus.machine(master).is_some_and(LssMaster::is_busy);
                if busy {
                    bus.with(master, |m, _| m.cancel());
                    checks.searching = false;
                }
            }
            Op::ToSlaves { data, len } => bus.inject(frame(0x7E5, &data, len)),
            Op::ToMaster { data, len } => {
                checks.tainted = true;
                bus.inject(frame(0x7E4, &data, len));
            }
            Op::Fastscan51 { id, bit, sub, next } => {
                let [a, b, c, d] = id.to_le_bytes();
                bus.inject(frame(0x7E5, &[0x51, a, b, c, d, bit, sub, next], 8));
            }
            Op::AnswerStore { which, code } => {
                let status = LssStatus {
                    code: LssErrorCode::from(code),
                    specific: 0,
                };
                bus.with(slaves[usize::from(which)], |s, _| {
                    let _ = s.answer_store(status);
                });
            }
            Op::Reset { which } => {
                bus.with(slaves[usize::from(which)], |s, _| {
                    let _ = s.reset_communication();
                });
            }
            Op::Advance { micros } => {
                bus.advance(bus.now().add_micros(u64::from(micros)));
            }
        }
        let now = bus.now();
        settle(&mut bus, &mut checks, now);
        // A search always has a deadline until it ends.
        if checks.searching {
            assert!(bus.machine(master).and_then(Machine::poll_timeout).is_some());
        }
    }
    // Run the master's timers out: a running search ends exactly once.
    for _ in 0..200 {
        let Some(t) = bus.machine(master).and_then(Machine::poll_timeout) else {
            break;
        };
        settle(&mut bus, &mut checks, t);
    }
    assert!(!checks.searching, "a search that never ended");
});
