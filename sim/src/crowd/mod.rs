//! People in the runtime: the map's `crowd_sim` walking among the robots (runtime.md §6),
//! like Menge in rmf_simulation's crowd plugin, with three deliberate differences: robots
//! see people (a slotcar stops for a person in its stop zone as for any obstacle, §1.8,
//! where upstream's actors are invisible), people take the whole avoidance towards robots
//! (robots do not avoid; Menge assumes they take half and people brush them), and every
//! robot on the crowd's level is an obstacle for people, not only the `agents_name` list.
//!
//! Each crowd step (`update_time_step` of the map, a whole number of physics steps): the
//! behaviour (`behaviour.rs`) moves agents between states; an agent entering a state picks
//! a goal and plans a path over the navmesh (`mesh.rs`); the preferred velocity heads for
//! the next waypoint at `pref_speed`; ORCA (`dodgy_2d`) turns it into a velocity that
//! avoids the other people, the robots and the mesh boundary; the velocity changes by at
//! most `max_accel·dt` and the position is integrated. Agents are processed in index order
//! with their own seeded RNG, so runs are deterministic and a map without a crowd does
//! not touch the world's RNG.
//!
//! Invariant: people walk on one level (Menge's scene is one level): the level of the
//! obstacle set's navmesh `<level>_navmesh.nav`, else of the first goal, else the first
//! level with human lanes.

mod behaviour;
mod grid;
mod mesh;
mod stats;
#[cfg(test)]
mod tests;

pub use stats::{compare_crowd, CrowdReport, FleetCompare, SpeedStats, Spread};

use crate::msgs::{self, Msg, Published, Topic};
use crate::truth::{People, RobotTruth};
use behaviour::{Fsm, Mind};
use dodgy_2d::{Agent, AvoidanceOptions, Obstacle};
use grid::Grid;
use mapc_ir::{AgentProfile, Building, Handle, Level, Vec2};
use mesh::Mesh;
use std::borrow::Cow;

/// The profile name of the robots' groups (external agents).
pub const EXTERNAL_PROFILE: &str = "external_agent";
/// A person's bounding box height (m) on `/rmf_obstacles`.
pub const PERSON_HEIGHT: f64 = 1.8;
/// Published on `/rmf_obstacles` as the obstacles' `source`.
pub const SOURCE: &str = "mapc_crowd";
/// Clearance (m, between the outlines) under which a robot and a person near-miss.
pub const NEAR_MISS: f64 = 0.5;
/// Radius (m) of the circle in which a person counts the others for the local density.
const DENSITY_RADIUS: f64 = 1.0;
/// Weidmann's fundamental diagram (1993): γ (m⁻²) and the jam density ρmax (m⁻²).
const WEIDMANN_GAMMA: f64 = 1.913;
const WEIDMANN_RHO_MAX: f64 = 5.4;

/// `pref` slowed to the speed of the fundamental diagram at the density of `others` people
/// within `DENSITY_RADIUS`, with the profile's `pref_speed` as the free speed v0. Alone,
/// nothing changes; at the jam density people still creep (5 % of v0) so that a crowd
/// never freezes for good.
fn density_speed(pref: Vec2, v0: f64, others: usize) -> Vec2 {
    let speed = len(pref);
    if others == 0 || speed <= 0.0 {
        return pref;
    }
    let rho = others as f64 / (std::f64::consts::PI * DENSITY_RADIUS * DENSITY_RADIUS);
    let v = v0 * (1.0 - (-WEIDMANN_GAMMA * (1.0 / rho - 1.0 / WEIDMANN_RHO_MAX)).exp());
    let v = v.max(0.05 * v0);
    if v >= speed {
        pref
    } else {
        pref.scale(v / speed)
    }
}

