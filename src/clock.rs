//! Caller-supplied time.
//!
//! The crate never reads a clock. Every frame and every timeout call comes
//! with a [`Timestamp`]: microseconds on a monotonic clock of the caller's
//! choosing (the epoch does not matter, only differences do). All arithmetic
//! saturates, so a clock that jumps backwards or far ahead never panics: a
//! duration "since" a later instant is zero, and adding past `u64::MAX`
//! stays at `u64::MAX`.

use core::fmt;
use core::marker::PhantomData;
use core::time::Duration;

/// An instant in microseconds on the caller's monotonic clock.
///
/// ```
/// use canopen_codec::Timestamp;
/// let t = Timestamp::from_millis(1500);
/// assert_eq!(t.as_micros(), 1_500_000);
/// assert_eq!(t.add_millis(500), Timestamp::from_millis(2000));
/// // Saturating: a later instant minus an earlier one is never negative.
/// assert_eq!(Timestamp::ZERO.saturating_micros_since(t), 0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Timestamp(u64);

impl Timestamp {
    /// Time zero: where simulated clocks start.
    pub const ZERO: Timestamp = Timestamp(0);
    /// The latest representable instant ("never").
    pub const MAX: Timestamp = Timestamp(u64::MAX);

    /// From microseconds.
    #[must_use]
    pub const fn from_micros(us: u64) -> Self {
        Timestamp(us)
    }

    /// From milliseconds (saturating).
    #[must_use]
    pub const fn from_millis(ms: u64) -> Self {
        Timestamp(ms.saturating_mul(1000))
    }

    /// Microseconds since the caller's epoch.
    #[must_use]
    pub const fn as_micros(self) -> u64 {
        self.0
    }

    /// Whole milliseconds since the caller's epoch.
    #[must_use]
    pub const fn as_millis(self) -> u64 {
        self.0 / 1000
    }

    /// `self + us`, saturating at [`Timestamp::MAX`].
    #[must_use]
    #[inline(never)]
    pub const fn add_micros(self, us: u64) -> Self {
        Timestamp(self.0.saturating_add(us))
    }

    /// `self + ms` milliseconds, saturating at [`Timestamp::MAX`].
    #[must_use]
    pub const fn add_millis(self, ms: u64) -> Self {
        self.add_micros(ms.saturating_mul(1000))
    }

    /// The deadline of a timer that runs `us` from `self`, or `None` when
    /// that is not before the end of the clock ([`Timestamp::MAX`]) or not
    /// later than `self` (`us` zero). A periodic timer re-armed at the end
    /// of the clock would otherwise be due again at once, for ever (and a
    /// timer table keeps a deadline at the end as the microsecond before
    /// it, see [`Timers::set`]); this way a far-ahead timestamp expires it
    /// once, as the state-machine contract says, and a period that would
    /// end past the clock does not start.
    #[must_use]
    #[inline(never)]
    pub(crate) const fn deadline_after(self, us: u64) -> Option<Timestamp> {
        match self.0.checked_add(us) {
            Some(at) if at > self.0 && at != u64::MAX => Some(Timestamp(at)),
            _ => None,
        }
    }

    /// The next due time of a periodic timer of `us` that was due at
    /// `self` and ran at `now`: a period after the due time while that is
    /// still ahead of `now` (a late call does not make the period drift),
    /// else a period from `now` (a call more than a period late); none at
    /// the end of the clock.
    #[must_use]
    pub(crate) const fn next_period(self, now: Timestamp, us: u64) -> Option<Timestamp> {
        match self.deadline_after(us) {
            Some(next) if next.0 > now.0 => Some(next),
            _ => now.deadline_after(us),
        }
    }

    /// `self + d`, saturating at [`Timestamp::MAX`] (sub-microsecond parts are dropped).
    #[must_use]
    pub fn add_duration(self, d: Duration) -> Self {
        let us = micros_of(d);
        self.add_micros(us)
    }

