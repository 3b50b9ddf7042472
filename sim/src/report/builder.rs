//! The report built from what is observed: published messages (task events, door and lift
//! states and requests, robot states) and ground-truth samples, accumulated per robot, door,
//! lift and approach, and finished into a [`Report`].

use super::*;

struct RobotAcc {
    name: String,
    fleet: String,
    footprint: f64,
    distance: f64,
    last: Option<(f64, f64)>,
    open_tasks: BTreeSet<String>,
    busy_since: Option<f64>,
    busy: Buckets,
    /// Where and since when the robot has been still (within STILL_TOLERANCE).
    anchor: Option<(f64, f64, f64)>,
    /// The still-since time already reported as stuck, and its entry in `stuck`.
    flagged: Option<(f64, usize)>,
    /// It last reported CHARGING: standing still is then waiting for its battery (the
    /// task's `charging` wait), not being stuck.
    charging: bool,
}

#[derive(Default)]
struct DoorAcc {
    report: DoorReport,
    /// Since when the door has not been closed, and the time summed so far.
    open_since: Option<f64>,
    open: Buckets,
    /// Open sessions by requester: the request time while waiting for the door to open.
    sessions: BTreeMap<String, Option<f64>>,
}

#[derive(Default)]
struct LiftAcc {
    report: LiftReport,
    /// Since when the lift has been in a session, and the time summed so far.
    busy_since: Option<f64>,
    busy: Buckets,
    /// Open sessions: (request time, destination) while waiting, None once served.
    sessions: BTreeMap<String, Option<(f64, String)>>,
    moving: bool,
}

struct Approach {
    min_d: f64,
    t_min: f64,
}

pub struct ReportBuilder {
    fleets: Vec<String>,
    reserve: BTreeMap<String, usize>,
    robots: Vec<RobotAcc>,
    robot_index: BTreeMap<String, usize>,
    tasks: Vec<TaskReport>,
    task_index: BTreeMap<String, usize>,
    doors: Vec<DoorAcc>,
    door_index: BTreeMap<String, usize>,
    lifts: Vec<LiftAcc>,
    lift_index: BTreeMap<String, usize>,
    approaches: BTreeMap<(usize, usize), Approach>,
    near_misses: Vec<Encounter>,
    contacts: Vec<Encounter>,
    stuck: Vec<StuckReport>,
    /// The latest episode of each (robot, event, detail), as an index into `stuck`.
    episodes: BTreeMap<(String, String, String), usize>,
    last_sample: Option<f64>,
    /// Interval of the utilisation timeline (s).
    period: f64,
}

fn slot<T: Default>(
    list: &mut Vec<T>,
    index: &mut BTreeMap<String, usize>,
    name: &str,
    init: impl FnOnce(&mut T),
) -> usize {
    if let Some(&i) = index.get(name) {
        return i;
    }
    let mut v = T::default();
    init(&mut v);
    list.push(v);
    index.insert(name.to_string(), list.len() - 1);
    list.len() - 1
}

impl ReportBuilder {
    pub fn new(
        building: &mapc_ir::Building,
        scenario: &crate::Scenario,
        placement: &crate::fleet::Placement,
    ) -> Self {
        let mut b = ReportBuilder {
            fleets: scenario.fleets.iter().map(|f| f.name.clone()).collect(),
            reserve: placement.reserve.iter().cloned().collect(),
            robots: Vec::new(),
            robot_index: BTreeMap::new(),
            tasks: Vec::new(),
            task_index: BTreeMap::new(),
            doors: Vec::new(),
            door_index: BTreeMap::new(),
            lifts: Vec::new(),
            lift_index: BTreeMap::new(),
            approaches: BTreeMap::new(),
            near_misses: Vec::new(),
            contacts: Vec::new(),
            stuck: Vec::new(),
            episodes: BTreeMap::new(),
            last_sample: None,
            period: timeline::period_for(scenario.duration),
        };
        for r in &placement.robots {
            b.robot_index.insert(r.name.clone(), b.robots.len());
            b.robots.push(RobotAcc {
                name: r.name.clone(),
                fleet: r.fleet.clone(),
                footprint: r.params.footprint,
                distance: 0.0,
                last: None,
                open_tasks: BTreeSet::new(),
                busy_since: None,
                busy: Buckets::new(b.period),
                anchor: None,
                flagged: None,
                charging: false,
            });
        }
        for (_, d) in building.doors.iter() {
            b.door(&d.name);
        }
        for (_, l) in building.lifts.iter() {
            b.lift(&l.name);
        }
        b
    }