/// Cell size (m) of the people's grid, unless the mesh is large for its crowd.
const PEOPLE_CELL: f64 = 0.5;
const PEOPLE_CELLS_PER_PERSON: f64 = 64.0;
const MIN_PEOPLE_CELLS: f64 = 16384.0;
/// Added (m) to a person's k-th neighbour distance for the next step's first scan.
const REACH_MARGIN: f64 = 0.2;
/// Most cells of the walls' grid (built once).
const MAX_WALL_CELLS: f64 = 1e6;
/// Extra clearance (m) people keep from a robot's footprint.
pub const ROBOT_BERTH: f64 = 0.15;
/// A person who wants to walk but has stood this long (s) beside a robot that stands
/// still gives way: the robot stops for people in front of it, so neither would move
/// again (a stand-off that lasted hours on the airport map). The person steps back
/// away from the robot for `GIVE_WAY` s, at half its preferred speed, then walks on.
const GIVE_WAY_AFTER: f64 = 3.0;
const GIVE_WAY: f64 = 3.0;
/// How near (m, beyond the robot's footprint and berth) a robot holds a person up.
const GIVE_WAY_NEAR: f64 = 1.0;
/// Most people a run may have (`crowd.scale` times the map's groups).
pub const MAX_PEOPLE: usize = 100_000;

/// Walking parameters of an agent profile, with the generator's defaults for values the
/// map leaves at 0 (building_crowdsim writes a default for every falsy value).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Profile {
    pub r: f64,
    pub pref_speed: f64,
    pub max_speed: f64,
    pub max_accel: f64,
    pub neighbor_dist: f64,
    pub max_neighbors: usize,
    pub tau: f64,
    pub tau_obst: f64,
}

impl Profile {
    pub fn from_map(p: &AgentProfile) -> Profile {
        let or = |v: f64, d: f64| if v.is_finite() && v > 0.0 { v } else { d };
        Profile {
            r: or(p.r, 0.2),
            // The generator writes the yaml value (0 when absent); Menge's own default,
            // 1.34 m/s, is what an unset speed means.
            pref_speed: or(p.pref_speed, 1.34),
            max_speed: or(p.max_speed, 2.0),
            max_accel: or(p.max_accel, 5.0),
            neighbor_dist: or(p.neighbor_dist, 5.0),
            max_neighbors: if p.max_neighbors > 0 {
                p.max_neighbors.min(1000) as usize
            } else {
                10
            },
            tau: or(p.orca_tau, 3.0),
            tau_obst: or(p.orca_tau_obst, 0.15),
        }
    }
}

pub(crate) struct Person {
    /// Local frame (map frame less the mesh origin).
    pub pos: Vec2,
    pub vel: Vec2,
    pub yaw: f64,
    pub profile: usize,
    mind: Mind,
    path: Vec<Vec2>,
    wp: usize,
    pref: Vec2,
    pub walked: f64,
    /// The navmesh node the person stands in.
    node: usize,
    /// How long (s) the person has wanted to walk and not moved.
    stalled: f64,
    /// Stepping back out of a waiting robot's way: until when, and which way.
    give_way: Option<(f64, Vec2)>,
}

pub(crate) struct Crowd {
    level_name: String,
    z: f64,
    mesh: Mesh,
    profiles: Vec<Profile>,
    fsm: Fsm,
    pub people: Vec<Person>,
    rng: fastrand::Rng,
    /// Physics steps per crowd step, and the crowd step (s).
    every: u64,
    dt: f64,
    /// Physics steps per `/rmf_obstacles` message (the robots' 2 Hz).
    publish_every: u64,
    grid: Grid,
    walls: Grid,
    /// Per person: the radius of the first neighbour scan (a guess; any value is exact).
    reach: Vec<f64>,
    wall_obstacles: Vec<Obstacle>,
    wall_segments: Vec<(Vec2, Vec2)>,
    max_r: f64,
    pub(crate) stats: stats::Stats,
}

/// Why the crowd cannot walk on this map.
pub type CrowdError = String;

