//! `mapc sweep` on the local executor and the Kubernetes manifest (the Slurm executor is in
//! tests/sweep_slurm.rs): rows equal plain `mapc sim` runs of the variants, reruns redo
//! only what changed, results do not depend on the number of cores, bad axes are reported
//! at their place before anything runs, and capacity.svg draws the runs' throughput.

mod support;

use saphyr::{LoadableYamlNode, YamlOwned};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const SWEEP: &str = "fixtures/sweep/clinic.sweep.yaml";

fn mapc_in(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn sweep(out: &Path, extra: &[&str]) -> (i32, String, String) {
    let o = out.to_str().unwrap();
    let mut args = vec!["sweep", SWEEP, "-o", o];
    args.extend(extra);
    support::mapc(&args)
}

/// results.csv as (header, rows).
fn csv(out: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let mut lines = text
        .lines()
        .map(|l| l.split(',').map(String::from).collect());
    (lines.next().unwrap(), lines.collect())
}

fn col(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap()
}

fn mtime(p: &Path) -> std::time::SystemTime {
    std::fs::metadata(p).unwrap().modified().unwrap()
}

#[test]
fn rows_equal_plain_sim_runs_and_reruns_redo_only_what_changed() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let (code, stdout, stderr) = sweep(&out, &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("6 runs, 6 to run, 0 up to date"),
        "{stderr}"
    );
    assert!(stdout.starts_with("6 of 6 runs done"), "{stdout}");

    let (header, rows) = csv(&out);
    assert_eq!(
        header[..4],
        ["run", "fleets.tinyRobot.count", "seed", "robots"].map(String::from)
    );
    assert_eq!(rows.len(), 6);
    // Run order: the last axis varies fastest.
    let axes: Vec<(&str, &str, &str)> = rows
        .iter()
        .map(|r| (r[0].as_str(), r[1].as_str(), r[2].as_str()))
        .collect();
    assert_eq!(
        axes,
        [
            ("0000", "1", "1"),
            ("0001", "1", "2"),
            ("0002", "2", "1"),
            ("0003", "2", "2"),
            ("0004", "3", "1"),
            ("0005", "3", "2")
        ]
    );
    for row in &rows {
        let run = &row[0];
        let dir = out.join("runs").join(run);
        // The variant is a scenario `mapc sim` runs as it is, to the same report.
        let mine = tmp.path().join(format!("{run}.json"));
        let (code, _, err) = support::mapc(&[
            "sim",
            dir.join("scenario.yaml").to_str().unwrap(),
            "--report",
            mine.to_str().unwrap(),
            "-q",
        ]);
        assert_eq!(code, 0, "{err}");
        let plain = std::fs::read(&mine).unwrap();
        assert_eq!(
            plain,
            std::fs::read(dir.join("report.json")).unwrap(),
            "run {run}"
        );
        // The row holds that report's numbers.
        let report: Value = serde_json::from_slice(&plain).unwrap();
        let fleets = report["fleets"].as_array().unwrap();
        let sum = |k: &str| fleets.iter().map(|f| f[k].as_f64().unwrap()).sum::<f64>();
        let num = |k: &str| row[col(&header, k)].parse::<f64>().unwrap();
        assert_eq!(num("robots"), row[1].parse::<f64>().unwrap());
        // The fleets' sizes: robots on the floor and those auto spawn kept in reserve.
        assert_eq!(
            num("robots"),
            report["robots"].as_array().unwrap().len() as f64 + num("reserve")
        );
        // Absent from a fleet's report when none.
        let reserve: f64 = fleets.iter().filter_map(|f| f["reserve"].as_f64()).sum();
        assert_eq!(num("reserve"), reserve);
        assert_eq!(num("tasks_completed"), sum("tasks_completed"));
        assert_eq!(num("throughput_per_hour"), sum("throughput_per_hour"));
        assert_eq!(
            num("wait_lift_s"),
            report["waits"]["lift_s"].as_f64().unwrap()
        );
        assert_eq!(
            row[col(&header, "bottleneck")],
            report["bottleneck"]["place"].as_str().unwrap_or("")
        );
        let bound = &report["throughput"];
        assert_eq!(
            num("bound_per_hour"),
            bound["tasks_per_hour"].as_f64().unwrap()
        );
        assert_eq!(num("bound_share"), bound["share"].as_f64().unwrap());
        assert_eq!(
            row[col(&header, "bound_limited_by")],
            bound["limited_by"].as_str().unwrap()
        );
        let scenario = std::fs::read_to_string(dir.join("scenario.yaml")).unwrap();
        assert!(
            scenario.contains(&format!("    count: {}\n", row[1])),
            "{scenario}"
        );
        assert!(
            scenario.contains(&format!("\nseed: {}\n", row[2])),
            "{scenario}"
        );
        assert!(scenario.contains("\nduration: 4min\n"), "{scenario}");
    }
    // Throughput is completed tasks per simulated hour: 4 minutes are 1/15 h.
    let tp = col(&header, "throughput_per_hour");
    let completed = col(&header, "tasks_completed");
    for r in &rows {
        let c: f64 = r[completed].parse().unwrap();
        assert!(c >= 1.0, "the delivery was not done: {r:?}");
        assert!((r[tp].parse::<f64>().unwrap() - c * 15.0).abs() < 1e-6);
    }

    // A rerun changes nothing.
    let csv1 = std::fs::read(out.join("results.csv")).unwrap();
    let json1 = std::fs::read(out.join("results.json")).unwrap();
    let kept = out.join("runs/0000/report.json");
    let before = mtime(&kept);
    let (code, _, stderr) = sweep(&out, &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("6 runs, 0 to run, 6 up to date"),
        "{stderr}"
    );
    // Deleting one run's directory redoes that run only.
    std::fs::remove_dir_all(out.join("runs/0003")).unwrap();
    let (code, _, stderr) = sweep(&out, &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("6 runs, 1 to run, 5 up to date"),
        "{stderr}"
    );
    assert_eq!(mtime(&kept), before, "run 0000 was redone");
    assert!(out.join("runs/0003/report.json").is_file());
    assert_eq!(std::fs::read(out.join("results.csv")).unwrap(), csv1);
    assert_eq!(std::fs::read(out.join("results.json")).unwrap(), json1);
    // A changed input (here the stamp of another version) redoes that run.
    std::fs::write(out.join("runs/0005/inputs.sha256"), "0\n").unwrap();
    let (_, _, stderr) = sweep(&out, &[]);
    assert!(
        stderr.contains("6 runs, 1 to run, 5 up to date"),
        "{stderr}"
    );

    // One core or all: the same bytes.
    let out1 = tmp.path().join("one_core");
    let (code, _, stderr) = sweep(&out1, &["--jobs", "1"]);
    assert_eq!(code, 0, "{stderr}");
    for f in ["results.csv", "results.json", "capacity.svg", "plan.json"] {
        assert_eq!(
            std::fs::read(out.join(f)).unwrap(),
            std::fs::read(out1.join(f)).unwrap(),
            "{f}"
        );
    }
    for r in &rows {
        for f in ["report.json", "scenario.yaml", "inputs.sha256"] {
            let p = PathBuf::from("runs").join(&r[0]).join(f);
            assert_eq!(
                std::fs::read(out.join(&p)).unwrap(),
                std::fs::read(out1.join(&p)).unwrap(),
                "{}",
                p.display()
            );
        }
    }

    // results.json: the same rows, typed.
    let json: Value = serde_json::from_slice(&json1).unwrap();
    let runs = json.as_array().unwrap();
    assert_eq!(runs.len(), 6);
    assert_eq!(runs[4]["fleets.tinyRobot.count"], 3);
    assert_eq!(runs[4]["seed"], 1);
    assert_eq!(runs[4]["status"], "done");
    assert_eq!(runs[4]["robots"], 3);
}

