//! Utilisation over time: how busy each resource (a fleet's robots, a door, a lift, the
//! busiest lanes) was in each interval of the run, so that a planner sees when the
//! building saturates, not only that it did.

use serde::Serialize;

/// Busy seconds of one resource per interval of `period` seconds.
#[derive(Debug, Clone, Default)]
pub struct Buckets {
    period: f64,
    busy: Vec<f64>,
    total: f64,
}

impl Buckets {
    pub fn new(period: f64) -> Buckets {
        Buckets {
            period: period.max(1e-3),
            busy: Vec::new(),
            total: 0.0,
        }
    }

    /// The resource was busy from `from` to `to` (s).
    pub fn add(&mut self, from: f64, to: f64) {
        let (from, to) = (from.max(0.0), to.max(0.0));
        if to <= from {
            return;
        }
        self.total += to - from;
        let mut t = from;
        while t < to {
            let k = (t / self.period).floor() as usize;
            let edge = ((k + 1) as f64 * self.period).min(to);
            if self.busy.len() <= k {
                self.busy.resize(k + 1, 0.0);
            }
            self.busy[k] += edge - t;
            t = edge;
        }
    }

    /// Busy seconds in all.
    pub fn total(&self) -> f64 {
        self.total
    }

    /// Busy share of each interval of a run of `end` seconds (the last interval may be
    /// shorter), with `capacity` users at once; to three decimals.
    pub fn shares(&self, end: f64, capacity: f64) -> Vec<f64> {
        let n = (end / self.period).ceil().max(0.0) as usize;
        (0..n)
            .map(|k| {
                let len = (end - k as f64 * self.period).min(self.period);
                let b = self.busy.get(k).copied().unwrap_or(0.0);
                if len > 0.0 && capacity > 0.0 {
                    (b / (len * capacity) * 1000.0).round() / 1000.0
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// `other`'s busy time added to this one's (same period).
    pub fn merge(&mut self, other: &Buckets) {
        if self.busy.len() < other.busy.len() {
            self.busy.resize(other.busy.len(), 0.0);
        }
        for (a, b) in self.busy.iter_mut().zip(&other.busy) {
            *a += b;
        }
        self.total += other.total;
    }
}

/// The interval for a run of `duration` seconds: the shortest of 1, 5, 10, 15, 30 min,
/// 1, 2, 4, 8 h... that cuts it into at most 48 intervals.
pub fn period_for(duration: f64) -> f64 {
    let mut p = [60.0, 300.0, 600.0, 900.0, 1800.0, 3600.0]
        .into_iter()
        .find(|p| duration / p <= 48.0)
        .unwrap_or(3600.0);
    while duration / p > 48.0 {
        p *= 2.0;
    }
    p
}

/// The report's utilisation over time.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Timeline {
    /// Length of each interval (s); the last one may be shorter.
    pub period_s: f64,
    /// One entry per resource: each fleet's robots (share of them with a task), each door
    /// (share of the time not closed), each lift (in a session), and the ten lanes robots
    /// drove longest (robots on it on average: above 1 where robots follow each other).
    pub series: Vec<Series>,
}

#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Series {
    /// `fleet NAME`, `door NAME`, `lift NAME`, `lane FROM – TO`.
    pub resource: String,
    /// Busy share in each interval.
    pub busy: Vec<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn busy_time_is_split_over_the_intervals_it_spans() {
        let mut b = Buckets::new(60.0);
        b.add(30.0, 150.0);
        b.add(170.0, 180.0);
        assert_eq!(b.total(), 130.0);
        // 30 s of the first minute, all of the second, 30 + 10 s of the third; the run
        // ends at 200 s, so the fourth interval is 20 s long and idle.
        assert_eq!(b.shares(200.0, 1.0), vec![0.5, 1.0, 0.667, 0.0]);
        // Two robots: half as busy.
        assert_eq!(b.shares(120.0, 2.0), vec![0.25, 0.5]);
    }

    #[test]
    fn at_most_48_intervals() {
        assert_eq!(period_for(600.0), 60.0);
        assert_eq!(period_for(3600.0), 300.0);
        assert_eq!(period_for(4.0 * 3600.0), 300.0);
        assert_eq!(period_for(8.0 * 3600.0), 600.0);
        assert_eq!(period_for(100.0 * 3600.0), 14400.0);
    }
}
