//! Progress of long calls: one interface for every library function that
//! takes long enough for a user to wonder whether it is still working.
//!
//! A call announces each phase of its work with [`Progress::phase`] (what it
//! counts, and how many there are) and then how many are done with
//! [`Progress::advance`]. Work runs on several threads, so a reporter is
//! `Sync`, and counts from different threads may arrive out of order: a
//! reporter shows the largest it has seen in the phase.
//!
//! ```
//! use holo::progress::{Counting, Progress, Silent};
//!
//! fn work(progress: &dyn Progress) {
//!     progress.phase("hololines", 3);
//!     for done in 1..=3 {
//!         progress.advance(done);
//!     }
//! }
//! work(&Silent);
//! let seen = std::sync::Mutex::new(Vec::new());
//! work(&Counting::new(|done, total| seen.lock().unwrap().push((done, total))));
//! assert_eq!(seen.into_inner().unwrap(), [(1, 3), (2, 3), (3, 3)]);
//! ```

use std::sync::atomic::{AtomicU64, Ordering};

/// Where a long call reports how far it is.
pub trait Progress: Sync {
    /// A phase of `total` steps begins; `name` says what a step is
    /// (`"hololines"`, `"frames"`, `"frame 3: hololines"`).
    fn phase(&self, name: &str, total: u64);
    /// `done` steps of the current phase are finished (a count, not an
    /// increment).
    fn advance(&self, done: u64);
    /// Whether the caller wants the work stopped: a long call checks between
    /// its steps and then returns [`crate::error::Error::Cancelled`], leaving
    /// nothing behind. Never, by default.
    fn cancelled(&self) -> bool {
        false
    }
}

/// Reports nothing: for callers that do not show progress.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn phase(&self, _name: &str, _total: u64) {}
    fn advance(&self, _done: u64) {}
}

/// Calls `f(done, total)` on every advance, `total` being the current
/// phase's: for a caller that only wants a fraction.
pub struct Counting<F> {
    f: F,
    total: AtomicU64,
}

impl<F: Fn(u64, u64) + Sync> Counting<F> {
    /// A reporter calling `f`.
    pub fn new(f: F) -> Self {
        Counting { f, total: AtomicU64::new(0) }
    }
}

impl<F: Fn(u64, u64) + Sync> Progress for Counting<F> {
    fn phase(&self, _name: &str, total: u64) {
        self.total.store(total, Ordering::Relaxed);
    }
    fn advance(&self, done: u64) {
        (self.f)(done, self.total.load(Ordering::Relaxed))
    }
}

/// Another reporter's phases named `"{label}: {name}"`: a call made for one
/// part of a larger job (a frame of a movie) says which part it is.
pub struct Labelled<'a> {
    inner: &'a dyn Progress,
    label: String,
}

impl<'a> Labelled<'a> {
    /// Phases of `inner`, prefixed with `label`.
    pub fn new(inner: &'a dyn Progress, label: impl Into<String>) -> Self {
        Labelled { inner, label: label.into() }
    }
}

impl Progress for Labelled<'_> {
    fn phase(&self, name: &str, total: u64) {
        self.inner.phase(&format!("{}: {name}", self.label), total);
    }
    fn advance(&self, done: u64) {
        self.inner.advance(done);
    }
    fn cancelled(&self) -> bool {
        self.inner.cancelled()
    }
}

/// One phase counted from any thread: each [`Steps::step`] is one more step
/// done.
pub struct Steps<'a> {
    progress: &'a dyn Progress,
    done: AtomicU64,
}

impl<'a> Steps<'a> {
    /// Begin the phase `name` of `total` steps on `progress`.
    pub fn begin(progress: &'a dyn Progress, name: &str, total: usize) -> Self {
        progress.phase(name, total as u64);
        Steps { progress, done: AtomicU64::new(0) }
    }

    /// Go on with the phase already begun on `progress`, `done` steps of it
    /// done (a frame rendered band by band: each band's steps follow the
    /// last's).
    pub fn continuing(progress: &'a dyn Progress, done: usize) -> Self {
        Steps { progress, done: AtomicU64::new(done as u64) }
    }

    /// Whether the reporter's caller wants the work stopped.
    pub fn cancelled(&self) -> bool {
        self.progress.cancelled()
    }

    /// One more step is done.
    pub fn step(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        self.progress.advance(done);
    }
}

