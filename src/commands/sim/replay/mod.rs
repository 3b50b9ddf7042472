//! `mapc sim --html FILE`: a self-contained page that replays a run. The [`Recorder`]
//! watches the messages the run publishes (the same ones the trace records) and keeps what
//! the page needs in compact form; [`page`] writes the HTML with the level pictures of
//! `mapc render`, the data (JSON) and the player (`replay.js`, `replay.css`) inline.
//!
//! Encoding (read by replay.js): time in ticks of 0.5 s (RobotState is published at 2 Hz,
//! so that is the finest rate kept); robot tracks as flat arrays of deltas
//! `[dticks, dx_cm, dy_cm, dyaw_deg, ...]` after an absolute first sample, with samples
//! left out while the robot stands still (the last still sample is kept before it moves
//! again, so linear interpolation between kept samples gives the 2 Hz track back);
//! everything else (level, mode, task, battery, carried item, doors) as `[tick, value, ...]`
//! change lists, lifts as `[tick, floor, door, motion, destination, ...]`.

use mapc_backends::render::{self, RenderOptions};
use mapc_ir::Building;
use mapc_sim::msgs::{door_mode, lift_request, lift_state, workcell_result, Msg, Published, Topic};
use mapc_sim::Scenario;
use serde_json::{json, Value};
use std::collections::BTreeMap;

const TICK: f64 = 0.5;

fn tick(t: f64) -> i64 {
    (t / TICK).round() as i64
}

#[derive(Default)]
struct Robot {
    name: String,
    fleet: String,
    /// (tick, x cm, y cm, yaw deg) kept, and the still sample not yet kept.
    track: Vec<i64>,
    first: Option<[i64; 4]>,
    last: [i64; 4],
    pending: Option<[i64; 4]>,
    level: Changes,
    mode: Changes,
    task: Changes,
    battery: Changes,
    carry: Changes,
}

/// `[tick, value, ...]`, appended only when the value changes.
#[derive(Default)]
struct Changes {
    v: Vec<i64>,
    last: Option<i64>,
}

impl Changes {
    fn set(&mut self, t: i64, value: i64) {
        if self.last != Some(value) {
            self.v.extend([t, value]);
            self.last = Some(value);
        }
    }
}

impl Robot {
    fn sample(&mut self, s: [i64; 4]) {
        let Some(_) = self.first else {
            self.first = Some(s);
            self.last = s;
            return;
        };
        if s[0] <= self.last[0] {
            return; // faster than 2 Hz: keep the first of the tick
        }
        if s[1..] == self.last[1..] {
            self.pending = Some(s);
            return;
        }
        if let Some(p) = self.pending.take() {
            self.push(p);
        }
        self.push(s);
    }
    fn push(&mut self, s: [i64; 4]) {
        let mut dyaw = s[3] - self.last[3];
        dyaw = (dyaw + 540).rem_euclid(360) - 180;
        self.track.extend([
            s[0] - self.last[0],
            s[1] - self.last[1],
            s[2] - self.last[2],
            dyaw,
        ]);
        self.last = [s[0], s[1], s[2], self.last[3] + dyaw];
    }
    fn finish(&mut self) {
        if let Some(p) = self.pending.take() {
            self.push(p);
        }
    }
}

#[derive(Default)]
struct Task {
    id: String,
    category: String,
    robot: Option<usize>,
    queued: Option<f64>,
    started: Option<f64>,
    ended: Option<f64>,
    ok: Option<bool>,
    detail: String,
}

#[derive(Default)]
struct Door {
    modes: Changes,
    waits: Vec<f64>,
    /// Requester → time of its open request not yet served.
    pending: BTreeMap<String, f64>,
}

#[derive(Default)]
struct Lift {
    /// `[tick, floor, door state, motion state, destination floor, ...]` on change.
    state: Vec<i64>,
    last: Option<[i64; 4]>,
    waits: Vec<f64>,
    /// Session → (request time, floor) of its first request, until served.
    pending: BTreeMap<String, (f64, String)>,
    /// Sessions whose summons was served (their later requests are rides, not waits).
    served: Vec<String>,
}

/// People from `/rmf_obstacles` (one message per tick while the crowd walks): the first
/// position of each in centimetres, then per tick `[dx, dy]` deltas.
#[derive(Default)]
struct People {
    start: Option<i64>,
    level: i64,
    r: Vec<f64>,
    first: Vec<[i64; 2]>,
    last: Vec<[i64; 2]>,
    track: Vec<Vec<i64>>,
}

/// Collects a run's messages for the replay page.
pub struct Recorder<'a> {
    building: &'a Building,
    scenario: &'a Scenario,
    robots: Vec<Robot>,
    robot_index: BTreeMap<String, usize>,
    fleet_of: BTreeMap<String, String>,
    tasks: Vec<Task>,
    task_index: BTreeMap<String, usize>,
    doors: BTreeMap<String, Door>,
    lifts: BTreeMap<String, Lift>,
    people: People,
    end: f64,
}

