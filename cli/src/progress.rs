//! The one progress reporter of the command line: a bar on stderr, drawn
//! only when stderr is a terminal (a log or a pipe gets nothing), fed by the
//! library's progress callbacks through [`Reporter::count`].

use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar showing the current phase: its name, how many of its steps
/// are done, and the time left. Cleared when dropped.
pub struct Reporter {
    /// Whether to draw at all.
    terminal: bool,
    /// The current phase's bar and its name and length: a new bar per
    /// phase, so a phase starts from its own name, length and time.
    bar: Mutex<(ProgressBar, String, u64)>,
    /// The largest count of the phase seen: threads report out of order.
    done: AtomicU64,
}

impl Reporter {
    /// A bar on stderr if it is a terminal, else a reporter that draws nothing.
    pub fn on_stderr() -> Reporter {
        Reporter {
            terminal: std::io::stderr().is_terminal(),
            bar: Mutex::new((ProgressBar::hidden(), String::new(), 0)),
            done: AtomicU64::new(0),
        }
    }

    /// `done` of `total` steps of the phase `name`: a new bar when the name
    /// or the total changes, else the count moves on.
    pub fn count(&self, name: &str, done: usize, total: usize) {
        if !self.terminal {
            return;
        }
        let (done, total) = (done as u64, total as u64);
        let mut current = self.bar.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if current.1 != name || current.2 != total {
            let style = ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len}, {eta} left")
                .expect("a valid template")
                .progress_chars("=> ");
            let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr())
                .with_style(style)
                .with_message(name.to_string());
            self.done.store(0, Ordering::Relaxed);
            std::mem::replace(&mut *current, (bar, name.to_string(), total)).0.finish_and_clear();
        }
        let before = self.done.fetch_max(done, Ordering::Relaxed);
        if done > before || done == 0 {
            current.0.set_position(done);
        }
    }

    /// A library callback `(done, total)` counting the steps of `name`.
    pub fn counter<'a>(&'a self, name: &'a str) -> impl Fn(usize, usize) + Sync + 'a {
        move |done, total| self.count(name, done, total)
    }
}

impl Drop for Reporter {
    fn drop(&mut self) {
        self.bar.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).0.finish_and_clear();
    }
}
