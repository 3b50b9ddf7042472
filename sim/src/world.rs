//! The simulated building: slotcars, doors, lifts, dispensers and ingestors, and the door
//! and lift supervisors, stepped in the order the Gazebo plugins run (runtime spec §0).
//!
//! Positions are in the map frame (nav-graph coordinates; `Building::offset` is not
//! subtracted), z = level elevation. Within one step: buffered requests are handled
//! first (ROS callbacks; a supervisor's answer to an adapter request reaches the plugins
//! in the same step), then slotcars, the door manager, the lift manager, dispensers and
//! ingestors; then the poses are integrated, and the supervisors react to the states
//! published in this step (their requests reach the plugins in the next step). Messages
//! are stamped with the time at the start of the step; `time()` is `steps · dt`.
//!
//! What is simulated: doors with a controller (`plugin` not `none`, known type), lifts
//! with `plugins` and at least one served level (cabin doors `CabinDoor_<lift>_<door>`,
//! shaft doors `ShaftDoor_<lift>_<level>_<door>`, floors in `level_doors` order),
//! `TeleportDispenser`/`TeleportIngestor` map models plus the scenario's workcells, one
//! item `<dispenser>_item` per dispenser, the map's non-static models as items (carts),
//! and chargers at the nav-graph vertices with `is_charger` true (any graph). Obstacles
//! for the slotcars' stop test are the other robots and the people of `crowd/`.

use crate::door::{self, DoorSim};
use crate::lift::{Cabin, Floor, LiftSim};
use crate::msgs::{DoorRequest, LiftRequest, Msg, Published, Topic, WorkcellRequest};
use crate::params::RobotParams;
use crate::scenario::WorkcellKind;
use crate::slotcar::{ChargeFlags, Ctx, Obstacles, Slotcar};
use crate::supervisor::{DoorSupervisor, LiftSupervisor};
use crate::truth::Item;
// Moved to `truth`; the old path stays for the code that names it here (report.rs).
pub(crate) use crate::truth::RobotTruth;
use crate::workcell::Workcell;
use mapc_ir::{Building, DoorKind, Handle, Level};
use std::collections::BTreeMap;

/// A robot placed in the world at start-up.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotSpawn {
    pub name: String,
    pub fleet: String,
    pub params: RobotParams,
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
    pub level: Handle<Level>,
}

/// A dispenser or ingestor placed in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkcellSpawn {
    pub name: String,
    pub kind: crate::scenario::WorkcellKind,
    pub x: f64,
    pub y: f64,
    pub level: Handle<Level>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct WorldSetup {
    pub dt: f64,
    pub seed: u64,
    pub robots: Vec<RobotSpawn>,
    /// Workcells from the scenario; the map's TeleportDispenser/TeleportIngestor models are
    /// added by `World::new`.
    pub workcells: Vec<WorkcellSpawn>,
    pub lifts_start_at_initial_floor: bool,
}

/// A robot, door or lift out of service over `[from, to)`.
struct Fault {
    from: f64,
    to: f64,
    what: Faulted,
    /// A robot's pause was requested (and, after `to`, its resume).
    paused: bool,
    resumed: bool,
}

#[derive(Clone, Copy, PartialEq)]
enum Faulted {
    Robot(usize),
    Door(usize),
    Lift(usize),
}

pub struct World {
    dt: f64,
    steps: u64,
    t: f64,
    levels: Vec<(String, f64)>,
    chargers: Vec<[f64; 3]>,
    flags: ChargeFlags,
    robots: Vec<Slotcar>,
    robot_index: BTreeMap<String, usize>,
    obstacles: Obstacles,
    doors: Vec<DoorSim>,
    /// ROS doors by name (lift doors have no ROS interface).
    door_index: BTreeMap<String, usize>,
    lifts: Vec<LiftSim>,
    lift_index: BTreeMap<String, usize>,
    workcells: Vec<Workcell>,
    items: Vec<Item>,
    /// Robot indices per fleet name, from the last `/fleet_states`.
    fleets: BTreeMap<String, Vec<usize>>,
    door_supervisor: DoorSupervisor,
    lift_supervisor: LiftSupervisor,
    /// Off when RMF's own supervisors drive the plugins (`plugins_only`).
    supervisors: bool,
    /// Messages for the supervisors and workcells, handled at the start of the next step.
    inbox: Vec<(Topic, Msg)>,
    /// Supervisor requests for the plugins, applied at the start of the next step.
    to_doors: Vec<DoorRequest>,
    to_lifts: Vec<LiftRequest>,
    /// Things out of service for a while (`Scenario::faults`).
    faults: Vec<Fault>,
    first_step: bool,
    /// The people (`crowd/`), when the map's crowd walks.
    crowd: Option<crate::crowd::Crowd>,
}

