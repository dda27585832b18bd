//! The decoder's line cache: real logs repeat themselves (a heartbeat is the
//! same frame every period, a PDO carries the same values for seconds; 83%
//! of the frames of the real Delta-Q captures equal the previous frame on
//! their identifier, 94% one of the last four), so the text after the time
//! column of the last four frames on each 11-bit identifier is kept, and a
//! frame equal to one of them is printed from there.
//!
//! Only frames whose text depends on nothing but the frame and the roles
//! and PDO mappings in force are cached (PDOs, heartbeats that answer no
//! guarding request, EMCY, NMT, SYNC, TIME, unknown identifiers), and
//! [`LineCache::clear`] is called whenever a role or a mapping changes. A
//! test decodes the same log with and without the cache and compares.

use crate::{CanFrame, CanId};
use std::prelude::rust_2021::*;

/// Frames kept per identifier: a PDO's values often flicker between a few
/// (on the real Delta-Q captures, one frame per identifier misses 8 593 of
/// 50 000 lines, four miss 2 941).
const WAYS: usize = 4;

/// One frame and its text.
#[derive(Default, Clone)]
struct Entry {
    /// `None`: unused.
    frame: Option<CanFrame>,
    text: String,
}

/// The last `WAYS` (4) cacheable frames per standard identifier, most
/// recently used first (2048 identifiers; 29-bit identifiers are not
/// cached).
pub struct LineCache {
    slots: Vec<[Entry; WAYS]>,
    enabled: bool,
}

impl LineCache {
    /// A cache, or one that never hits when `enabled` is false. Its table
    /// is made by the first frame kept.
    pub fn new(enabled: bool) -> Self {
        LineCache {
            slots: Vec::new(),
            enabled,
        }
    }

    fn slot(&mut self, frame: &CanFrame) -> Option<&mut [Entry; WAYS]> {
        if !self.enabled {
            return None;
        }
        let CanId::Standard(id) = frame.id() else {
            return None;
        };
        if self.slots.is_empty() {
            self.slots.resize_with(2048, Default::default);
        }
        self.slots.get_mut(usize::from(id))
    }

    /// Appends the cached text of `frame` to `out`; false when there is none.
    pub fn get(&mut self, frame: &CanFrame, out: &mut String) -> bool {
        let Some(ways) = self.slot(frame) else {
            return false;
        };
        let Some(k) = ways.iter().position(|e| e.frame.as_ref() == Some(frame)) else {
            return false;
        };
        // Most recently used first.
        if let Some(head) = ways.get_mut(..=k) {
            head.rotate_right(1);
        }
        out.push_str(&ways[0].text);
        true
    }

    /// Keeps `text` as the text of `frame`, in place of the least recently
    /// used frame of its identifier.
    pub fn put(&mut self, frame: &CanFrame, text: &str) {
        let Some(ways) = self.slot(frame) else {
            return;
        };
        ways.rotate_right(1);
        let e = &mut ways[0];
        e.frame = Some(*frame);
        e.text.clear();
        e.text.push_str(text);
    }

    /// Forgets every text (a role or a PDO mapping changed).
    pub fn clear(&mut self) {
        for e in self.slots.iter_mut().flatten() {
            e.frame = None;
        }
    }
}
