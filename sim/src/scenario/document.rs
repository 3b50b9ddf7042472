//! The scenario document: its top-level keys, `options` and `crowd`, and the checks
//! across its parts (tasks against the fleets that may do them, how many tasks it asks).

use super::*;

impl P<'_> {
    pub(super) fn scenario(&mut self, root: &Node, base: &Path) -> Option<Scenario> {
        let top = self.entries(root, "the scenario", Some((TOP_KEYS, codes::UNKNOWN_KEY)))?;
        let mut ok = true;

        let map = match top.get("map") {
            None => None,
            Some(v) => match self.name(v, "`map`") {
                Some(m) => Some(base.join(m)),
                None => {
                    ok = false;
                    None
                }
            },
        };
        if let Some(v) = top.get("description") {
            if v.key_text().is_none() && !v.is_null() {
                self.wrong_type(v, "`description`", "a string");
            }
        }
        let seed = match top.get("seed") {
            None => Some(0),
            Some(v) => match self.int(v, "`seed`") {
                Some(i) if i >= 0 => Some(i as u64),
                Some(_) => {
                    self.error(codes::OUT_OF_RANGE, v.span, "`seed` must be 0 or more");
                    None
                }
                None => None,
            },
        };
        let duration = self
            .required(&top, "duration", "the scenario")
            .and_then(|v| {
                let d = self.duration(v, "`duration`")?;
                let d = self.positive(v, d, "`duration`")?;
                if d > MAX_DURATION {
                    self.error(
                        codes::TOO_LARGE,
                        v.span,
                        format!("`duration` of {d} s is longer than one year ({MAX_DURATION} s)"),
                    );
                    self.help("check the unit; split very long studies into several runs");
                    return None;
                }
                Some(d)
            });
        let step = match top.get("step") {
            None => Some(0.01),
            Some(v) => self.duration(v, "`step`").and_then(|s| {
                let s = self.positive(v, s, "`step`")?;
                if s > MAX_STEP {
                    self.error(
                        codes::STEP_TOO_LARGE,
                        v.span,
                        format!("`step` of {s} s is larger than {MAX_STEP} s"),
                    );
                    self.help(
                        "the plugins run at 100 Hz; leave `step` out (0.01 s) or use at most 0.1 s",
                    );
                    return None;
                }
                Some(s)
            }),
        };

        let fleets = match self.required(&top, "fleets", "the scenario") {
            Some(v) => self.fleets(v),
            None => None,
        };
        let workcells = match top.get("workcells") {
            Some(v) if !v.is_null() => self.workcells(v),
            _ => Some(Vec::new()),
        };
        let tasks = match top.get("tasks") {
            Some(v) if !v.is_null() => self.seq(v, "`tasks`", |p, n| p.task(n, duration)),
            _ => Some(Vec::new()),
        };
        let generators = match top.get("generators") {
            Some(v) if !v.is_null() => self.seq(v, "`generators`", |p, n| p.generator(n, duration)),
            _ => Some(Vec::new()),
        };
        let faults = match top.get("faults") {
            Some(v) if !v.is_null() => self.seq(v, "`faults`", |p, n| p.fault(n, duration)),
            _ => Some(Vec::new()),
        };
        let mut options = match top.get("options") {
            Some(v) if !v.is_null() => self.options(v),
            _ => Some(SimOptions::default()),
        };
        if let Some(v) = top.get("crowd").filter(|v| !v.is_null()) {
            match (self.crowd(v), options.as_mut()) {
                (Some(c), Some(o)) => o.crowd = c,
                (None, _) => ok = false,
                _ => {}
            }
        }

        let requests = match top.get("requests") {
            Some(v) if !v.is_null() => self.requests_file(Some(v), duration),
            _ if self.requests.is_some() => self.requests_file(None, duration),
            _ => Some(Vec::new()),
        };
        if let (Some(fleets), Some(tasks), Some(gens)) = (&fleets, &tasks, &generators) {
            self.cross_check(fleets, tasks, gens);
            ok &= self.count_tasks(tasks, gens, duration);
        }

        if self.had_error || self.suppressed > 0 || !ok {
            return None;
        }
        Some(Scenario {
            map,
            seed: seed?,
            duration: duration?,
            step: step?,
            fleets: fleets?,
            workcells: workcells?,
            tasks: tasks?,
            generators: generators?,
            faults: faults?,
            options: options?,
            requests: requests?,
            cancels: Vec::new(),
        })
    }

    pub(super) fn options(&mut self, v: &Node) -> Option<SimOptions> {
        let e = self.entries(v, "`options`", Some((OPTION_KEYS, codes::UNKNOWN_OPTION)))?;
        let mut o = SimOptions::default();
        let mut ok = true;
        if let Some(n) = e.get("lifts_start_at_initial_floor") {
            match self.bool(n, "`lifts_start_at_initial_floor`") {
                Some(b) => o.lifts_start_at_initial_floor = b,
                None => ok = false,
            }
        }
        for (key, field) in [
            ("stop_when_done", &mut o.stop_when_done),
            ("charging", &mut o.charging),
            ("instant_charging", &mut o.instant_charging),
            ("battery_drain", &mut o.battery_drain),
        ] {
            if let Some(n) = e.get(key) {
                match self.bool(n, &format!("`{key}`")) {
                    Some(b) => *field = b,
                    None => ok = false,
                }
            }
        }
        if let Some(n) = e.get("clean_duration") {
            match self
                .duration(n, "`clean_duration`")
                .and_then(|x| self.positive(n, x, "`clean_duration`"))
            {
                Some(x) => o.clean_duration = x,
                None => ok = false,
            }
        }
        ok.then_some(o)
    }

    pub(super) fn crowd(&mut self, v: &Node) -> Option<CrowdOptions> {
        let e = self.entries(v, "`crowd`", Some((CROWD_KEYS, codes::UNKNOWN_KEY)))?;
        let mut c = CrowdOptions::default();
        let mut ok = true;
        if let Some(n) = e.get("enabled") {
            match self.bool(n, "`crowd.enabled`") {
                Some(b) => c.enabled = b,
                None => ok = false,
            }
        }
        if let Some(n) = e.get("scale") {
            match self.number(n, "`crowd.scale`") {
                Some(x) if (0.0..=MAX_CROWD_SCALE).contains(&x) => c.scale = x,
                Some(x) => {
                    self.error(
                        codes::OUT_OF_RANGE,
                        n.span,
                        format!("`crowd.scale` of {x} is not between 0 and {MAX_CROWD_SCALE}"),
                    );
                    ok = false;
                }
                None => ok = false,
            }
        }
        ok.then_some(c)
    }

    /// Fleets named by tasks exist and accept the task's category. Lookups are by map, so
    /// that a million tasks against ten thousand fleets stay fast.
    pub(super) fn cross_check(
        &mut self,
        fleets: &[FleetSpec],
        tasks: &[TaskSpec],
        gens: &[GeneratorSpec],
    ) {
        let accepts =
            |f: &FleetSpec, c: TaskCategory| f.task_kinds.is_empty() || f.task_kinds.contains(&c);
        let by_name: BTreeMap<&str, &FleetSpec> =
            fleets.iter().map(|f| (f.name.as_str(), f)).collect();
        let all = [
            TaskCategory::Loop,
            TaskCategory::Delivery,
            TaskCategory::Clean,
            TaskCategory::GoToPlace,
        ];
        let accepted: BTreeSet<TaskCategory> = all
            .into_iter()
            .filter(|&c| fleets.iter().any(|f| accepts(f, c)))
            .collect();
        let names: Vec<&str> = fleets.iter().map(|f| f.name.as_str()).collect();
        let items = tasks
            .iter()
            .map(|t| (&t.fleet, t.kind.category(), t.span))
            .chain(gens.iter().map(|g| (&g.fleet, g.kind.category(), g.span)));
        for (fleet, cat, span) in items {
            let cat_name = cat.as_str();
            match fleet.as_deref().map(|n| (n, by_name.get(n))) {
                Some((name, None)) => {
                    self.error(
                        codes::UNKNOWN_FLEET,
                        span,
                        format!("no fleet is named `{name}`"),
                    );
                    // The hint costs an edit distance per fleet: only while reporting.
                    if !self.full() {
                        let hint = closest(name, names.iter().copied())
                            .map(|c| format!("did you mean `{c}`? "))
                            .unwrap_or_default();
                        let shown: Vec<&str> = names.iter().copied().take(20).collect();
                        let more = if names.len() > shown.len() {
                            ", ..."
                        } else {
                            ""
                        };
                        self.help(format!("{hint}fleets: {}{more}", list(&shown)));
                    }
                }
                Some((name, Some(f))) if !accepts(f, cat) => {
                    let fspan = f.span;
                    self.error(
                        codes::NO_FLEET_FOR_TASK,
                        span,
                        format!("fleet `{name}` does not accept {cat_name} tasks"),
                    )
                    .labels
                    .push(mapc_ir::Label {
                        span: fspan,
                        message: "the fleet".into(),
                    });
                    self.help(format!(
                        "add `{cat_name}` to the fleet's `tasks`, or send the task to another fleet"
                    ));
                }
                None if !accepted.contains(&cat) => {
                    self.error(
                        codes::NO_FLEET_FOR_TASK,
                        span,
                        format!("no fleet accepts {cat_name} tasks"),
                    );
                    self.help(format!("add `{cat_name}` to a fleet's `tasks`"));
                }
                _ => {}
            }
        }
    }

    /// Bounds the number of task requests, generators included (S0109).
    pub(super) fn count_tasks(
        &mut self,
        tasks: &[TaskSpec],
        gens: &[GeneratorSpec],
        duration: Option<f64>,
    ) -> bool {
        let mut total = tasks.len() as f64;
        for g in gens {
            let end = match (g.end, duration) {
                (Some(e), Some(d)) => e.min(d),
                (Some(e), None) => e,
                (None, Some(d)) => d,
                (None, None) => continue,
            };
            // Requests at start, start + every, ... while before `end`.
            let n = if end > g.start {
                ((end - g.start) / g.every).ceil()
            } else {
                0.0
            };
            total += n;
            if total > MAX_TASKS {
                self.error(
                    codes::TOO_LARGE,
                    g.span,
                    format!(
                        "this generator requests {n} tasks, more than {MAX_TASKS} task requests in all"
                    ),
                );
                self.help("check the unit of `every` (1ms instead of 1min?)");
                return false;
            }
        }
        true
    }
}
