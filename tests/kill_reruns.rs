//! Kills leave nothing behind: `mapc gazebo` is killed with SIGKILL at random moments (30
//! times), each time rerun into the same place to completion, and the tree must then be
//! byte-equal to a clean run's (no `.*.mapc-tmp-*` temporary left, every file complete).
//! Before each rerun, the killed run's tree is checked too: every file in it is whole (the
//! clean run's bytes), whatever the moment of the kill (ARCHITECTURE.md, "Crash safety").
//! A run into a place that does not exist stages it whole beside itself
//! (`.killed.mapc-tmp-<pid>`): after each rerun nothing of that kind may be left there.
//! The map is the airport demo from `../shared` when present (prints `skipped: ../shared not
//! found` and uses a fixture otherwise). `MAPC_KILL_SEED` replays a run's kill moments.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const KILLS: usize = 30;

fn map() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let demo = root.join("../shared/maps/airport_terminal/airport_terminal.building.yaml");
    if demo.is_file() {
        demo
    } else {
        eprintln!("skipped: ../shared not found (using fixtures/two_level_clinic)");
        root.join("fixtures/two_level_clinic.building.yaml")
    }
}

/// The demo textures, when present: found images are staged as hard links to them, so the
/// kills also hit linked temporaries (and must leave the sources as they were).
fn textures() -> Option<PathBuf> {
    let t = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/textures");
    t.is_dir().then_some(t)
}

fn gazebo(map: &Path, out: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_mapc"));
    c.arg("gazebo")
        .arg(map)
        .arg(out.join("world.world"))
        .arg(out.join("models"))
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    if let Some(t) = textures() {
        c.arg("--texture-path").arg(t);
    }
    c
}

/// Every file under `dir` (relative path -> bytes); directories as empty entries.
fn tree(dir: &Path) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            let rel = p.strip_prefix(dir).unwrap().to_path_buf();
            if e.file_type().unwrap().is_dir() {
                out.insert(rel, None);
                stack.push(p);
            } else {
                out.insert(rel, Some(std::fs::read(&p).unwrap()));
            }
        }
    }
    out
}

#[test]
fn reruns_after_kill_9_leave_a_clean_tree() {
    let map = map();
    let sources = textures().map(|t| tree(&t));
    let tmp = tempfile::tempdir().unwrap();
    let clean = tmp.path().join("clean");
    let start = Instant::now();
    assert!(gazebo(&map, &clean).status().unwrap().success());
    let run_time = start.elapsed();
    let expected = tree(&clean);
    assert!(expected.len() > 3, "{:?}", expected.keys());

    let seed: u64 = std::env::var("MAPC_KILL_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(18, |d| d.as_nanos() as u64)
        });
    eprintln!("MAPC_KILL_SEED={seed}");
    let mut rng = seed | 1;
    let mut next = || {
        // xorshift64
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    let out = tmp.path().join("killed");
    let span = run_time.as_micros().max(1000) as u64;
    let mut left_behind = 0;
    for i in 0..KILLS {
        // An existing identical file is not rewritten, so a killed run over a complete
        // tree writes nothing: start each killed run from an empty place (or, every third
        // time, from the tree the last rerun left, for the "interrupted rebuild" case).
        if i % 3 != 2 && out.exists() {
            std::fs::remove_dir_all(&out).unwrap();
        }
        // Kill moments over the whole run, more of them late, where files are written.
        let u = (next() % 1_000_000) as f64 / 1e6;
        let delay = Duration::from_micros((span as f64 * u.sqrt()) as u64);
        let mut child = gazebo(&map, &out).spawn().unwrap();
        std::thread::sleep(delay);
        let _ = child.kill(); // SIGKILL
        let _ = child.wait();
        // What the kill left: every file is whole, the old one or the new one (both are the
        // clean run's bytes here: an empty place has no old files, and a rerun left the
        // clean tree), never partly written; only temporaries are extra.
        if out.exists() {
            let killed = tree(&out);
            if killed
                .keys()
                .any(|p| p.to_string_lossy().contains(".mapc-tmp-"))
            {
                left_behind += 1;
            }
            for (k, v) in &killed {
                if k.to_string_lossy().contains(".mapc-tmp-") {
                    continue;
                }
                assert!(
                    expected.get(k) == Some(v),
                    "kill {i} after {delay:?} left {} partly written or unknown",
                    k.display()
                );
            }
        }
        assert!(gazebo(&map, &out).status().unwrap().success(), "rerun {i}");
        let beside: Vec<_> = std::fs::read_dir(tmp.path())
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.contains(".mapc-tmp-"))
            .collect();
        assert!(
            beside.is_empty(),
            "kill {i} after {delay:?}: left {beside:?}"
        );
        let got = tree(&out);
        let extra: Vec<_> = got.keys().filter(|k| !expected.contains_key(*k)).collect();
        let missing: Vec<_> = expected.keys().filter(|k| !got.contains_key(*k)).collect();
        assert!(
            extra.is_empty() && missing.is_empty(),
            "kill {i} after {delay:?}: extra {extra:?}, missing {missing:?}"
        );
        for (k, v) in &expected {
            assert!(
                got[k] == *v,
                "kill {i} after {delay:?}: {} differs",
                k.display()
            );
        }
    }
    if let Some(t) = textures() {
        assert!(Some(tree(&t)) == sources, "a texture source changed");
    }
    eprintln!("{KILLS} kills, {left_behind} left temporaries that the rerun swept");
}