/// Where a command's time went, stage by stage (`open`, `decode`, `render`,
/// `write`, `read`, `assemble`, `encode`), summed over its frames: what
/// `--timings` prints. Wall-clock time on the calling thread; a stage that
/// runs on several cores counts once.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timings {
    stages: Vec<(&'static str, std::time::Duration)>,
}

impl Timings {
    /// `time` more in `stage` (added to it, or a new stage after the others).
    pub fn add(&mut self, stage: &'static str, time: std::time::Duration) {
        match self.stages.iter_mut().find(|(s, _)| *s == stage) {
            Some((_, t)) => *t += time,
            None => self.stages.push((stage, time)),
        }
    }

    /// Every stage of `other` added.
    pub fn merge(&mut self, other: &Timings) {
        for &(stage, time) in &other.stages {
            self.add(stage, time);
        }
    }

    /// The time in `stage` (zero when it never ran).
    pub fn get(&self, stage: &str) -> std::time::Duration {
        self.stages.iter().find(|(s, _)| *s == stage).map_or(std::time::Duration::ZERO, |(_, t)| *t)
    }

    /// The stages in the order first seen.
    pub fn stages(&self) -> &[(&'static str, std::time::Duration)] {
        &self.stages
    }

    /// `f`'s result, its time added to `stage`.
    pub fn time<T>(&mut self, stage: &'static str, f: impl FnOnce() -> T) -> T {
        let started = std::time::Instant::now();
        let out = f();
        self.add(stage, started.elapsed());
        out
    }

    /// One line: each stage in seconds, and per frame when there are
    /// several (`decode 0.10 s, render 2.91 s, write 1.02 s; per frame 14 ms, 97 ms, 34 ms`).
    pub fn line(&self, frames: usize) -> String {
        let total: Vec<String> = self.stages.iter().map(|(s, t)| format!("{s} {:.2} s", t.as_secs_f64())).collect();
        let mut line = total.join(", ");
        if frames > 1 {
            let each: Vec<String> = self
                .stages
                .iter()
                .map(|(s, t)| format!("{s} {:.0} ms", 1e3 * t.as_secs_f64() / frames as f64))
                .collect();
            line += &format!("; per frame ({frames}): {}", each.join(", "));
        }
        line
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    #[test]
    fn labelled_steps_reach_the_total_from_many_threads() {
        let seen = Mutex::new(Vec::new());
        let names = Mutex::new(Vec::new());
        struct Record<'a>(&'a Mutex<Vec<u64>>, &'a Mutex<Vec<String>>);
        impl Progress for Record<'_> {
            fn phase(&self, name: &str, _total: u64) {
                self.1.lock().unwrap().push(name.to_string());
            }
            fn advance(&self, done: u64) {
                self.0.lock().unwrap().push(done);
            }
        }
        let record = Record(&seen, &names);
        let labelled = Labelled::new(&record, "frame 2");
        let steps = Steps::begin(&labelled, "hololines", 64);
        std::thread::scope(|s| {
            for _ in 0..4 {
                s.spawn(|| (0..16).for_each(|_| steps.step()));
            }
        });
        let mut seen = seen.into_inner().unwrap();
        seen.sort_unstable();
        assert_eq!(seen, (1..=64).collect::<Vec<u64>>());
        assert_eq!(names.into_inner().unwrap(), ["frame 2: hololines"]);
    }

    #[test]
    fn timings_add_up_by_stage_in_the_order_first_seen() {
        use std::time::Duration;
        let mut t = Timings::default();
        t.add("render", Duration::from_millis(300));
        t.add("write", Duration::from_millis(100));
        t.add("render", Duration::from_millis(300));
        let mut other = Timings::default();
        other.add("write", Duration::from_millis(50));
        other.add("decode", Duration::from_millis(30));
        t.merge(&other);
        assert_eq!(t.get("render"), Duration::from_millis(600));
        assert_eq!(t.get("write"), Duration::from_millis(150));
        assert_eq!(t.get("open"), Duration::ZERO);
        assert_eq!(
            t.line(3),
            "render 0.60 s, write 0.15 s, decode 0.03 s; per frame (3): render 200 ms, write 50 ms, decode 10 ms"
        );
        assert_eq!(t.line(1), "render 0.60 s, write 0.15 s, decode 0.03 s");
    }
}
