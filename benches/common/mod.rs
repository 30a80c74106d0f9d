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
