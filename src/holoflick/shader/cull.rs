//! Work a frame does not need: objects no ray of the display can meet, and
//! triangles whose front faces away from every allowed viewpoint.
//!
//! Both tests are conservative: they may keep what is invisible, never drop
//! what is seen, so a frame converts to the same samples with them or
//! without them (the renderers draw only what rays meet).

use crate::geometry::Geometry;
use crate::mesh::Object;

/// Whether some ray of `g` (any hololine, emitter aperture, view, and the
/// supersampling around them) may meet the axis-aligned box `[lo, hi]`
/// (display metres). Rays are whole lines: content on either side of the
/// emitter plane is seen.
///
/// Over the box's depth range every ray lies, horizontally, between the
/// extremes of `x(z) = x_e + tan θ · (z − z_e)` and, vertically, of
/// `y(z) = y_j + (y_v − y_j)(z − z_e)/(z_v − z_e)` (every ray of hololine
/// `j` goes through the viewer line at height `y_v`, depth `z_v`). Both are
/// bilinear in (position, depth), so the extremes are at the corners of the
/// domain: the box is unseen when its `x` or `y` extent misses them.
pub fn display_sees_box(g: &Geometry, lo: [f64; 3], hi: [f64; 3]) -> bool {
    if (0..3).any(|k| lo[k].is_nan() || hi[k].is_nan()) {
        return true; // unknown: keep
    }
    if (0..3).any(|k| lo[k] > hi[k]) {
        return false; // empty
    }
    let (e_first, e_last) = (g.emitter_x_m(0), g.emitter_x_m(g.emitters.saturating_sub(1)));
    let half_e = 0.5 * g.emitter_pitch_m.abs();
    let xs = [e_first.min(e_last) - half_e, e_first.max(e_last) + half_e];
    let (j_first, j_last) = (g.hololine_y_m(0), g.hololine_y_m(g.hololines.saturating_sub(1)));
    let half_j = 0.5 * g.hololine_pitch_m.abs();
    let ys = [j_first.min(j_last) - half_j, j_first.max(j_last) + half_j];
    // Slopes, widened by half a view spacing each side for view supersampling.
    let n = g.views.count;
    let (mut s_lo, mut s_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in 0..n {
        let s = g.ray_slope_x(v as f64);
        s_lo = s_lo.min(s);
        s_hi = s_hi.max(s);
    }
    let spacing = if n > 1 { (s_hi - s_lo) / (n - 1) as f64 } else { 0.0 };
    let slopes = [s_lo - 0.5 * spacing, s_hi + 0.5 * spacing];
    let z_e = g.emitter_z_m;
    // Rays rise or fall toward the viewer line; a geometry with that line on
    // the emitter plane (invalid) has no such slope: keep its rays level.
    let slope_y = |y: f64| if g.viewer_distance_m != z_e { g.ray_slope_y(y) } else { 0.0 };
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for z in [lo[2], hi[2]] {
        let dz = z - z_e;
        for x in xs {
            for s in slopes {
                let at = x + s * dz;
                x_lo = x_lo.min(at);
                x_hi = x_hi.max(at);
            }
        }
        for y in ys {
            let at = y + slope_y(y) * dz;
            y_lo = y_lo.min(at);
            y_hi = y_hi.max(at);
        }
    }
    if !(x_lo.is_finite() && x_hi.is_finite() && y_lo.is_finite() && y_hi.is_finite()) {
        return true;
    }
    hi[0] >= x_lo && lo[0] <= x_hi && hi[1] >= y_lo && lo[1] <= y_hi
}

/// Drop the triangles of one-sided objects whose front faces away from every
/// point of the convex set spanned by `viewpoints` (for a box, its eight
/// corners: a plane splits space in two, so the front is seen from some
/// point of the set exactly when it is seen from one of its corners).
/// Returns the triangles dropped.
pub fn cull_back_faces(objects: &mut [Object], viewpoints: &[[f64; 3]]) -> u64 {
    let mut dropped = 0;
    for o in objects.iter_mut().filter(|o| !o.material.double_sided) {
        let before = o.triangles.len();
        let positions = &o.positions;
        o.triangles.retain(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let (u, v) = ([b[0] - a[0], b[1] - a[1], b[2] - a[2]], [c[0] - a[0], c[1] - a[1], c[2] - a[2]]);
            let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
            // Degenerate or not finite: keep (the renderers decide).
            if !n.iter().all(|x| x.is_finite()) || n == [0.0; 3] {
                return true;
            }
            viewpoints.iter().any(|p| n[0] * (p[0] - a[0]) + n[1] * (p[1] - a[1]) + n[2] * (p[2] - a[2]) > 0.0)
        });
        dropped += (before - o.triangles.len()) as u64;
    }
    dropped
}
