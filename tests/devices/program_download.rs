//! Program download (CiA 302-3) on the simulated bus: the master's
//! `sdo::ProgramDownload` against the Delta-Q charger with an in-memory
//! `ProgramStore` (stop, clear, block or segmented download into 1F50h:01,
//! 1F57h, 1F56h, start), the failures a master must report, and the
//! recorded log `tests/data/program-download.log` (regenerated with
//! `REGENERATE_PROGRAM_DOWNLOAD=1` after a deliberate change).

use crate::common;

use std::sync::{Arc, Mutex};

use canopen_codec::deltaq::{Charger, ChargerConfig};
use canopen_codec::device::program::{Crc32, FlashError, FlashStatus, ProgramState, ProgramStore};
use canopen_codec::sdo::{
    AbortCode, AbortOrigin, Client, ClientConfig, ClientEvent, ProgramDownload,
    ProgramDownloadConfig, ProgramDownloadError, ProgramDownloadEvent, ProgramStep, TransferEnd,
};
use canopen_codec::trace::candump::LogLineDisplay;
use canopen_codec::{NodeId, Timestamp};
use common::sim::Bus;

const CHARGER: u8 = 10;
const EPOCH_US: u64 = 1_763_800_000_000_000;
const FILE: &str = "tests/data/program-download.log";

/// What the test sees of the store the charger writes into.
#[derive(Debug, Default)]
struct Flash {
    image: Vec<u8>,
    cleared: u32,
    started: bool,
    /// A write at or after this offset fails (flash write error).
    fail_at: Option<usize>,
}

/// The store the charger owns; the test keeps the other handle.
struct RamStore(Arc<Mutex<Flash>>);

impl ProgramStore for RamStore {
    fn capacity(&self) -> usize {
        64 * 1024
    }
    fn software_id(&self) -> Option<u32> {
        None
    }
    fn clear(&mut self) -> Result<(), FlashError> {
        let mut f = self.0.lock().unwrap();
        f.image.clear();
        f.cleared += 1;
        Ok(())
    }
    fn write(&mut self, offset: usize, bytes: &[u8]) -> Result<(), FlashError> {
        let mut f = self.0.lock().unwrap();
        if f.fail_at.is_some_and(|at| offset >= at) {
            return Err(FlashError::FlashWriteError);
        }
        if offset != f.image.len() {
            return Err(FlashError::GeneralAddressError);
        }
        f.image.extend_from_slice(bytes);
        Ok(())
    }
    fn finish(&mut self, len: usize) -> Result<u32, FlashError> {
        let f = self.0.lock().unwrap();
        if f.image.len() != len {
            return Err(FlashError::DataFormatError);
        }
        Ok(Crc32::of(&f.image))
    }
    fn start(&mut self) -> Result<(), FlashError> {
        self.0.lock().unwrap().started = true;
        Ok(())
    }
    fn stop(&mut self) -> Result<(), FlashError> {
        self.0.lock().unwrap().started = false;
        Ok(())
    }
}

/// A deterministic "random" image.
fn image(len: usize) -> Vec<u8> {
    let mut x = 0x1F50_u32;
    (0..len)
        .map(|_| {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (x >> 24) as u8
        })
        .collect()
}

fn node() -> NodeId {
    NodeId::new(CHARGER).unwrap()
}

type Master = common::sim::Handle<ProgramDownload<Vec<u8>>>;

/// The charger (with a store, or none) booted on a bus with the master.
fn bus(
    store: Option<Flash>,
    block: bool,
) -> (Bus, common::sim::Handle<Charger>, Master, Arc<Mutex<Flash>>) {
    let flash = Arc::new(Mutex::new(Flash::default()));
    let config = ChargerConfig::new(node(), NodeId::new(1).unwrap());
    let charger = match store {
        Some(f) => {
            *flash.lock().unwrap() = f;
            let store = Box::leak(Box::new(RamStore(Arc::clone(&flash))));
            Charger::with_program_store(config, store)
        }
        None => Charger::new(config),
    };
    let mut sim = common::sim::bus(500);
    let c = sim.add("Charger", charger);
    let config = ProgramDownloadConfig {
        block,
        ..ProgramDownloadConfig::for_server(node())
    };
    let m = sim.add("Master", ProgramDownload::new(config));
    sim.with(c, |c, now| c.boot(now));
    (sim, c, m, flash)
}

