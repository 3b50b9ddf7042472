//! The door and lift supervisors of rmf_fleet_adapter (runtime spec §3, §4.7). Their
//! requests to the plugins are returned to the world, which hands them to the plugins.
//!
//! No difference from the nodes' behaviour. Headless detail: the heartbeat lists doors
//! in name order (the node's map order).

use crate::msgs::{
    door_mode, lift_request, DoorMode, DoorRequest, DoorSessions, DoorState, LiftRequest,
    LiftState, Msg, Published, Session, SupervisorHeartbeat, Time, Topic,
};
use std::collections::BTreeMap;

const SUPERVISOR_ID: &str = "door_supervisor";

#[derive(Debug, Default)]
pub(crate) struct DoorSupervisor {
    log: BTreeMap<String, BTreeMap<String, Time>>,
}

fn door_request(t: f64, door: &str, mode: u32) -> DoorRequest {
    DoorRequest {
        request_time: Time::from_secs(t),
        requester_id: SUPERVISOR_ID.to_string(),
        door_name: door.to_string(),
        requested_mode: DoorMode { value: mode },
    }
}

fn time_lt(a: Time, b: Time) -> bool {
    (a.sec, a.nanosec) < (b.sec, b.nanosec)
}

impl DoorSupervisor {
    fn publish_request(
        t: f64,
        r: DoorRequest,
        out: &mut Vec<Published>,
        to_doors: &mut Vec<DoorRequest>,
    ) {
        out.push(Published {
            t,
            topic: Topic::DoorRequests,
            msg: Msg::DoorRequest(r.clone()),
        });
        to_doors.push(r);
    }

    fn heartbeat(&self, t: f64, out: &mut Vec<Published>) {
        let all_sessions = self
            .log
            .iter()
            .map(|(door, sessions)| DoorSessions {
                door_name: door.clone(),
                sessions: sessions
                    .iter()
                    .map(|(who, &time)| Session {
                        request_time: time,
                        requester_id: who.clone(),
                    })
                    .collect(),
            })
            .collect();
        out.push(Published {
            t,
            topic: Topic::DoorSupervisorHeartbeat,
            msg: Msg::DoorHeartbeat(SupervisorHeartbeat { all_sessions }),
        });
    }

    /// `/adapter_door_requests`.
    pub fn adapter_request(
        &mut self,
        t: f64,
        msg: &DoorRequest,
        out: &mut Vec<Published>,
        to_doors: &mut Vec<DoorRequest>,
    ) {
        match msg.requested_mode.value {
            door_mode::OPEN => {
                let entry = self.log.entry(msg.door_name.clone()).or_default();
                let time = entry
                    .get(&msg.requester_id)
                    .map_or(msg.request_time, |&old| {
                        if time_lt(old, msg.request_time) {
                            msg.request_time
                        } else {
                            old
                        }
                    });
                entry.insert(msg.requester_id.clone(), time);
                Self::publish_request(
                    t,
                    door_request(t, &msg.door_name, door_mode::OPEN),
                    out,
                    to_doors,
                );
            }
            door_mode::CLOSED => {
                if let Some(entry) = self.log.get_mut(&msg.door_name) {
                    if let Some(&opened) = entry.get(&msg.requester_id) {
                        if !time_lt(msg.request_time, opened) {
                            entry.remove(&msg.requester_id);
                            if entry.is_empty() {
                                Self::publish_request(
                                    t,
                                    door_request(t, &msg.door_name, door_mode::CLOSED),
                                    out,
                                    to_doors,
                                );
                            }
                        }
                    }
                }
            }
            _ => return,
        }
        self.heartbeat(t, out);
    }

    /// `/door_states`: reminders when the door disagrees with the sessions.
    pub fn door_state(
        &mut self,
        t: f64,
        msg: &DoorState,
        out: &mut Vec<Published>,
        to_doors: &mut Vec<DoorRequest>,
    ) {
        let held = self.log.get(&msg.door_name).is_some_and(|s| !s.is_empty());
        let m = msg.current_mode.value;
        if !held && (m == door_mode::OPEN || m == door_mode::MOVING) {
            Self::publish_request(
                t,
                door_request(t, &msg.door_name, door_mode::CLOSED),
                out,
                to_doors,
            );
        } else if held && (m == door_mode::CLOSED || m == door_mode::MOVING) {
            Self::publish_request(
                t,
                door_request(t, &msg.door_name, door_mode::OPEN),
                out,
                to_doors,
            );
        }
    }
}

#[derive(Debug, Default)]
pub(crate) struct LiftSupervisor {
    active: BTreeMap<String, Option<LiftRequest>>,
}

impl LiftSupervisor {
    fn publish(
        t: f64,
        mut r: LiftRequest,
        out: &mut Vec<Published>,
        to_lifts: &mut Vec<LiftRequest>,
    ) {
        r.request_time = Time::from_secs(t);
        out.push(Published {
            t,
            topic: Topic::LiftRequests,
            msg: Msg::LiftRequest(r.clone()),
        });
        to_lifts.push(r);
    }

    /// `/adapter_lift_requests`.
    pub fn adapter_request(
        &mut self,
        t: f64,
        msg: &LiftRequest,
        out: &mut Vec<Published>,
        to_lifts: &mut Vec<LiftRequest>,
    ) {
        let slot = self.active.entry(msg.lift_name.clone()).or_default();
        let end = msg.request_type == lift_request::END_SESSION;
        match slot {
            Some(cur) if cur.session_id == msg.session_id => {
                if end {
                    *slot = None;
                } else {
                    *cur = msg.clone();
                }
                Self::publish(t, msg.clone(), out, to_lifts);
            }
            Some(_) => {}
            None => {
                if !end {
                    *slot = Some(msg.clone());
                    Self::publish(t, msg.clone(), out, to_lifts);
                }
            }
        }
    }

    /// `/lift_states`: retries unsatisfied requests, ends orphaned sessions.
    pub fn lift_state(
        &mut self,
        t: f64,
        st: &LiftState,
        out: &mut Vec<Published>,
        to_lifts: &mut Vec<LiftRequest>,
    ) {
        match self.active.get(&st.lift_name) {
            Some(Some(req)) => {
                let floor_ok = req.destination_floor == st.destination_floor
                    || (req.destination_floor == st.current_floor
                        && st.destination_floor.is_empty());
                let ok =
                    floor_ok && req.door_state == st.door_state && req.session_id == st.session_id;
                if !ok {
                    Self::publish(t, req.clone(), out, to_lifts);
                }
            }
            _ => {
                if !st.session_id.is_empty() {
                    let r = LiftRequest {
                        lift_name: st.lift_name.clone(),
                        request_time: Time::default(),
                        session_id: st.session_id.clone(),
                        request_type: lift_request::END_SESSION,
                        destination_floor: st.current_floor.clone(),
                        door_state: lift_request::DOOR_CLOSED,
                    };
                    Self::publish(t, r, out, to_lifts);
                }
            }
        }
    }
}
