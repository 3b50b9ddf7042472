//! Two jobs at once, the second one on another CPU from its first instruction.
//!
//! Why not `std::thread::scope` alone: Linux often queues a new thread on its parent's CPU,
//! where it waits until the parent blocks; on a 2-vCPU VM, 60 % of such threads started
//! only when the parent joined them (0.5 ms late in a 0.5 ms job: no parallelism at all).
//! So the helper is placed on another CPU the process may use before it first runs, and
//! takes back every CPU as soon as it does (it may still move later, as any thread).
//! Measured (BENCHMARKS.md, "First compile, third pass"): it then starts 60-180 µs after
//! the spawn, the time an idle vCPU takes to wake, and sometimes much later; so a job the
//! helper has not started by the time its result is needed is run by the caller
//! (`task`).

mod task;

pub use task::{task, Task};

/// Runs `a` on a new thread, placed on another CPU, and `b` on this one; returns both
/// results. `a` runs here after `b` instead when the thread has not started it by then
/// ([`Task`]). A panic in either is resumed here, after both have ended (or, when `b`
/// panics first, with `a` cancelled if it had not started).
pub fn join<RA, RB>(a: impl FnOnce() -> RA + Send, b: impl FnOnce() -> RB) -> (RA, RB)
where
    RA: Send,
{
    let a = task(a);
    let rb = b();
    (a.get(), rb)
}

/// `f` of every item on two threads (as in [`join`]), each taking the next item from a
/// shared counter as it comes free; the results in the items' order.
pub fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let next = AtomicUsize::new(0);
    let run = || {
        let mut done = Vec::new();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(i) else { break };
            done.push((i, f(item)));
        }
        done
    };
    let (mut done, here) = join(run, run);
    done.extend(here);
    done.sort_unstable_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, r)| r).collect()
}

/// [`map`], the two threads starting at opposite ends of `items` and meeting in between:
/// for work where neighbours contend, such as creating files, which in one directory take
/// turns on its lock.
pub fn map_ends<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    // Front and back of what is left.
    let left = std::sync::Mutex::new((0, items.len()));
    let run = |from_back: bool| {
        let (f, left) = (&f, &left);
        move || {
            let mut done = Vec::new();
            loop {
                let i = {
                    let mut l = left.lock().unwrap_or_else(|e| e.into_inner());
                    if l.0 >= l.1 {
                        break;
                    }
                    if from_back {
                        l.1 -= 1;
                        l.1
                    } else {
                        l.0 += 1;
                        l.0 - 1
                    }
                };
                done.push((i, f(&items[i])));
            }
            done
        }
    };
    let (mut done, here) = join(run(true), run(false));
    done.extend(here);
    done.sort_unstable_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, r)| r).collect()
}

/// A named thread (as [`std::thread::Builder::spawn`]: an error when none can be made),
/// placed on another CPU (as in [`join`]).
pub fn spawn<T: Send + 'static>(
    name: &str,
    f: impl FnOnce() -> T + Send + 'static,
) -> std::io::Result<std::thread::JoinHandle<T>> {
    let cpus = Placement::now();
    let h = std::thread::Builder::new()
        .name(name.into())
        .spawn(move || {
            cpus.restore();
            crate::heap::prepare_thread();
            f()
        })?;
    cpus.move_away(&h);
    Ok(h)
}

