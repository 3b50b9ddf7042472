//! `mapc diff` on fixture pairs (fixtures/diff: a base map and one map per kind of change),
//! every map against itself, the exit codes, the Markdown output (snapshot), and git using
//! it as a diff driver and a difftool.

mod support;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/diff")
}

fn path(name: &str) -> String {
    dir()
        .join(format!("{name}.building.yaml"))
        .display()
        .to_string()
}

/// `mapc diff --format json base NAME`: exit code and the changes as
/// `section | level | change | subject | detail` lines.
fn changes(name: &str) -> (i32, Vec<String>) {
    let r = support::run(
        &["diff", "--format", "json", &path("base"), &path(name)],
        Duration::from_secs(60),
    );
    let v: Value = serde_json::from_slice(&r.stdout).expect("JSON on stdout");
    assert_eq!(v["changed"], r.code == 1);
    let lines = v["changes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            format!(
                "{} | {} | {} | {} | {}",
                c["section"].as_str().unwrap(),
                c["level"].as_str().unwrap_or("-"),
                c["change"].as_str().unwrap(),
                c["subject"].as_str().unwrap(),
                c["detail"].as_str().unwrap()
            )
        })
        .collect();
    (r.code, lines)
}

fn check(name: &str, want: &[&str]) {
    let (code, got) = changes(name);
    assert_eq!(got, want, "{name}");
    assert_eq!(code, 1, "{name}: something changed");
}

#[test]
fn waypoints_added_removed_renamed_moved() {
    check("waypoints", &[
        "waypoints | L1 | added | waypoint `storage` | at (8.00, 5.00)",
        "waypoints | L1 | removed | waypoint `office` | was at (5.00, 5.00)",
        "waypoints | L1 | changed | waypoint `lobby` | moved 0.50 m: (5.00, 2.00) → (5.00, 2.50)",
        "waypoints | L1 | changed | waypoint `lobby` | roles none → holding point",
        "waypoints | L1 | changed | waypoint `pantry` | renamed `pantry` → `kitchen`",
        "lanes | L1 | added | lane `kitchen` – `storage` | graph 0, two-way",
        "lanes | L1 | removed | lane `lobby` – `office` | graph 0, two-way",
    ]);
}

#[test]
fn lanes_direction_speed_graph() {
    check(
        "lanes",
        &[
            "lanes | L1 | added | lane `dock` – `office` | graph 0, two-way",
            "lanes | L1 | changed | lane `dock` – `lobby` | two-way → one-way `dock` → `lobby`",
            "lanes | L1 | changed | lane `lobby` – `office` | graph 0 → 1",
            "lanes | L1 | changed | lane `lobby` – `pantry` | speed limit none → 0.50 m/s",
        ],
    );
}

#[test]
fn doors_and_lifts() {
    check("doors", &[
        "doors | L1 | added | door `store_door` | double_sliding door, 1.50 m wide, at (9.00, 0.75)",
        "doors | L1 | changed | door `office_door` | type hinged → sliding; width 2.00 m → 2.50 m; moved 0.25 m: (5.00, 6.50) → (5.25, 6.50)",
        "diagnostics | - | added | warning[W0306] | no lane crosses door `store_door` on level `L1`, so robots never ask for it to open",
    ]);
    check("lifts", &[
        "lifts | - | added | lift `lift_2` | 1.50 × 1.50 m cabin at (-3.00, 4.00), serving L2",
        "lifts | - | changed | lift `lift_1` | moved 1.00 m: (12.00, 4.00) → (13.00, 4.00); cabin 2.00 × 2.00 m → 2.50 × 2.00 m",
    ]);
}

#[test]
fn walls_floors_and_levels() {
    // (8, 2) to (5, 5): 3√2 = 4.24 m; the L2 floor 10 × 8 → 12 × 8 with a slanted side: 88 m².
    check(
        "walls_floors",
        &[
            "walls | L1 | added | 1 wall | 4.24 m",
            "walls | L1 | removed | 1 wall | 10.00 m",
            "floors | L2 | added | 1 floor polygon | 88.00 m²",
            "floors | L2 | removed | 1 floor polygon | 80.00 m²",
        ],
    );
    check(
        "levels",
        &[
            "levels | - | added | level `L3` | elevation 8.00 m",
            "levels | - | changed | level `L2` | elevation 4.00 m → 5.00 m",
            "waypoints | L3 | added | waypoint `roof` | at (0.00, 0.00)",
        ],
    );
}

#[test]
fn connectivity_and_diagnostics() {
    let (_, got) = changes("connectivity");
    assert!(got.contains(&"connectivity | - | removed | waypoint `pantry` | no longer reachable from the main part of graph 0".to_string()), "{got:#?}");
    assert!(
        got.contains(
            &"lanes | L1 | removed | lane `lobby` – `pantry` | graph 0, two-way".to_string()
        ),
        "{got:#?}"
    );
    let (_, got) = changes("diagnostics");
    assert!(got.contains(&"diagnostics | - | added | error[E0201] | lane of graph 0 starts and ends at vertex `office` (index # of level `L1`)".to_string()), "{got:#?}");
    assert!(got.contains(&"diagnostics | - | removed | warning[W0306] | no lane crosses door `office_door` on level `L1`, so robots never ask for it to open".to_string()), "{got:#?}");
    // The reverse diff swaps added and removed.
    let r = support::run(
        &[
            "diff",
            "--format",
            "json",
            &path("diagnostics"),
            &path("base"),
        ],
        Duration::from_secs(60),
    );
    let v: Value = serde_json::from_slice(&r.stdout).unwrap();
    assert!(v["changes"]
        .as_array()
        .unwrap()
        .iter()
        .any(|c| c["change"] == "removed" && c["subject"] == "error[E0201]"));
}

