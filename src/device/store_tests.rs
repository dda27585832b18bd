//! Store parameters (1010h) and restore default parameters (1011h), CiA
//! 301 sections 7.5.2.13 and 7.5.2.14, one test per rule; the record
//! format of the module docs.

use super::*;
use crate::clock::Timestamp;
use crate::cob_id::NodeId;
use crate::device::{Cia301Device, DeviceConfig, DeviceEvent, PowerOnValues, ProfiledDevice};
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::od::fixture::Word;
use crate::pdo::{PdoCobId, PdoCommParams, PdoConfig, PdoDirection, PdoMapping, PdoSlot};
use std::boxed::Box;
use std::string::{String, ToString};
use std::vec::Vec;

/// The application: 2000h, a U16 parameter, stored as its 2 bytes.
type App = Word<2>;

impl PowerOnValues for App {
    type Snapshot = [u8; 2];
    fn snapshot(&self) -> [u8; 2] {
        (self.0 as u16).to_le_bytes()
    }
    fn restore(&mut self, snapshot: &[u8; 2]) {
        self.0 = u32::from(u16::from_le_bytes(*snapshot));
    }
    fn parameter_bytes(snapshot: &[u8; 2]) -> Option<&[u8]> {
        Some(snapshot)
    }
    fn parameter_bytes_mut(snapshot: &mut [u8; 2]) -> Option<&mut [u8]> {
        Some(snapshot)
    }
    fn parameter_layout() -> u32 {
        0x2000_0002
    }
}

/// An application whose parameters cannot be stored (the default
/// methods): the device tests' one U8 object, 2000h.
use crate::device::tests::App as Unstorable;

type Dev = Cia301Device<App>;

const NODE: u8 = 4;
const T0: Timestamp = Timestamp::ZERO;
const SAVE: u32 = SAVE_SIGNATURE;
const LOAD: u32 = LOAD_SIGNATURE;

/// TPDO 1 on 184h mapping 2000h (16 bits), event timer 100 ms.
fn config() -> DeviceConfig {
    let mapping = PdoMapping::new(&[MappingEntry::new(0x2000, 0, 16)]).unwrap();
    let mut pdos = PdoConfig::new();
    let comm = PdoCommParams::event_driven(PdoCobId::standard(0x184), 100);
    pdos.insert(
        PdoDirection::Transmit,
        PdoNumber::P0,
        PdoSlot::new(comm, &mapping),
    );
    DeviceConfig {
        pdos,
        ..DeviceConfig::new(NodeId::new(NODE).unwrap())
    }
}

fn ram() -> &'static mut RamStorage {
    Box::leak(Box::new(RamStorage::new()))
}

/// A device on `storage` (if any), booted, its boot frames and events
/// drained.
fn device(storage: Option<&'static mut dyn ParameterStorage>) -> Dev {
    let mut d = Dev::plain(config(), Word(0x0102));
    if let Some(s) = storage {
        d.set_storage(s);
    }
    d.boot(T0);
    let _ = sent(&mut d);
    d
}

fn sent(d: &mut Dev) -> Vec<String> {
    core::iter::from_fn(|| d.poll_transmit())
        .map(|f| f.to_string())
        .collect()
}

fn events(d: &mut Dev) -> Vec<DeviceEvent> {
    core::iter::from_fn(|| d.poll_event()).collect()
}

fn storage_events(d: &mut Dev) -> Vec<StorageEvent> {
    events(d)
        .into_iter()
        .filter_map(|e| match e {
            DeviceEvent::Storage(s) => Some(s),
            _ => None,
        })
        .collect()
}

/// An expedited SDO download of the U32 `value`; the answer.
fn download(d: &mut Dev, index: u16, sub: u8, value: u32) -> String {
    download_sized(d, 0x23, index, sub, value)
}

/// 1017h, a U16.
fn heartbeat(d: &mut Dev, ms: u16) -> String {
    download_sized(d, 0x2B, 0x1017, 0, u32::from(ms))
}

fn download_sized(d: &mut Dev, command: u8, index: u16, sub: u8, value: u32) -> String {
    let [lo, hi] = index.to_le_bytes();
    let [a, b, c, e] = value.to_le_bytes();
    let request = [command, lo, hi, sub, a, b, c, e];
    d.handle_frame(T0, &CanFrame::standard(0x604, &request).unwrap());
    sent(d).join(" ")
}

/// An expedited SDO upload; the answer.
fn upload(d: &mut Dev, index: u16, sub: u8) -> String {
    let [lo, hi] = index.to_le_bytes();
    let request = [0x40, lo, hi, sub, 0, 0, 0, 0];
    d.handle_frame(T0, &CanFrame::standard(0x604, &request).unwrap());
    sent(d).join(" ")
}

