//! What `canopen-replay` makes of a recording: every frame of a trace
//! (read by [`crate::log::input`], the decoder's reader) with its time,
//! split into the frames of the played nodes (sent to the device under
//! test) and the rest (what the device should send), and, in [`diff`],
//! each side's traffic summarised and the device's compared with the
//! recording's. [`player`] plays the recording into a device on the
//! caller's clock (sans-IO); the device's pipe and the wall clock stay in
//! the program (`src/bin/canopen-replay/`).

pub mod diff;
pub mod player;

use std::prelude::rust_2021::*;

use std::collections::BTreeSet;

use crate::{CanFrame, CanId};

use crate::log::input::{Frames, Kind};

/// One recorded frame; `t` is microseconds since the recording's first frame.
#[derive(Clone, Copy)]
pub struct Recorded {
    /// Microseconds since the recording's first frame.
    pub t: u64,
    /// The frame.
    pub frame: CanFrame,
}

/// The recording split into what the replay sends and what it expects.
pub struct Recording {
    /// The played nodes' frames (and NMT, SYNC, TIME), to send.
    pub played: Vec<Recorded>,
    /// The other frames: what the device under test should send.
    pub expected: Vec<Recorded>,
    /// The time of the recording's last frame.
    pub end: u64,
}

/// The node a frame is addressed to or sent by, by the CiA 301
/// pre-defined connection set (CiA 301 section 7.3.5): `(node, to_node)`.
/// RPDOs (200h/300h/400h/500h + node), SDO requests (600h + node) and NMT
/// commands are sent *to* a node; everything else is sent *by* the node
/// its COB-ID carries. SYNC, TIME and broadcast NMT name no node.
pub fn addressing(frame: &CanFrame) -> Option<(u8, bool)> {
    let CanId::Standard(id) = frame.id() else {
        return None;
    };
    let node = (id & 0x7F) as u8;
    match id & 0x780 {
        0x000 => frame
            .data()
            .get(1)
            .copied()
            .filter(|n| *n != 0)
            .map(|n| (n, true)),
        _ if node == 0 => None,
        0x200 | 0x300 | 0x400 | 0x500 | 0x600 => Some((node, true)),
        _ => Some((node, false)),
    }
}

/// Whether the played side sent `frame`: a frame sent by a played node, or
/// addressed to a node that is not played; SYNC, TIME and broadcast NMT go
/// with the played side.
pub fn is_played(frame: &CanFrame, play: &BTreeSet<u8>) -> bool {
    match addressing(frame) {
        None => true,
        Some((node, to_node)) => play.contains(&node) != to_node,
    }
}

/// The recording of a trace's frames (read by the decoder's reader, any
/// format). A frame without a time is an error, and so is a trace with no
/// frame (which says how it was read and its first unreadable line);
/// unreadable lines or objects beside frames are said on stderr.
pub fn of(read: &Frames, play: &BTreeSet<u8>) -> Result<Recording, String> {
    let totals = read.totals;
    let first_bad = read
        .first_bad
        .as_deref()
        .map(|b| format!("; the first: {b}"))
        .unwrap_or_default();
    if read.frames.is_empty() {
        let hint = match totals.kind {
            Kind::Lines { .. } => "; --format names one",
            Kind::Binary { .. } => "",
        };
        return Err(format!(
            "the trace has no frames ({} unreadable {}, {}{hint}{first_bad})",
            totals.bad,
            totals.kind.units(),
            totals.kind
        ));
    }
    let mut frames = Vec::with_capacity(read.frames.len());
    let mut first = None;
    for f in &read.frames {
        let Some(ts) = f.timestamp else {
            return Err(format!("{}: a frame without a time", f.at));
        };
        let us = ts.as_micros();
        let base = *first.get_or_insert(us);
        frames.push(Recorded {
            t: us.saturating_sub(base),
            frame: f.frame,
        });
    }
    if totals.bad > 0 {
        eprintln!(
            "canopen-replay: {} unreadable {} skipped{first_bad}",
            totals.bad,
            totals.kind.units()
        );
    }
    if let Some(first) = &read.first_unsupported {
        eprintln!(
            "canopen-replay: {} {} not replayed (CAN FD or error frames, other events); the first: {first}",
            totals.unsupported,
            totals.kind.units()
        );
    }
    let end = frames.iter().map(|r| r.t).max().unwrap_or(0);
    let (played, expected) = frames.into_iter().partition(|r| is_played(&r.frame, play));
    Ok(Recording {
        played,
        expected,
        end,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::frame::standard_frame as f;

    #[test]
    fn sides_follow_the_predefined_connection_set() {
        let battery: BTreeSet<u8> = [1].into();
        assert!(is_played(&f(0x701, &[5]), &battery));
        assert!(is_played(&f(0x20A, &[0; 8]), &battery));
        assert!(is_played(&f(0x000, &[1, 10]), &battery));
        assert!(!is_played(&f(0x18A, &[0; 8]), &battery));
        assert!(!is_played(&f(0x08A, &[0; 8]), &battery));
        assert!(!is_played(
            &f(0x601, &[0x40, 0, 0x10, 0, 0, 0, 0, 0]),
            &battery
        ));
        let charger: BTreeSet<u8> = [10].into();
        assert!(!is_played(&f(0x000, &[1, 10]), &charger));
        assert!(!is_played(&f(0x20A, &[0; 8]), &charger));
        assert!(is_played(&f(0x080, &[]), &charger));
    }

    fn read(text: &str, play: &BTreeSet<u8>) -> Result<Recording, String> {
        let frames = crate::log::input::frames(
            text.as_bytes(),
            Default::default(),
            &mut crate::log::input::NoInflate,
        )
        .unwrap();
        of(&frames, play)
    }

    #[test]
    fn times_are_relative_and_an_empty_trace_is_an_error() {
        let text = "(100.5) can0 701#05\n(101.0) can0 18A#00\n";
        let r = read(text, &[1].into()).unwrap();
        assert_eq!(r.end, 500_000);
        assert_eq!(r.played[0].t, 0);
        assert_eq!(r.expected[0].t, 500_000);
        assert_eq!(
            read("nothing here\n", &[1].into()).err().as_deref(),
            Some(
                "the trace has no frames (1 unreadable line(s), no format detected; \
                 --format names one; the first: line 1: the line does not match any known trace format: nothing here)"
            )
        );
        assert_eq!(
            read("  can0  18A   [1]  01\n", &[1].into())
                .err()
                .as_deref(),
            Some("line 1: a frame without a time")
        );
    }
}
