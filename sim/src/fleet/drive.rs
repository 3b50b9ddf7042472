//! Driving a route: PathRequests of the reserved edges, progress read back from
//! RobotState, door and lift sessions at the gates on the way.

use super::*;
use crate::report::timeline::{Buckets, Series};

/// Per IR lane, when robots drove it (the report's timeline).
///
/// Invariant: a lane's buckets hold exactly the spans robots were on it, each added when
/// the robot reached the lane's end (from when it left the lane before, or was sent,
/// if later); buckets are `period` s long. Guarantees the report's ten busiest lanes
/// ([`LaneUse::series`]), in a fixed order.
pub(super) struct LaneUse {
    busy: BTreeMap<usize, Buckets>,
    /// The timeline's interval (s).
    period: f64,
}

impl LaneUse {
    /// No lane driven yet; intervals of `period` s.
    pub(super) fn new(period: f64) -> LaneUse {
        LaneUse {
            busy: BTreeMap::new(),
            period,
        }
    }

    /// A robot was on IR lane `lane` from `since` to `t`.
    fn add(&mut self, lane: usize, since: f64, t: f64) {
        let period = self.period;
        self.busy
            .entry(lane)
            .or_insert_with(|| Buckets::new(period))
            .add(since, t);
    }

    /// The ten lanes robots drove longest (named by `nav`'s vertices), each with its busy
    /// share per interval of a run of `end` seconds.
    pub(super) fn series(&self, nav: &Nav, end: f64) -> Vec<Series> {
        let mut lanes: Vec<(&usize, &Buckets)> = self.busy.iter().collect();
        lanes.sort_by(|a, b| b.1.total().total_cmp(&a.1.total()).then(a.0.cmp(b.0)));
        lanes
            .into_iter()
            .take(10)
            .filter_map(|(&lane, busy)| {
                let e = nav.edges.iter().find(|e| e.lane == Some(lane))?;
                let name = |v: usize| {
                    let x = &nav.vertices[v];
                    if x.name.is_empty() {
                        format!("({:.1}, {:.1})", x.pos.x, x.pos.y)
                    } else {
                        x.name.clone()
                    }
                };
                Some(Series {
                    resource: format!(
                        "lane {} – {} on {}",
                        name(e.from),
                        name(e.to),
                        nav.vertices[e.from].level_name
                    ),
                    busy: busy.shares(end, 1.0),
                })
            })
            .collect()
    }
}

impl Floor {
    /// Drops the leg being driven (the robot finishes the traversals it was sent along, then
    /// its itinerary takes it to park) and gives back any door/lift it had asked for.
    pub(super) fn abandon_route(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let r = &mut self.robots[i];
        r.leg = None;
        r.legs.clear();
        r.waiting = None;
        self.drop_gate(i, t, out);
    }

    /// Gives back the door or lift robot `i` had asked for (a lift it is in stays its
    /// own until it drives out), and asks for none.
    pub(super) fn drop_gate(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        match std::mem::replace(&mut self.robots[i].gate, Gate::None) {
            Gate::Door { door, .. } => self.door_request(i, door, false, t, out),
            Gate::Lift { lift, .. } if self.nav.vertices[self.robots[i].at].lift.is_none() => {
                self.lift_request(i, lift, None, t, out)
            }
            _ => {}
        }
    }

    // ----- per-robot state machine -----

    /// Reads the latest RobotState of the current PathRequest: pops the edges reached.
    pub(super) fn observe_progress(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let r = &self.robots[i];
        if r.n_sent == 0 {
            return;
        }
        let Some(s) = &r.state else { return };
        if s.task_id != r.path_id {
            return;
        }
        if s.mode.mode == robot_mode::ADAPTER_ERROR {
            // The robot was too far from the path start: send it again from where it is.
            let n = self.robots[i].n_sent;
            self.send_path(i, n, t, out);
            return;
        }
        let reached = r.n_sent.saturating_sub(s.path.len());
        for _ in 0..reached {
            self.reach_next(i, t, out);
        }
    }

