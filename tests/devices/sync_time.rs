//! SYNC and TIME on the simulated bus (CiA 301 "CANopen application layer
//! and communication profile", sections 7.2.5 "Synchronization object" and
//! 7.2.6 "Time stamp object"): the producer's counter runs 1..=overflow and
//! wraps for every overflow value, a device that generates SYNC runs its
//! own synchronous TPDOs from it, a consumer reports skipped counters and
//! synchronous PDOs outside the window, and TIME goes from a producing
//! device to a consuming one.

use crate::common;

use core::time::Duration;

use crate::common::ms;
use canopen_codec::device::{Cia301Device, DeviceConfig, DeviceEvent};
use canopen_codec::machine::{drive_timers, Machine};
use canopen_codec::od::{Access, MemoryDictionary};
use canopen_codec::pdo::{
    MappingEntry, PdoCobId, PdoCommParams, PdoConfig, PdoDirection, PdoMapping, PdoSlot,
    TransmissionType,
};
use canopen_codec::sync::{SyncCobId, SyncConsumer, SyncEvent, SyncProducer};
use canopen_codec::time::{TimeCobId, TimeConsumer, TimeEvent, TimeOfDay, TimeProducer};
use canopen_codec::{CanFrame, CanId, Codec, NodeId, PdoNumber, Timestamp};
use common::sim::bus;

type Dev = Cia301Device<MemoryDictionary>;

fn node(n: u8) -> NodeId {
    NodeId::new(n).unwrap()
}

/// 2000h, a mappable U8 holding 0x42.
fn app() -> MemoryDictionary {
    let mut od = MemoryDictionary::new();
    od.insert(0x2000, 0, Access::ReadWrite, &[0x42])
        .set_mappable(0x2000, 0, true);
    od
}

fn params(id: u16, transmission_type: TransmissionType) -> PdoCommParams {
    PdoCommParams {
        transmission_type,
        ..PdoCommParams::event_driven(PdoCobId::standard(id), 0)
    }
}

/// TPDO 0 on 180h + node, synchronous every SYNC; RPDO 0 on 200h + node,
/// synchronous acyclic; both map 2000h.
fn pdos(n: u8) -> PdoConfig {
    let mapping = PdoMapping::new(&[MappingEntry::new(0x2000, 0, 8)]).unwrap();
    let mut pdos = PdoConfig::new();
    pdos.insert(
        PdoDirection::Transmit,
        PdoNumber::P0,
        PdoSlot::new(
            params(0x180 + u16::from(n), TransmissionType::SynchronousCyclic(1)),
            &mapping,
        ),
    );
    pdos.insert(
        PdoDirection::Receive,
        PdoNumber::P0,
        PdoSlot::new(
            params(0x200 + u16::from(n), TransmissionType::SynchronousAcyclic),
            &mapping,
        ),
    );
    pdos
}

/// 1019h row by row: 0 sends SYNC without data, 2..=240 a counter that
/// runs 1..=overflow and wraps; 1 and 241..=255 are refused.
#[test]
fn producer_counter_runs_to_overflow_and_wraps() {
    for overflow in 0..=255u8 {
        let Some(mut p) = SyncProducer::new(Duration::from_millis(1), overflow) else {
            assert!(overflow == 1 || overflow > 240, "{overflow} refused");
            continue;
        };
        assert!(overflow == 0 || (2..=240).contains(&overflow));
        p.start(Timestamp::ZERO);
        let mut data = Vec::new();
        let cycles = u64::from(overflow.max(1)) * 2 + 1;
        drive_timers(&mut p, ms(cycles), |_, f| {
            assert_eq!(f.id(), canopen_codec::CanId::Standard(0x080));
            data.push(f.data().to_vec());
        });
        assert_eq!(data.len() as u64, cycles, "overflow {overflow}");
        for (i, d) in data.iter().enumerate() {
            if overflow == 0 {
                assert!(d.is_empty());
            } else {
                let want = (i % usize::from(overflow)) as u8 + 1;
                assert_eq!(d, &[want], "overflow {overflow}, SYNC {i}");
            }
        }
    }
}

