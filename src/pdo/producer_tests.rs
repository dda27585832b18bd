use std::vec::Vec;

use super::*;
use crate::pdo::{PdoCobId, TransmissionType};

fn ms(n: u64) -> Timestamp {
    Timestamp::from_millis(n)
}

fn payload(b: &[u8]) -> Payload {
    Payload::new(b).unwrap()
}

/// Runs the producer from `from` to `to` (ms), calling handle_timeout at
/// every deadline; returns the send times in ms.
fn run(p: &mut TpdoProducer, from: u64, to: u64) -> Vec<u64> {
    let mut sent = Vec::new();
    let mut now = ms(from);
    if p.poll_transmit().is_some() {
        sent.push(from);
    }
    for _ in 0..10_000 {
        let Some(t) = p.poll_timeout() else { break };
        if t > ms(to) {
            break;
        }
        assert!(t >= now, "deadline in the past: {t} < {now}");
        now = t;
        p.handle_timeout(now);
        if let Some(f) = p.poll_transmit() {
            assert_eq!(f.id(), crate::CanId::Standard(0x18A));
            sent.push(now.as_millis());
        }
    }
    sent
}

fn charger_tpdo0() -> PdoCommParams {
    PdoCommParams::event_driven(PdoCobId::standard(0x18A), 200)
}

/// A producer configured with `comm` and operational at `at`.
fn running(at: Timestamp, comm: PdoCommParams) -> TpdoProducer {
    let mut p = TpdoProducer::new();
    p.configure(at, comm);
    p.set_operational(at, true);
    p
}

#[test]
fn nothing_before_configured_valid_and_operational() {
    let mut p = TpdoProducer::new();
    p.set_payload(ms(0), payload(&[1]));
    p.set_operational(ms(0), true);
    assert_eq!(
        (p.poll_transmit(), p.poll_timeout()),
        (None, None),
        "not configured"
    );
    p.configure(ms(1), charger_tpdo0().clone_with_cob(0x8000_018A));
    assert_eq!(
        (p.poll_transmit(), p.poll_timeout()),
        (None, None),
        "COB-ID not valid"
    );
    p.set_operational(ms(2), false);
    p.configure(ms(3), charger_tpdo0());
    assert_eq!(
        (p.poll_transmit(), p.poll_timeout()),
        (None, None),
        "not operational"
    );
    p.trigger(ms(4));
    assert_eq!(p.poll_transmit(), None);
    p.set_operational(ms(10), true);
    assert_eq!(p.poll_transmit().map(|f| f.data().to_vec()), Some(vec![1]));
    assert_eq!(p.poll_timeout(), Some(ms(210)));
}

trait CloneWithCob {
    fn clone_with_cob(&self, raw: u32) -> Self;
}
impl CloneWithCob for PdoCommParams {
    fn clone_with_cob(&self, raw: u32) -> Self {
        PdoCommParams {
            cob_id: PdoCobId::from_u32(raw),
            ..*self
        }
    }
}

#[test]
fn event_timer_period() {
    let mut p = TpdoProducer::new();
    p.configure(ms(0), charger_tpdo0());
    p.set_operational(ms(100), true);
    assert_eq!(run(&mut p, 100, 1000), vec![100, 300, 500, 700, 900]);
}

#[test]
fn events_restart_the_event_timer_and_respect_inhibit() {
    let mut comm = charger_tpdo0();
    comm.inhibit_time_100us = 500; // 50 ms
    let mut p = running(ms(0), comm);
    assert!(p.poll_transmit().is_some());
    // A change at 20 ms is inside the inhibit time: deferred to 50 ms.
    p.set_payload(ms(20), payload(&[2]));
    assert_eq!(p.poll_transmit(), None);
    assert_eq!(p.poll_timeout(), Some(ms(50)));
    p.handle_timeout(ms(50));
    assert_eq!(p.poll_transmit().map(|f| f.data().to_vec()), Some(vec![2]));
    // The event timer restarted at 50 ms.
    assert_eq!(p.poll_timeout(), Some(ms(250)));
    // An unchanged payload is not an event.
    p.set_payload(ms(120), payload(&[2]));
    assert_eq!(p.poll_transmit(), None);
    // A trigger after the inhibit time is sent at once.
    p.trigger(ms(130));
    assert!(p.poll_transmit().is_some());
    assert_eq!(run(&mut p, 130, 800), vec![330, 530, 730]);
}

#[test]
fn event_timer_inside_inhibit_is_deferred_not_lost() {
    let mut comm = PdoCommParams::event_driven(PdoCobId::standard(0x18A), 10);
    comm.inhibit_time_100us = 300; // 30 ms > the 10 ms event timer
    let mut p = running(ms(0), comm);
    assert_eq!(run(&mut p, 0, 100), vec![0, 30, 60, 90]);
}

