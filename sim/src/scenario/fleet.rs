//! Fleets: a fleet's keys or its RMF fleet config, the robot's parameters and presets,
//! spawn, the task categories it takes, and workcells.

use super::*;

/// Robot parameters a `robot:` mapping may set, and whether they must be > 0 (else ≥ 0).
pub(super) const ROBOT_NUMBERS: &[(&str, bool)] = &[
    ("nominal_drive_speed", true),
    ("nominal_drive_acceleration", true),
    ("max_drive_acceleration", true),
    ("nominal_turn_speed", true),
    ("nominal_turn_acceleration", true),
    ("max_turn_acceleration", true),
    ("stop_distance", false),
    ("stop_radius", false),
    ("nominal_voltage", true),
    ("nominal_capacity", true),
    ("charging_current", false),
    ("mass", true),
    ("inertia", true),
    ("friction_coefficient", false),
    ("nominal_power", false),
    ("footprint", true),
];

fn robot_number<'p>(p: &'p mut RobotParams, key: &str) -> Option<&'p mut f64> {
    Some(match key {
        "nominal_drive_speed" => &mut p.nominal_drive_speed,
        "nominal_drive_acceleration" => &mut p.nominal_drive_acceleration,
        "max_drive_acceleration" => &mut p.max_drive_acceleration,
        "nominal_turn_speed" => &mut p.nominal_turn_speed,
        "nominal_turn_acceleration" => &mut p.nominal_turn_acceleration,
        "max_turn_acceleration" => &mut p.max_turn_acceleration,
        "stop_distance" => &mut p.stop_distance,
        "stop_radius" => &mut p.stop_radius,
        "nominal_voltage" => &mut p.nominal_voltage,
        "nominal_capacity" => &mut p.nominal_capacity,
        "charging_current" => &mut p.charging_current,
        "mass" => &mut p.mass,
        "inertia" => &mut p.inertia,
        "friction_coefficient" => &mut p.friction_coefficient,
        "nominal_power" => &mut p.nominal_power,
        "footprint" => &mut p.footprint,
        _ => return None,
    })
}

