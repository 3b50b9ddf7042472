//! `config:` in a fleet: an RMF fleet adapter configuration (`config.yaml`) read as the
//! fleet's description. Both generations of the format are read: the `rmf_fleet:` block
//! with `robots:` inside it (EasyFullControl, rmf_demos today) and the older adapter
//! template whose robots are top-level, each with
//! `rmf_config: {start: {map_name, waypoint, orientation}, charger: {waypoint}}`.
//! Values are mapped onto mapc's own fleet and robot parameters; keys that only matter to
//! a real deployment (fleet manager address, credentials, update rates) are read and
//! ignored; other unknown keys are warned about, located in the config file.

use super::{codes, Entries, P};
use crate::params::RobotParams;
use crate::scenario::TaskCategory;
use mapc_frontend::yaml_tree::Node;
use mapc_ir::Span;
use std::path::PathBuf;

/// What a fleet adapter config says beyond mapc's own robot parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct RmfFleet {
    /// The config file, as resolved against the scenario's directory.
    pub config: PathBuf,
    /// The config's robots, in file order (robots spawn at their start waypoint, else at
    /// their charger).
    pub robots: Vec<RmfRobot>,
    /// `profile.vicinity` (m): traffic planning keeps other robots' footprints out of it
    /// (the contact check in the report still uses the footprints).
    pub vicinity: f64,
    /// Fleet-wide `finishing_request`.
    pub finishing_request: Finishing,
    /// Fleet-wide `responsive_wait` (default false).
    pub responsive_wait: bool,
    /// `account_for_battery_drain` (default true): when false, as in RMF, battery drain is
    /// left out of the fleet's decisions (its robots are not sent to charge on a low
    /// battery); the robots' batteries still drain in the simulation.
    pub account_for_battery_drain: bool,
    /// `actions` the fleet's robots can perform (`clean`, `teleop`, ...).
    pub actions: Vec<String>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RmfRobot {
    pub name: String,
    /// Where it starts: `rmf_config.start.waypoint` (older template), else its charger.
    pub start: String,
    pub charger: Option<String>,
    /// The robot's own `finishing_request`, overriding the fleet's.
    pub finishing_request: Option<Finishing>,
    pub responsive_wait: Option<bool>,
    /// Its start waypoint's name in the config file.
    pub span: Span,
}

/// `finishing_request`: what a robot does when it has no more tasks.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Finishing {
    /// Park; at the named waypoint when the robot's request names one.
    Park(Option<String>),
    Charge,
    Nothing,
}

/// The config read, before the scenario's own keys override it.
pub(super) struct ConfigFleet {
    pub name: String,
    pub robot: RobotParams,
    pub recharge_threshold: f64,
    pub recharge_soc: f64,
    pub task_kinds: Vec<TaskCategory>,
    pub rmf: RmfFleet,
}

/// Top-level keys of a config file. `fleet_manager`, `reference_coordinates`: the robots'
/// own API and coordinate frame, not simulated.
const TOP_KEYS: &[&str] = &[
    "rmf_fleet",
    "robots",
    "fleet_manager",
    "reference_coordinates",
];
/// Keys of `rmf_fleet` that mapc uses.
const FLEET_KEYS: &[&str] = &[
    "name",
    "limits",
    "profile",
    "reversible",
    "battery_system",
    "mechanical_system",
    "ambient_system",
    "tool_system",
    "cleaning_system",
    "recharge_threshold",
    "recharge_soc",
    "account_for_battery_drain",
    "task_capabilities",
    "actions",
    "finishing_request",
    "responsive_wait",
    "robots",
];
/// Keys of `rmf_fleet` read by RMF that change nothing in a simulation of the building:
/// connections, publish and update rates, reassignment and merging tolerances.
const FLEET_IGNORED: &[&str] = &[
    "fleet_manager",
    "publish_fleet_state",
    "robot_state_update_frequency",
    "max_delay",
    "default_maximum_delay",
    "update_interval",
    "server_uri",
    "reassign_task_interval",
    "task_assignment_strategy",
    "use_parking_reservations",
    "lane_merge_distance",
    "skip_rotation_commands",
    "retreat_to_charger_interval",
    "lift_emergency_level",
    "use_simulated_clock",
    "default_responsive_wait",
    // Read by rmf_ros2's EasyFullControl: graph merging and lane handling, emergency
    // levels, map transforms; and adapters' logging and topic names.
    "strict_lanes",
    "max_merge_waypoint_distance",
    "max_merge_lane_distance",
    "min_lane_length",
    "lift_emergency_levels",
    "transforms",
    "debug",
    "fleet_state_topic",
    "fleet_state_publish_frequency",
    "waypoint_merge_distance",
    "max_waypoint_merge_distance",
];
const ROBOT_KEYS: &[&str] = &["charger", "finishing_request", "responsive_wait", "start"];
const ROBOT_IGNORED: &[&str] = &[
    "max_merge_waypoint_distance",
    "max_merge_lane_distance",
    "min_lane_length",
    "robot_config",
    "rmf_config",
];
const OLD_RMF_CONFIG_KEYS: &[&str] = &["start", "charger"];
const OLD_RMF_CONFIG_IGNORED: &[&str] = &["robot_state_update_frequency"];
const START_KEYS: &[&str] = &["map_name", "waypoint"];
const START_IGNORED: &[&str] = &[
    "orientation",
    "max_merge_waypoint_distance",
    "max_merge_lane_distance",
    "min_lane_length",
];