#[test]
fn every_map_against_itself_is_nothing() {
    for e in std::fs::read_dir(dir()).unwrap() {
        let p = e.unwrap().path().display().to_string();
        for format in ["human", "json", "markdown"] {
            let r = support::run(
                &["diff", "--format", format, &p, &p],
                Duration::from_secs(60),
            );
            assert_eq!(r.code, 0, "{p} {format}");
            match format {
                "human" => assert!(r.stdout.is_empty(), "{p}"),
                "json" => assert_eq!(
                    serde_json::from_slice::<Value>(&r.stdout).unwrap()["changes"],
                    serde_json::json!([])
                ),
                _ => assert!(String::from_utf8_lossy(&r.stdout).contains("No changes by meaning.")),
            }
        }
    }
}

#[test]
fn exit_codes() {
    let r = support::run(
        &["diff", &path("base"), &path("missing")],
        Duration::from_secs(60),
    );
    assert_eq!(r.code, 2);
    assert!(String::from_utf8_lossy(&r.stderr).contains("missing.building.yaml"));
    let tmp = tempfile::tempdir().unwrap();
    let bad = tmp.path().join("bad.building.yaml");
    std::fs::write(&bad, "levels: {L1: [1, 2}\n").unwrap();
    let r = support::run(
        &["diff", &path("base"), bad.to_str().unwrap()],
        Duration::from_secs(60),
    );
    assert_eq!(r.code, 2);
    assert!(
        String::from_utf8_lossy(&r.stderr).contains("could not be read (E0001)"),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
}

#[test]
fn markdown_for_a_pull_request() {
    let r = support::run(
        &[
            "diff",
            "--format",
            "markdown",
            &path("base"),
            &path("waypoints"),
        ],
        Duration::from_secs(60),
    );
    assert_eq!(r.code, 1);
    let text = String::from_utf8(r.stdout)
        .unwrap()
        .replace(&dir().display().to_string(), "fixtures/diff");
    insta::assert_snapshot!("diff_waypoints_markdown", text);
}

fn git(repo: &Path, args: &[&str]) -> std::process::Output {
    Command::new("git")
        .args([
            "-c",
            "user.name=t",
            "-c",
            "user.email=t@example.com",
            "-c",
            "core.pager=cat",
        ])
        .args(args)
        .current_dir(repo)
        .env("GIT_CONFIG_NOSYSTEM", "1")
        .env("HOME", repo)
        .output()
        .expect("git runs")
}

#[test]
fn git_diff_driver_and_difftool() {
    if Command::new("git").arg("--version").output().is_err() {
        println!("skipped: git not found");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let repo = tmp.path();
    let mapc = env!("CARGO_BIN_EXE_mapc");
    assert!(git(repo, &["init", "-q"]).status.success());
    std::fs::copy(path("base"), repo.join("site.building.yaml")).unwrap();
    // The lines docs/editors.md gives.
    std::fs::write(
        repo.join(".gitattributes"),
        "*.building.yaml diff=rmf-map\n",
    )
    .unwrap();
    assert!(git(
        repo,
        &["config", "diff.rmf-map.command", &format!("{mapc} diff")]
    )
    .status
    .success());
    assert!(git(repo, &["add", "."]).status.success());
    assert!(git(repo, &["commit", "-qm", "base"]).status.success());
    std::fs::copy(path("lanes"), repo.join("site.building.yaml")).unwrap();
    let out = git(repo, &["diff", "--ext-diff"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.starts_with(
            "a/site.building.yaml → b/site.building.yaml: 1 added, 0 removed, 3 changed"
        ),
        "{text}"
    );
    assert!(
        text.contains("~ lane `lobby` – `pantry`: speed limit none → 0.50 m/s"),
        "{text}"
    );
    // As a difftool: `git difftool -x 'mapc diff'` runs it with LOCAL REMOTE.
    // (Without the driver's command, which git would prefer to the tool.)
    assert!(git(repo, &["config", "--unset", "diff.rmf-map.command"])
        .status
        .success());
    let tool = format!("{mapc} diff --format markdown");
    let out = git(
        repo,
        &["difftool", "-y", "-x", &tool, "--", "site.building.yaml"],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("| ✏️ | lane `dock` – `lobby` | two-way → one-way `dock` → `lobby` |"),
        "{text} {}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A new map (old side /dev/null).
    assert!(git(
        repo,
        &["config", "diff.rmf-map.command", &format!("{mapc} diff")]
    )
    .status
    .success());
    std::fs::copy(path("base"), repo.join("new.building.yaml")).unwrap();
    assert!(git(repo, &["add", "-N", "new.building.yaml"])
        .status
        .success());
    let out = git(repo, &["diff", "--ext-diff", "--", "new.building.yaml"]);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "b/new.building.yaml: new map\n"
    );
}

#[test]
fn renumbered_vertices_are_no_change() {
    // Every index of L1 differs, the text diff is most of the level; the map is the same.
    let r = support::run(
        &["diff", &path("base"), &path("reordered")],
        Duration::from_secs(60),
    );
    assert_eq!(
        (r.code, r.stdout.len()),
        (0, 0),
        "{}",
        String::from_utf8_lossy(&r.stdout)
    );
}
