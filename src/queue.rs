//! Fixed-capacity FIFOs for the state machines' outputs (no allocation).
//!
//! Every machine queues what it sends in a [`FrameQueue`] and what it
//! reports in an [`EventQueue`]: both are [`DropOldest`], which, when full,
//! drops the oldest item and counts it. That is the back-pressure rule of
//! [`crate::machine`], written once, so it is the same in every machine.
//! [`FrameSlot`] is the frame queue of a machine that makes at most one
//! frame per call (the SDO client and server), with the same rule.

use crate::frame::CanFrame;

/// Up to `N` items, first in first out; `push` fails when full. Slots hold a
/// filler value when empty, so push and pop are plain copies (no `Option`
/// tags to test and rewrite on the hot path). `N` is at most 255: the
/// indexes are bytes (a queue's state is its items and two bytes).
#[derive(Debug, Clone)]
pub(crate) struct Queue<T: Copy, const N: usize> {
    items: [T; N],
    head: u8,
    len: u8,
}

impl<T: Copy, const N: usize> Queue<T, N> {
    /// Refuses, at compile time, a capacity the byte indexes cannot count.
    const CAPACITY_FITS: () = assert!(N <= u8::MAX as usize, "queue capacity over 255");

    /// An empty queue whose free slots hold `filler` (never returned).
    pub(crate) const fn new(filler: T) -> Self {
        let () = Self::CAPACITY_FITS;
        Queue {
            items: [filler; N],
            head: 0,
            len: 0,
        }
    }

    /// The oldest item.
    #[inline]
    pub(crate) fn pop(&mut self) -> Option<T> {
        let slot = take(&mut self.head, &mut self.len, N)?;
        self.items.get(slot).copied()
    }
}

/// Up to `N` items, first in first out; pushing onto a full queue drops
/// the oldest item and counts it, so the newest (a transfer's terminal
/// event, the latest answer) are always kept.
#[derive(Debug, Clone)]
pub(crate) struct DropOldest<T: Copy, const N: usize> {
    queue: Queue<T, N>,
    /// Saturating at `u32::MAX`, as the contract says.
    dropped: u32,
}

impl<T: Copy, const N: usize> DropOldest<T, N> {
    /// An empty queue (`filler` is never returned).
    pub(crate) const fn new(filler: T) -> Self {
        DropOldest {
            queue: Queue::new(filler),
            dropped: 0,
        }
    }

    /// Appends `event`; when full, the oldest event is dropped and counted.
    ///
    /// The index arithmetic is [`claim_evicting`], which does not depend
    /// on `T`: one routine serves every queue.
    #[inline]
    pub(crate) fn push(&mut self, event: T) {
        let q = &mut self.queue;
        let slot = claim_evicting(&mut q.head, &mut q.len, N, &mut self.dropped);
        if let Some(item) = q.items.get_mut(slot) {
            *item = event;
        }
    }

    /// The oldest event.
    #[inline]
    pub(crate) fn pop(&mut self) -> Option<T> {
        self.queue.pop()
    }

    /// Events dropped so far (saturating at `u32::MAX`).
    #[inline]
    pub(crate) const fn dropped(&self) -> u64 {
        self.dropped as u64
    }
}

/// A machine's events: the oldest dropped and counted when full.
pub(crate) type EventQueue<T, const N: usize> = DropOldest<T, N>;

/// A machine's frames to send: the oldest dropped and counted when full
/// (a caller that drains [`Machine::poll_transmit`](crate::machine::Machine::poll_transmit)
/// after every call never loses one).
pub(crate) type FrameQueue<const N: usize> = DropOldest<CanFrame, N>;

impl<const N: usize> DropOldest<CanFrame, N> {
    /// An empty frame queue.
    pub(crate) const fn empty() -> Self {
        Self::new(CanFrame::EMPTY)
    }
}

/// The slot of a [`Queue`]'s oldest item, with `head` and `len` moved past
/// it; none when empty.
#[inline(never)]
fn take(head: &mut u8, len: &mut u8, cap: usize) -> Option<usize> {
    if *len == 0 || cap == 0 {
        return None;
    }
    let slot = usize::from(*head);
    // Both below 256: `cap` is at most 255 (`Queue::CAPACITY_FITS`).
    *head = ((slot + 1) % cap) as u8;
    *len -= 1;
    Some(slot)
}

/// The slot an [`EventQueue`] of capacity `cap` stores its next event in,
/// with `head` and `len` updated for it: when full, the oldest slot is
/// given up and counted in `dropped`. Capacity 0 returns an index past
/// the end (nothing is stored) and counts the event as dropped.
#[inline(never)]
fn claim_evicting(head: &mut u8, len: &mut u8, cap: usize, dropped: &mut u32) -> usize {
    if cap == 0 {
        *dropped = dropped.saturating_add(1);
        return usize::MAX;
    }
    if usize::from(*len) >= cap {
        // Both below 256: `cap` is at most 255 (`Queue::CAPACITY_FITS`).
        *head = ((usize::from(*head) + 1) % cap) as u8;
        *len -= 1;
        *dropped = dropped.saturating_add(1);
    }
    let slot = (usize::from(*head) + usize::from(*len)) % cap;
    *len += 1;
    slot
}