    pub(super) fn reach_next(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let Some((to, edge, begun_at)) = self
            .traffic
            .sched
            .itinerary(i)
            .travs
            .front()
            .map(|tr| (tr.to, tr.edge, tr.begun_at))
        else {
            return;
        };
        if let Some(lane) = self.nav.edges[edge].lane {
            // On the lane from when it left the lane before (or was sent, if later).
            let since = begun_at.max(self.robots[i].reached_at);
            self.lane_use.add(lane, since, t);
        }
        self.robots[i].reached_at = t;
        self.traffic.sched.complete_front(i, t);
        self.traffic
            .check(t, || format!("schedule broken after robot {i} arrived"));
        self.traffic.release();
        let r = &mut self.robots[i];
        r.n_sent = r.n_sent.saturating_sub(1);
        if let Some(l) = &mut r.leg {
            *l = l.saturating_sub(1);
        } else if let Some(l) = r.legs.front_mut() {
            // A task planned after traversals the robot was already sent along (`keep`)
            // counts them in its first leg; one may end before the task's first step
            // starts (in the same update). Not counted, the robot waited at its place for
            // a traversal its itinerary no longer had, for good.
            *l = l.saturating_sub(1);
        }
        r.at = to;
        r.stuck_reported = false;
        if let Some(d) = r.close_door.take() {
            self.door_request(i, d, false, t, out);
        }
        let r = &mut self.robots[i];
        if let Some(l) = r.end_lift {
            if self.nav.vertices[r.at].lift != Some(l) {
                r.end_lift = None;
                self.lift_request(i, l, None, t, out);
            }
        }
    }

    /// Advances a GoTo. Some(true) arrived, Some(false) in progress, None no route.
    pub(super) fn drive(
        &mut self,
        i: usize,
        goal: usize,
        planned: bool,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) -> Option<bool> {
        if !planned {
            if t < self.robots[i].replan_at {
                // The last try found no way: drive what the itinerary holds (to park).
                self.robots[i].wake = self.robots[i].replan_at;
                let n = self.traffic.sched.itinerary(i).travs.len();
                self.advance(i, n, t, out);
                return Some(false);
            }
            let goals = self.remaining_goals(i, goal);
            match self.plan_to(i, &goals, t) {
                Ok(leg) => {
                    let r = &mut self.robots[i];
                    r.leg = Some(leg);
                    r.cur = Cur::GoTo {
                        goal,
                        planned: true,
                    };
                }
                Err(NoPlan::Unreachable) => return None,
                Err(NoPlan::Busy) => {
                    // Not now: at least it goes to stand where it blocks nobody (a robot
                    // spawned in a corridor may be what keeps the others from planning).
                    let end = self.traffic.sched.end_vertex(i);
                    if self.traffic.parks(self.robots[i].slot)[end] == 0 {
                        let _ = self.plan_to(i, &[], t);
                    }
                    let r = &mut self.robots[i];
                    r.wake = r.replan_at;
                    if r.waiting.is_none() {
                        r.waiting = Some(t);
                    }
                    let n = self.traffic.sched.itinerary(i).travs.len();
                    self.advance(i, n, t, out);
                    return Some(false);
                }
            }
        }
        let r = &self.robots[i];
        let leg = r.leg.unwrap_or(0);
        if leg == 0 && r.n_sent == 0 {
            if r.at == goal {
                self.robots[i].leg = None;
                return Some(true);
            }
            // Somewhere else (the leg was dropped): plan again.
            if let Cur::GoTo { planned, .. } = &mut self.robots[i].cur {
                *planned = false;
            }
            self.robots[i].dirty = true;
            return Some(false);
        }
        debug_assert!(
            leg <= self.traffic.sched.itinerary(i).travs.len(),
            "robot {i}'s leg of {leg} traversals is longer than its itinerary"
        );
        self.advance(i, leg, t, out);
        Some(false)
    }

    /// Waits on a door or lift. True when it is ready (open / at the floor with doors open).
    pub(super) fn gate(
        &mut self,
        i: usize,
        want: Gate,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) -> bool {
        let same = match (&self.robots[i].gate, &want) {
            (Gate::Door { door: a, .. }, Gate::Door { door: b, .. }) => a == b,
            (
                Gate::Lift {
                    lift: a, floor: fa, ..
                },
                Gate::Lift {
                    lift: b, floor: fb, ..
                },
            ) => a == b && fa == fb,
            _ => false,
        };
        if !same {
            self.robots[i].gate = want;
        }
        let name = self.robots[i].name.clone();
        match self.robots[i].gate.clone() {
            Gate::None => true,
            Gate::Door {
                door,
                next_send,
                since,
            } => {
                if self.devices.door_open_for(door, &name) {
                    return true;
                }
                if t - since > EXTERNAL_TIMEOUT {
                    self.end_task(
                        i,
                        t,
                        false,
                        format!("door {} did not open", self.nav.doors[door].name),
                        out,
                    );
                    return false;
                }
                if t >= next_send {
                    self.door_request(i, door, true, t, out);
                    if let Gate::Door { next_send, .. } = &mut self.robots[i].gate {
                        *next_send = t + RESEND;
                    }
                }
                self.robots[i].wake = t + RESEND;
                false
            }
            Gate::Lift {
                lift,
                floor,
                next_send,
                since,
            } => {
                if self.devices.lift_ready_for(lift, &floor, &name) {
                    return true;
                }
                if t - since > EXTERNAL_TIMEOUT {
                    self.end_task(
                        i,
                        t,
                        false,
                        format!("lift {} did not come", self.nav.lifts[lift].name),
                        out,
                    );
                    return false;
                }
                if t >= next_send {
                    self.lift_request(i, lift, Some(floor), t, out);
                    if let Gate::Lift { next_send, .. } = &mut self.robots[i].gate {
                        *next_send = t + RESEND;
                    }
                }
                self.robots[i].wake = t + RESEND;
                false
            }
        }
    }

