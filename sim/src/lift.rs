//! The lift plugin (runtime spec §4.1–§4.6): cabin motion with the building profile, its
//! cabin and shaft doors, LiftState on change and at 1 Hz, and robots riding the cabin.
//!
//! Differences from the plugin (its quirks, §4.3), intended behaviour:
//! - A request is compared with the reference command including its `door_state`, so a
//!   request that only changes the doors (e.g. close them at the current floor) is
//!   accepted instead of ignored.
//! - END_SESSION is compared as stored (empty session), so a repeated END_SESSION is a
//!   no-op rather than "different" (re-accepted when idle, dropped when busy).
//! - `available_floors` keeps the map's order (`level_doors`), not a hash order.
//! - With `lifts_start_at_initial_floor` (the default) the cabin starts at its initial
//!   floor; otherwise, as in Gazebo, at z = 0 and drives there first (§4.2).
//! - Payloads: robots standing on the cabin floor ride with it (origin within the cabin's
//!   footprint, turned with the cabin, and within the floor's thickness of its height);
//!   items attached to a robot follow the robot. The plugin carries whatever lies in the
//!   cabin's axis-aligned bounding box, from under its floor to its roof: a robot waiting
//!   on the landing beside a turned cabin, or standing on the floor above the cabin's
//!   path, would be lifted off its floor and left between floors.
//! - A cabin that stops at a floor is at the floor's elevation exactly, and so is what
//!   stands on it (Gazebo's contacts keep a robot on the cabin floor; here each stop's
//!   error stayed with the robot until a cabin left it behind).

use crate::msgs::{
    door_mode, lift_request, lift_state, LiftRequest, LiftState, Msg, Published, Time, Topic,
};
use crate::profile::{self, Limits};
use crate::truth::{Body, DoorControl};

/// Generator values (§4.1).
pub(crate) const CABIN: Limits = Limits {
    v_max: 2.0,
    a_max: 1.2,
    a_nom: 1.0,
};
pub(crate) const CABIN_DX_MIN: f64 = 0.001;
/// Cabin floor thickness (§4.6): a robot's origin down to this below the cabin floor's
/// top, or up to `ON_FLOOR` above it, stands on it.
const FLOOR_THICKNESS: f64 = 0.05;
const ON_FLOOR: f64 = 0.01;

/// The cabin's footprint: where a robot stands on its floor.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cabin {
    /// Centre, world frame.
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
    /// Half its width and depth (with the shaft's margin).
    pub half: [f64; 2],
}

impl Cabin {
    /// Whether a robot at `(x, y, z)` stands on the floor of this cabin at height `floor`.
    fn holds(&self, [x, y, z]: [f64; 3], floor: f64) -> bool {
        let (dx, dy) = (x - self.x, y - self.y);
        let (s, c) = self.yaw.sin_cos();
        let (u, v) = (c * dx + s * dy, -s * dx + c * dy);
        u.abs() <= self.half[0]
            && v.abs() <= self.half[1]
            && (floor - FLOOR_THICKNESS..=floor + ON_FLOOR).contains(&z)
    }
}

#[derive(Debug, Clone)]
pub(crate) struct Floor {
    pub name: String,
    pub elevation: f64,
    /// Door indices, per door pair: the shaft door then the cabin door.
    pub doors: Vec<usize>,
}

#[derive(Debug, Clone, PartialEq)]
struct Cmd {
    request_type: u8,
    dest: usize,
    session: String,
    door_open: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Compact {
    cur: usize,
    dest: usize,
    door: u8,
    motion: u8,
}

#[derive(Debug)]
pub(crate) struct LiftSim {
    pub name: String,
    pub floors: Vec<Floor>,
    pub z: f64,
    last_v: f64,
    /// Cabin velocity commanded this step.
    pub v: f64,
    last_cmd: Cmd,
    active: Option<Cmd>,
    last_state: Option<(Compact, String)>,
    last_pub: f64,
    cabin: Cabin,
    first: bool,
}

impl LiftSim {
    pub fn new(name: String, floors: Vec<Floor>, initial: usize, z: f64, cabin: Cabin) -> Self {
        let cmd = Cmd {
            request_type: lift_request::AGV_MODE,
            dest: initial,
            session: String::new(),
            door_open: false,
        };
        LiftSim {
            name,
            floors,
            z,
            last_v: 0.0,
            v: 0.0,
            last_cmd: cmd.clone(),
            active: Some(cmd),
            last_state: None,
            last_pub: 0.0,
            cabin,
            first: true,
        }
    }

