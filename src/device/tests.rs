use super::*;
#[cfg(feature = "heartbeat-consumer")]
use crate::cob_id::test_node as n;
use crate::cob_id::PdoNumber;
use crate::machine::Machine;
#[cfg(feature = "heartbeat-consumer")]
use crate::nmt::heartbeat::{ConsumerEntry, HeartbeatEvent};
use crate::od::fixture::Word;
use crate::pdo::{MappingEntry, PdoCobId, PdoCommParams, PdoMapping, PdoSlot};
use crate::pdo::{PdoDirection, RpdoError};
#[cfg(feature = "heartbeat-consumer")]
use core::time::Duration;
use std::string::{String, ToString};
use std::vec::Vec;

/// The application: one mappable, writable U8 object, 2000h:00.
pub(super) type App = Word<1>;

/// Its one object is a parameter: a full copy.
impl PowerOnValues for App {
    type Snapshot = u32;
    fn snapshot(&self) -> u32 {
        self.0
    }
    fn restore(&mut self, snapshot: &u32) {
        self.0 = *snapshot;
    }
}

type Dev = Cia301Device<App>;

fn node() -> NodeId {
    NodeId::new(4).unwrap()
}

fn ms(n: u64) -> Timestamp {
    Timestamp::from_millis(n)
}

use crate::frame::standard_frame as frame;

/// TPDO 0 on 184h and RPDO 0 on 204h, both mapping 2000h (8 bits); node 1
/// watched for 1000 ms (1016h, feature `heartbeat-consumer`).
fn config() -> DeviceConfig {
    let mapping = PdoMapping::new(&[MappingEntry::new(0x2000, 0, 8)]).unwrap();
    let mut pdos = PdoConfig::new();
    pdos.insert(
        PdoDirection::Transmit,
        PdoNumber::P0,
        PdoSlot::new(
            PdoCommParams::event_driven(PdoCobId::standard(0x184), 100),
            &mapping,
        ),
    );
    pdos.insert(
        PdoDirection::Receive,
        PdoNumber::P0,
        PdoSlot::new(
            PdoCommParams::event_driven(PdoCobId::standard(0x204), 0),
            &mapping,
        ),
    );
    let config = DeviceConfig {
        device_type: 0x1234,
        device_name: "dev",
        pdos,
        ..DeviceConfig::new(node())
    };
    #[cfg(feature = "heartbeat-consumer")]
    let config = config.with_consumers(&[ConsumerEntry::new(
        NodeId::new(1).unwrap(),
        Duration::from_millis(1000),
    )]);
    config
}

fn booted() -> Dev {
    let mut d = Dev::plain(config(), Word(7));
    d.boot(ms(0));
    d
}

/// A consumer entry for `node` with a 1 s heartbeat time.
#[cfg(feature = "heartbeat-consumer")]
fn entry(node: u8) -> ConsumerEntry {
    ConsumerEntry::new(n(node), Duration::from_millis(1000))
}

/// A booted device whose 1016h watches nodes 1 and 2 (1 s each).
#[cfg(feature = "heartbeat-consumer")]
fn watching_nodes_1_and_2() -> Dev {
    let mut d = Dev::plain(config().with_consumers(&[entry(1), entry(2)]), Word(7));
    d.boot(ms(0));
    d
}

/// A booted device that has raised `errors` (an EMCY each, default
/// fields), with everything it sent drained.
fn with_errors(errors: &[ErrorRegister]) -> Dev {
    let mut d = booted();
    for &bits in errors {
        d.raise_error(bits, Emergency::default());
    }
    let _ = sent(&mut d);
    d
}

fn sent(d: &mut impl Machine) -> Vec<String> {
    core::iter::from_fn(|| d.poll_transmit())
        .map(|f| f.to_string())
        .collect()
}

fn events(d: &mut Dev) -> Vec<DeviceEvent> {
    core::iter::from_fn(|| d.poll_event()).collect()
}

fn sdo_write_u8(d: &mut Dev, now: Timestamp, index: u16, value: u8) {
    let [lo, hi] = index.to_le_bytes();
    sdo_request(d, now, [0x2F, lo, hi, 0, value, 0, 0, 0]);
}

/// The SDO client's request `data` to this node (604h).
fn sdo_request(d: &mut impl Machine, now: Timestamp, data: [u8; 8]) {
    d.handle_frame(now, &frame(0x604, &data));
}

