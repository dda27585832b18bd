//! The decoder's line cache: real logs repeat themselves (a heartbeat is the
//! same frame every period, a PDO carries the same values for seconds; 83%
//! of the frames of the real Delta-Q captures equal the previous frame on
//! their identifier), so the text after the time column of the last
//! frame on each 11-bit identifier is kept, and a frame equal to it is
//! printed from there.
//!
//! Only frames whose text depends on nothing but the frame and the roles
//! and PDO mappings in force are cached (PDOs, heartbeats that answer no
//! guarding request, EMCY, NMT, SYNC, TIME, unknown identifiers), and
//! [`LineCache::clear`] is called whenever a role or a mapping changes. A
//! test decodes the same log with and without the cache and compares.

use canopen_codec::{CanFrame, CanId};

/// One identifier's last frame and its text.
#[derive(Default, Clone)]
struct Entry {
    used: bool,
    remote: bool,
    data: [u8; 8],
    len: u8,
    text: String,
}

/// The last cacheable frame per standard identifier (2048 slots; 29-bit
/// identifiers are not cached).
pub struct LineCache {
    slots: Vec<Entry>,
    enabled: bool,
}

impl LineCache {
    /// A cache, or one that never hits when `enabled` is false.
    pub fn new(enabled: bool) -> Self {
        LineCache {
            slots: if enabled {
                vec![Entry::default(); 2048]
            } else {
                Vec::new()
            },
            enabled,
        }
    }

    fn slot(&mut self, frame: &CanFrame) -> Option<&mut Entry> {
        if !self.enabled {
            return None;
        }
        let CanId::Standard(id) = frame.id() else {
            return None;
        };
        self.slots.get_mut(usize::from(id))
    }

    /// Appends the cached text of `frame` to `out`; false when there is none.
    pub fn get(&mut self, frame: &CanFrame, out: &mut String) -> bool {
        let remote = frame.is_remote();
        let data = frame.data();
        let Some(e) = self.slot(frame) else {
            return false;
        };
        if !e.used || e.remote != remote || e.data.get(..usize::from(e.len)) != Some(data) {
            return false;
        }
        out.push_str(&e.text);
        true
    }

    /// Keeps `text` as the text of `frame`.
    pub fn put(&mut self, frame: &CanFrame, text: &str) {
        let remote = frame.is_remote();
        let data = frame.data();
        let Some(e) = self.slot(frame) else {
            return;
        };
        e.used = true;
        e.remote = remote;
        e.len = u8::try_from(data.len()).unwrap_or(0);
        if let Some(dst) = e.data.get_mut(..data.len()) {
            dst.copy_from_slice(data);
        }
        e.text.clear();
        e.text.push_str(text);
    }

    /// Forgets every text (a role or a PDO mapping changed).
    pub fn clear(&mut self) {
        for e in &mut self.slots {
            e.used = false;
        }
    }
}