/// How many CPUs this thread may run on: its affinity mask, one syscall. Not the cgroup's
/// CPU quota, which `std::thread::available_parallelism` also reads (a dozen syscalls on
/// files under /proc and /sys); enough for choosing between one thread and two.
pub fn cpus() -> usize {
    #[cfg(target_os = "linux")]
    if let Some(set) = Placement::now().allowed {
        // SAFETY: CPU_COUNT only reads the set.
        return usize::try_from(unsafe { libc::CPU_COUNT(&set) }).map_or(1, |n| n.max(1));
    }
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The CPUs this thread may run on, and the one it runs on.
#[derive(Clone, Copy)]
struct Placement {
    #[cfg(target_os = "linux")]
    allowed: Option<libc::cpu_set_t>,
    #[cfg(target_os = "linux")]
    here: i32,
}

impl Placement {
    fn now() -> Placement {
        #[cfg(target_os = "linux")]
        // SAFETY: plain syscalls with a zeroed out-parameter of the right size.
        unsafe {
            let mut set: libc::cpu_set_t = std::mem::zeroed();
            let ok = libc::sched_getaffinity(0, std::mem::size_of_val(&set), &mut set) == 0;
            Placement {
                allowed: ok.then_some(set),
                here: libc::sched_getcpu(),
            }
        }
        #[cfg(not(target_os = "linux"))]
        Placement {}
    }

    /// Makes the thread behind `h` (not yet running, or just started) run on one of the
    /// allowed CPUs other than this one; nothing when there is none.
    fn move_away<T>(&self, h: &std::thread::JoinHandle<T>) {
        #[cfg(target_os = "linux")]
        {
            let (Some(mut set), Ok(here)) = (self.allowed, usize::try_from(self.here)) else {
                return;
            };
            if here >= libc::CPU_SETSIZE as usize {
                return;
            }
            // SAFETY: CPU_* only touch the set; the pthread is alive (not yet joined).
            unsafe {
                libc::CPU_CLR(here, &mut set);
                if libc::CPU_COUNT(&set) > 0 {
                    use std::os::unix::thread::JoinHandleExt;
                    let t = h.as_pthread_t();
                    libc::pthread_setaffinity_np(t, std::mem::size_of_val(&set), &set);
                }
            }
        }
        #[cfg(not(target_os = "linux"))]
        let _ = h;
    }

    /// On the new thread: may run anywhere the parent could.
    fn restore(&self) {
        #[cfg(target_os = "linux")]
        if let Some(set) = self.allowed {
            // SAFETY: a plain syscall on the calling thread with a valid set.
            unsafe {
                libc::sched_setaffinity(0, std::mem::size_of_val(&set), &set);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_results_come_back_and_borrows_work() {
        let data: Vec<u64> = (1..=1000).collect();
        let (a, b) = join(
            || data.iter().filter(|&&x| x % 2 == 0).sum::<u64>(),
            || data.iter().filter(|&&x| x % 2 == 1).sum::<u64>(),
        );
        assert_eq!((a, b), (250_500, 250_000));
        let squares = map(&data, |x| x * x);
        assert_eq!(squares.len(), 1000);
        assert!(squares.iter().zip(&data).all(|(s, x)| *s == x * x));
        let h = spawn("answer", || {
            (std::thread::current().name().map(str::to_owned), 6 * 7)
        });
        let (name, answer) = h.unwrap().join().unwrap();
        assert_eq!((name.as_deref(), answer), (Some("answer"), 42));
    }

    /// The count follows the thread's affinity mask: all allowed CPUs, then one.
    #[cfg(target_os = "linux")]
    #[test]
    fn cpus_counts_the_allowed_cpus() {
        let all = cpus();
        assert!(
            all >= 1
                && all
                    <= std::thread::available_parallelism()
                        .map_or(1, |n| n.get())
                        .max(all)
        );
        std::thread::spawn(|| {
            // SAFETY: plain syscalls on this thread with a valid set.
            unsafe {
                let mut set: libc::cpu_set_t = std::mem::zeroed();
                assert_eq!(
                    libc::sched_getaffinity(0, std::mem::size_of_val(&set), &mut set),
                    0
                );
                let first = (0..libc::CPU_SETSIZE as usize)
                    .find(|&c| libc::CPU_ISSET(c, &set))
                    .unwrap();
                libc::CPU_ZERO(&mut set);
                libc::CPU_SET(first, &mut set);
                assert_eq!(
                    libc::sched_setaffinity(0, std::mem::size_of_val(&set), &set),
                    0
                );
            }
            assert_eq!(cpus(), 1);
        })
        .join()
        .unwrap();
    }

    /// From both ends: every item once, results in order, each thread on one end's run.
    #[test]
    fn map_ends_takes_each_item_once_from_both_ends() {
        for n in [0usize, 1, 2, 3, 100] {
            let items: Vec<usize> = (0..n).collect();
            let who = map_ends(&items, |&i| (i, std::thread::current().id()));
            assert_eq!(who.iter().map(|w| w.0).collect::<Vec<_>>(), items);
            // The thread that made item 0 made a prefix; the other one the rest.
            if let Some(first) = who.first().map(|w| w.1) {
                let prefix = who.iter().take_while(|w| w.1 == first).count();
                assert!(who[prefix..].iter().all(|w| w.1 != first), "{n}");
            }
        }
    }

    #[test]
    fn a_panic_on_either_side_reaches_the_caller_after_both_ended() {
        let done = std::sync::atomic::AtomicBool::new(false);
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            join(
                || panic!("helper"),
                || done.store(true, std::sync::atomic::Ordering::SeqCst),
            )
        }));
        assert!(r.is_err());
        assert!(done.load(std::sync::atomic::Ordering::SeqCst));
        let r = std::panic::catch_unwind(|| join(|| 1, || -> u8 { panic!("here") }));
        assert!(r.is_err());
    }

    /// The helper is held off every CPU but the caller's, then may run anywhere again.
    #[cfg(target_os = "linux")]
    #[test]
    fn the_helper_is_placed_away_then_released() {
        fn affinity(t: libc::pthread_t) -> libc::cpu_set_t {
            // SAFETY: a zeroed set of the right size, filled by the call.
            unsafe {
                let mut set: libc::cpu_set_t = std::mem::zeroed();
                assert_eq!(
                    libc::pthread_getaffinity_np(t, std::mem::size_of_val(&set), &mut set),
                    0
                );
                set
            }
        }
        let cpus = Placement::now();
        let (Some(allowed), Ok(here)) = (cpus.allowed, usize::try_from(cpus.here)) else {
            return;
        };
        // SAFETY: reads a plain set.
        if unsafe { libc::CPU_COUNT(&allowed) } < 2 {
            eprintln!("skipped: a single CPU, nowhere else to place the helper");
            return;
        }
        let go = std::sync::Barrier::new(2);
        let (tx, rx) = std::sync::mpsc::channel();
        let helper = || {
            go.wait();
            cpus.restore();
            // SAFETY: the calling thread's own id.
            tx.send(affinity(unsafe { libc::pthread_self() })).unwrap();
        };
        // SAFETY: joined below, before `go` and `tx` go.
        let h = unsafe { std::thread::Builder::new().spawn_unchecked(helper) }.unwrap();
        cpus.move_away(&h);
        use std::os::unix::thread::JoinHandleExt;
        let placed = affinity(h.as_pthread_t());
        // SAFETY: reads plain sets.
        unsafe {
            assert!(!libc::CPU_ISSET(here, &placed), "still allowed on {here}");
            assert_eq!(libc::CPU_COUNT(&placed), libc::CPU_COUNT(&allowed) - 1);
        }
        go.wait();
        let released = rx.recv().unwrap();
        h.join().unwrap();
        // SAFETY: reads plain sets.
        unsafe {
            assert!(libc::CPU_EQUAL(&released, &allowed));
        }
    }
}