#[test]
fn device_generating_sync_runs_its_own_synchronous_tpdos() {
    let config = DeviceConfig {
        heartbeat: Duration::ZERO,
        pdos: pdos(3),
        sync_cob_id: SyncCobId::DEFAULT.with_generate(true),
        cycle_period: Duration::from_millis(10),
        sync_counter_overflow: 3,
        ..DeviceConfig::new(node(3))
    };
    let mut sim = bus(100);
    let d = sim.add("Device", Dev::plain(config, app()));
    sim.with(d, |dev, now| dev.boot(now));
    // Pre-operational: SYNC only.
    sim.run_until(ms(25)).unwrap();
    assert_eq!(
        sim.lines(1, 25),
        ["    10.000 Device 080#01", "    20.000 Device 080#02"]
    );
    // Operational: each SYNC followed by the synchronous TPDO.
    sim.inject(CanFrame::standard(0x000, &[0x01, 3]).unwrap());
    sim.run_until(ms(45)).unwrap();
    assert_eq!(
        sim.lines(26, 45),
        [
            "    30.000 Device 080#03",
            "    30.000 Device 183#42",
            "    40.000 Device 080#01",
            "    40.000 Device 183#42",
        ]
    );
    // Stopped: no SYNC, no PDO.
    sim.inject(CanFrame::standard(0x000, &[0x02, 3]).unwrap());
    sim.run_until(ms(100)).unwrap();
    assert_eq!(sim.lines(46, 100), Vec::<String>::new());
    // Reset communication: pre-operational again, counter from 1.
    sim.inject(CanFrame::standard(0x000, &[0x82, 3]).unwrap());
    sim.run_until(ms(111)).unwrap();
    assert_eq!(
        sim.lines(100, 111),
        [
            "   100.000 Outside 000#8203",
            "   100.100 Device 703#00",
            "   110.100 Device 080#01"
        ]
    );
}

#[test]
fn device_consumes_external_sync_and_reports_a_skip() {
    // A device consuming an external producer's SYNC with counter 5:
    // the synchronous TPDO follows every SYNC; a lost SYNC is a skip.
    let config = DeviceConfig {
        heartbeat: Duration::ZERO,
        pdos: pdos(4),
        sync_counter_overflow: 5,
        ..DeviceConfig::new(node(4))
    };
    let mut sim = bus(100);
    let d = sim.add("Device", Dev::plain(config, app()));
    let mut producer = SyncProducer::new(Duration::from_millis(10), 5).unwrap();
    producer.start(Timestamp::ZERO);
    sim.add("Master", producer);
    sim.with(d, |dev, now| dev.boot(now));
    sim.inject(CanFrame::standard(0x000, &[0x01, 4]).unwrap());
    sim.drop_if(|s| s.from == "Master" && s.at == ms(30));
    sim.run_until(ms(55)).unwrap();
    let tpdos = sim.frames_on(0x184).len();
    assert_eq!(tpdos, 4, "{:#?}", sim.lines(0, 55));
    let skips: Vec<_> = sim
        .event_list(d)
        .into_iter()
        .filter_map(|e| match e {
            DeviceEvent::Sync(s) => Some(s),
            _ => None,
        })
        .collect();
    assert_eq!(
        skips,
        [SyncEvent::CounterSkipped {
            expected: 3,
            got: 4
        }]
    );
}