impl Crowd {
    /// The crowd of `b` when its crowd_sim is enabled and has people; `floors` are the
    /// levels' floor heights in the world (by level index); `scale` multiplies every human
    /// group; `physics_dt` is the world's step.
    pub fn new(
        b: &Building,
        floors: &[f64],
        scale: f64,
        seed: u64,
        physics_dt: f64,
    ) -> Result<Option<Crowd>, CrowdError> {
        let Some(c) = b.crowd_sim.as_ref().filter(|c| c.enable) else {
            return Ok(None);
        };
        let human = |g: &&mapc_ir::AgentGroup| {
            g.profile_selector != EXTERNAL_PROFILE && g.agents_name.is_empty()
        };
        let mut counts = Vec::new();
        for g in c.agent_groups.iter().filter(human) {
            let n = (g.agents_number.max(0) as f64 * scale).round();
            counts.push(if n.is_finite() { n as usize } else { 0 });
        }
        let total: usize = counts.iter().sum();
        if total == 0 {
            return Ok(None);
        }
        if total > MAX_PEOPLE {
            return Err(format!(
                "the crowd would have {total} people, more than {MAX_PEOPLE}"
            ));
        }
        let level = crowd_level(b).ok_or("no level has human lanes for the crowd to walk on")?;
        let nav = mapc_ir::human_navmesh(b, level, Vec2::default())
            .ok_or("the crowd's level has no usable human lanes")?;
        let mesh = Mesh::new(&nav);
        let mut rng = fastrand::Rng::with_seed(seed ^ 0x6372_6f77_645f_7369);
        let fsm = Fsm::new(b, c, &mut rng);
        let profiles: Vec<Profile> = c.agent_profiles.iter().map(Profile::from_map).collect();
        let every = ((c.update_time_step / physics_dt).round() as u64).max(1);
        let dt = every as f64 * physics_dt;
        let publish_every = ((0.5 / physics_dt).round() as u64).max(1);
        let (lo, hi) = mesh.verts.iter().fold(
            (
                Vec2::new(f64::INFINITY, f64::INFINITY),
                Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
            ),
            |(lo, hi), v| {
                (
                    Vec2::new(lo.x.min(v.x), lo.y.min(v.y)),
                    Vec2::new(hi.x.max(v.x), hi.y.max(v.y)),
                )
            },
        );
        // The people's grid is rebuilt every step: at most PEOPLE_CELLS_PER_PERSON cells
        // per person (larger cells on meshes much larger than their crowd).
        let cap = (PEOPLE_CELLS_PER_PERSON * total as f64).max(MIN_PEOPLE_CELLS);
        let grid = Grid::new(lo, hi, PEOPLE_CELL, cap);
        let mut walls = Grid::new(lo, hi, 2.0, MAX_WALL_CELLS);
        // A wall matters to an agent within tau_obst·max_speed + r (RVO2's range).
        let reach = profiles
            .iter()
            .map(|p| p.tau_obst * p.max_speed + p.r)
            .fold(1.0, f64::max);
        let boxes: Vec<(Vec2, Vec2)> = mesh
            .walls
            .iter()
            .map(|(a, b)| {
                (
                    Vec2::new(a.x.min(b.x) - reach, a.y.min(b.y) - reach),
                    Vec2::new(a.x.max(b.x) + reach, a.y.max(b.y) + reach),
                )
            })
            .collect();
        walls.rebuild_boxes(&boxes);
        let wall_obstacles = mesh
            .walls
            .iter()
            .map(|(a, b)| Obstacle::Open {
                vertices: vec![f32v(*a), f32v(*b)],
            })
            .collect();
        let wall_segments = mesh.walls.clone();
        let mut crowd = Crowd {
            level_name: b.levels[level].name.clone(),
            z: floors
                .get(level.index())
                .copied()
                .unwrap_or(b.levels[level].elevation),
            mesh,
            profiles,
            fsm,
            people: Vec::new(),
            rng,
            every,
            dt,
            publish_every,
            grid,
            walls,
            reach: Vec::new(),
            wall_obstacles,
            wall_segments,
            max_r: 0.0,
            stats: stats::Stats::default(),
        };
        let mut placed: Vec<Vec2> = Vec::new();
        for (g, n) in c.agent_groups.iter().filter(human).zip(counts) {
            let profile = c
                .agent_profiles
                .iter()
                .position(|p| p.name == g.profile_selector)
                .ok_or_else(|| format!("unknown agent profile `{}`", g.profile_selector))?;
            let state = c
                .states
                .iter()
                .position(|s| s.name == g.state_selector)
                .ok_or_else(|| format!("unknown crowd state `{}`", g.state_selector))?;
            let r = crowd.profiles[profile].r;
            let spots = crowd.spread(g.pos.minus(crowd.mesh.origin), n, r, &placed);
            if spots.len() < n {
                return Err(format!(
                    "agent group {} at ({}, {}): only {} of its {n} people fit on the navmesh",
                    g.group_id,
                    g.pos.x,
                    g.pos.y,
                    spots.len()
                ));
            }
            for p in spots {
                placed.push(p);
                crowd.people.push(Person {
                    pos: p,
                    vel: Vec2::default(),
                    yaw: 0.0,
                    profile,
                    mind: Mind::default(),
                    path: Vec::new(),
                    wp: 0,
                    pref: Vec2::default(),
                    walked: 0.0,
                    node: crowd.mesh.locate(p).unwrap_or(0),
                    stalled: 0.0,
                    give_way: None,
                });
                let i = crowd.people.len() - 1;
                crowd.enter(i, state, 0.0);
            }
        }
        crowd.max_r = crowd
            .people
            .iter()
            .map(|p| crowd.profiles[p.profile].r)
            .fold(0.0, f64::max);
        crowd.stats = stats::Stats::new(crowd.people.len());
        crowd.reach = vec![0.0; crowd.people.len()];
        crowd.grid.rebuild(crowd.people.iter().map(|p| p.pos));
        Ok(Some(crowd))
    }

