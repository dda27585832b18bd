//! The heartbeat consumer reports exactly one `Lost` per silence longer
//! than its consumer time, at the moment the time runs out, and never a
//! false one.

use canopen_codec::machine::Machine;
use canopen_codec::nmt::heartbeat::{ConsumerEntry, HeartbeatConsumer, HeartbeatEvent};
use canopen_codec::{CanFrame, NodeId, Timestamp};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 1024, failure_persistence: Some(Box::new(proptest::test_runner::FileFailurePersistence::Direct("tests/proptest-regressions/heartbeat_props.txt"))), ..ProptestConfig::default() })]

    #[test]
    fn one_lost_per_silence_longer_than_the_time(
        time_ms in 1u16..=3000,
        start in 0u64..=10_000,
        gaps in proptest::collection::vec(0u64..=6000, 0..40),
        tail in 0u64..=8000,
    ) {
        let node = NodeId::new(1).unwrap();
        let mut c: HeartbeatConsumer<2> = HeartbeatConsumer::new();
        c.set_entry(Timestamp::ZERO, 0, ConsumerEntry { node: 1, time_ms });
        // Heartbeat arrival times (ms): start, then each gap.
        let mut arrivals = vec![start];
        for g in &gaps {
            arrivals.push(arrivals.last().unwrap() + g);
        }
        let end = arrivals.last().unwrap() + tail;
        // Expected Lost instants: after each silence strictly longer than the
        // time (a heartbeat arriving exactly at the deadline comes first).
        let t = u64::from(time_ms);
        let mut expected = Vec::new();
        for w in arrivals.windows(2) {
            if w[1] - w[0] > t {
                expected.push(w[0] + t);
            }
        }
        if end - arrivals.last().unwrap() >= t {
            expected.push(arrivals.last().unwrap() + t);
        }
        // Drive: frames first at equal instants, then timeouts.
        let frame = CanFrame::standard(0x701, &[0x05]).unwrap();
        let mut lost = Vec::new();
        let mut restored = 0;
        let mut i = 0;
        loop {
            let next_frame = arrivals.get(i).copied();
            let next_timeout = c.poll_timeout().map(|d| d.as_millis()).filter(|d| *d <= end);
            let now = match (next_frame, next_timeout) {
                (Some(f), Some(d)) if f <= d => { c.handle_frame(Timestamp::from_millis(f), &frame); i += 1; f }
                (Some(f), None) => { c.handle_frame(Timestamp::from_millis(f), &frame); i += 1; f }
                (_, Some(d)) => { c.handle_timeout(Timestamp::from_millis(d)); d }
                (None, None) => break,
            };
            while let Some(e) = c.poll_event() {
                match e {
                    HeartbeatEvent::Lost(n) => { prop_assert_eq!(n, node); lost.push(now); }
                    HeartbeatEvent::Restored { .. } => restored += 1,
                    other => prop_assert!(false, "unexpected {:?}", other),
                }
            }
        }
        prop_assert_eq!(&lost, &expected);
        // Every silence but a final one ends in a Restored.
        let final_silence = usize::from(end - arrivals.last().unwrap() >= t);
        prop_assert_eq!(restored, lost.len() - final_silence);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, failure_persistence: Some(Box::new(proptest::test_runner::FileFailurePersistence::Direct("tests/proptest-regressions/heartbeat_props.txt"))), ..ProptestConfig::default() })]

    /// The back-pressure rule: a consumer whose events are never read still
    /// takes every heartbeat. A node beating within its time (with state
    /// changes that fill the event queue) is never reported lost, its
    /// deadline is always one consumer time after its last heartbeat, and
    /// once the events are read a silence gives exactly one `Lost`.
    #[test]
    fn undrained_events_never_make_a_beating_node_lost(
        time_ms in 2u16..=3000,
        beats in proptest::collection::vec((0u16..=u16::MAX, 0u8..4), 1..80),
        silences in 1usize..4,
    ) {
        let node = NodeId::new(1).unwrap();
        let mut c: HeartbeatConsumer<1> = HeartbeatConsumer::new();
        c.set_entry(Timestamp::ZERO, 0, ConsumerEntry { node: 1, time_ms });
        let states = [0x05u8, 0x7F, 0x04, 0x05];
        let t = u64::from(time_ms);
        let mut now = 0u64;
        let mut events_made = 0u64;
        let mut last_state: Option<u8> = None;
        for (gap, s) in &beats {
            // A gap shorter than the consumer time.
            now += u64::from(*gap) % t;
            let state = states[usize::from(*s)];
            c.handle_timeout(Timestamp::from_millis(now));
            c.handle_frame(Timestamp::from_millis(now), &CanFrame::standard(0x701, &[state]).unwrap());
            c.handle_timeout(Timestamp::from_millis(now));
            if last_state.is_some_and(|p| p != state) {
                events_made += 1;
            }
            last_state = Some(state);
            prop_assert!(c.is_alive(node), "lost while beating at {} ms", now);
            prop_assert_eq!(c.poll_timeout(), Some(Timestamp::from_millis(now + t)));
        }
        // Nothing was read: the queue kept the newest 8 and counted the rest.
        prop_assert_eq!(c.events_dropped(), events_made.saturating_sub(8));
        let kept: Vec<HeartbeatEvent> = std::iter::from_fn(|| c.poll_event()).collect();
        prop_assert_eq!(kept.len() as u64, events_made.min(8));
        prop_assert!(kept.iter().all(|e| matches!(e, HeartbeatEvent::StateChanged { .. })), "only state changes");
        // Drained from now on: each silence longer than the time is one Lost.
        for _ in 0..silences {
            now += t;
            c.handle_timeout(Timestamp::from_millis(now));
            c.handle_timeout(Timestamp::from_millis(now + 5 * t));
            prop_assert_eq!(c.poll_event(), Some(HeartbeatEvent::Lost(node)));
            prop_assert_eq!(c.poll_event(), None);
            now += 5 * t;
            c.handle_frame(Timestamp::from_millis(now), &CanFrame::standard(0x701, &[0x05]).unwrap());
            prop_assert!(matches!(c.poll_event(), Some(HeartbeatEvent::Restored { .. })), "restored");
        }
    }
}