/// Starts the master with `image` and runs the bus for 5 s (more than the
/// 2 s SDO timeout).
fn run(sim: &mut Bus, m: Master, image: Vec<u8>) {
    let start = sim.now();
    sim.with(m, |m, now| m.start(now, image)).unwrap().unwrap();
    sim.run_until(Timestamp::from_millis(start.as_millis() + 5000))
        .unwrap();
}

fn steps_then(last: ProgramDownloadEvent, done: &[ProgramStep]) -> Vec<ProgramDownloadEvent> {
    let mut v: Vec<_> = done
        .iter()
        .map(|s| ProgramDownloadEvent::StepDone(*s))
        .collect();
    v.push(last);
    v
}

const ALL_STEPS: [ProgramStep; 6] = [
    ProgramStep::Stop,
    ProgramStep::Clear,
    ProgramStep::Download,
    ProgramStep::FlashStatus,
    ProgramStep::SoftwareId,
    ProgramStep::Start,
];

#[test]
fn the_image_arrives_byte_exact_by_block_and_segmented() {
    for block in [true, false] {
        let (mut sim, c, m, flash) = bus(Some(Flash::default()), block);
        let img = image(5000);
        run(&mut sim, m, img.clone());
        let finished = ProgramDownloadEvent::Finished {
            len: 5000,
            software_id: Crc32::of(&img),
        };
        assert_eq!(
            sim.event_list(m),
            steps_then(finished, &ALL_STEPS),
            "block {block}"
        );
        let f = flash.lock().unwrap();
        assert!(f.image == img, "block {block}: the image in the store");
        assert_eq!((f.cleared, f.started), (1, true));
        let program = sim.machine(c).unwrap().objects();
        assert_eq!(program.state(), ProgramState::Started);
        assert_eq!(program.software_id(), Some(Crc32::of(&img)));
        // The transfer went the way asked: the first request on 60Ah after
        // the clear is a block initiate (C6h: crc, size) or a segmented one
        // (21h: size indicated).
        let requests: Vec<u8> = sim.frames_on(0x60A).iter().map(|(_, d)| d[0]).collect();
        assert_eq!(
            requests[2],
            if block { 0xC6 } else { 0x21 },
            "block {block}"
        );
        assert!(!sim.machine(m).unwrap().is_busy());
    }
}

#[test]
fn a_store_that_fails_is_in_1f57h_and_the_master_reports_it() {
    let failing = Flash {
        fail_at: Some(2000),
        ..Flash::default()
    };
    let (mut sim, c, m, flash) = bus(Some(failing), true);
    run(&mut sim, m, image(5000));
    let failed = ProgramDownloadEvent::Failed(ProgramDownloadError::Flash {
        status: FlashStatus::new(false, Some(FlashError::FlashWriteError)),
        code: Some(AbortCode::DataCannotBeStored),
    });
    assert_eq!(
        sim.event_list(m),
        steps_then(failed, &[ProgramStep::Stop, ProgramStep::Clear])
    );
    let program = sim.machine(c).unwrap().objects();
    assert_eq!(
        (program.state(), program.software_id()),
        (ProgramState::NoProgram, None)
    );
    assert!(!flash.lock().unwrap().started);
    // The charger aborted the download with 08000020h on its SDO channel.
    let abort = [0x80, 0x50, 0x1F, 0x01, 0x20, 0x00, 0x00, 0x08];
    assert!(sim.frames_on(0x58A).iter().any(|(_, d)| d[..] == abort));
}

