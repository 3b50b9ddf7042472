//! SIGINT and SIGTERM. The handler only records the signal; a watcher thread does the rest
//! outside signal context: it removes the temporary files `output` has open and exits with
//! 128 + the signal number. `mapc sim` asks for one signal of grace instead: the first only
//! sets [`INTERRUPTED`] (the run loop stops at the current step and the command writes what
//! ran), a second one exits like the other commands.

use std::sync::atomic::{AtomicBool, AtomicI32, AtomicUsize, Ordering};

/// Set by the first SIGINT/SIGTERM.
pub static INTERRUPTED: AtomicBool = AtomicBool::new(false);
static SIGNAL: AtomicI32 = AtomicI32::new(0);
static COUNT: AtomicUsize = AtomicUsize::new(0);

#[cfg(unix)]
extern "C" fn on_signal(sig: libc::c_int) {
    // Only async-signal-safe work here: atomics.
    SIGNAL.store(sig, Ordering::SeqCst);
    INTERRUPTED.store(true, Ordering::SeqCst);
    COUNT.fetch_add(1, Ordering::SeqCst);
}

/// Installs the handlers. After `grace` signals have been stopped cooperatively, the next one
/// removes the temporaries and exits (`grace` 0: the first one does).
pub fn install(grace: usize) {
    #[cfg(unix)]
    unsafe {
        // SAFETY: the handler only touches atomics. std has no API to install a signal
        // handler.
        let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
        libc::signal(libc::SIGINT, handler);
        libc::signal(libc::SIGTERM, handler);
    }
    // The watcher, outside signal context: it may take locks and remove files.
    let _ = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || loop {
            if COUNT.load(Ordering::SeqCst) > grace {
                let sig = SIGNAL.load(Ordering::SeqCst);
                super::output::remove_temporaries_and_exit(128 + sig);
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        });
}