#[test]
fn nothing_before_boot_then_boot_up_and_pre_operational() {
    let mut d = Dev::plain(config(), Word(7));
    d.handle_frame(ms(0), &frame(0x000, &[0x01, 0x04]));
    d.handle_timeout(ms(5000));
    assert_eq!((sent(&mut d), d.poll_timeout()), (Vec::new(), None));
    d.boot(ms(0));
    assert_eq!(sent(&mut d), ["704#00"]);
    assert_eq!(d.nmt_state(), NmtState::PreOperational);
    assert_eq!(
        events(&mut d),
        [DeviceEvent::NmtStateChanged {
            from: NmtState::BootUp,
            to: NmtState::PreOperational
        }]
    );
    assert_eq!(d.poll_timeout(), Some(ms(1000)));
}

#[test]
fn reset_node_restores_every_object_reset_communication_only_the_communication_objects() {
    for (cs, restored) in [(0x81u8, true), (0x82, false)] {
        let mut d = booted();
        d.update(ms(1), |a| a.0 = 99);
        sdo_write_u8(&mut d, ms(2), 0x2000, 42);
        assert_eq!(d.objects().0, 42);
        d.update_comm(ms(3), |c| c.heartbeat_ms = 250);
        d.raise_error(ErrorRegister::CURRENT, Emergency::default());
        let _ = (sent(&mut d), events(&mut d));
        d.handle_frame(ms(10), &frame(0x000, &[cs, 0]));
        assert_eq!(d.objects().0, if restored { 7 } else { 42 }, "{cs:02X}h");
        assert_eq!(d.comm().heartbeat_ms, 1000, "{cs:02X}h restores 1017h");
        assert!(d.error_register().is_empty() && d.comm().errors().is_empty());
        assert_eq!(sent(&mut d), ["704#00"], "boot-up again");
        assert_eq!(
            events(&mut d),
            [DeviceEvent::Reset { node: restored }],
            "already pre-operational: no state change"
        );
        assert_eq!(d.poll_timeout(), Some(ms(1010)));
    }
}

#[test]
fn sdo_write_of_1017h_rearms_the_heartbeat() {
    let mut d = booted();
    let _ = sent(&mut d);
    sdo_request(&mut d, ms(100), [0x2B, 0x17, 0x10, 0, 0xF4, 0x01, 0, 0]);
    assert_eq!(sent(&mut d), ["584#6017100000000000"]);
    assert_eq!(d.poll_timeout(), Some(ms(600)));
    assert_eq!(
        events(&mut d)[1..],
        [DeviceEvent::ObjectWritten {
            index: 0x1017,
            sub: 0
        }]
    );
}

#[test]
fn emcy_raise_and_clear_with_the_register_and_history() {
    let mut d = booted();
    let _ = sent(&mut d);
    let emcy = Emergency {
        code: ErrorCode(0x5010),
        register: ErrorRegister::empty(),
        manufacturer: [1, 2, 0, 0, 0],
    };
    d.raise_error(ErrorRegister::DEVICE_PROFILE, emcy);
    assert_eq!(sent(&mut d), ["084#1050210102000000"]);
    assert_eq!(d.comm().errors(), &[0x0201_5010]);
    d.clear_error(ErrorRegister::DEVICE_PROFILE);
    assert_eq!(sent(&mut d), ["084#0000000000000000"]);
    d.clear_error(ErrorRegister::DEVICE_PROFILE);
    assert_eq!(sent(&mut d), Vec::<String>::new(), "nothing to clear");
    // Stopped: the register changes, no frame.
    d.handle_frame(ms(1), &frame(0x000, &[0x02, 4]));
    d.raise_error(ErrorRegister::VOLTAGE, emcy);
    assert_eq!(sent(&mut d), Vec::<String>::new());
    assert!(d
        .error_register()
        .contains(ErrorRegister::VOLTAGE | ErrorRegister::GENERIC));
}

