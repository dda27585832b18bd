//! The boot-up manager's "check and update software version" step (CiA
//! 302-2 "Network management", section 4.4; 1F81h bits 5 and 6) on the
//! simulated bus: the slave's 1F52h "verify application software" date and
//! time against 1F53h and 1F54h (matching, a date or a time that differs:
//! H, no 1F52h: G), after 1F56h against 1F55h; and the software update: the
//! manager downloads the program into a slave's 1F50h (CiA 302-3 program
//! download objects over a RAM store) and boots it again, or ends with I
//! (no program, a failed download, a check still differing after it).

use crate::common;

use std::sync::{Arc, Mutex};

use core::time::Duration;

use crate::common::ms;
use canopen_codec::device::program::{Crc32, FlashError, ProgramStore};
use canopen_codec::device::{Cia301Device, DeviceConfig, ProgramObjects};
use canopen_codec::manager::{
    BootError, BootEvent, BootManager, ManagerConfig, NodeConfig, SlaveAssignment, SoftwareCheck,
    UpdateFailure,
};
use canopen_codec::nmt::NmtState;
use canopen_codec::od::{Access, Address, ConciseDcf, ConciseEntry, MemoryDictionary};
use canopen_codec::sdo::ProgramDownloadError;
use canopen_codec::NodeId;
use common::sim::{Bus, Handle};

type Slave = Cia301Device<ProgramObjects<MemoryDictionary>>;
type Manager = BootManager<'static, 2>;

const NODE: u8 = 5;
const DEVICE_TYPE: u32 = 0x0001_0191;
/// The application object the configuration writes.
const SETTING: Address = Address::new(0x2000, 0);
/// 1F52h of the slave: the application software's date (days since 1984)
/// and time (ms after midnight).
const DATE: u32 = 15_340;
const TIME: u32 = 43_200_000;
/// 1F56h of the slave's program before an update.
const OLD_PROGRAM: u32 = 0x0BAD_F00D;

fn id() -> NodeId {
    NodeId::new(NODE).unwrap()
}

/// What the test sees of the slave's flash.
#[derive(Debug, Default)]
struct Flash {
    image: Vec<u8>,
    /// Stop commands received (one per download).
    stops: u32,
    /// A write fails (flash write error).
    broken: bool,
}

struct RamStore(Arc<Mutex<Flash>>);

impl ProgramStore for RamStore {
    fn capacity(&self) -> usize {
        4096
    }
    fn software_id(&self) -> Option<u32> {
        Some(OLD_PROGRAM)
    }
    fn clear(&mut self) -> Result<(), FlashError> {
        self.0.lock().unwrap().image.clear();
        Ok(())
    }
    fn write(&mut self, _offset: usize, bytes: &[u8]) -> Result<(), FlashError> {
        let mut f = self.0.lock().unwrap();
        if f.broken {
            return Err(FlashError::FlashWriteError);
        }
        f.image.extend_from_slice(bytes);
        Ok(())
    }
    fn finish(&mut self, _len: usize) -> Result<u32, FlashError> {
        Ok(Crc32::of(&self.0.lock().unwrap().image))
    }
    fn start(&mut self) -> Result<(), FlashError> {
        Ok(())
    }
    fn stop(&mut self) -> Result<(), FlashError> {
        self.0.lock().unwrap().stops += 1;
        Ok(())
    }
}

/// The program the manager holds for the slave.
const PROGRAM: &[u8] = b"the application software, version 2, for node 5 (41 bytes)";

/// A slave with `SETTING` = 0 (rw), its 1F52h when `stamp` is given, and
/// the program download objects over `flash` when given.
fn slave(stamp: Option<(u32, u32)>, flash: Option<&Arc<Mutex<Flash>>>) -> Slave {
    let config = DeviceConfig {
        device_type: DEVICE_TYPE,
        heartbeat: Duration::ZERO,
        ..DeviceConfig::new(id())
    };
    let mut app = MemoryDictionary::new();
    app.insert(SETTING.index, SETTING.sub, Access::ReadWrite, &[0; 4]);
    if let Some((date, time)) = stamp {
        app.insert(0x1F52, 1, Access::ReadOnly, &date.to_le_bytes());
        app.insert(0x1F52, 2, Access::ReadOnly, &time.to_le_bytes());
    }
    let mut objects = ProgramObjects::new(app);
    if let Some(flash) = flash {
        objects.attach(Box::leak(Box::new(RamStore(Arc::clone(flash)))));
    }
    Cia301Device::plain(config, objects)
}

/// Node 5 expected with its device type, configured (`SETTING`), with the
/// software check (1F81h bit 5) and `update` (bit 6).
fn node(update: bool) -> NodeConfig<'static> {
    let entries = [ConciseEntry::new(SETTING, &[0x78, 0x56, 0x34, 0x12])];
    let bytes = ConciseDcf::encode_vec(entries).unwrap().leak();
    let mut n = NodeConfig::new(id()).with_configuration(ConciseDcf::new_checked(bytes).unwrap());
    n.expected.device_type = DEVICE_TYPE;
    n.assignment = SlaveAssignment::BOOTED.verify_software();
    if update {
        n.assignment = n.assignment.allow_software_update();
    }
    n
}

