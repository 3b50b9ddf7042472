//! glibc's allocator, set up for a short batch run (`mapc gazebo`, `nav`, `build`, ...).
//!
//! Why: by default a thread's arena grows one `mprotect` per page it needs (about 200 on
//! clinic's helpers, each one splitting or merging a mapping), and buffers of 128 KiB or
//! more are fresh mappings, returned when freed and faulted in again by the next one. A run
//! that lasts milliseconds and frees nothing it could give back gains from neither.
//!
//! Huge pages: each 4 KiB page a run touches for the first time costs a page fault, and
//! work again to free it at exit, about 1.5 µs together on a VM; a map's run touches
//! 1-4 MiB of main heap, 250-1000 pages. So the main heap is laid out to be allocated from
//! a 2 MiB boundary on, in memory marked for transparent huge pages (`MADV_HUGEPAGE`): a
//! huge page is one fault (0.2 ms, mostly zeroing it) and one free. Where the kernel has
//! none, or they are off, the same memory comes in small pages, as before. Helper threads'
//! arenas stay in small pages: each touches a few hundred KiB. Measured in BENCHMARKS.md
//! (part 5, fourth and fifth passes).

use std::sync::atomic::{AtomicBool, Ordering};

static TUNED: AtomicBool = AtomicBool::new(false);

/// What a new thread's arena is grown by at once (address space only: pages are touched
/// when used).
const THREAD_ARENA: usize = 4 << 20;

/// A transparent huge page on x86-64 and arm64 (with 4 KiB base pages).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const HUGE_PAGE: usize = 2 << 20;

/// How far the main heap grows at a time with huge pages (from the start: the part in
/// huge pages).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MAIN_HEAP_STEP: usize = 8 << 20;

/// The largest map whose run gets huge pages (`tune_for_batch(true)`): every demo map and
/// nearly every real one. A larger map's run lasts long enough for its page faults not to
/// matter, and its memory is bounded by its size (10 times the file, issue 12), which a
/// 2 MiB page rounding counts against.
pub const HUGE_PAGES_UP_TO: u64 = 1 << 20;

/// Keeps large buffers in the heap (below 32 MiB), frees memory back to the system only
/// past 64 MiB at the top, and grows the main heap 1 MiB at a time; with `huge_pages`,
/// 8 MiB at a time and laid out for huge pages. For batch commands only: a long-lived
/// server should give memory back. A no-op off glibc.
pub fn tune_for_batch(huge_pages: bool) {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets allocator parameters; called before other threads exist.
    // `from_huge_boundary` only allocates, shrinks its own block, and advises memory that
    // the heap holds.
    unsafe {
        let ok = libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20) == 1
            && libc::mallopt(libc::M_TRIM_THRESHOLD, 64 << 20) == 1
            && libc::mallopt(
                libc::M_TOP_PAD,
                if huge_pages { MAIN_HEAP_STEP } else { 1 << 20 } as i32,
            ) == 1;
        TUNED.store(ok, Ordering::Relaxed);
        if ok && huge_pages {
            if let Some((from, _)) = from_huge_boundary(HUGE_PAGE) {
                // On the main heap (the main thread's arena, below the break), which grew
                // past the probe by a step: all of it to the break.
                let to = libc::sbrk(0) as usize & !(HUGE_PAGE - 1);
                if to > from {
                    libc::madvise(from as *mut libc::c_void, to - from, libc::MADV_HUGEPAGE);
                }
            }
        }
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    let _ = huge_pages;
}

/// Makes what this thread's arena allocates next start on a huge-page boundary, with at
/// least `room` bytes after it in the arena; the boundary and the end of those bytes
/// (rounded down to a huge page), or `None` when an allocation failed. A block larger than
/// any freed one comes from the arena's top; it is shrunk in place to end at the boundary
/// (the rest returns to the top, which then starts there) and kept: its bytes below the
/// boundary are address space only, never touched nor freed.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
unsafe fn from_huge_boundary(room: usize) -> Option<(usize, usize)> {
    let probe = libc::malloc(room + HUGE_PAGE).cast::<u8>();
    if probe.is_null() {
        return None;
    }
    let at = probe as usize;
    let boundary = (at + 64 + HUGE_PAGE - 1) & !(HUGE_PAGE - 1);
    // A block's bytes follow a 16-byte header: the top's header then ends at the boundary.
    if libc::realloc(probe.cast(), boundary - at - 16).is_null() {
        return None;
    }
    Some((boundary, (at + room + HUGE_PAGE) & !(HUGE_PAGE - 1)))
}

/// At the start of a helper thread: grows its arena once (one `mprotect` rather than one
/// per page). Only after [`tune_for_batch`], which keeps the block in the arena (not a
/// mapping of its own) and the arena grown once it is freed. Small pages: a helper touches
/// a few hundred KiB, which fault in faster than one huge page is zeroed (0.2 ms).
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
        super::tune_for_batch(true);
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

    /// After the layout, the arena's next block starts on the huge-page boundary, with the
    /// room asked for after it (a thread's arena here: the harness's main thread is not
    /// ours; `tune_for_batch` does the same on the main heap).
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    #[test]
    fn the_next_block_starts_on_a_huge_page() {
        super::tune_for_batch(true);
        std::thread::spawn(|| {
            // SAFETY: plain allocations, freed below; the probe block is kept, as in use.
            unsafe {
                let (from, to) = super::from_huge_boundary(4 << 20).unwrap();
                assert_eq!(from % super::HUGE_PAGE, 0, "{from:#x}");
                assert!(to >= from + (2 << 20), "{from:#x}..{to:#x}");
                let next = libc::malloc(3 << 20);
                assert_eq!(next as usize, from);
                libc::free(next);
            }
        })
        .join()
        .unwrap();
    }
}