    /// `n` spots for people of radius `r` around `centre` (local frame): a hexagonal
    /// lattice in rings of growing distance, spots on the mesh and clear of `taken`.
    fn spread(&self, centre: Vec2, n: usize, r: f64, taken: &[Vec2]) -> Vec<Vec2> {
        let mut out: Vec<Vec2> = Vec::new();
        let gap = 2.0 * r + 0.1;
        let clear = |p: Vec2, out: &[Vec2]| {
            taken
                .iter()
                .chain(out.iter())
                .all(|q| q.minus(p).norm() >= gap - 1e-9)
        };
        let start = self.mesh.snap(centre).map_or(centre, |(_, q)| q);
        // Rings of a hexagonal lattice: ring k has 6k spots at distance ~k·gap.
        let dirs = [
            Vec2::new(1.0, 0.0),
            Vec2::new(0.5, 3f64.sqrt() / 2.0),
            Vec2::new(-0.5, 3f64.sqrt() / 2.0),
            Vec2::new(-1.0, 0.0),
            Vec2::new(-0.5, -(3f64.sqrt()) / 2.0),
            Vec2::new(0.5, -(3f64.sqrt()) / 2.0),
        ];
        for k in 0..400usize {
            if out.len() >= n {
                break;
            }
            let ring: Vec<Vec2> = if k == 0 {
                vec![start]
            } else {
                let mut ring = Vec::with_capacity(6 * k);
                for s in 0..6 {
                    let corner = start.plus(dirs[s].scale(k as f64 * gap));
                    let step = dirs[(s + 2) % 6].scale(gap);
                    for j in 0..k {
                        ring.push(corner.plus(step.scale(j as f64)));
                    }
                }
                ring
            };
            for p in ring {
                if out.len() >= n {
                    break;
                }
                // The whole disc on the mesh: its centre in a node, r from every wall.
                if self.mesh.locate(p).is_some() && self.wall_clear(p, r) && clear(p, &out) {
                    out.push(p);
                }
            }
        }
        out
    }

    fn wall_clear(&self, p: Vec2, r: f64) -> bool {
        self.walls.cell(p).iter().all(|&k| {
            let (a, b) = self.wall_segments[k as usize];
            seg_dist(p, a, b) >= r
        })
    }

