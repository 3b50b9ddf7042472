//! The local executor: runs on `std::thread::scope` workers pulling run indices from an
//! atomic counter (each run is single-threaded and deterministic, so the order in which they
//! finish changes nothing written). Only the main thread prints: the progress line (on a
//! terminal) and failures.

use super::plan::{Plan, Run};
use std::io::IsTerminal;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Instant;

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
    let started = Instant::now();
    let mut bar = Bar::new(todo.len(), !quiet);
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
        for (i, result) in rx {
            if let Err(e) = result {
                bar.clear();
                eprintln!("error: {e}");
                failures.push((todo[i].name.clone(), e));
            }
            bar.done(failures.len(), started);
        }
    });
    bar.clear();
    failures.sort();
    failures
}

/// `[=====     ] 12/24 runs, 0 failed, 0:01:20 left` on stderr, when it is a terminal.
struct Bar {
    total: usize,
    finished: usize,
    shown: bool,
    on: bool,
}

impl Bar {
    fn new(total: usize, wanted: bool) -> Bar {
        let mut b = Bar {
            total,
            finished: 0,
            shown: false,
            on: wanted && std::io::stderr().is_terminal(),
        };
        b.draw(0, None);
        b
    }

    fn done(&mut self, failed: usize, started: Instant) {
        self.finished += 1;
        let elapsed = started.elapsed().as_secs_f64();
        let left = elapsed / self.finished as f64 * (self.total - self.finished) as f64;
        self.draw(failed, Some(left));
    }

    fn draw(&mut self, failed: usize, left: Option<f64>) {
        if !self.on || self.total == 0 {
            return;
        }
        let width = 30;
        let filled = self.finished * width / self.total;
        let left = match left {
            Some(t) => {
                let s = t.round() as u64;
                format!("{}:{:02}:{:02} left", s / 3600, s / 60 % 60, s % 60)
            }
            None => "starting".into(),
        };
        eprint!(
            "\r[{}{}] {}/{} runs, {failed} failed, {left}   ",
            "=".repeat(filled),
            " ".repeat(width - filled),
            self.finished,
            self.total
        );
        self.shown = true;
    }

    fn clear(&mut self) {
        if self.shown {
            eprint!("\r{}\r", " ".repeat(79));
            self.shown = false;
        }
    }
}