fn ok(index: u16, sub: u8) -> String {
    let [lo, hi] = index.to_le_bytes();
    std::format!("584#60{lo:02X}{hi:02X}{sub:02X}00000000")
}

fn abort(index: u16, sub: u8, code: u32) -> String {
    let [lo, hi] = index.to_le_bytes();
    let [a, b, c, e] = code.to_le_bytes();
    std::format!("584#80{lo:02X}{hi:02X}{sub:02X}{a:02X}{b:02X}{c:02X}{e:02X}")
}

fn nmt(d: &mut Dev, command: u8) {
    d.handle_frame(T0, &CanFrame::standard(0, &[command, NODE]).unwrap());
    let _ = sent(d);
}

const RESET_NODE: u8 = 0x81;
const RESET_COMM: u8 = 0x82;

fn tpdo_cob(d: &Dev) -> u32 {
    let slot = d.pdo_config().get(PdoDirection::Transmit, PdoNumber::P0);
    slot.unwrap().comm.cob_id.to_u32()
}

/// The changes the tests store: 1017h 250 ms, TPDO 1 on 1F1h, 2000h 0BEEh.
fn change(d: &mut Dev) {
    assert_eq!(heartbeat(d, 250), ok(0x1017, 0));
    d.update_pdos(T0, |p| {
        let slot = p.get_mut(PdoDirection::Transmit, PdoNumber::P0).unwrap();
        slot.comm.cob_id = PdoCobId::standard(0x1F1);
    });
    d.update(T0, |a| a.0 = 0x0BEE);
    let _ = (sent(d), events(d));
}

/// A device on RAM storage with [`change`]'s changes stored by 1010h
/// sub 1 ("save all parameters").
fn changed_and_saved() -> Dev {
    let mut d = device(Some(ram()));
    change(&mut d);
    assert_eq!(download(&mut d, 0x1010, 1, SAVE), ok(0x1010, 1));
    d
}

fn changed(d: &Dev) -> (u16, u32, u32) {
    (d.comm().heartbeat_ms, tpdo_cob(d), d.objects().0)
}

const DEFAULTS: (u16, u32, u32) = (1000, 0x184, 0x0102);
const CHANGED: (u16, u32, u32) = (250, 0x1F1, 0x0BEE);

/// CiA 301 7.5.2.13: sub 0 is the highest sub-index (3); each sub reads
/// its capability: 1 (on command) with a storage.
#[test]
fn sub_0_and_the_capability_words() {
    let mut d = device(Some(ram()));
    for index in [0x1010u16, 0x1011] {
        let [lo, hi] = index.to_le_bytes();
        assert_eq!(
            upload(&mut d, index, 0),
            std::format!("584#4F{lo:02X}{hi:02X}0003000000")
        );
        for sub in 1..=3 {
            assert_eq!(
                upload(&mut d, index, sub),
                std::format!("584#43{lo:02X}{hi:02X}{sub:02X}01000000")
            );
        }
        // Sub 0 is const.
        assert_eq!(download(&mut d, index, 0, 3), abort(index, 0, 0x0601_0002));
    }
}

/// Without a storage (the default) every capability is 0 and a "save" or
/// "load" is refused with 08000020h.
#[test]
fn no_storage_reads_0_and_refuses() {
    let mut d = device(None);
    assert!(!d.has_storage());
    assert_eq!(upload(&mut d, 0x1010, 1), "584#4310100100000000");
    assert_eq!(upload(&mut d, 0x1011, 3), "584#4311100300000000");
    assert_eq!(
        download(&mut d, 0x1010, 1, SAVE),
        abort(0x1010, 1, 0x0800_0020)
    );
    assert_eq!(
        download(&mut d, 0x1011, 2, LOAD),
        abort(0x1011, 2, 0x0800_0020)
    );
}

/// CiA 301 7.5.2.13/7.5.2.14: only the signature is accepted ("save" to
/// 1010h, "load" to 1011h); another value is 08000020h and stores nothing.
#[test]
fn wrong_signature_is_refused() {
    let storage = ram();
    let mut d = device(Some(storage));
    for (index, value) in [(0x1010, LOAD), (0x1010, 0), (0x1011, SAVE), (0x1011, 1)] {
        assert_eq!(
            download(&mut d, index, 1, value),
            abort(index, 1, 0x0800_0020)
        );
    }
    assert_eq!(storage_events(&mut d), []);
    let storage = d.take_storage().unwrap();
    let mut buf = [0u8; RECORD_CAPACITY];
    assert_eq!(storage.load(ParameterGroup::Communication, &mut buf), Ok(0));
}