#[test]
fn stopped_drops_a_transfer_silently_and_serves_no_sdo() {
    let mut d = booted();
    let _ = sent(&mut d);
    // A segmented upload of 1008h ("dev" is 3 bytes: expedited) -- use a
    // segmented download to 1008h instead: initiate, then stop.
    sdo_request(&mut d, ms(1), [0x21, 0x00, 0x20, 0, 1, 0, 0, 0]);
    assert_eq!(sent(&mut d), ["584#6000200000000000"]);
    d.handle_frame(ms(2), &frame(0x000, &[0x02, 0]));
    d.handle_timeout(ms(10_000));
    assert!(
        sent(&mut d).iter().all(|f| f.starts_with("704#")),
        "no abort frame in stopped"
    );
    sdo_request(&mut d, ms(10_001), [0x40, 0x00, 0x10, 0, 0, 0, 0, 0]);
    assert_eq!(sent(&mut d), Vec::<String>::new());
}

#[test]
fn pdos_only_in_operational_and_short_rpdos_refused() {
    let mut d = booted();
    let _ = sent(&mut d);
    d.handle_frame(ms(1), &frame(0x204, &[5]));
    assert_eq!(d.objects().0, 7, "no RPDO in pre-operational");
    d.handle_frame(ms(2), &frame(0x000, &[0x01, 4]));
    assert_eq!(sent(&mut d), ["184#07"]);
    d.handle_frame(ms(3), &frame(0x204, &[5]));
    assert_eq!(d.objects().0, 5);
    assert_eq!(
        sent(&mut d),
        ["184#05"],
        "a changed mapped value is an event"
    );
    d.handle_frame(ms(4), &frame(0x204, &[]));
    assert_eq!(sent(&mut d), ["084#1082110000000000"]);
    let evs = events(&mut d);
    assert!(evs.contains(&DeviceEvent::RpdoRefused {
        pdo: PdoNumber::P0,
        error: RpdoError::TooShort { need: 1, got: 0 }
    }));
    d.set_tpdos_enabled(ms(5), false);
    d.handle_timeout(ms(500));
    assert!(sent(&mut d).iter().all(|f| !f.starts_with("184#")));
}

/// The TPDOs read the mapped objects again after any input that may have
/// changed them, and may skip the reading otherwise: a value set without
/// side effects is an event at the next input, a value set before an
/// update that reports no change of its own is one at that update, and an
/// SDO download of the mapped object is one at once.
#[test]
fn a_mapped_value_changed_by_any_path_is_an_event() {
    let mut d = booted();
    let _ = sent(&mut d);
    d.handle_frame(ms(1), &frame(0x000, &[0x01, 4]));
    assert_eq!(sent(&mut d), ["184#07"]);
    d.objects_mut().0 = 8;
    assert!(sent(&mut d).is_empty(), "no side effects");
    d.handle_timeout(ms(2));
    assert_eq!(sent(&mut d), ["184#08"]);
    d.update_changed(ms(3), |_| false);
    d.handle_timeout(ms(4));
    assert!(sent(&mut d).is_empty(), "nothing changed");
    d.objects_mut().0 = 9;
    d.update_changed(ms(5), |_| false);
    assert_eq!(sent(&mut d), ["184#09"]);
    d.update_changed(ms(6), |o| core::mem::replace(&mut o.0, 10) != 10);
    assert_eq!(sent(&mut d), ["184#0A"]);
    sdo_write_u8(&mut d, ms(7), 0x2000, 11);
    assert_eq!(sent(&mut d), ["584#6000200000000000", "184#0B"]);
}

#[test]
fn undrained_events_change_nothing() {
    // Two devices fed the same frames; one is drained, one never.
    let mut drained = booted();
    let mut undrained = booted();
    let hb = frame(0x701, &[0x05]);
    for i in 0..200u64 {
        let now = ms(i * 700);
        for d in [&mut drained, &mut undrained] {
            d.handle_frame(now, &hb);
            sdo_write_u8(d, now, 0x2000, i as u8);
            d.handle_timeout(now);
        }
        assert_eq!(sent(&mut drained), sent(&mut undrained), "step {i}");
        assert_eq!(drained.poll_timeout(), undrained.poll_timeout());
        let _ = events(&mut drained);
    }
    // The boot state change and 200 object writes, 16 kept.
    assert_eq!(undrained.events_dropped(), 201 - 16);
    assert_eq!(drained.events_dropped(), 0);
    #[cfg(feature = "heartbeat-consumer")]
    assert!(undrained
        .heartbeat_consumer()
        .is_alive(NodeId::new(1).unwrap()));
    let kept = events(&mut undrained);
    assert_eq!(kept.len(), 16);
    #[cfg(feature = "heartbeat-consumer")]
    assert!(!kept
        .iter()
        .any(|e| matches!(e, DeviceEvent::Heartbeat(HeartbeatEvent::Lost(_)))));
}