#[test]
fn bad_axes_are_reported_at_their_place_before_anything_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let (code, _, stderr) = support::mapc(&[
        "sweep",
        "fixtures/sweep/bad.sweep.yaml",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(!out.exists(), "something was written");
    let file = "fixtures/sweep/bad.sweep.yaml";
    for (code, line, col, what) in [
        ("S0402", 6, 3, "`fleets` has no item `tinyRobots`"),
        ("S0402", 7, 3, "unknown key `cont`"),
        ("S0403", 8, 13, "`seed` must be an integer"),
        (
            "S0403",
            9,
            16,
            "`step: 1`: `step` of 1 s is larger than 0.1 s",
        ),
        ("S0405", 12, 3, "has 2 value(s), but"),
    ] {
        let at = format!("{file}:{line}:{col}");
        let head = stderr
            .split("error[")
            .find(|d| d.starts_with(code) && d.contains(&at))
            .unwrap_or_else(|| panic!("no {code} at {at}:\n{stderr}"));
        assert!(
            head.contains(what),
            "{code} at {at} does not say {what:?}:\n{head}"
        );
    }
    assert!(stderr.contains("did you mean `tinyRobot`?"), "{stderr}");
    assert!(stderr.contains("did you mean `count`?"), "{stderr}");
    assert!(stderr.contains("5 error(s), nothing run"), "{stderr}");
}

#[test]
fn a_scenario_that_does_not_fit_the_map_is_reported_before_anything_runs() {
    // spawn_points: the clinic has one tinyRobot spawn, so two robots cannot be placed.
    let tmp = tempfile::tempdir().unwrap();
    let sweep = tmp.path().join("s.sweep.yaml");
    let scenario =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/two_level_clinic.scenario.yaml");
    std::fs::write(
        &sweep,
        format!(
            "scenario: {}\nset: {{duration: 1min}}\nruns:\n  fleets.tinyRobot.count: [1, 2]\n",
            scenario.display()
        ),
    )
    .unwrap();
    let out = tmp.path().join("out");
    let (code, _, stderr) = mapc_in(
        tmp.path(),
        &["sweep", "s.sweep.yaml", "-o", out.to_str().unwrap()],
    );
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("error[S0202]"), "{stderr}");
    assert!(
        stderr.contains("(run 0001: fleets.tinyRobot.count=2)"),
        "{stderr}"
    );
    assert!(!out.exists());
}

