//! The one progress reporter of the command line: a bar on stderr, drawn
//! only when stderr is a terminal (a log or a pipe gets nothing), fed by the
//! library's [`holo::progress::Progress`] calls.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};

use holo::progress::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar showing the current phase: its name, how many of its steps
/// are done, and the time left. Cleared when dropped.
pub struct Reporter {
    bar: ProgressBar,
    /// The largest count of the phase seen: threads report out of order.
    done: AtomicU64,
}

impl Reporter {
    /// A bar on stderr if it is a terminal, else a reporter that draws nothing.
    pub fn on_stderr() -> Reporter {
        let target =
            if std::io::stderr().is_terminal() { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
        let style = ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len}, {eta} left")
            .expect("a valid template")
            .progress_chars("=> ");
        Reporter { bar: ProgressBar::with_draw_target(Some(0), target).with_style(style), done: AtomicU64::new(0) }
    }
}

impl Progress for Reporter {
    fn phase(&self, name: &str, total: u64) {
        self.done.store(0, Ordering::Relaxed);
        self.bar.reset();
        self.bar.set_length(total);
        self.bar.set_message(name.to_string());
    }

    fn advance(&self, done: u64) {
        let before = self.done.fetch_max(done, Ordering::Relaxed);
        if done > before {
            self.bar.set_position(done);
        }
    }
}

impl Drop for Reporter {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}
