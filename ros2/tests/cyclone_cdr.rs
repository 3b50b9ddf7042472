//! CDR bytes of every message type against Eclipse Cyclone DDS (its Python package): for the
//! same values, Cyclone's serialiser must produce mapc's bytes, mapc must decode Cyclone's
//! bytes to those values, and Cyclone must decode mapc's bytes to them too. Needs the venv
//! that .ci/run makes (`target/ros2-venv`, or `MAPC_ROS2_PYTHON`); prints `skipped: ...`
//! without it.

use mapc_ros2::cdr;
use mapc_ros2::msgs::{self, *};
use mapc_sim::msgs::{ItemType, WorkcellRequest, WorkcellResult, WorkcellState};
use serde::{de::DeserializeOwned, Serialize};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::Command;

fn python() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("MAPC_ROS2_PYTHON") {
        return Some(p.into());
    }
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/ros2-venv/bin/python");
    let ok = Command::new(&p)
        .args(["-c", "import cyclonedds.idl"])
        .output()
        .is_ok_and(|o| o.status.success());
    ok.then_some(p)
}

/// Deterministic, varied values for a field type: odd string lengths and 1-, 2-, 4- and
/// 8-byte fields in a row exercise CDR's alignment; sequences of 0 to 3 elements.
struct Gen(u32);

impl Gen {
    fn next(&mut self) -> u32 {
        self.0 = self.0.wrapping_mul(1_103_515_245).wrapping_add(12_345);
        (self.0 >> 8) & 0xffff
    }

    fn scalar(&mut self, ty: &str) -> Value {
        let n = self.next();
        match ty {
            "bool" => json!(n % 2 == 1),
            "uint8" => json!(n % 256),
            "int8" => json!((n % 256) as i64 - 128),
            "int32" => json!(n as i64 - 40_000),
            "uint32" => json!(n * 7),
            "uint64" => json!(u64::from(n) << 33 | 5),
            // Exactly representable in f32, so both sides start from the same number.
            "float32" => json!((n as f64 - 30_000.0) / 64.0),
            "float64" => json!((n as f64 - 30_000.0) / 1024.0 + f64::from(n) * 1e-9),
            "string" => {
                let words = [
                    "",
                    "a",
                    "L1",
                    "door_3",
                    "tinyRobot1",
                    "ward_ä",
                    "lift_1 cabin",
                ];
                json!(words[n as usize % words.len()])
            }
            other => panic!("no generator for {other}"),
        }
    }

    fn value(&mut self, name: &str) -> Value {
        let def = msgs::definition(name).expect("defined");
        let mut obj = serde_json::Map::new();
        for line in def.lines() {
            let (ty, field) = line.split_once(' ').expect("type and name");
            let (base, seq) = match ty.strip_suffix("[]") {
                Some(b) => (b, true),
                None => (ty, false),
            };
            let one = |g: &mut Gen| match base.split_once('/') {
                Some((pkg, n)) => g.value(&format!("{pkg}/msg/{n}")),
                None => g.scalar(base),
            };
            let v = if seq {
                let len = self.next() % 4;
                Value::Array((0..len).map(|_| one(self)).collect())
            } else {
                one(self)
            };
            obj.insert(field.to_string(), v);
        }
        Value::Object(obj)
    }
}

/// Decodes Cyclone's bytes as the case's type and compares with its value.
type Check = Box<dyn Fn(&[u8]) -> Result<(), String>>;

/// One sample per type: its value, mapc's bytes, and a check of Cyclone's answer.
struct Case {
    name: &'static str,
    value: Value,
    mapc: Vec<u8>,
    check: Check,
}

fn case<T: RosMsg + std::fmt::Debug + PartialEq + 'static>(gen: &mut Gen) -> Case {
    case_as::<T>(T::NAME, gen)
}