/// A sub above sub 0 does not exist (06090011h); a sub whose group cannot
/// be stored (an application without storable parameters) reads 0 and
/// refuses with 08000020h, while sub 1 stores what can be.
#[test]
fn subs_the_device_does_not_support() {
    let mut d = device(Some(ram()));
    assert_eq!(
        download(&mut d, 0x1010, 4, SAVE),
        abort(0x1010, 4, 0x0609_0011)
    );
    assert_eq!(upload(&mut d, 0x1011, 4), abort(0x1011, 4, 0x0609_0011));
    let mut u: Cia301Device<Unstorable> = ProfiledDevice::plain(config(), Word(1));
    u.set_storage(ram());
    u.boot(T0);
    let answers = |u: &mut Cia301Device<Unstorable>, data: [u8; 8]| {
        u.handle_frame(T0, &CanFrame::standard(0x604, &data).unwrap());
        core::iter::from_fn(|| u.poll_transmit())
            .map(|f| f.to_string())
            .last()
    };
    assert_eq!(
        answers(&mut u, [0x40, 0x10, 0x10, 3, 0, 0, 0, 0]).unwrap(),
        "584#4310100300000000"
    );
    assert_eq!(
        answers(&mut u, [0x23, 0x10, 0x10, 3, 0x73, 0x61, 0x76, 0x65]).unwrap(),
        abort(0x1010, 3, 0x0800_0020)
    );
    assert_eq!(
        answers(&mut u, [0x23, 0x10, 0x10, 1, 0x73, 0x61, 0x76, 0x65]).unwrap(),
        ok(0x1010, 1)
    );
    let stored: Vec<_> = core::iter::from_fn(|| u.poll_event())
        .filter_map(|e| match e {
            DeviceEvent::Storage(s) => Some(s),
            _ => None,
        })
        .collect();
    assert_eq!(
        stored,
        [StorageEvent::Stored(ParameterGroup::Communication)]
    );
}

/// 1010h sub 1 stores both groups: they survive reset node and come back
/// in a new device on the same storage (power cycle).
#[test]
fn save_all_survives_reset_node_and_power_cycle() {
    let mut d = changed_and_saved();
    assert_eq!(
        storage_events(&mut d),
        [
            StorageEvent::Stored(ParameterGroup::Communication),
            StorageEvent::Stored(ParameterGroup::Application)
        ]
    );
    nmt(&mut d, RESET_NODE);
    assert_eq!(changed(&d), CHANGED);
    assert_eq!(
        storage_events(&mut d),
        [
            StorageEvent::Loaded(ParameterGroup::Communication),
            StorageEvent::Loaded(ParameterGroup::Application)
        ]
    );
    let mut again = device(d.take_storage());
    assert_eq!(changed(&again), CHANGED);
    // The loaded heartbeat period is the one in effect.
    again.handle_timeout(Timestamp::from_millis(250));
    assert_eq!(sent(&mut again), ["704#7F"]);
}

/// Sub 2 stores the communication group only, sub 3 the application
/// group only.
#[test]
fn each_group_alone() {
    let storage = ram();
    let mut d = device(Some(storage));
    change(&mut d);
    assert_eq!(download(&mut d, 0x1010, 2, SAVE), ok(0x1010, 2));
    nmt(&mut d, RESET_NODE);
    assert_eq!(changed(&d), (250, 0x1F1, 0x0102));
    change(&mut d);
    let mut d = device(d.take_storage());
    assert_eq!(download(&mut d, 0x1011, 2, LOAD), ok(0x1011, 2));
    change(&mut d);
    assert_eq!(download(&mut d, 0x1010, 3, SAVE), ok(0x1010, 3));
    let d = device(d.take_storage());
    assert_eq!(changed(&d), (1000, 0x184, 0x0BEE));
}

/// CiA 301 7.5.2.14: "load" takes effect at the next reset: reset
/// communication brings the communication defaults back and keeps the
/// application objects, reset node brings both back.
#[test]
fn restore_then_reset_communication_or_node() {
    let mut d = changed_and_saved();
    assert_eq!(download(&mut d, 0x1011, 1, LOAD), ok(0x1011, 1));
    assert_eq!(
        storage_events(&mut d),
        [
            StorageEvent::Stored(ParameterGroup::Communication),
            StorageEvent::Stored(ParameterGroup::Application),
            StorageEvent::Erased(ParameterGroup::Communication),
            StorageEvent::Erased(ParameterGroup::Application)
        ]
    );
    // Not before the reset.
    assert_eq!(changed(&d), CHANGED);
    nmt(&mut d, RESET_COMM);
    assert_eq!(changed(&d), (1000, 0x184, 0x0BEE));
    nmt(&mut d, RESET_NODE);
    assert_eq!(changed(&d), DEFAULTS);
    assert_eq!(storage_events(&mut d), []);
}

