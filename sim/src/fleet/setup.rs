//! Setting the fleets up: robots and workcells placed on the map, the graphs, conflict
//! sets and parking spots built once.

use super::*;
use crate::traffic::parks::PARK;

impl Fleets {
    /// Resolves spawns and workcells (named waypoints must exist on the fleet's graph).
    pub fn place(building: &Building, scenario: &Scenario) -> Result<Placement, Vec<Diagnostic>> {
        let graphs: Vec<i64> = scenario.fleets.iter().map(|f| f.graph).collect();
        let nav = Nav::build(building, &graphs);
        let conf = conflicts(&nav, scenario);
        let mut diags = Vec::new();
        let mut robots: Vec<RobotSpawn> = Vec::new();
        let mut reserve: Vec<(String, usize)> = Vec::new();
        // (vertex, footprint) of robots placed so far.
        let mut taken: Vec<(usize, f64)> = Vec::new();
        // Named spawns first, then auto spawn around them; robots are listed in fleet order.
        let mut explicit: Vec<Option<Vec<Spawn>>> = vec![None; scenario.fleets.len()];
        let mut auto = Vec::new();
        for (fi, f) in scenario.fleets.iter().enumerate() {
            let Some(slot) = nav.slot(f.graph).filter(|&s| !nav.members[s].is_empty()) else {
                diags.push(
                    Diagnostic::error(
                        codes::EMPTY_GRAPH,
                        f.span,
                        format!(
                            "fleet `{}` drives on graph {}, which has no lanes",
                            f.name, f.graph
                        ),
                    )
                    .with_help(format!(
                        "graphs with lanes in this map: {:?}",
                        building.graph_indices()
                    )),
                );
                continue;
            };
            let mut chosen: Vec<(usize, Option<String>)> = Vec::new();
            match &f.spawn {
                SpawnSpec::MapSpawnPoints => {
                    let spawns: Vec<usize> = nav.members[slot]
                        .iter()
                        .copied()
                        .filter(|&v| nav.vertices[v].roles.spawn_robot_type.is_some())
                        .collect();
                    let matching: Vec<usize> = spawns
                        .iter()
                        .copied()
                        .filter(|&v| {
                            nav.vertices[v]
                                .roles
                                .spawn_robot_type
                                .as_deref()
                                .is_some_and(|t| {
                                    t.rsplit('/')
                                        .next()
                                        .unwrap_or(t)
                                        .eq_ignore_ascii_case(&f.robot.model)
                                })
                        })
                        .collect();
                    let pool = if matching.is_empty() {
                        spawns
                    } else {
                        matching
                    };
                    for v in pool {
                        if chosen.len() == f.count {
                            break;
                        }
                        if taken.iter().any(|&(w, _)| w == v) {
                            continue;
                        }
                        chosen.push((v, nav.vertices[v].roles.spawn_robot_name.clone()));
                    }
                }
                SpawnSpec::Waypoints(names) => {
                    for (k, name) in names.iter().take(f.count).enumerate() {
                        // A fleet config's robots: located at their waypoint in the config.
                        let span = f
                            .rmf
                            .as_ref()
                            .and_then(|r| r.robots.get(k))
                            .map_or(f.span, |r| r.span);
                        match nav.find(slot, name) {
                            Some(v)
                                if taken.iter().any(|&(w, _)| w == v)
                                    || chosen.iter().any(|c| c.0 == v) =>
                            {
                                diags.push(
                                    Diagnostic::error(
                                        codes::SPAWN_CLASH,
                                        f.span,
                                        format!("two robots would start on waypoint `{name}`"),
                                    )
                                    .with_help("name a different waypoint for each robot"),
                                );
                            }
                            Some(v) => chosen.push((v, None)),
                            None => diags.push(unknown_waypoint(&nav, slot, name, span, &f.name)),
                        }
                    }
                }
                SpawnSpec::Auto => {
                    auto.push(spawn::AutoFleet {
                        fleet: fi,
                        slot,
                        count: f.count,
                    });
                    continue;
                }
            }
            for &(v, _) in &chosen {
                taken.push((v, f.robot.footprint));
            }
            explicit[fi] = Some(chosen);
        }
        // Parking vertices for every robot asked (and spares), around the named spawns.
        let mut per_slot = vec![0usize; nav.graphs.len()];
        for f in &scenario.fleets {
            if let Some(s) = nav.slot(f.graph) {
                per_slot[s] += f.count;
            }
        }
        let spawned: Vec<usize> = taken.iter().map(|&(v, _)| v).collect();
        let mut parks = choose_parks(&nav, &conf, scenario, &spawned, &per_slot);
        let reach = if auto.is_empty() {
            Vec::new()
        } else {
            spawn::reach(&nav, &park::task_places(&nav, scenario))
        };
        let mut auto_chosen = spawn::auto_spawn(&nav, &conf, &parks, &reach, &auto, &spawned);
        // A building that holds fewer robots than asked: parking and spawns are chosen again
        // for the robots on the floor, so that the run depends on them and not on how many
        // more were asked (asking 32 or 64 where 15 fit is the same run). Kept only when
        // every robot of the first choice still finds a place.
        if auto
            .iter()
            .zip(&auto_chosen)
            .any(|(a, c)| c.len() < a.count)
        {
            let placed: Vec<spawn::AutoFleet> = auto
                .iter()
                .zip(&auto_chosen)
                .map(|(a, c)| spawn::AutoFleet {
                    fleet: a.fleet,
                    slot: a.slot,
                    count: c.len(),
                })
                .collect();
            let mut on_floor = per_slot.clone();
            for (a, p) in auto.iter().zip(&placed) {
                on_floor[a.slot] -= a.count - p.count;
            }
            let parks2 = choose_parks(&nav, &conf, scenario, &spawned, &on_floor);
            let chosen2 = spawn::auto_spawn(&nav, &conf, &parks2, &reach, &placed, &spawned);
            if chosen2.iter().zip(&placed).all(|(c, p)| c.len() == p.count) {
                parks = parks2;
                auto_chosen = chosen2;
            }
        }
        for (a, vs) in auto.iter().zip(auto_chosen) {
            explicit[a.fleet] = Some(vs.into_iter().map(|v| (v, None)).collect());
        }
        let mut warnings = well_formed_warnings(&nav, &conf, scenario);
        let mut finishes = Vec::new();
        for (fi, f) in scenario.fleets.iter().enumerate() {
            let (Some(chosen), Some(slot)) = (explicit[fi].take(), nav.slot(f.graph)) else {
                continue;
            };
            if f.spawn == SpawnSpec::Auto && !chosen.is_empty() && chosen.len() < f.count {
                reserve.push((f.name.clone(), f.count - chosen.len()));
                warnings.push(
                    Diagnostic::warning(
                        codes::NO_ROOM,
                        f.span,
                        format!(
                            "fleet `{}`: {} robots asked, room for {}: {}",
                            f.name,
                            f.count,
                            chosen.len(),
                            if nav.members[slot].iter().any(|&v| parks.per_slot[slot][v] == PARK) {
                                "the building has no more waypoints where a standing robot blocks no route (one is kept free for robots making room)"
                            } else {
                                "robots can stand out of the way only on task places here, and park on at most half of them (on every one, no task could end)"
                            }
                        ),
                    )
                    .with_help("lower `count`, add parking spots off the corridors, or name spawn waypoints"),
                );
            } else if chosen.len() < f.count
                && !matches!(f.spawn, SpawnSpec::Waypoints(ref n) if n.len() >= f.count && chosen.len() + diags.len() >= f.count)
            {
                let what = match f.spawn {
                    SpawnSpec::MapSpawnPoints => "free spawn waypoints (`spawn_robot_type`)",
                    SpawnSpec::Waypoints(_) => "spawn waypoints listed",
                    SpawnSpec::Auto => "free waypoints far enough apart",
                };
                diags.push(
                    Diagnostic::error(
                        codes::NOT_ENOUGH_SPAWNS,
                        f.span,
                        format!(
                            "fleet `{}` has {} robots but only {} {what}",
                            f.name,
                            f.count,
                            chosen.len()
                        ),
                    )
                    .with_help(match f.spawn {
                        SpawnSpec::Auto => "lower `count` or add parking spots to the graph",
                        _ => "lower `count`, list more waypoints, or use `spawn: auto`",
                    }),
                );
            }
            for (i, (v, name)) in chosen.into_iter().enumerate() {
                let robot_name = f
                    .rmf
                    .as_ref()
                    .and_then(|r| r.robots.get(i))
                    .map(|r| r.name.clone())
                    .or_else(|| name.clone())
                    .unwrap_or_else(|| format!("{}_{i}", f.name));
                let (finish, warning) =
                    finish_of(&nav, &conf, &parks, scenario, (fi, i), &robot_name);
                finishes.push(finish);
                warnings.extend(warning);
                let nv = &nav.vertices[v];
                // A fleet config's robots are named as in the config.
                let own = f
                    .rmf
                    .as_ref()
                    .and_then(|r| r.robots.get(i))
                    .map(|r| r.name.clone());
                let name = own.or(name).unwrap_or_else(|| format!("{}_{i}", f.name));
                if robots.iter().any(|r| r.name == name) {
                    diags.push(Diagnostic::error(
                        codes::SPAWN_CLASH,
                        f.span,
                        format!("two robots are named `{name}`"),
                    ));
                }
                // Face along the first lane leaving the spawn point, as a parked robot would.
                let yaw = nav.out[slot][v].first().map_or(0.0, |&e| {
                    let d = nav.vertices[nav.edges[e].to].pos.minus(nv.pos);
                    d.y.atan2(d.x)
                });
                robots.push(RobotSpawn {
                    name,
                    fleet: f.name.clone(),
                    params: f.robot.clone(),
                    x: nv.pos.x,
                    y: nv.pos.y,
                    yaw,
                    level: nv.level,
                });
            }
        }
        let mut workcells = Vec::new();
        for w in &scenario.workcells {
            // The map's own dispensers and ingestors are workcells too, addressed by name:
            // two of one name both answer a request (a robot was handed two items, and the
            // one it did not deliver was never seen again).
            let in_map = building.models.iter().any(|(_, m)| {
                m.name == w.name
                    && (m.model_name.ends_with("TeleportDispenser")
                        || m.model_name.ends_with("TeleportIngestor"))
            });
            if in_map {
                diags.push(
                    Diagnostic::error(
                        codes::DUPLICATE_WORKCELL,
                        w.span,
                        format!(
                            "workcell `{}`: the map has a dispenser or ingestor of that name",
                            w.name
                        ),
                    )
                    .with_help("rename it, or leave it out and use the map's"),
                );
                continue;
            }
            match building
                .vertices
                .iter()
                .find(|(_, v)| v.name == w.waypoint && !w.waypoint.is_empty())
            {
                Some((_, v)) => workcells.push(WorkcellSpawn {
                    name: w.name.clone(),
                    kind: w.kind,
                    x: v.pos.x,
                    y: v.pos.y,
                    level: v.level,
                }),
                None => diags.push(
                    Diagnostic::error(
                        codes::UNKNOWN_WAYPOINT,
                        w.span,
                        format!("workcell `{}`: no waypoint named `{}`", w.name, w.waypoint),
                    )
                    .with_help("use the name of a vertex of the map"),
                ),
            }
        }
        if diags.iter().any(Diagnostic::is_error) {
            return Err(diags);
        }
        Ok(Placement {
            robots,
            workcells,
            reserve,
            warnings,
            parks,
            finishes,
        })
    }