    pub fn set_phase(&mut self, phase: f64) {
        self.last_pub = phase;
    }

    /// Destination floor of the active command.
    #[cfg(test)]
    pub fn active_dest(&self) -> Option<usize> {
        self.active.as_ref().map(|c| c.dest)
    }

    /// `/lift_requests` (§4.3).
    pub fn request(&mut self, msg: &LiftRequest) {
        let Some(dest) = self
            .floors
            .iter()
            .position(|f| f.name == msg.destination_floor)
        else {
            return;
        };
        let end = msg.request_type == lift_request::END_SESSION;
        let same = |c: &Cmd| {
            c.dest == dest
                && c.request_type == msg.request_type
                && c.door_open == (msg.door_state == lift_request::DOOR_OPEN)
                && if end {
                    c.session.is_empty()
                } else {
                    c.session == msg.session_id
                }
        };
        // Busy: identical is a no-op, anything else is dropped (not queued).
        if self.active.is_some() {
            return;
        }
        if same(&self.last_cmd) {
            return;
        }
        let cmd = Cmd {
            request_type: msg.request_type,
            dest,
            session: if end {
                String::new()
            } else {
                msg.session_id.clone()
            },
            door_open: msg.door_state == lift_request::DOOR_OPEN,
        };
        self.last_cmd = cmd.clone();
        self.active = Some(cmd);
    }

    fn cur_floor(&self) -> usize {
        let mut best = 0;
        let mut bd = f64::INFINITY;
        for (i, f) in self.floors.iter().enumerate() {
            let d = (f.elevation - self.z).abs();
            if d < bd {
                bd = d;
                best = i;
            }
        }
        best
    }

    fn door_state(&self, cur: usize, doors: &[impl DoorControl]) -> u8 {
        let modes = || {
            self.floors[cur]
                .doors
                .iter()
                .filter_map(|&d| doors.get(d))
                .map(|d| d.mode())
        };
        if modes().all(|m| m == door_mode::OPEN) {
            lift_state::DOOR_OPEN
        } else if modes().all(|m| m == door_mode::CLOSED) {
            lift_state::DOOR_CLOSED
        } else {
            lift_state::DOOR_MOVING
        }
    }

    fn compact(&self, cur: usize, doors: &[impl DoorControl]) -> Compact {
        let (dest, motion) = match &self.active {
            Some(c) => {
                let target = self.floors[c.dest].elevation;
                let m = if (target - self.z).abs() < CABIN_DX_MIN {
                    lift_state::MOTION_STOPPED
                } else if target > self.z {
                    lift_state::MOTION_UP
                } else {
                    lift_state::MOTION_DOWN
                };
                (c.dest, m)
            }
            None => (cur, lift_state::MOTION_STOPPED),
        };
        Compact {
            cur,
            dest,
            door: self.door_state(cur, doors),
            motion,
        }
    }

    fn publish(&self, t: f64, c: Compact, out: &mut Vec<Published>) {
        let name = |i: usize| {
            self.floors
                .get(i)
                .map(|f| f.name.clone())
                .unwrap_or_default()
        };
        out.push(Published {
            t,
            topic: Topic::LiftStates,
            msg: Msg::LiftState(LiftState {
                lift_time: Time::from_secs(t),
                lift_name: self.name.clone(),
                available_floors: self.floors.iter().map(|f| f.name.clone()).collect(),
                current_floor: name(c.cur),
                destination_floor: name(c.dest),
                door_state: c.door,
                motion_state: c.motion,
                available_modes: Vec::new(),
                current_mode: lift_state::MODE_AGV,
                session_id: self.last_cmd.session.clone(),
            }),
        });
    }

