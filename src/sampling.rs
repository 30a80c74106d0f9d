//! Sampling shared by every renderer and resampler: mesh textures and camera
//! pictures are read between their texels with the same bilinear blend, and
//! samples between rows, emitters or views with the same linear taps.

/// Bilinear blend of the corners `[top left, top right, bottom left,
/// bottom right]` at fractions `fx`, `fy`, in one fixed order of
/// operations: every texture and picture lookup uses it, so the fast paths
/// can match the reference bit for bit.
#[inline(always)]
pub fn bilerp<const N: usize>(corners: [[f32; N]; 4], fx: f32, fy: f32) -> [f32; N] {
    let [a, b, c, d] = corners;
    let mut out = [0.0; N];
    for k in 0..N {
        let top = a[k] + (b[k] - a[k]) * fx;
        let bottom = c[k] + (d[k] - c[k]) * fx;
        out[k] = top + (bottom - top) * fy;
    }
    out
}

/// Linear interpolation taps of fractional index `f` among `n` samples
/// (views, emitters, hololines), each sample covering `±½` about its index:
/// the two samples either side and their weights, clamped to the first or
/// last sample within half a sample beyond them; `None` further outside.
/// A quilt's cameras and an eye's view of a light field read the stored
/// samples with it.
pub fn linear_taps(f: f64, n: usize) -> Option<[(usize, f32); 2]> {
    if !(-0.5..=n as f64 - 0.5).contains(&f) {
        return None;
    }
    if n == 1 {
        return Some([(0, 1.0), (0, 0.0)]);
    }
    let f = f.clamp(0.0, (n - 1) as f64);
    let i = (f.floor() as usize).min(n - 2);
    let t = (f - i as f64) as f32;
    Some([(i, 1.0 - t), (i + 1, t)])
}