    pub fn new(
        building: &Building,
        scenario: &Scenario,
        placement: &Placement,
    ) -> Result<Fleets, Vec<Diagnostic>> {
        let graphs: Vec<i64> = scenario.fleets.iter().map(|f| f.graph).collect();
        let nav = Nav::build(building, &graphs);
        let conf = conflicts(&nav, scenario);
        let mut diags = Vec::new();
        let mut fleets = Vec::new();
        let mut robots = Vec::new();
        let mut by_name = BTreeMap::new();
        for f in &scenario.fleets {
            let Some(slot) = nav.slot(f.graph) else {
                continue;
            };
            let mut rt = FleetRt {
                name: f.name.clone(),
                slot,
                speed: f.robot.nominal_drive_speed.max(0.05),
                accel: f.robot.nominal_drive_acceleration.max(0.01),
                max_accel: f
                    .robot
                    .max_drive_acceleration
                    .max(f.robot.nominal_drive_acceleration)
                    .max(0.01),
                kin: crate::traffic::sipp::Kinematics {
                    speed: f.robot.nominal_drive_speed.max(0.05),
                    accel: f.robot.nominal_drive_acceleration.max(0.01),
                    turn: f.robot.nominal_turn_speed.max(0.05),
                },
                recharge_threshold: f.recharge_threshold,
                recharge_soc: f.recharge_soc,
                charge_rate: 100.0 * f.robot.charging_current
                    / (f.robot.nominal_capacity * 3600.0).max(1e-9),
                kinds: f.task_kinds.clone(),
                robots: Vec::new(),
            };
            for (si, spawn) in placement
                .robots
                .iter()
                .enumerate()
                .filter(|(_, s)| s.fleet == f.name)
            {
                let at = nav.members[slot].iter().copied().find(|&v| {
                    let nv = &nav.vertices[v];
                    nv.level == spawn.level && (nv.pos.x - spawn.x).hypot(nv.pos.y - spawn.y) < 1e-6
                });
                let Some(at) = at else {
                    diags.push(Diagnostic::error(
                        codes::UNKNOWN_WAYPOINT,
                        f.span,
                        format!(
                            "robot `{}` does not start on a waypoint of graph {}",
                            spawn.name, f.graph
                        ),
                    ));
                    continue;
                };
                let i = robots.len();
                by_name.insert(spawn.name.clone(), i);
                rt.robots.push(i);
                robots.push(Robot {
                    name: spawn.name.clone(),
                    fleet: fleets.len(),
                    slot,
                    at,
                    state: None,
                    n_sent: 0,
                    leg: None,
                    legs: VecDeque::new(),
                    path_id: String::new(),
                    path_seq: 0,
                    gate: Gate::None,
                    close_door: None,
                    end_lift: None,
                    steps: VecDeque::new(),
                    cur: Cur::None,
                    task: None,
                    wake: f64::INFINITY,
                    dirty: true,
                    waiting: None,
                    replan_at: 0.0,
                    retreat: None,
                    free_since: 0.0,
                    stuck_reported: false,
                    last_pos: (spawn.x, spawn.y),
                    last_moved: 0.0,
                    charger: None,
                    carrying: None,
                    item_from: None,
                    task_started: 0.0,
                    reached_at: 0.0,
                    park_pending: false,
                    detour: 0,
                    finish: placement.finishes.get(si).copied().unwrap_or_default(),
                    waiting_for: None,
                    waits: TaskWaits::default(),
                });
            }
            fleets.push(rt);
        }

        // Tasks: validate against the fleets, then order by request time (stable).
        let mut upcoming = Vec::new();
        let check = |kind: &TaskKind,
                     fleet: &Option<String>,
                     span: Span,
                     diags: &mut Vec<Diagnostic>| {
            let cat = kind.category();
            let cands: Vec<&FleetRt> = fleets
                .iter()
                .filter(|f| fleet.as_ref().is_none_or(|n| *n == f.name))
                .filter(|f| f.kinds.is_empty() || f.kinds.contains(&cat))
                .collect();
            if cands.is_empty() {
                diags.push(
                    Diagnostic::error(
                        codes::NO_FLEET,
                        span,
                        format!(
                            "no fleet{} accepts {} tasks",
                            fleet
                                .as_ref()
                                .map(|n| format!(" named `{n}`"))
                                .unwrap_or_default(),
                            cat.as_str()
                        ),
                    )
                    .with_help("add the category to a fleet's task kinds, or name another fleet"),
                );
                return;
            }
            for name in kind.places() {
                let found: Vec<usize> = cands
                    .iter()
                    .filter_map(|f| nav.find(f.slot, name))
                    .collect();
                if found.is_empty() {
                    diags.push(unknown_waypoint(
                        &nav,
                        cands[0].slot,
                        name,
                        span,
                        &cands[0].name,
                    ));
                } else if found.iter().any(|&v| nav.vertices[v].lift.is_some()) {
                    // A robot parked in a cabin would keep the lift's session forever.
                    diags.push(
                        Diagnostic::error(
                            codes::IN_LIFT,
                            span,
                            format!("waypoint `{name}` is inside a lift cabin"),
                        )
                        .with_help("use a waypoint in front of the lift"),
                    );
                }
            }
            if let TaskKind::Delivery {
                pickup,
                dropoff,
                dispenser,
                ingestor,
            } = kind
            {
                let role = |name: &str, f: &dyn Fn(&mapc_ir::WaypointRoles) -> Option<String>| {
                    cands
                        .iter()
                        .find_map(|c| nav.find(c.slot, name))
                        .and_then(|v| f(&nav.vertices[v].roles))
                };
                if dispenser.is_none() && role(pickup, &|r| r.pickup_dispenser.clone()).is_none() {
                    diags.push(
                        Diagnostic::error(
                            codes::NO_WORKCELL,
                            span,
                            format!("delivery from `{pickup}`: no dispenser named and the waypoint has no `pickup_dispenser`"),
                        )
                        .with_help("add `dispenser: <name>` to the task"),
                    );
                }
                if ingestor.is_none() && role(dropoff, &|r| r.dropoff_ingestor.clone()).is_none() {
                    diags.push(
                        Diagnostic::error(
                            codes::NO_WORKCELL,
                            span,
                            format!("delivery to `{dropoff}`: no ingestor named and the waypoint has no `dropoff_ingestor`"),
                        )
                        .with_help("add `ingestor: <name>` to the task"),
                    );
                }
            }
        };
        for (i, t) in scenario.tasks.iter().enumerate() {
            check(&t.kind, &t.fleet, t.span, &mut diags);
            upcoming.push((
                t.at,
                i,
                NewTask {
                    kind: t.kind.clone(),
                    fleet: t.fleet.clone(),
                    robot: t.robot.clone(),
                    priority: t.priority,
                },
            ));
        }
        let base = scenario.tasks.len();
        for (g, gen) in scenario.generators.iter().enumerate() {
            check(&gen.kind, &gen.fleet, gen.span, &mut diags);
            for at in gen.times(scenario.duration) {
                upcoming.push((
                    at,
                    base + g,
                    NewTask {
                        kind: gen.kind.clone(),
                        fleet: gen.fleet.clone(),
                        robot: None,
                        priority: 0,
                    },
                ));
            }
        }
        if diags.iter().any(Diagnostic::is_error) {
            return Err(diags);
        }
        upcoming.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // A robot that does not start on a parking vertex drives to one first.
        let parks = placement.parks.clone();
        for r in robots.iter_mut() {
            // (A config's robot starting on its charger waits there for its first task
            // when the charger is in nobody's way: it is then a parking vertex of its own.)
            r.park_pending = match r.finish {
                Finish::Home(h) => r.at != h && parks.per_slot[r.slot][r.at] == 0,
                _ => parks.per_slot[r.slot][r.at] == 0,
            };
        }
        let starts: Vec<usize> = robots.iter().map(|r| r.at).collect();
        let ways_out = crate::traffic::parks::out_of_the_way(&nav, &parks);
        let traffic = traffic::Traffic::new(&nav, conf, &starts, parks);
        let floor = Floor {
            devices: devices::Devices::new(&nav),
            nav,
            traffic,
            fleets,
            robots,
            by_name,
            tasks: Vec::new(),
            clean_duration: scenario.options.clean_duration,
            lane_use: drive::LaneUse::new(crate::report::timeline::period_for(scenario.duration)),
            just_free: Vec::new(),
            ways_out,
            freed_at: f64::INFINITY,
        };
        Ok(Fleets {
            floor,
            dispatcher: assign::Dispatcher::new(upcoming),
            cancels: cancel::Cancels::new(scenario),
            next_wake: 0.0,
            next_fleet_state: 0.0,
            next_traffic: f64::INFINITY,
        })
    }
}

