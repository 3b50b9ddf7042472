//! The local executor: runs on `std::thread::scope` workers pulling run indices from an
//! atomic counter (each run is single-threaded and deterministic, so the order in which they
//! finish changes nothing written). Only the main thread prints: the progress line (on a
//! terminal) and failures.

use super::plan::{Plan, Run};
use crate::ui::progress::Progress;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;

/// Runs `todo` on `jobs` threads; returns the failures (run name, message). `quiet`: no
/// progress line.
pub(crate) fn execute(
    plan: &Plan,
    todo: &[&Run],
    out: &Path,
    jobs: usize,
    quiet: bool,
) -> Vec<(String, String)> {
    let next = AtomicUsize::new(0);
    let (tx, rx) = mpsc::channel::<(usize, Result<(), String>)>();
    let mut failures = Vec::new();
    let bar = Progress::new(todo.len() as u64, "runs", !quiet);
    std::thread::scope(|s| {
        for _ in 0..jobs.clamp(1, todo.len().max(1)) {
            let tx = tx.clone();
            let next = &next;
            s.spawn(move || loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(r) = todo.get(i) else { break };
                let result = super::run::execute(plan, r, out);
                if tx.send((i, result)).is_err() {
                    break;
                }
            });
        }
        drop(tx);
        for (n, (i, result)) in rx.into_iter().enumerate() {
            if let Err(e) = result {
                bar.suspend(|| crate::ui::error(&e));
                failures.push((todo[i].name.clone(), e));
            }
            bar.set(n as u64 + 1, format!("{} failed", failures.len()));
        }
    });
    drop(bar);
    failures.sort();
    failures
}