    /// Enters `state`: a goal and its path.
    fn enter(&mut self, i: usize, state: usize, t: f64) {
        let mut mind = std::mem::take(&mut self.people[i].mind);
        self.fsm.enter(&mut mind, state, t, &mut self.rng);
        let goal = mind
            .goal
            .map(|g| self.fsm.goals[g].pos.minus(self.mesh.origin));
        self.people[i].mind = mind;
        let r = self.profiles[self.people[i].profile].r;
        let p = &mut self.people[i];
        p.wp = 0;
        p.path.clear();
        if let Some(goal) = goal {
            let from = self.mesh.snap(p.pos);
            let to = self.mesh.snap(goal);
            if let (Some((a, fa)), Some((b, tb))) = (from, to) {
                p.path = self
                    .mesh
                    .path(fa, a, tb, b, r)
                    .or_else(|| self.mesh.path(fa, a, tb, b, 0.0))
                    .unwrap_or_default();
            }
        }
    }

    fn goal_dist(&self, i: usize) -> f64 {
        let p = &self.people[i];
        p.mind.goal.map_or(f64::INFINITY, |g| {
            len(self.fsm.goals[g].pos.minus(self.mesh.origin).minus(p.pos))
        })
    }

    /// Is a person closer than `r` (3-D, to their centre) to `p` (map frame)?
    pub fn any_within(&self, p: [f64; 3], r: f64) -> bool {
        if (p[2] - self.z).abs() >= r {
            return false;
        }
        let q = Vec2::new(p[0], p[1]).minus(self.mesh.origin);
        let dz = p[2] - self.z;
        let r2 = r * r - dz * dz;
        let mut hit = false;
        self.grid.visit_points(q, r, |_, pos| {
            let d = pos.minus(q);
            hit |= d.x * d.x + d.y * d.y < r2;
        });
        hit
    }

    /// Called after every physics step `step` (1-based count of steps done) at the time
    /// `t` the step started; walks on crowd steps and publishes at 2 Hz.
    pub fn tick(&mut self, step: u64, t: f64, robots: &[RobotTruth], out: &mut Vec<Published>) {
        if (step - 1) % self.publish_every == 0 {
            out.push(Published {
                t,
                topic: Topic::RmfObstacles,
                msg: Msg::Obstacles(self.obstacles_msg(t)),
            });
        }
        if step % self.every == 0 {
            let now = step as f64 * (self.dt / self.every as f64);
            self.walk(now, robots);
        }
    }