/// The slave booted at 0 ms, the manager (SDO timeout 100 ms) started at
/// 1 ms, the bus run for 2 s.
fn run(slave: Slave, node: NodeConfig<'static>) -> (Bus, Handle<Slave>, Handle<Manager>) {
    let mut sim = common::sim::bus(200);
    let s = sim.add("Slave", slave);
    sim.with(s, |d, now| d.boot(now));
    let mut manager = Manager::new(ManagerConfig {
        sdo_timeout: Duration::from_millis(100),
        ..ManagerConfig::default()
    });
    manager.add_node(node).unwrap();
    let m = sim.add("Manager", manager);
    sim.run_until(ms(1)).unwrap();
    sim.with(m, |m, now| m.start(now));
    sim.run_until(ms(2000)).unwrap();
    (sim, s, m)
}

/// The boot's errors.
fn errors(sim: &Bus, m: Handle<Manager>) -> Vec<BootError> {
    sim.event_list(m)
        .into_iter()
        .filter_map(|e| match e {
            BootEvent::Error { error, .. } => Some(error),
            _ => None,
        })
        .collect()
}

/// Whether the manager read `index`:`sub` of the slave.
fn read(sim: &Bus, index: u16, sub: u8) -> bool {
    let [lo, hi] = index.to_le_bytes();
    sim.frames_on(0x600 + u16::from(NODE))
        .iter()
        .any(|(_, d)| d[..4] == [0x40, lo, hi, sub])
}

/// Whether the configuration reached the slave.
fn configured(sim: &Bus, s: Handle<Slave>) -> bool {
    let slave = sim.machine(s).unwrap();
    slave.objects().get(SETTING.index, SETTING.sub) == Some(&[0x78, 0x56, 0x34, 0x12][..])
}

#[test]
fn the_date_and_time_check_reads_1f52h_and_refuses_with_g_or_h() {
    struct Case {
        name: &'static str,
        /// 1F52h sub 1 and 2 of the slave (`None`: it has no 1F52h).
        serves: Option<(u32, u32)>,
        /// 1F53h and 1F54h for the slave.
        expects: (u32, u32),
        /// The error, or `None`: verified, configured and started.
        error: Option<BootError>,
        /// Whether the manager reads 1F52h sub 2 (the time).
        reads_time: bool,
    }
    let differs = |check, expected, read| {
        Some(BootError::SoftwareDiffers {
            check,
            expected,
            read,
        })
    };
    let cases = [
        Case {
            name: "the same date and time",
            serves: Some((DATE, TIME)),
            expects: (DATE, TIME),
            error: None,
            reads_time: true,
        },
        Case {
            name: "another date: the time is not read",
            serves: Some((DATE + 1, TIME)),
            expects: (DATE, TIME),
            error: differs(SoftwareCheck::Date, DATE, DATE + 1),
            reads_time: false,
        },
        Case {
            name: "another time",
            serves: Some((DATE, TIME - 1)),
            expects: (DATE, TIME),
            error: differs(SoftwareCheck::Time, TIME, TIME - 1),
            reads_time: true,
        },
        Case {
            name: "midnight is a time that is checked",
            serves: Some((DATE, TIME)),
            expects: (DATE, 0),
            error: differs(SoftwareCheck::Time, 0, TIME),
            reads_time: true,
        },
        Case {
            name: "no 1F52h on the slave",
            serves: None,
            expects: (DATE, TIME),
            error: Some(BootError::SoftwareUnreadable {
                check: SoftwareCheck::Date,
                code: canopen_codec::sdo::AbortCode::ObjectDoesNotExist,
            }),
            reads_time: false,
        },
        Case {
            name: "neither 1F53h nor 1F55h configured",
            serves: Some((DATE, TIME)),
            expects: (0, TIME),
            error: Some(BootError::SoftwareNotConfigured),
            reads_time: false,
        },
    ];
    for case in cases {
        let name = case.name;
        let mut n = node(false);
        (n.expected.software_date, n.expected.software_time) = case.expects;
        let (sim, s, m) = run(slave(case.serves, None), n);
        assert_eq!(
            read(&sim, 0x1F52, 2),
            case.reads_time,
            "{name}: read of 1F52h:02"
        );
        let state = sim.machine(s).unwrap().nmt_state();
        match case.error {
            None => {
                let events = sim.event_list(m);
                for (check, value) in [(SoftwareCheck::Date, DATE), (SoftwareCheck::Time, TIME)] {
                    let verified = BootEvent::SoftwareVerified {
                        node: id(),
                        check,
                        value,
                    };
                    assert!(events.contains(&verified), "{name}: {events:?}");
                }
                assert!(configured(&sim, s), "{name}: configured");
                assert_eq!(state, NmtState::Operational, "{name}");
            }
            Some(error) => {
                assert_eq!(errors(&sim, m), [error], "{name}");
                let letter = if error == BootError::SoftwareNotConfigured
                    || matches!(error, BootError::SoftwareUnreadable { .. })
                {
                    'G'
                } else {
                    'H'
                };
                assert_eq!(error.letter(), letter, "{name}");
                assert!(!configured(&sim, s), "{name}: not configured");
                assert_eq!(state, NmtState::PreOperational, "{name}");
            }
        }
    }
}

