//! The crowd's part of the report: how far and how fast people walked, and how close they
//! came to robots (measured between outlines: centre distance less the robot's footprint
//! radius and the person's radius), counted once per approach of a robot–person pair.

use super::Person;
use serde::Serialize;
use std::collections::BTreeSet;

/// Speeds below this (m/s) count as standing.
const WALKING: f64 = 0.05;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CrowdReport {
    pub humans: usize,
    /// Distance each person walked (m).
    pub walked_m: Spread,
    /// Mean speed while walking (distance over time above 0.05 m/s), and the fastest seen.
    pub speed_m_s: SpeedStats,
    /// Approaches of a robot and a person closer than 0.5 m (outline to outline) without
    /// touching.
    pub near_misses: usize,
    /// Approaches where a robot and a person overlapped.
    pub contacts: usize,
    /// Smallest robot–person clearance seen (m; none when no robot came within 0.5 m).
    pub min_clearance_m: Option<f64>,
    /// With `--compare-crowd`: each fleet's mean task time in this run and in the same run
    /// without people.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub compare: Vec<FleetCompare>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spread {
    pub total: f64,
    pub mean: f64,
    pub min: f64,
    pub max: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpeedStats {
    pub mean: f64,
    pub max: f64,
}

/// One fleet's tasks with and without people.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FleetCompare {
    pub fleet: String,
    pub completed: usize,
    pub completed_without_crowd: usize,
    /// Mean time from request to completion (s), over completed tasks.
    pub mean_task_s: Option<f64>,
    pub mean_task_s_without_crowd: Option<f64>,
    /// `mean_task_s / mean_task_s_without_crowd`: the effect of people in one number.
    pub slowdown: Option<f64>,
}

#[derive(Debug, Default)]
pub(crate) struct Stats {
    moving_s: Vec<f64>,
    moving_m: Vec<f64>,
    max_speed: f64,
    near: BTreeSet<(usize, usize)>,
    touching: BTreeSet<(usize, usize)>,
    near_misses: usize,
    contacts: usize,
    min_clearance: Option<f64>,
}

fn round(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

impl Stats {
    pub fn new(n: usize) -> Stats {
        Stats {
            moving_s: vec![0.0; n],
            moving_m: vec![0.0; n],
            ..Stats::default()
        }
    }

    pub fn walk(&mut self, i: usize, speed: f64, dt: f64) {
        if speed > WALKING {
            self.moving_s[i] += dt;
            self.moving_m[i] += speed * dt;
        }
        self.max_speed = self.max_speed.max(speed);
    }

    /// This step's (robot, person, clearance) pairs closer than the near-miss distance.
    pub fn encounters(&mut self, _t: f64, seen: &[(usize, usize, f64)]) {
        let mut near = BTreeSet::new();
        let mut touching = BTreeSet::new();
        for &(r, p, gap) in seen {
            self.min_clearance = Some(self.min_clearance.map_or(gap, |m: f64| m.min(gap)));
            if gap < 0.0 {
                if !self.touching.contains(&(r, p)) {
                    self.contacts += 1;
                    // An approach that ends in contact is a contact, not a near miss.
                    if self.near.contains(&(r, p)) {
                        self.near_misses = self.near_misses.saturating_sub(1);
                    }
                }
                touching.insert((r, p));
            } else if !self.near.contains(&(r, p)) && !self.touching.contains(&(r, p)) {
                self.near_misses += 1;
            }
            near.insert((r, p));
        }
        // A pair stays "touching" until it leaves the near zone (one approach, one count).
        self.touching = touching
            .union(&self.touching.intersection(&near).copied().collect())
            .copied()
            .collect();
        self.near = near;
    }

    pub fn report(&self, humans: usize, _end: f64, people: &[Person]) -> CrowdReport {
        let walked: Vec<f64> = people.iter().map(|p| p.walked).collect();
        let total: f64 = walked.iter().sum();
        let n = walked.len().max(1) as f64;
        let (ms, mm): (f64, f64) = (self.moving_s.iter().sum(), self.moving_m.iter().sum());
        CrowdReport {
            humans,
            walked_m: Spread {
                total: round(total),
                mean: round(total / n),
                min: round(
                    walked
                        .iter()
                        .copied()
                        .fold(f64::INFINITY, f64::min)
                        .min(total),
                ),
                max: round(walked.iter().copied().fold(0.0, f64::max)),
            },
            speed_m_s: SpeedStats {
                mean: round(if ms > 0.0 { mm / ms } else { 0.0 }),
                max: round(self.max_speed),
            },
            near_misses: self.near_misses,
            contacts: self.contacts,
            min_clearance_m: self.min_clearance.map(round),
            compare: Vec::new(),
        }
    }
}

/// Fills `with.crowd.compare` from the same scenario run without people.
pub fn compare_crowd(with: &mut crate::Report, without: &crate::Report) {
    let stats = |r: &crate::Report, fleet: &str| {
        let times: Vec<f64> = r
            .tasks
            .iter()
            .filter(|t| t.fleet == fleet && t.result == "completed")
            .filter_map(|t| Some(t.finished? - t.requested?))
            .collect();
        let mean =
            (!times.is_empty()).then(|| round(times.iter().sum::<f64>() / times.len() as f64));
        (times.len(), mean)
    };
    let fleets: Vec<String> = with.fleets.iter().map(|f| f.name.clone()).collect();
    let rows: Vec<FleetCompare> = fleets
        .iter()
        .map(|f| {
            let (n, m) = stats(with, f);
            let (n0, m0) = stats(without, f);
            FleetCompare {
                fleet: f.clone(),
                completed: n,
                completed_without_crowd: n0,
                mean_task_s: m,
                mean_task_s_without_crowd: m0,
                slowdown: match (m, m0) {
                    (Some(a), Some(b)) if b > 0.0 => Some(round(a / b)),
                    _ => None,
                },
            }
        })
        .collect();
    if let Some(c) = with.crowd.as_mut() {
        c.compare = rows;
    }
}
