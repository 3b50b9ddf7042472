//! Peak memory of `mapc check` and `mapc nav` (the release binary, as users run it) on
//! issue 18's adversarial shapes at the acceptance sizes (the line also with CRLF line ends
//! and with flow-style lists, which the general YAML reader reads) and on issue 12's huge buildings
//! (40,000 and 100,000 waypoints), against issue 18's bound max(10 × file, 64 MB). Fails
//! when any run is over the bound, so a regression shows; prints a table for
//! BENCHMARKS.md. The debug test `tests/bounded_shapes.rs` checks the same bound on the
//! shapes in CI, `tests/huge_map.rs` on a 40,000-waypoint building.
//!
//! Run with `cargo bench --bench memory`. Peak RSS is the child's `VmHWM`, sampled every
//! 2 ms (`tests/support/`), independent of the machine's load; the times printed are wall
//! times and are not (see BENCHMARKS.md).

#[path = "../tests/shapes/mod.rs"]
mod shapes;
#[path = "../tests/support/mod.rs"]
mod support;

use std::time::Duration;

fn main() {
    // `cargo bench` passes `--bench`; a filter argument picks maps by name.
    let filter: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let mut maps = shapes::acceptance();
    // The line through the general YAML reader: CRLF line ends, flow-style lists.
    maps.push(("line_crlf", shapes::crlf(&shapes::line(100_000))));
    maps.push(("line_flow", shapes::line_flow(100_000)));
    maps.push(("huge_40k", shapes::huge(40_000)));
    maps.push(("huge_100k", shapes::huge(100_000)));
    let dir = tempfile::tempdir().expect("temp dir");
    let mut over = Vec::new();
    println!("| map | file | command | peak RSS | × file | bound | wall | exit |");
    println!("| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: |");
    for (name, text) in maps {
        if !filter.is_empty() && !filter.iter().any(|f| name.contains(f.as_str())) {
            continue;
        }
        let map = dir.path().join(format!("{name}.building.yaml"));
        std::fs::write(&map, &text).expect("write map");
        let file = text.len() as u64;
        drop(text);
        let bound = (10 * file).max(64 << 20);
        let out = dir.path().join(format!("{name}-nav"));
        let (m, o) = (map.to_str().unwrap(), out.to_str().unwrap());
        for args in [vec!["check", m], vec!["nav", m, o]] {
            let r = support::run(&args, Duration::from_secs(120));
            let peak = r.peak_rss.unwrap_or(0);
            println!(
                "| {name} | {:.1} MB | {} | {:.1} MB | {:.1} | {:.0} MB | {:.2} s | {} |",
                file as f64 / 1e6,
                args[0],
                peak as f64 / 1e6,
                peak as f64 / file as f64,
                bound as f64 / 1e6,
                r.elapsed.as_secs_f64(),
                r.code
            );
            if peak > bound || !(r.code == 0 || r.code == 1) {
                over.push(format!("{name} {}: {peak} bytes, exit {}", args[0], r.code));
            }
        }
    }
    assert!(over.is_empty(), "over issue 18's bound: {over:#?}");
}
