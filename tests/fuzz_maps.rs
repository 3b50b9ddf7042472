//! Structure-aware fuzzing of the whole command line: maps from `tests/mapgen` (hostile
//! names, adversarial layouts, small and large) run through `mapc build` and `mapc check`.
//! Each case must exit 0, 1 or 2 (never a panic, abort or signal), stay within time and
//! memory bounds, print at most 1 MB, write nothing outside the output directory, write
//! no path with a control or bidi character, and print none raw.
//!
//! Memory: the bound here is max(`MEMORY_FACTOR` × file, 128 MB), a guard against blow-ups
//! (quadratic memory, a report held whole), not issue 18's max(10 × file, 64 MB): dense
//! maps read by the general YAML reader (saphyr: an owned string per scalar) peak at about
//! 50 × their size, which is still open (see tests/bounded_shapes.rs for the shapes that
//! meet 10 ×).
//!
//! Runs for `MAPC_FUZZ_SECONDS` (default 3) in the normal test suite; set it higher to fuzz
//! longer (`MAPC_FUZZ_SECONDS=600 cargo test --release --test fuzz_maps`). `MAPC_FUZZ_SEED`
//! replays a run. A failing case is saved under `target/fuzz-maps/` for a regression test
//! (`tests/fuzz_regressions/`).

mod mapgen;
mod support;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Per-case time bound for the debug binary (generous: CI shares 2 cores).
const CASE_SECONDS: u64 = 30;
const MAX_OUTPUT: usize = 1 << 20;
/// Peak RSS bound: max(MEMORY_FACTOR × file, 128 MB).
const MEMORY_FACTOR: u64 = 80;

fn unsafe_char(c: char) -> bool {
    c.is_control() || matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// Every path under `dir`, relative.
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            out.push(p.strip_prefix(dir).unwrap().to_path_buf());
            if e.file_type().is_ok_and(|t| t.is_dir()) {
                stack.push(p);
            }
        }
    }
    out
}

/// Runs one map; returns what went wrong, if anything.
fn case(root: &Path, text: &str) -> Result<(), String> {
    let dir = root.join("case");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let map = dir.join("map.building.yaml");
    std::fs::write(&map, text).unwrap();
    let out = dir.join("out");
    let memory_bound = (MEMORY_FACTOR * text.len() as u64).max(128 << 20);
    let limit = Duration::from_secs(2 * CASE_SECONDS);
    let m = map.to_str().unwrap();
    let o = out.to_str().unwrap();
    for (what, args, codes) in [
        (
            "build",
            vec!["build", m, "-o", o, "--targets", "nav,meshes,gz"],
            &[0, 1, 2][..],
        ),
        ("check", vec!["check", m], &[0, 1][..]),
        (
            "check json",
            vec!["check", "--format", "json", m],
            &[0, 1][..],
        ),
    ] {
        let r = support::run(&args, limit);
        let stderr = String::from_utf8_lossy(&r.stderr);
        if !codes.contains(&r.code) {
            return Err(format!("{what}: exit {}\n{stderr}", r.code));
        }
        if r.elapsed > Duration::from_secs(CASE_SECONDS) {
            return Err(format!("{what}: took {:?}", r.elapsed));
        }
        if r.peak_rss.is_some_and(|p| p > memory_bound) {
            return Err(format!(
                "{what}: peak RSS {:?} over {memory_bound}",
                r.peak_rss
            ));
        }
        if r.stdout.len() + r.stderr.len() > MAX_OUTPUT {
            return Err(format!(
                "{what}: printed {} bytes",
                r.stdout.len() + r.stderr.len()
            ));
        }
        let stdout = String::from_utf8_lossy(&r.stdout);
        if let Some(c) = stderr
            .chars()
            .chain(stdout.chars())
            .find(|&c| c != '\n' && unsafe_char(c))
        {
            return Err(format!("{what}: printed a raw {c:?}\n{stderr}{stdout}"));
        }
    }
    // Nothing outside the output directory; no unsafe name inside it.
    for p in walk(&dir) {
        if p != Path::new("map.building.yaml") && !p.starts_with("out") {
            return Err(format!(
                "wrote {} outside the output directory",
                p.display()
            ));
        }
        if p.to_string_lossy().chars().any(unsafe_char) {
            return Err(format!("wrote the unsafe path {:?}", p));
        }
    }
    for p in walk(root) {
        if !p.starts_with("case") {
            return Err(format!("wrote {} outside the case directory", p.display()));
        }
    }
    Ok(())
}

#[test]
fn generated_maps_are_handled_within_bounds() {
    let seconds: u64 = std::env::var("MAPC_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    let seed: u64 = std::env::var("MAPC_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(18, |d| d.as_nanos() as u64)
        });
    eprintln!("MAPC_FUZZ_SEED={seed}");
    let mut rng = seed | 1;
    let mut bytes = vec![0u8; 1 << 16];
    let tmp = tempfile::tempdir().unwrap();
    let start = Instant::now();
    let mut n = 0usize;
    while n == 0 || start.elapsed() < Duration::from_secs(seconds) {
        for b in bytes.iter_mut() {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            *b = rng as u8;
        }
        // Every fourth map may be large.
        let max_vertices = if n % 4 == 3 { 20_000 } else { 300 };
        let mut u = arbitrary::Unstructured::new(&bytes);
        let Ok(text) = mapgen::building(&mut u, max_vertices) else {
            continue;
        };
        if let Err(e) = case(tmp.path(), &text) {
            let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-maps");
            std::fs::create_dir_all(&dir).unwrap();
            let saved = dir.join(format!("case-{seed}-{n}.building.yaml"));
            std::fs::write(&saved, &text).unwrap();
            panic!(
                "case {n} (seed {seed}): {e}\nmap saved as {}",
                saved.display()
            );
        }
        n += 1;
    }
    eprintln!("{n} generated maps in {:?}", start.elapsed());
}