    fn door(&mut self, name: &str) -> usize {
        let period = self.period;
        slot(
            &mut self.doors,
            &mut self.door_index,
            name,
            |d: &mut DoorAcc| {
                d.report.name = name.to_string();
                d.open = Buckets::new(period);
            },
        )
    }

    fn lift(&mut self, name: &str) -> usize {
        let period = self.period;
        slot(
            &mut self.lifts,
            &mut self.lift_index,
            name,
            |l: &mut LiftAcc| {
                l.report.name = name.to_string();
                l.busy = Buckets::new(period);
            },
        )
    }

    pub fn observe(&mut self, p: &crate::msgs::Published) {
        match (&p.topic, &p.msg) {
            (_, Msg::RobotState(s)) => {
                if let Some(&i) = self.robot_index.get(&s.name) {
                    self.robots[i].charging = s.mode.mode == robot_mode::CHARGING;
                }
            }
            (Topic::AdapterDoorRequests, Msg::DoorRequest(r)) => {
                let i = self.door(&r.door_name);
                let d = &mut self.doors[i];
                if r.requested_mode.value == door_mode::OPEN {
                    if !d.sessions.contains_key(&r.requester_id) {
                        d.report.open_requests += 1;
                        d.sessions.insert(r.requester_id.clone(), Some(p.t));
                    }
                } else if let Some(pending) = d.sessions.remove(&r.requester_id) {
                    if pending.is_some() {
                        d.report.wait.unserved += 1;
                    }
                }
            }
            (Topic::DoorStates, Msg::DoorState(s)) => {
                let i = self.door(&s.door_name);
                let d = &mut self.doors[i];
                let closed = s.current_mode.value == door_mode::CLOSED;
                match (closed, d.open_since) {
                    (true, Some(t0)) => {
                        d.open.add(t0, p.t);
                        d.open_since = None;
                    }
                    (false, None) => d.open_since = Some(p.t),
                    _ => {}
                }
                if s.current_mode.value != door_mode::OPEN {
                    return;
                }
                for pending in d.sessions.values_mut() {
                    if let Some(t0) = pending.take() {
                        d.report.wait.add(p.t - t0);
                    }
                }
            }
            (Topic::AdapterLiftRequests, Msg::LiftRequest(r)) => {
                let i = self.lift(&r.lift_name);
                let l = &mut self.lifts[i];
                if r.request_type == lift_request::END_SESSION {
                    if let Some(Some(_)) = l.sessions.remove(&r.session_id) {
                        l.report.wait.unserved += 1;
                    }
                } else if !l.sessions.contains_key(&r.session_id) {
                    l.report.sessions += 1;
                    l.sessions.insert(
                        r.session_id.clone(),
                        Some((p.t, r.destination_floor.clone())),
                    );
                }
            }
            (Topic::LiftStates, Msg::LiftState(s)) => {
                let i = self.lift(&s.lift_name);
                let l = &mut self.lifts[i];
                let moving = matches!(
                    s.motion_state,
                    lift_state::MOTION_UP | lift_state::MOTION_DOWN
                );
                if moving && !l.moving {
                    l.report.trips += 1;
                }
                match (s.session_id.is_empty(), l.busy_since) {
                    (true, Some(t0)) => {
                        l.busy.add(t0, p.t);
                        l.busy_since = None;
                    }
                    (false, None) => l.busy_since = Some(p.t),
                    _ => {}
                }
                l.moving = moving;
                if s.door_state == lift_state::DOOR_OPEN {
                    if let Some(pending) = l.sessions.get_mut(&s.session_id) {
                        if pending.as_ref().is_some_and(|(_, f)| *f == s.current_floor) {
                            if let Some((t0, _)) = pending.take() {
                                l.report.wait.add(p.t - t0);
                            }
                        }
                    }
                }
            }
            (Topic::TaskEvents, Msg::TaskEvent(e)) => self.task_event(p.t, e),
            _ => {}
        }
    }