impl P<'_> {
    /// A mapping's entries; keys in `ignored` are accepted silently, others not in `known`
    /// are warned about.
    fn config_entries<'n, 'a>(
        &mut self,
        v: &'n Node<'a>,
        what: &str,
        known: &[&str],
        ignored: &[&str],
    ) -> Option<Entries<'n, 'a>> {
        let mut all: Vec<&str> = known.to_vec();
        all.extend(ignored);
        let e = self.entries(v, what, None)?;
        for (key, k, _) in &e.items {
            if !all.contains(key) {
                self.warning(
                    codes::UNKNOWN_KEY,
                    k.span,
                    format!("unknown key `{key}` in {what}; it is ignored"),
                );
                match super::closest(key, known.iter().copied()) {
                    Some(c) => self.help(format!("did you mean `{c}`?")),
                    None => self.help(format!("keys mapc uses: {}", super::list(known))),
                }
            }
        }
        Some(e)
    }

    /// A number > 0 (`strict`) or ≥ 0.
    fn config_number(&mut self, v: &Node, what: &str, strict: bool) -> Option<f64> {
        let x = self.number(v, what)?;
        if strict && x <= 0.0 {
            self.error(
                codes::NOT_POSITIVE,
                v.span,
                format!("{what} is {x}; it must be greater than 0"),
            );
            return None;
        }
        if x < 0.0 {
            self.error(
                codes::OUT_OF_RANGE,
                v.span,
                format!("{what} is {x}; it must be 0 or more"),
            );
            return None;
        }
        Some(x)
    }

    /// `[velocity, acceleration]`.
    fn limit_pair(&mut self, v: &Node, what: &str) -> Option<(f64, f64)> {
        let Some(items) = v.as_seq() else {
            self.wrong_type(v, what, "a list [velocity, acceleration]");
            return None;
        };
        if items.len() != 2 {
            self.wrong_type(v, what, "a list of two numbers [velocity, acceleration]");
            return None;
        }
        let vel = self.config_number(&items[0], &format!("{what} velocity"), true);
        let acc = self.config_number(&items[1], &format!("{what} acceleration"), true);
        Some((vel?, acc?))
    }

    /// Reads the numbers of a sub-mapping such as `battery_system` into `set`.
    fn config_block(
        &mut self,
        fleet: &Entries,
        key: &str,
        fields: &[(&str, bool)],
        mut set: impl FnMut(&str, f64),
    ) -> bool {
        let Some(v) = fleet.get(key) else {
            return true;
        };
        let names: Vec<&str> = fields.iter().map(|f| f.0).collect();
        let Some(e) = self.config_entries(v, &format!("`{key}`"), &names, &[]) else {
            return false;
        };
        let mut ok = true;
        for &(field, strict) in fields {
            if let Some(n) = e.get(field) {
                match self.config_number(n, &format!("`{key}.{field}`"), strict) {
                    Some(x) => set(field, x),
                    None => ok = false,
                }
            }
        }
        ok
    }

    fn finishing(&mut self, v: &Node, what: &str) -> Option<Finishing> {
        let (kind, node, waypoint) = if v.as_map().is_some() {
            let e = self.config_entries(v, what, &["type", "waypoint_name"], &[])?;
            let t = self.required(&e, "type", what)?;
            let wp = match e.get("waypoint_name") {
                Some(n) => Some(self.name(n, &format!("{what}'s `waypoint_name`"))?),
                None => None,
            };
            (self.name(t, &format!("{what}'s `type`"))?, t, wp)
        } else {
            (self.name(v, what)?, v, None)
        };
        match kind.as_str() {
            "park" => Some(Finishing::Park(waypoint)),
            "charge" => Some(Finishing::Charge),
            "nothing" => Some(Finishing::Nothing),
            _ => {
                self.wrong_type(node, what, "`park`, `charge` or `nothing`");
                None
            }
        }
    }

    /// Reads the config file named by `config:` (already loaded as `root`).
    pub(super) fn rmf_config(&mut self, root: &Node, path: PathBuf) -> Option<ConfigFleet> {
        let top = self.config_entries(root, "the fleet config", TOP_KEYS, &[])?;
        let Some(fleet_node) = top.get("rmf_fleet").filter(|n| !n.is_null()) else {
            self.error(
                codes::RMF_CONFIG_NO_FLEET,
                top.span,
                "the fleet config has no `rmf_fleet`",
            );
            self.help("an RMF fleet adapter config describes its fleet under `rmf_fleet:` (name, limits, profile, battery_system, robots, ...)");
            return None;
        };
        let f = self.config_entries(fleet_node, "`rmf_fleet`", FLEET_KEYS, FLEET_IGNORED)?;
        let mut ok = true;
        let name = self
            .required(&f, "name", "`rmf_fleet`")
            .and_then(|n| self.name(n, "`rmf_fleet.name`"));
        let mut p = RobotParams::default();
        if let Some(n) = &name {
            p.model = n.clone();
        }
        if let Some(l) = f.get("limits") {
            match self.config_entries(l, "`limits`", &["linear", "angular"], &[]) {
                Some(e) => {
                    if let Some(n) = e.get("linear") {
                        match self.limit_pair(n, "`limits.linear`") {
                            // The adapter plans with these; the robot drives by them.
                            Some((v, a)) => {
                                p.nominal_drive_speed = v;
                                p.nominal_drive_acceleration = a;
                                p.max_drive_acceleration = a;
                            }
                            None => ok = false,
                        }
                    }
                    if let Some(n) = e.get("angular") {
                        match self.limit_pair(n, "`limits.angular`") {
                            Some((w, al)) => {
                                p.nominal_turn_speed = w;
                                p.nominal_turn_acceleration = al;
                                p.max_turn_acceleration = al;
                            }
                            None => ok = false,
                        }
                    }
                }
                None => ok = false,
            }
        }
        let mut vicinity = None;
        ok &= self.config_block(
            &f,
            "profile",
            &[("footprint", true), ("vicinity", true)],
            |k, x| match k {
                "footprint" => p.footprint = x,
                _ => vicinity = Some(x),
            },
        );
        if let Some(r) = f.get("reversible") {
            match self.bool(r, "`reversible`") {
                Some(b) => p.reversible = b,
                None => ok = false,
            }
        }
        ok &= self.config_block(
            &f,
            "battery_system",
            &[
                ("voltage", true),
                ("capacity", true),
                ("charging_current", false),
            ],
            |k, x| match k {
                "voltage" => p.nominal_voltage = x,
                "capacity" => p.nominal_capacity = x,
                _ => p.charging_current = x,
            },
        );
        ok &= self.config_block(
            &f,
            "mechanical_system",
            &[
                ("mass", true),
                ("moment_of_inertia", true),
                ("friction_coefficient", false),
            ],
            |k, x| match k {
                "mass" => p.mass = x,
                "moment_of_inertia" => p.inertia = x,
                _ => p.friction_coefficient = x,
            },
        );
        // RMF drains the battery by the ambient and the tool power sinks alike (W each).
        let (mut ambient, mut tool, mut cleaning) = (None, None, None);
        ok &= self.config_block(&f, "ambient_system", &[("power", false)], |_, x| {
            ambient = Some(x)
        });
        ok &= self.config_block(&f, "tool_system", &[("power", false)], |_, x| {
            tool = Some(x)
        });
        // fleet_adapter_mir's older configs name their tool's sink `cleaning_system`.
        ok &= self.config_block(&f, "cleaning_system", &[("power", false)], |_, x| {
            cleaning = Some(x)
        });
        if ambient.is_some() || tool.is_some() || cleaning.is_some() {
            p.nominal_power =
                ambient.unwrap_or(0.0) + tool.unwrap_or(0.0) + cleaning.unwrap_or(0.0);
        }
        let threshold = match f.get("recharge_threshold") {
            None => Some(0.2),
            Some(t) => self.recharge_threshold(t),
        };
        // RMF takes any fraction in [0, 1] (0: a charge that ends at once).
        let soc = match f.get("recharge_soc") {
            None => Some(1.0),
            Some(t) => self.number(t, "`recharge_soc`").and_then(|x| {
                if (0.0..=1.0).contains(&x) {
                    Some(x)
                } else {
                    self.error(
                        codes::OUT_OF_RANGE,
                        t.span,
                        format!("`recharge_soc` is {x}; it must be in [0, 1]"),
                    );
                    self.help("it is a fraction of the battery: 1.0 means full");
                    None
                }
            }),
        };
        let drain = match f.get("account_for_battery_drain") {
            None => Some(true),
            Some(b) => self.bool(b, "`account_for_battery_drain`"),
        };
        let responsive_wait = match f.get("responsive_wait") {
            None => Some(false),
            Some(b) => self.bool(b, "`responsive_wait`"),
        };
        let mut actions = match f.get("actions") {
            None => Some(Vec::new()),
            Some(a) if a.is_null() => Some(Vec::new()),
            Some(a) => self.seq(a, "`actions`", |p, n| p.name(n, "an action")),
        };
        let mut finishing = match f.get("finishing_request") {
            None => Some(None),
            Some(n) => self.finishing(n, "`finishing_request`").map(Some),
        };
        let mut kinds = vec![TaskCategory::GoToPlace];
        if let Some(tc) = f.get("task_capabilities") {
            let known = [
                "loop",
                "patrol",
                "delivery",
                "clean",
                "finishing_request",
                "action",
                "action_categories",
            ];
            match self.config_entries(tc, "`task_capabilities`", &known, &[]) {
                Some(e) => {
                    // `patrol` is what RMF's task API calls a loop.
                    for (key, cat) in [
                        ("loop", TaskCategory::Loop),
                        ("patrol", TaskCategory::Loop),
                        ("delivery", TaskCategory::Delivery),
                        ("clean", TaskCategory::Clean),
                    ] {
                        if let Some(n) = e.get(key) {
                            match self.bool(n, &format!("`task_capabilities.{key}`")) {
                                Some(true) => kinds.push(cat),
                                Some(false) => {}
                                None => ok = false,
                            }
                        }
                    }
                    // The older template listed the custom actions here too (rmf_demos:
                    // `action`; fleet_adapter_mir and others: `action_categories`).
                    for key in ["action", "action_categories"] {
                        if let Some(a) = e.get(key).filter(|a| !a.is_null()) {
                            let what = format!("`task_capabilities.{key}`");
                            match (
                                self.seq(a, &what, |p, n| p.name(n, "an action")),
                                &mut actions,
                            ) {
                                (Some(more), Some(all)) => all.extend(more),
                                _ => ok = false,
                            }
                        }
                    }
                    // The older template put the finishing request here.
                    if let (Some(n), Some(None)) = (e.get("finishing_request"), &finishing) {
                        finishing = self
                            .finishing(n, "`task_capabilities.finishing_request`")
                            .map(Some);
                    }
                }
                None => ok = false,
            }
        }
        // A fleet that can perform `clean` takes clean tasks (composed `perform_action`).
        if actions
            .as_ref()
            .is_some_and(|a| a.iter().any(|x| x == "clean"))
        {
            kinds.push(TaskCategory::Clean);
        }
        kinds.sort();
        kinds.dedup();

        // Robots: under `rmf_fleet` (today), or top-level (the older template).
        let robots = match (f.get("robots"), top.get("robots")) {
            (Some(r), _) if !r.is_null() => self.config_robots(r, false),
            (_, Some(r)) if !r.is_null() => self.config_robots(r, true),
            _ => {
                self.error(
                    codes::RMF_CONFIG_NO_FLEET,
                    f.span,
                    "the fleet config lists no robots",
                );
                self.help("list the robots under `rmf_fleet.robots` (name: {charger: <waypoint>}), or top-level `robots:` with `rmf_config: {start: {waypoint}, charger: {waypoint}}`");
                None
            }
        };
        if !ok {
            return None;
        }
        Some(ConfigFleet {
            name: name?,
            robot: p,
            // Not accounting for drain, or charging to no more than the threshold: never
            // sent to charge for a low battery (a charge would end where it began).
            recharge_threshold: match (drain?, threshold?, soc?) {
                (true, t, s) if s > t => t,
                _ => 0.0,
            },
            recharge_soc: soc?,
            task_kinds: kinds,
            rmf: RmfFleet {
                config: path,
                robots: robots?,
                vicinity: vicinity.unwrap_or(0.0),
                finishing_request: finishing?.unwrap_or(Finishing::Park(None)),
                responsive_wait: responsive_wait?,
                account_for_battery_drain: drain?,
                actions: actions?,
            },
        })
    }

    fn config_robots(&mut self, v: &Node, old: bool) -> Option<Vec<RmfRobot>> {
        let Some(m) = v.as_map() else {
            self.wrong_type(v, "`robots`", "a mapping of robot names to their settings");
            return None;
        };
        if m.is_empty() {
            self.error(
                codes::RMF_CONFIG_NO_FLEET,
                v.span,
                "the fleet config lists no robots",
            );
            return None;
        }
        let mut out = Vec::with_capacity(m.len());
        let mut ok = true;
        for (k, r) in m {
            let Some(name) = self.name(k, "a robot's name") else {
                ok = false;
                continue;
            };
            match self.config_robot(&name, r, old) {
                Some(x) => out.push(x),
                None => ok = false,
            }
        }
        ok.then_some(out)
    }

    fn config_robot(&mut self, name: &str, v: &Node, old: bool) -> Option<RmfRobot> {
        let what = format!("robot `{name}`");
        let e = self.config_entries(v, &what, ROBOT_KEYS, ROBOT_IGNORED)?;
        let mut charger = match e.get("charger") {
            None => None,
            Some(c) if c.as_map().is_some() => {
                let ce = self.config_entries(c, "`charger`", &["waypoint"], &[])?;
                let w = self.required(&ce, "waypoint", "`charger`")?;
                Some((self.name(w, "the charger's `waypoint`")?, w.span))
            }
            Some(c) => Some((self.name(c, &format!("{what}'s `charger`"))?, c.span)),
        };
        let mut start = None;
        let mut start_of = |p: &mut Self, s: &Node| -> Option<()> {
            let se = p.config_entries(s, "`start`", START_KEYS, START_IGNORED)?;
            if let Some(w) = se.get("waypoint").filter(|w| !w.is_null()) {
                start = Some((p.name(w, "the start `waypoint`")?, w.span));
            }
            if let Some(m) = se.get("map_name") {
                p.name(m, "the start `map_name`")?;
            }
            Some(())
        };
        if let Some(s) = e.get("start") {
            start_of(self, s)?;
        }
        // The older template: `rmf_config: {start: {...}, charger: {waypoint}}`.
        if let Some(rc) = e.get("rmf_config").filter(|_| old) {
            let re = self.config_entries(
                rc,
                "`rmf_config`",
                OLD_RMF_CONFIG_KEYS,
                OLD_RMF_CONFIG_IGNORED,
            )?;
            if let Some(s) = re.get("start") {
                start_of(self, s)?;
            }
            if let Some(c) = re.get("charger") {
                let ce = self.config_entries(c, "`charger`", &["waypoint"], &[])?;
                let w = self.required(&ce, "waypoint", "`charger`")?;
                charger = Some((self.name(w, "the charger's `waypoint`")?, w.span));
            }
        }
        let finishing_request = match e.get("finishing_request") {
            None => None,
            Some(n) => Some(self.finishing(n, &format!("{what}'s `finishing_request`"))?),
        };
        let responsive_wait = match e.get("responsive_wait") {
            None => None,
            Some(n) => Some(self.bool(n, "`responsive_wait`")?),
        };
        let Some((start, span)) = start.or_else(|| charger.clone()) else {
            self.error(
                codes::MISSING_KEY,
                v.span,
                format!("{what} has no `charger` and no start waypoint"),
            );
            self.help("give it `charger: <waypoint>`: robots start at their charger");
            return None;
        };
        Some(RmfRobot {
            name: name.to_string(),
            start,
            charger: charger.map(|c| c.0),
            finishing_request,
            responsive_wait,
            span,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::{parse, parse_files, FleetSpec, SpawnSpec};
    use super::*;
    use mapc_ir::{Diagnostic, FileId};
    use std::path::Path;

    fn fixtures() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/rmf")
    }

    fn fleet_of(config: &str, extra: &str) -> (Option<FleetSpec>, Vec<Diagnostic>) {
        let text = format!("duration: 1h\nfleets:\n  - {{config: {config}{extra}}}\n");
        let p = parse_files(FileId(0), &text, &fixtures());
        (p.scenario.map(|s| s.fleets[0].clone()), p.diagnostics)
    }

    /// A config written into a scratch directory; returns the diagnostics of a scenario
    /// that names it, and the config's text.
    fn broken(dir: &Path, name: &str, config: &str) -> Vec<Diagnostic> {
        std::fs::write(dir.join(name), config).expect("write config");
        let text = format!("duration: 1h\nfleets:\n  - {{config: {name}}}\n");
        let p = parse_files(FileId(0), &text, dir);
        assert!(p.scenario.is_none() || !mapc_ir::has_errors(&p.diagnostics));
        p.diagnostics
    }

    /// Values and keys that deployments' configs have and RMF (or their adapter) reads:
    /// a `recharge_soc` of 0, actions under `task_capabilities.action_categories`, a
    /// `cleaning_system` power sink, RMF's merge and lane settings. Read, no warning.
    #[test]
    fn deployments_keys_and_values_are_read_quietly() {
        let tmp = tempfile::tempdir().expect("scratch dir");
        let dir = tmp.path();
        let config = "rmf_fleet:
  name: scrubbers
  limits: {linear: [0.5, 0.3], angular: [0.6, 1.0]}
  profile: {footprint: 0.5, vicinity: 0.7}
  ambient_system: {power: 20.0}
  tool_system: {power: 30.0}
  cleaning_system: {power: 650.0}
  recharge_threshold: 0.2
  recharge_soc: 0.0
  account_for_battery_drain: True
  strict_lanes: False
  max_merge_waypoint_distance: 0.3
  lift_emergency_levels: {lift_1: L1}
  fleet_state_topic: fleet_states
  debug: False
  task_capabilities: {loop: True, action_categories: [custom_mission_1]}
robots:
  scrubber_1:
    rmf_config:
      start: {map_name: L1, waypoint: null, orientation: null}
      charger: {waypoint: charger_a}
";
        std::fs::write(dir.join("deploy.yaml"), config).expect("write config");
        let text = "duration: 1h\nfleets:\n  - {config: deploy.yaml}\n";
        let p = parse_files(FileId(0), text, dir);
        assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
        let f = p.scenario.expect("scenario").fleets[0].clone();
        // Every power sink drains: 20 + 30 + 650 W.
        assert_eq!(f.robot.nominal_power, 700.0);
        // Charging to 0 % would end at once: never sent to charge for a low battery.
        assert_eq!((f.recharge_threshold, f.recharge_soc), (0.0, 0.0));
        let r = f.rmf.expect("rmf");
        assert_eq!(r.actions, vec!["custom_mission_1".to_string()]);
        // No start waypoint (null): it starts on its charger.
        assert_eq!(f.spawn, SpawnSpec::Waypoints(vec!["charger_a".into()]));
        // Out of RMF's range is still an error.
        let d = broken(
            dir,
            "soc.yaml",
            &config.replace("recharge_soc: 0.0", "recharge_soc: 1.5"),
        );
        assert!(
            d.iter().any(|d| d.code == codes::OUT_OF_RANGE.code),
            "{d:#?}"
        );
    }

    #[test]
    fn todays_generation_maps_onto_the_fleet() {
        let (f, d) = fleet_of("movers_config.yaml", "");
        assert!(d.is_empty(), "{d:#?}");
        let f = f.expect("fleet");
        assert_eq!((f.name.as_str(), f.count), ("movers", 2));
        let p = &f.robot;
        assert_eq!(p.model, "movers");
        assert_eq!(
            (p.nominal_drive_speed, p.max_drive_acceleration),
            (0.8, 0.4)
        );
        assert_eq!(p.nominal_drive_acceleration, 0.4);
        assert_eq!((p.nominal_turn_speed, p.max_turn_acceleration), (0.7, 1.5));
        assert_eq!((p.footprint, p.reversible), (0.35, false));
        assert_eq!(
            (p.nominal_voltage, p.nominal_capacity, p.charging_current),
            (24.0, 30.0, 6.0)
        );
        assert_eq!(
            (p.mass, p.inertia, p.friction_coefficient),
            (50.0, 15.0, 0.2)
        );
        // Ambient and tool power sinks both drain the battery.
        assert_eq!(p.nominal_power, 40.0);
        assert_eq!((f.recharge_threshold, f.recharge_soc), (0.15, 0.9));
        assert_eq!(
            f.task_kinds,
            vec![
                TaskCategory::Loop,
                TaskCategory::Delivery,
                TaskCategory::GoToPlace
            ]
        );
        assert_eq!(
            f.spawn,
            SpawnSpec::Waypoints(vec!["charger_a".into(), "dropoff".into()])
        );
        let r = f.rmf.expect("rmf");
        assert_eq!(r.vicinity, 0.5);
        assert!(r.responsive_wait && r.account_for_battery_drain);
        assert_eq!(r.finishing_request, Finishing::Charge);
        assert_eq!(r.actions, vec!["teleop".to_string()]);
        let names: Vec<&str> = r.robots.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["mover_1", "mover_2"]);
        assert_eq!(
            r.robots[0].finishing_request,
            Some(Finishing::Park(Some("hold_a".into())))
        );
        assert_eq!(r.robots[1].responsive_wait, Some(false));
        // The robot's waypoint is located in the config file (file id 1, line 39).
        assert_eq!(
            (r.robots[0].span.file, r.robots[0].span.line),
            (FileId(1), 38)
        );
    }

    #[test]
    fn the_older_template_reads_top_level_robots() {
        let (f, d) = fleet_of("movers_legacy_config.yaml", "");
        assert!(d.is_empty(), "{d:#?}");
        let f = f.expect("fleet");
        assert_eq!((f.name.as_str(), f.count), ("legacy_movers", 1));
        assert_eq!(f.robot.nominal_drive_speed, 0.6);
        assert_eq!(f.robot.footprint, 0.4);
        // It starts at its start waypoint, not at its charger.
        assert_eq!(f.spawn, SpawnSpec::Waypoints(vec!["hold_a".into()]));
        let r = f.rmf.expect("rmf");
        assert_eq!(r.robots[0].charger.as_deref(), Some("charger_a"));
        // `finishing_request` and `action` inside `task_capabilities`, as that template
        // had them.
        assert_eq!(r.finishing_request, Finishing::Nothing);
        assert_eq!(r.actions, vec!["teleop".to_string()]);
        // Drain not accounted for: never sent to charge on a low battery.
        assert!(!r.account_for_battery_drain);
        assert_eq!(f.recharge_threshold, 0.0);
        assert_eq!(
            f.task_kinds,
            vec![TaskCategory::Loop, TaskCategory::GoToPlace]
        );
    }

    #[test]
    fn the_scenario_overrides_the_config() {
        let (f, d) = fleet_of(
            "movers_config.yaml",
            ", name: m, count: 1, robot: {nominal_drive_speed: 1.1}, recharge_soc: 0.95, tasks: [loop]",
        );
        assert!(d.is_empty(), "{d:#?}");
        let f = f.expect("fleet");
        assert_eq!((f.name.as_str(), f.count), ("m", 1));
        assert_eq!(f.robot.nominal_drive_speed, 1.1);
        // The rest of the robot stays the config's.
        assert_eq!((f.robot.footprint, f.robot.mass), (0.35, 50.0));
        assert_eq!(f.spawn, SpawnSpec::Waypoints(vec!["charger_a".into()]));
        assert_eq!((f.recharge_threshold, f.recharge_soc), (0.15, 0.95));
        assert_eq!(f.task_kinds, vec![TaskCategory::Loop]);
        // More robots than the config lists: placed automatically.
        let (f, _) = fleet_of("movers_config.yaml", ", count: 5");
        assert_eq!(f.expect("fleet").spawn, SpawnSpec::Auto);
    }

    #[test]
    fn broken_configs_are_located_in_the_config() {
        let at = |d: &[Diagnostic]| -> Vec<(&str, u32, u32, u32)> {
            let mut v: Vec<_> = d
                .iter()
                .map(|x| (x.code, x.span.file.0, x.span.line, x.span.col))
                .collect();
            v.sort_by_key(|x| (x.2, x.3));
            v
        };
        let tmp = tempfile::tempdir().expect("scratch dir");
        let dir = tmp.path();
        let d = broken(dir, "no_fleet.yaml", "fleet_manager:\n  ip: 127.0.0.1\n");
        assert_eq!(at(&d), [("S0312", 1, 1, 1)], "{d:#?}");
        let d = broken(
            dir,
            "negative.yaml",
            "rmf_fleet:\n  name: f\n  limits:\n    linear: [-0.5, 0.75]\n  robots:\n    r: {charger: c}\n",
        );
        assert_eq!(at(&d), [("S0106", 1, 4, 14)], "{d:#?}");
        let d = broken(
            dir,
            "types.yaml",
            "rmf_fleet:\n  name: f\n  battery_system: {voltage: twelve}\n  reversible: maybe\n  robots:\n    r: {charger: c}\n",
        );
        assert_eq!(at(&d), [("S0101", 1, 3, 29), ("S0101", 1, 4, 15)], "{d:#?}");
        let d = broken(dir, "no_robots.yaml", "rmf_fleet:\n  name: f\n");
        assert_eq!(at(&d), [("S0312", 1, 2, 3)], "{d:#?}");
        // Unknown keys warn; keys only a deployment uses are silent.
        let d = broken(
            dir,
            "unknown.yaml",
            "rmf_fleet:\n  name: f\n  top_sped: 3\n  publish_fleet_state: 10.0\n  robots:\n    r: {charger: c, colour: red}\nfleet_manager: {ip: x}\n",
        );
        assert_eq!(at(&d), [("S0103", 1, 3, 3), ("S0103", 1, 6, 21)], "{d:#?}");
        assert!(!mapc_ir::has_errors(&d));
        let d = broken(dir, "bad.yaml", "rmf_fleet: [\n");
        assert_eq!(at(&d)[0].0, "S0001");
        // A missing file is said at the scenario's `config:`.
        let text = "duration: 1h\nfleets:\n  - {config: nowhere.yaml}\n";
        let p = parse_files(FileId(0), text, &fixtures());
        assert_eq!(at(&p.diagnostics), [("S0004", 0, 3, 14)]);
        // Through `parse`, a config's problem is put at `config:`, its position in the text.
        let (s, d) = parse(
            FileId(0),
            "duration: 1h\nfleets:\n  - {config: negative.yaml}\n",
            dir,
        );
        assert!(s.is_none());
        assert_eq!(at(&d), [("S0106", 0, 3, 14)]);
        assert!(
            d[0].message.contains("negative.yaml:4:14: "),
            "{}",
            d[0].message
        );
    }

    #[test]
    fn garbage_configs_never_panic() {
        let tmp = tempfile::tempdir().expect("scratch dir");
        let dir = tmp.path();
        for text in [
            "",
            "~",
            "[]",
            "42",
            "rmf_fleet: 3",
            "rmf_fleet: {robots: [a, b]}",
            "rmf_fleet: {name: [x], limits: {linear: [1]}, robots: {r: 3}}",
            "rmf_fleet: {name: f, limits: {linear: [.nan, 1]}, robots: {r: {charger: {}}}}",
            "robots: {r: {rmf_config: {start: 5}}}",
            "rmf_fleet: {name: f, finishing_request: {type: fly}, robots: {r: {charger: c}}}",
        ] {
            let d = broken(dir, "garbage.yaml", text);
            assert!(mapc_ir::has_errors(&d), "{text}: {d:#?}");
            for x in &d {
                assert!(x.span.line > 0, "{text}: {x:?}");
            }
        }
    }
}
