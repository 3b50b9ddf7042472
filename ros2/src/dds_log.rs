//! RustDDS's own log on stderr when `MAPC_DDS_LOG` is set (`error`, `warn`, `info`, `debug`
//! or `trace`): what discovery matched, what a writer repaired. For diagnosing a peer that
//! does not hear mapc; silent otherwise.

use log::{Level, Log, Metadata, Record};
use std::io::Write;
use std::time::Instant;

struct Stderr {
    start: Instant,
}

impl Log for Stderr {
    fn enabled(&self, m: &Metadata) -> bool {
        m.target().starts_with("rustdds")
    }

    fn log(&self, r: &Record) {
        if self.enabled(r.metadata()) {
            let t = self.start.elapsed().as_secs_f64();
            let _ = writeln!(
                std::io::stderr().lock(),
                "{t:9.4} {:5} {}: {}",
                r.level(),
                r.target(),
                r.args()
            );
        }
    }

    fn flush(&self) {}
}

/// Installs the logger once, if `MAPC_DDS_LOG` names a level.
pub fn init() {
    let Some(level) = std::env::var("MAPC_DDS_LOG")
        .ok()
        .and_then(|v| v.parse::<Level>().ok())
    else {
        return;
    };
    let logger = Box::leak(Box::new(Stderr {
        start: Instant::now(),
    }));
    if log::set_logger(logger).is_ok() {
        log::set_max_level(level.to_level_filter());
    }
}
