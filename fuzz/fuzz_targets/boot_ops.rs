//! The CiA 302-2 boot-up manager (`canopen_codec::manager::BootManager`)
//! with three slaves (a mandatory keep-alive one with heartbeat, a software
//! check and a configuration, a guarded one whose software date and time
//! are checked and updated by a program download when they differ, an
//! optional one checked only)
//! under an arbitrary sequence of frames (the slaves' SDO answers, heartbeats, boot-ups and anything
//! else), time steps and start commands. Invariants after every call: no
//! panic; no frame dropped for a caller that drains after every call; the
//! manager sends only NMT commands (000h, two bytes, to all or to one of
//! its slaves), SDO requests on 600h + a slave, and guarding requests
//! (remote, 700h + the guarded slave); every due timer runs and leaves the
//! next one after `now`; a slave is reported operational only after it was
//! reported booted in its current boot process; a node that is not a slave
//! is only ever reported with letter A.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::machine::Machine;
use canopen_codec::manager::{
    BootEvent, BootManager, ManagerConfig, NmtStartup, NodeConfig, SlaveAssignment,
};
use canopen_codec::od::ConciseDcf;
use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};
use core::time::Duration;
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    /// A frame from one of the slaves (`kind` picks SDO answer, heartbeat
    /// or another identifier) or from anywhere.
    Frame { slave: u8, kind: u8, id: u16, data: [u8; 8], len: u8 },
    /// Time passes.
    Advance { millis: u16 },
    /// The manager starts (again).
    Start,
    /// The application starts one slave (1F80h bit 3).
    StartNode { slave: u8 },
    /// The application starts the network.
    StartNetwork,
}

/// 1017h = 50 ms, 2000h:01 = 0x11223344.
const CONFIGURATION: [u8; 24] = [
    2, 0, 0, 0, 0x17, 0x10, 0, 2, 0, 0, 0, 50, 0, 0x00, 0x20, 1, 4, 0, 0, 0, 0x44, 0x33, 0x22,
    0x11,
];
const SLAVES: [u8; 3] = [5, 6, 7];
/// The program the manager downloads into node 6 when its software differs
/// (segmented: 10 bytes).
const PROGRAM: [u8; 10] = *b"program v2";

fn manager(start_all: bool) -> BootManager<'static, 4> {
    let startup = if start_all {
        NmtStartup::MASTER | NmtStartup::START_ALL | NmtStartup::STOP_ALL
    } else {
        NmtStartup::MASTER
    };
    let mut m = BootManager::new(ManagerConfig {
        startup,
        sdo_timeout: Duration::from_millis(30),
        retries: 1,
        boot_up_wait: Duration::from_millis(40),
        heartbeat_margin: Duration::from_millis(5),
        boot_time: Duration::from_millis(300),
        retry_interval: Duration::from_millis(70),
    });
    let dcf = ConciseDcf::new_checked(&CONFIGURATION).expect("a valid concise DCF");
    let mut first = NodeConfig::new(NodeId::new(5).unwrap()).with_configuration(dcf);
    first.assignment = SlaveAssignment::BOOTED
        .mandatory()
        .keep_alive()
        .verify_software();
    first.expected.device_type = 0x191;
    first.expected.software = 0x5150;
    first.expected.vendor_id = 0x2A;
    let mut guarded = NodeConfig::new(NodeId::new(6).unwrap());
    guarded.assignment = SlaveAssignment::BOOTED
        .verify_software()
        .allow_software_update()
        .with_guarding(Duration::from_millis(20), 2);
    guarded.expected.serial = 9;
    guarded.expected.software_date = 15_340;
    guarded.expected.software_time = 43_200_000;
    guarded.program = Some(&PROGRAM);
    let mut plain = NodeConfig::new(NodeId::new(7).unwrap());
    plain.assignment = SlaveAssignment::from_raw(1);
    for n in [first, guarded, plain] {
        m.add_node(n).expect("room for three");
    }
    m
}

struct Checks {
    /// Per slave: reported booted in its current boot process.
    booted: [bool; 3],
}

impl Checks {
    fn drain(&mut self, m: &mut BootManager<'static, 4>) {
        while let Some(f) = m.poll_transmit() {
            let CanId::Standard(id) = f.id() else { panic!("extended frame {f}") };
            match id {
                0x000 => {
                    let [_, target] = f.data() else { panic!("NMT of {} bytes", f.data().len()) };
                    assert!(*target == 0 || SLAVES.contains(target), "NMT to {target}");
                }
                0x605..=0x607 => assert_eq!(f.data().len(), 8, "{f}"),
                0x706 => assert!(f.is_remote(), "{f}"),
                _ => panic!("the manager sent {f}"),
            }
        }
        assert_eq!(m.frames_dropped(), 0);
        while let Some(e) = m.poll_event() {
            let slot = |node: NodeId| SLAVES.iter().position(|n| *n == node.raw());
            match e {
                BootEvent::Booted { node } => self.booted[slot(node).expect("a slave")] = true,
                BootEvent::BootUp { node } => self.booted[slot(node).expect("a slave")] = false,
                BootEvent::Operational { node } => {
                    assert!(self.booted[slot(node).expect("a slave")], "{node} started unbooted");
                }
                BootEvent::Error { node, error } => match slot(node) {
                    Some(i) => self.booted[i] = false,
                    None => assert_eq!(error.letter(), 'A'),
                },
                _ => {}
            }
        }
    }
}

fuzz_target!(|input: (bool, Vec<Op>)| {
    let (start_all, ops) = input;
    let mut m = manager(start_all);
    let mut checks = Checks { booted: [false; 3] };
    let mut now = Timestamp::ZERO;
    m.start(now);
    checks.drain(&mut m);
    for op in ops.into_iter().take(512) {
        match op {
            Op::Frame { slave, kind, id, data, len } => {
                let node = u16::from(SLAVES[usize::from(slave) % 3]);
                let id = match kind % 4 {
                    0 => 0x580 + node,
                    1 => 0x700 + node,
                    2 => 0x700 + (id & 0x7F),
                    _ => id & 0x7FF,
                };
                let len = usize::from(len % 9);
                let frame = CanFrame::standard(id, &data[..len]).expect("a standard frame");
                m.handle_frame(now, &frame);
            }
            Op::Advance { millis } => {
                now = now.add_millis(u64::from(millis));
                // Many deadlines may fall in one long step (a 20 ms guard
                // time over a minute); what must not happen is a deadline
                // that handling leaves where it was.
                let mut last = None;
                let mut same = 0;
                while let Some(due) = m.poll_timeout().filter(|t| *t <= now) {
                    if last == Some(due) {
                        same += 1;
                        assert!(same < 64, "timer at {due} runs again and again");
                    } else {
                        last = Some(due);
                        same = 0;
                    }
                    m.handle_timeout(due);
                    checks.drain(&mut m);
                }
                if let Some(next) = m.poll_timeout() {
                    assert!(next > now, "timer {next} not after now {now}");
                }
            }
            Op::Start => {
                checks.booted = [false; 3];
                m.start(now);
            }
            Op::StartNode { slave } => {
                let node = NodeId::new(SLAVES[usize::from(slave) % 3]).unwrap();
                // Refused unless booted: the checks catch a start otherwise.
                let _ = m.start_node(now, node);
            }
            Op::StartNetwork => m.start_network(now),
        }
        checks.drain(&mut m);
    }
});