/// `(lower, upper)` of the right joint, of the left joint if any, and the door family.
type DoorJoints = ((f64, f64), Option<(f64, f64)>, door::DoorParams);

fn door_joints(b: &Building, d: &mapc_ir::Door) -> Option<DoorJoints> {
    let s = b.vertices[d.start].pos;
    let e = b.vertices[d.end].pos;
    let l = s.minus(e).norm();
    // The generator's swing limit uses 3.14, not π (§2.1).
    #[allow(clippy::approx_constant)]
    let mu = 3.14 * d.motion_degrees / 180.0;
    let k = d.right_left_ratio;
    let l_r = k / (1.0 + k) * l;
    let l_l = l - l_r;
    Some(match d.kind {
        DoorKind::Sliding => ((0.0, l), None, door::SLIDING),
        DoorKind::DoubleSliding => ((0.0, l_r), Some((-l_l, 0.0)), door::SLIDING),
        DoorKind::Hinged => ((0.0, mu), None, door::SWING),
        DoorKind::DoubleHinged => ((0.0, mu), Some((-mu, 0.0)), door::SWING),
        DoorKind::Other(_) => return None,
    })
}

impl World {
    pub fn new(building: &Building, setup: &WorldSetup) -> World {
        let b = building;
        let mut rng = fastrand::Rng::with_seed(setup.seed);
        let floors_z = crate::levels::elevations(b);
        let levels: Vec<(String, f64)> = b
            .levels
            .iter()
            .zip(&floors_z)
            .map(|((_, l), &z)| (l.name.clone(), z))
            .collect();
        let elev = |h: Handle<Level>| levels.get(h.index()).map_or(0.0, |l| l.1);
        let chargers = b
            .vertices
            .iter()
            .filter(|(_, v)| v.roles.is_charger)
            .map(|(_, v)| [v.pos.x, v.pos.y, elev(v.level)])
            .collect();

        let mut robots = Vec::new();
        let mut robot_index = BTreeMap::new();
        for (i, r) in setup.robots.iter().enumerate() {
            robot_index.entry(r.name.clone()).or_insert(i);
            robots.push(Slotcar::new(
                r.name.clone(),
                r.params.clone(),
                [r.x, r.y, elev(r.level), r.yaw],
                (r.level.index() < levels.len()).then_some(r.level.index()),
            ));
        }

        let mut doors = Vec::new();
        let mut door_index = BTreeMap::new();
        for (_, d) in b.doors.iter() {
            if !d.plugin {
                continue;
            }
            let Some((right, left, params)) = door_joints(b, d) else {
                continue;
            };
            let mut door = DoorSim::new(d.name.clone(), true, right, left, params);
            door.set_phase(rng.f64());
            door_index.entry(d.name.clone()).or_insert(doors.len());
            doors.push(door);
        }

        let mut lifts = Vec::new();
        let mut lift_index = BTreeMap::new();
        for (_, l) in b.lifts.iter() {
            if !l.plugins || l.level_doors.is_empty() {
                continue;
            }
            let mut cabin_doors = Vec::new();
            for ld in &l.doors {
                let half = ld.width / 2.0;
                cabin_doors.push(doors.len());
                doors.push(DoorSim::new(
                    format!("CabinDoor_{}_{}", l.name, ld.name),
                    false,
                    (0.0, half),
                    Some((-half, 0.0)),
                    door::LIFT_DOOR,
                ));
            }
            let mut floors = Vec::new();
            for lvl in &l.level_doors {
                let (lname, lelev) = levels.get(lvl.level.index()).cloned().unwrap_or_default();
                let mut fd = Vec::new();
                for (k, ld) in l.doors.iter().enumerate() {
                    if lvl.doors.iter().any(|(n, _)| *n == ld.name) {
                        let half = ld.width / 2.0;
                        fd.push(doors.len());
                        doors.push(DoorSim::new(
                            format!("ShaftDoor_{}_{}_{}", l.name, lname, ld.name),
                            false,
                            (0.0, half),
                            Some((-half, 0.0)),
                            door::LIFT_DOOR,
                        ));
                        fd.push(cabin_doors[k]);
                    }
                }
                floors.push(Floor {
                    name: lname,
                    elevation: lelev,
                    doors: fd,
                });
            }
            let initial = l
                .initial_floor()
                .and_then(|h| levels.get(h.index()))
                .and_then(|(n, _)| floors.iter().position(|f| f.name == *n))
                .unwrap_or(0);
            let z = if setup.lifts_start_at_initial_floor {
                floors.get(initial).map_or(0.0, |f| f.elevation)
            } else {
                0.0
            };
            let cabin = Cabin {
                x: l.pos.x,
                y: l.pos.y,
                yaw: l.yaw,
                half: [
                    l.width / 2.0 + mapc_ir::SHAFT_MARGIN,
                    l.depth / 2.0 + mapc_ir::SHAFT_MARGIN,
                ],
            };
            let mut lift = LiftSim::new(l.name.clone(), floors, initial, z, cabin);
            lift.set_phase(rng.f64());
            lift_index.entry(l.name.clone()).or_insert(lifts.len());
            lifts.push(lift);
        }

        let mut items = Vec::new();
        let mut workcells = Vec::new();
        let mut add_workcell = |name: String, kind: WorkcellKind, pos: [f64; 3]| {
            let item = (kind == WorkcellKind::Dispenser).then(|| {
                items.push(Item::new(format!("{name}_item"), pos, 0.0));
                items.len() - 1
            });
            workcells.push(Workcell::new(name, kind, pos, item));
        };
        for (_, m) in b.models.iter() {
            let kind = if m.model_name.ends_with("TeleportDispenser") {
                WorkcellKind::Dispenser
            } else if m.model_name.ends_with("TeleportIngestor") {
                WorkcellKind::Ingestor
            } else {
                continue;
            };
            add_workcell(
                m.name.clone(),
                kind,
                [m.pos.x, m.pos.y, elev(m.level) + m.z],
            );
        }
        for w in &setup.workcells {
            add_workcell(w.name.clone(), w.kind, [w.x, w.y, elev(w.level)]);
        }
        // Non-static map models (carts, boxes) can be attached and ingested too.
        for (_, m) in b.models.iter() {
            if !m.is_static
                && !m.model_name.ends_with("TeleportDispenser")
                && !m.model_name.ends_with("TeleportIngestor")
            {
                items.push(Item::new(
                    m.name.clone(),
                    [m.pos.x, m.pos.y, elev(m.level) + m.z],
                    m.yaw,
                ));
            }
        }

        World {
            dt: setup.dt,
            steps: 0,
            t: 0.0,
            levels,
            chargers,
            flags: ChargeFlags::default(),
            robots,
            robot_index,
            obstacles: Obstacles::default(),
            doors,
            door_index,
            lifts,
            lift_index,
            workcells,
            items,
            fleets: BTreeMap::new(),
            door_supervisor: DoorSupervisor::default(),
            lift_supervisor: LiftSupervisor::default(),
            supervisors: true,
            inbox: Vec::new(),
            to_doors: Vec::new(),
            to_lifts: Vec::new(),
            faults: Vec::new(),
            first_step: true,
            crowd: None,
        }
    }

