//! CLI behaviour around diagnostics: --deny-warnings, SARIF, several inputs, exit codes.

mod support;
use std::path::Path;
use support::mapc;

const WARN_ONLY: &str = "fixtures/invalid/W0213-demo-mock-lift-without-floor.building.yaml";
const ERROR: &str = "fixtures/invalid/E0201-lane-self-loop.building.yaml";
const CLEAN: &str = "fixtures/two_level_clinic.building.yaml";

#[test]
fn warnings_pass_unless_denied() {
    assert_eq!(mapc(&["check", WARN_ONLY]).0, 0);
    assert_eq!(mapc(&["check", "--deny-warnings", WARN_ONLY]).0, 1);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    assert_eq!(mapc(&["nav", WARN_ONLY, out]).0, 0);
    assert!(Path::new(out).join("0.yaml").exists());
    let dir2 = tempfile::tempdir().unwrap();
    let out2 = dir2.path().join("nav");
    let (code, _, err) = mapc(&["nav", "--deny-warnings", WARN_ONLY, out2.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(
        !out2.exists(),
        "nothing may be written when warnings are denied"
    );
}

#[test]
fn several_inputs_report_the_worst_exit_code() {
    assert_eq!(mapc(&["check", CLEAN, WARN_ONLY]).0, 0);
    assert_eq!(mapc(&["check", CLEAN, ERROR, WARN_ONLY]).0, 1);
    assert_eq!(mapc(&["check", CLEAN, "does/not/exist.building.yaml"]).0, 2);
    // Usage errors are exit 2 too.
    assert_eq!(mapc(&["check"]).0, 2);
    assert_eq!(mapc(&["check", "--format", "xml", CLEAN]).0, 2);
}

#[test]
fn sarif_log_is_valid_and_complete() {
    let (code, out, _) = mapc(&["check", "--format", "sarif", ERROR, WARN_ONLY]);
    assert_eq!(code, 1);
    let log: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(log["version"], "2.1.0");
    let run = &log["runs"][0];
    assert_eq!(run["tool"]["driver"]["name"], "mapc");
    let results = run["results"].as_array().unwrap();
    let ids: Vec<&str> = results
        .iter()
        .map(|r| r["ruleId"].as_str().unwrap())
        .collect();
    assert!(ids.contains(&"E0201") && ids.contains(&"W0213"), "{ids:?}");
    for r in results {
        let loc = &r["locations"][0]["physicalLocation"];
        assert!(loc["artifactLocation"]["uri"]
            .as_str()
            .unwrap()
            .starts_with("fixtures/invalid/"));
        assert!(loc["region"]["startLine"].as_u64().unwrap() >= 1);
        assert!(["error", "warning"].contains(&r["level"].as_str().unwrap()));
    }
    let rules = run["tool"]["driver"]["rules"].as_array().unwrap();
    assert!(rules
        .iter()
        .any(|r| r["id"] == "E0201" && r["name"] == "lane-self-loop"));
}

#[test]
fn json_lines_have_the_documented_fields() {
    let (code, out, _) = mapc(&["check", "--format", "json", ERROR]);
    assert_eq!(code, 1);
    let d: serde_json::Value = serde_json::from_str(out.lines().next().unwrap()).unwrap();
    for key in [
        "severity", "code", "name", "message", "location", "labels", "help",
    ] {
        assert!(d.get(key).is_some(), "missing {key}: {d}");
    }
    for key in [
        "file",
        "line",
        "column",
        "end_line",
        "end_column",
        "byte_start",
        "byte_end",
    ] {
        assert!(
            d["location"].get(key).is_some(),
            "missing location.{key}: {d}"
        );
    }
}
