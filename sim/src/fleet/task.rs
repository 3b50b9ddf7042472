//! Executing tasks: the per-robot state machine of task steps (go to, workcell
//! requests, dwell, charging) and their sessions.

use super::*;

impl Floor {
    pub(super) fn end_task(
        &mut self,
        i: usize,
        t: f64,
        ok: bool,
        detail: String,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let result = if ok { "completed" } else { "failed" };
        self.end_task_as(i, t, result, detail, out);
    }

    /// Ends robot `i`'s task with `result` (`completed`, `failed` or `cancelled`); any but
    /// `completed` drops the rest of its route.
    pub(super) fn end_task_as(
        &mut self,
        i: usize,
        t: f64,
        result: &str,
        detail: String,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let ok = result == "completed";
        let Some(ti) = self.robots[i].task.take() else {
            return;
        };
        // Its way to parking is what it drives next: nobody's plan goes before it now.
        self.traffic.sched.harden(i);
        // The robot is free (once its steps are done): waiting tasks may go to it.
        self.freed_at = self.freed_at.min(t);
        if let Some(tk) = self.tasks.get_mut(ti) {
            tk.ended = true;
        }
        self.event(t, ti, result, Some(i), detail, out);
        let waits = self.take_waits(i, t);
        if let Some((_, Msg::TaskEvent(e))) = out.last_mut() {
            e.waits = Some(waits);
        }
        let r = &mut self.robots[i];
        let ingesting = matches!(
            r.cur,
            Cur::Workcell {
                dispenser: false,
                ..
            }
        );
        r.steps.clear();
        r.legs.clear();
        r.detour = 0;
        r.cur = Cur::None;
        if !ok {
            self.abandon_route(i, t, out);
            // A failed delivery still takes the item it carries to the ingestor, so that
            // its dispenser gets it back (else the dispenser stays empty for good).
            let r = &mut self.robots[i];
            match r.carrying.take() {
                Some((v, ing)) if !ingesting => {
                    r.steps.push_back(Step::GoTo(v));
                    r.steps.push_back(Step::Ingest(ing));
                    r.dirty = true;
                }
                _ => {}
            }
        }
    }

