//! glibc's allocator, set up for a short batch run (`mapc gazebo`, `nav`, `build`, ...).
//!
//! Why: by default a thread's arena grows one `mprotect` per page it needs (about 200 on
//! clinic's helpers, each one splitting or merging a mapping), and buffers of 128 KiB or
//! more are fresh mappings, returned when freed and faulted in again by the next one. A run
//! that lasts milliseconds and frees nothing it could give back gains from neither.
//! Measured in BENCHMARKS.md (part 5, fourth pass).

use std::sync::atomic::{AtomicBool, Ordering};

static TUNED: AtomicBool = AtomicBool::new(false);

/// What a new thread's arena is grown by at once (address space only: pages are touched
/// when used).
const THREAD_ARENA: usize = 4 << 20;

/// Keeps large buffers in the heap (below 32 MiB), frees memory back to the system only
/// past 64 MiB at the top, and grows the main heap 1 MiB at a time. For batch commands
/// only: a long-lived server should give memory back. A no-op off glibc.
pub fn tune_for_batch() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets allocator parameters; called before other threads exist.
    unsafe {
        let ok = libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20) == 1
            && libc::mallopt(libc::M_TRIM_THRESHOLD, 64 << 20) == 1
            && libc::mallopt(libc::M_TOP_PAD, 1 << 20) == 1;
        TUNED.store(ok, Ordering::Relaxed);
    }
}

/// At the start of a helper thread: grows its arena once (one `mprotect` rather than one
/// per page). Only after [`tune_for_batch`], which keeps the block in the arena (not a
/// mapping of its own) and the arena grown once it is freed.
pub(crate) fn prepare_thread() {
    if TUNED.load(Ordering::Relaxed) {
        let block: Vec<u8> = Vec::with_capacity(THREAD_ARENA);
        // Not optimised away: the allocation is the point.
        drop(std::hint::black_box(block));
    }
}

#[cfg(test)]
mod tests {
    /// The set-up leaves allocation working, on this thread and a helper's.
    #[test]
    fn allocation_works_after_tuning() {
        super::tune_for_batch();
        let (a, b) = crate::par::join(
            || {
                (0..100_000u32)
                    .map(|i| i.to_string())
                    .collect::<Vec<_>>()
                    .len()
            },
            || {
                vec![7u8; 40 << 20]
                    .iter()
                    .map(|&x| usize::from(x))
                    .sum::<usize>()
            },
        );
        assert_eq!((a, b), (100_000, 7 * (40 << 20)));
    }
}