    fn task_event(&mut self, t: f64, e: &crate::msgs::TaskEvent) {
        if matches!(e.event.as_str(), "stuck" | "deadlock") {
            // One episode per robot and condition: repeats of the same event continue it.
            let key = (e.robot.clone(), e.event.clone(), e.detail.clone());
            let episode = self
                .episodes
                .get(&key)
                .and_then(|&i| self.stuck.get_mut(i))
                .filter(|s| t - s.until <= STUCK_EVENT_GAP);
            match episode {
                Some(s) => {
                    s.until = t;
                    s.events += 1;
                }
                None => {
                    self.episodes.insert(key, self.stuck.len());
                    self.stuck.push(StuckReport {
                        robot: e.robot.clone(),
                        fleet: e.fleet.clone(),
                        task_id: e.task_id.clone(),
                        t,
                        until: t,
                        events: 1,
                        reason: e.event.clone(),
                        detail: e.detail.clone(),
                    });
                }
            }
            return;
        }
        let i = slot(&mut self.tasks, &mut self.task_index, &e.task_id, |r| {
            r.id = e.task_id.clone();
            r.result = "unfinished".into();
        });
        if e.event == "phase" {
            self.tasks[i].phase_done(t, &e.detail);
            return;
        }
        let previous_robot = self.tasks[i].robot.clone();
        {
            let task = &mut self.tasks[i];
            if !e.category.is_empty() {
                task.category = e.category.clone();
            }
            if !e.fleet.is_empty() {
                task.fleet = e.fleet.clone();
            }
            if !e.robot.is_empty() {
                task.robot = e.robot.clone();
            }
            if !e.detail.is_empty() {
                task.detail = e.detail.clone();
            }
            if e.waits.is_some() {
                task.waits = e.waits.clone();
            }
            if e.planned_finish.is_some() {
                task.planned_finish = e.planned_finish;
            }
        }
        match e.event.as_str() {
            "queued" => {
                self.tasks[i].requested.get_or_insert(t);
            }
            "assigned" => {
                self.tasks[i].assigned = Some(t);
                // A reassignment frees the previous robot.
                if previous_robot != e.robot {
                    self.release(&previous_robot, &e.task_id, t);
                }
                if let Some(&r) = self.robot_index.get(&e.robot) {
                    let robot = &mut self.robots[r];
                    if robot.open_tasks.is_empty() {
                        robot.busy_since = Some(t);
                    }
                    robot.open_tasks.insert(e.task_id.clone());
                }
            }
            "started" => {
                let task = &mut self.tasks[i];
                task.started.get_or_insert(t);
                if let Some(names) = &e.phases {
                    task.phases = names
                        .iter()
                        .map(|d| PhaseReport {
                            detail: d.clone(),
                            result: "pending".into(),
                            ..PhaseReport::default()
                        })
                        .collect();
                    if let Some(p) = task.phases.first_mut() {
                        p.started = Some(t);
                        p.result = "unfinished".into();
                    }
                }
            }
            "completed" | "failed" | "cancelled" => {
                self.tasks[i].phases_end(t, &e.event);
                self.tasks[i].finished = Some(t);
                self.tasks[i].result = e.event.clone();
                if e.event == "completed" {
                    self.tasks[i].delay = self.tasks[i].planned_finish.map(|p| t - p);
                }
                let robot = self.tasks[i].robot.clone();
                self.release(&robot, &e.task_id, t);
            }
            _ => {}
        }
    }

    fn release(&mut self, robot: &str, task: &str, t: f64) {
        let Some(&r) = self.robot_index.get(robot) else {
            return;
        };
        let robot = &mut self.robots[r];
        if robot.open_tasks.remove(task) && robot.open_tasks.is_empty() {
            if let Some(since) = robot.busy_since.take() {
                robot.busy.add(since, t);
            }
        }
    }

    /// Ground-truth positions (spawn order), about every 0.1 s.
    pub fn sample(&mut self, t: f64, robots: &[RobotTruth]) {
        self.last_sample = Some(t);
        let n = robots.len().min(self.robots.len());
        for (acc, r) in self.robots.iter_mut().zip(robots) {
            if let Some((x, y)) = acc.last {
                acc.distance += (r.x - x).hypot(r.y - y);
            }
            acc.last = Some((r.x, r.y));
            // Motionless with a task for too long (charging does not count).
            match acc.anchor {
                Some((ax, ay, _))
                    if !acc.charging && (r.x - ax).hypot(r.y - ay) <= STILL_TOLERANCE => {}
                _ => acc.anchor = Some((r.x, r.y, t)),
            }
            if let (Some(busy), Some((_, _, still))) = (acc.busy_since, acc.anchor) {
                let since = still.max(busy);
                match acc.flagged {
                    Some((s, i)) if s == since => {
                        if let Some(entry) = self.stuck.get_mut(i) {
                            entry.until = t;
                        }
                    }
                    _ if t - since > STUCK_AFTER => {
                        acc.flagged = Some((since, self.stuck.len()));
                        let task = acc.open_tasks.iter().next().cloned().unwrap_or_default();
                        self.stuck.push(StuckReport {
                            robot: acc.name.clone(),
                            fleet: acc.fleet.clone(),
                            task_id: task.clone(),
                            t: since,
                            until: t,
                            events: 1,
                            reason: "no_motion".into(),
                            detail: format!(
                                "did not move for more than {STUCK_AFTER} s while assigned task `{task}`"
                            ),
                        });
                    }
                    _ => {}
                }
            }
        }
        self.encounters(t, &robots[..n]);
    }

