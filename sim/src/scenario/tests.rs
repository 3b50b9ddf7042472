use super::fleet::ROBOT_NUMBERS;
use super::*;

fn run(text: &str) -> (Option<Scenario>, Vec<Diagnostic>) {
    parse(FileId(0), text, Path::new("/scen"))
}

fn ok(text: &str) -> Scenario {
    let (s, d) = run(text);
    assert!(!mapc_ir::has_errors(&d), "{d:#?}");
    s.expect("a scenario when there are no errors")
}

/// Codes of the diagnostics; every one must have a position.
fn codes_of(text: &str) -> Vec<&'static str> {
    let (s, d) = run(text);
    for x in &d {
        assert!(x.span.line > 0 && x.span.col > 0, "no position: {x:?}");
    }
    if mapc_ir::has_errors(&d) {
        assert!(s.is_none());
    }
    d.iter().map(|x| x.code).collect()
}

const MIN: &str = "duration: 1h\nfleets: [{name: f, robot: TinyRobot, count: 1}]\n";

#[test]
fn durations() {
    assert_eq!(parse_duration("1h30min"), Ok(5400.0));
    assert_eq!(parse_duration("90s"), Ok(90.0));
    assert_eq!(parse_duration("15min"), Ok(900.0));
    assert_eq!(parse_duration("8h"), Ok(8.0 * 3600.0));
    assert_eq!(parse_duration("2.5h"), Ok(9000.0));
    assert_eq!(parse_duration("1d 2h"), Ok(86_400.0 + 7200.0));
    assert_eq!(parse_duration("250ms"), Ok(0.25));
    assert_eq!(parse_duration("42"), Ok(42.0));
    for bad in ["15m", "8 hours", "h", "1h30", "", "1.2.3s", "-5s", "1e3s"] {
        assert!(parse_duration(bad).is_err(), "{bad}");
    }
    let s = ok(&format!("{MIN}step: 10ms\n").replace("duration: 1h", "duration: 1h30min"));
    assert_eq!(s.duration, 5400.0);
    assert!((s.step - 0.01).abs() < 1e-15);
    assert_eq!(ok(&MIN.replace("1h", "7200")).duration, 7200.0);
    assert_eq!(ok(&MIN.replace("1h", "0.5")).duration, 0.5);
}

