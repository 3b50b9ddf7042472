//! mapc-sim: a headless, deterministic reference runtime of what the RMF Gazebo plugins do
//! (slotcar robots, doors, lifts, dispensers and ingestors, door and lift supervisors),
//! driven by a minimal fleet layer that runs tasks. Behaviour follows the runtime spec;
//! where the plugins have a quirk, the intended behaviour is the default.
//!
//! The only I/O is the trace writer handed to [`simulate`].

pub mod codes;
mod crowd;
mod door;
mod fleet;
mod graph;
mod levels;
mod lift;
pub mod msgs;
mod params;
mod profile;
mod report;
mod scenario;
mod slotcar;
mod supervisor;
mod trace;
mod traffic;
mod truth;
mod workcell;
mod world;

pub use crowd::{compare_crowd, CrowdReport, FleetCompare, SpeedStats, Spread};
pub use params::RobotParams;
pub use report::rmf_states;
pub use report::{
    DoorReport, Encounter, FleetReport, LiftReport, PhaseReport, Report, RequestReport,
    RobotReport, ScenarioWarning, StuckReport, TaskReport, TrafficReport, Waits,
};
pub use scenario::{
    parse as parse_scenario, parse_duration, parse_files as parse_scenario_files,
    parse_files_with as parse_scenario_files_with, CancelSpec, CrowdOptions, FaultSpec,
    FaultTarget, Finishing, FleetSpec, GeneratorSpec, Included, Parsed, RequestKind, RequestSpec,
    RequestedTask, RmfFleet, RmfRobot, Scenario, SimOptions, SpawnSpec, TaskCategory, TaskKind,
    TaskSpec, WorkcellKind, WorkcellSpec, MAX_DURATION,
};
pub use trace::TraceFilter;

use mapc_ir::{Building, Diagnostic};
use msgs::{Msg, Published, Topic};
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

/// How long to run and what to record.
#[derive(Default)]
pub struct RunOptions<'a> {
    /// Stop at this sim time (s); default: the scenario's duration.
    pub until: Option<f64>,
    /// One JSON object per message (JSON Lines).
    pub trace: Option<&'a mut dyn Write>,
    /// Called about once per simulated minute with (t, end).
    pub progress: Option<&'a mut dyn FnMut(f64, f64)>,
    /// Checked before every step: when set, the run ends there and the report says it was
    /// interrupted (how a caller stops on Ctrl-C and still gets the report of what ran).
    pub stop: Option<&'a AtomicBool>,
    /// Which messages go to the trace (every one by default); the report sees them all.
    pub trace_filter: trace::TraceFilter,
    /// Sees every message the trace records, in the same order (e.g. to build a replay);
    /// it cannot change the run.
    pub observer: Option<&'a mut dyn FnMut(&Published)>,
    /// Called before every step with the sim time: appends the requests other nodes sent
    /// (a DDS bridge), which are recorded and delivered like the fleet layer's.
    pub inject: Option<&'a mut Inject<'a>>,
    /// Only the plugins run (slotcars, doors, lifts, workcells, as Gazebo would): the fleet
    /// layer sends nothing and the run lasts its whole duration; requests come from `inject`.
    pub plugins_only: bool,
    /// Receives the wall-clock time (s) of every traffic decision (one robot's plan against
    /// the schedule), for benchmarks; the run itself does not depend on it.
    pub plan_times: Option<&'a mut Vec<f64>>,
}

/// Appends, at sim time `t`, the requests other nodes sent (see `RunOptions::inject`).
pub type Inject<'a> = dyn FnMut(f64, &mut Vec<(Topic, Msg)>) + 'a;

/// Why a run could not start or finish.
#[derive(Debug)]
pub enum SimError {
    /// The scenario does not fit the map (unknown waypoints, fleets without robots...).
    Invalid(Vec<Diagnostic>),
    /// Writing the trace failed.
    Io(std::io::Error),
}