    fn store_and_publish_if_changed(
        &mut self,
        t: f64,
        c: Compact,
        force: bool,
        out: &mut Vec<Published>,
    ) {
        let changed = match &self.last_state {
            Some((lc, ls)) => *lc != c || *ls != self.last_cmd.session,
            None => true,
        };
        if changed {
            self.last_state = Some((c, self.last_cmd.session.clone()));
        }
        if changed || force {
            self.publish(t, c, out);
        }
    }

    /// One manager update (§4.4, §4.5); sets `self.v` and the z velocity of the robots
    /// in the cabin.
    pub fn update(
        &mut self,
        t: f64,
        dt: f64,
        doors: &mut [impl DoorControl],
        robots: &mut [impl Body],
        out: &mut Vec<Published>,
    ) {
        self.v = 0.0;
        if self.first {
            self.first = false;
            return;
        }
        let cur = self.cur_floor();
        let cmd = self.active.as_ref().unwrap_or(&self.last_cmd);
        let (dest, door_open) = (cmd.dest, cmd.door_open);
        let target = self.floors.get(dest).map_or(self.z, |f| f.elevation);
        let mut finished = false;
        if (self.z - target).abs() < CABIN_DX_MIN {
            // Stopped at the floor: the cabin and what stands on it are at the floor's
            // elevation exactly. (A ride stops within `CABIN_DX_MIN` of it, and a robot kept
            // the last stop's error: over some hundred rides its height walked off the
            // cabin floor's, the cabin left it behind, and the fleet drove a robot it
            // thought on the floor below into robots on this one: seven robots stood
            // still for the last four of eight hours on a public clinic map.)
            if self.z != target {
                for r in robots.iter_mut() {
                    let [x, y, z, _] = r.pose();
                    if self.cabin.holds([x, y, z], self.z) {
                        r.settle(target);
                    }
                }
                self.z = target;
            }
            let want = if door_open {
                door_mode::OPEN
            } else {
                door_mode::CLOSED
            };
            let mut all = true;
            for &d in &self.floors[cur].doors {
                if let Some(door) = doors.get_mut(d) {
                    door.command(door_open);
                    all &= door.mode() == want;
                }
            }
            finished = dest == cur && all;
        } else {
            let mut closed = true;
            for &d in &self.floors[cur].doors {
                if let Some(door) = doors.get_mut(d) {
                    door.command(false);
                    closed &= door.mode() == door_mode::CLOSED;
                }
            }
            if closed {
                let mut s = target - self.z;
                if s.abs() < CABIN_DX_MIN / 2.0 {
                    s = 0.0;
                }
                let v = profile::building(s, self.last_v, CABIN, dt);
                self.last_v = v;
                self.v = v;
                if v != 0.0 {
                    for r in robots.iter_mut() {
                        let [x, y, z, _] = r.pose();
                        if self.cabin.holds([x, y, z], self.z) {
                            r.ride(v);
                        }
                    }
                }
            }
        }
        if self.active.is_some() || self.last_state.is_none() || self.v != 0.0 || !finished {
            let c = self.compact(cur, doors);
            self.store_and_publish_if_changed(t, c, false, out);
        }
        if finished {
            self.active = None;
        }
        if t - self.last_pub >= 1.0 {
            self.last_pub = t;
            let c = self.compact(cur, doors);
            self.store_and_publish_if_changed(t, c, true, out);
        }
    }

    #[inline]
    pub fn integrate(&mut self, dt: f64) {
        if self.v != 0.0 {
            self.z += self.v * dt;
        }
    }
}

#[cfg(test)]
mod cabin_tests {
    use super::Cabin;