    /// One crowd step at time `t` (the end of the physics step that triggered it).
    pub(crate) fn walk(&mut self, t: f64, robots: &[RobotTruth]) {
        let dt = self.dt;
        // Behaviour.
        for i in 0..self.people.len() {
            let gd = self.goal_dist(i);
            if let Some(s) = self.fsm.next(&self.people[i].mind, t, gd, &mut self.rng) {
                self.enter(i, s, t);
            }
        }
        // Preferred velocities.
        let origin = self.mesh.origin;
        let z = self.z;
        for i in 0..self.people.len() {
            let pr = self.profiles[self.people[i].profile];
            let final_state = self.fsm.states[self.people[i].mind.state].is_final;
            let p = &mut self.people[i];
            p.pref = Vec2::default();
            if final_state || p.path.is_empty() {
                continue;
            }
            if p.stalled >= GIVE_WAY_AFTER {
                p.stalled = 0.0;
                let held_by = robots
                    .iter()
                    .filter(|r| (r.z - z).abs() < 0.5 && r.v.abs() < 0.05)
                    .map(|r| (Vec2::new(r.x, r.y).minus(origin), r.footprint))
                    .map(|(q, fp)| (p.pos.minus(q), fp))
                    .filter(|(d, fp)| d.norm() < fp + ROBOT_BERTH + pr.r + GIVE_WAY_NEAR)
                    .min_by(|a, b| a.0.norm().total_cmp(&b.0.norm()));
                if let Some((d, _)) = held_by {
                    let n = d.norm();
                    if n > 1e-6 {
                        p.give_way = Some((t + GIVE_WAY, d.scale(1.0 / n)));
                    }
                }
            }
            if let Some((until, dir)) = p.give_way {
                if t < until {
                    p.pref = dir.scale(0.5 * pr.pref_speed);
                    continue;
                }
                p.give_way = None;
            }
            // Past a waypoint (within reach, or beyond it along the next leg): next one.
            while p.wp + 1 < p.path.len() {
                let w = p.path[p.wp];
                let next = p.path[p.wp + 1];
                let d = w.minus(p.pos);
                let leg = next.minus(w);
                let beyond = (p.pos.minus(w).x * leg.x + p.pos.minus(w).y * leg.y) > 0.0;
                if len(d) < pr.r.max(0.2) || beyond {
                    p.wp += 1;
                } else {
                    break;
                }
            }
            let d = p.path[p.wp].minus(p.pos);
            let dist = len(d);
            if dist * dist <= 1e-4 {
                continue;
            }
            let speed = pr.pref_speed.min(dist / dt);
            p.pref = d.scale(speed / dist);
        }
        // Avoidance against the positions at the start of the step: the grid holds them
        // (rebuilt after the last move; the behaviour above moves no one).
        let origin = self.mesh.origin;
        let on_level: Vec<Agent> = robots
            .iter()
            .filter(|r| (r.z - self.z).abs() < 0.5)
            .map(|r| Agent {
                position: f32v(Vec2::new(r.x, r.y).minus(origin)),
                velocity: f32v(Vec2::new(r.v * r.yaw.cos(), r.v * r.yaw.sin())),
                // People keep a berth from robots, which neither avoid nor brake hard.
                radius: (r.footprint + ROBOT_BERTH) as f32,
                // Robots do not avoid: people take the whole correction.
                avoidance_responsibility: 0.0,
            })
            .collect();
        let mut new_vel = Vec::with_capacity(self.people.len());
        let mut near: Vec<(f64, usize)> = Vec::new();
        let mut neighbours: Vec<Cow<Agent>> = Vec::new();
        let mut walls: Vec<Cow<Obstacle>> = Vec::new();
        for i in 0..self.people.len() {
            let p = &self.people[i];
            let pr = self.profiles[p.profile];
            // The max_neighbors nearest within neighbor_dist (squared distances, ties by
            // index: deterministic), and the local density: how many others stand within
            // DENSITY_RADIUS. People slow down in a crowd as the fundamental diagram says
            // (Weidmann), which ORCA alone does not do in a crowd without closing speeds (a
            // density filter, as in DenseSense).
            let others = self.grid.nearest(
                p.pos,
                pr.neighbor_dist,
                pr.max_neighbors,
                i,
                DENSITY_RADIUS,
                self.reach[i],
                &mut near,
            );
            // Next step's first guess: the k-th distance now, plus what two people can
            // close in one step at walking speed (a wrong guess costs a wider scan only).
            self.reach[i] = if near.len() >= pr.max_neighbors {
                near.last().map_or(0.0, |n| n.0.sqrt()) + REACH_MARGIN
            } else {
                pr.neighbor_dist
            };
            let pref = density_speed(self.people[i].pref, pr.pref_speed, others);
            neighbours.clear();
            for &(_, k) in &near {
                let q = &self.people[k];
                neighbours.push(Cow::Owned(Agent {
                    position: f32v(q.pos),
                    velocity: f32v(q.vel),
                    radius: self.profiles[q.profile].r as f32,
                    avoidance_responsibility: 1.0,
                }));
            }
            for a in &on_level {
                let d = (a.position - f32v(p.pos)).length() as f64;
                if d < pr.neighbor_dist && d > 1e-4 {
                    neighbours.push(Cow::Borrowed(a));
                }
            }
            walls.clear();
            let range = pr.tau_obst * pr.max_speed + pr.r;
            for &k in self.walls.cell(p.pos) {
                let (a, b) = self.wall_segments[k as usize];
                let d = seg_dist(p.pos, a, b);
                // A person standing on the mesh edge (the clamp below) is not avoided
                // from: the crate normalises the vector to the wall, which is zero there.
                if d < range && d > 1e-4 {
                    walls.push(Cow::Borrowed(&self.wall_obstacles[k as usize]));
                }
            }
            let me = Agent {
                position: f32v(p.pos),
                velocity: f32v(p.vel),
                radius: pr.r as f32,
                avoidance_responsibility: 1.0,
            };
            let opts = AvoidanceOptions {
                obstacle_margin: pr.r as f32,
                time_horizon: pr.tau as f32,
                obstacle_time_horizon: pr.tau_obst as f32,
            };
            // The crate asserts on degenerate input (NaN in its linear program); the guards
            // above keep that out, and should one slip through the person stands still for
            // a step rather than the run aborting.
            let v = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                me.compute_avoiding_velocity(
                    &neighbours,
                    &walls,
                    f32v(pref),
                    pr.max_speed as f32,
                    dt as f32,
                    &opts,
                )
            }))
            .unwrap_or(dodgy_2d::Vec2::ZERO);
            let v = Vec2::new(v.x as f64, v.y as f64);
            new_vel.push(if v.x.is_finite() && v.y.is_finite() {
                v
            } else {
                Vec2::default()
            });
        }
        // Integrate: acceleration-limited velocity change, then the position.
        for (i, v_new) in new_vel.into_iter().enumerate() {
            let pr = self.profiles[self.people[i].profile];
            let p = &mut self.people[i];
            let dv = v_new.minus(p.vel);
            let lim = pr.max_accel * dt;
            p.vel = if len(dv) > lim {
                p.vel.plus(dv.scale(lim / len(dv)))
            } else {
                v_new
            };
            let step = p.vel.scale(dt);
            let mut next = p.pos.plus(step);
            // ORCA keeps people off the walls only within its obstacle horizon; braking
            // under the acceleration limit can carry them further. Never off the mesh: a
            // step that would leave it is not taken (the person stops at the edge; snapping
            // to the nearest mesh point instead could put two people on one corner).
            match self.mesh.relocate(p.node, next) {
                Some(n) => p.node = n,
                None => {
                    next = p.pos;
                    p.vel = Vec2::default();
                }
            }
            p.walked += len(next.minus(p.pos));
            p.pos = next;
            let speed = len(p.vel);
            p.stalled = if len(p.pref) > 0.1 && speed < 0.05 {
                p.stalled + dt
            } else {
                0.0
            };
            if speed > 1e-3 {
                p.yaw = p.vel.y.atan2(p.vel.x);
            }
        }
        self.grid.rebuild(self.people.iter().map(|p| p.pos));
        self.observe(t, robots);
    }

    /// Robot–person encounters and speeds, for the report.
    fn observe(&mut self, t: f64, robots: &[RobotTruth]) {
        let reach = self.max_r + NEAR_MISS;
        let mut seen = Vec::new();
        for (ri, r) in robots.iter().enumerate() {
            if (r.z - self.z).abs() >= 0.5 {
                continue;
            }
            let q = Vec2::new(r.x, r.y).minus(self.mesh.origin);
            self.grid.visit_points(q, r.footprint + reach, |k, _| {
                let p = &self.people[k];
                let gap = len(p.pos.minus(q)) - r.footprint - self.profiles[p.profile].r;
                if gap < NEAR_MISS {
                    seen.push((ri, k, gap));
                }
            });
        }
        self.stats.encounters(t, &seen);
        for (i, p) in self.people.iter().enumerate() {
            self.stats.walk(i, len(p.vel), self.dt);
        }
    }

    fn obstacles_msg(&self, t: f64) -> msgs::Obstacles {
        let stamp = msgs::Time::from_secs(t);
        let obstacles = self
            .people
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let r = self.profiles[p.profile].r;
                let pos = p.pos.plus(self.mesh.origin);
                let half = p.yaw / 2.0;
                msgs::Obstacle {
                    header: msgs::Header {
                        stamp,
                        frame_id: "map".into(),
                    },
                    id: i as i32,
                    source: SOURCE.into(),
                    level_name: self.level_name.clone(),
                    classification: "human".into(),
                    bbox: msgs::BoundingBox3D {
                        center: msgs::Pose {
                            position: msgs::Vector3 {
                                x: round_mm(pos.x),
                                y: round_mm(pos.y),
                                z: round_mm(self.z + PERSON_HEIGHT / 2.0),
                            },
                            orientation: msgs::Quaternion {
                                x: 0.0,
                                y: 0.0,
                                z: round_mm(half.sin() * 1000.0) / 1000.0,
                                w: round_mm(half.cos() * 1000.0) / 1000.0,
                            },
                        },
                        size: msgs::Vector3 {
                            x: 2.0 * r,
                            y: 2.0 * r,
                            z: PERSON_HEIGHT,
                        },
                    },
                    data_resolution: 0.0,
                    data: Vec::new(),
                    // Valid until the next message and one more.
                    lifetime: msgs::Time { sec: 1, nanosec: 0 },
                    action: msgs::OBSTACLE_ACTION_ADD,
                }
            })
            .collect();
        msgs::Obstacles {
            header: msgs::Header {
                stamp,
                frame_id: "map".into(),
            },
            obstacles,
        }
    }

    /// People positions in the map frame.
    #[cfg(test)]
    pub fn positions(&self) -> Vec<Vec2> {
        self.people
            .iter()
            .map(|p| p.pos.plus(self.mesh.origin))
            .collect()
    }

    pub fn report(&self, end: f64) -> CrowdReport {
        self.stats.report(self.people.len(), end, &self.people)
    }
}