/// CiA 301, 1001h: bit 0 (generic error) is set whenever any error is
/// signalled. Clearing only the generic bit while another error remains
/// keeps it (and says so in the error reset EMCY). Failed before the fix:
/// the register became 04h (current, no generic bit).
#[test]
fn clearing_the_generic_bit_keeps_it_while_other_errors_remain() {
    let mut d = with_errors(&[ErrorRegister::CURRENT, ErrorRegister::GENERIC]);
    d.clear_error(ErrorRegister::GENERIC);
    assert_eq!(
        d.error_register(),
        ErrorRegister::GENERIC | ErrorRegister::CURRENT
    );
    assert_eq!(sent(&mut d), ["084#0000030000000000"]);
    d.clear_error(ErrorRegister::CURRENT);
    assert!(d.error_register().is_empty());
    assert_eq!(sent(&mut d), ["084#0000000000000000"]);
}

/// The heartbeat supervision follows 1016h whatever the order of the
/// changed entries: moving node 2 from sub 2 to sub 1 while sub 2 takes
/// node 3 watches nodes 2 and 3 and no longer node 1. Failed before the
/// fix: sub 1 was refused as a duplicate of the old sub 2 and kept
/// watching node 1, so node 2's silence went unnoticed there.
#[cfg(feature = "heartbeat-consumer")]
#[test]
fn consumer_entries_follow_1016h_whatever_the_order() {
    let mut d = watching_nodes_1_and_2();
    d.update_comm(ms(1), |c| c.set_consumers(&[entry(2), entry(3)]));
    let watched: Vec<_> = (0..2).map(|s| d.heartbeat_consumer().entry(s)).collect();
    assert_eq!(watched, [Some(entry(2)), Some(entry(3))]);
    let _ = events(&mut d);
    // Node 1 is no longer watched, node 2 is.
    d.handle_frame(ms(2), &frame(0x701, &[0x05]));
    d.handle_frame(ms(2), &frame(0x702, &[0x05]));
    d.handle_timeout(ms(1500));
    assert_eq!(
        events(&mut d),
        [DeviceEvent::Heartbeat(HeartbeatEvent::Lost(n(2)))]
    );
}

/// A download that NMT stop or reset communication drops ends in the
/// dictionary's `abort_write`, as the `ObjectDictionary` contract says
/// ("the download was aborted after some write calls"): the next download
/// of the same object succeeds. Failed before the fix: the dictionary still
/// held the dropped transfer's bytes and refused the new value with
/// 08000000h.
#[cfg(feature = "alloc")]
#[test]
fn a_dropped_download_is_aborted_in_the_dictionary() {
    use crate::od::{Access, MemoryDictionary};
    for cs in [0x02u8, 0x82] {
        let mut od = MemoryDictionary::new();
        od.insert(0x2100, 0, Access::ReadWrite, &[0; 8]);
        let mut d: Cia301Device<MemoryDictionary> =
            ProfiledDevice::plain(DeviceConfig::new(node()), od);
        d.boot(ms(0));
        let _ = sent(&mut d);
        // Segmented download of 8 bytes: initiate, first segment.
        sdo_request(&mut d, ms(1), [0x21, 0x00, 0x21, 0, 8, 0, 0, 0]);
        assert_eq!(sent(&mut d), ["584#6000210000000000"]);
        sdo_request(&mut d, ms(2), [0x00, 1, 2, 3, 4, 5, 6, 7]);
        assert_eq!(sent(&mut d), ["584#2000000000000000"]);
        d.handle_frame(ms(3), &frame(0x000, &[cs, 4]));
        d.handle_frame(ms(4), &frame(0x000, &[0x80, 4]));
        let _ = sent(&mut d);
        // The same object again, expedited.
        sdo_request(&mut d, ms(5), [0x23, 0x00, 0x21, 0, 9, 9, 9, 9]);
        assert_eq!(
            sent(&mut d),
            ["584#8000210013000706"],
            "{cs:02X}h: the 4-byte value is refused by length only"
        );
        let mut answers = Vec::new();
        for (t, data) in [
            (6, [0x21, 0x00, 0x21, 0, 8, 0, 0, 0]),
            (7, [0x00, 1, 2, 3, 4, 5, 6, 7]),
            (8, [0x1D, 8, 0, 0, 0, 0, 0, 0]),
        ] {
            d.handle_frame(ms(t), &frame(0x604, &data));
            answers.extend(sent(&mut d));
        }
        assert_eq!(
            answers,
            [
                "584#6000210000000000",
                "584#2000000000000000",
                "584#3000000000000000"
            ],
            "{cs:02X}h"
        );
        let mut buf = [0u8; 8];
        let mut app = d.dictionary().inner.app.clone();
        let _ = crate::od::ObjectDictionary::read(&mut app, 0x2100, 0, 0, &mut buf);
        assert_eq!(buf, [1, 2, 3, 4, 5, 6, 7, 8], "{cs:02X}h");
    }
}