    #[test]
    fn a_turned_cabin_holds_its_floor_not_its_bounding_box() {
        // 2.5 m × 3 m, turned 45°: its axis-aligned hull reaches 1.94 m from the centre
        // along x, the cabin itself 1.25 m (across) to 1.5 m (along its depth).
        let c = Cabin {
            x: 10.0,
            y: -5.0,
            yaw: std::f64::consts::FRAC_PI_4,
            half: [1.25, 1.5],
        };
        assert!(c.holds([10.0, -5.0, 4.0], 4.0));
        // Inside the hull, outside the cabin: the landing beside it.
        assert!(!c.holds([11.8, -5.0, 4.0], 4.0));
        // 1.4 m along its depth (turned), inside.
        let (s, co) = std::f64::consts::FRAC_PI_4.sin_cos();
        assert!(c.holds([10.0 - 1.4 * s, -5.0 + 1.4 * co, 4.0], 4.0));
        // On its floor, just under its top (thickness 5 cm), not above it.
        assert!(c.holds([10.0, -5.0, 3.96], 4.0));
        assert!(!c.holds([10.0, -5.0, 3.9], 4.0));
        assert!(!c.holds([10.0, -5.0, 4.5], 4.0));
    }
}

#[cfg(test)]
mod ride_tests {
    use super::*;

    /// A robot as the lift sees it: a pose and the z velocity a ride gives it.
    struct Rider {
        pose: [f64; 4],
        vz: f64,
    }

    impl Body for Rider {
        fn pose(&self) -> [f64; 4] {
            self.pose
        }
        fn ride(&mut self, vz: f64) {
            self.vz = vz;
        }
        fn settle(&mut self, z: f64) {
            self.pose[2] = z;
        }
    }

    /// A cabin or shaft door that is where it was told at once.
    struct Door(u32);

    impl DoorControl for Door {
        fn command(&mut self, open: bool) {
            self.0 = if open {
                door_mode::OPEN
            } else {
                door_mode::CLOSED
            };
        }
        fn mode(&self) -> u32 {
            self.0
        }
    }

    /// Rides between three floors at uneven heights, hundreds of times: the robot on the
    /// cabin floor rides every time and stops at each floor's elevation exactly (it used
    /// to keep each stop's error, until the cabin left it behind).
    #[test]
    fn a_robot_rides_every_time_and_stops_at_the_floor() {
        let elevations = [0.0, 3.7, 11.13];
        let floors: Vec<Floor> = elevations
            .iter()
            .enumerate()
            .map(|(i, &elevation)| Floor {
                name: format!("L{i}"),
                elevation,
                doors: Vec::new(),
            })
            .collect();
        let cabin = Cabin {
            x: 2.0,
            y: -1.0,
            yaw: 0.3,
            half: [1.1, 1.25],
        };
        let mut lift = LiftSim::new("lift".into(), floors, 0, 0.0, cabin);
        let mut doors: Vec<Door> = Vec::new();
        let mut robot = [Rider {
            pose: [2.1, -0.9, 0.0, 0.0],
            vz: 0.0,
        }];
        let (dt, mut t) = (0.05, 0.0);
        let mut out = Vec::new();
        // Its start: the first update only begins, the initial floor's command then ends.
        for _ in 0..3 {
            lift.update(t, dt, &mut doors, &mut robot, &mut out);
            t += dt;
        }
        assert_eq!(lift.active_dest(), None);
        for ride in 0..600 {
            let dest = [1, 2, 0, 2, 1, 0][ride % 6];
            lift.request(&LiftRequest {
                lift_name: "lift".into(),
                request_time: Time::default(),
                session_id: "r".into(),
                request_type: lift_request::AGV_MODE,
                destination_floor: format!("L{dest}"),
                door_state: lift_request::DOOR_OPEN,
            });
            let mut steps = 0;
            while lift.active_dest().is_some() {
                lift.update(t, dt, &mut doors, &mut robot, &mut out);
                lift.integrate(dt);
                let r = &mut robot[0];
                r.pose[2] += r.vz * dt;
                r.vz = 0.0;
                assert!(
                    (r.pose[2] - lift.z).abs() < ON_FLOOR,
                    "ride {ride}: left behind at {} with the cabin at {}",
                    r.pose[2],
                    lift.z
                );
                t += dt;
                steps += 1;
                assert!(steps < 10_000, "ride {ride} never ends");
            }
            assert_eq!(robot[0].pose[2], elevations[dest], "ride {ride}");
            assert_eq!(lift.z, elevations[dest], "ride {ride}");
        }
    }
}
