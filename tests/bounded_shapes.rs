//! Issue 18's adversarial shapes, generated (never committed) and run through the real
//! binary: `check` and `nav` must exit 0 or 1, print at most 1 MB, state the count of every
//! code they cut, and stay within time and memory bounds.
//!
//! The test profile is a debug build, several times slower than release; the time bound
//! asserted here is `DEBUG_SECONDS` (release figures, measured with `--release`, are in
//! BENCHMARKS.md). Peak memory is the child's `VmHWM` from /proc, sampled every 2 ms
//! (`tests/support/`: why not `wait4`).
//!
//! Memory: issue 18 asks for max(10 × file, 64 MB), and every shape is held to it. The
//! line shape (10.4 MB, 100,000 waypoints) is the one whose bound is the ratio rather than
//! the 64 MB floor (release: 6.3 × in check, 7.0 × in nav; `cargo bench --bench memory`
//! runs the release binary on every shape and on issue 12's huge buildings).

mod shapes;
mod support;

use std::path::Path;
use std::time::Duration;
use support::run;

/// Time bound for the debug binary (release: at most 2 s, see BENCHMARKS.md).
const DEBUG_SECONDS: u64 = 30;
/// Output bound of issue 18.
const MAX_OUTPUT: usize = 1 << 20;
/// Issue 18's memory bound: max(FACTOR × file, 64 MB).
const FACTOR: u64 = 10;

/// Runs `check` and `nav` on `text` and checks the bounds; returns check's stderr.
fn bounded(name: &str, text: &str, factor: u64) -> String {
    let dir = tempfile::tempdir().expect("temp dir");
    let map = dir.path().join(format!("{name}.building.yaml"));
    std::fs::write(&map, text).expect("write map");
    let file = text.len() as u64;
    // The bound is on what the map costs: the executable's own resident pages before it reads
    // anything (shared libraries, and a debug build's far larger code) are measured here and
    // not counted; in release they are a few MB (`cargo bench --bench memory`).
    let idle = run(&["--version"], Duration::from_secs(DEBUG_SECONDS))
        .peak_rss
        .unwrap_or(0);
    let memory_bound = (factor * file).max(64 << 20) + idle;
    let out_dir = dir.path().join("nav");
    let mut check_stderr = String::new();
    for (cmd, args) in [
        ("check", vec!["check", path(&map)]),
        ("nav", vec!["nav", path(&map), path(&out_dir)]),
    ] {
        let r = run(&args, Duration::from_secs(4 * DEBUG_SECONDS));
        let printed = r.stdout.len() + r.stderr.len();
        let stderr = String::from_utf8_lossy(&r.stderr).into_owned();
        eprintln!(
            "{name} {cmd}: {} bytes of map, exit {}, {:.2} s (debug), peak RSS {} MB, {} bytes printed",
            file,
            r.code,
            r.elapsed.as_secs_f64(),
            r.peak_rss.map_or("?".into(), |m| (m >> 20).to_string()),
            printed
        );
        assert!(
            r.code == 0 || r.code == 1,
            "{name} {cmd}: exit {}\n{stderr}",
            r.code
        );
        assert!(
            printed <= MAX_OUTPUT,
            "{name} {cmd}: printed {printed} bytes"
        );
        assert!(
            r.elapsed <= Duration::from_secs(DEBUG_SECONDS),
            "{name} {cmd}: {:?}",
            r.elapsed
        );
        if let Some(peak) = r.peak_rss {
            assert!(
                peak <= memory_bound,
                "{name} {cmd}: peak RSS {} MB over the bound {} MB",
                peak >> 20,
                memory_bound >> 20
            );
        }
        if cmd == "check" {
            check_stderr = stderr;
        } else {
            // The drop-in prints no snippets.
            assert!(
                !stderr.contains(" │ "),
                "{name} nav printed a snippet:\n{stderr}"
            );
        }
    }
    check_stderr
}

fn path(p: &Path) -> &str {
    p.to_str().expect("UTF-8 temp path")
}

#[test]
fn scattered_waypoints_and_random_lanes() {
    let err = bounded("scattered", &shapes::scattered(20_000, 10_000), FACTOR);
    // Far more spots than are shown: the summary states the true count.
    let summary = err
        .lines()
        .find(|l| l.starts_with("W0207 unconnected-near-waypoints: "))
        .unwrap_or_else(|| panic!("no W0207 summary line:\n{}", tail(&err)));
    assert!(summary.ends_with(" found, 20 shown; --max-diagnostics all to see them"));
    assert_eq!(err.matches("warning[W0207]").count(), 20);
}

#[test]
fn waypoints_on_one_vertical_line() {
    let err = bounded("line", &shapes::line(100_000), FACTOR);
    assert!(!err.contains("W0207"), "{}", tail(&err));
}

/// The line read by the general YAML reader (CRLF line ends; lists in flow style over many
/// lines), which leaves level lists out of the tree as the fast reader does. 70,000
/// waypoints (7 MB): the bound is the ratio, not the 64 MB floor.
#[test]
fn waypoints_on_one_line_through_the_general_reader() {
    for (name, text) in [
        ("line_crlf", shapes::crlf(&shapes::line(70_000))),
        ("line_flow", shapes::line_flow(70_000)),
    ] {
        let err = bounded(name, &text, FACTOR);
        assert!(!err.contains("W0207"), "{}", tail(&err));
    }
}

#[test]
fn many_separate_lanes() {
    let err = bounded("pairs", &shapes::pairs(30_000), FACTOR);
    assert_eq!(err.matches("warning[W0208]").count(), 1, "{}", tail(&err));
    assert!(
        err.contains("falls apart into 30,000 pieces (of 2, 2, 2, 2, 2, 2, 2, 2 … and 29,992 more pieces of 2 waypoints)"),
        "{}",
        tail(&err)
    );
}

#[test]
fn waypoints_on_one_spot() {
    let err = bounded("spot", &shapes::spot(3_000), FACTOR);
    assert_eq!(err.matches("warning[W0207]").count(), 1, "{}", tail(&err));
    assert!(
        err.contains("3000 waypoints of graph 0 lie within 0.1 m of vertex 0"),
        "{}",
        tail(&err)
    );
}

/// The last lines of `s`, for failure messages.
fn tail(s: &str) -> String {
    let lines: Vec<&str> = s.lines().collect();
    lines[lines.len().saturating_sub(20)..].join("\n")
}
