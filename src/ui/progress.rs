//! The one progress bar of every long command (`build`, `sim`, `sweep`): indicatif, one
//! look. It draws only on a terminal (never into logs or pipes) and not under `--quiet`;
//! whatever else a command prints while it runs goes through [`Progress::suspend`], so the
//! bar is cleared first and redrawn after.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

pub(crate) struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// A bar of `total` steps of `unit` ("maps", "runs", "s sim"); hidden unless `shown`
    /// and stderr is a terminal.
    pub(crate) fn new(total: u64, unit: &str, shown: bool) -> Progress {
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden());
        let template =
            format!("[{{bar:30}}] {{pos}}/{{len}} {unit} {{msg}} ({{elapsed}}, {{eta}} left)");
        if let Ok(style) = ProgressStyle::with_template(&template) {
            bar.set_style(style.progress_chars("=> "));
        }
        if shown && std::io::stderr().is_terminal() {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        Progress { bar }
    }

    /// Moves the bar to `pos` of its length, with `msg` after the count.
    pub(crate) fn set(&self, pos: u64, msg: String) {
        self.bar.set_position(pos);
        self.bar.set_message(msg);
    }

    /// Moves the bar to `pos` of `len` (a length known only as the work goes: `mapc sim`'s
    /// end time).
    pub(crate) fn update(&self, pos: u64, len: u64, msg: String) {
        self.bar.set_length(len);
        self.set(pos, msg);
    }

    /// Whether the bar is drawn at all (a command skips the work of feeding a hidden one).
    pub(crate) fn is_shown(&self) -> bool {
        !self.bar.is_hidden()
    }

    /// Runs `f` (which prints) with the bar cleared.
    pub(crate) fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.bar.suspend(f)
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}
