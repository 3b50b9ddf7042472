//! `mapc sweep` on all cores against the same runs one after another: the 24-run sweep of
//! `fixtures/sweep/bench.sweep.yaml` (the two-level clinic fixture, 1-4 tiny robots × 6
//! seeds, four simulated hours each), run by the mapc binary into a fresh output directory
//! each time (nothing reused), with `--jobs 1` and with `--jobs` = the number of CPUs.
//!
//! Run with `cargo bench --bench sweep`; the speed-up is `serial / all_cores`.

use divan::Bencher;
use std::process::Command;

fn main() {
    divan::main();
}

const SWEEP: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/fixtures/sweep/bench.sweep.yaml"
);

fn sweep(jobs: usize) {
    let dir = tempfile::tempdir().unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args(["sweep", SWEEP, "-q", "--jobs", &jobs.to_string(), "-o"])
        .arg(dir.path().join("out"))
        .status()
        .unwrap();
    assert!(status.success());
}

fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn serial(b: Bencher) {
    b.bench(|| sweep(1));
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn all_cores(b: Bencher) {
    b.bench(|| sweep(cores()));
}