/// The level people walk on (see the module doc).
fn crowd_level(b: &Building) -> Option<Handle<Level>> {
    let has_lanes = |h: Handle<Level>| !b.levels[h].human_lanes.is_empty();
    let c = b.crowd_sim.as_ref()?;
    let named = c.obstacle_set.as_ref().and_then(|o| {
        b.levels
            .iter()
            .find(|(_, l)| o.file_name == format!("{}_navmesh.nav", l.name))
            .map(|(h, _)| h)
    });
    let goal = || {
        c.goal_sets
            .iter()
            .flat_map(|g| g.set_area.iter())
            .find_map(|a| {
                b.vertices
                    .iter()
                    .find(|(_, v)| v.roles.human_goal_set_name.as_deref() == Some(a.as_str()))
                    .map(|(_, v)| v.level)
            })
    };
    named
        .filter(|&h| has_lanes(h))
        .or_else(|| goal().filter(|&h| has_lanes(h)))
        .or_else(|| b.levels.iter().map(|(h, _)| h).find(|&h| has_lanes(h)))
}

fn f32v(v: Vec2) -> dodgy_2d::Vec2 {
    dodgy_2d::Vec2::new(v.x as f32, v.y as f32)
}

/// The length of `v`: a square root where `Vec2::norm` calls libm's `hypot` (which guards
/// against overflow that metre-scale vectors never reach, at several times the cost; a
/// tenth of the crowd step's time went there).
#[inline]
fn len(v: Vec2) -> f64 {
    (v.x * v.x + v.y * v.y).sqrt()
}

fn seg_dist(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let d = b.minus(a);
    let l2 = d.x * d.x + d.y * d.y;
    let t = if l2 > 0.0 {
        ((p.x - a.x) * d.x + (p.y - a.y) * d.y) / l2
    } else {
        0.0
    };
    len(a.plus(d.scale(t.clamp(0.0, 1.0))).minus(p))
}

fn round_mm(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

impl People for Crowd {
    fn any_within(&self, p: [f64; 3], r: f64) -> bool {
        Crowd::any_within(self, p, r)
    }
}