/// Reset communication loads the stored communication group, not the
/// application group.
#[test]
fn reset_communication_loads_the_communication_group_only() {
    let mut d = changed_and_saved();
    d.update(T0, |a| a.0 = 0x0777);
    assert_eq!(heartbeat(&mut d, 500), ok(0x1017, 0));
    let _ = events(&mut d);
    nmt(&mut d, RESET_COMM);
    assert_eq!(changed(&d), (250, 0x1F1, 0x0777));
    assert_eq!(
        storage_events(&mut d),
        [StorageEvent::Loaded(ParameterGroup::Communication)]
    );
}

/// A corrupt record (a flipped bit) or a truncated one is ignored with an
/// event at boot and at every reset; the defaults stay.
#[test]
fn corrupt_records_are_ignored() {
    let mut d = changed_and_saved();
    let storage = d.take_storage().unwrap();
    let mut corrupt = RamStorage::<RECORD_CAPACITY>::new();
    let mut buf = [0u8; RECORD_CAPACITY];
    let n = storage
        .load(ParameterGroup::Communication, &mut buf)
        .unwrap();
    corrupt
        .save(ParameterGroup::Communication, &buf[..n])
        .unwrap();
    corrupt.record_mut(ParameterGroup::Communication)[11] ^= 0x01;
    let n = storage.load(ParameterGroup::Application, &mut buf).unwrap();
    corrupt
        .save(ParameterGroup::Application, &buf[..n - 1])
        .unwrap();
    let ignored = [
        StorageEvent::Ignored {
            group: ParameterGroup::Communication,
            error: RecordError::Checksum,
        },
        StorageEvent::Ignored {
            group: ParameterGroup::Application,
            error: RecordError::Truncated { need: 14, got: 13 },
        },
    ];
    let mut d = Dev::plain(config(), Word(0x0102));
    d.set_storage(Box::leak(Box::new(corrupt)));
    d.boot(T0);
    assert_eq!(storage_events(&mut d), ignored);
    assert_eq!(changed(&d), DEFAULTS);
    nmt(&mut d, RESET_NODE);
    assert_eq!(storage_events(&mut d), ignored);
    assert_eq!(changed(&d), DEFAULTS);
}

/// The communication objects and PDOs of [`config`] as they are at boot,
/// and their communication record (in a buffer, its length).
fn default_comm_record() -> (
    crate::device::CommObjects,
    PdoConfig,
    [u8; RECORD_CAPACITY],
    usize,
) {
    let mut buf = [0u8; RECORD_CAPACITY];
    let comm = crate::device::CommObjects::new(NodeId::new(NODE).unwrap());
    let pdos = config().pdos;
    let n = encode_comm(&mut buf, &comm, &pdos).unwrap();
    (comm, pdos, buf, n)
}

/// The record's header: magic, format, group and layout are checked; a
/// record of another PDO count (another device) is foreign.
#[test]
fn record_header_checks() {
    let (comm, pdos, buf, n) = default_comm_record();
    assert_eq!(n, 12 + 39 + 8 * 44);
    let record = &buf[..n];
    let (mut c, mut p) = (comm.clone(), pdos);
    assert_eq!(apply_comm(record, &mut c, &mut p), Ok(()));
    assert_eq!((c.clone(), p), (comm.clone(), pdos));
    let mut small = PdoConfig::<3, 3>::empty();
    assert_eq!(
        apply_comm(record, &mut c, &mut small),
        Err(RecordError::Layout {
            expected: 0x0303,
            found: 0x0404
        })
    );
    assert_eq!(
        decode_record(record, ParameterGroup::Application, 0x0404),
        Err(RecordError::Group(1))
    );
    let mut other = buf;
    other[0] = b'X';
    assert_eq!(
        apply_comm(&other[..n], &mut c, &mut p),
        Err(RecordError::Magic)
    );
    other = buf;
    other[2] = 2;
    assert_eq!(
        apply_comm(&other[..n], &mut c, &mut p),
        Err(RecordError::Format(2))
    );
    for cut in 0..n {
        assert!(apply_comm(&buf[..cut], &mut c, &mut p).is_err(), "{cut}");
    }
    assert_eq!((c, p), (comm, pdos), "a refused record changes nothing");
}