/// A robot's start: the vertex, and the name the map gives it (spawn points).
type Spawn = (usize, Option<String>);

/// Conflict sets of every graph with the clearances of the fleets that drive on it.
fn conflicts(nav: &Nav, scenario: &Scenario) -> Conflicts {
    let zero = Clearance {
        footprint: 0.0,
        vicinity: 0.0,
        stop_distance: 0.0,
        stop_radius: 0.0,
    };
    let mut per_slot = vec![zero; nav.graphs.len()];
    let mut footprint: f64 = 0.0;
    for f in &scenario.fleets {
        footprint = footprint.max(f.robot.footprint);
        if let Some(c) = nav.slot(f.graph).and_then(|s| per_slot.get_mut(s)) {
            c.footprint = c.footprint.max(f.robot.footprint);
            if let Some(r) = &f.rmf {
                c.vicinity = c.vicinity.max(r.vicinity);
            }
            c.stop_distance = c.stop_distance.max(f.robot.stop_distance);
            c.stop_radius = c.stop_radius.max(f.robot.stop_radius);
        }
    }
    Conflicts::build_per_slot(nav, footprint, &per_slot)
}

fn unknown_waypoint(nav: &Nav, slot: usize, name: &str, span: Span, fleet: &str) -> Diagnostic {
    let mut names: Vec<&str> = nav.members[slot]
        .iter()
        .map(|&v| nav.vertices[v].name.as_str())
        .filter(|n| !n.is_empty())
        .collect();
    names.sort_unstable();
    names.dedup();
    // The nearest name first (a typo is the usual cause), then what else there is, saying
    // how many names the list leaves out.
    const LISTED: usize = 12;
    let nearest = mapc_frontend::spelling::nearest(name, names.iter().copied());
    let others: Vec<&str> = names
        .iter()
        .copied()
        .filter(|n| Some(*n) != nearest)
        .collect();
    let left_out = others.len().saturating_sub(LISTED);
    let mut help = match nearest {
        Some(n) => format!("nearest: `{n}`"),
        None => "this graph has no named waypoints".to_string(),
    };
    if !others.is_empty() {
        help.push_str(&format!(
            "; others: {}",
            others[..others.len().min(LISTED)].join(", ")
        ));
        if left_out > 0 {
            help.push_str(&format!(" and {left_out} more"));
        }
    }
    Diagnostic::error(
        codes::UNKNOWN_WAYPOINT,
        span,
        format!("no waypoint named `{name}` on the graph of fleet `{fleet}`"),
    )
    .with_help(help)
}
