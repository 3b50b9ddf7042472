//! fixtures/invalid/<CODE>-<slug>.building.yaml: one broken map per rule and per crash case.
//! Each fixture marks the line where its diagnostic must point with a trailing
//! `# expect: <CODE>` comment. For every fixture this test checks the exit code, that the
//! JSON output has that code on that line, and snapshots the human and JSON output.

use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn run(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(root())
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// (code, 1-based line) pairs marked in the fixture.
fn expectations(bytes: &[u8]) -> Vec<(String, u32)> {
    let text = String::from_utf8_lossy(bytes);
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if let Some(pos) = line.find("# expect: ") {
            for code in line[pos + 10..].split([',', ' ']).filter(|c| !c.is_empty()) {
                out.push((code.to_string(), i as u32 + 1));
            }
        }
    }
    out
}

#[test]
fn invalid_fixtures() {
    let dir = root().join("fixtures/invalid");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".yaml"))
        .collect();
    files.sort();
    // MAPC_INVALID_FILTER=E02 runs only fixtures whose name starts with it (while writing
    // new fixtures); the full suite always runs every fixture.
    let filter = std::env::var("MAPC_INVALID_FILTER").unwrap_or_default();
    let total = files.len();
    files.retain(|n| n.starts_with(&filter));
    let mut failures = Vec::new();
    for name in &files {
        let rel = format!("fixtures/invalid/{name}");
        let code = name.split('-').next().unwrap().to_string();
        let bytes = std::fs::read(root().join(&rel)).unwrap();
        let expected = expectations(&bytes);
        if !expected.iter().any(|(c, _)| *c == code) {
            failures.push(format!("{name}: no `# expect: {code}` marker"));
            continue;
        }

        let (status, json, _) = run(&["check", "--format", "json", &rel]);
        let (status_h, _, human) = run(&["check", &rel]);
        assert_eq!(
            status, status_h,
            "{name}: exit codes differ between formats"
        );
        let want_status = if expected.iter().any(|(c, _)| c.starts_with('E')) {
            1
        } else {
            0
        };
        if status != want_status {
            failures.push(format!(
                "{name}: exit {status}, expected {want_status}\n{human}"
            ));
        }
        let diags: Vec<serde_json::Value> = json
            .lines()
            .map(|l| {
                serde_json::from_str(l).unwrap_or_else(|e| panic!("{name}: bad JSON {e}: {l}"))
            })
            .collect();
        for (c, line) in &expected {
            let hit = diags.iter().any(|d| {
                d["code"] == c.as_str() && d["location"]["line"].as_u64() == Some(*line as u64)
            });
            if !hit {
                failures.push(format!(
                    "{name}: no {c} at line {line}; got {:?}",
                    diags
                        .iter()
                        .map(|d| format!("{}@{}", d["code"], d["location"]["line"]))
                        .collect::<Vec<_>>()
                ));
            }
        }
        let stem = name.trim_end_matches(".yaml").trim_end_matches(".building");
        insta::assert_snapshot!(format!("{stem}__human"), human);
        insta::assert_snapshot!(format!("{stem}__json"), json);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(total >= 40, "only {total} invalid fixtures");
}