impl<'a> Recorder<'a> {
    pub fn new(building: &'a Building, scenario: &'a Scenario) -> Self {
        Recorder {
            building,
            scenario,
            robots: Vec::new(),
            robot_index: BTreeMap::new(),
            fleet_of: BTreeMap::new(),
            tasks: Vec::new(),
            task_index: BTreeMap::new(),
            doors: BTreeMap::new(),
            lifts: BTreeMap::new(),
            people: People::default(),
            end: 0.0,
        }
    }

    fn level_index(&self, name: &str) -> i64 {
        self.building
            .levels
            .iter()
            .position(|(_, l)| l.name == name)
            .map_or(-1, |i| i as i64)
    }

    fn robot(&mut self, name: &str) -> usize {
        if let Some(&i) = self.robot_index.get(name) {
            return i;
        }
        let i = self.robots.len();
        self.robots.push(Robot {
            name: name.to_string(),
            fleet: self.fleet_of.get(name).cloned().unwrap_or_default(),
            ..Robot::default()
        });
        self.robot_index.insert(name.to_string(), i);
        i
    }

    fn task(&mut self, id: &str) -> usize {
        if let Some(&i) = self.task_index.get(id) {
            return i;
        }
        let i = self.tasks.len();
        self.tasks.push(Task {
            id: id.to_string(),
            ..Task::default()
        });
        self.task_index.insert(id.to_string(), i);
        i
    }

    /// The robot of the task a workcell request guid belongs to (`<task>_pickup...`).
    fn robot_of_guid(&self, guid: &str) -> Option<usize> {
        let base = guid
            .rsplit_once("_pickup")
            .or_else(|| guid.rsplit_once("_dropoff"))
            .map(|(b, _)| b)?;
        self.task_index.get(base).and_then(|&t| self.tasks[t].robot)
    }