#[test]
fn synchronous_rpdo_outside_the_window() {
    let config = DeviceConfig {
        heartbeat: Duration::ZERO,
        pdos: pdos(5),
        sync_window: Duration::from_millis(2),
        ..DeviceConfig::new(node(5))
    };
    let mut dev = Dev::plain(config, app());
    dev.boot(ms(0));
    dev.handle_frame(ms(0), &CanFrame::standard(0x000, &[0x01, 5]).unwrap());
    dev.handle_frame(ms(10), &CanFrame::standard(0x080, &[]).unwrap());
    // 1 ms after the SYNC: inside; 3 ms after: outside.
    dev.handle_frame(ms(11), &CanFrame::standard(0x205, &[0x01]).unwrap());
    dev.handle_frame(ms(13), &CanFrame::standard(0x205, &[0x02]).unwrap());
    let events: Vec<_> = std::iter::from_fn(|| dev.poll_event())
        .filter_map(|e| match e {
            DeviceEvent::Sync(s) => Some(s),
            _ => None,
        })
        .collect();
    assert_eq!(
        events,
        [SyncEvent::OutsideWindow {
            since_sync_us: 3_000
        }]
    );
    // The bare consumer: no window means always inside, before any SYNC
    // too; with a window, before any SYNC is outside.
    let mut c = SyncConsumer::new();
    assert!(c.note_synchronous_pdo(ms(5)));
    c.set_window(Duration::from_millis(1));
    assert!(!c.note_synchronous_pdo(ms(5)));
    assert_eq!(
        c.poll_event(),
        Some(SyncEvent::OutsideWindow {
            since_sync_us: u32::MAX
        })
    );
    // The largest window (1007h = FFFFFFFFh µs) is kept whole, the elapsed
    // time is compared unsaturated, and only the reported value saturates.
    let sync = CanFrame::standard(0x080, &[]).unwrap();
    let us = Timestamp::from_micros;
    c.set_window(Duration::from_secs(1 << 40));
    assert!(c.accept(us(0), &sync));
    assert_eq!(c.poll_event(), Some(SyncEvent::Received { counter: None }));
    assert!(c.note_synchronous_pdo(us(u64::from(u32::MAX))));
    assert!(!c.note_synchronous_pdo(us(u64::from(u32::MAX) + 1)));
    assert_eq!(
        c.poll_event(),
        Some(SyncEvent::OutsideWindow {
            since_sync_us: u32::MAX
        })
    );
    assert_eq!(c.last_sync(), Some(us(0)));
}

#[test]
fn time_round_trip_between_devices() {
    let producing = DeviceConfig {
        time_cob_id: TimeCobId::DEFAULT.with_produce(true),
        ..DeviceConfig::new(node(6))
    };
    let consuming = DeviceConfig {
        time_cob_id: TimeCobId::DEFAULT.with_consume(true),
        ..DeviceConfig::new(node(7))
    };
    let mut sim = bus(100);
    let a = sim.add("A", Dev::plain(producing, app()));
    let b = sim.add("B", Dev::plain(consuming, app()));
    sim.with(a, |d, now| d.boot(now));
    sim.with(b, |d, now| d.boot(now));
    sim.run_until(ms(5)).unwrap();
    // 2026-12-01T11:30:00.250Z.
    let t = TimeOfDay::from_unix_millis(1_796_124_600_250).unwrap();
    assert_eq!(sim.with(a, |d, now| d.send_time(now, t)), Some(true));
    // The consumer cannot send.
    assert_eq!(sim.with(b, |d, now| d.send_time(now, t)), Some(false));
    sim.run_until(ms(10)).unwrap();
    let received: Vec<_> = sim
        .events(b)
        .iter()
        .filter_map(|(_, e)| match e {
            DeviceEvent::Time(TimeEvent::Received { time, at }) => Some((*time, at.as_micros())),
            _ => None,
        })
        .collect();
    assert_eq!(received, [(t, 5_100)]);
    assert_eq!(sim.machine(b).unwrap().last_time(), Some(t));
    assert_eq!(sim.frames_on(0x100).len(), 1);
    assert_eq!(t.unix_millis(), 1_796_124_600_250);
    // The bare machines: no produce bit, nothing sent; no consume bit,
    // nothing received.
    let mut p = TimeProducer::new(TimeCobId::DEFAULT);
    assert!(!p.send_time(ms(0), t));
    let mut c = TimeConsumer::new(TimeCobId::DEFAULT);
    c.handle_frame(ms(0), &t.to_frame_on(CanId::Standard(0x100)));
    assert_eq!(c.poll_event(), None);
}

