//! Properties of node guarding and of the SYNC / TIME COB-ID codecs: the
//! slave's replies carry its state and a toggle that alternates from 0;
//! the master declares a node lost exactly when `life time factor`
//! requests in a row went unanswered, and restored at the next reply; the
//! 1005h and 1012h values keep every bit.

use core::time::Duration;

use canopen_codec::machine::Machine;
use canopen_codec::nmt::guarding::{GuardingMaster, GuardingSlave, MasterGuardingEvent};
use canopen_codec::nmt::NmtState;
use canopen_codec::sync::SyncCobId;
use canopen_codec::time::TimeCobId;
use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, failure_persistence: Some(Box::new(proptest::test_runner::FileFailurePersistence::Direct("tests/proptest-regressions/guarding_props.txt"))), ..ProptestConfig::default() })]

    #[test]
    fn slave_replies_carry_state_and_alternate(states in proptest::collection::vec(any::<u8>(), 1..60), reset_at in any::<prop::sample::Index>()) {
        let node = NodeId::new(33).unwrap();
        let mut s = GuardingSlave::new(node);
        let request = CanFrame::remote(CanId::Standard(0x721), 1).unwrap();
        let reset = reset_at.index(states.len());
        let mut toggle = false;
        for (i, raw) in states.iter().enumerate() {
            if i == reset {
                s.reset();
                toggle = false;
            }
            let state = NmtState::from_bits(*raw);
            s.set_state(state);
            s.handle_frame(Timestamp::from_millis(i as u64), &request);
            let f = s.poll_transmit().unwrap();
            prop_assert_eq!(f.data(), &[state.bits() | if toggle { 0x80 } else { 0 }]);
            toggle = !toggle;
        }
    }

    #[test]
    fn master_lost_exactly_after_factor_misses(
        factor in 0u8..=5,
        answered in proptest::collection::vec(any::<bool>(), 1..80),
    ) {
        let node = NodeId::new(7).unwrap();
        let mut m = GuardingMaster::new(node, Duration::from_millis(50), factor);
        let mut s = GuardingSlave::new(node);
        s.set_state(NmtState::Operational);
        m.start(Timestamp::ZERO);
        let needed = usize::from(factor.max(1));
        let (mut misses, mut lost) = (0usize, false);
        for (i, ok) in answered.iter().enumerate() {
            let now = Timestamp::from_millis(50 * i as u64);
            if i > 0 {
                m.handle_timeout(now);
                // The request before this one: answered or not.
                if answered[i - 1] {
                    misses = 0;
                } else {
                    misses += 1;
                }
                let event = m.poll_event();
                if misses >= needed && !lost {
                    prop_assert_eq!(event, Some(MasterGuardingEvent::Lost(node)));
                    lost = true;
                } else {
                    prop_assert_eq!(event, None);
                }
            }
            let request = m.poll_transmit().unwrap();
            prop_assert!(request.is_remote());
            if *ok {
                s.handle_frame(now, &request);
                let reply = s.poll_transmit().unwrap();
                m.handle_frame(now.add_micros(300), &reply);
                let event = m.poll_event();
                if lost {
                    prop_assert_eq!(event, Some(MasterGuardingEvent::Restored { node, state: NmtState::Operational }));
                    lost = false;
                } else {
                    prop_assert_eq!(event, None);
                }
            }
            prop_assert_eq!(m.is_lost(), lost);
        }
    }

    #[test]
    fn cob_id_values_keep_every_bit(raw in any::<u32>()) {
        let sync = SyncCobId::from_raw(raw);
        prop_assert_eq!(sync.raw(), raw);
        prop_assert_eq!(sync.generates(), raw & 0x4000_0000 != 0);
        prop_assert_eq!(sync.with_generate(sync.generates()), sync);
        let time = TimeCobId::from_raw(raw);
        prop_assert_eq!(time.raw(), raw);
        prop_assert_eq!((time.consumes(), time.produces()), (raw >> 31 == 1, raw & 0x4000_0000 != 0));
        prop_assert_eq!(time.with_consume(time.consumes()).with_produce(time.produces()), time);
        // The identifier: 29 bits with bit 29, else 11 bits (bits 11-28 zero).
        let want = if raw & 0x2000_0000 != 0 {
            CanId::extended(raw & 0x1FFF_FFFF)
        } else if raw & 0x1FFF_F800 == 0 {
            CanId::standard((raw & 0x7FF) as u16)
        } else {
            None
        };
        prop_assert_eq!(sync.id(), want);
        prop_assert_eq!(time.id(), want);
    }
}
