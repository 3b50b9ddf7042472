//! A job handed to a new thread, which the caller runs itself when the thread has not
//! started it by the time the result is needed ([`Task::get`]).
//!
//! Why: on a 2-vCPU VM a new thread started 0.07-1.5 ms after its spawn (an idle vCPU
//! takes that long to wake), and a parked caller learnt of its end up to 0.7 ms late
//! (BENCHMARKS.md, part 5, fourth pass). So the caller takes back a job not yet started,
//! spins briefly rather than parks while a short one ends, and never waits for the thread
//! itself to exit (it ends on its own, detached).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How long a caller spins for the end of a running job before it parks.
const SPIN: Duration = Duration::from_micros(200);

type Job<'a, R> = Box<dyn FnOnce() -> R + Send + 'a>;

enum State<'a, R> {
    /// Not started: whoever comes first (the thread, or the caller) runs it.
    Queued(Job<'a, R>),
    /// On the thread.
    Running,
    Done(std::thread::Result<R>),
    /// Taken: run by the caller, cancelled, or its result handed over.
    Taken,
}

struct Inner<'a, R> {
    state: State<'a, R>,
    /// The thread to wake when the job ends, once one waits.
    waiter: Option<std::thread::Thread>,
}

struct Shared<'a, R> {
    inner: Mutex<Inner<'a, R>>,
    /// Set once `state` is `Done`: read without the lock while spinning.
    done: AtomicBool,
}

