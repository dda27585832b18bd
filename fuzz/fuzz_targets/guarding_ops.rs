//! Node guarding, master and slave, on the simulated bus
//! (`canopen_codec::sim::bus`) under an arbitrary sequence of frames put on
//! the bus, time steps and commands: every frame one sends reaches the
//! other unless the input drops it (a drop fault while the step asks for
//! it). Invariants, checked around every single delivery through the bus's
//! observer and after every command: no panic; the master's lost and
//! restored events alternate (lost first) and agree with `is_lost`; the
//! slave's life-guarding lost and resumed events alternate the same way;
//! no call arms a timer at or before `now`; the master sends only remote
//! frames on 700h + node; the slave sends only one-byte replies there,
//! never while the heartbeat is active, with a toggle that alternates from
//! 0 after every reset.
#![no_main]

use std::cell::Cell;
use std::rc::Rc;

use arbitrary::Arbitrary;
use canopen_codec::machine::Machine;
use canopen_codec::nmt::guarding::{
    GuardingMaster, GuardingSlave, MasterGuardingEvent, SlaveGuardingEvent,
};
use canopen_codec::nmt::NmtState;
use canopen_codec::sim::bus::{Bus, Delivery, Handle, OUTSIDE};
use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};
use core::time::Duration;
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    /// An arbitrary frame put on the bus (both machines hear it).
    Frame { near: bool, id: u16, remote: bool, data: [u8; 8], len: u8 },
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
const MASTER: &str = "Master";
const SLAVE: &str = "Slave";

fn check_timer(t: Option<Timestamp>, now: Timestamp, who: &str) {
    if let Some(t) = t {
        assert!(t > now, "{who} timer {t} not after now {now}");
    }
}

/// What the checks remember between two looks at the bus.
struct Checks {
    master: Handle<GuardingMaster>,
    slave: Handle<GuardingSlave>,
    master_lost: bool,
    slave_lost: bool,
    heartbeat: bool,
    next_toggle: bool,
    /// Log entries, master events and slave events already checked.
    frames: usize,
    master_events: usize,
    slave_events: usize,
    /// Whether the receiver's timer was after `now` before the delivery.
    timer_was_later: bool,
}