    /// Adds the map's people.
    pub fn set_crowd(&mut self, crowd: crate::crowd::Crowd) {
        self.crowd = Some(crowd);
    }

    pub fn crowd(&self) -> Option<&crate::crowd::Crowd> {
        self.crowd.as_ref()
    }

    /// Current sim time (s).
    pub fn time(&self) -> f64 {
        self.t
    }

    /// A message from outside (fleet layer) on an input topic: handled like a ROS callback,
    /// i.e. before the next step. Messages on other topics, and requests for unknown
    /// robots, doors, lifts or workcells, are ignored.
    pub fn deliver(&mut self, topic: Topic, msg: Msg) {
        let robot = |w: &mut World, name: &str| w.robot_index.get(name).copied();
        match (topic, msg) {
            (Topic::RobotPathRequests, Msg::PathRequest(m)) => {
                if let Some(i) = robot(self, &m.robot_name) {
                    self.robots[i].path_request(m);
                }
            }
            (Topic::RobotModeRequests, Msg::ModeRequest(m)) => {
                if let Some(i) = robot(self, &m.robot_name) {
                    self.robots[i].mode_request(m.mode);
                }
            }
            (Topic::RobotPauseRequests, Msg::PauseRequest(m)) => {
                if let Some(i) = robot(self, &m.robot_name) {
                    self.robots[i].pause_request(m.kind, m.mode_request_id, m.at_checkpoint);
                }
            }
            (Topic::FleetStates, Msg::FleetState(f)) => {
                let members = f
                    .robots
                    .iter()
                    .filter_map(|r| self.robot_index.get(&r.name).copied())
                    .collect();
                self.fleets.insert(f.name, members);
            }
            (Topic::DoorRequests, Msg::DoorRequest(m)) => self.to_doors.push(m),
            (Topic::LiftRequests, Msg::LiftRequest(m)) => self.to_lifts.push(m),
            (
                t @ (Topic::AdapterDoorRequests
                | Topic::AdapterLiftRequests
                | Topic::DispenserRequests
                | Topic::IngestorRequests),
                m,
            ) => self.inbox.push((t, m)),
            _ => {}
        }
    }