impl<'a, R> Shared<'a, R> {
    fn lock(&self) -> std::sync::MutexGuard<'_, Inner<'a, R>> {
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A job started on its own thread (see the module); its result with [`Task::get`].
/// Dropped unfinished, it waits for a running job and cancels a queued one, so nothing the
/// job borrows ends while it runs.
pub struct Task<'a, R> {
    shared: Arc<Shared<'a, R>>,
}

/// Starts `f` on a new thread, placed on another CPU ([`super::Placement`]).
pub fn task<'a, R: Send + 'a>(f: impl FnOnce() -> R + Send + 'a) -> Task<'a, R> {
    let t = queued(f);
    let theirs = Arc::clone(&t.shared);
    let cpus = super::Placement::now();
    // SAFETY: the thread runs the job only while its `Task` waits for it (`get` and `drop`
    // wait for a running job; a queued one is taken away first), so what the job borrows
    // outlives every use. Afterwards the thread touches only `Shared`, which it co-owns,
    // and whose state no longer holds the job or its result.
    let spawned = unsafe {
        std::thread::Builder::new().spawn_unchecked(move || {
            cpus.restore();
            crate::heap::prepare_thread();
            run(&theirs);
        })
    };
    // Detached: never joined. Without a thread (spawning failed) the caller runs the job.
    if let Ok(h) = spawned {
        cpus.move_away(&h);
    }
    t
}

/// The task of `f`, queued with no thread started yet.
fn queued<'a, R: Send + 'a>(f: impl FnOnce() -> R + Send + 'a) -> Task<'a, R> {
    Task {
        shared: Arc::new(Shared {
            inner: Mutex::new(Inner {
                state: State::Queued(Box::new(f)),
                waiter: None,
            }),
            done: AtomicBool::new(false),
        }),
    }
}

/// On the thread: the job if it is still queued, then its end reported.
fn run<R>(shared: &Shared<'_, R>) {
    let job = {
        let mut inner = shared.lock();
        match std::mem::replace(&mut inner.state, State::Running) {
            State::Queued(f) => f,
            other => {
                inner.state = other;
                return;
            }
        }
    };
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(job));
    let waiter = {
        let mut inner = shared.lock();
        inner.state = State::Done(r);
        inner.waiter.take()
    };
    shared.done.store(true, Ordering::Release);
    if let Some(w) = waiter {
        w.unpark();
    }
}

impl<R> Task<'_, R> {
    /// The job's result: run here if the thread has not started it, else waited for. A
    /// panic of the job is resumed here.
    pub fn get(self) -> R {
        match self.take() {
            Ok(r) => r,
            Err(p) => std::panic::resume_unwind(p),
        }
    }

    fn take(&self) -> std::thread::Result<R> {
        let queued = {
            let mut inner = self.shared.lock();
            match std::mem::replace(&mut inner.state, State::Taken) {
                State::Queued(f) => f,
                State::Done(r) => return r,
                State::Running => {
                    inner.state = State::Running;
                    drop(inner);
                    return self.wait();
                }
                State::Taken => unreachable!("a task's result is taken once"),
            }
        };
        // Not started: here, now (a panic unwinds from here; the state says `Taken`).
        Ok(queued())
    }

    /// Waits for the running job to end, then takes its result.
    fn wait(&self) -> std::thread::Result<R> {
        let start = Instant::now();
        while !self.shared.done.load(Ordering::Acquire) {
            if start.elapsed() < SPIN {
                std::hint::spin_loop();
                continue;
            }
            {
                let mut inner = self.shared.lock();
                if matches!(inner.state, State::Done(_)) {
                    break;
                }
                inner.waiter = Some(std::thread::current());
            }
            // Woken by `run`; the timeout only guards against a lost wake-up.
            std::thread::park_timeout(Duration::from_millis(5));
        }
        let mut inner = self.shared.lock();
        match std::mem::replace(&mut inner.state, State::Taken) {
            State::Done(r) => r,
            _ => unreachable!("waited until done"),
        }
    }
}

impl<R> Drop for Task<'_, R> {
    fn drop(&mut self) {
        let running = {
            let mut inner = self.shared.lock();
            match std::mem::replace(&mut inner.state, State::Taken) {
                State::Running => {
                    inner.state = State::Running;
                    true
                }
                // Queued: cancelled (dropped unrun); Done: the result dropped.
                _ => false,
            }
        };
        if running {
            // Dropped with the result (a panic included): only the wait matters.
            drop(self.wait());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_result_comes_back_whoever_runs_the_job() {
        let data: Vec<u64> = (1..=1000).collect();
        // Started on the thread (most likely) or taken back: the same result.
        let t = task(|| data.iter().sum::<u64>());
        assert_eq!(t.get(), 500_500);
        // Taken back at once: the caller runs it.
        let t = task(|| data.len());
        assert_eq!(t.take().ok(), Some(1000));
        // A slow job is waited for (spin, then park).
        let t = task(|| {
            std::thread::sleep(Duration::from_millis(20));
            7
        });
        std::thread::sleep(Duration::from_millis(5));
        assert_eq!(t.get(), 7);
    }

    #[test]
    fn a_panic_comes_back_to_the_caller() {
        let t = task(|| -> u8 { panic!("in the job") });
        std::thread::sleep(Duration::from_millis(10));
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| t.get()));
        assert!(r.is_err());
        // Run by the caller: the same.
        let t = task(|| -> u8 { panic!("in the job") });
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| t.get()));
        assert!(r.is_err());
    }

    /// Dropped unfinished: a running job is waited for (what it borrows stays alive), a
    /// queued one never runs.
    #[test]
    fn dropping_waits_for_a_running_job() {
        let (started, ran) = (AtomicBool::new(false), AtomicBool::new(false));
        let t = task(|| {
            started.store(true, Ordering::SeqCst);
            std::thread::sleep(Duration::from_millis(20));
            ran.store(true, Ordering::SeqCst);
        });
        // Running (a busy machine may start the helper late; not started, it is cancelled).
        while !started.load(Ordering::SeqCst) {
            std::thread::sleep(Duration::from_millis(1));
        }
        drop(t);
        assert!(ran.load(Ordering::SeqCst));
        // Cancelled while queued: a thread coming late finds nothing to run.
        let never = AtomicBool::new(false);
        let t = queued(|| never.store(true, Ordering::SeqCst));
        let late = Arc::clone(&t.shared);
        drop(t);
        run(&late);
        assert!(!never.load(Ordering::SeqCst));
        // Taken back by the caller: the same.
        let t = queued(|| 5);
        let late = Arc::clone(&t.shared);
        assert_eq!(t.get(), 5);
        run(&late);
        assert!(!late.done.load(Ordering::SeqCst));
    }
}