    pub(super) fn tick(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        self.robots[i].wake = f64::INFINITY;
        self.observe_progress(i, t, out);
        // Bounded: each pass either finishes a step or returns.
        for _ in 0..64 {
            let cur = self.robots[i].cur.clone();
            let done = match cur {
                Cur::None => {
                    if !self.next_step(i, t, out) {
                        return;
                    }
                    continue;
                }
                Cur::GoTo { goal, planned } => match self.drive(i, goal, planned, t, out) {
                    Some(true) => true,
                    Some(false) => return,
                    None => {
                        self.end_task(i, t, false, "no route".into(), out);
                        continue;
                    }
                },
                Cur::Workcell {
                    guid,
                    target,
                    dispenser,
                    next_send,
                    deadline,
                    tries,
                    since,
                    sent,
                } => match self.devices.result(&guid) {
                    Some(workcell_result::SUCCESS) => {
                        let r = &mut self.robots[i];
                        if dispenser {
                            // Carrying the item now: where it is to go, in case the task
                            // fails before it gets there.
                            let to = r.steps.iter().find_map(|s| match s {
                                Step::GoTo(v) => Some(*v),
                                _ => None,
                            });
                            let ing = r.steps.iter().find_map(|s| match s {
                                Step::Ingest(x) => Some(x.clone()),
                                _ => None,
                            });
                            r.carrying = to.zip(ing);
                            r.item_from = Some(target.clone());
                        } else {
                            r.carrying = None;
                            if let Some(d) = r.item_from.take() {
                                self.devices.ingested(d, t);
                            }
                        }
                        true
                    }
                    // An empty dispenser: its item is still out with another delivery
                    // (it comes back once ingested). Ask again for a while.
                    Some(_)
                        if dispenser && (t - since < ITEM_WAIT || self.item_coming(&target, t)) =>
                    {
                        let base = guid.split("_retry").next().unwrap_or(&guid).to_string();
                        self.robots[i].cur = Cur::Workcell {
                            guid: format!("{base}_retry{}", tries + 1),
                            target,
                            dispenser,
                            next_send: t + ITEM_RETRY,
                            deadline: t + ITEM_RETRY + EXTERNAL_TIMEOUT,
                            tries: tries + 1,
                            since,
                            sent: false,
                        };
                        let r = &mut self.robots[i];
                        r.wake = r.wake.min(t + ITEM_RETRY);
                        return;
                    }
                    Some(_) => {
                        self.end_task(i, t, false, format!("{target} failed"), out);
                        continue;
                    }
                    None if t >= deadline => {
                        self.end_task(i, t, false, format!("{target} did not answer"), out);
                        continue;
                    }
                    // Waiting to ask an empty dispenser again, on a place another robot
                    // waits to pass: it goes to park, and comes back to ask.
                    None if dispenser
                        && tries > 0
                        && !sent
                        && t < next_send
                        && self.make_room(i, t) =>
                    {
                        continue;
                    }
                    None => {
                        if t >= next_send {
                            self.workcell_request(i, &guid, &target, dispenser, t, out);
                            if let Cur::Workcell {
                                next_send, sent, ..
                            } = &mut self.robots[i].cur
                            {
                                *next_send = t + 2.0 * RESEND;
                                *sent = true;
                            }
                        }
                        let r = &mut self.robots[i];
                        r.wake = r.wake.min(t + 2.0 * RESEND);
                        return;
                    }
                },
                Cur::Dwell { until } => {
                    if t >= until {
                        true
                    } else {
                        self.robots[i].wake = until;
                        return;
                    }
                }
                Cur::Charge { pct, best, best_t } => {
                    let b = self.robots[i].battery();
                    if b >= pct {
                        true
                    } else if b > best {
                        self.robots[i].cur = Cur::Charge {
                            pct,
                            best: b,
                            best_t: t,
                        };
                        self.robots[i].wake = t + 10.0;
                        return;
                    } else if t - best_t > 900.0 {
                        // Not charging at all (charging disabled in the world?): give up.
                        true
                    } else {
                        self.robots[i].wake = t + 10.0;
                        return;
                    }
                }
            };
            if done {
                if self.robots[i].detour > 0 {
                    self.robots[i].detour -= 1;
                } else {
                    self.phase_done(i, t, out);
                }
                if matches!(self.robots[i].cur, Cur::Charge { .. }) {
                    let r = &mut self.robots[i];
                    if let Some(c) = r.charger.take() {
                        self.devices.free_charger(c);
                    }
                }
                self.robots[i].cur = Cur::None;
            }
        }
    }

    /// Robot `i` has done the step in `cur`: a `phase` event when it ends a phase of its
    /// task (steps outside a task, such as taking back an item, are no phase).
    fn phase_done(&self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let r = &self.robots[i];
        let Some(ti) = r.task else {
            return;
        };
        let step = match &r.cur {
            Cur::None => return,
            Cur::GoTo { goal, .. } => Step::GoTo(*goal),
            Cur::Workcell {
                target, dispenser, ..
            } if *dispenser => Step::Dispense(target.clone()),
            Cur::Workcell { target, .. } => Step::Ingest(target.clone()),
            Cur::Dwell { .. } => Step::Dwell(0.0),
            Cur::Charge { pct, .. } => Step::Charge(*pct),
        };
        if let Some(name) = self.phase_name(ti, &step, r.steps.is_empty()) {
            self.event(t, ti, "phase", Some(i), name, out);
        }
    }

    /// The phases of task `ti` whose robot has `steps` to do, in order (see `phase_name`).
    pub(super) fn phase_names(&self, ti: usize, steps: &VecDeque<Step>) -> Vec<String> {
        let n = steps.len();
        steps
            .iter()
            .enumerate()
            .filter_map(|(k, s)| self.phase_name(ti, s, k + 1 == n))
            .collect()
    }