#[test]
fn full_example_and_defaults() {
    let s = ok(r#"
map: ../maps/hotel/hotel.building.yaml   # relative to the scenario file
seed: 7
duration: 8h
step: 0.01
fleets:
  - name: tinyRobot
    graph: 0
    robot: TinyRobot
    count: 4
    spawn: spawn_points
    recharge_threshold: 0.2
    recharge_soc: 1.0
    tasks: [loop, delivery]
  - name: deliveryRobot
    robot: {preset: DeliveryRobot, nominal_drive_speed: 0.6, footprint: 0.3}
    spawn: [a, b]
workcells:
  - {name: pantry_dispenser, kind: dispenser, waypoint: pantry}
tasks:
  - {at: 0, loop: {start: lobby, finish: room_1, loops: 3}, fleet: tinyRobot}
  - {at: 5min, delivery: {pickup: pantry, dropoff: room_1}}
  - {at: 10min, go_to_place: {place: lobby}}
  - {at: 20min, go_to_place: lobby}
generators:
  - {every: 5min, start: 0, end: 8h, delivery: {pickup: pantry, dropoff: room_1}}
options: {lifts_start_at_initial_floor: false, clean_duration: 2min, stop_when_done: true}
"#);
    assert_eq!(
        s.map,
        Some(PathBuf::from("/scen/../maps/hotel/hotel.building.yaml"))
    );
    assert_eq!((s.seed, s.duration, s.step), (7, 28_800.0, 0.01));
    let f = &s.fleets[0];
    assert_eq!((f.name.as_str(), f.graph, f.count), ("tinyRobot", 0, 4));
    assert_eq!(f.spawn, SpawnSpec::MapSpawnPoints);
    assert_eq!(
        f.task_kinds,
        vec![TaskCategory::Loop, TaskCategory::Delivery]
    );
    assert_eq!(f.robot, RobotParams::preset("TinyRobot").unwrap());
    let g = &s.fleets[1];
    // count defaults to the number of spawn waypoints; other defaults as documented.
    assert_eq!(g.count, 2);
    assert_eq!((g.recharge_threshold, g.recharge_soc), (0.2, 1.0));
    assert!(g.task_kinds.is_empty());
    assert_eq!(g.robot.nominal_drive_speed, 0.6);
    assert_eq!(g.robot.nominal_drive_acceleration, 0.5); // from the preset
    assert_eq!(g.robot.nominal_capacity, 40.0);
    assert_eq!(g.robot.footprint, 0.3);
    assert_eq!(s.workcells[0].kind, WorkcellKind::Dispenser);
    assert_eq!(
        s.tasks[0].kind,
        TaskKind::Loop {
            start: "lobby".into(),
            finish: "room_1".into(),
            loops: 3
        }
    );
    assert_eq!(s.tasks[0].fleet.as_deref(), Some("tinyRobot"));
    assert_eq!(s.tasks[1].at, 300.0);
    assert_eq!(s.tasks[2].kind, s.tasks[3].kind);
    assert_eq!(s.generators[0].every, 300.0);
    assert_eq!(s.generators[0].end, Some(28_800.0));
    assert_eq!(
        s.options,
        SimOptions {
            lifts_start_at_initial_floor: false,
            clean_duration: 120.0,
            stop_when_done: true,
            ..SimOptions::default()
        }
    );
    // Defaults of a minimal scenario.
    let m = ok(MIN);
    assert_eq!((m.seed, m.step, m.map.clone()), (0, 0.01, None));
    assert_eq!(m.fleets[0].spawn, SpawnSpec::Auto);
    assert_eq!(m.options, SimOptions::default());
}

#[test]
fn presets_are_the_runtime_spec_table() {
    // Runtime spec §1.1: v_nom a_nom a_max w_nom α_nom α_max stop reversible V Ah I m I μ P.
    let rows: [(&str, [f64; 7], bool, [f64; 7]); 4] = [
        (
            "TinyRobot",
            [0.5, 0.25, 0.75, 0.6, 1.5, 2.0, 0.75],
            true,
            [12., 24., 5., 20., 10., 0.22, 20.],
        ),
        (
            "DeliveryRobot",
            [0.7, 0.5, 0.75, 0.6, 1.5, 2.0, 0.75],
            true,
            [24., 40., 8.8, 70., 40., 0.22, 20.],
        ),
        (
            "CleanerBotA",
            [0.7, 0.5, 0.6, 0.4, 1.0, 1.2, 1.5],
            false,
            [24., 20., 10., 70., 40., 0.22, 100.],
        ),
        (
            "HospitalRobot",
            [0.7, 0.5, 0.75, 0.3, 1.5, 2.0, 0.75],
            false,
            [24., 24., 5., 70., 40., 0.22, 20.],
        ),
    ];
    for (name, m, rev, b) in rows {
        let s = ok(&MIN.replace("TinyRobot", name));
        let r = &s.fleets[0].robot;
        assert_eq!(r.model, name);
        let got = [
            r.nominal_drive_speed,
            r.nominal_drive_acceleration,
            r.max_drive_acceleration,
            r.nominal_turn_speed,
            r.nominal_turn_acceleration,
            r.max_turn_acceleration,
            r.stop_distance,
        ];
        assert_eq!(got, m, "{name}");
        assert_eq!(r.stop_radius, m[6]);
        assert_eq!(r.reversible, rev);
        let got = [
            r.nominal_voltage,
            r.nominal_capacity,
            r.charging_current,
            r.mass,
            r.inertia,
            r.friction_coefficient,
            r.nominal_power,
        ];
        assert_eq!(got, b, "{name}");
    }
    // Custom robot: slotcar defaults (§1.1) plus what is set.
    let s = ok(&MIN.replace(
        "TinyRobot",
        "{model: Mine, nominal_drive_speed: 1.2, reversible: false}",
    ));
    let r = &s.fleets[0].robot;
    assert_eq!(
        (r.model.as_str(), r.nominal_drive_speed, r.reversible),
        ("Mine", 1.2, false)
    );
    assert_eq!(r.nominal_turn_speed, std::f64::consts::PI / 8.0);
    assert_eq!(r.nominal_capacity, 24.0);
}

#[test]
fn unknown_preset_lists_presets() {
    let (_, d) = run(&MIN.replace("TinyRobot", "TinyBot"));
    assert_eq!(d.len(), 1);
    assert_eq!(d[0].code, "S0301");
    let help = d[0].help.as_deref().unwrap();
    assert!(help.contains("did you mean `TinyRobot`"), "{help}");
    for p in RobotParams::preset_names() {
        assert!(help.contains(p), "{help}");
    }
    // line 2, column of `TinyBot` in `fleets: [{name: f, robot: TinyBot, ...`.
    assert_eq!((d[0].span.line, d[0].span.col), (2, 27));
}

#[test]
fn unknown_keys_warn_with_a_suggestion_and_keep_the_scenario() {
    let text = format!("{MIN}sed: 3\noptions: {{stop_when_finished: true}}\n")
        .replace("count: 1", "count: 1, recharge_treshold: 0.5");
    let (s, d) = run(&text);
    assert!(s.is_some());
    let codes: Vec<_> = d.iter().map(|x| x.code).collect();
    assert_eq!(codes, ["S0103", "S0103", "S0307"]);
    assert!(d.iter().all(|x| !x.is_error()));
    // Top-level keys are read before the fleets.
    assert_eq!(d[0].help.as_deref(), Some("did you mean `seed`?"));
    assert_eq!(
        d[1].help.as_deref(),
        Some("did you mean `recharge_threshold`?")
    );
    // Too far from any option for a guess: the help lists them.
    assert_eq!(
        d[2].help.as_deref(),
        Some(
            "known keys: `lifts_start_at_initial_floor`, `clean_duration`, `stop_when_done`, \
                 `charging`, `instant_charging`, `battery_drain`"
        )
    );
    assert_eq!(d[0].span.line, 3);
}

#[test]
fn every_problem_is_reported_in_one_run() {
    let text = "\
seed: seven
duration: 8 hours
step: 1
fleets:
  - {name: a, robot: TinyRobot, count: 0}
  - {name: a, robot: TinyRobot, count: 2, recharge_threshold: 20}
  - {robot: [1], count: x}
tasks:
  - {at: 0, patrol: {start: a, finish: b}}
  - {at: 0, loop: {start: a}, go_to_place: b}
  - {go_to_place: {place: p}, fleet: nobody}
";
    let codes = codes_of(text);
    for want in [
        "S0101", "S0105", "S0107", "S0106", "S0108", "S0102", "S0302", "S0303",
    ] {
        assert!(codes.contains(&want), "{want} missing from {codes:?}");
    }
    // seed, duration, step, count 0, threshold, missing name, robot type, count type,
    // patrol, two kinds.
    assert!(codes.len() >= 10, "{codes:?}");
}

#[test]
fn fleet_cross_checks() {
    let base = "duration: 1h\nfleets:\n  - {name: tinyRobot, robot: TinyRobot, count: 1}\n  - {name: cleaners, robot: CleanerBotA, count: 1, tasks: [clean]}\n";
    let t = |task: &str| codes_of(&format!("{base}tasks:\n  - {task}\n"));
    assert_eq!(t("{go_to_place: lobby, fleet: tinyRobots}"), ["S0305"]);
    assert_eq!(
        t("{delivery: {pickup: a, dropoff: b}, fleet: cleaners}"),
        ["S0306"]
    );
    assert!(t("{clean: zone_1, fleet: cleaners}").is_empty());
    let (_, d) = run(&format!(
        "{base}tasks:\n  - {{go_to_place: lobby, fleet: tinyRobots}}\n"
    ));
    assert_eq!(
        d[0].help.as_deref(),
        Some("did you mean `tinyRobot`? fleets: `tinyRobot`, `cleaners`")
    );
    assert_eq!(
        codes_of(&base.replace("name: cleaners", "name: tinyRobot")),
        ["S0304"]
    );
    let only_cleaners =
        "duration: 1h\nfleets: [{name: c, robot: CleanerBotA, count: 1, tasks: [clean]}]\n";
    assert_eq!(
        codes_of(&format!(
            "{only_cleaners}tasks: [{{loop: {{start: a, finish: b}}}}]\n"
        )),
        ["S0306"]
    );
    assert_eq!(
        codes_of(&MIN.replace("count: 1", "count: 3, spawn: [a, b]")),
        ["S0309"]
    );
    assert_eq!(
        codes_of(&MIN.replace("count: 1", "spawn: [a, a]")),
        ["S0309"]
    );
    assert_eq!(
        codes_of(&MIN.replace("count: 1", "count: 1, spawn: anywhere")),
        ["S0101"]
    );
    assert_eq!(
            codes_of(&format!("{MIN}workcells:\n  - {{name: w, kind: dispenser, waypoint: a}}\n  - {{name: w, kind: ingestor, waypoint: b}}\n")),
            ["S0308"]
        );
    assert_eq!(
        codes_of(&format!(
            "{MIN}workcells: [{{name: w, kind: robot, waypoint: a}}]\n"
        )),
        ["S0101"]
    );
}

#[test]
fn ranges_and_absurd_sizes() {
    assert_eq!(
        codes_of(&MIN.replace("count: 1", "count: 10001")),
        ["S0109"]
    );
    assert_eq!(
        codes_of(&MIN.replace("count: 1", "count: 1e300")),
        ["S0109"]
    );
    assert_eq!(codes_of(&MIN.replace("count: 1", "count: -2")), ["S0106"]);
    assert_eq!(codes_of(&MIN.replace("count: 1", "count: 1.5")), ["S0101"]);
    assert!(codes_of(&MIN.replace("count: 1", "count: 10000")).is_empty());
    assert_eq!(codes_of(&MIN.replace("1h", "366d")), ["S0109"]);
    assert!(codes_of(&MIN.replace("1h", "365d")).is_empty());
    assert_eq!(codes_of(&MIN.replace("1h", "0")), ["S0106"]);
    assert_eq!(codes_of(&MIN.replace("1h", ".inf")), ["S0105"]);
    assert_eq!(codes_of(&MIN.replace("1h", "-3")), ["S0105"]);
    assert_eq!(codes_of(&format!("{MIN}step: 0.2\n")), ["S0107"]);
    assert!(codes_of(&format!("{MIN}step: 0.1\n")).is_empty());
    assert_eq!(codes_of(&format!("{MIN}step: 0\n")), ["S0106"]);
    assert_eq!(codes_of(&format!("{MIN}seed: -1\n")), ["S0108"]);
    assert_eq!(
        codes_of(&MIN.replace("count: 1", "count: 1, recharge_soc: 1.5")),
        ["S0108"]
    );
    assert_eq!(
        codes_of(&MIN.replace("count: 1", "count: 1, recharge_threshold: 1")),
        ["S0108"]
    );
    assert_eq!(
        codes_of(&MIN.replace(
            "count: 1",
            "count: 1, recharge_threshold: 0.5, recharge_soc: 0.4"
        )),
        ["S0108"]
    );
    assert_eq!(
        codes_of(&MIN.replace("count: 1", "count: 1, graph: -1")),
        ["S0108"]
    );
    assert_eq!(
        codes_of(&MIN.replace(
            "TinyRobot",
            "{preset: TinyRobot, mass: 0, stop_distance: -1, nominal_power: .nan}"
        )),
        ["S0106", "S0108", "S0108"]
    );
    // 8 h every 30 ms is 960,000 requests: accepted; every 20 ms is 1,440,000: refused.
    let gen = |every: &str| {
        codes_of(&format!(
            "{}generators: [{{every: {every}, go_to_place: a}}]\n",
            MIN.replace("1h", "8h")
        ))
    };
    assert!(gen("30ms").is_empty());
    assert_eq!(gen("20ms"), ["S0109"]);
    assert_eq!(gen("0"), ["S0106"]);
    assert_eq!(
        codes_of(&format!(
            "{MIN}generators: [{{every: 1min, start: 2h, end: 1h, go_to_place: a}}]\n"
        )),
        ["S0108"]
    );
    assert_eq!(
        codes_of(&format!("{MIN}tasks: [{{at: 2h, go_to_place: a}}]\n")),
        ["S0310"]
    );
    assert_eq!(
        codes_of(&format!(
            "{MIN}tasks: [{{loop: {{start: a, finish: b, loops: 2000000}}}}]\n"
        )),
        ["S0109"]
    );
}

#[test]
fn malformed_files_never_panic_and_are_located() {
    let bomb = "a: &a [x, x, x, x, x, x, x, x, x, x]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a, *a]\nc: &c [*b, *b, *b, *b, *b, *b, *b, *b, *b, *b]\nd: &d [*c, *c, *c, *c, *c, *c, *c, *c, *c, *c]\ne: &e [*d, *d, *d, *d, *d, *d, *d, *d, *d, *d]\nf: [*e, *e, *e, *e, *e, *e, *e, *e, *e, *e]\n";
    let deep = format!("duration: {}1{}\n", "[".repeat(200), "]".repeat(200));
    let garbage: String = (0u32..2000)
        .map(|i| char::from_u32((i * 7919) % 0x2FF + 1).unwrap_or('?'))
        .collect();
    let cases: Vec<(&str, String, &str)> = vec![
        ("empty", String::new(), "S0001"),
        ("comment only", "# nothing\n".into(), "S0001"),
        ("scalar root", "hello".into(), "S0101"),
        ("list root", "- a\n- b\n".into(), "S0101"),
        ("syntax", "fleets: [{name: a\n".into(), "S0001"),
        ("tab", "duration:\n\t- 1\n".into(), "S0001"),
        ("alias bomb", bomb.into(), "S0002"),
        ("deep nesting", deep, "S0002"),
        ("garbage", garbage, ""),
        ("missing all", "seed: 1\n".into(), "S0102"),
        (
            "fleets map",
            "duration: 1\nfleets: {a: 1}\n".into(),
            "S0101",
        ),
        ("fleet scalar", "duration: 1\nfleets: [3]\n".into(), "S0101"),
        (
            "huge int",
            "duration: 99999999999999999999999\nfleets: []\n".into(),
            "S0109",
        ),
        (
            "huge float",
            "duration: 1e400\nfleets: []\n".into(),
            "S0105",
        ),
        ("empty fleets", "duration: 1\nfleets: []\n".into(), "S0102"),
        (
            "null key",
            "duration: 1\n~: 3\nfleets: []\n".into(),
            "S0101",
        ),
        ("task not map", format!("{MIN}tasks: [loop]\n"), "S0101"),
        (
            "kind not map",
            format!("{MIN}tasks: [{{loop: 3}}]\n"),
            "S0101",
        ),
        ("no kind", format!("{MIN}tasks: [{{at: 3}}]\n"), "S0102"),
        (
            "loop no finish",
            format!("{MIN}tasks: [{{loop: {{start: a}}}}]\n"),
            "S0102",
        ),
        ("options list", format!("{MIN}options: [1]\n"), "S0101"),
        (
            "option type",
            format!("{MIN}options: {{stop_when_done: yes}}\n"),
            "S0101",
        ),
        ("dup key", format!("{MIN}seed: 1\nseed: 2\n"), "S0104"),
    ];
    for (name, text, want) in cases {
        let (s, d) = run(&text);
        assert!(!d.is_empty(), "{name}: no diagnostics");
        for x in &d {
            assert!(
                x.span.line > 0 && x.span.col > 0,
                "{name}: no position: {x:?}"
            );
        }
        if !want.is_empty() {
            assert!(
                d.iter().any(|x| x.code == want),
                "{name}: want {want}, got {d:#?}"
            );
        }
        if mapc_ir::has_errors(&d) {
            assert!(s.is_none(), "{name}");
        }
    }
}

#[test]
fn codes_in_use_are_listed() {
    // Every file of the reader.
    let src = [
        include_str!("../scenario.rs"),
        include_str!("document.rs"),
        include_str!("faults.rs"),
        include_str!("fleet.rs"),
        include_str!("include.rs"),
        include_str!("read.rs"),
        include_str!("requests.rs"),
        include_str!("rmf_config.rs"),
        include_str!("task.rs"),
    ]
    .concat();
    for c in codes::CODES {
        assert!(c.code.starts_with('S') && c.code.len() == 5);
    }
    for (i, _) in src.match_indices("codes::") {
        let name: String = src[i + 7..]
            .chars()
            .take_while(|c| c.is_ascii_uppercase() || *c == '_' || c.is_ascii_digit())
            .collect();
        if name.len() > 2 && name != "CODES" {
            assert!(
                codes::CODES.iter().any(|c| {
                    let const_src = include_str!("../codes.rs");
                    const_src.contains(&format!(
                        "pub const {name}: Code = Code {{\n    code: \"{}\"",
                        c.code
                    ))
                }),
                "{name} is not in CODES"
            );
        }
    }
}

#[test]
fn json_schema_lists_the_keys_the_parser_reads() {
    let schema: serde_json::Value =
        serde_json::from_str(include_str!("../../../docs/scenario.schema.json")).unwrap();
    assert_eq!(
        schema["$schema"],
        "https://json-schema.org/draft/2020-12/schema"
    );
    let keys = |v: &serde_json::Value| -> Vec<String> {
        let mut k: Vec<String> = v["properties"]
            .as_object()
            .unwrap_or_else(|| panic!("no properties in {v}"))
            .keys()
            .cloned()
            .collect();
        k.sort();
        k
    };
    let want = |names: &[&str], more: &[&str]| -> Vec<String> {
        let mut k: Vec<String> = names.iter().chain(more).map(|s| s.to_string()).collect();
        k.sort();
        k
    };
    let defs = &schema["$defs"];
    assert_eq!(keys(&schema), want(TOP_KEYS, &[]));
    assert_eq!(keys(&defs["fleet"]), want(FLEET_KEYS, &[]));
    assert_eq!(keys(&defs["workcell"]), want(WORKCELL_KEYS, &[]));
    assert_eq!(keys(&defs["options"]), want(OPTION_KEYS, &[]));
    assert_eq!(keys(&defs["crowd"]), want(CROWD_KEYS, &[]));
    assert_eq!(keys(&defs["task"]), want(TASK_KEYS, KINDS));
    assert_eq!(keys(&defs["generator"]), want(GENERATOR_KEYS, KINDS));
    assert_eq!(keys(&defs["fault"]), want(faults::FAULT_KEYS, &[]));
    let robot: Vec<&str> = ROBOT_NUMBERS.iter().map(|r| r.0).collect();
    assert_eq!(
        keys(&defs["robot"]["oneOf"][1]),
        want(&robot, &["preset", "model", "reversible"])
    );
    // Strictly positive robot numbers have exclusiveMinimum 0, the others minimum 0.
    for (k, strict) in ROBOT_NUMBERS {
        let p = &defs["robot"]["oneOf"][1]["properties"][k];
        let bound = if *strict {
            "exclusiveMinimum"
        } else {
            "minimum"
        };
        assert_eq!(p[bound], 0, "{k}");
    }
    for p in RobotParams::preset_names() {
        assert!(defs["preset"]["pattern"].as_str().unwrap().contains(p));
    }
}

#[test]
fn huge_garbage_is_capped_and_fast() {
    // 100,000 unknown keys and 100,000 tasks naming unknown fleets: at most
    // MAX_DIAGNOSTICS are kept, then one S0002; quadratic checks would take minutes.
    let mut text = String::from(MIN);
    for i in 0..100_000 {
        text.push_str(&format!("k{i}: 1\n"));
    }
    text.push_str("tasks:\n");
    for i in 0..100_000 {
        text.push_str(&format!("  - {{go_to_place: p, fleet: g{i}}}\n"));
    }
    let start = std::time::Instant::now();
    let (s, d) = run(&text);
    assert!(s.is_none());
    assert_eq!(d.len(), MAX_DIAGNOSTICS + 1);
    let last = d.last().unwrap();
    assert_eq!(last.code, "S0002");
    assert!(
        last.message.starts_with("199000 more problem(s)"),
        "{}",
        last.message
    );
    // Generous even for a debug build on a loaded machine.
    assert!(start.elapsed().as_secs() < 30, "{:?}", start.elapsed());
    // Warnings alone past the limit still refuse the file.
    let mut text = String::from(MIN);
    for i in 0..1500 {
        text.push_str(&format!("k{i}: 1\n"));
    }
    let (s, d) = run(&text);
    assert!(s.is_none());
    assert_eq!(d.last().unwrap().code, "S0002");
}