    /// Near misses and contacts: pairs on one level closer than their near-miss distance,
    /// counted once per approach. A sweep over x finds candidate pairs in O(n log n + k).
    fn encounters(&mut self, t: f64, robots: &[RobotTruth]) {
        // Follow open approaches: update the minimum, or end them.
        let mut ended = Vec::new();
        for (&(a, b), ap) in self.approaches.iter_mut() {
            let (Some(ra), Some(rb)) = (robots.get(a), robots.get(b)) else {
                ended.push((a, b));
                continue;
            };
            let d = (ra.x - rb.x).hypot(ra.y - rb.y);
            let near = self.robots[a].footprint + self.robots[b].footprint + NEAR_MISS_MARGIN;
            if (ra.z - rb.z).abs() >= SAME_LEVEL_DZ || d >= near + NEAR_MISS_HYSTERESIS {
                ended.push((a, b));
            } else if d < ap.min_d {
                ap.min_d = d;
                ap.t_min = t;
            }
        }
        for k in ended {
            self.close(k);
        }
        // New approaches.
        let max_near =
            2.0 * self.robots.iter().map(|r| r.footprint).fold(0.0, f64::max) + NEAR_MISS_MARGIN;
        let mut order: Vec<usize> = (0..robots.len()).collect();
        order.sort_by(|&i, &j| robots[i].x.total_cmp(&robots[j].x).then(i.cmp(&j)));
        for (k, &i) in order.iter().enumerate() {
            for &j in &order[k + 1..] {
                let (ri, rj) = (&robots[i], &robots[j]);
                if rj.x - ri.x >= max_near {
                    break;
                }
                if (ri.z - rj.z).abs() >= SAME_LEVEL_DZ {
                    continue;
                }
                let d = (ri.x - rj.x).hypot(ri.y - rj.y);
                let key = (i.min(j), i.max(j));
                if d < self.robots[i].footprint + self.robots[j].footprint + NEAR_MISS_MARGIN
                    && !self.approaches.contains_key(&key)
                {
                    self.approaches.insert(key, Approach { min_d: d, t_min: t });
                }
            }
        }
    }

    fn close(&mut self, key: (usize, usize)) {
        let Some(ap) = self.approaches.remove(&key) else {
            return;
        };
        let (a, b) = (&self.robots[key.0], &self.robots[key.1]);
        let contact = a.footprint + b.footprint;
        let e = Encounter {
            robots: [a.name.clone(), b.name.clone()],
            t: ap.t_min,
            min_distance_m: ap.min_d,
            near_miss_distance_m: contact + NEAR_MISS_MARGIN,
            contact_distance_m: contact,
        };
        if ap.min_d < contact {
            self.contacts.push(e);
        } else {
            self.near_misses.push(e);
        }
    }

