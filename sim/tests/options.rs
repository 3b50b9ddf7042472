//! The toggle_charging switches as scenario options: `battery_drain: false` keeps every
//! battery full, the default drains it (runtime spec §1.9).

use mapc_sim::{parse_scenario, simulate, RunOptions};
use std::path::Path;

fn min_battery(drain: bool) -> f64 {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let text = std::fs::read_to_string(dir.join("two_level_clinic.scenario.yaml")).unwrap();
    let (scenario, diags) = parse_scenario(mapc_ir::FileId(0), &text, &dir);
    let mut scenario = scenario.unwrap_or_else(|| panic!("{diags:?}"));
    scenario.options.battery_drain = drain;
    let map = mapc_frontend::load(&dir.join("two_level_clinic.building.yaml")).unwrap();
    let building = map.valid_building().expect("valid fixture");
    let mut trace = Vec::new();
    simulate(
        building,
        &scenario,
        RunOptions {
            until: Some(600.0),
            trace: Some(&mut trace),
            progress: None,
            ..Default::default()
        },
    )
    .expect("runs");
    let mut min = f64::INFINITY;
    for line in String::from_utf8(trace).unwrap().lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        if v["topic"] == "/robot_state" {
            min = min.min(v["msg"]["battery_percent"].as_f64().unwrap());
        }
    }
    assert!(min.is_finite(), "no RobotState in the trace");
    min
}

#[test]
fn battery_drain_switch() {
    assert_eq!(min_battery(false), 100.0);
    // TinyRobot: 20 W on board alone is 20/12/(24·3600) ≈ 1.9e-5 per s, 1.2 % in 600 s,
    // so the reported (ceiled) percentage must have dropped below 100.
    assert!(min_battery(true) <= 99.0);
}