impl P<'_> {
    pub(super) fn fleets(&mut self, v: &Node) -> Option<Vec<FleetSpec>> {
        let fleets = self.seq(v, "`fleets`", |p, n| p.fleet(n))?;
        if fleets.is_empty() {
            self.error(
                codes::MISSING_KEY,
                v.span,
                "`fleets` is empty; a scenario needs at least one fleet",
            );
            return None;
        }
        let total: usize = fleets.iter().map(|f| f.count).sum();
        if total as i64 > MAX_ROBOTS {
            self.error(
                codes::TOO_LARGE,
                v.span,
                format!("the fleets have {total} robots in all, more than {MAX_ROBOTS}"),
            );
            return None;
        }
        let mut ok = true;
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        for f in &fleets {
            if let Some(&first_span) = seen.get(f.name.as_str()) {
                self.error(
                    codes::DUPLICATE_FLEET,
                    f.span,
                    format!("a fleet named `{}` is already defined", f.name),
                )
                .labels
                .push(mapc_ir::Label {
                    span: first_span,
                    message: "first defined here".into(),
                });
                self.help("give every fleet its own name");
                ok = false;
            }
            seen.entry(&f.name).or_insert(f.span);
        }
        ok.then_some(fleets)
    }

    /// The fleet described by an RMF fleet adapter config (`config:`).
    pub(super) fn config_fleet(&mut self, v: &Node) -> Option<rmf_config::ConfigFleet> {
        let k = self.include(v, "`config`")?;
        let id = self.included_id(k);
        let text = self.included[k].text.clone();
        let path = self.included[k].path.clone();
        let root = match yaml_tree::parse(&text, id) {
            Ok(r) => r,
            Err(mut d) => {
                d.code = codes::INVALID_YAML.code;
                if !d.span.is_known() {
                    d.span = v.span;
                }
                self.push(d);
                return None;
            }
        };
        if root.is_null() {
            self.error(
                codes::RMF_CONFIG_NO_FLEET,
                v.span,
                "the fleet config is empty",
            );
            return None;
        }
        self.rmf_config(&root, path)
    }

    pub(super) fn recharge_threshold(&mut self, t: &Node) -> Option<f64> {
        self.number(t, "`recharge_threshold`").and_then(|x| {
            if (0.0..1.0).contains(&x) {
                Some(x)
            } else {
                self.error(
                    codes::OUT_OF_RANGE,
                    t.span,
                    format!("`recharge_threshold` is {x}; it must be in [0, 1)"),
                );
                self.help("it is a fraction of the battery: 0.2 means 20 %");
                None
            }
        })
    }

    pub(super) fn recharge_soc(&mut self, t: &Node) -> Option<f64> {
        self.number(t, "`recharge_soc`").and_then(|x| {
            if x > 0.0 && x <= 1.0 {
                Some(x)
            } else {
                self.error(
                    codes::OUT_OF_RANGE,
                    t.span,
                    format!("`recharge_soc` is {x}; it must be in (0, 1]"),
                );
                self.help("it is a fraction of the battery: 1.0 means full");
                None
            }
        })
    }

    pub(super) fn fleet(&mut self, v: &Node) -> Option<FleetSpec> {
        let e = self.entries(v, "a fleet", Some((FLEET_KEYS, codes::UNKNOWN_KEY)))?;
        // From an RMF fleet adapter config; the scenario's own keys override it.
        let cfg = match e.get("config") {
            Some(c) => Some(self.config_fleet(c)?),
            None => None,
        };
        let name = match (e.get("name"), &cfg) {
            (None, Some(c)) => Some(c.name.clone()),
            _ => self
                .required(&e, "name", "a fleet")
                .and_then(|n| self.name(n, "a fleet's `name`")),
        };
        let graph = match e.get("graph") {
            None => Some(0),
            Some(g) => self.int(g, "`graph`").and_then(|i| {
                if i < 0 {
                    self.error(codes::OUT_OF_RANGE, g.span, "`graph` must be 0 or more");
                    None
                } else {
                    Some(i)
                }
            }),
        };
        let robot = match (e.get("robot"), &cfg) {
            (None, Some(c)) => Some(c.robot.clone()),
            (r, c) => r
                .or_else(|| self.required(&e, "robot", "a fleet"))
                .and_then(|r| self.robot(r, c.as_ref().map(|c| c.robot.clone()))),
        };
        let count = match e.get("count") {
            Some(c) => self.int(c, "`count`").and_then(|i| {
                if i <= 0 {
                    self.error(
                        codes::NOT_POSITIVE,
                        c.span,
                        "`count` must be greater than 0",
                    );
                    self.help("a fleet needs at least one robot; remove the fleet instead");
                    None
                } else if i > MAX_ROBOTS {
                    self.error(
                        codes::TOO_LARGE,
                        c.span,
                        format!("`count` must be at most {MAX_ROBOTS}"),
                    );
                    None
                } else {
                    Some(i as usize)
                }
            }),
            None => None,
        };
        let spawn = match (e.get("spawn"), &cfg) {
            (Some(s), _) => self.spawn(s),
            // The config's robots at their start waypoints; more robots than it lists
            // (a `count` override) are placed automatically.
            (None, Some(c)) => Some(match count {
                Some(n) if n > c.rmf.robots.len() => SpawnSpec::Auto,
                n => SpawnSpec::Waypoints(
                    c.rmf
                        .robots
                        .iter()
                        .take(n.unwrap_or(usize::MAX))
                        .map(|r| r.start.clone())
                        .collect(),
                ),
            }),
            (None, None) => Some(SpawnSpec::Auto),
        };
        let count = match (count, e.get("count")) {
            (Some(n), _) => Some(n),
            (None, Some(_)) => None,
            (None, None) => match &spawn {
                Some(SpawnSpec::Waypoints(w)) => Some(w.len()),
                Some(_) => {
                    self.error(codes::MISSING_KEY, e.span, "a fleet has no `count`");
                    self.help("set `count`, or list one spawn waypoint per robot under `spawn`");
                    None
                }
                None => None,
            },
        };
        if let (Some(SpawnSpec::Waypoints(w)), Some(n), Some(s)) = (&spawn, count, e.get("spawn")) {
            if w.len() != n {
                self.error(
                    codes::SPAWN_COUNT,
                    s.span,
                    format!("`spawn` names {} waypoint(s) for {n} robot(s)", w.len()),
                );
                self.help("list one waypoint per robot, leave `count` out, or use `spawn: auto`");
            }
        }
        let threshold = match (e.get("recharge_threshold"), &cfg) {
            (None, Some(c)) => Some(c.recharge_threshold),
            (None, None) => Some(0.2),
            (Some(t), _) => self.recharge_threshold(t),
        };
        let soc = match (e.get("recharge_soc"), &cfg) {
            (None, Some(c)) => Some(c.recharge_soc),
            (None, None) => Some(1.0),
            (Some(t), _) => self.recharge_soc(t),
        };
        // A config's own pair is made consistent where it is read (`rmf_config`).
        let own_pair = e.get("recharge_soc").is_some() || e.get("recharge_threshold").is_some();
        if let (Some(t), Some(s), true) = (threshold, soc, own_pair || cfg.is_none()) {
            if t >= s {
                let span = e
                    .get("recharge_soc")
                    .or(e.get("recharge_threshold"))
                    .map_or(e.span, |n| n.span);
                self.error(
                    codes::OUT_OF_RANGE,
                    span,
                    format!("`recharge_soc` ({s}) must be above `recharge_threshold` ({t})"),
                );
                self.help("a robot leaves the charger at recharge_soc and goes back below recharge_threshold");
            }
        }
        let kinds = match (e.get("tasks"), &cfg) {
            (None, Some(c)) => Some(c.task_kinds.clone()),
            (None, None) => Some(Vec::new()),
            (Some(t), _) => self.categories(t),
        };
        Some(FleetSpec {
            name: name?,
            graph: graph?,
            robot: robot?,
            count: count?,
            spawn: spawn?,
            recharge_threshold: threshold?,
            recharge_soc: soc?,
            task_kinds: kinds?,
            span: v.span,
            rmf: cfg.map(|c| Box::new(c.rmf)),
        })
    }

    /// A preset name, or a mapping of parameters over a preset or over `base` (a fleet
    /// config's robot).
    pub(super) fn robot(&mut self, v: &Node, base: Option<RobotParams>) -> Option<RobotParams> {
        if v.as_map().is_none() {
            let name = self.name(v, "`robot`")?;
            return self.preset(v, &name);
        }
        let mut known: Vec<&str> = vec!["preset", "model", "reversible"];
        known.extend(ROBOT_NUMBERS.iter().map(|r| r.0));
        let e = self.entries(v, "`robot`", Some((&known, codes::UNKNOWN_KEY)))?;
        let mut p = match e.get("preset") {
            Some(n) => {
                let name = self.name(n, "`preset`")?;
                self.preset(n, &name)?
            }
            None => base.unwrap_or_default(),
        };
        let mut ok = true;
        if let Some(m) = e.get("model") {
            match self.name(m, "`model`") {
                Some(n) => p.model = n,
                None => ok = false,
            }
        }
        if let Some(r) = e.get("reversible") {
            match self.bool(r, "`reversible`") {
                Some(b) => p.reversible = b,
                None => ok = false,
            }
        }
        // Document order, so that diagnostics come out in reading order.
        for &(key, _, n) in &e.items {
            let Some(&(_, strictly)) = ROBOT_NUMBERS.iter().find(|r| r.0 == key) else {
                continue;
            };
            let what = format!("`{key}`");
            let Some(x) = self.number(n, &what) else {
                ok = false;
                continue;
            };
            if strictly && x <= 0.0 {
                self.error(
                    codes::NOT_POSITIVE,
                    n.span,
                    format!("{what} must be greater than 0"),
                );
                ok = false;
            } else if x < 0.0 {
                self.error(
                    codes::OUT_OF_RANGE,
                    n.span,
                    format!("{what} must be 0 or more"),
                );
                ok = false;
            } else if let Some(slot) = robot_number(&mut p, key) {
                *slot = x;
            }
        }
        ok.then_some(p)
    }

    pub(super) fn preset(&mut self, v: &Node, name: &str) -> Option<RobotParams> {
        let p = RobotParams::preset(name);
        if p.is_none() {
            let names: Vec<&str> = RobotParams::preset_names().collect();
            self.error(
                codes::UNKNOWN_PRESET,
                v.span,
                format!("unknown robot preset `{name}`"),
            );
            let hint = closest(name, names.iter().copied())
                .map(|c| format!("did you mean `{c}`? "))
                .unwrap_or_default();
            self.help(format!(
                "{hint}presets: {}; or describe the robot as a mapping of parameters",
                list(&names)
            ));
        }
        p
    }

    pub(super) fn spawn(&mut self, v: &Node) -> Option<SpawnSpec> {
        if let Some(items) = v.as_seq() {
            let mut names: Vec<String> = Vec::with_capacity(items.len());
            let mut seen: BTreeSet<String> = BTreeSet::new();
            let mut ok = true;
            for n in items {
                match self.name(n, "a spawn waypoint") {
                    Some(s) if seen.contains(&s) => {
                        self.error(
                            codes::SPAWN_COUNT,
                            n.span,
                            format!("waypoint `{s}` is listed twice; two robots would start on it"),
                        );
                        ok = false;
                    }
                    Some(s) => {
                        seen.insert(s.clone());
                        names.push(s);
                    }
                    None => ok = false,
                }
            }
            return ok.then_some(SpawnSpec::Waypoints(names));
        }
        match v.scalar() {
            Some(Scalar::Str("spawn_points")) => Some(SpawnSpec::MapSpawnPoints),
            Some(Scalar::Str("auto")) => Some(SpawnSpec::Auto),
            _ => {
                self.error(
                    codes::WRONG_TYPE,
                    v.span,
                    format!(
                        "`spawn` must be `spawn_points`, `auto` or a list of waypoint names, found {}",
                        v.type_name()
                    ),
                );
                None
            }
        }
    }

    pub(super) fn categories(&mut self, v: &Node) -> Option<Vec<TaskCategory>> {
        let mut out: Vec<TaskCategory> = self.seq(v, "a fleet's `tasks`", |p, n| {
            let s = p.name(n, "a task category")?;
            let c = category(&s);
            if c.is_none() {
                p.error(
                    codes::UNKNOWN_TASK_KIND,
                    n.span,
                    format!("unknown task category `{s}`"),
                );
                p.help(format!("categories: {}", list(KINDS)));
            }
            c
        })?;
        if out.is_empty() {
            self.wrong_type(
                v,
                "a fleet's `tasks`",
                "a non-empty list (leave it out to accept every category)",
            );
            return None;
        }
        out.sort();
        out.dedup();
        Some(out)
    }

    pub(super) fn workcells(&mut self, v: &Node) -> Option<Vec<WorkcellSpec>> {
        let cells = self.seq(v, "`workcells`", |p, n| {
            let e = p.entries(n, "a workcell", Some((WORKCELL_KEYS, codes::UNKNOWN_KEY)))?;
            let name = p
                .required(&e, "name", "a workcell")
                .and_then(|x| p.name(x, "a workcell's `name`"));
            let kind = p
                .required(&e, "kind", "a workcell")
                .and_then(|k| match k.scalar() {
                    Some(Scalar::Str("dispenser")) => Some(WorkcellKind::Dispenser),
                    Some(Scalar::Str("ingestor")) => Some(WorkcellKind::Ingestor),
                    _ => {
                        p.wrong_type(k, "a workcell's `kind`", "`dispenser` or `ingestor`");
                        None
                    }
                });
            let waypoint = p
                .required(&e, "waypoint", "a workcell")
                .and_then(|x| p.name(x, "a workcell's `waypoint`"));
            Some(WorkcellSpec {
                name: name?,
                kind: kind?,
                waypoint: waypoint?,
                span: n.span,
            })
        })?;
        let mut ok = true;
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        for c in &cells {
            if let Some(&first_span) = seen.get(c.name.as_str()) {
                self.error(
                    codes::DUPLICATE_WORKCELL,
                    c.span,
                    format!("a workcell named `{}` is already defined", c.name),
                )
                .labels
                .push(mapc_ir::Label {
                    span: first_span,
                    message: "first defined here".into(),
                });
                ok = false;
            }
            seen.entry(&c.name).or_insert(c.span);
        }
        ok.then_some(cells)
    }
}