#[test]
fn a_download_while_started_is_refused_with_08000022h() {
    let (mut sim, c, m, _flash) = bus(Some(Flash::default()), true);
    run(&mut sim, m, image(300));
    assert_eq!(
        sim.machine(c).unwrap().objects().state(),
        ProgramState::Started
    );
    // Another master writes into 1F50h:01 without stopping the program.
    let other: Client<Vec<u8>> = Client::new(ClientConfig::for_server(node()));
    let o = sim.add("Other", other);
    sim.with(o, |o, now| {
        o.start_block_download(now, 0x1F50, 1, image(100))
    })
    .unwrap()
    .unwrap();
    let end = Timestamp::from_millis(sim.now().as_millis() + 500);
    sim.run_until(end).unwrap();
    assert_eq!(
        sim.event_list(o),
        [ClientEvent::Ended(TransferEnd::Aborted {
            index: 0x1F50,
            sub: 1,
            code: AbortCode::DataCannotBeStoredDeviceState,
            origin: AbortOrigin::Peer,
        })]
    );
    assert_eq!(
        sim.machine(c).unwrap().objects().state(),
        ProgramState::Started
    );
}

#[test]
fn without_a_store_there_are_no_program_objects() {
    let (mut sim, _c, m, _flash) = bus(None, true);
    run(&mut sim, m, image(10));
    assert_eq!(
        sim.event_list(m),
        [ProgramDownloadEvent::Failed(
            ProgramDownloadError::Aborted {
                step: ProgramStep::Stop,
                code: AbortCode::ObjectDoesNotExist,
                origin: AbortOrigin::Peer,
            }
        )]
    );
}

#[test]
fn a_device_that_does_not_answer_times_out_once() {
    let (mut sim, _c, m, _flash) = bus(Some(Flash::default()), true);
    // Every answer of the charger after the stop is lost.
    sim.drop_if(|s| s.from == "Charger" && s.frame.id().raw() == 0x58A && s.n > 2);
    run(&mut sim, m, image(50));
    let events = sim.event_list(m);
    assert_eq!(events.len(), 2, "{events:?}");
    assert!(matches!(
        events[1],
        ProgramDownloadEvent::Failed(ProgramDownloadError::Aborted {
            step: ProgramStep::Clear,
            code: AbortCode::SdoProtocolTimedOut,
            origin: AbortOrigin::Local,
        })
    ));
}

/// The sequence of a 64-byte image, as a candump log.
fn recorded() -> String {
    let (mut sim, _c, m, _flash) = bus(Some(Flash::default()), true);
    let boot = sim.log().len();
    run(&mut sim, m, image(64));
    let mut out = String::new();
    for s in &sim.log()[boot..] {
        if s.frame.id().raw() & 0x780 == 0x700 {
            continue; // the heartbeats
        }
        let line = LogLineDisplay {
            timestamp: Timestamp::from_micros(EPOCH_US + s.at.as_micros()),
            interface: "vcan0",
            frame: &s.frame,
        };
        out.push_str(&format!("{line}\n"));
    }
    out
}

#[test]
fn the_recorded_log_is_what_the_nodes_produce() {
    let fresh = recorded();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(FILE);
    if std::env::var_os("REGENERATE_PROGRAM_DOWNLOAD").is_some() {
        std::fs::write(&path, &fresh).unwrap();
    }
    let recorded = std::fs::read_to_string(&path).expect("tests/data/program-download.log");
    assert_eq!(
        recorded, fresh,
        "regenerate with REGENERATE_PROGRAM_DOWNLOAD=1 if the change is deliberate"
    );
    // Stop, clear, block initiate, start.
    for line in [
        "60A#2F511F0100000000",
        "60A#2F511F0103000000",
        "60A#C6501F0140000000",
        "60A#2F511F0101000000",
    ] {
        assert!(fresh.contains(line), "{line}");
    }
}