#[test]
fn the_identification_is_checked_before_the_date() {
    // 1F56h matches, 1F52h's date does not: H for the date, after both
    // reads, in that order.
    let flash = Arc::new(Mutex::new(Flash::default()));
    let mut n = node(false);
    n.expected.software = OLD_PROGRAM;
    (n.expected.software_date, n.expected.software_time) = (DATE + 7, TIME);
    let (sim, _, m) = run(slave(Some((DATE, TIME)), Some(&flash)), n);
    let requests = sim.frames_on(0x605);
    let at = |index: u16, sub| {
        let [lo, hi] = index.to_le_bytes();
        requests
            .iter()
            .position(|(_, d)| d[..4] == [0x40, lo, hi, sub])
    };
    let (id_read, date_read) = (at(0x1F56, 1), at(0x1F52, 1));
    assert!(id_read.is_some() && date_read.is_some() && id_read < date_read);
    let verified = BootEvent::SoftwareVerified {
        node: id(),
        check: SoftwareCheck::Identification,
        value: OLD_PROGRAM,
    };
    assert!(sim.event_list(m).contains(&verified));
    let want = BootError::SoftwareDiffers {
        check: SoftwareCheck::Date,
        expected: DATE + 7,
        read: DATE,
    };
    assert_eq!(errors(&sim, m), [want]);
}

#[test]
fn an_allowed_update_downloads_the_program_and_boots_the_slave_again() {
    let flash = Arc::new(Mutex::new(Flash::default()));
    let mut n = node(true);
    n.expected.software = Crc32::of(PROGRAM);
    n.program = Some(PROGRAM);
    let (sim, s, m) = run(slave(None, Some(&flash)), n);
    assert_eq!(flash.lock().unwrap().image, PROGRAM, "the image in flash");
    assert_eq!(flash.lock().unwrap().stops, 1, "one download");
    let events = sim.event_list(m);
    let updated = BootEvent::SoftwareUpdated {
        node: id(),
        len: PROGRAM.len(),
        identification: Crc32::of(PROGRAM),
    };
    let verified = BootEvent::SoftwareVerified {
        node: id(),
        check: SoftwareCheck::Identification,
        value: Crc32::of(PROGRAM),
    };
    let (u, v) = (
        events.iter().position(|e| *e == updated),
        events.iter().position(|e| *e == verified),
    );
    assert!(u.is_some() && u < v, "{events:?}");
    assert_eq!(errors(&sim, m), []);
    assert!(configured(&sim, s));
    assert_eq!(sim.machine(s).unwrap().nmt_state(), NmtState::Operational);
}

#[test]
fn a_required_update_that_cannot_be_done_is_i_and_without_bit_6_it_is_h() {
    // (name, bit 6, program, broken flash, 1F55h) -> the error.
    type Case = (&'static str, bool, Option<&'static [u8]>, bool, u32);
    let other = Crc32::of(PROGRAM) ^ 1;
    let cases: [Case; 4] = [
        ("no update allowed", false, Some(PROGRAM), false, other),
        ("no program", true, None, false, other),
        ("the flash fails", true, Some(PROGRAM), true, other),
        ("still another program", true, Some(PROGRAM), false, other),
    ];
    for (name, allowed, program, broken, expected) in cases {
        let flash = Arc::new(Mutex::new(Flash {
            broken,
            ..Flash::default()
        }));
        let mut n = node(allowed);
        n.expected.software = expected;
        n.program = program;
        let (sim, s, m) = run(slave(None, Some(&flash)), n);
        let errors = errors(&sim, m);
        let [error] = errors[..] else {
            panic!("{name}: {errors:?}")
        };
        let stops = flash.lock().unwrap().stops;
        match (allowed, program, broken) {
            (false, ..) => {
                assert_eq!(error.letter(), 'H', "{name}");
                assert_eq!(stops, 0, "{name}: no download");
            }
            (true, None, _) => {
                let failure = UpdateFailure::NoProgram;
                assert_eq!(error, BootError::SoftwareUpdate { failure }, "{name}");
                assert_eq!(stops, 0, "{name}: no download");
            }
            (true, Some(_), true) => {
                let BootError::SoftwareUpdate {
                    failure: UpdateFailure::Download(ProgramDownloadError::Flash { .. }),
                } = error
                else {
                    panic!("{name}: {error:?}")
                };
                assert_eq!(stops, 1, "{name}: one download");
            }
            (true, Some(_), false) => {
                let failure = UpdateFailure::StillDiffers {
                    check: SoftwareCheck::Identification,
                    expected,
                    read: Crc32::of(PROGRAM),
                };
                assert_eq!(error, BootError::SoftwareUpdate { failure }, "{name}");
                assert_eq!(stops, 1, "{name}: one download, not a second");
            }
        }
        if allowed {
            assert_eq!(error.letter(), 'I', "{name}");
        }
        assert!(!configured(&sim, s), "{name}: not configured");
    }
}