/// 1016h over SDO, end to end (CiA 301): a consumer entry takes effect at
/// once (supervision of the new node from its first heartbeat), an enabled
/// entry for a node another sub-index watches is refused with 06040043h
/// and changes nothing.
#[cfg(feature = "heartbeat-consumer")]
#[test]
fn sdo_writes_of_1016h() {
    let mut d = watching_nodes_1_and_2();
    let _ = sent(&mut d);
    // 1016h sub 1 = node 3, 500 ms (0003_01F4h).
    sdo_request(&mut d, ms(1), [0x23, 0x16, 0x10, 1, 0xF4, 0x01, 3, 0]);
    assert_eq!(sent(&mut d), ["584#6016100100000000"]);
    assert_eq!(
        d.heartbeat_consumer().entry(0),
        Some(ConsumerEntry::new(n(3), Duration::from_millis(500)))
    );
    // Sub 2 = node 3 as well: refused, sub 2 still watches node 2.
    sdo_request(&mut d, ms(2), [0x23, 0x16, 0x10, 2, 0xE8, 0x03, 3, 0]);
    assert_eq!(sent(&mut d), ["584#8016100243000406"]);
    assert_eq!(
        d.comm().consumers(),
        [
            ConsumerEntry::new(n(3), Duration::from_millis(500)),
            entry(2)
        ]
    );
    assert_eq!(d.heartbeat_consumer().entry(1), Some(entry(2)));
    let _ = events(&mut d);
    d.handle_frame(ms(10), &frame(0x703, &[0x05]));
    d.handle_timeout(ms(510));
    assert_eq!(
        events(&mut d),
        [DeviceEvent::Heartbeat(HeartbeatEvent::Lost(n(3)))]
    );
}

/// 1003h over SDO, end to end (CiA 301): writing 0 to sub 0 clears the
/// history and any other value is refused with 06090030h.
#[test]
fn sdo_writes_of_1003h() {
    let mut d = with_errors(&[ErrorRegister::CURRENT, ErrorRegister::CURRENT]);
    sdo_request(&mut d, ms(600), [0x2F, 0x03, 0x10, 0, 1, 0, 0, 0]);
    assert_eq!(sent(&mut d), ["584#8003100030000906"]);
    assert_eq!(d.comm().errors().len(), 2);
    sdo_request(&mut d, ms(601), [0x2F, 0x03, 0x10, 0, 0, 0, 0, 0]);
    assert_eq!(sent(&mut d), ["584#6003100000000000"]);
    assert!(d.comm().errors().is_empty());
    assert!(
        !d.error_register().is_empty(),
        "clearing the history leaves 1001h alone"
    );
}