impl Checks {
    /// Checks what was sent and recorded since the last look.
    fn look(&mut self, bus: &Bus) {
        let id = CanId::Standard(0x700 + u16::from(NODE));
        for s in bus.log().get(self.frames..).unwrap_or_default() {
            match s.from {
                MASTER => assert!(s.frame.is_remote() && s.frame.id() == id, "master sent {}", s.frame),
                SLAVE => {
                    assert!(!self.heartbeat, "a reply while the heartbeat runs");
                    assert!(!s.frame.is_remote() && s.frame.id() == id);
                    let [b] = s.frame.data() else { panic!("reply of {} bytes", s.frame.data().len()) };
                    assert_eq!(b & 0x80 != 0, self.next_toggle, "toggle did not alternate");
                    self.next_toggle = !self.next_toggle;
                }
                _ => assert_eq!(s.from, OUTSIDE),
            }
        }
        self.frames = bus.log().len();
        let events = bus.events(self.master);
        for (_, e) in events.get(self.master_events..).unwrap_or_default() {
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
        self.master_events = events.len();
        let events = bus.events(self.slave);
        for (_, e) in events.get(self.slave_events..).unwrap_or_default() {
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
        self.slave_events = events.len();
        let (Some(master), Some(slave)) = (bus.machine(self.master), bus.machine(self.slave)) else {
            panic!("a machine unplugged");
        };
        assert_eq!(master.is_lost(), self.master_lost);
        assert_eq!(slave.is_master_lost(), self.slave_lost);
    }

    /// The receiver's timer around one delivery: handling a frame never
    /// arms a timer at or before `now` (one already due stays until the
    /// step's timeouts run).
    fn timer(&self, bus: &Bus, to: &str) -> Option<Timestamp> {
        match to {
            MASTER => bus.machine(self.master).and_then(Machine::poll_timeout),
            _ => bus.machine(self.slave).and_then(Machine::poll_timeout),
        }
    }

    fn delivery(&mut self, d: &Delivery, bus: &Bus) {
        let later = self.timer(bus, d.to).is_none_or(|t| t > d.at);
        if d.handled {
            if self.timer_was_later {
                check_timer(self.timer(bus, d.to), d.at, d.to);
            }
            self.look(bus);
        } else {
            self.timer_was_later = later;
        }
    }

    /// After a command or a settled step: both timers after `now`.
    fn settled(&mut self, bus: &Bus) {
        self.look(bus);
        check_timer(self.timer(bus, MASTER), bus.now(), MASTER);
        check_timer(self.timer(bus, SLAVE), bus.now(), SLAVE);
    }
}

/// Delivers everything due now, checking around every delivery.
fn settle(bus: &mut Bus, checks: &mut Checks) {
    let now = bus.now();
    let run = bus.run_until_observed(now, &mut |d, bus| checks.delivery(d, bus));
    assert!(run.is_ok(), "{run:?}");
    checks.settled(bus);
}

fuzz_target!(|ops: Vec<Op>| {
    let node = NodeId::new(NODE).unwrap();
    let mut bus = Bus::new(Duration::ZERO);
    let dropping = Rc::new(Cell::new(false));
    let flag = Rc::clone(&dropping);
    bus.drop_if(move |s| s.from != OUTSIDE && flag.get());
    let master = bus.add(MASTER, GuardingMaster::new(node, Duration::from_millis(100), 3));
    let slave = bus.add(SLAVE, GuardingSlave::new(node));
    bus.advance(Timestamp::from_millis(1));
    let mut checks = Checks {
        master,
        slave,
        master_lost: false,
        slave_lost: false,
        heartbeat: false,
        next_toggle: false,
        frames: 0,
        master_events: 0,
        slave_events: 0,
        timer_was_later: true,
    };
    for op in ops.into_iter().take(512) {
        match op {
            Op::Frame { near, id, remote, data, len } => {
                let id = if near { 0x700 + u16::from(NODE) + (id % 3) - 1 } else { id & 0x7FF };
                let len = usize::from(len % 9);
                let frame = if remote {
                    CanFrame::remote(CanId::Standard(id), len as u8)
                } else {
                    CanFrame::standard(id, &data[..len])
                };
                let Ok(frame) = frame else { continue };
                bus.inject(frame);
            }
            Op::Advance { micros, drop } => {
                // One step at the new time: both told the time, then what
                // they send delivered (or lost, while `drop`).
                dropping.set(drop);
                bus.advance(bus.now().add_micros(u64::from(micros)));
                settle(&mut bus, &mut checks);
                dropping.set(false);
                continue;
            }
            Op::MasterStart => {
                bus.with(master, |m, now| m.start(now));
            }
            Op::MasterStop => {
                bus.with(master, |m, _| m.stop());
            }
            Op::MasterExpect(s) => {
                bus.with(master, |m, _| m.set_expected_state(s.map(NmtState::from_bits)));
            }
            Op::SlaveReset => {
                bus.with(slave, |s, _| s.reset());
                checks.slave_lost = false;
                checks.next_toggle = false;
            }
            Op::SlaveState(s) => {
                bus.with(slave, |sl, _| sl.set_state(NmtState::from_bits(s)));
            }
            Op::SlaveLifeGuarding { guard_ms, factor } => {
                bus.with(slave, |s, now| {
                    s.set_life_guarding(now, Duration::from_millis(u64::from(guard_ms)), factor);
                });
            }
            Op::SlaveHeartbeat(on) => {
                checks.heartbeat = on;
                bus.with(slave, |s, now| s.set_heartbeat_active(now, on));
            }
        }
        checks.settled(&bus);
        settle(&mut bus, &mut checks);
    }
});
