//! What the benchmarks that time whole frames share.

use std::time::Instant;

use holo::geometry::Geometry;

/// `hololines` hololines from the middle of `g` (for timing slow references
/// on a band and scaling to a frame).
pub fn band(g: &Geometry, hololines: usize) -> Geometry {
    let first = (g.hololines - hololines) / 2;
    Geometry { hololines, hololine_top_y_m: g.hololine_y_m(first), ..g.clone() }
}

/// The fastest of `runs` calls of `f`, seconds.
pub fn time(runs: usize, mut f: impl FnMut()) -> f64 {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Seconds of CPU time the calling thread has used. On a shared machine
/// this leaves out the time other processes held the core, which wall time
/// (and so criterion) counts: single-threaded figures stay comparable
/// between runs. Falls back to wall time off Linux.
#[allow(dead_code)] // not every benchmark times one thread
pub fn thread_cpu_s() -> f64 {
    cpu_clock_s(CLOCK_THREAD_CPUTIME_ID)
}

/// Seconds of CPU time the whole process (every thread) has used: for
/// multi-threaded work on a shared machine, what [`thread_cpu_s`] is for one
/// thread. Falls back to wall time off Linux.
#[allow(dead_code)] // not every benchmark times the process
pub fn process_cpu_s() -> f64 {
    cpu_clock_s(CLOCK_PROCESS_CPUTIME_ID)
}

const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
const CLOCK_THREAD_CPUTIME_ID: i32 = 3;

/// The CPU-time clock `clock` (Linux `clock_gettime`), seconds.
fn cpu_clock_s(clock: i32) -> f64 {
    #[cfg(all(target_os = "linux", target_pointer_width = "64"))]
    {
        #[repr(C)]
        struct Timespec {
            seconds: i64,
            nanoseconds: i64,
        }
        extern "C" {
            fn clock_gettime(clock: i32, out: *mut Timespec) -> i32;
        }
        let mut t = Timespec { seconds: 0, nanoseconds: 0 };
        // SAFETY: clock_gettime writes one timespec (two 64-bit fields on
        // 64-bit Linux) through a pointer to a live, writable one.
        if unsafe { clock_gettime(clock, &mut t) } == 0 {
            return t.seconds as f64 + t.nanoseconds as f64 * 1e-9;
        }
    }
    let _ = clock;
    static START: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}

/// The fastest of `runs` calls of `f` in thread CPU time ([`thread_cpu_s`]), seconds.
#[allow(dead_code)]
pub fn cpu_time(runs: usize, mut f: impl FnMut()) -> f64 {
    (0..runs)
        .map(|_| {
            let t = thread_cpu_s();
            f();
            thread_cpu_s() - t
        })
        .fold(f64::INFINITY, f64::min)
}

/// The fastest of `runs` calls of `f` in the process's CPU time ([`process_cpu_s`]), seconds.
#[allow(dead_code)]
pub fn process_cpu_time(runs: usize, mut f: impl FnMut()) -> f64 {
    (0..runs)
        .map(|_| {
            let t = process_cpu_s();
            f();
            process_cpu_s() - t
        })
        .fold(f64::INFINITY, f64::min)
}