    pub fn finish(mut self, t: f64, robots: &[RobotTruth]) -> Report {
        if self.last_sample.is_none_or(|s| s < t) {
            self.sample(t, robots);
        }
        // What is still busy at the end is busy until the end.
        for r in &mut self.robots {
            if let Some(s) = r.busy_since.take() {
                r.busy.add(s, t);
            }
        }
        for d in &mut self.doors {
            if let Some(s) = d.open_since.take() {
                d.open.add(s, t);
            }
        }
        for l in &mut self.lifts {
            if let Some(s) = l.busy_since.take() {
                l.busy.add(s, t);
            }
        }
        let mut timeline = Timeline {
            period_s: self.period,
            series: Vec::new(),
        };
        for name in &self.fleets {
            let mut busy = Buckets::new(self.period);
            let mut n = 0;
            for r in self.robots.iter().filter(|r| &r.fleet == name) {
                busy.merge(&r.busy);
                n += 1;
            }
            timeline.series.push(timeline::Series {
                resource: format!("fleet {name}"),
                busy: busy.shares(t, n as f64),
            });
        }
        for d in &self.doors {
            timeline.series.push(timeline::Series {
                resource: format!("door {}", d.report.name),
                busy: d.open.shares(t, 1.0),
            });
        }
        for l in &self.lifts {
            timeline.series.push(timeline::Series {
                resource: format!("lift {}", l.report.name),
                busy: l.busy.shares(t, 1.0),
            });
        }
        let open: Vec<_> = self.approaches.keys().copied().collect();
        for k in open {
            self.close(k);
        }
        let by_time = |a: &Encounter, b: &Encounter| {
            a.t.total_cmp(&b.t).then_with(|| a.robots.cmp(&b.robots))
        };
        self.near_misses.sort_by(by_time);
        self.contacts.sort_by(by_time);
        self.stuck
            .sort_by(|a, b| a.t.total_cmp(&b.t).then_with(|| a.robot.cmp(&b.robot)));

        let names: Vec<(&str, &str)> = self
            .robots
            .iter()
            .map(|r| (r.name.as_str(), r.fleet.as_str()))
            .collect();
        let idle = idle::idle_with_work(&self.tasks, &names, t);
        let robots: Vec<RobotReport> = self
            .robots
            .iter()
            .map(|r| RobotReport {
                name: r.name.clone(),
                fleet: r.fleet.clone(),
                distance_m: r.distance,
                busy_s: r.busy.total(),
                idle_with_work_s: idle.get(&r.name).copied().unwrap_or(0.0),
                battery_soc: 1.0,
            })
            .collect();
        let fleets = self
            .fleets
            .iter()
            .map(|name| {
                let mine: Vec<&RobotReport> = robots.iter().filter(|r| &r.fleet == name).collect();
                let tasks = self.tasks.iter().filter(|k| &k.fleet == name);
                let count = |res: &str| tasks.clone().filter(|k| k.result == res).count();
                let completed = count("completed");
                let busy: f64 = mine.iter().map(|r| r.busy_s).sum();
                FleetReport {
                    name: name.clone(),
                    robots: mine.len(),
                    reserve: self.reserve.get(name).copied().unwrap_or(0),
                    tasks_completed: completed,
                    tasks_failed: count("failed"),
                    tasks_unfinished: count("unfinished"),
                    throughput_per_hour: if t > 0.0 {
                        completed as f64 / (t / 3600.0)
                    } else {
                        0.0
                    },
                    utilisation: if t > 0.0 && !mine.is_empty() {
                        busy / (t * mine.len() as f64)
                    } else {
                        0.0
                    },
                    distance_m: mine.iter().map(|r| r.distance_m).sum(),
                    idle_with_work_s: mine.iter().map(|r| r.idle_with_work_s).sum(),
                }
            })
            .collect();
        let share = |busy: f64| if t > 0.0 { busy / t } else { 0.0 };
        let doors = self
            .doors
            .into_iter()
            .map(|mut d| {
                d.report.wait.unserved += d.sessions.values().filter(|p| p.is_some()).count();
                d.report.utilisation = share(d.open.total());
                d.report
            })
            .collect();
        let lifts = self
            .lifts
            .into_iter()
            .map(|mut l| {
                l.report.wait.unserved += l.sessions.values().filter(|p| p.is_some()).count();
                l.report.utilisation = share(l.busy.total());
                l.report
            })
            .collect();
        let (waits, bottleneck) = bottleneck(&self.tasks);
        Report {
            end_time: t,
            tasks: self.tasks,
            fleets,
            robots,
            doors,
            lifts,
            near_misses: self.near_misses,
            contacts: self.contacts,
            stuck: self.stuck,
            waits,
            bottleneck,
            throughput: None,
            timeline,
            interrupted: false,
            crowd: None,
            traffic: TrafficReport::default(),
            warnings: Vec::new(),
            requests: Vec::new(),
        }
    }
}

/// Task waits by cause, and the place waited at longest over all tasks (ties by name).
fn bottleneck(tasks: &[TaskReport]) -> (WaitTotals, Option<Bottleneck>) {
    let mut totals = WaitTotals::default();
    let mut places: BTreeMap<&str, f64> = BTreeMap::new();
    for w in tasks.iter().filter_map(|k| k.waits.as_ref()) {
        totals.traffic_s += w.traffic_s;
        totals.lift_s += w.lift_s;
        totals.door_s += w.door_s;
        totals.workcell_s += w.workcell_s;
        totals.charging_s += w.charging_s;
        for (p, s) in &w.places {
            *places.entry(p).or_insert(0.0) += s;
        }
    }
    let all =
        totals.traffic_s + totals.lift_s + totals.door_s + totals.workcell_s + totals.charging_s;
    let top = places
        .iter()
        .max_by(|a, b| a.1.total_cmp(b.1).then_with(|| b.0.cmp(a.0)))
        .filter(|(_, &s)| s > 0.0)
        .map(|(p, &s)| Bottleneck {
            place: p.to_string(),
            cause: p.split(' ').next().unwrap_or_default().to_string(),
            wait_s: s,
            share: if all > 0.0 { s / all } else { 0.0 },
        });
    (totals, top)
}