/// A case of ROS type `name`, sent as `T` (where one runtime type stands for several ROS
/// types of the same fields: Time for Duration, a workcell's messages for a dispenser's and
/// an ingestor's).
fn case_as<T>(name: &'static str, gen: &mut Gen) -> Case
where
    T: Serialize + DeserializeOwned + std::fmt::Debug + PartialEq + 'static,
{
    let value: T = serde_json::from_value(gen.value(name)).expect("sample fits the type");
    let mapc = cdr::encode(&value);
    let json = serde_json::to_value(&value).expect("json");
    Case {
        name,
        value: json,
        mapc,
        check: Box::new(move |cyclone: &[u8]| {
            let back: T = cdr::decode(cyclone)?;
            if back == value {
                Ok(())
            } else {
                Err(format!("decoded {back:?}\n  expected {value:?}"))
            }
        }),
    }
}

fn cases() -> Vec<Case> {
    let mut g = Gen(7);
    let g = &mut g;
    vec![
        case::<builtin_interfaces::Time>(g),
        case_as::<builtin_interfaces::Time>("builtin_interfaces/msg/Duration", g),
        case::<std_msgs::String>(g),
        case::<std_msgs::Header>(g),
        case_as::<geometry_msgs::Vector3>("geometry_msgs/msg/Point", g),
        case::<geometry_msgs::Vector3>(g),
        case::<geometry_msgs::Quaternion>(g),
        case::<geometry_msgs::Pose>(g),
        case::<rmf_obstacle_msgs::BoundingBox3D>(g),
        case::<rmf_obstacle_msgs::Obstacle>(g),
        case::<rmf_obstacle_msgs::Obstacles>(g),
        case::<rosgraph_msgs::Clock>(g),
        case::<rmf_fleet_msgs::Location>(g),
        case::<rmf_fleet_msgs::RobotMode>(g),
        case::<rmf_fleet_msgs::RobotState>(g),
        case::<rmf_fleet_msgs::FleetState>(g),
        case::<rmf_fleet_msgs::PathRequest>(g),
        case::<rmf_fleet_msgs::ModeParameter>(g),
        case::<rmf_fleet_msgs::ModeRequest>(g),
        case::<rmf_fleet_msgs::PauseRequest>(g),
        case::<rmf_door_msgs::DoorMode>(g),
        case::<rmf_door_msgs::DoorRequest>(g),
        case::<rmf_door_msgs::DoorState>(g),
        case::<rmf_door_msgs::Session>(g),
        case::<rmf_door_msgs::DoorSessions>(g),
        case::<rmf_door_msgs::SupervisorHeartbeat>(g),
        case::<rmf_lift_msgs::LiftRequest>(g),
        case::<rmf_lift_msgs::LiftState>(g),
        case_as::<ItemType>("rmf_dispenser_msgs/msg/DispenserRequestItem", g),
        case_as::<WorkcellRequest>("rmf_dispenser_msgs/msg/DispenserRequest", g),
        case_as::<WorkcellResult>("rmf_dispenser_msgs/msg/DispenserResult", g),
        case_as::<WorkcellState>("rmf_dispenser_msgs/msg/DispenserState", g),
        case_as::<ItemType>("rmf_ingestor_msgs/msg/IngestorRequestItem", g),
        case_as::<WorkcellRequest>("rmf_ingestor_msgs/msg/IngestorRequest", g),
        case_as::<WorkcellResult>("rmf_ingestor_msgs/msg/IngestorResult", g),
        case_as::<WorkcellState>("rmf_ingestor_msgs/msg/IngestorState", g),
        case::<rmf_building_map_msgs::Param>(g),
        case::<rmf_building_map_msgs::GraphNode>(g),
        case::<rmf_building_map_msgs::GraphEdge>(g),
        case::<rmf_building_map_msgs::Graph>(g),
        case::<rmf_building_map_msgs::AffineImage>(g),
        case::<rmf_building_map_msgs::Place>(g),
        case::<rmf_building_map_msgs::Door>(g),
        case::<rmf_building_map_msgs::Level>(g),
        case::<rmf_building_map_msgs::Lift>(g),
        case::<rmf_building_map_msgs::BuildingMap>(g),
    ]
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

fn unhex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("hex"))
        .collect()
}

#[test]
fn every_type_is_tested() {
    let tested: Vec<&str> = cases().iter().map(|c| c.name).collect();
    for (name, _) in msgs::definitions() {
        assert!(tested.contains(name), "{name} has no CDR case");
    }
}

#[test]
fn cdr_bytes_match_cyclone_dds() {
    let Some(py) = python() else {
        println!("skipped: cyclonedds (Python) not found; .ci/run makes target/ros2-venv");
        return;
    };
    let cases = cases();
    let defs: serde_json::Map<String, Value> = msgs::definitions()
        .iter()
        .map(|(n, d)| (n.to_string(), json!(d)))
        .collect();
    let samples: Vec<Value> = cases
        .iter()
        .map(|c| json!({"name": c.name, "value": c.value, "mapc": hex(&c.mapc)}))
        .collect();
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("input.json");
    std::fs::write(
        &input,
        json!({"definitions": defs, "samples": samples}).to_string(),
    )
    .expect("write");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python/cdr_check.py");
    let out = Command::new(&py)
        .arg(&script)
        .arg(&input)
        .output()
        .expect("python runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let answers: Value = serde_json::from_slice(&out.stdout).expect("json answer");
    let mut failures = Vec::new();
    for c in &cases {
        let a = &answers[c.name];
        if let Some(e) = a["error"].as_str() {
            failures.push(format!("{}: Cyclone: {e}", c.name));
            continue;
        }
        let cyclone = unhex(a["cyclone"].as_str().expect("bytes"));
        if cyclone != c.mapc {
            failures.push(format!(
                "{}: bytes differ\n  mapc    {}\n  cyclone {}",
                c.name,
                hex(&c.mapc),
                hex(&cyclone)
            ));
        }
        if let Err(e) = (c.check)(&cyclone) {
            failures.push(format!("{}: mapc decoding Cyclone's bytes: {e}", c.name));
        }
        if a["decoded"] != c.value {
            failures.push(format!(
                "{}: Cyclone decoding mapc's bytes: {} != {}",
                c.name, a["decoded"], c.value
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    println!(
        "{} message types: same CDR bytes as Cyclone DDS",
        cases.len()
    );
}
