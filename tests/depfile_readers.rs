//! `mapc build --depfile` read by the real readers: GNU Make and Ninja must find every path
//! the depfile names, for a map in a directory whose name has a space, `#` and `$` (the
//! characters a depfile must escape). Each part prints `skipped: make not found` /
//! `skipped: ninja not found` when the tool is absent (.ci/run installs both).

use std::path::{Path, PathBuf};
use std::process::Command;

fn have(tool: &str) -> bool {
    Command::new(tool).arg("--version").output().is_ok()
}

/// A temp dir holding `maps dir #1 $x/clinic.building.yaml`.
fn setup() -> (tempfile::TempDir, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("maps dir #1 $x");
    std::fs::create_dir_all(&dir).unwrap();
    let map = dir.join("clinic.building.yaml");
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/two_level_clinic.building.yaml");
    std::fs::copy(src, &map).unwrap();
    (tmp, map)
}

fn mapc_build(cwd: &Path, map: &str) {
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(cwd)
        .args([
            "build",
            map,
            "-o",
            "out",
            "--targets",
            "nav,meshes",
            "--stamp",
            "out.stamp",
            "--depfile",
            "deps.d",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn make_reads_the_depfile() {
    if !have("make") {
        eprintln!("skipped: make not found");
        return;
    }
    let (tmp, _) = setup();
    let cwd = tmp.path();
    mapc_build(cwd, "maps dir #1 $x/clinic.building.yaml");
    let d = std::fs::read_to_string(cwd.join("deps.d")).unwrap();
    assert!(
        d.contains("maps\\ dir\\ \\#1\\ $$x/clinic.building.yaml"),
        "{d}"
    );
    // The depfile's first rule is the default goal. Make fails with "No rule to make
    // target" for any prerequisite that, as Make reads it, does not exist.
    std::fs::write(cwd.join("Makefile"), "include deps.d\n").unwrap();
    let make = |dir: &Path| Command::new("make").current_dir(dir).output().unwrap();
    let out = make(cwd);
    assert!(
        out.status.success(),
        "make: {}\n{d}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The same check fails on an unescaped path: it can tell.
    std::fs::write(
        cwd.join("deps.d"),
        "out.stamp: maps dir #1 $x/clinic.building.yaml\n",
    )
    .unwrap();
    assert!(!make(cwd).status.success());
}

#[test]
fn ninja_reads_the_depfile() {
    if !have("ninja") {
        eprintln!("skipped: ninja not found");
        return;
    }
    let (tmp, _) = setup();
    let cwd = tmp.path();
    // In build.ninja `$$` is `$`; the shell gets the path in single quotes.
    let ninja_file = format!(
        "rule mapc\n  command = {} build 'maps dir #1 $$x/clinic.building.yaml' -o out \
         --targets nav,meshes --stamp out.stamp --depfile deps.d\n  depfile = deps.d\n  \
         deps = gcc\nbuild out.stamp: mapc\n",
        env!("CARGO_BIN_EXE_mapc")
    );
    std::fs::write(cwd.join("build.ninja"), ninja_file).unwrap();
    let ninja = |args: &[&str]| {
        let out = Command::new("ninja")
            .current_dir(cwd)
            .args(args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "ninja {args:?}: {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    ninja(&[]);
    // Every dependency Ninja recorded from the depfile exists, the map among them.
    let deps = ninja(&["-t", "deps"]);
    let paths: Vec<&str> = deps
        .lines()
        .filter(|l| l.starts_with("    "))
        .map(str::trim)
        .collect();
    assert!(
        paths.contains(&"maps dir #1 $x/clinic.building.yaml"),
        "{deps}"
    );
    for p in &paths {
        assert!(
            cwd.join(p).exists(),
            "ninja read `{p}`, which does not exist\n{deps}"
        );
    }
    // Nothing is missing, so nothing is rebuilt.
    assert!(ninja(&[]).contains("no work to do"), "second run rebuilt");
}

#[test]
fn unsafe_names_stop_the_build_with_nothing_written() {
    let tmp = tempfile::tempdir().unwrap();
    let map = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/invalid/E0509-unsafe-characters-in-name.building.yaml");
    let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(tmp.path())
        .arg("build")
        .arg(&map)
        .args(["-o", "out", "--stamp", "out.stamp", "--depfile", "deps.d"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("error[E0509]"), "{stderr}");
    // No raw control or bidi character reaches the terminal.
    assert!(
        !stderr
            .chars()
            .any(|c| (c.is_control() && c != '\n') || ('\u{202a}'..='\u{202e}').contains(&c)),
        "{stderr:?}"
    );
    let written: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().collect();
    assert!(written.is_empty(), "{written:?}");
}
