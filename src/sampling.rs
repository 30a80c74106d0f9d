//! Sampling shared by every renderer and resampler: mesh textures and camera
//! pictures are read between their texels with the same bilinear blend.

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
