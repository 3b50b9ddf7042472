//! Robot parameters: the slotcar plugin's SDF parameters (runtime spec §1.1) plus what a
//! fleet adapter configures (footprint). Presets are the rmf_demos robot models.

use std::f64::consts::PI;

#[derive(Debug, Clone, PartialEq)]
pub struct RobotParams {
    /// Name of the robot type (`TinyRobot`, or the scenario's own name).
    pub model: String,
    pub nominal_drive_speed: f64,
    pub nominal_drive_acceleration: f64,
    pub max_drive_acceleration: f64,
    pub nominal_turn_speed: f64,
    pub nominal_turn_acceleration: f64,
    pub max_turn_acceleration: f64,
    pub stop_distance: f64,
    pub stop_radius: f64,
    pub reversible: bool,
    pub nominal_voltage: f64,
    pub nominal_capacity: f64,
    pub charging_current: f64,
    pub mass: f64,
    pub inertia: f64,
    pub friction_coefficient: f64,
    pub nominal_power: f64,
    /// Radius of the robot's footprint (m), as in a fleet adapter's config: two robots are
    /// in contact when their centres are closer than the sum of their footprints.
    pub footprint: f64,
}

impl Default for RobotParams {
    /// The slotcar plugin's defaults (§1.1); footprint 0.3 m as in rmf_demos configs.
    fn default() -> Self {
        RobotParams {
            model: "slotcar".into(),
            nominal_drive_speed: 0.5,
            nominal_drive_acceleration: 0.05,
            max_drive_acceleration: 0.1,
            nominal_turn_speed: PI / 8.0,
            nominal_turn_acceleration: PI / 10.0,
            max_turn_acceleration: PI,
            stop_distance: 1.0,
            stop_radius: 1.0,
            reversible: true,
            nominal_voltage: 12.0,
            nominal_capacity: 24.0,
            charging_current: 2.0,
            mass: 20.0,
            inertia: 10.0,
            friction_coefficient: 0.3,
            nominal_power: 10.0,
            footprint: 0.3,
        }
    }
}

/// (name, v_nom, a_nom, a_max, w_nom, α_nom, α_max, stop, reversible, V, Ah, I_chg, m, I, μ, P,
/// footprint) from the rmf_demos models (runtime spec §1.1 table).
type Row = (&'static str, [f64; 6], f64, bool, [f64; 7], f64);
const PRESETS: &[Row] = &[
    (
        "TinyRobot",
        [0.5, 0.25, 0.75, 0.6, 1.5, 2.0],
        0.75,
        true,
        [12.0, 24.0, 5.0, 20.0, 10.0, 0.22, 20.0],
        0.3,
    ),
    (
        "DeliveryRobot",
        [0.7, 0.5, 0.75, 0.6, 1.5, 2.0],
        0.75,
        true,
        [24.0, 40.0, 8.8, 70.0, 40.0, 0.22, 20.0],
        0.4,
    ),
    (
        "CleanerBotA",
        [0.7, 0.5, 0.6, 0.4, 1.0, 1.2],
        1.5,
        false,
        [24.0, 20.0, 10.0, 70.0, 40.0, 0.22, 100.0],
        0.4,
    ),
    (
        "HospitalRobot",
        [0.7, 0.5, 0.75, 0.3, 1.5, 2.0],
        0.75,
        false,
        [24.0, 24.0, 5.0, 70.0, 40.0, 0.22, 20.0],
        0.4,
    ),
];

impl RobotParams {
    /// Names accepted by [`RobotParams::preset`].
    pub fn preset_names() -> impl Iterator<Item = &'static str> {
        PRESETS.iter().map(|r| r.0)
    }

    /// A robot type of rmf_demos by name (`TinyRobot`, `DeliveryRobot`, `CleanerBotA`,
    /// `HospitalRobot`; an `Open-RMF/` prefix, as in spawn waypoints, is accepted).
    pub fn preset(name: &str) -> Option<RobotParams> {
        let short = name.rsplit('/').next().unwrap_or(name);
        let (n, [v, a, amax, w, al, almax], stop, rev, [volt, ah, ichg, m, i, mu, p], fp) =
            *PRESETS.iter().find(|r| r.0.eq_ignore_ascii_case(short))?;
        Some(RobotParams {
            model: n.to_string(),
            nominal_drive_speed: v,
            nominal_drive_acceleration: a,
            max_drive_acceleration: amax,
            nominal_turn_speed: w,
            nominal_turn_acceleration: al,
            max_turn_acceleration: almax,
            stop_distance: stop,
            stop_radius: stop,
            reversible: rev,
            nominal_voltage: volt,
            nominal_capacity: ah,
            charging_current: ichg,
            mass: m,
            inertia: i,
            friction_coefficient: mu,
            nominal_power: p,
            footprint: fp,
        })
    }
}
