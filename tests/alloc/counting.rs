//! The counting allocator of this test binary: it wraps `System` and
//! counts, per thread, every `alloc`, `alloc_zeroed` and `realloc` (one
//! call each) and the bytes live and at their peak. The counters are
//! thread-local, so the test harness's other threads, running the other
//! tests of this binary, cannot disturb a measurement.
//!
//! The bytes count a `realloc` as the default `GlobalAlloc::realloc` would
//! (the new block allocated while the old one is still live, then the old
//! one freed), so the peak is the same figure as with that default.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

std::thread_local! {
    static CALLS: Cell<u64> = const { Cell::new(0) };
    /// Bytes allocated minus bytes freed on this thread (signed: a block
    /// may be freed on another thread than the one that allocated it).
    static LIVE: Cell<i64> = const { Cell::new(0) };
    static PEAK: Cell<i64> = const { Cell::new(0) };
}

fn bytes(n: usize) -> i64 {
    i64::try_from(n).unwrap_or(i64::MAX)
}

/// One allocation call of `size` bytes (freeing `freed` bytes after it).
fn allocated(size: usize, freed: usize) {
    // `try_with`: the slots may already be gone while a thread shuts down.
    let _ = CALLS.try_with(|c| c.set(c.get() + 1));
    let _ = LIVE.try_with(|live| {
        let now = live.get().wrapping_add(bytes(size));
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(now)));
        live.set(now.wrapping_sub(bytes(freed)));
    });
}

fn freed(size: usize) {
    let _ = LIVE.try_with(|live| live.set(live.get().wrapping_sub(bytes(size))));
}

// SAFETY: every call is forwarded unchanged to `System`; counting does not
// allocate (a const-initialised thread-local `Cell` needs no heap).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        allocated(layout.size(), 0);
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        allocated(layout.size(), 0);
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        allocated(new_size, layout.size());
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        freed(layout.size());
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// How many allocation calls this thread has made.
pub fn allocations() -> u64 {
    CALLS.with(Cell::get)
}

/// Bytes this thread has allocated and not freed.
#[cfg(feature = "alloc")] // eds_alloc
pub fn live_bytes() -> i64 {
    LIVE.with(Cell::get)
}

/// The most bytes live on this thread since the last [`reset_peak`].
#[cfg(feature = "alloc")] // eds_alloc
pub fn peak_bytes() -> i64 {
    PEAK.with(Cell::get)
}

/// Starts a new peak from the bytes live now.
#[cfg(feature = "alloc")] // eds_alloc
pub fn reset_peak() {
    PEAK.with(|p| p.set(live_bytes()));
}
