//! The door plugin (runtime spec §2): one world-level manager stepping every door's
//! joints with the building profile. Lift cabin and shaft doors are doors too (no ROS
//! interface; the lift commands them).
//!
//! No difference from the plugin's behaviour. Headless details: joint positions are
//! integrated after every plugin ran (`pos += v·dt`); door positions are not modelled
//! (robots never collide with doors).

use crate::msgs::{door_mode, DoorMode, DoorState, Msg, Published, Time, Topic};
use crate::profile::{self, Limits};

#[derive(Debug, Clone, Copy)]
struct Joint {
    pos: f64,
    open: f64,
    closed: f64,
    v: f64,
}

/// Generator values of one door family (§2.1).
#[derive(Debug, Clone, Copy)]
pub(crate) struct DoorParams {
    pub limits: Limits,
    pub dx_min: f64,
}

pub(crate) const SLIDING: DoorParams = DoorParams {
    limits: Limits {
        v_max: 0.2,
        a_max: 0.2,
        a_nom: 0.08,
    },
    dx_min: 0.001,
};
pub(crate) const SWING: DoorParams = DoorParams {
    limits: Limits {
        v_max: 0.5,
        a_max: 0.3,
        a_nom: 0.15,
    },
    dx_min: 0.01,
};
pub(crate) const LIFT_DOOR: DoorParams = DoorParams {
    limits: Limits {
        v_max: 0.3,
        a_max: 0.2,
        a_nom: 0.1,
    },
    dx_min: 1e-4,
};

#[derive(Debug)]
pub(crate) struct DoorSim {
    pub name: String,
    pub ros: bool,
    joints: [Joint; 2],
    n: usize,
    params: DoorParams,
    pub open_cmd: bool,
    /// Mode from the joint positions at the start of the last update.
    pub mode: u32,
    last_pub: f64,
    /// At the commanded end with zero velocity: nothing moves until the command changes.
    settled: bool,
}

impl DoorSim {
    /// A door from `(lower, upper)` limits of its right and (optional) left joint: the
    /// right joint opens to `upper`, the left one to `lower` (§2.1). Starts closed.
    pub fn new(
        name: String,
        ros: bool,
        right: (f64, f64),
        left: Option<(f64, f64)>,
        params: DoorParams,
    ) -> DoorSim {
        let j = |closed: f64, open: f64| Joint {
            pos: 0.0,
            open,
            closed,
            v: 0.0,
        };
        let mut joints = [j(right.0, right.1); 2];
        let mut n = 1;
        if let Some((lo, hi)) = left {
            joints[1] = j(hi, lo);
            n = 2;
        }
        // First update: every joint at 0 (the generator's closed position).
        for jt in &mut joints {
            jt.pos = 0.0;
        }
        DoorSim {
            name,
            ros,
            joints,
            n,
            params,
            open_cmd: false,
            mode: door_mode::CLOSED,
            last_pub: 0.0,
            settled: false,
        }
    }

    pub fn set_phase(&mut self, phase: f64) {
        self.last_pub = phase;
    }

    /// Sets the command (OPEN when `open`, else CLOSE).
    #[inline]
    pub fn command(&mut self, open: bool) {
        if self.open_cmd != open {
            self.open_cmd = open;
            self.settled = false;
        }
    }

    fn classify(&self) -> u32 {
        let js = &self.joints[..self.n];
        let dx = self.params.dx_min;
        if js.iter().all(|j| (j.open - j.pos).abs() < dx) {
            door_mode::OPEN
        } else if js.iter().all(|j| (j.closed - j.pos).abs() < dx) {
            door_mode::CLOSED
        } else {
            door_mode::MOVING
        }
    }

    /// One manager update (§2.3) at `t`.
    pub fn update(&mut self, t: f64, dt: f64, out: &mut Vec<Published>) {
        if !self.settled {
            self.mode = self.classify();
            let half = self.params.dx_min / 2.0;
            let mut still = true;
            for j in &mut self.joints[..self.n] {
                let target = if self.open_cmd { j.open } else { j.closed };
                let mut s = target - j.pos;
                if s.abs() < half {
                    s = 0.0;
                }
                j.v = profile::building(s, j.v, self.params.limits, dt);
                still &= s == 0.0 && j.v == 0.0;
            }
            self.settled = still;
        }
        if self.ros && t - self.last_pub >= 1.0 {
            self.last_pub = t;
            out.push(Published {
                t,
                topic: Topic::DoorStates,
                msg: Msg::DoorState(DoorState {
                    door_time: Time::from_secs(t),
                    door_name: self.name.clone(),
                    current_mode: DoorMode { value: self.mode },
                }),
            });
        }
    }

    #[inline]
    pub fn integrate(&mut self, dt: f64) {
        if !self.settled {
            for j in &mut self.joints[..self.n] {
                j.pos += j.v * dt;
            }
        }
    }
}

impl crate::truth::DoorControl for DoorSim {
    fn command(&mut self, open: bool) {
        DoorSim::command(self, open);
    }

    fn mode(&self) -> u32 {
        self.mode
    }
}
