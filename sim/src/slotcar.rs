//! The diff-drive slotcar (runtime spec §1.1–§1.11).
//!
//! Differences from the plugin at HEAD (its quirks, §1.4–§1.9), all intended behaviour:
//! - Heading error is the true signed angle (`atan2`), not `asin` of the sine: turns of
//!   more than 90° (and exactly 180°) toward a requested yaw work, and a non-reversible
//!   robot turns around toward a waypoint behind it instead of driving away.
//! - No one-step glitch: on the step a waypoint is reached the heading and the distance
//!   are taken to the *new* target (and its speed limit); when the last waypoint is
//!   reached the final turn starts on the same step.
//! - Path requests: the first request is accepted even with an empty `task_id` (upstream
//!   compares with the initial "" and drops it).
//! - Adapter error (first waypoint > 1 m away): the robot holds position and keeps the
//!   previous remaining path as is (upstream drops its first element one step later).
//! - Mode bookkeeping: the yaw change between steps is wrapped to (-π, π] (upstream's
//!   wrap uses the last commanded direction and can misfire; only |ω| and the battery's
//!   angular acceleration term see the difference).
//! - A reversing robot checks for obstacles behind it (the direction it drives), not in
//!   front of its body.
//! - Obstacles are the other robots only (no other non-static models exist headless).
//! - Level lookup keeps the robot's current level (its spawn level at first) while its z
//!   still matches it, so levels sharing an elevation are told apart; upstream takes the
//!   first level in map order.
//! - `PAUSE_AT_CHECKPOINT` with no remaining path entry (adapter-error hold) does not
//!   pause (upstream reads past the end of the path).

use crate::msgs::{
    pause_type, robot_mode, Location, Msg, PathRequest, Published, RobotMode, RobotState, Time,
    Topic,
};
use crate::params::RobotParams;
use crate::profile::{self, Limits};
use crate::truth::{Body, Item, People};
use std::f64::consts::PI;

const WAYPOINT_TOL: f64 = 0.02;
const WAYPOINT_TOL_ROTATING: f64 = 0.04;
const DRIVE_HEADING_TOL: f64 = 5.0 * PI / 180.0;
const STATIONARY: f64 = 0.01;
const CHARGER_RADIUS: f64 = 0.3;
const INITIAL_DISTANCE: f64 = 1.0;
const LEVEL_TOL: f64 = 0.1;
const STATE_PERIOD: f64 = 0.5;
const CART_ATTACH: f64 = 1.0;

/// Wraps an angle to (-π, π].
#[inline]
pub(crate) fn wrap(a: f64) -> f64 {
    if a > PI || a <= -PI {
        let r = (a + PI).rem_euclid(2.0 * PI) - PI;
        if r <= -PI {
            r + 2.0 * PI
        } else {
            r
        }
    } else {
        a
    }
}

#[derive(Debug, Clone, Copy)]
struct Waypoint {
    x: f64,
    y: f64,
    yaw: f64,
    limit: Option<f64>,
}

/// The world-wide `/charge_state` toggles (§1.9).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ChargeFlags {
    pub enable_charge: bool,
    pub enable_instant_charge: bool,
    pub enable_drain: bool,
}

impl Default for ChargeFlags {
    fn default() -> Self {
        ChargeFlags {
            enable_charge: true,
            enable_instant_charge: false,
            enable_drain: true,
        }
    }
}

/// Robot positions at the start of a step, for the obstacle test (§1.8). Above 8 robots
/// they are bucketed by a spatial hash over a uniform grid whose cells are twice the
/// largest stop radius (a counting sort into ~2n buckets, rebuilt every step: linear);
/// a query visits the 2×2 cells a stop disc can touch.
#[derive(Debug, Default)]
pub(crate) struct Obstacles {
    pos: Vec<[f64; 3]>,
    inv_cell: f64,
    mask: usize,
    /// Bucket b holds `items[start[b]..start[b + 1]]`.
    start: Vec<u32>,
    cursor: Vec<u32>,
    items: Vec<u32>,
    bucket: Vec<u32>,
}

const BRUTE_FORCE_MAX: usize = 8;