    /// The phase of task `ti` that `step` ends (`last`: no step of the task follows), or
    /// None when the step does not end one: `go_to_place <place>`, `pickup at <place> from
    /// <dispenser>`, `dropoff at <place> into <ingestor>`, `clean <zone>` (the wait in the
    /// zone, or the trip along its docking lane and back, which ends at the return).
    fn phase_name(&self, ti: usize, step: &Step, last: bool) -> Option<String> {
        let kind = &self.tasks.get(ti)?.kind;
        let place = |v: usize| &self.nav.vertices[v].name;
        Some(match (step, kind) {
            (Step::GoTo(v), TaskKind::Clean { zone }) if place(*v) != zone => return None,
            (Step::GoTo(_), TaskKind::Clean { zone }) if last => format!("clean {zone}"),
            (Step::GoTo(v), _) => format!("go_to_place {}", place(*v)),
            (Step::Dispense(d), TaskKind::Delivery { pickup, .. }) => {
                format!("pickup at {pickup} from {d}")
            }
            (Step::Dispense(d), _) => format!("pickup from {d}"),
            (Step::Resume(c), _) => match &**c {
                Cur::Workcell {
                    target,
                    dispenser: true,
                    ..
                } => return self.phase_name(ti, &Step::Dispense(target.clone()), last),
                _ => return None,
            },
            (Step::Ingest(x), TaskKind::Delivery { dropoff, .. }) => {
                format!("dropoff at {dropoff} into {x}")
            }
            (Step::Ingest(x), _) => format!("dropoff into {x}"),
            (Step::Dwell(_), TaskKind::Clean { zone }) => format!("clean {zone}"),
            (Step::Dwell(_), _) => "wait".to_string(),
            (Step::Charge(_), _) => "charge".to_string(),
        })
    }

    /// Starts the next step (or task). False when there is nothing to do.
    pub(super) fn next_step(&mut self, i: usize, t: f64, out: &mut Vec<(Topic, Msg)>) -> bool {
        if let Some(step) = self.robots[i].steps.pop_front() {
            // Requests outside a task (an item taken back) get their own ids.
            let task_id = self.robots[i]
                .task
                .and_then(|ti| self.tasks.get(ti))
                .map_or_else(
                    || format!("{}_return{}", self.robots[i].name, self.robots[i].path_seq),
                    |tk| tk.id.clone(),
                );
            let r = &mut self.robots[i];
            let workcell = |target: String, dispenser: bool| Cur::Workcell {
                guid: format!("{task_id}_{}", if dispenser { "pickup" } else { "dropoff" }),
                target,
                dispenser,
                next_send: t,
                deadline: t + EXTERNAL_TIMEOUT,
                tries: 0,
                since: t,
                sent: false,
            };
            r.cur = match step {
                // Planned with the task (or the leg before): its leg is known.
                Step::GoTo(goal) => match r.legs.pop_front() {
                    Some(n) => {
                        r.leg = Some(n);
                        Cur::GoTo {
                            goal,
                            planned: true,
                        }
                    }
                    None => Cur::GoTo {
                        goal,
                        planned: false,
                    },
                },
                Step::Dwell(d) => Cur::Dwell { until: t + d },
                Step::Charge(pct) => Cur::Charge {
                    pct,
                    best: r.battery(),
                    best_t: t,
                },
                Step::Dispense(target) => workcell(target, true),
                // Asks again at once, under the same request and time limits.
                Step::Resume(cur) => match *cur {
                    Cur::Workcell {
                        guid,
                        target,
                        dispenser,
                        deadline,
                        tries,
                        since,
                        ..
                    } => Cur::Workcell {
                        guid,
                        target,
                        dispenser,
                        next_send: t,
                        deadline: deadline.max(t + EXTERNAL_TIMEOUT),
                        tries,
                        since,
                        sent: false,
                    },
                    other => other,
                },
                Step::Ingest(target) => workcell(target, false),
            };
            return true;
        }
        let ended = self.robots[i].task.is_some();
        if ended {
            self.end_task(i, t, true, String::new(), out);
        }
        // Charging comes before the next task when the battery is low.
        if self.robots[i].charger.is_none() && self.maybe_charge(i) {
            // The charger is where it stays afterwards.
            self.robots[i].park_pending = false;
            return true;
        }
        // Nothing to do: to a parking vertex (a robot that did not start on one plans its
        // way there first; every plan ends on one).
        if self.robots[i].park_pending && t >= self.robots[i].replan_at {
            match self.plan_to(i, &[], t) {
                Ok(_) => self.robots[i].park_pending = false,
                Err(_) => {
                    let r = &mut self.robots[i];
                    r.replan_at = t + 2.0;
                    r.wake = r.replan_at;
                }
            }
        }
        if ended {
            // Just free where its task ended: the dispatch round after this update's ticks
            // may give it a task from here, so it sets off to park only after that round
            // ([`Fleets::update`]). Sent on at once, it drove to park and back for a task
            // at the place it stood on.
            self.just_free.push(i);
            return false;
        }
        let n = self.traffic.sched.itinerary(i).travs.len();
        self.advance(i, n, t, out);
        false
    }