    pub fn observe(&mut self, p: &Published) {
        let t = p.t;
        self.end = self.end.max(t);
        let tk = tick(t);
        match (&p.topic, &p.msg) {
            (Topic::RmfObstacles, Msg::Obstacles(o)) => {
                let start = *self.people.start.get_or_insert(tk);
                if let Some(first) = o.obstacles.first() {
                    self.people.level = self.level_index(&first.level_name);
                }
                let k = (tk - start).max(0) as usize;
                for (i, ob) in o.obstacles.iter().enumerate() {
                    let c = &ob.bbox.center.position;
                    let xy = [(c.x * 100.0).round() as i64, (c.y * 100.0).round() as i64];
                    let pp = &mut self.people;
                    if i >= pp.first.len() {
                        pp.r.push(ob.bbox.size.x / 2.0);
                        pp.first.push(xy);
                        pp.last.push(xy);
                        pp.track.push(Vec::new());
                    }
                    // One sample per tick after the first message (a person seen late
                    // stands at its first position until then).
                    if k == 0 {
                        continue;
                    }
                    while pp.track[i].len() / 2 < k - 1 {
                        pp.track[i].extend([0, 0]);
                    }
                    if pp.track[i].len() / 2 == k - 1 {
                        let l = pp.last[i];
                        pp.track[i].extend([xy[0] - l[0], xy[1] - l[1]]);
                        pp.last[i] = xy;
                    }
                }
            }
            (Topic::FleetStates, Msg::FleetState(f)) => {
                for r in &f.robots {
                    if !self.fleet_of.contains_key(&r.name) {
                        self.fleet_of.insert(r.name.clone(), f.name.clone());
                        if let Some(&i) = self.robot_index.get(&r.name) {
                            self.robots[i].fleet = f.name.clone();
                        }
                    }
                }
            }
            (Topic::RobotState, Msg::RobotState(s)) => {
                let i = self.robot(&s.name);
                let level = self.level_index(&s.location.level_name);
                let r = &mut self.robots[i];
                let loc = &s.location;
                r.sample([
                    tk,
                    (loc.x * 100.0).round() as i64,
                    (loc.y * 100.0).round() as i64,
                    loc.yaw.to_degrees().round() as i64,
                ]);
                r.level.set(tk, level);
                r.mode.set(tk, s.mode.mode as i64);
                if r.task.last.is_none() {
                    r.task.set(tk, -1);
                }
                r.battery.set(tk, s.battery_percent.round() as i64);
            }
            (Topic::TaskEvents, Msg::TaskEvent(e)) => {
                let ti = self.task(&e.task_id);
                let robot = (!e.robot.is_empty()).then(|| self.robot(&e.robot));
                let task = &mut self.tasks[ti];
                task.category.clone_from(&e.category);
                if robot.is_some() {
                    task.robot = robot;
                }
                // The robot's task is the one it started until that one ends (RobotState's
                // task_id names the path request, not the task).
                match e.event.as_str() {
                    "queued" => task.queued = Some(t),
                    "started" => {
                        task.started = Some(t);
                        if let Some(r) = task.robot {
                            self.robots[r].task.set(tk, ti as i64);
                        }
                    }
                    "completed" | "failed" => {
                        task.ended = Some(t);
                        task.ok = Some(e.event == "completed");
                        task.detail.clone_from(&e.detail);
                        if let Some(r) = task.robot {
                            let robot = &mut self.robots[r];
                            robot.carry.set(tk, 0);
                            if robot.task.last == Some(ti as i64) {
                                robot.task.set(tk, -1);
                            }
                        }
                    }
                    _ => {
                        if !e.detail.is_empty() {
                            task.detail.clone_from(&e.detail);
                        }
                    }
                }
            }
            (Topic::DispenserResults | Topic::IngestorResults, Msg::WorkcellResult(w))
                if w.status == workcell_result::SUCCESS =>
            {
                if let Some(r) = self.robot_of_guid(&w.request_guid) {
                    let carrying = p.topic == Topic::DispenserResults;
                    self.robots[r].carry.set(tk, i64::from(carrying));
                }
            }
            (Topic::AdapterDoorRequests, Msg::DoorRequest(d)) => {
                let door = self.doors.entry(d.door_name.clone()).or_default();
                if d.requested_mode.value == door_mode::OPEN {
                    door.pending.entry(d.requester_id.clone()).or_insert(t);
                } else {
                    door.pending.remove(&d.requester_id);
                }
            }
            (Topic::DoorStates, Msg::DoorState(d)) => {
                let door = self.doors.entry(d.door_name.clone()).or_default();
                door.modes.set(tk, d.current_mode.value as i64);
                if d.current_mode.value == door_mode::OPEN {
                    for (_, t0) in std::mem::take(&mut door.pending) {
                        door.waits.extend([t0, t - t0]);
                    }
                }
            }
            (Topic::AdapterLiftRequests, Msg::LiftRequest(l)) => {
                let lift = self.lifts.entry(l.lift_name.clone()).or_default();
                if l.request_type == lift_request::END_SESSION {
                    lift.pending.remove(&l.session_id);
                    lift.served.retain(|s| s != &l.session_id);
                } else if !lift.served.contains(&l.session_id) {
                    lift.pending
                        .entry(l.session_id.clone())
                        .or_insert((t, l.destination_floor.clone()));
                }
            }
            (Topic::LiftStates, Msg::LiftState(l)) => {
                let floor = self.level_index(&l.current_floor);
                let dest = self.level_index(&l.destination_floor);
                let lift = self.lifts.entry(l.lift_name.clone()).or_default();
                let st = [floor, l.door_state as i64, l.motion_state as i64, dest];
                if lift.last != Some(st) {
                    lift.state.extend([tk, st[0], st[1], st[2], st[3]]);
                    lift.last = Some(st);
                }
                if l.door_state == lift_state::DOOR_OPEN {
                    if let Some((t0, dest)) = lift.pending.get(&l.session_id) {
                        if *dest == l.current_floor {
                            lift.waits.extend([*t0, t - t0]);
                            lift.pending.remove(&l.session_id);
                            lift.served.push(l.session_id.clone());
                        }
                    }
                }
            }
            _ => {}
        }
    }

