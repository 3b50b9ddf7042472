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
    /// Peak resident memory in bytes (`ru_maxrss` of the child, Linux only).
    pub peak_rss: Option<u64>,
}

/// Reaps the child if it has exited: its exit status (as `wait` gives it) and its peak
/// resident memory in bytes. `wait4` gives the peak exactly, where sampling /proc misses
/// whatever the process reaches after the last sample.
#[cfg(target_os = "linux")]
fn try_reap(pid: u32) -> Option<(i32, Option<u64>)> {
    let mut status = 0;
    // SAFETY: `rusage` is plain data that wait4 fills; the pid is our own child's.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let r = unsafe { libc::wait4(pid as i32, &mut status, libc::WNOHANG, &mut usage) };
    if r <= 0 {
        return None;
    }
    // Linux gives ru_maxrss in kilobytes.
    Some((status, Some(usage.ru_maxrss as u64 * 1024)))
}

/// Runs mapc with `args`, killing it (and failing) after `limit`.
// The child is reaped by `wait4` (for its peak memory), which clippy cannot see.
#[allow(clippy::zombie_processes)]
pub fn run(args: &[&str], limit: Duration) -> Run {
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mapc starts");
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
    let (code, peak) = loop {
        #[cfg(target_os = "linux")]
        if let Some((status, peak)) = try_reap(child.id()) {
            // Killed by a signal (an abort, say): -1, which no bound accepts.
            let code = if libc::WIFEXITED(status) {
                libc::WEXITSTATUS(status)
            } else {
                -1
            };
            break (code, peak);
        }
        #[cfg(not(target_os = "linux"))]
        if let Some(s) = child.try_wait().expect("wait") {
            break (s.code().unwrap_or(-1), None);
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("mapc {args:?} still running after {:?}", start.elapsed());
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Run {
        code,
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