impl Obstacles {
    /// Cell coordinate and the position inside the cell (0..1).
    #[inline]
    fn cell_of(&self, v: f64) -> (i64, f64) {
        // `floor` without the libm call (`as` saturates, NaN gives 0).
        let q = v * self.inv_cell;
        let t = q as i64;
        let i = t - i64::from((t as f64) > q);
        (i, q - i as f64)
    }

    #[inline]
    fn col_hash(col: i64) -> u64 {
        (col as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
    }

    #[inline]
    fn row_hash(row: i64) -> u64 {
        (row as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
    }

    #[inline]
    fn bucket_of(&self, h: u64) -> usize {
        (h >> 32) as usize & self.mask
    }

    pub fn rebuild(&mut self, cars: &[Slotcar]) {
        self.pos.clear();
        self.pos.extend(cars.iter().map(|c| [c.x, c.y, c.z]));
        let n = self.pos.len();
        if n <= BRUTE_FORCE_MAX {
            return;
        }
        if self.items.len() != n {
            // Cells twice the largest stop radius: a stop disc then touches ≤ 2×2 cells.
            let cell = 2.0 * cars.iter().map(|c| c.p.stop_radius).fold(0.25, f64::max);
            self.inv_cell = 1.0 / cell;
            let buckets = (2 * n).next_power_of_two();
            self.mask = buckets - 1;
            self.start = vec![0; buckets + 1];
            self.cursor = vec![0; buckets];
            self.items = vec![0; n];
            self.bucket = vec![0; n];
        }
        self.start.fill(0);
        for i in 0..n {
            let p = self.pos[i];
            let h = Self::col_hash(self.cell_of(p[0]).0) ^ Self::row_hash(self.cell_of(p[1]).0);
            let b = self.bucket_of(h);
            self.bucket[i] = b as u32;
            self.start[b + 1] += 1;
        }
        for b in 0..self.mask + 1 {
            self.start[b + 1] += self.start[b];
        }
        self.cursor.copy_from_slice(&self.start[..self.mask + 1]);
        for i in 0..n {
            let b = self.bucket[i] as usize;
            let k = self.cursor[b] as usize;
            self.cursor[b] += 1;
            if let Some(slot) = self.items.get_mut(k) {
                *slot = i as u32;
            }
        }
    }

    /// Is any robot other than `me` closer than `r` (3-D) to `p`? `r` must not exceed the
    /// largest stop radius of the robots given to `rebuild` (the robots' own radii).
    pub fn any_within(&self, me: usize, p: [f64; 3], r: f64) -> bool {
        let r2 = r * r;
        let hit = |i: usize, q: &[f64; 3]| {
            let (dx, dy, dz) = (q[0] - p[0], q[1] - p[1], q[2] - p[2]);
            dx * dx + dy * dy + dz * dz < r2 && i != me
        };
        if self.pos.len() <= BRUTE_FORCE_MAX {
            return self.pos.iter().enumerate().any(|(i, q)| hit(i, q));
        }
        // A disc of radius r ≤ cell/2 touches at most the 2×2 cells on the sides of the
        // point's cell that it is nearest to. (Two cells sharing a bucket are visited
        // twice: harmless for "any".)
        let ((col, fx), (row, fy)) = (self.cell_of(p[0]), self.cell_of(p[1]));
        let c0 = col - i64::from(fx < 0.5);
        let r0 = row - i64::from(fy < 0.5);
        let (h0, h1) = (Self::col_hash(c0), Self::col_hash(c0 + 1));
        let (v0, v1) = (Self::row_hash(r0), Self::row_hash(r0 + 1));
        let (start, items, pos) = (&self.start[..], &self.items[..], &self.pos[..]);
        for h in [h0 ^ v0, h1 ^ v0, h0 ^ v1, h1 ^ v1] {
            let b = self.bucket_of(h);
            let (Some(&s), Some(&e)) = (start.get(b), start.get(b + 1)) else {
                continue;
            };
            for &i in items.get(s as usize..e as usize).unwrap_or(&[]) {
                if let Some(q) = pos.get(i as usize) {
                    if hit(i as usize, q) {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// What a slotcar needs from the world in its update.
pub(crate) struct Ctx<'a> {
    pub t: f64,
    pub dt: f64,
    pub levels: &'a [(String, f64)],
    pub chargers: &'a [[f64; 3]],
    pub obstacles: &'a Obstacles,
    pub flags: ChargeFlags,
    /// People are obstacles too (upstream's crowd actors are not, runtime.md §1.8).
    pub people: Option<&'a dyn People>,
}

#[derive(Debug)]
pub(crate) struct Slotcar {
    pub name: String,
    p: RobotParams,
    lin: Limits,
    ang: Limits,
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub yaw: f64,
    cos: f64,
    sin: f64,
    old: [f64; 3],
    initialized: bool,
    trajectory: Vec<Waypoint>,
    wp_idx: usize,
    remaining: Vec<Location>,
    /// `remaining[rem_start..]` is the plugin's `remaining_path`.
    rem_start: usize,
    task_id: Option<String>,
    adapter_error: bool,
    pause_kind: u32,
    pause_id: u64,
    pause_at: u32,
    mode: RobotMode,
    pub soc: f64,
    old_lin_vel: [f64; 2],
    old_ang_vel: f64,
    was_rotating: bool,
    /// Open-loop commanded forward speed and yaw rate.
    pub v: f64,
    pub w: f64,
    /// World z velocity for this step, set by a lift carrying the robot (§4.6).
    pub vz: f64,
    last_state_pub: f64,
    last_update: f64,
    seq: u64,
    level: Option<usize>,
    level_z: f64,
    /// Near-charger cache: while the robot stays within `charger_safe` (the distance of
    /// the nearest charger from the 0.3 m radius) of `charger_ref`, the answer stays
    /// `charger_near` (triangle inequality).
    charger_ref: [f64; 3],
    charger_safe: f64,
    charger_near: bool,
    /// Index of the cart attached by `attach_cart` (§1.11).
    cart: Option<usize>,
    /// State of charge per joule: 1 / (V · Ah · 3600).
    per_joule: f64,
}

impl Slotcar {
    /// A robot at rest at `(x, y, z, yaw)` on level `level` (index into the world's
    /// levels, if known).
    pub fn new(name: String, p: RobotParams, pose: [f64; 4], level: Option<usize>) -> Self {
        let [x, y, z, yaw] = pose;
        let lin = Limits {
            v_max: p.nominal_drive_speed,
            a_max: p.max_drive_acceleration,
            a_nom: p.nominal_drive_acceleration,
        };
        let ang = Limits {
            v_max: p.nominal_turn_speed,
            a_max: p.max_turn_acceleration,
            a_nom: p.nominal_turn_acceleration,
        };
        let yaw = wrap(yaw);
        let (sin, cos) = yaw.sin_cos();
        let per_joule = 1.0 / (p.nominal_voltage * p.nominal_capacity * 3600.0);
        Slotcar {
            name,
            p,
            lin,
            ang,
            x,
            y,
            z,
            yaw,
            cos,
            sin,
            old: [x, y, yaw],
            initialized: false,
            trajectory: Vec::new(),
            wp_idx: 0,
            remaining: Vec::new(),
            rem_start: 0,
            task_id: None,
            adapter_error: false,
            pause_kind: pause_type::RESUME,
            pause_id: 0,
            pause_at: 0,
            mode: RobotMode {
                mode: robot_mode::MOVING,
                ..RobotMode::default()
            },
            soc: 1.0,
            old_lin_vel: [0.0; 2],
            old_ang_vel: 0.0,
            was_rotating: false,
            v: 0.0,
            w: 0.0,
            vz: 0.0,
            last_state_pub: 0.0,
            last_update: 0.0,
            seq: 0,
            level,
            level_z: f64::NAN,
            charger_ref: [f64::NAN; 3],
            charger_safe: 0.0,
            charger_near: false,
            cart: None,
            per_joule,
        }
    }

    pub fn footprint(&self) -> f64 {
        self.p.footprint
    }

    pub fn mode(&self) -> u32 {
        if self.adapter_error {
            robot_mode::ADAPTER_ERROR
        } else {
            self.mode.mode
        }
    }

    /// `/robot_path_requests` (§1.4).
    pub fn path_request(&mut self, msg: PathRequest) {
        if self.task_id.as_deref() == Some(msg.task_id.as_str()) || msg.path.is_empty() {
            return;
        }
        self.task_id = Some(msg.task_id);
        self.adapter_error = false;
        let mut trajectory: Vec<Waypoint> = msg
            .path
            .iter()
            .map(|l| Waypoint {
                x: l.x,
                y: l.y,
                yaw: l.yaw,
                limit: (l.obey_approach_speed_limit && l.approach_speed_limit > 0.0)
                    .then_some(l.approach_speed_limit),
            })
            .collect();
        self.wp_idx = 0;
        let first = &msg.path[0];
        let d0 = (first.x - self.x).hypot(first.y - self.y);
        if d0 > INITIAL_DISTANCE {
            // Hold where we are; keep the old remaining path so the adapter sees it.
            self.trajectory = vec![Waypoint {
                x: self.x,
                y: self.y,
                yaw: self.yaw,
                limit: None,
            }];
            self.adapter_error = true;
            return;
        }
        trajectory.remove(0);
        let mut path = msg.path;
        path.remove(0);
        self.trajectory = trajectory;
        self.remaining = path;
        self.rem_start = 0;
    }

    /// `/robot_mode_requests` (§1.7): the mode is taken verbatim.
    pub fn mode_request(&mut self, mode: RobotMode) {
        self.mode = mode;
    }

    /// `/robot_pause_requests` (§1.5): latest wins.
    pub fn pause_request(&mut self, kind: u32, id: u64, at_checkpoint: u32) {
        self.pause_kind = kind;
        self.pause_id = id;
        self.pause_at = at_checkpoint;
    }

    fn level_name<'a>(&mut self, levels: &'a [(String, f64)]) -> Option<&'a str> {
        if self.z != self.level_z {
            self.level_z = self.z;
            let on = |i: usize| {
                levels
                    .get(i)
                    .is_some_and(|l| (l.1 - self.z).abs() < LEVEL_TOL)
            };
            // Keep the remembered level while it matches: levels sharing an elevation
            // would otherwise all report the first of them.
            if !self.level.is_some_and(on) {
                if let Some(i) = (0..levels.len()).find(|&i| on(i)) {
                    self.level = Some(i);
                }
            }
        }
        self.level.and_then(|i| levels.get(i)).map(|l| l.0.as_str())
    }

    fn publish(&mut self, t: f64, levels: &[(String, f64)], out: &mut Vec<Published>) {
        let Some(level) = self.level_name(levels) else {
            return;
        };
        self.seq += 1;
        let msg = RobotState {
            name: self.name.clone(),
            model: self.p.model.clone(),
            task_id: self.task_id.clone().unwrap_or_default(),
            seq: self.seq,
            mode: RobotMode {
                mode: self.mode(),
                mode_request_id: self.pause_id.max(self.mode.mode_request_id),
                performing_action: self.mode.performing_action.clone(),
            },
            battery_percent: (100.0 * self.soc).ceil(),
            location: Location {
                t: Time::from_secs(t),
                x: self.x,
                y: self.y,
                yaw: self.yaw,
                level_name: level.to_string(),
                ..Location::default()
            },
            path: self.remaining.get(self.rem_start..).unwrap_or(&[]).to_vec(),
        };
        out.push(Published {
            t,
            topic: Topic::RobotState,
            msg: Msg::RobotState(msg),
        });
    }

    fn near_charger(&mut self, chargers: &[[f64; 3]]) -> bool {
        let p = [self.x, self.y, self.z];
        let d2 = |q: &[f64; 3]| {
            let (a, b, c) = (q[0] - p[0], q[1] - p[1], q[2] - p[2]);
            a * a + b * b + c * c
        };
        // Cached answer while the robot stays within `charger_safe` of where it was
        // computed (NaN at first: recompute).
        if d2(&self.charger_ref) < self.charger_safe * self.charger_safe {
            return self.charger_near;
        }
        let d = chargers.iter().map(d2).fold(f64::INFINITY, f64::min).sqrt();
        self.charger_ref = p;
        self.charger_near = d < CHARGER_RADIUS;
        self.charger_safe = (d - CHARGER_RADIUS).abs();
        self.charger_near
    }

    /// Heading error toward the vector `(dx, dy)` of length `d` (§1.4, with `atan2`):
    /// `(e, dir)`.
    #[inline]
    fn heading_to(&self, dx: f64, dy: f64, d: f64) -> (f64, f64) {
        if d < 1e-3 {
            return (0.0, 1.0);
        }
        let (mut tx, mut ty, mut dir) = (dx, dy, 1.0);
        if self.p.reversible && self.cos * tx + self.sin * ty < 0.0 {
            tx = -tx;
            ty = -ty;
            dir = -1.0;
        }
        let cross = self.cos * ty - self.sin * tx;
        let dot = self.cos * tx + self.sin * ty;
        // Nearly aligned (the common case while driving): atan2(c, d) = c/d − (c/d)³/3 + …,
        // so c/d is exact to 1e-12 relative; saves the libm call.
        if dot > 0.0 && cross.abs() < 1e-4 * dot {
            return (cross / dot, dir);
        }
        (cross.atan2(dot), dir)
    }

    /// One plugin update at time `ctx.t` (§1.3 steps 2–10); the pose is integrated later
    /// by [`Slotcar::integrate`].
    pub fn update(&mut self, ctx: &Ctx, me: usize, items: &mut [Item], out: &mut Vec<Published>) {
        let t = ctx.t;
        if t - self.last_state_pub > STATE_PERIOD {
            self.last_state_pub = t;
            self.publish(t, ctx.levels, out);
        }
        let dt_u = t - self.last_update;
        self.last_update = t;
        if self.initialized && dt_u > 0.0 {
            self.bookkeeping(ctx, dt_u, me, items);
        }
        self.old = [self.x, self.y, self.yaw];
        self.initialized = true;

        if self.trajectory.is_empty() {
            if self.v == 0.0 && self.w == 0.0 {
                return;
            }
            self.v = profile::robot(0.0, self.v, 0.0, 0.0, self.lin, ctx.dt);
            self.w = profile::robot(0.0, self.w, 0.0, 0.0, self.ang, ctx.dt);
            return;
        }
        let (mut s_lin, mut v_now, mut limit) = (0.0, 0.0, None);
        let s_yaw;
        let mut dir = 1.0;
        let n = self.trajectory.len();
        if self.wp_idx < n {
            let wp = self.trajectory[self.wp_idx];
            limit = wp.limit;
            let (mut dx, mut dy) = (wp.x - self.x, wp.y - self.y);
            let mut d = (dx * dx + dy * dy).sqrt();
            let tol = if self.was_rotating {
                WAYPOINT_TOL_ROTATING
            } else {
                WAYPOINT_TOL
            };
            let close = d < tol;
            let at_checkpoint = self.pause_kind == pause_type::PAUSE_AT_CHECKPOINT
                && self
                    .remaining
                    .get(self.rem_start)
                    .is_some_and(|l| u64::from(self.pause_at) <= l.index);
            let pause = at_checkpoint || self.pause_kind == pause_type::PAUSE_IMMEDIATELY;
            let rotate = close && pause;
            self.was_rotating = rotate;
            if rotate {
                s_yaw = wrap(wp.yaw - self.yaw);
                self.mode.mode = robot_mode::PAUSED;
            } else {
                if close {
                    self.wp_idx += 1;
                    if !self.adapter_error && self.rem_start < self.remaining.len() {
                        self.rem_start += 1;
                    }
                    if let Some(next) = self.trajectory.get(self.wp_idx) {
                        limit = next.limit;
                        dx = next.x - self.x;
                        dy = next.y - self.y;
                        d = (dx * dx + dy * dy).sqrt();
                    }
                }
                if self.wp_idx < n {
                    let (e, di) = self.heading_to(dx, dy, d);
                    s_yaw = e;
                    if e.abs() < DRIVE_HEADING_TOL {
                        s_lin = di * d;
                        dir = di;
                        v_now = self.p.nominal_drive_speed;
                    }
                } else {
                    s_yaw = wrap(self.trajectory[n - 1].yaw - self.yaw);
                }
            }
        } else {
            s_yaw = wrap(self.trajectory[n - 1].yaw - self.yaw);
        }
        let immediate = self.pause_kind == pause_type::PAUSE_IMMEDIATELY;
        if immediate {
            s_lin = 0.0;
            self.mode.mode = robot_mode::PAUSED;
        }
        if v_now > 0.0 {
            let k = self.p.stop_distance * dir;
            let zone = [self.x + k * self.cos, self.y + k * self.sin, self.z];
            if ctx.obstacles.any_within(me, zone, self.p.stop_radius)
                || ctx
                    .people
                    .is_some_and(|c| c.any_within(zone, self.p.stop_radius))
            {
                s_lin = 0.0;
                self.mode.mode = if immediate {
                    robot_mode::PAUSED
                } else {
                    robot_mode::WAITING
                };
            }
        }
        let lin = Limits {
            v_max: limit.unwrap_or(self.p.nominal_drive_speed),
            ..self.lin
        };
        self.v = profile::robot(s_lin, self.v, v_now, 0.0, lin, ctx.dt);
        self.w = profile::robot(
            s_yaw,
            self.w,
            self.p.nominal_turn_speed,
            0.0,
            self.ang,
            ctx.dt,
        );
    }

    /// Battery and mode from the motion measured since the last update (§1.7, §1.9).
    fn bookkeeping(&mut self, ctx: &Ctx, dt_u: f64, me: usize, items: &mut [Item]) {
        let inv = 1.0 / dt_u;
        let vx = (self.old[0] - self.x) * inv;
        let vy = (self.old[1] - self.y) * inv;
        let ang_vel = wrap(self.yaw - self.old[2]) * inv;
        let lin_speed = (vx * vx + vy * vy).sqrt();
        let stationary = lin_speed < STATIONARY && ang_vel.abs() < STATIONARY;
        let near = self.near_charger(ctx.chargers);
        let f = ctx.flags;
        if stationary && near {
            if f.enable_instant_charge {
                self.soc = 1.0;
            } else if f.enable_charge {
                self.soc = (self.soc
                    + self.p.charging_current * dt_u / (self.p.nominal_capacity * 3600.0))
                    .min(1.0);
            }
        }
        if f.enable_drain && !near {
            let p = &self.p;
            let v = lin_speed.min(p.nominal_drive_speed);
            let w = ang_vel.abs().min(p.nominal_turn_speed);
            let (ax, ay) = (vx - self.old_lin_vel[0], vy - self.old_lin_vel[1]);
            let a = ((ax * ax + ay * ay).sqrt() * inv).min(p.max_drive_acceleration);
            let alpha = ((ang_vel - self.old_ang_vel).abs() * inv).min(p.max_turn_acceleration);
            let e_acc = (p.mass * a * v + p.inertia * alpha * w) * dt_u;
            let e_fric = p.friction_coefficient * p.mass * 9.81 * v * dt_u;
            let e_dev = p.nominal_power * dt_u;
            self.soc = (self.soc - (e_acc + e_fric + e_dev) * self.per_joule).max(0.0);
        }
        self.old_lin_vel = [vx, vy];
        self.old_ang_vel = ang_vel;

        let m = self.mode.mode;
        self.mode.mode = if stationary && near && (f.enable_instant_charge || f.enable_charge) {
            robot_mode::CHARGING
        } else if m == robot_mode::DOCKING || m == robot_mode::ACTION_COMPLETED {
            m
        } else if m == robot_mode::PERFORMING_ACTION {
            match self.mode.performing_action.as_str() {
                "attach_cart" => {
                    if self.attach_cart(me, items) {
                        robot_mode::ACTION_COMPLETED
                    } else {
                        robot_mode::IDLE
                    }
                }
                "detach_cart" => {
                    if let Some(c) = self.cart.take().and_then(|c| items.get_mut(c)) {
                        c.attached = None;
                    }
                    robot_mode::ACTION_COMPLETED
                }
                _ => robot_mode::IDLE,
            }
        } else if stationary {
            robot_mode::IDLE
        } else {
            robot_mode::MOVING
        };
    }

    /// §1.11: the nearest model whose name contains "dispensable", within 1 m.
    fn attach_cart(&mut self, me: usize, items: &mut [Item]) -> bool {
        let p = [self.x, self.y, self.z];
        let nearest = items
            .iter()
            .enumerate()
            .filter(|(_, it)| it.name.contains("dispensable"))
            .map(|(i, it)| (i, it.distance(p)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((i, d)) = nearest else {
            return false;
        };
        if d > CART_ATTACH {
            return false;
        }
        if self.cart.is_some() {
            return true;
        }
        if let Some(it) = items.get_mut(i) {
            it.attach(me, p, self.yaw);
        }
        self.cart = Some(i);
        true
    }

    /// Integrates the commanded twist over `dt` (after every plugin ran).
    #[inline]
    pub fn integrate(&mut self, dt: f64) {
        if self.w != 0.0 {
            let d = self.w * dt;
            self.yaw = wrap(self.yaw + d);
            if d.abs() < 1e-7 {
                // First-order rotation of the heading (error < d²/2 < 5e-15 per step);
                // tiny yaw rates are the rule while driving straight.
                let (s, c) = (self.sin, self.cos);
                self.sin = s + c * d;
                self.cos = c - s * d;
            } else {
                let (s, c) = self.yaw.sin_cos();
                self.sin = s;
                self.cos = c;
            }
        }
        if self.v != 0.0 {
            self.x += self.v * self.cos * dt;
            self.y += self.v * self.sin * dt;
        }
        if self.vz != 0.0 {
            self.z += self.vz * dt;
            self.vz = 0.0;
        }
    }
}

impl Body for Slotcar {
    #[inline]
    fn pose(&self) -> [f64; 4] {
        [self.x, self.y, self.z, self.yaw]
    }

    #[inline]
    fn ride(&mut self, vz: f64) {
        self.vz = vz;
    }

    #[inline]
    fn settle(&mut self, z: f64) {
        self.z = z;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_stays_in_half_open_interval() {
        for a in [0.0, PI, -PI, 3.0 * PI, -3.0 * PI, 7.5, -7.5, 1e-12] {
            let w = wrap(a);
            assert!(w > -PI && w <= PI, "{a} -> {w}");
            assert!(((w - a) / (2.0 * PI)).round() * 2.0 * PI - (w - a) < 1e-9);
        }
    }

    /// The spatial hash finds exactly what brute force finds.
    #[test]
    fn obstacle_grid_matches_brute_force() {
        let mut rng = fastrand::Rng::with_seed(3);
        for n in [9, 30, 100] {
            let mut cars: Vec<Slotcar> = (0..n)
                .map(|i| {
                    let p = RobotParams {
                        stop_radius: if i % 3 == 0 { 1.5 } else { 0.75 },
                        ..RobotParams::default()
                    };
                    let z = if i % 5 == 0 { 4.0 } else { 0.0 };
                    Slotcar::new(
                        format!("r{i}"),
                        p,
                        [rng.f64() * 20.0 - 10.0, rng.f64() * 20.0 - 10.0, z, 0.0],
                        None,
                    )
                })
                .collect();
            let mut obs = Obstacles::default();
            for round in 0..3 {
                for c in &mut cars {
                    c.x += rng.f64() - 0.5;
                    c.y += rng.f64() - 0.5;
                }
                obs.rebuild(&cars);
                for _ in 0..2000 {
                    let me = rng.usize(0..n);
                    let p = [rng.f64() * 24.0 - 12.0, rng.f64() * 24.0 - 12.0, 0.0];
                    let r = if rng.bool() { 1.5 } else { 0.75 };
                    let brute = cars.iter().enumerate().any(|(i, c)| {
                        let d =
                            ((c.x - p[0]).powi(2) + (c.y - p[1]).powi(2) + (c.z - p[2]).powi(2))
                                .sqrt();
                        i != me && d < r
                    });
                    assert_eq!(
                        obs.any_within(me, p, r),
                        brute,
                        "n={n} round={round} p={p:?} r={r}"
                    );
                }
            }
        }
    }
}