    /// The page's data.
    fn data(mut self) -> Value {
        let b = self.building;
        for r in &mut self.robots {
            r.finish();
        }
        let levels: Vec<Value> = b
            .levels
            .iter()
            .enumerate()
            .map(|(i, (h, l))| {
                let view = render::level_view(b, h);
                let svg = render::render_level(b, h, &RenderOptions::default());
                json!({
                    "name": l.name,
                    "svg": embeddable(&svg, i),
                    "view": [view.k, view.min_x, view.max_y, view.left, view.top],
                })
            })
            .collect();
        let footprint = |fleet: &str| {
            self.scenario
                .fleets
                .iter()
                .find(|f| f.name == fleet)
                .map_or(0.3, |f| f.robot.footprint)
        };
        let fleets: Vec<&str> = self
            .scenario
            .fleets
            .iter()
            .map(|f| f.name.as_str())
            .collect();
        let robots: Vec<Value> = self
            .robots
            .iter()
            .map(|r| {
                json!({
                    "name": r.name,
                    "fleet": fleets.iter().position(|f| *f == r.fleet).map_or(-1, |i| i as i64),
                    "r": footprint(&r.fleet),
                    "first": r.first.unwrap_or_default(),
                    "track": r.track,
                    "level": r.level.v,
                    "mode": r.mode.v,
                    "task": r.task.v,
                    "battery": r.battery.v,
                    "carry": r.carry.v,
                })
            })
            .collect();
        let round = |x: f64| (x * 10.0).round() / 10.0;
        let opt = |x: Option<f64>| x.map(round);
        let tasks: Vec<Value> = self
            .tasks
            .iter()
            .map(|t| {
                json!({
                    "id": t.id,
                    "cat": t.category,
                    "robot": t.robot.map_or(-1, |r| r as i64),
                    "q": opt(t.queued),
                    "s": opt(t.started),
                    "e": opt(t.ended),
                    "ok": t.ok,
                    "detail": t.detail,
                })
            })
            .collect();
        let doors: Vec<Value> = self
            .doors
            .iter()
            .map(|(name, d)| {
                json!({
                    "name": name,
                    "modes": d.modes.v,
                    "waits": d.waits.iter().map(|&x| round(x)).collect::<Vec<_>>(),
                })
            })
            .collect();
        let lifts: Vec<Value> = self
            .lifts
            .iter()
            .map(|(name, l)| {
                json!({
                    "name": name,
                    "state": l.state,
                    "waits": l.waits.iter().map(|&x| round(x)).collect::<Vec<_>>(),
                })
            })
            .collect();
        let mut data = json!({
            "building": b.name,
            "tick": TICK,
            "end": round(self.end),
            "fleets": fleets,
            "levels": levels,
            "robots": robots,
            "tasks": tasks,
            "doors": doors,
            "lifts": lifts,
        });
        // Only when people walked, so pages of runs without them are unchanged.
        if let (Some(start), Some(obj)) = (self.people.start, data.as_object_mut()) {
            let p = &self.people;
            obj.insert(
                "people".into(),
                json!({
                    "start": start,
                    "level": p.level,
                    "r": p.r,
                    "first": p.first,
                    "track": p.track,
                }),
            );
        }
        data
    }

    /// The complete HTML page.
    pub fn page(self) -> String {
        let title = format!("{}: replay", self.building.name);
        // `<` only occurs inside JSON strings, where `\u003c` means the same; so no
        // `</script>` can end the data early.
        let data = self.data().to_string().replace('<', "\\u003c");
        let mut html = String::with_capacity(data.len() + 64 * 1024);
        html.push_str("<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n");
        html.push_str("<meta name=\"viewport\" content=\"width=device-width\">\n<title>");
        html.push_str(&escape_html(&title));
        html.push_str("</title>\n<style>\n");
        html.push_str(include_str!("replay.css"));
        html.push_str("</style>\n</head>\n<body>\n");
        html.push_str(include_str!("body.html"));
        html.push_str("<script id=\"data\" type=\"application/json\">");
        html.push_str(&data);
        html.push_str("</script>\n<script>\n");
        html.push_str(include_str!("replay.js"));
        html.push_str("</script>\n</body></html>\n");
        html
    }
}

/// A level picture ready to sit inline in the page: no XML namespace attribute (an inline
/// `<svg>` in HTML needs none, and the page references no URL), ids unique per level.
fn embeddable(svg: &str, level: usize) -> String {
    svg.replace(" xmlns=\"http://www.w3.org/2000/svg\"", "")
        .replace("id=\"map-area\"", &format!("id=\"map-area-{level}\""))
        .replace("url(#map-area)", &format!("url(#map-area-{level})"))
}

fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn still_samples_are_left_out_but_the_last_is_kept() {
        let mut r = Robot::default();
        r.sample([0, 0, 0, 0]);
        r.sample([1, 0, 0, 0]);
        r.sample([2, 0, 0, 0]);
        r.sample([3, 10, 0, 0]);
        r.sample([3, 20, 0, 0]); // same tick: ignored
        r.sample([4, 20, 0, 350]);
        r.finish();
        assert_eq!(r.first, Some([0, 0, 0, 0]));
        // Kept: tick 2 (last still), 3, 4; yaw 0 → 350 is a turn of -10 degrees.
        assert_eq!(r.track, vec![2, 0, 0, 0, 1, 10, 0, 0, 1, 10, 0, -10]);
    }

    #[test]
    fn changes_keep_only_new_values() {
        let mut c = Changes::default();
        c.set(0, 1);
        c.set(1, 1);
        c.set(2, 3);
        assert_eq!(c.v, vec![0, 1, 2, 3]);
    }

    #[test]
    fn embedded_svg_has_no_url_and_unique_ids() {
        let svg = "<svg xmlns=\"http://www.w3.org/2000/svg\"><clipPath id=\"map-area\"/><g clip-path=\"url(#map-area)\"/></svg>";
        let e = embeddable(svg, 2);
        assert!(!e.contains("http"));
        assert!(e.contains("id=\"map-area-2\"") && e.contains("url(#map-area-2)"));
    }
}
