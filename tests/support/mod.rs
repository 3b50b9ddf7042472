//! Running the mapc binary from tests with its exit code, output, time and peak memory.
#![allow(dead_code)] // each user takes what it needs

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What one run of mapc did. `code` is -1 when a signal ended it.
pub struct Run {
    pub code: i32,
    pub stdout: Vec<u8>,
    pub stderr: Vec<u8>,
    pub elapsed: Duration,
    /// Peak resident memory in bytes (the child's `VmHWM`, sampled; Linux only).
    pub peak_rss: Option<u64>,
}

/// Peak resident memory of process `pid` so far (`VmHWM`), in bytes.
///
/// Why sampled and not `wait4`'s `ru_maxrss`: Linux folds the high-water mark of the
/// memory a process had before `exec` into `ru_maxrss`, and a spawned child starts with
/// its parent's (the test process, holding the generated maps), so `ru_maxrss` reports at
/// least the parent's peak. `VmHWM` is that of mapc's own memory and only grows, so a
/// sample taken after the peak sees it; only growth in the last few milliseconds before
/// exit can be missed.
pub fn vm_hwm(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Runs mapc with `args`, killing it (and failing) after `limit`.
pub fn run(args: &[&str], limit: Duration) -> Run {
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mapc starts");
    let pid = child.id();
    // Drain the pipes on threads so a full pipe never blocks the child.
    let mut out = child.stdout.take().expect("stdout");
    let mut err = child.stderr.take().expect("stderr");
    let t_out = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = std::io::Read::read_to_end(&mut out, &mut v);
        v
    });
    let t_err = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = std::io::Read::read_to_end(&mut err, &mut v);
        v
    });
    let mut peak = None;
    let status = loop {
        if let Some(m) = vm_hwm(pid) {
            peak = Some(peak.map_or(m, |p: u64| p.max(m)));
        }
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("mapc {args:?} still running after {:?}", start.elapsed());
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    Run {
        // Killed by a signal (an abort, say): -1, which no bound accepts.
        code: status.code().unwrap_or(-1),
        stdout: t_out.join().expect("stdout thread"),
        stderr: t_err.join().expect("stderr thread"),
        elapsed: start.elapsed(),
        peak_rss: peak,
    }
}

/// Runs mapc in the crate's directory: (exit code, stdout, stderr).
pub fn mapc(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mapc"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
pub mod ros2;