    /// Puts robots, doors and lifts out of service for a while. Returns the faults that
    /// name nothing in this world (by index in `faults`).
    pub fn set_faults(&mut self, faults: &[crate::scenario::FaultSpec]) -> Vec<usize> {
        use crate::scenario::FaultTarget;
        let mut unknown = Vec::new();
        self.faults.clear();
        for (k, f) in faults.iter().enumerate() {
            let what = match &f.target {
                FaultTarget::Robot(n) => self.robot_index.get(n).map(|&i| Faulted::Robot(i)),
                FaultTarget::Door(n) => self.door_index.get(n).map(|&i| Faulted::Door(i)),
                FaultTarget::Lift(n) => self.lift_index.get(n).map(|&i| Faulted::Lift(i)),
            };
            match what {
                Some(what) => self.faults.push(Fault {
                    from: f.at,
                    to: f.at + f.duration,
                    what,
                    paused: false,
                    resumed: false,
                }),
                None => unknown.push(k),
            }
        }
        unknown
    }

    /// Whether `what` is out of service at `t`.
    fn out_of_service(&self, what: Faulted, t: f64) -> bool {
        self.faults
            .iter()
            .any(|f| f.what == what && f.from <= t && t < f.to)
    }

    /// Pauses and resumes the robots whose faults begin or end at `t` (as a pause request
    /// from outside would).
    fn robot_faults(&mut self, t: f64) {
        use crate::msgs::pause_type;
        for f in &mut self.faults {
            let Faulted::Robot(i) = f.what else { continue };
            let Some(r) = self.robots.get_mut(i) else {
                continue;
            };
            if !f.paused && t >= f.from {
                f.paused = true;
                r.pause_request(pause_type::PAUSE_IMMEDIATELY, 0, 0);
            }
            if f.paused && !f.resumed && t >= f.to {
                f.resumed = true;
                r.pause_request(pause_type::RESUME, 0, 0);
            }
        }
    }

    /// Whether mapc's door and lift supervisors run (off: only the plugins answer requests).
    pub fn set_supervisors(&mut self, on: bool) {
        self.supervisors = on;
    }

    /// Sets the world-wide `/charge_state` toggles (§1.9, §8).
    pub fn set_charging(&mut self, enable_charge: bool, instant_charge: bool, enable_drain: bool) {
        self.flags = ChargeFlags {
            enable_charge,
            enable_instant_charge: instant_charge,
            enable_drain,
        };
    }