/// The transmit queue of a machine that makes at most one frame per call
/// (the SDO client and server): one frame; pushing onto a full slot drops
/// the older frame and counts it, as [`EventQueue`] does.
#[derive(Debug, Clone)]
pub(crate) struct FrameSlot {
    frame: CanFrame,
    full: bool,
    /// Saturating, as [`EventQueue`]'s.
    dropped: u32,
}

impl FrameSlot {
    /// An empty slot.
    pub(crate) const fn new() -> Self {
        FrameSlot {
            frame: CanFrame::EMPTY,
            full: false,
            dropped: 0,
        }
    }

    /// Queues `frame`; an unsent older frame is dropped and counted.
    #[inline]
    pub(crate) fn push(&mut self, frame: CanFrame) {
        if self.full {
            self.dropped = self.dropped.saturating_add(1);
        }
        self.frame = frame;
        self.full = true;
    }

    /// The queued frame.
    #[inline]
    pub(crate) fn pop(&mut self) -> Option<CanFrame> {
        if !self.full {
            return None;
        }
        self.full = false;
        Some(self.frame)
    }

    /// Frames dropped so far (saturating at `u32::MAX`).
    #[inline]
    pub(crate) const fn dropped(&self) -> u64 {
        self.dropped as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fifo_order_below_capacity() {
        let mut q: FrameQueue<3> = FrameQueue::empty();
        let f = |b: u8| CanFrame::standard(0x100, &[b]).unwrap();
        q.push(f(1));
        q.push(f(2));
        assert_eq!((q.pop(), q.pop(), q.pop()), (Some(f(1)), Some(f(2)), None));
        q.push(f(3));
        q.push(f(4));
        q.push(f(5));
        q.push(f(6));
        assert_eq!(q.dropped(), 1);
        assert_eq!(
            (q.pop(), q.pop(), q.pop(), q.pop()),
            (Some(f(4)), Some(f(5)), Some(f(6)), None)
        );
    }

    #[test]
    fn event_queue_drops_oldest_and_counts() {
        let mut q: EventQueue<u8, 2> = EventQueue::new(0);
        q.push(1);
        q.push(2);
        assert_eq!(q.dropped(), 0);
        q.push(3);
        q.push(4);
        assert_eq!(q.dropped(), 2);
        assert_eq!((q.pop(), q.pop(), q.pop()), (Some(3), Some(4), None));
        q.push(5);
        assert_eq!((q.pop(), q.dropped()), (Some(5), 2));
        // Wrapping around many times keeps the newest two, in order.
        for v in 6..=40 {
            q.push(v);
        }
        assert_eq!((q.pop(), q.pop(), q.pop()), (Some(39), Some(40), None));
        assert_eq!(q.dropped(), 2 + 33);
    }

    #[test]
    fn event_queue_of_capacity_zero_drops_everything() {
        let mut q: EventQueue<u8, 0> = EventQueue::new(0);
        q.push(1);
        q.push(2);
        assert_eq!((q.pop(), q.dropped()), (None, 2));
    }

    #[test]
    fn byte_indexes_serve_the_largest_capacity() {
        let mut q: DropOldest<u16, 255> = DropOldest::new(0);
        for round in 0..3u16 {
            for v in 0..255 {
                q.push(round * 1000 + v);
            }
            assert_eq!(q.dropped(), 0);
            for v in 0..255 {
                assert_eq!(q.pop(), Some(round * 1000 + v));
            }
            assert_eq!(q.pop(), None);
        }
        let mut e: EventQueue<u16, 255> = EventQueue::new(0);
        for v in 0..600 {
            e.push(v);
        }
        assert_eq!((e.pop(), e.dropped()), (Some(600 - 255), 600 - 255));
    }

    #[test]
    fn drop_counters_saturate() {
        let mut e: EventQueue<u8, 1> = EventQueue::new(0);
        e.dropped = u32::MAX - 1;
        e.push(1);
        e.push(2);
        e.push(3);
        assert_eq!((e.pop(), e.dropped()), (Some(3), u64::from(u32::MAX)));
        let mut f = FrameSlot::new();
        f.dropped = u32::MAX;
        f.push(CanFrame::EMPTY);
        f.push(CanFrame::EMPTY);
        assert_eq!(f.dropped(), u64::from(u32::MAX));
    }

    #[test]
    fn frame_slot_keeps_the_newest_and_counts() {
        let a = CanFrame::standard(0x601, &[0x40, 0x00, 0x20]).unwrap();
        let b = CanFrame::standard(0x601, &[0x60]).unwrap();
        let mut q = FrameSlot::new();
        assert_eq!(q.pop(), None);
        q.push(a);
        assert_eq!((q.pop(), q.pop(), q.dropped()), (Some(a), None, 0));
        q.push(a);
        q.push(b);
        assert_eq!((q.pop(), q.pop(), q.dropped()), (Some(b), None, 1));
    }
}
