//! The frame half of the back-pressure rule (`canopen_codec::machine`): a
//! machine whose frames are not drained keeps the newest ones, drops the
//! oldest and counts each drop in `Machine::frames_dropped`, the same in
//! every machine. Each case makes one more frame than the machine keeps
//! (or, for the machines that keep one frame, two), then drains.

use core::time::Duration;

use crate::common::ms;
use canopen_codec::machine::Machine;
use canopen_codec::nmt::guarding::{GuardingMaster, GuardingSlave};
use canopen_codec::nmt::heartbeat::HeartbeatProducer;
use canopen_codec::pdo::{PdoCobId, PdoCommParams, TpdoProducer};
use canopen_codec::sync::SyncProducer;
use canopen_codec::time::{TimeCobId, TimeOfDay, TimeProducer};
use canopen_codec::{CanFrame, CanId, NodeId};

fn node(n: u8) -> NodeId {
    NodeId::new(n).unwrap()
}

/// Every frame left, as candump text.
fn drain<M: Machine>(m: &mut M) -> Vec<String> {
    std::iter::from_fn(|| m.poll_transmit())
        .map(|f| f.to_string())
        .collect()
}

#[test]
fn heartbeat_producer_keeps_the_newest_two() {
    let mut p = HeartbeatProducer::new(node(5), Duration::from_millis(100));
    p.boot(ms(0));
    for t in [100, 200] {
        p.handle_timeout(ms(t));
    }
    assert_eq!(p.frames_dropped(), 1);
    assert_eq!(drain(&mut p), ["705#7F", "705#7F"]);
    p.handle_timeout(ms(300));
    assert_eq!(
        (drain(&mut p), p.frames_dropped()),
        (vec!["705#7F".to_string()], 1)
    );
}

#[test]
fn sync_producer_keeps_the_newest_two() {
    let mut p = SyncProducer::new(Duration::from_millis(10), 5).unwrap();
    p.start(ms(0));
    for t in [10, 20, 30] {
        p.handle_timeout(ms(t));
    }
    assert_eq!(p.frames_dropped(), 1);
    assert_eq!(drain(&mut p), ["080#02", "080#03"]);
}

#[test]
fn time_producer_keeps_the_newest_two() {
    let mut p = TimeProducer::new(TimeCobId::DEFAULT.with_produce(true));
    for day in 1..=3 {
        assert!(p.send_time(ms(0), TimeOfDay::new(0, day).unwrap()));
    }
    assert_eq!(p.frames_dropped(), 1);
    assert_eq!(drain(&mut p), ["100#000000000200", "100#000000000300"]);
}

#[test]
fn guarding_slave_keeps_the_newest_two_replies() {
    let mut s = GuardingSlave::new(node(3));
    let request = CanFrame::remote(CanId::Standard(0x703), 1).unwrap();
    for t in 0..3 {
        s.handle_frame(ms(t), &request);
    }
    assert_eq!(s.frames_dropped(), 1);
    // The toggle alternates with every reply: the kept ones are the second
    // and the third.
    assert_eq!(drain(&mut s), ["703#80", "703#00"]);
}

#[test]
fn guarding_master_keeps_the_newest_two_requests() {
    let mut m = GuardingMaster::new(node(3), Duration::from_millis(10), 5);
    m.start(ms(0));
    for t in [10, 20] {
        m.handle_timeout(ms(t));
    }
    assert_eq!(m.frames_dropped(), 1);
    assert_eq!(drain(&mut m), ["703#R1", "703#R1"]);
}

#[test]
fn tpdo_producer_sends_the_latest_value_once() {
    let mut p = TpdoProducer::new();
    p.configure(
        ms(0),
        PdoCommParams::event_driven(PdoCobId::standard(0x18A), 0),
    );
    p.set_operational(ms(0), true);
    p.set_payload(ms(1), canopen_codec::bytes::Payload::new(&[1]).unwrap());
    p.set_payload(ms(2), canopen_codec::bytes::Payload::new(&[2]).unwrap());
    assert_eq!(p.frames_dropped(), 2);
    assert_eq!(drain(&mut p), ["18A#02"]);
}

#[cfg(feature = "alloc")]
#[test]
fn sdo_server_keeps_the_newest_answer() {
    use canopen_codec::od::{Access, MemoryDictionary};
    use canopen_codec::sdo::{Server, ServerConfig};
    let mut od = MemoryDictionary::new();
    od.insert(0x1000, 0, Access::ReadOnly, &[0x91, 0x01, 0x00, 0x00]);
    od.insert(0x1001, 0, Access::ReadOnly, &[0x00]);
    let mut s = Server::new(ServerConfig::for_node(node(10)), od);
    let read = |index: u16| {
        let [lo, hi] = index.to_le_bytes();
        CanFrame::standard(0x60A, &[0x40, lo, hi, 0, 0, 0, 0, 0]).unwrap()
    };
    s.handle_frame(ms(0), &read(0x1000));
    s.handle_frame(ms(1), &read(0x1001));
    assert_eq!(s.frames_dropped(), 1);
    assert_eq!(drain(&mut s), ["58A#4F01100000000000"]);
}