    fn callbacks(&mut self, t: f64, out: &mut Vec<Published>) {
        let mut inbox = std::mem::take(&mut self.inbox);
        for (topic, msg) in inbox.drain(..) {
            match (topic, &msg) {
                (Topic::AdapterDoorRequests, Msg::DoorRequest(m)) => self
                    .door_supervisor
                    .adapter_request(t, m, out, &mut self.to_doors),
                (Topic::AdapterLiftRequests, Msg::LiftRequest(m)) => self
                    .lift_supervisor
                    .adapter_request(t, m, out, &mut self.to_lifts),
                (Topic::DispenserRequests, Msg::WorkcellRequest(m)) => {
                    self.workcell_request(t, WorkcellKind::Dispenser, m, out)
                }
                (Topic::IngestorRequests, Msg::WorkcellRequest(m)) => {
                    self.workcell_request(t, WorkcellKind::Ingestor, m, out)
                }
                _ => {}
            }
        }
        self.inbox = inbox;
        // A door or lift out of service answers nothing (its requests are lost, as with a
        // plugin that is down).
        for r in std::mem::take(&mut self.to_doors) {
            if let Some(&i) = self.door_index.get(&r.door_name) {
                if self.out_of_service(Faulted::Door(i), t) {
                    continue;
                }
                if let Some(d) = self.doors.get_mut(i) {
                    d.command(r.requested_mode.value == crate::msgs::door_mode::OPEN);
                }
            }
        }
        for r in std::mem::take(&mut self.to_lifts) {
            if let Some(&i) = self.lift_index.get(&r.lift_name) {
                if self.out_of_service(Faulted::Lift(i), t) {
                    continue;
                }
                if let Some(l) = self.lifts.get_mut(i) {
                    l.request(&r);
                }
            }
        }
    }

    fn workcell_request(
        &mut self,
        t: f64,
        kind: WorkcellKind,
        m: &WorkcellRequest,
        out: &mut Vec<Published>,
    ) {
        for w in self.workcells.iter_mut().filter(|w| w.kind == kind) {
            w.request(t, m, out);
        }
    }

    /// Advances one step; appends everything published during it.
    pub fn step(&mut self, out: &mut Vec<Published>) {
        let t = self.t;
        let dt = self.dt;
        let start = out.len();
        self.robot_faults(t);
        self.callbacks(t, out);

        // Slotcars read the poses at the start of the step.
        self.obstacles.rebuild(&self.robots);
        let ctx = Ctx {
            t,
            dt,
            levels: &self.levels,
            chargers: &self.chargers,
            obstacles: &self.obstacles,
            flags: self.flags,
            people: self.crowd.as_ref().map(|c| c as &dyn crate::truth::People),
        };
        for (i, r) in self.robots.iter_mut().enumerate() {
            r.update(&ctx, i, &mut self.items, out);
        }
        // Door manager; its first update only initialises (§2.3).
        if !self.first_step {
            for d in &mut self.doors {
                d.update(t, dt, out);
            }
        }
        for l in &mut self.lifts {
            l.update(t, dt, &mut self.doors, &mut self.robots, out);
        }
        for w in &mut self.workcells {
            w.update(t, &self.robots, &mut self.items, &self.fleets, out);
        }
        self.first_step = false;

        // Physics.
        for r in &mut self.robots {
            r.integrate(dt);
        }
        for d in &mut self.doors {
            d.integrate(dt);
        }
        for l in &mut self.lifts {
            l.integrate(dt);
        }
        for it in &mut self.items {
            it.follow(&self.robots);
        }
        // The crowd plugin runs after the slotcars and sees their new poses.
        if self.crowd.is_some() {
            let robots = self.robots();
            if let Some(c) = self.crowd.as_mut() {
                c.tick(self.steps + 1, t, &robots, out);
            }
        }

        // Supervisors react to this step's states; their requests apply next step.
        let end = if self.supervisors { out.len() } else { start };
        for k in start..end {
            match &out[k].msg {
                Msg::DoorState(s) => {
                    let s = s.clone();
                    self.door_supervisor
                        .door_state(t, &s, out, &mut self.to_doors);
                }
                Msg::LiftState(s) => {
                    let s = s.clone();
                    self.lift_supervisor
                        .lift_state(t, &s, out, &mut self.to_lifts);
                }
                _ => {}
            }
        }

        self.steps += 1;
        // Whole steps times dt: no drift from summing dt.
        self.t = self.steps as f64 * dt;
    }

    /// Robots in spawn order.
    pub fn robots(&self) -> Vec<RobotTruth> {
        self.robots
            .iter()
            .map(|r| RobotTruth {
                x: r.x,
                y: r.y,
                z: r.z,
                yaw: r.yaw,
                v: r.v,
                footprint: r.footprint(),
            })
            .collect()
    }

    /// State of charge (0..1) of robot `i` (spawn order).
    pub fn soc(&self, i: usize) -> Option<f64> {
        self.robots.get(i).map(|r| r.soc)
    }
}

#[cfg(test)]
#[path = "world_tests.rs"]
mod tests;
