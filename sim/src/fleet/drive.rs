//! Driving a route: PathRequests of the reserved edges, progress read back from
//! RobotState, door and lift sessions at the gates on the way.

use super::*;

impl Fleets {
    /// Drops the planned route (the robot stays where it is once the edges it is already
    /// driving are done) and gives back any door/lift it had asked for.
    pub(super) fn abandon_route(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let r = &mut self.robots[i];
        let keep = r.n_sent;
        r.route.truncate(keep);
        r.n_res = keep;
        r.wait_since = None;
        r.blockers.clear();
        match std::mem::replace(&mut r.gate, Gate::None) {
            Gate::Door { door, .. } => self.door_request(i, door, false, t, out),
            Gate::Lift { lift, .. } if self.nav.vertices[self.robots[i].at].lift.is_none() => {
                self.lift_request(i, lift, None, t, out)
            }
            _ => {}
        }
        self.rehold(i);
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
            self.send_path(i, t, out);
            return;
        }
        let reached = r.n_sent.saturating_sub(s.path.len());
        for _ in 0..reached {
            self.reach_next(i, t, out);
        }
    }

    pub(super) fn reach_next(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let r = &mut self.robots[i];
        let Some(e) = r.route.pop_front() else { return };
        r.n_sent = r.n_sent.saturating_sub(1);
        r.n_res = r.n_res.saturating_sub(1);
        r.at = self.nav.edges[e].to;
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
        self.rehold(i);
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
            let r = &self.robots[i];
            if r.n_sent > 0 {
                return Some(false);
            }
            let speed = self.fleets[r.fleet].speed;
            // Around robots parked on the graph when there is a way, else through them
            // (they will be asked to move aside).
            let mut parked: Vec<Res> = Vec::new();
            for (o, x) in self.robots.iter().enumerate() {
                if o != i && x.idle() && x.n_sent == 0 {
                    parked.extend_from_slice(self.res.held(o));
                }
            }
            parked.sort_unstable();
            parked.dedup();
            let clear = |e: usize| {
                !self.conf.edge[e]
                    .iter()
                    .any(|x| parked.binary_search(x).is_ok())
            };
            let (_, edges) = if parked.is_empty() {
                None
            } else {
                self.nav.plan_with(r.slot, r.at, goal, speed, &clear)
            }
            .or_else(|| self.nav.plan(r.slot, r.at, goal, speed))?;
            let r = &mut self.robots[i];
            // Keep edges already reserved (they are a prefix only if the plan agrees).
            r.route = edges.into();
            r.n_res = 0;
            r.cur = Cur::GoTo {
                goal,
                planned: true,
            };
            self.rehold(i);
        }
        let r = &self.robots[i];
        if r.n_sent > 0 {
            // Moving: reserve ahead and extend the path while lanes stay plain.
            let all_plain = r.route.iter().take(r.n_sent).all(|&e| self.is_plain(e));
            if all_plain && r.n_res == r.n_sent && r.n_res < LOOKAHEAD {
                if let Some(&next) = r.route.get(r.n_res) {
                    if self.is_plain(next) && self.try_reserve(i, t) {
                        self.send_path(i, t, out);
                    } else {
                        // Retry on the next RobotState; traffic waits only count at rest.
                        self.robots[i].wait_since = None;
                    }
                }
            }
            return Some(false);
        }
        if r.route.is_empty() {
            return Some(r.at == goal).filter(|&b| b).or_else(|| {
                // Arrived somewhere else (route dropped): plan again next tick.
                if let Cur::GoTo { planned, .. } = &mut self.robots[i].cur {
                    *planned = false;
                }
                self.robots[i].dirty = true;
                Some(false)
            });
        }
        let Some(&e) = r.route.front() else {
            return Some(false);
        };
        let edge = self.nav.edges[e].clone();
        // 1. Reserve the next edge (all-or-nothing).
        if r.n_res == 0 && !self.try_reserve(i, t) {
            return Some(false);
        }
        // 2. Gates: lift ride, lift call, door.
        if let EdgeKind::Lift(l) = edge.kind {
            let floor = self.nav.vertices[edge.to].level_name.clone();
            if !self.gate(
                i,
                Gate::Lift {
                    lift: l,
                    floor: floor.clone(),
                    next_send: t,
                    since: t,
                },
                t,
                out,
            ) {
                return Some(false);
            }
            // Arrived at the destination floor: the robot is now on the other cabin vertex.
            let r = &mut self.robots[i];
            r.gate = Gate::None;
            r.end_lift = Some(l);
            self.reach_next_lift(i);
            self.robots[i].dirty = true;
            return Some(false);
        }
        let to_lift = self.nav.vertices[edge.to].lift;
        let from_lift = self.nav.vertices[edge.from].lift;
        if let Some(l) = to_lift.filter(|&l| from_lift != Some(l)) {
            let floor = self.nav.vertices[edge.from].level_name.clone();
            if !self.gate(
                i,
                Gate::Lift {
                    lift: l,
                    floor,
                    next_send: t,
                    since: t,
                },
                t,
                out,
            ) {
                return Some(false);
            }
            self.robots[i].gate = Gate::None;
            self.robots[i].end_lift = Some(l);
        } else if let Some(d) = edge.door.filter(|&d| self.nav.doors[d].controlled) {
            if !self.gate(
                i,
                Gate::Door {
                    door: d,
                    next_send: t,
                    since: t,
                },
                t,
                out,
            ) {
                return Some(false);
            }
            self.robots[i].gate = Gate::None;
            self.robots[i].close_door = Some(d);
        } else {
            // Plain lanes: reserve a few more while they stay plain.
            while self.robots[i].n_res < LOOKAHEAD {
                let r = &self.robots[i];
                let Some(&next) = r.route.get(r.n_res) else {
                    break;
                };
                if !(self.is_plain(e) && self.is_plain(next) && self.try_reserve(i, t)) {
                    self.robots[i].wait_since = None;
                    self.robots[i].blockers.clear();
                    break;
                }
            }
        }
        self.send_path(i, t, out);
        Some(false)
    }

    pub(super) fn reach_next_lift(&mut self, i: usize) {
        let r = &mut self.robots[i];
        if let Some(e) = r.route.pop_front() {
            r.n_res = r.n_res.saturating_sub(1);
            r.at = self.nav.edges[e].to;
        }
        self.rehold(i);
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
                let v = &self.doors[door];
                if v.mode == door_mode::OPEN && v.sessions.contains(&name) {
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
                let v = &self.lifts[lift];
                if v.current_floor == floor
                    && v.door_state == lift_state::DOOR_OPEN
                    && v.session_id == name
                {
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
                self.lifts[lift].current_floor.clone(),
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

    /// PathRequest: where the robot is, then the targets of the reserved edges.
    pub(super) fn send_path(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
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
        for (k, &e) in r.route.iter().take(r.n_res).enumerate() {
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

    // ----- traffic supervision -----
}