#[test]
fn disabling_stops_and_reenabling_resends() {
    let mut p = running(ms(0), charger_tpdo0());
    assert!(p.poll_transmit().is_some());
    p.configure(ms(50), charger_tpdo0().clone_with_cob(0x8000_018A));
    assert_eq!((p.poll_transmit(), p.poll_timeout()), (None, None));
    p.configure(ms(60), charger_tpdo0());
    assert!(p.poll_transmit().is_some());
    p.set_operational(ms(70), false);
    assert_eq!(p.poll_timeout(), None);
    p.unconfigure();
    p.set_operational(ms(80), true);
    assert_eq!((p.poll_transmit(), p.poll_timeout()), (None, None));
}

#[test]
fn synchronous_types() {
    let mut comm = charger_tpdo0();
    comm.transmission_type = TransmissionType::SynchronousCyclic(3);
    let mut p = running(ms(0), comm);
    assert_eq!((p.poll_transmit(), p.poll_timeout()), (None, None));
    let sync = CanFrame::standard(0x080, &[]).unwrap();
    let mut sent = Vec::new();
    for i in 1..=9u64 {
        // Neither another identifier nor a remote frame is a SYNC.
        p.handle_frame(ms(i), &CanFrame::standard(0x081, &[]).unwrap());
        p.handle_frame(
            ms(i),
            &CanFrame::remote(crate::CanId::Standard(0x080), 0).unwrap(),
        );
        p.handle_frame(ms(i), &sync);
        if p.poll_transmit().is_some() {
            sent.push(i);
        }
    }
    assert_eq!(sent, vec![3, 6, 9]);
    comm.transmission_type = TransmissionType::SynchronousAcyclic;
    p.configure(ms(10), comm);
    p.handle_frame(ms(11), &sync);
    assert_eq!(p.poll_transmit(), None, "no event yet");
    p.set_payload(ms(12), payload(&[9]));
    assert_eq!(p.poll_transmit(), None, "waits for SYNC");
    p.set_sync_id(crate::CanId::Standard(0x090));
    p.handle_frame(ms(13), &sync);
    assert_eq!(p.poll_transmit(), None, "SYNC on 090h now");
    p.handle_frame(ms(13), &CanFrame::standard(0x090, &[1]).unwrap());
    assert_eq!(p.poll_transmit().map(|f| f.data().to_vec()), Some(vec![9]));
}

#[test]
fn time_going_backwards_is_harmless() {
    let mut p = running(ms(1000), charger_tpdo0());
    assert!(p.poll_transmit().is_some());
    p.handle_timeout(ms(10));
    assert_eq!(p.poll_transmit(), None);
    p.handle_timeout(Timestamp::MAX);
    assert!(p.poll_transmit().is_some());
    assert_eq!(
        p.poll_timeout(),
        None,
        "no event timer after the end of time"
    );
}

#[test]
fn an_undrained_frame_carries_the_latest_payload() {
    let mut p = TpdoProducer::new();
    p.set_payload(ms(0), payload(&[1]));
    p.configure(ms(0), charger_tpdo0());
    p.set_operational(ms(0), true);
    // Sent at 0 with [1]; before it is drained the payload changes: one
    // frame, with the new value, and the event timer from the last send.
    p.set_payload(ms(3), payload(&[2]));
    assert_eq!(p.poll_transmit().map(|f| f.data().to_vec()), Some(vec![2]));
    assert_eq!(p.poll_transmit(), None);
    assert_eq!(p.poll_timeout(), Some(ms(203)));
}

/// The timer paths trust that a deadline is only set while active: over
/// a pseudo-random mix of every input (configure valid / not valid /
/// synchronous, unconfigure, operational on and off, payloads, triggers,
/// SYNC, timeouts), an inactive producer never has a deadline nor sends.
#[test]
fn no_deadline_or_frame_while_inactive() {
    let mut p = TpdoProducer::new();
    let mut seed = 0x2545_F491_u32;
    let mut now = 0u64;
    let sync = CanFrame::standard(0x080, &[]).unwrap();
    for step in 0..20_000 {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        now += u64::from(seed % 300);
        let t = ms(now);
        match seed >> 28 {
            0 => p.configure(t, charger_tpdo0()),
            1 => p.configure(t, charger_tpdo0().clone_with_cob(0x8000_018A)),
            2 => p.configure(
                t,
                PdoCommParams {
                    transmission_type: TransmissionType::from_u8((seed >> 8) as u8 % 3).unwrap(),
                    inhibit_time_100us: 50,
                    ..charger_tpdo0()
                },
            ),
            3 => p.unconfigure(),
            4 | 5 => p.set_operational(t, seed & 0x100 != 0),
            6 | 7 => p.set_payload(t, payload(&[(seed >> 8) as u8])),
            8 => p.trigger(t),
            9 | 10 => p.handle_frame(t, &sync),
            _ => p.handle_timeout(t),
        }
        if !p.is_active() {
            assert_eq!(
                p.poll_timeout(),
                None,
                "step {step}: a deadline while inactive"
            );
            p.handle_timeout(ms(now + 1_000_000));
            assert_eq!(
                p.poll_transmit(),
                None,
                "step {step}: a frame while inactive"
            );
        }
        let _ = p.poll_transmit();
    }
}