    pub(super) fn maybe_charge(&mut self, i: usize) -> bool {
        let r = &self.robots[i];
        let f = &self.fleets[r.fleet];
        if r.state.is_none() || r.battery() >= f.recharge_threshold * 100.0 {
            return false;
        }
        let times = self.nav.times_from(f.slot, r.at, f.speed);
        let best = self.nav.members[f.slot]
            .iter()
            .copied()
            .filter(|&v| {
                self.nav.vertices[v].roles.is_charger && self.nav.vertices[v].lift.is_none()
            })
            .filter(|&v| self.devices.charger_free_for(v, i))
            .filter(|&v| times[v].is_finite())
            .min_by(|&a, &b| times[a].total_cmp(&times[b]).then(a.cmp(&b)));
        let Some(c) = best else {
            return false;
        };
        let pct = f.recharge_soc * 100.0;
        self.devices.take_charger(c, i);
        let r = &mut self.robots[i];
        r.charger = Some(c);
        r.steps.push_back(Step::GoTo(c));
        r.steps.push_back(Step::Charge(pct));
        true
    }

    pub(super) fn workcell_request(
        &self,
        i: usize,
        guid: &str,
        target: &str,
        dispenser: bool,
        t: f64,
        out: &mut Vec<(Topic, Msg)>,
    ) {
        let r = &self.robots[i];
        let msg = Msg::WorkcellRequest(WorkcellRequest {
            time: Time::from_secs(t),
            request_guid: guid.to_string(),
            target_guid: target.to_string(),
            transporter_type: self.fleets[r.fleet].name.clone(),
            items: vec![ItemType {
                type_guid: "item".into(),
                quantity: 1,
                compartment_name: String::new(),
            }],
        });
        let topic = if dispenser {
            Topic::DispenserRequests
        } else {
            Topic::IngestorRequests
        };
        out.push((topic, msg));
    }

    /// Whether a robot still on its way (a delivery or the return trip of a failed one)
    /// carries `dispenser`'s item: it will come back, so waiting for it is not in vain.
    pub(super) fn item_coming(&self, dispenser: &str, t: f64) -> bool {
        // Ingested lately: on its way home (the ingestor returns it after a few seconds).
        let home_soon = self.devices.home_soon(dispenser, t);
        home_soon
            || self.robots.iter().any(|x| {
                x.item_from.as_deref() == Some(dispenser)
                    && !(matches!(x.cur, Cur::None) && x.steps.is_empty())
            })
    }
}
