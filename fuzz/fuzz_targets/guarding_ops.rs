//! Node guarding, master and slave, under an arbitrary sequence of frames,
//! time steps and commands; the two are wired to each other (every frame
//! one sends reaches the other unless the input drops it) and both also
//! get arbitrary frames. Invariants: no panic; the master's lost and
//! restored events alternate (lost first) and agree with `is_lost`; the
//! slave's life-guarding lost and resumed events alternate the same way;
//! after every call neither machine has a timer at or before `now`; the
//! master sends only remote frames on 700h + node; the slave sends only
//! one-byte replies there, never while the heartbeat is active, with a
//! toggle that alternates from 0 after every reset.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::nmt::guarding::{
    GuardingMaster, GuardingSlave, MasterGuardingEvent, SlaveGuardingEvent,
};
use canopen_codec::machine::Machine;
use canopen_codec::nmt::NmtState;
use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};
use core::time::Duration;
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    /// An arbitrary frame to the master or the slave.
    Frame { to_master: bool, near: bool, id: u16, remote: bool, data: [u8; 8], len: u8 },
    /// Time passes; `drop` loses what the two send to each other this step.
    Advance { micros: u32, drop: bool },
    MasterStart,
    MasterStop,
    MasterExpect(Option<u8>),
    SlaveReset,
    SlaveState(u8),
    SlaveLifeGuarding { guard_ms: u16, factor: u8 },
    SlaveHeartbeat(bool),
}

const NODE: u8 = 10;

fn check_timer(t: Option<Timestamp>, now: Timestamp, who: &str) {
    if let Some(t) = t {
        assert!(t > now, "{who} timer {t} not after now {now}");
    }
}

struct Run {
    master: GuardingMaster,
    slave: GuardingSlave,
    now: Timestamp,
    master_lost: bool,
    slave_lost: bool,
    heartbeat: bool,
    next_toggle: bool,
}

impl Run {
    fn check(&mut self) {
        check_timer(self.master.poll_timeout(), self.now, "master");
        check_timer(self.slave.poll_timeout(), self.now, "slave");
        while let Some(e) = self.master.poll_event() {
            match e {
                MasterGuardingEvent::Lost(_) => {
                    assert!(!self.master_lost, "lost twice");
                    self.master_lost = true;
                }
                MasterGuardingEvent::Restored { .. } => {
                    assert!(self.master_lost, "restored without lost");
                    self.master_lost = false;
                }
                _ => {}
            }
        }
        assert_eq!(self.master.is_lost(), self.master_lost);
        while let Some(e) = self.slave.poll_event() {
            match e {
                SlaveGuardingEvent::LifeGuardingLost => {
                    assert!(!self.slave_lost, "life guarding lost twice");
                    self.slave_lost = true;
                }
                SlaveGuardingEvent::LifeGuardingResumed => {
                    assert!(self.slave_lost, "resumed without lost");
                    self.slave_lost = false;
                }
                _ => {}
            }
        }
        assert_eq!(self.slave.is_master_lost(), self.slave_lost);
    }

    /// Drains both transmit queues, checks the frames and delivers them.
    fn exchange(&mut self, drop: bool) {
        let id = CanId::Standard(0x700 + u16::from(NODE));
        for _ in 0..4 {
            let from_master: Vec<CanFrame> = core::iter::from_fn(|| self.master.poll_transmit()).collect();
            let from_slave: Vec<CanFrame> = core::iter::from_fn(|| self.slave.poll_transmit()).collect();
            if from_master.is_empty() && from_slave.is_empty() {
                break;
            }
            for f in &from_master {
                assert!(f.is_remote() && f.id() == id, "master sent {f}");
                if !drop {
                    self.slave.handle_frame(self.now, f);
                    self.check();
                }
            }
            for f in &from_slave {
                self.check_reply(f);
                if !drop {
                    self.master.handle_frame(self.now, f);
                    self.check();
                }
            }
        }
    }

    fn check_reply(&mut self, f: &CanFrame) {
        assert!(!self.heartbeat, "a reply while the heartbeat runs");
        assert!(!f.is_remote() && f.id() == CanId::Standard(0x700 + u16::from(NODE)));
        let [b] = f.data() else { panic!("reply of {} bytes", f.data().len()) };
        assert_eq!(b & 0x80 != 0, self.next_toggle, "toggle did not alternate");
        self.next_toggle = !self.next_toggle;
    }
}

fuzz_target!(|ops: Vec<Op>| {
    let node = NodeId::new(NODE).unwrap();
    let mut run = Run {
        master: GuardingMaster::new(node, Duration::from_millis(100), 3),
        slave: GuardingSlave::new(node),
        now: Timestamp::from_millis(1),
        master_lost: false,
        slave_lost: false,
        heartbeat: false,
        next_toggle: false,
    };
    for op in ops.into_iter().take(512) {
        match op {
            Op::Frame { to_master, near, id, remote, data, len } => {
                let id = if near { 0x700 + u16::from(NODE) + (id % 3) - 1 } else { id & 0x7FF };
                let len = usize::from(len % 9);
                let frame = if remote {
                    CanFrame::remote(CanId::Standard(id), len as u8)
                } else {
                    CanFrame::standard(id, &data[..len])
                };
                let Ok(frame) = frame else { continue };
                if to_master {
                    run.master.handle_frame(run.now, &frame);
                } else {
                    run.slave.handle_frame(run.now, &frame);
                    // A request the slave answers is checked in exchange.
                }
                run.check();
            }
            Op::Advance { micros, drop } => {
                run.now = run.now.add_micros(u64::from(micros));
                // Both told the time before either is checked.
                run.master.handle_timeout(run.now);
                run.slave.handle_timeout(run.now);
                run.check();
                run.exchange(drop);
                continue;
            }
            Op::MasterStart => run.master.start(run.now),
            Op::MasterStop => run.master.stop(),
            Op::MasterExpect(s) => run.master.set_expected_state(s.map(NmtState::from_bits)),
            Op::SlaveReset => {
                run.exchange(true);
                run.slave.reset();
                run.slave_lost = false;
                run.next_toggle = false;
            }
            Op::SlaveState(s) => run.slave.set_state(NmtState::from_bits(s)),
            Op::SlaveLifeGuarding { guard_ms, factor } => {
                run.slave.set_life_guarding(run.now, Duration::from_millis(u64::from(guard_ms)), factor);
            }
            Op::SlaveHeartbeat(on) => {
                run.exchange(false);
                run.heartbeat = on;
                run.slave.set_heartbeat_active(run.now, on);
            }
        }
        run.check();
        run.exchange(false);
    }
});