/// A record whose CRC is right but whose values the objects cannot hold
/// (a reserved transmission type) is refused whole.
#[test]
fn record_with_an_invalid_value_is_refused_whole() {
    let (comm, _, mut buf, n) = default_comm_record();
    // RPDO 1's transmission type: header, 39 bytes, present, COB-ID.
    buf[10 + 39 + 5] = 245;
    let crc = crate::sdo::crc16(&buf[..n - 2]);
    buf[n - 2..n].copy_from_slice(&crc.to_le_bytes());
    let mut c = comm.clone();
    c.heartbeat_ms = 77;
    let mut p = PdoConfig::new();
    assert_eq!(
        apply_comm(&buf[..n], &mut c, &mut p),
        Err(RecordError::Value)
    );
    assert_eq!((c.heartbeat_ms, p), (77, PdoConfig::new()));
}

/// A storage that fails: the SDO answer is 06060000h (CiA 301 7.5.2.13),
/// reported as Failed and SdoAborted.
#[test]
fn a_failing_storage_aborts_with_06060000h() {
    struct Broken;
    impl ParameterStorage for Broken {
        fn save(&mut self, _: ParameterGroup, _: &[u8]) -> Result<(), StorageError> {
            Err(StorageError::Medium)
        }
        fn load(&mut self, _: ParameterGroup, _: &mut [u8]) -> Result<usize, StorageError> {
            Err(StorageError::Medium)
        }
        fn erase(&mut self, _: ParameterGroup) -> Result<(), StorageError> {
            Err(StorageError::Medium)
        }
    }
    let mut d = Dev::plain(config(), Word(0x0102));
    d.set_storage(Box::leak(Box::new(Broken)));
    d.boot(T0);
    let _ = sent(&mut d);
    let failed = StorageEvent::Failed {
        group: ParameterGroup::Communication,
        error: StorageError::Medium,
    };
    assert_eq!(
        storage_events(&mut d),
        [
            failed,
            StorageEvent::Failed {
                group: ParameterGroup::Application,
                error: StorageError::Medium,
            }
        ]
    );
    for index in [0x1010, 0x1011] {
        let value = if index == 0x1010 { SAVE } else { LOAD };
        assert_eq!(
            download(&mut d, index, 2, value),
            abort(index, 2, 0x0606_0000)
        );
        let code = crate::abort::AbortCode::HardwareError;
        assert_eq!(
            events(&mut d),
            [
                DeviceEvent::Storage(failed),
                DeviceEvent::SdoAborted {
                    index,
                    sub: 2,
                    code,
                    origin: crate::sdo::AbortOrigin::Local
                }
            ]
        );
    }
}

/// CiA 305 store configuration goes through the same storage: the pending
/// node-ID is stored, answered with success, and a new device whose LSS
/// slave has no node-ID boots up under the stored one.
#[cfg(feature = "lss")]
#[test]
fn lss_store_configuration_uses_the_storage() {
    use crate::lss::{LssAddress, LssSlave, LssSlaveConfig};
    let unconfigured = || LssSlave::new(LssSlaveConfig::new(LssAddress::default(), None));
    let lss_frame = |data: [u8; 2]| {
        let mut bytes = [0u8; 8];
        bytes[..2].copy_from_slice(&data);
        CanFrame::standard(0x7E5, &bytes).unwrap()
    };
    let mut d = Dev::plain_with_lss(config(), Word(0x0102), unconfigured());
    d.set_storage(ram());
    d.boot(T0);
    for data in [[0x04, 1], [0x11, 9], [0x17, 0]] {
        d.handle_frame(T0, &lss_frame(data));
    }
    assert_eq!(
        sent(&mut d),
        ["7E4#1100000000000000", "7E4#1700000000000000"]
    );
    assert!(storage_events(&mut d).contains(&StorageEvent::Stored(ParameterGroup::Lss)));
    let storage = d.take_storage().unwrap();
    let mut again = Dev::plain_with_lss(config(), Word(0x0102), unconfigured());
    again.set_storage(storage);
    again.boot(T0);
    assert_eq!(sent(&mut again), ["709#00"]);
    assert_eq!(again.node(), NodeId::new(9).unwrap());
    // Without a storage the request is the application's: no answer.
    let mut plain = Dev::plain_with_lss(config(), Word(0x0102), unconfigured());
    plain.boot(T0);
    for data in [[0x04, 1], [0x11, 9], [0x17, 0]] {
        plain.handle_frame(T0, &lss_frame(data));
    }
    assert_eq!(sent(&mut plain), ["7E4#1100000000000000"]);
}