/// Pixels of `png` within 8 of `rgb`.
fn count_colour(png_bytes: &[u8], rgb: [u8; 3]) -> usize {
    let mut d = png::Decoder::new(std::io::Cursor::new(png_bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; d.output_buffer_size().unwrap()];
    let info = d.next_frame(&mut buf).unwrap();
    let step = match info.color_type {
        png::ColorType::Rgba => 4,
        png::ColorType::Rgb => 3,
        other => panic!("unexpected colour type {other:?}"),
    };
    buf[..info.buffer_size()]
        .chunks(step)
        .filter(|p| (0..3).all(|i| (p[i] as i32 - rgb[i] as i32).abs() <= 8))
        .count()
}

#[test]
fn capacity_svg_draws_the_mean_over_seeds_against_robots() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let (code, stdout, stderr) = sweep(&out, &[]);
    assert_eq!(code, 0, "{stderr}");
    let (header, rows) = csv(&out);
    let tp = col(&header, "throughput_per_hour");
    // Mean over the two seeds per robot count, from the table.
    let mut means = Vec::new();
    for n in ["1", "2", "3"] {
        let ys: Vec<f64> = rows
            .iter()
            .filter(|r| r[1] == n)
            .map(|r| r[tp].parse().unwrap())
            .collect();
        assert_eq!(ys.len(), 2);
        means.push(ys.iter().sum::<f64>() / 2.0);
    }
    let svg = std::fs::read_to_string(out.join("capacity.svg")).unwrap();
    // Well-formed XML, one line with a point per robot count.
    let mut reader = quick_xml::Reader::from_str(&svg);
    let mut polylines = Vec::new();
    let mut titles = Vec::new();
    let mut in_title = false;
    loop {
        match reader.read_event().unwrap() {
            quick_xml::events::Event::Eof => break,
            quick_xml::events::Event::Start(e) | quick_xml::events::Event::Empty(e) => {
                if e.name().as_ref() == b"polyline" {
                    let attr = |k: &str| {
                        e.try_get_attribute(k)
                            .unwrap()
                            .unwrap()
                            .unescape_value()
                            .unwrap()
                            .into_owned()
                    };
                    polylines.push((attr("class"), attr("points")));
                }
                in_title = e.name().as_ref() == b"title";
            }
            quick_xml::events::Event::Text(t) if in_title => {
                titles.push(t.decode().unwrap().into_owned());
                in_title = false;
            }
            _ => {}
        }
    }
    // The mean line, and the dashed throughput bound above it.
    assert_eq!(polylines.len(), 2, "{svg}");
    let points = |class: &str| -> Vec<(f64, f64)> {
        let (_, pts) = polylines.iter().find(|(c, _)| c == class).unwrap();
        pts.split(' ')
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect()
    };
    let pts = points("mean");
    let bound = points("bound");
    assert_eq!(bound.len(), 3);
    for (b, m) in bound.iter().zip(&pts) {
        assert_eq!(b.0, m.0);
        assert!(
            b.1 <= m.1,
            "the bound is drawn below the throughput: {bound:?} {pts:?}"
        );
    }
    assert_eq!(pts.len(), 3);
    assert!(pts[0].0 < pts[1].0 && pts[1].0 < pts[2].0, "{pts:?}");
    // Equal x steps for 1, 2, 3 robots.
    assert!(((pts[1].0 - pts[0].0) - (pts[2].0 - pts[1].0)).abs() < 0.2);
    for (k, m) in means.iter().enumerate() {
        let want = format!("{} robots: {m:.2} tasks/h", k + 1);
        assert!(
            titles.iter().any(|t| t.starts_with(&want)),
            "{want} not in {titles:?}"
        );
    }
    // Higher throughput is drawn higher.
    for a in 0..3 {
        for b in 0..3 {
            if means[a] > means[b] {
                assert!(pts[a].1 < pts[b].1);
            }
        }
    }
    assert!(stdout.contains("robots"), "{stdout}");

    // Chromium draws it: the line's colour is on the screenshot.
    let Some(chromium) = ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|n| {
            std::env::split_paths(&std::env::var_os("PATH")?)
                .map(|d| d.join(n))
                .find(|f| f.is_file())
        })
    else {
        println!("skipped: chromium not found");
        return;
    };
    let shot = tmp.path().join("capacity.png");
    let res = Command::new(&chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--no-first-run",
            "--window-size=940,520",
        ])
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", out.join("capacity.svg").display()))
        .output()
        .unwrap();
    assert!(shot.exists(), "{}", String::from_utf8_lossy(&res.stderr));
    let png = std::fs::read(&shot).unwrap();
    assert!(
        count_colour(&png, [0x1f, 0x77, 0xb4]) > 300,
        "no line drawn"
    );
}

