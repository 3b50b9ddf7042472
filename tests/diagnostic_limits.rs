//! The diagnostic cap (`--max-diagnostics`) and its per-code summary in every format, the
//! one-line style of the drop-ins, and snippets of long lines cut around the span.

mod shapes;

use std::process::Command;

fn mapc(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// 30 separate spots of 2 near waypoints: 30 W0207 warnings (and one W0208: the graph is
/// in 60 pieces).
fn thirty_spots() -> String {
    let mut v = Vec::new();
    let mut l = Vec::new();
    for i in 0..30 {
        let x = 10.0 * i as f64;
        let base = v.len();
        v.extend([(x, 0.0), (x + 0.05, 0.0), (x, 5.0), (x + 3.0, 5.0)]);
        l.push((base, base + 2));
        l.push((base + 1, base + 3));
    }
    shapes::map("spots", &v, &l)
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn cap_and_summary_in_every_format() {
    let tmp = tempfile::tempdir().unwrap();
    let map = write(tmp.path(), "spots.building.yaml", &thirty_spots());

    // Human: 20 by default, then the summary line with the true count.
    let (code, _, err) = mapc(&["check", &map]);
    assert_eq!(code, 0);
    assert_eq!(err.matches("warning[W0207]").count(), 20, "{err}");
    assert!(err.contains(
        "W0207 unconnected-near-waypoints: 30 found, 20 shown; --max-diagnostics all to see them"
    ));
    assert!(err.contains("0 error(s), 31 warning(s)"), "{err}");

    let (_, _, err) = mapc(&["check", "--max-diagnostics", "3", &map]);
    assert_eq!(err.matches("warning[W0207]").count(), 3);
    assert!(err.contains("30 found, 3 shown"));
    let (_, _, err) = mapc(&["check", "--max-diagnostics", "all", &map]);
    assert_eq!(err.matches("warning[W0207]").count(), 30);
    assert!(!err.contains("found,"));
    let (code, _, err) = mapc(&["check", "--max-diagnostics", "many", &map]);
    assert_eq!(code, 2, "{err}");

    // JSON: 20 diagnostics, then one summary record.
    let (_, out, _) = mapc(&["check", "--format", "json", &map]);
    let lines: Vec<serde_json::Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 22);
    let w0207 = lines[..21].iter().filter(|d| d["code"] == "W0207");
    assert_eq!(w0207.count(), 20);
    assert!(lines[..21].iter().all(|d| d.get("kind").is_none()));
    let s = &lines[21];
    assert_eq!(
        (&s["kind"], &s["code"], &s["found"], &s["shown"]),
        (
            &serde_json::json!("summary"),
            &serde_json::json!("W0207"),
            &serde_json::json!(30),
            &serde_json::json!(20)
        )
    );

    // SARIF: 20 results and a tool notification with the counts.
    let (_, out, _) = mapc(&["check", "--format", "sarif", &map]);
    let log: serde_json::Value = serde_json::from_str(&out).unwrap();
    let run = &log["runs"][0];
    assert_eq!(run["results"].as_array().unwrap().len(), 21);
    let note = &run["invocations"][0]["toolExecutionNotifications"][0];
    assert_eq!(note["descriptor"]["id"], "W0207");
    assert_eq!(note["properties"]["found"], 30);
    assert_eq!(note["properties"]["shown"], 20);
}

#[test]
fn drop_ins_print_one_line_per_diagnostic() {
    let tmp = tempfile::tempdir().unwrap();
    let map = write(tmp.path(), "spots.building.yaml", &thirty_spots());
    let out = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let world = out.join("w.world");
    let models = out.join("models");
    for args in [
        vec!["nav", &map, o],
        vec![
            "gazebo",
            &map,
            world.to_str().unwrap(),
            models.to_str().unwrap(),
        ],
    ] {
        let (code, _, err) = mapc(&args);
        assert_eq!(code, 0, "{err}");
        let first = err.lines().next().unwrap();
        assert!(
            first.starts_with(&format!("{map}:")) && first.contains(": warning[W0207]: "),
            "{first}"
        );
        assert!(!err.contains(" │ "), "{err}");
        // 20 + 1 lines, the summary, the total; then the success line of what was written.
        let lines = err
            .lines()
            .take_while(|l| !l.contains(" written to "))
            .count();
        assert_eq!(lines, 23, "{err}");
        let mut verbose = args.clone();
        verbose.push("--verbose");
        let (_, _, err) = mapc(&verbose);
        assert!(err.contains(" │ "), "{err}");
    }
}

#[test]
fn long_lines_are_cut_around_the_span() {
    // A lane whose line is 20,000 characters long, with an index out of range (E0103)
    // near its start and one near its end (E0103 for the end index of the next lane).
    let pad = "x".repeat(20_000);
    let text = format!(
        "name: long\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    elevation: 0\n    \
         vertices:\n      - [0, 0, 0, a]\n      - [1, 0, 0, b]\n    lanes:\n      - [0, 7, \
         {{graph_idx: [2, 0], note: [1, \"{pad}\"], bidirectional: [4, true]}}]\n"
    );
    let tmp = tempfile::tempdir().unwrap();
    let map = write(tmp.path(), "long.building.yaml", &text);
    let (code, _, err) = mapc(&["check", &map]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[E0103]"), "{err}");
    assert!(err.contains(":10:13"), "the real column is kept: {err}");
    let longest = err.lines().map(|l| l.chars().count()).max().unwrap();
    assert!(longest < 400, "a line of {longest} characters was printed");
    assert!(err.contains('…'), "{err}");
}

#[test]
fn lines_shown_between_labels_are_escaped_too() {
    // Regression (tests/fuzz_maps.rs, seed 1795619889687424002, case 476): W0207 labels the
    // lines of `a` and `c`; the renderer also prints the line between them, which names a
    // vertex with U+2066 (joined to `a` by a lane, so not part of the spot).
    let text = "name: between\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    \
                elevation: 0\n    vertices:\n      - [0, 0, 0, a]\n      - [0.001, 0, 0, \
                \"\u{2066}iso\"]\n      - [0.002, 0, 0, c]\n      - [5, 0, 0, far]\n    lanes:\n      \
                - [0, 1, {graph_idx: [2, 0], bidirectional: [4, true]}]\n      - [0, 3, \
                {graph_idx: [2, 0], bidirectional: [4, true]}]\n      - [2, 3, {graph_idx: [2, \
                0], bidirectional: [4, true]}]\n";
    let tmp = tempfile::tempdir().unwrap();
    let map = write(tmp.path(), "between.building.yaml", text);
    let (code, _, err) = mapc(&["check", &map]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning[W0207]"), "{err}");
    assert!(err.contains("\\u{2066}iso"), "{err}");
    assert!(!err.contains('\u{2066}'), "{err}");
}
