//! One PDO field over time, decimated for drawing as it streams in: the
//! log is cut into time buckets (columns) and each keeps the lowest and the
//! highest sample it saw, with their times, so a plot drawn from the
//! buckets shows every peak and trough a plot of all samples would, at
//! most [`MAX_BUCKETS`] columns wide. Memory is bounded by the bucket
//! count, not by the log's length: when the buckets overflow their width
//! doubles and neighbours merge. The sample count and the samples without
//! a value (the object's "invalid" marker) are counted, never dropped.

use std::prelude::rust_2021::*;

/// At most this many buckets per series (two screen widths of columns): a
/// series of fewer samples keeps every sample.
pub const MAX_BUCKETS: usize = 2400;

/// A sample: microseconds since the log's first frame, and the value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Microseconds since the log's first frame.
    pub t: u64,
    /// The value.
    pub v: f64,
}

/// One column of the plot: its lowest and highest sample.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bucket {
    /// The bucket's number: its start is `index * width`.
    index: u64,
    min: Sample,
    max: Sample,
}

/// A field's samples, decimated.
#[derive(Debug)]
pub struct Series {
    /// Microseconds per bucket (1: every distinct time its own bucket).
    width: u64,
    buckets: Vec<Bucket>,
    /// Samples taken, values or not.
    pub samples: u64,
    /// Samples without a value (drawn as a gap).
    pub invalid: u64,
    /// Gaps (invalid samples) kept for drawing, as times.
    gaps: Vec<u64>,
}

impl Default for Series {
    fn default() -> Self {
        Series {
            width: 1,
            buckets: Vec::new(),
            samples: 0,
            invalid: 0,
            gaps: Vec::new(),
        }
    }
}

impl Series {
    /// Adds a sample at `t` (µs since the log's start). A time before the
    /// last bucket (an out-of-order log) joins the last bucket.
    pub fn push(&mut self, t: u64, v: f64) {
        if !v.is_finite() {
            self.push_gap(t);
            return;
        }
        self.samples += 1;
        let s = Sample { t, v };
        let index = t / self.width;
        match self.buckets.last_mut() {
            Some(b) if index <= b.index => {
                if v < b.min.v {
                    b.min = s;
                }
                if v > b.max.v {
                    b.max = s;
                }
            }
            _ => {
                self.buckets.push(Bucket {
                    index,
                    min: s,
                    max: s,
                });
                if self.buckets.len() > MAX_BUCKETS {
                    self.widen();
                }
            }
        }
    }

    /// A sample without a value at `t`: the line is broken there.
    pub fn push_gap(&mut self, t: u64) {
        self.samples += 1;
        self.invalid += 1;
        // One gap per bucket is all a drawing can show.
        let index = t / self.width;
        if self.gaps.last().is_none_or(|&g| g / self.width < index) {
            self.gaps.push(t);
            if self.gaps.len() > MAX_BUCKETS {
                let w = self.width.saturating_mul(2);
                self.gaps.dedup_by_key(|g| *g / w);
            }
        }
    }

    /// Doubles the bucket width until the buckets fit, merging neighbours.
    fn widen(&mut self) {
        while self.buckets.len() > MAX_BUCKETS {
            self.width = self.width.saturating_mul(2);
            let mut merged: Vec<Bucket> = Vec::with_capacity(self.buckets.len() / 2 + 1);
            for b in self.buckets.drain(..) {
                let index = b.min.t.min(b.max.t) / self.width;
                match merged.last_mut() {
                    Some(m) if index <= m.index => {
                        if b.min.v < m.min.v {
                            m.min = b.min;
                        }
                        if b.max.v > m.max.v {
                            m.max = b.max;
                        }
                    }
                    _ => merged.push(Bucket { index, ..b }),
                }
            }
            self.buckets = merged;
            let w = self.width;
            self.gaps.dedup_by_key(|g| *g / w);
        }
    }

    /// The points to draw, in time order: each bucket's lowest and highest
    /// sample (one point when they are the same sample).
    pub fn points(&self) -> Vec<Sample> {
        let mut out = Vec::with_capacity(self.buckets.len() * 2);
        for b in &self.buckets {
            let (first, second) = if b.min.t <= b.max.t {
                (b.min, b.max)
            } else {
                (b.max, b.min)
            };
            out.push(first);
            if second != first {
                out.push(second);
            }
        }
        out
    }

    /// Times of the samples without a value (at most one per bucket).
    pub fn gaps(&self) -> &[u64] {
        &self.gaps
    }

    /// True when every sample is kept as it was (no bucket merged two).
    pub fn exact(&self) -> bool {
        self.width == 1
    }
}