    /// Microseconds from `earlier` to `self`; zero if `earlier` is later.
    #[must_use]
    pub const fn saturating_micros_since(self, earlier: Timestamp) -> u64 {
        self.0.saturating_sub(earlier.0)
    }

    /// Time from `earlier` to `self`; zero if `earlier` is later.
    #[must_use]
    pub const fn saturating_duration_since(self, earlier: Timestamp) -> Duration {
        Duration::from_micros(self.saturating_micros_since(earlier))
    }

    /// True once `self` has reached `deadline`.
    #[must_use]
    #[inline]
    pub const fn has_reached(self, deadline: Timestamp) -> bool {
        self.0 >= deadline.0
    }
}

impl fmt::Display for Timestamp {
    /// Seconds with microsecond precision, as candump prints them.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{:06}", self.0 / 1_000_000, self.0 % 1_000_000)
    }
}

/// The timers of one machine, named by the machine's own enum: each
/// variant is a slot of its [`Timers`] table. Implement it with the
/// variants numbered from 0 (`self as usize`) and `COUNT` their number;
/// [`Timers::new`] refuses, at compile time, a table whose size is not
/// `COUNT`.
///
/// ```
/// use canopen_codec::clock::{TimerKind, Timers};
/// use canopen_codec::Timestamp;
///
/// #[derive(Debug, Clone, Copy, PartialEq, Eq)]
/// enum Timer {
///     Request,
///     Response,
/// }
/// impl TimerKind for Timer {
///     const COUNT: usize = 2;
///     fn index(self) -> usize {
///         self as usize
///     }
/// }
///
/// let mut t: Timers<Timer, 2> = Timers::new();
/// t.set(Timer::Request, Some(Timestamp::from_millis(30)));
/// t.set(Timer::Response, Some(Timestamp::from_millis(10)));
/// assert_eq!(t.next(), Some(Timestamp::from_millis(10)));
/// assert!(!t.expire(Timer::Request, Timestamp::from_millis(20)));
/// assert!(t.expire(Timer::Response, Timestamp::from_millis(20)));
/// assert_eq!(t.next(), Some(Timestamp::from_millis(30)));
/// ```
pub trait TimerKind: Copy {
    /// How many timers the machine has: the size of its table.
    const COUNT: usize;
    /// The slot of this timer, below [`COUNT`](Self::COUNT).
    fn index(self) -> usize;
}

/// A machine's timers in one fixed table, indexed by its [`TimerKind`]
/// enum: each slot holds one deadline or none, and [`Timers::next`] is the
/// earliest, which is what the machine's `poll_timeout` returns. No
/// allocation. "None" is one value for every machine (a stopped slot), so
/// no machine keeps a deadline of its own in another form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Timers<K, const N: usize> {
    deadlines: [MaybeTimestamp; N],
    kind: PhantomData<K>,
}

impl<K: TimerKind, const N: usize> Default for Timers<K, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<K: TimerKind, const N: usize> Timers<K, N> {
    /// The table's size is the number of timers the enum names.
    const SIZE_MATCHES: () = assert!(K::COUNT == N, "Timers<K, N>: N is not K::COUNT");

    /// Every timer stopped.
    #[must_use]
    pub const fn new() -> Self {
        let () = Self::SIZE_MATCHES;
        Timers {
            deadlines: [MaybeTimestamp::NONE; N],
            kind: PhantomData,
        }
    }

    /// Arms (`Some`) or stops (`None`) `timer`. A deadline at
    /// [`Timestamp::MAX`] is kept one microsecond earlier (the end of the
    /// clock is the table's "none"): it still expires once at the end of
    /// the clock, as every running timer does.
    #[inline]
    pub fn set(&mut self, timer: K, deadline: Option<Timestamp>) {
        set_slot(&mut self.deadlines, timer.index(), deadline);
    }