    pub(super) fn door_request(
        &self,
        i: usize,
        door: usize,
        open: bool,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        out.push((
            Topic::AdapterDoorRequests,
            Msg::DoorRequest(DoorRequest {
                request_time: Time::from_secs(t),
                requester_id: self.robots[i].name.clone(),
                door_name: self.nav.doors[door].name.clone(),
                requested_mode: DoorMode {
                    value: if open {
                        door_mode::OPEN
                    } else {
                        door_mode::CLOSED
                    },
                },
            }),
        ));
    }

    /// AGV_MODE to `floor` with doors open, or END_SESSION at the current floor (None).
    pub(super) fn lift_request(
        &self,
        i: usize,
        lift: usize,
        floor: Option<String>,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let r = &self.robots[i];
        let (request_type, door_state, destination_floor) = match floor {
            Some(f) => (lift_request::AGV_MODE, lift_request::DOOR_OPEN, f),
            None => (
                lift_request::END_SESSION,
                lift_request::DOOR_CLOSED,
                self.devices.lift_floor(lift).to_string(),
            ),
        };
        out.push((
            Topic::AdapterLiftRequests,
            Msg::LiftRequest(LiftRequest {
                lift_name: self.nav.lifts[lift].name.clone(),
                request_time: Time::from_secs(t),
                session_id: r.name.clone(),
                request_type,
                destination_floor,
                door_state,
            }),
        ));
    }

    /// PathRequest: where the robot is, then the ends of its first `n` traversals.
    pub(super) fn send_path(&mut self, i: usize, n: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let edges: Vec<usize> = self
            .traffic
            .sched
            .itinerary(i)
            .travs
            .iter()
            .take(n)
            .map(|tr| tr.edge)
            .collect();
        let r = &mut self.robots[i];
        r.path_seq += 1;
        r.path_id = format!("{}", r.path_seq);
        let at = &self.nav.vertices[r.at];
        let start = match &r.state {
            Some(s) => Location {
                t: Time::from_secs(t),
                x: s.location.x,
                y: s.location.y,
                yaw: s.location.yaw,
                level_name: at.level_name.clone(),
                ..Location::default()
            },
            None => Location {
                t: Time::from_secs(t),
                x: at.pos.x,
                y: at.pos.y,
                level_name: at.level_name.clone(),
                ..Location::default()
            },
        };
        let mut path = vec![start];
        let speed = self.fleets[r.fleet].speed;
        let mut eta = t;
        for (k, &e) in edges.iter().enumerate() {
            let edge = &self.nav.edges[e];
            if edge.kind != EdgeKind::Lane {
                break;
            }
            let (a, z) = (&self.nav.vertices[edge.from], &self.nav.vertices[edge.to]);
            let d = z.pos.minus(a.pos);
            let mut yaw = d.y.atan2(d.x);
            if edge.orientation == mapc_ir::Orientation::Backward {
                yaw = (yaw + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI);
            }
            eta += self.nav.edge_cost(e, speed);
            path.push(Location {
                t: Time::from_secs(eta),
                x: z.pos.x,
                y: z.pos.y,
                yaw,
                obey_approach_speed_limit: edge.speed_limit.is_some(),
                approach_speed_limit: edge.speed_limit.unwrap_or(0.0),
                level_name: z.level_name.clone(),
                index: k as u64 + 1,
            });
        }
        r.n_sent = path.len() - 1;
        out.push((
            Topic::RobotPathRequests,
            Msg::PathRequest(PathRequest {
                fleet_name: self.fleets[r.fleet].name.clone(),
                robot_name: r.name.clone(),
                path,
                task_id: r.path_id.clone(),
            }),
        ));
    }
}