fn kubernetes_validate() -> Option<PathBuf> {
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ci-venv/bin/kubernetes-validate");
    if venv.is_file() {
        return Some(venv);
    }
    std::env::split_paths(&std::env::var_os("PATH")?)
        .map(|d| d.join("kubernetes-validate"))
        .find(|f| f.is_file())
}

#[test]
fn kubernetes_manifest_is_a_valid_indexed_job_whose_pods_do_the_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    // Relative paths, as in a pod whose working directory is the claim's root.
    let out = tmp.path().join("out");
    let (code, _, stderr) = sweep(&out, &["--executor", "k8s-manifest", "--max-parallel", "2"]);
    assert_eq!(code, 0, "{stderr}");
    let manifest = out.join("k8s/job.yaml");
    let text = std::fs::read_to_string(&manifest).unwrap();
    let job = YamlOwned::load_from_str(&text).unwrap().remove(0);
    let spec = &job["spec"];
    assert_eq!(job["kind"].as_str(), Some("Job"));
    assert_eq!(spec["completionMode"].as_str(), Some("Indexed"));
    assert_eq!(spec["completions"].as_integer(), Some(6));
    assert_eq!(spec["parallelism"].as_integer(), Some(2));
    let container = &spec["template"]["spec"]["containers"][0];
    let command: Vec<String> = container["command"]
        .as_vec()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap().to_string())
        .collect();
    assert_eq!(command[0], "mapc");
    assert!(command.contains(&"$(JOB_COMPLETION_INDEX)".to_string()));
    // What each pod does: the command with its index, in the working directory.
    assert!(
        !out.join("runs").exists(),
        "the manifest executor ran something"
    );
    for i in 0..6 {
        let args: Vec<String> = command[1..]
            .iter()
            .map(|a| a.replace("$(JOB_COMPLETION_INDEX)", &i.to_string()))
            .collect();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, _, err) = mapc_in(root, &args);
        assert_eq!(code, 0, "pod {i}: {err}");
    }
    let (code, _, err) = support::mapc(&["sweep", "collect", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let local = tmp.path().join("local");
    let (code, _, err) = sweep(&local, &[]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read(out.join("results.csv")).unwrap(),
        std::fs::read(local.join("results.csv")).unwrap()
    );

    // The Kubernetes schema (no cluster here: kubernetes-validate carries the schemas).
    match kubernetes_validate() {
        None => println!("skipped: kubernetes-validate not found"),
        Some(kv) => {
            let res = Command::new(kv)
                .arg("--strict")
                .arg(&manifest)
                .output()
                .unwrap();
            assert!(
                res.status.success(),
                "{}{}",
                String::from_utf8_lossy(&res.stdout),
                String::from_utf8_lossy(&res.stderr)
            );
        }
    }
}

#[test]
fn collect_reports_runs_that_are_not_done() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let (code, _, stderr) = sweep(&out, &["--executor", "k8s-manifest"]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = support::mapc(&["sweep", "collect", out.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(stdout.starts_with("0 of 6 runs done"), "{stdout}");
    assert!(stderr.contains("6 run(s) not done: 0000, 0001"), "{stderr}");
    let (_, rows) = csv(&out);
    assert_eq!(rows.len(), 6);
    assert!(rows.iter().all(|r| r[3].is_empty()));
    assert!(!out.join("capacity.svg").exists());
}

#[test]
fn a_killed_sweep_resumes_where_it_stopped() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/two_level_clinic.scenario.yaml");
    let sweep = tmp.path().join("s.sweep.yaml");
    std::fs::write(
        &sweep,
        format!(
            "scenario: {}\nset: {{duration: 30min, fleets.tinyRobot.spawn: auto}}\nruns:\n  fleets.tinyRobot.count: [1, 2, 3]\n  seed: [1, 2]\n",
            scenario.display()
        ),
    )
    .unwrap();
    let out = tmp.path().join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args([
            "sweep",
            sweep.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--jobs",
            "1",
        ])
        .stderr(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while !out.join("runs/0000/inputs.sha256").exists() {
        assert!(start.elapsed().as_secs() < 120, "no run finished");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let done = (0..6)
        .filter(|i| out.join(format!("runs/{i:04}/inputs.sha256")).exists())
        .count();
    assert!(done >= 1);
    let s = sweep.to_str().unwrap();
    let (code, _, stderr) = support::mapc(&["sweep", s, "-o", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains(&format!("6 runs, {} to run, {done} up to date", 6 - done)),
        "{stderr}"
    );
    // The same results as a sweep that was never interrupted, and no temporaries left.
    let clean = tmp.path().join("clean");
    let (code, _, stderr) = support::mapc(&["sweep", s, "-o", clean.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(
        std::fs::read(out.join("results.csv")).unwrap(),
        std::fs::read(clean.join("results.csv")).unwrap()
    );
    for i in 0..6 {
        for e in std::fs::read_dir(out.join(format!("runs/{i:04}"))).unwrap() {
            let name = e.unwrap().file_name().into_string().unwrap();
            assert!(!name.contains(".mapc-tmp-"), "{name} left in run {i}");
        }
    }
}

#[test]
fn a_sweep_of_more_than_100000_runs_is_refused_at_once() {
    let tmp = tempfile::tempdir().unwrap();
    let values: Vec<String> = (0..400).map(|i| i.to_string()).collect();
    let values = values.join(", ");
    let sweep = tmp.path().join("huge.sweep.yaml");
    std::fs::write(
        &sweep,
        format!("scenario: base.yaml\nruns:\n  seed: [{values}]\n  duration: [{values}]\n"),
    )
    .unwrap();
    let out = tmp.path().join("out");
    let (code, _, stderr) = support::mapc(&[
        "sweep",
        sweep.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("error[S0401]: the axes make more than 100000 runs"),
        "{stderr}"
    );
    assert!(stderr.contains("huge.sweep.yaml:3:3"), "{stderr}");
    assert!(!out.exists());
}

/// The walkthrough's sweep (docs/sweep.md) stays valid: planned and checked on the clinic
/// demo map, without running it (the manifest executor runs nothing).
#[test]
fn the_walkthrough_sweep_plans_on_the_clinic_demo_map() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/maps/clinic");
    if !shared.is_dir() {
        println!("skipped: ../shared not found");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let (code, _, stderr) = support::mapc(&[
        "sweep",
        "fixtures/sweep/clinic_demo.sweep.yaml",
        "-o",
        out.to_str().unwrap(),
        "--executor",
        "k8s-manifest",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("18 runs, 18 to run"), "{stderr}");
    let plan: Value =
        serde_json::from_slice(&std::fs::read(out.join("plan.json")).unwrap()).unwrap();
    assert_eq!(plan["runs"].as_array().unwrap().len(), 18);
}

#[test]
fn axes_override_a_fleet_config_and_runs_find_its_files() {
    // The scenario names its fleet config and requests file relative to itself; the runs
    // (in OUT/runs/NNNN) find them, and axes override the config's count and speed.
    let out = tempfile::tempdir().unwrap();
    let (code, _, err) = support::mapc(&[
        "sweep",
        "fixtures/rmf/warehouse.sweep.yaml",
        "-o",
        out.path().to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (h, rows) = csv(out.path());
    assert_eq!(rows.len(), 4);
    let robots: Vec<&str> = rows.iter().map(|r| r[col(&h, "robots")].as_str()).collect();
    assert_eq!(robots, ["1", "1", "2", "2"]);
    // The same work at half the speed keeps the robots busy longer.
    let util = |i: usize| rows[i][col(&h, "utilisation")].parse::<f64>().unwrap();
    assert!(util(0) > 1.2 * util(1), "{} vs {}", util(0), util(1));
    let done = |i: usize| rows[i][col(&h, "tasks_completed")].parse::<u32>().unwrap();
    assert!((0..4).all(|i| done(i) >= 3), "{rows:?}");
}