    /// The deadline of `timer`.
    #[must_use]
    #[inline]
    pub fn get(&self, timer: K) -> Option<Timestamp> {
        self.deadlines.get(timer.index()).and_then(|d| d.get())
    }

    /// True (and the timer stopped) when `timer` is armed and `now` has
    /// reached its deadline.
    #[inline]
    pub fn expire(&mut self, timer: K, now: Timestamp) -> bool {
        expire_slot(&mut self.deadlines, timer.index(), now)
    }

    /// The step of a periodic producer (the heartbeat producer, CiA 301
    /// section 7.2.8.3.2.2; the SYNC producer, section 7.2.5): true when
    /// `timer` is armed and `now` has reached its deadline, and the timer
    /// then re-armed for the next one ([`Timestamp::next_period`]: one
    /// `period_us` after the deadline just due, so a late call does not
    /// make the period drift, or one period from `now` when the call is
    /// more than a period late). False, nothing changed, otherwise.
    #[inline]
    pub(crate) fn periodic(&mut self, timer: K, now: Timestamp, period_us: u64) -> bool {
        let Some(due) = self.get(timer) else {
            return false;
        };
        if !now.has_reached(due) {
            return false;
        }
        self.set(timer, due.next_period(now, period_us));
        true
    }

    /// Stops every timer.
    pub fn clear(&mut self) {
        self.deadlines = [MaybeTimestamp::NONE; N];
    }

    /// The earliest armed deadline.
    #[must_use]
    #[inline]
    pub fn next(&self) -> Option<Timestamp> {
        earliest_slot(&self.deadlines)
    }
}

// The table's work, once for every machine's table (a firmware carries
// one copy, not one per timer enum): slot `i` of `slots`.

#[inline(never)]
fn set_slot(slots: &mut [MaybeTimestamp], i: usize, deadline: Option<Timestamp>) {
    if let Some(d) = slots.get_mut(i) {
        *d = MaybeTimestamp::new(deadline);
    }
}

#[inline(never)]
fn expire_slot(slots: &mut [MaybeTimestamp], i: usize, now: Timestamp) -> bool {
    match slots.get_mut(i) {
        // A stopped timer holds u64::MAX, which `now` reaches only when
        // it is u64::MAX itself: excluded by the first test.
        Some(d) if d.0 != u64::MAX && now.0 >= d.0 => {
            *d = MaybeTimestamp::NONE;
            true
        }
        _ => false,
    }
}

#[inline(never)]
fn earliest_slot(slots: &[MaybeTimestamp]) -> Option<Timestamp> {
    // Stopped timers hold u64::MAX, so the plain minimum is the answer.
    slots
        .iter()
        .fold(MaybeTimestamp::NONE, |m, d| m.min(*d))
        .get()
}

/// The earliest of `deadlines` (`None` where none is armed): the one way
/// every machine of the crate combines deadlines. A machine answers
/// [`Machine::poll_timeout`](crate::machine::Machine::poll_timeout) with
/// its own [`Timers::next`] alone, or, when it owns other machines, with
/// this over theirs and its own:
/// `earliest([self.client.poll_timeout(), self.timers.next()])`. A
/// deadline is kept as given (no saturation, no rounding); an empty input
/// or one of `None`s only is `None`.
///
/// ```
/// use canopen_codec::clock::earliest;
/// use canopen_codec::Timestamp;
///
/// let (a, b) = (Timestamp::from_millis(30), Timestamp::from_millis(10));
/// assert_eq!(earliest([Some(a), None, Some(b)]), Some(b));
/// assert_eq!(earliest([None, None]), None);
/// // Any iterator: a table of machines.
/// assert_eq!(earliest([Some(a), Some(b)].iter().copied().filter(|d| *d != Some(b))), Some(a));
/// ```
#[must_use]
#[inline]
pub fn earliest(deadlines: impl IntoIterator<Item = Option<Timestamp>>) -> Option<Timestamp> {
    deadlines
        .into_iter()
        .fold(None, |first, d| match (first, d) {
            (Some(f), Some(t)) if t.0 < f.0 => d,
            (None, _) => d,
            _ => first,
        })
}