/// A sum per aligned 1-second window (frames, bits), as a series of one
/// sample per window at its start: windows start at the log's first frame
/// and follow each other. Windows without anything are zero: the series
/// gets one zero sample after a busy window and one before the next, so a
/// silent hour costs two samples, not 3 600.
#[derive(Debug, Default)]
pub struct PerSecond {
    /// The current window's number and its sum.
    current: Option<(u64, f64)>,
    series: Series,
}

impl PerSecond {
    /// Adds `amount` at `t` (µs since the log's start). A time before the
    /// current window (an out-of-order log) joins the current window.
    pub fn add(&mut self, t: u64, amount: f64) {
        let w = t / 1_000_000;
        match self.current {
            Some((cur, ref mut sum)) if w <= cur => *sum += amount,
            Some((cur, sum)) => {
                self.series.push(cur.saturating_mul(1_000_000), sum);
                let next = cur.saturating_add(1);
                if w > next {
                    self.series.push(next.saturating_mul(1_000_000), 0.0);
                    if w > next.saturating_add(1) {
                        self.series.push((w - 1).saturating_mul(1_000_000), 0.0);
                    }
                }
                self.current = Some((w, amount));
            }
            None => self.current = Some((w, amount)),
        }
    }

    /// The windows' samples so far (the current one included), in the
    /// shape [`Series::points`] gives, and whether none was merged.
    pub fn points(&self) -> (Vec<Sample>, bool) {
        let mut p = self.series.points();
        if let Some((cur, sum)) = self.current {
            p.push(Sample {
                t: cur.saturating_mul(1_000_000),
                v: sum,
            });
        }
        (p, self.series.exact())
    }

    /// Windows counted so far (merged or not).
    pub fn windows(&self) -> u64 {
        self.series.samples + u64::from(self.current.is_some())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_series_keeps_every_sample() {
        let mut s = Series::default();
        for i in 0..100u64 {
            s.push(i * 1000, i as f64);
        }
        assert!(s.exact());
        let p = s.points();
        assert_eq!(p.len(), 100);
        assert_eq!(p[37], Sample { t: 37_000, v: 37.0 });
    }

    #[test]
    fn a_long_series_is_bounded_and_keeps_its_extremes() {
        let mut s = Series::default();
        // One million samples of a slow ramp with one spike up and one down.
        for i in 0..1_000_000u64 {
            let v = match i {
                123_457 => 1e6,
                876_543 => -1e6,
                _ => (i % 1000) as f64,
            };
            s.push(i * 100, v);
        }
        assert_eq!(s.samples, 1_000_000);
        assert!(!s.exact());
        let p = s.points();
        assert!(p.len() <= 2 * MAX_BUCKETS, "{} points", p.len());
        assert!(p.len() >= MAX_BUCKETS / 2, "{} points", p.len());
        assert!(p.contains(&Sample {
            t: 12_345_700,
            v: 1e6
        }));
        assert!(p.contains(&Sample {
            t: 87_654_300,
            v: -1e6
        }));
        // In time order.
        assert!(p.windows(2).all(|w| w[0].t <= w[1].t));
        // Every bucket's range covers the ramp's full range (0..999).
        let max = p
            .iter()
            .filter(|s| s.v < 1e5)
            .map(|s| s.v)
            .fold(0.0, f64::max);
        assert_eq!(max, 999.0);
    }

    #[test]
    fn out_of_order_and_invalid_samples_are_counted() {
        let mut s = Series::default();
        s.push(5000, 1.0);
        s.push(1000, 7.0);
        s.push(6000, f64::NAN);
        s.push_gap(7000);
        assert_eq!((s.samples, s.invalid), (4, 2));
        assert_eq!(
            s.points(),
            vec![Sample { t: 1000, v: 7.0 }, Sample { t: 5000, v: 1.0 }]
        );
        assert_eq!(s.gaps(), &[6000, 7000]);
    }

    #[test]
    fn per_second_sums_windows_and_fills_silences_with_two_zeros() {
        let mut p = PerSecond::default();
        for t in [0, 300_000, 999_999, 1_000_000] {
            p.add(t, 1.0);
        }
        // An hour of silence, then a frame out of order.
        p.add(3_601_500_000, 2.0);
        p.add(3_601_400_000, 1.0);
        p.add(u64::MAX, 5.0);
        let (points, exact) = p.points();
        assert!(exact);
        let want = [
            (0, 3.0),
            (1_000_000, 1.0),
            (2_000_000, 0.0),
            (3_600_000_000, 0.0),
            (3_601_000_000, 3.0),
            (3_602_000_000, 0.0),
        ];
        for (i, (t, v)) in want.iter().enumerate() {
            assert_eq!(points[i], Sample { t: *t, v: *v }, "{i}");
        }
        assert_eq!(points.len(), 8);
        assert_eq!(points[7].v, 5.0);
        assert_eq!(p.windows(), 8);
    }
}
