//! The passive [`Observer`] fed the frames of a simulated run: every frame
//! that reached the machines, in the order and at the time it arrived
//! (a duplicated frame twice), then the end of the trace. The checks
//! compare what it reports with what the client and the server saw.

use canopen_codec::machine::Machine;
use canopen_codec::sdo::{AbortCode, Observer, ObserverEvent, Side};

use super::sim::{Bus, Fate};

/// What the observer made of a run.
#[derive(Debug, Default)]
pub struct Observed {
    /// Every event, in order.
    pub events: Vec<ObserverEvent>,
    /// Some frame reached the machines twice.
    pub repeated_frames: bool,
}

impl Observed {
    fn is_of(e: &ObserverEvent, object: (u16, u8)) -> bool {
        match e {
            ObserverEvent::Started(t)
            | ObserverEvent::Completed { transfer: t, .. }
            | ObserverEvent::Aborted { transfer: t, .. }
            | ObserverEvent::BrokenOff { transfer: t, .. } => (t.index, t.sub) == object,
            _ => false,
        }
    }

    /// The terminal events of transfers of `object`.
    pub fn ends(&self, object: (u16, u8)) -> Vec<ObserverEvent> {
        self.events
            .iter()
            .copied()
            .filter(|e| e.is_terminal() && Self::is_of(e, object))
            .collect()
    }

    /// The transfers of `object` started.
    pub fn started(&self, object: (u16, u8)) -> usize {
        self.events
            .iter()
            .filter(|e| matches!(e, ObserverEvent::Started(_)) && Self::is_of(e, object))
            .count()
    }

    /// The value the data events of the last transfer of `object` carried
    /// (checked to come in order, without gaps).
    pub fn value(&self, object: (u16, u8)) -> Vec<u8> {
        let mut value = Vec::new();
        let mut current = false;
        for e in &self.events {
            match e {
                ObserverEvent::Started(_) => {
                    current = Self::is_of(e, object);
                    if current {
                        value.clear();
                    }
                }
                ObserverEvent::Data { offset, data, .. } if current => {
                    assert_eq!(*offset, value.len(), "observer data out of order");
                    value.extend_from_slice(data.as_slice());
                }
                _ => {}
            }
        }
        value
    }
}

/// Replays the frames of `sim` (delivered `latency_us` after sending)
/// through an observer, draining it after every frame.
pub fn replay(sim: &Bus, latency_us: u64) -> Observed {
    let mut obs = Observer::default();
    let mut seen = Observed::default();
    let take = |obs: &mut Observer, seen: &mut Observed| {
        while let Some(e) = obs.poll_event() {
            seen.events.push(e);
        }
    };
    for sent in sim.log() {
        let copies = match sent.fate {
            Fate::Delivered => 1,
            Fate::Duplicated => 2,
            _ => continue,
        };
        // Replayed in send order: a delayed (reordered) frame would be
        // out of place; tests that delay frames watch at the receiver.
        assert!(sent.delay.is_zero(), "replay of a delayed frame");
        seen.repeated_frames |= copies == 2;
        let at = sent.at.add_micros(latency_us);
        for _ in 0..copies {
            obs.handle_timeout(at);
            take(&mut obs, &mut seen);
            obs.handle_frame(at, &sent.frame);
            take(&mut obs, &mut seen);
        }
    }
    while let Some(e) = obs.end_of_trace() {
        seen.events.push(e);
    }
    assert_eq!(obs.events_dropped(), 0, "observer events dropped");
    seen
}

/// The abort frames that reached the machines, with their sender's side
/// (`client` is the client's name in the sim).
pub fn aborts_on_the_bus(sim: &Bus, client: &str) -> Vec<(Side, AbortCode)> {
    sim.log()
        .iter()
        .filter(|s| s.fate.reached_the_bus() && s.frame.data().first() == Some(&0x80))
        .filter_map(|s| {
            let code = canopen_codec::sdo::abort_code_of(s.frame.data())?;
            let side = if s.from == client {
                Side::Client
            } else {
                Side::Server
            };
            Some((side, code))
        })
        .collect()
}

/// The checks for one transfer of `value` to or from `object` that the
/// client and the server ended (`both_completed` when both report success):
///
/// - the observer ended each transfer of the object it started, once;
/// - the last one completed exactly when both sides did, with every byte
///   of `value`;
/// - an abort it reports is one that was on the bus, from that side;
/// - whatever the end, the bytes it delivered are the start of `value`.
pub fn check_one_transfer(
    seen: &Observed,
    object: (u16, u8),
    value: &[u8],
    both_completed: bool,
    aborts: &[(Side, AbortCode)],
) {
    let ends = seen.ends(object);
    let Some(last) = ends.last() else {
        // The initiate never reached the bus's machines: nothing started.
        assert_eq!(seen.started(object), 0, "{:?}", seen.events);
        assert!(!both_completed, "both completed unseen: {:?}", seen.events);
        return;
    };
    assert_eq!(
        ends.len(),
        seen.started(object),
        "starts and ends differ: {:?}",
        seen.events
    );
    let delivered = seen.value(object);
    match *last {
        ObserverEvent::Completed { bytes, .. } => {
            assert!(
                both_completed,
                "observer completed, a side did not: {:?}",
                seen.events
            );
            assert_eq!(bytes, value.len());
            assert_eq!(delivered, value);
        }
        ObserverEvent::Aborted { code, by, .. } => {
            assert!(
                aborts.contains(&(by, code)),
                "observer abort {by:?} {code:?} not on the bus {aborts:?}"
            );
        }
        ObserverEvent::BrokenOff { .. } => {
            assert!(
                !both_completed,
                "both completed, observer broke off: {:?}",
                seen.events
            );
        }
        e => panic!("{e:?}"),
    }
    // With repeated frames a receiver can take segments at the wrong place
    // until the CRC or the size tells (CiA 301 does not number sub-blocks);
    // the observer takes what the receiver took.
    assert!(
        seen.repeated_frames || value.starts_with(&delivered),
        "observer delivered bytes that were not sent: first difference at {:?}, ends {:?}",
        delivered.iter().zip(value).position(|(a, b)| a != b),
        ends
    );
}