/// Declares a machine's timer enum and its [`TimerKind`] (variants
/// numbered from 0, `COUNT` their number).
macro_rules! timer_kind {
    ($(#[$meta:meta])* $vis:vis enum $name:ident { $($(#[$vmeta:meta])* $variant:ident),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        $vis enum $name {
            $($(#[$vmeta])* $variant),+
        }
        impl $crate::clock::TimerKind for $name {
            const COUNT: usize = [$(stringify!($variant)),+].len();
            #[inline]
            fn index(self) -> usize {
                self as usize
            }
        }
    };
}
pub(crate) use timer_kind;

/// An optional [`Timestamp`], the one "none" of every timer: `u64::MAX` means none, so
/// [`Timestamp::MAX`] itself is kept as the microsecond before it. For the
/// timer tables and the "last seen" instants of the machines: a deadline
/// at the end of the clock still expires there (a microsecond early), and
/// an instant seen at the end of the clock is still an instant.
///
/// Aligned to 4 bytes, so a machine's state that otherwise has 4-byte
/// fields keeps that alignment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(C, packed(4))]
pub(crate) struct MaybeTimestamp(u64);

impl MaybeTimestamp {
    /// None.
    pub(crate) const NONE: MaybeTimestamp = MaybeTimestamp(u64::MAX);

    /// `t` kept (`Timestamp::MAX` as the microsecond before it).
    #[must_use]
    #[inline(never)]
    pub(crate) const fn new(t: Option<Timestamp>) -> Self {
        match t {
            Some(Timestamp(u64::MAX)) => MaybeTimestamp(u64::MAX - 1),
            Some(t) => MaybeTimestamp(t.0),
            None => Self::NONE,
        }
    }

    /// The earlier of `self` and `other` (none is later than any instant):
    /// one 64-bit comparison, as none is `u64::MAX`.
    #[must_use]
    #[inline]
    pub(crate) const fn min(self, other: MaybeTimestamp) -> Self {
        if other.0 < self.0 {
            other
        } else {
            self
        }
    }

    /// The instant, if any.
    #[must_use]
    #[inline]
    pub(crate) const fn get(self) -> Option<Timestamp> {
        if self.0 == u64::MAX {
            None
        } else {
            Some(Timestamp(self.0))
        }
    }
}

impl Default for MaybeTimestamp {
    fn default() -> Self {
        Self::NONE
    }
}

/// `d` in whole microseconds, saturating at `u64::MAX`: what
/// `u64::try_from(d.as_micros())` gives, in 64-bit arithmetic.
#[must_use]
#[inline(never)]
pub(crate) fn micros_of(d: Duration) -> u64 {
    d.as_secs()
        .saturating_mul(1_000_000)
        .saturating_add(u64::from(d.subsec_micros()))
}

/// `d` in whole milliseconds, saturating at `u64::MAX` (as
/// [`micros_of`], for `as_millis`).
#[must_use]
#[inline(never)]
pub(crate) fn millis_of(d: Duration) -> u64 {
    d.as_secs()
        .saturating_mul(1000)
        .saturating_add(u64::from(d.subsec_millis()))
}

/// A duration as whole microseconds for a 32-bit object (1006h, 1007h),
/// saturating at `u32::MAX`.
#[must_use]
pub(crate) fn micros_u32(d: Duration) -> u32 {
    u32::try_from(micros_of(d)).unwrap_or(u32::MAX)
}

/// A duration as whole milliseconds in 32 bits (an SDO timeout kept for
/// resets), saturating at `u32::MAX`.
#[must_use]
pub(crate) fn millis_u32(d: Duration) -> u32 {
    u32::try_from(millis_of(d)).unwrap_or(u32::MAX)
}

/// A duration as whole milliseconds for a 16-bit object (1017h, 1016h,
/// event timers), saturating at 65535 ms.
#[must_use]
pub fn millis_u16(d: Duration) -> u16 {
    u16::try_from(millis_of(d)).unwrap_or(u16::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saturates_both_ways() {
        assert_eq!(Timestamp::MAX.add_millis(1), Timestamp::MAX);
        assert_eq!(Timestamp::from_millis(u64::MAX), Timestamp::MAX);
        assert_eq!(
            Timestamp::from_micros(5).saturating_micros_since(Timestamp::from_micros(9)),
            0
        );
        assert_eq!(
            Timestamp::from_micros(9).saturating_duration_since(Timestamp::from_micros(5)),
            Duration::from_micros(4)
        );
        assert_eq!(Timestamp::ZERO.add_duration(Duration::MAX), Timestamp::MAX);
        assert!(Timestamp::from_millis(2).has_reached(Timestamp::from_millis(2)));
        assert!(!Timestamp::from_millis(1).has_reached(Timestamp::from_millis(2)));
    }

    timer_kind! {
        enum Three { A, B, C }
    }

    #[test]
    fn timers_keep_deadlines_in_eight_bytes() {
        use Three::{A, B, C};
        assert_eq!(core::mem::size_of::<Timers<Three, 3>>(), 24);
        let mut t: Timers<Three, 3> = Timers::new();
        assert_eq!(t.next(), None);
        t.set(A, Some(Timestamp::ZERO));
        t.set(C, Some(Timestamp::from_micros(u64::MAX - 1)));
        assert_eq!(t.next(), Some(Timestamp::ZERO));
        assert_eq!(t.get(C), Some(Timestamp::from_micros(u64::MAX - 1)));
        assert!(t.expire(A, Timestamp::ZERO));
        assert_eq!(t.next(), Some(Timestamp::from_micros(u64::MAX - 1)));
        assert!(!t.expire(C, Timestamp::from_micros(u64::MAX - 2)));
        assert!(t.expire(C, Timestamp::MAX));
        assert_eq!((t.get(C), t.next()), (None, None));
        // A deadline at the end of the clock is kept a microsecond earlier:
        // it expires once, at the end of the clock at the latest.
        let last = Some(Timestamp::from_micros(u64::MAX - 1));
        t.set(B, Some(Timestamp::MAX));
        assert_eq!((t.get(B), t.next()), (last, last));
        assert!(!t.expire(B, Timestamp::from_micros(u64::MAX - 2)));
        assert!(t.expire(B, Timestamp::MAX));
        assert!(!t.expire(B, Timestamp::MAX));
        assert_eq!(t.next(), None);
        t.set(A, Some(Timestamp::from_millis(5)));
        t.clear();
        assert_eq!(t.next(), None);
        assert_eq!(<Three as TimerKind>::COUNT, 3);
    }

    #[test]
    fn earliest_is_the_first_armed_deadline_of_every_source() {
        let t = |ms| Some(Timestamp::from_millis(ms));
        assert_eq!(earliest([]), None);
        assert_eq!(earliest([None, None, None]), None);
        assert_eq!(earliest([t(5), None, t(3), t(9)]), t(3));
        assert_eq!(earliest([None, t(7)]), t(7));
        assert_eq!(earliest([t(7), None]), t(7));
        // The ends of the clock are kept as given.
        assert_eq!(earliest([Some(Timestamp::MAX), None]), Some(Timestamp::MAX));
        assert_eq!(
            earliest([Some(Timestamp::MAX), Some(Timestamp::ZERO)]),
            Some(Timestamp::ZERO)
        );
        // A timer table and other machines' deadlines together.
        let mut own: Timers<Three, 3> = Timers::new();
        own.set(Three::B, t(4));
        assert_eq!(earliest([t(6), own.next()]), t(4));
        own.set(Three::B, None);
        assert_eq!(earliest([t(6), own.next()]), t(6));
    }

    #[test]
    fn maybe_timestamp_keeps_all_but_the_last_microsecond() {
        for us in [0, 1, 1_756_955_646_068_614, u64::MAX - 1] {
            let t = Some(Timestamp::from_micros(us));
            assert_eq!(MaybeTimestamp::new(t).get(), t);
        }
        assert_eq!(MaybeTimestamp::new(None).get(), None);
        assert_eq!(
            MaybeTimestamp::new(Some(Timestamp::MAX)).get(),
            Some(Timestamp::from_micros(u64::MAX - 1))
        );
        assert_eq!(MaybeTimestamp::default(), MaybeTimestamp::NONE);
        let (one, two) = (MaybeTimestamp(1), MaybeTimestamp(2));
        assert_eq!((one.min(two), two.min(one)), (one, one));
        assert_eq!(MaybeTimestamp::NONE.min(two).min(MaybeTimestamp::NONE), two);
        assert_eq!(MaybeTimestamp::NONE.min(MaybeTimestamp::NONE).get(), None);
    }

    #[test]
    fn duration_conversions_agree_with_the_128_bit_ones() {
        let secs = [
            0,
            1,
            59,
            4_294,
            18_446_744_073_709,
            18_446_744_073_710,
            u64::MAX,
        ];
        let nanos = [
            0,
            1,
            999,
            1_000,
            999_999,
            1_000_000,
            551_615_999,
            999_999_999,
        ];
        for s in secs {
            for n in nanos {
                let d = Duration::new(s, n);
                let us = u64::try_from(d.as_micros()).unwrap_or(u64::MAX);
                let ms = u64::try_from(d.as_millis()).unwrap_or(u64::MAX);
                assert_eq!((micros_of(d), millis_of(d)), (us, ms), "{d:?}");
            }
        }
        assert_eq!(millis_u16(Duration::from_millis(65_535)), 65_535);
        assert_eq!(millis_u16(Duration::from_micros(65_535_999)), 65_535);
        assert_eq!(millis_u16(Duration::from_millis(65_536)), u16::MAX);
        assert_eq!(
            micros_u32(Duration::from_micros(u64::from(u32::MAX))),
            u32::MAX
        );
        assert_eq!(micros_u32(Duration::from_micros(7)), 7);
        assert_eq!(micros_u32(Duration::from_secs(1 << 40)), u32::MAX);
        assert_eq!(millis_u32(Duration::from_micros(2_500_900)), 2_500);
        assert_eq!(millis_u32(Duration::MAX), u32::MAX);
    }

    proptest::proptest! {
        #![proptest_config(crate::testing::proptest_config("tests/proptest-regressions/src-clock.txt"))]
        #[test]
        fn earliest_is_the_minimum_of_the_armed(deadlines in proptest::collection::vec(proptest::option::of(proptest::num::u64::ANY), 0..12)) {
            let deadlines: std::vec::Vec<Option<Timestamp>> = deadlines.into_iter().map(|d| d.map(Timestamp::from_micros)).collect();
            let armed = deadlines.iter().flatten().copied().min();
            proptest::prop_assert_eq!(earliest(deadlines.iter().copied()), armed);
        }

        #[test]
        fn duration_conversions_agree_everywhere(s in proptest::num::u64::ANY, n in 0u32..1_000_000_000) {
            let d = Duration::new(s, n);
            proptest::prop_assert_eq!(micros_of(d), u64::try_from(d.as_micros()).unwrap_or(u64::MAX));
            proptest::prop_assert_eq!(millis_of(d), u64::try_from(d.as_millis()).unwrap_or(u64::MAX));
        }
    }

    #[test]
    fn displays_like_candump() {
        assert_eq!(
            format!("{}", Timestamp::from_micros(1_756_955_646_068_614)),
            "1756955646.068614"
        );
    }
}