/// Runs `scenario` on a validated `building`.
pub fn simulate(
    building: &Building,
    scenario: &Scenario,
    mut opts: RunOptions<'_>,
) -> Result<Report, SimError> {
    // RMF task requests become tasks (or are refused) on this map.
    let accepted;
    let mut outcomes = Vec::new();
    let scenario = if scenario.requests.is_empty() {
        scenario
    } else {
        let (s, o) = scenario::accept_requests(building, scenario).map_err(SimError::Invalid)?;
        accepted = s;
        outcomes = o;
        &accepted
    };
    let placement = fleet::Fleets::place(building, scenario).map_err(SimError::Invalid)?;
    let mut fleets =
        fleet::Fleets::new(building, scenario, &placement).map_err(SimError::Invalid)?;
    let setup = world::WorldSetup {
        dt: scenario.step,
        seed: scenario.seed,
        robots: placement.robots.clone(),
        workcells: placement.workcells.clone(),
        lifts_start_at_initial_floor: scenario.options.lifts_start_at_initial_floor,
    };
    if opts.plan_times.is_some() {
        fleets.time_plans();
    }
    let mut world = world::World::new(building, &setup);
    let unknown = world.set_faults(&scenario.faults);
    if !unknown.is_empty() {
        return Err(SimError::Invalid(
            unknown
                .into_iter()
                .map(|k| {
                    let f = &scenario.faults[k];
                    Diagnostic::error(
                        codes::UNKNOWN_FAULT_TARGET.code,
                        f.span,
                        format!(
                            "the fault names {} `{}`, which this run does not have",
                            f.target.kind(),
                            f.target.name()
                        ),
                    )
                })
                .collect(),
        ));
    }
    let o = &scenario.options;
    if o.crowd.enabled {
        let floors = levels::elevations(building);
        let crowd = crowd::Crowd::new(
            building,
            &floors,
            o.crowd.scale,
            scenario.seed,
            scenario.step,
        )
        .map_err(|e| {
            SimError::Invalid(vec![Diagnostic::error(
                codes::CROWD.code,
                mapc_ir::Span::UNKNOWN,
                format!("the crowd cannot walk: {e}"),
            )])
        })?;
        if let Some(c) = crowd {
            world.set_crowd(c);
        }
    }
    world.set_charging(o.charging, o.instant_charging, o.battery_drain);
    world.set_supervisors(!opts.plugins_only);
    let mut report = report::ReportBuilder::new(building, scenario, &placement);
    let end = opts.until.unwrap_or(scenario.duration);
    // Whole steps: comparing accumulated float time with `end` would depend on rounding.
    let steps = (end / scenario.step).round().max(0.0) as u64;
    let mut inbox: Vec<Published> = Vec::new();
    let mut requests: Vec<(Topic, Msg)> = Vec::new();
    let mut next_progress = 60.0;
    // Ground truth every 0.1 s is enough to see robots pass each other (≤ 0.2 m apart at
    // the fastest presets' speeds), whatever the step.
    let sample_every = ((0.1 / scenario.step).round() as u64).max(1);
    let mut interrupted = false;
    for i in 0..steps {
        if opts.stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
            interrupted = true;
            break;
        }
        let t = world.time();
        requests.clear();
        if !opts.plugins_only {
            fleets.update(t, &inbox, &mut requests);
        }
        if let Some(inject) = opts.inject.as_mut() {
            inject(t, &mut requests);
        }
        inbox.clear();
        for (topic, msg) in requests.drain(..) {
            let p = Published { t, topic, msg };
            record(
                &mut opts.trace,
                &mut opts.trace_filter,
                &mut opts.observer,
                &mut report,
                &p,
            )?;
            if topic != Topic::TaskEvents {
                world.deliver(topic, p.msg);
            }
        }
        world.step(&mut inbox);
        for p in &inbox {
            record(
                &mut opts.trace,
                &mut opts.trace_filter,
                &mut opts.observer,
                &mut report,
                p,
            )?;
        }
        if i % sample_every == 0 {
            report.sample(world.time(), &world.robots());
        }
        if let Some(p) = opts.progress.as_mut() {
            if world.time() >= next_progress {
                p(world.time(), end);
                next_progress += 60.0;
            }
        }
        if !opts.plugins_only && fleets.all_done(world.time()) && scenario.options.stop_when_done {
            break;
        }
    }
    if let Some(w) = opts.trace.as_mut() {
        w.flush().map_err(SimError::Io)?;
    }
    let mut report = report.finish(world.time(), &world.robots());
    report.interrupted = interrupted;
    if !outcomes.is_empty() {
        let ids = scenario::task_ids(scenario);
        let cancels = fleets.cancel_results();
        report.requests = scenario
            .requests
            .iter()
            .zip(outcomes)
            .map(|(r, o)| match o {
                scenario::RequestOutcome::Task(i) => report::RequestReport {
                    line: r.line,
                    at: r.at,
                    task_id: ids.get(i).cloned(),
                    refused: None,
                },
                scenario::RequestOutcome::Cancel(id, k) => report::RequestReport {
                    line: r.line,
                    at: r.at,
                    task_id: Some(id),
                    refused: cancels.get(k).and_then(|c| c.clone().err()),
                },
                scenario::RequestOutcome::Refused(why) => report::RequestReport {
                    line: r.line,
                    at: r.at,
                    task_id: None,
                    refused: Some(why),
                },
            })
            .collect();
    }
    // Robots are listed in spawn order, as the world has them.
    for (i, r) in report.robots.iter_mut().enumerate() {
        r.battery_soc = world.soc(i).unwrap_or(1.0);
    }
    report.crowd = world.crowd().map(|c| c.report(world.time()));
    report.traffic = fleets.traffic_report();
    let lanes = fleets.lane_series(report.end_time);
    report.timeline.series.extend(lanes);
    if !opts.plugins_only {
        let broken_off = report
            .tasks
            .iter()
            .any(|t| t.started.is_some() && (t.result == "failed" || t.result == "cancelled"));
        report.throughput =
            report::bound::throughput(&fleets.demands(broken_off), &report.tasks, report.end_time);
    }
    if let Some(out) = opts.plan_times {
        out.extend(fleets.plan_times());
    }
    report.warnings = placement
        .warnings
        .iter()
        .map(|d| report::ScenarioWarning {
            code: d.code.to_string(),
            message: d.message.clone(),
            line: d.span.line,
            column: d.span.col,
        })
        .collect();
    Ok(report)
}

fn record(
    trace: &mut Option<&mut dyn Write>,
    filter: &mut trace::TraceFilter,
    observer: &mut Option<&mut dyn FnMut(&Published)>,
    report: &mut report::ReportBuilder,
    p: &Published,
) -> Result<(), SimError> {
    if let Some(w) = trace.as_mut() {
        if filter.accepts(p) {
            trace::write(&mut **w, p).map_err(SimError::Io)?;
        }
    }
    if let Some(o) = observer.as_mut() {
        o(p);
    }
    report.observe(p);
    Ok(())
}