/// The generic path: a [`MemoryDictionary`](crate::od::MemoryDictionary)'s
/// power-on values are all of it, so reset node rolls back what the bus
/// wrote (rw) and what the application changed after boot (ro, and an
/// object it added) alike; reset communication keeps them.
#[cfg(feature = "alloc")]
#[test]
fn reset_node_restores_every_object_of_a_memory_dictionary() {
    use crate::od::{Access, MemoryDictionary};
    for (cs, restored) in [(0x81u8, true), (0x82, false)] {
        let mut od = MemoryDictionary::new();
        od.insert(0x2000, 0, Access::ReadWrite, &[1]);
        od.insert(0x2001, 0, Access::ReadOnly, &[2, 0]);
        let mut d: Cia301Device<MemoryDictionary> =
            ProfiledDevice::plain(DeviceConfig::new(node()), od);
        d.update(ms(0), |o| {
            o.set(0x2001, 0, &[3, 0]);
        });
        d.boot(ms(0));
        let at_boot = d.objects().clone();
        sdo_request(&mut d, ms(1), [0x2F, 0x00, 0x20, 0, 9, 0, 0, 0]);
        d.update(ms(2), |o| {
            o.set(0x2001, 0, &[4, 0]);
            o.insert(0x2002, 0, Access::ReadOnly, &[5]);
        });
        let _ = sent(&mut d);
        assert_eq!(d.objects().get(0x2000, 0), Some(&[9][..]), "written by SDO");
        let changed = d.objects().clone();
        d.handle_frame(ms(3), &frame(0x000, &[cs, 4]));
        assert_eq!(sent(&mut d), ["704#00"], "{cs:02X}h");
        let want = if restored { &at_boot } else { &changed };
        assert_eq!(d.objects(), want, "{cs:02X}h");
        assert_eq!(
            d.objects().get(0x2001, 0),
            Some(&[if restored { 3 } else { 4 }, 0][..])
        );
    }
}

/// Without the heartbeat consumer (feature `heartbeat-consumer`) the
/// device has no 1016h: an SDO upload or download of it is aborted with
/// 06020000h, as for any absent object.
#[cfg(not(feature = "heartbeat-consumer"))]
#[test]
fn no_1016h_over_sdo_without_the_heartbeat_consumer() {
    let mut d = booted();
    let _ = (sent(&mut d), events(&mut d));
    // Upload of sub 0 and sub 1, expedited download of sub 1 (node 1, 2000 ms).
    for request in [
        [0x40, 0x16, 0x10, 0, 0, 0, 0, 0],
        [0x40, 0x16, 0x10, 1, 0, 0, 0, 0],
        [0x23, 0x16, 0x10, 1, 0xD0, 0x07, 1, 0],
    ] {
        d.handle_frame(ms(1), &frame(0x604, &request));
        let [_, lo, hi, sub, ..] = request;
        let abort = std::format!("584#80{lo:02X}{hi:02X}{sub:02X}00000206");
        assert_eq!(sent(&mut d), [abort]);
    }
    // The aborts are the only events; 1017h is still served.
    let evs = events(&mut d);
    assert_eq!(evs.len(), 3, "{evs:?}");
    assert!(evs
        .iter()
        .all(|e| matches!(e, DeviceEvent::SdoAborted { index: 0x1016, .. })));
    sdo_request(&mut d, ms(2), [0x40, 0x17, 0x10, 0, 0, 0, 0, 0]);
    assert_eq!(sent(&mut d), ["584#4B171000E8030000"]);
}

/// Without the heartbeat consumer another node's heartbeats, boot-up and
/// silence change nothing: the same frames, deadlines and (no) events as a
/// device that never saw them.
#[cfg(not(feature = "heartbeat-consumer"))]
#[test]
fn other_heartbeats_change_nothing_without_the_heartbeat_consumer() {
    let mut fed = booted();
    let mut quiet = booted();
    let _ = (events(&mut fed), events(&mut quiet));
    let _ = (sent(&mut fed), sent(&mut quiet));
    for (i, data) in [[0x00u8], [0x05], [0x7F], [0x05]].iter().enumerate() {
        let now = ms(i as u64 * 300);
        fed.handle_frame(now, &frame(0x701, data));
        fed.handle_frame(now, &frame(0x702, data));
        for d in [&mut fed, &mut quiet] {
            d.handle_timeout(now);
        }
        assert_eq!(sent(&mut fed), sent(&mut quiet), "step {i}");
        assert_eq!(fed.poll_timeout(), quiet.poll_timeout(), "step {i}");
    }
    // Long silence: no loss is reported.
    for d in [&mut fed, &mut quiet] {
        d.handle_timeout(ms(10_000));
    }
    assert_eq!(sent(&mut fed), sent(&mut quiet));
    assert_eq!(events(&mut fed), []);
    assert_eq!(fed.poll_timeout(), Some(ms(11_000)));
}