/// 1006h then 1005h with the generate bit, written over SDO: the device
/// starts producing at once; clearing the bit stops it.
#[test]
fn sync_production_switched_over_sdo() {
    let mut sim = bus(100);
    let d = sim.add("Device", Dev::plain(DeviceConfig::new(node(8)), app()));
    sim.with(d, |dev, now| dev.boot(now));
    let sdo = |index: u16, value: u32| {
        let [i0, i1] = index.to_le_bytes();
        let [a, b, c, e] = value.to_le_bytes();
        CanFrame::standard(0x608, &[0x23, i0, i1, 0, a, b, c, e]).unwrap()
    };
    sim.inject(sdo(0x1006, 5_000));
    sim.inject(sdo(0x1005, 0x4000_0080));
    sim.run_until(ms(12)).unwrap();
    sim.inject(sdo(0x1005, 0x0000_0080));
    sim.run_until(ms(30)).unwrap();
    let syncs: Vec<u64> = sim.frames_on(0x080).iter().map(|(t, _)| *t).collect();
    assert_eq!(syncs, [5_100, 10_100]);
    assert!(!sim.machine(d).unwrap().sync_producer().is_running());
    // Every SDO write was answered (2 x 1005h, 1006h).
    assert_eq!(sim.frames_on(0x588).len(), 3);
}

/// What the producers send decodes, and reads in words as the decoder
/// prints it: SYNC with its counter, TIME with its day and milliseconds,
/// the guarding request and reply.
#[test]
fn produced_frames_decode_in_words() {
    use canopen_codec::nmt::guarding::{GuardingMaster, GuardingSlave};
    use canopen_codec::nmt::NmtState;
    use canopen_codec::Message;
    let words = |f: &CanFrame| {
        let m = Message::decode(f).unwrap();
        assert_eq!(m.encode(), *f);
        m.to_string()
    };
    let mut sync = SyncProducer::new(Duration::from_millis(1), 240).unwrap();
    sync.start(Timestamp::ZERO);
    let mut seen = Vec::new();
    drive_timers(&mut sync, ms(241), |_, f| seen.push(words(&f)));
    assert_eq!(seen[0], "SYNC counter 1");
    assert_eq!(seen[239], "SYNC counter 240");
    assert_eq!(seen[240], "SYNC counter 1");
    let mut time = TimeProducer::new(TimeCobId::DEFAULT.with_produce(true));
    assert!(time.send_time(ms(0), TimeOfDay::new(12 * 3_600_000, 2).unwrap()));
    assert_eq!(
        words(&time.poll_transmit().unwrap()),
        "TIME day 2 since 1984-01-01, 43200000 ms after midnight"
    );
    let mut master = GuardingMaster::new(node(5), Duration::from_millis(100), 3);
    master.start(ms(0));
    let request = master.poll_transmit().unwrap();
    assert_eq!(words(&request), "node guarding request node 5, DLC 1");
    let mut slave = GuardingSlave::new(node(5));
    slave.set_state(NmtState::Operational);
    slave.handle_frame(ms(0), &request);
    slave.handle_frame(ms(1), &request);
    // Without the request beside it, a reply with toggle 0 reads as a
    // heartbeat (the decoder program pairs them); toggle 1 is a reply.
    assert_eq!(
        words(&slave.poll_transmit().unwrap()),
        "heartbeat node 5: operational"
    );
    assert_eq!(
        words(&slave.poll_transmit().unwrap()),
        "node guarding reply node 5: operational, toggle 1"
    );
}
