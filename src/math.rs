//! 3-vectors and small matrices, once for the whole crate.
//!
//! Vectors are plain arrays, `[f64; 3]` ([`Vec3`]) and, in the fast shader,
//! `[f32; 3]` ([`Vec3f`]): the scene, rig and HoloFlick data already hold
//! them that way, so nothing converts at the boundaries. The vector helpers
//! are generic over [`Real`] (`f32` and `f64`) and do the same arithmetic in
//! both.
//!
//! # Matrix convention
//!
//! Matrices are **row-major**: `m[row][column]`, acting on column vectors,
//! `p′ = M · p`. A 4×4 transform ([`Mat4`]) is affine: its linear part is the
//! upper-left 3×3 ([`linear`]), its translation the last column
//! (`m[0][3], m[1][3], m[2][3]`) and its last row `0 0 0 1`. Placement
//! matrices, the HoloFlick container's object transforms (spec/holoflick.md)
//! and glTF node transforms all read this way: glTF stores its matrices
//! column by column, and the loader transposes them as it reads them.
//!
//! # Arithmetic order
//!
//! Every helper does its floating-point operations in one fixed order,
//! spelled out in its documentation, with no fused multiply-add: the frozen
//! `.holo`, `.hflk` and `.cg` bytes follow from meshes through placement,
//! dicing, baking and rendering, and depend on the last bit. For the same
//! reason there are two normalisations: [`normalize_or`] multiplies by the
//! reciprocal of the length (the shaders' form, one division), [`unit()`]
//! divides each component by the length (the loaders' form, each component
//! correctly rounded).

use std::ops::{Add, Div, Mul, Sub};

/// A 3-vector in double precision (positions in metres, directions).
pub type Vec3 = [f64; 3];
/// A 3-vector in single precision (the fast shader's normals and directions).
pub type Vec3f = [f32; 3];
/// A 3×3 matrix, row-major (`m[row][column]`, `v′ = M · v`).
pub type Mat3 = [[f64; 3]; 3];
/// An affine 4×4 transform, row-major (`m[row][column]`,
/// `p′ = M · (x, y, z, 1)ᵀ`): translation in the last column, last row
/// `0 0 0 1`. See the module documentation for the convention.
pub type Mat4 = [[f64; 4]; 4];

/// The identity transform.
pub const IDENTITY4: Mat4 = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];

/// The float types the vector helpers work in (`f32` and `f64`).
pub trait Real:
    Copy + PartialOrd + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// 1.
    const ONE: Self;
    /// ½.
    const HALF: Self;
    /// Zero.
    const ZERO: Self;
    /// The square root.
    fn sqrt(self) -> Self;
    /// Neither infinite nor NaN.
    fn is_finite(self) -> bool;
}

macro_rules! real {
    ($($t:ty),*) => {$(
        impl Real for $t {
            const ONE: Self = 1.0;
            const HALF: Self = 0.5;
            const ZERO: Self = 0.0;
            #[inline]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
        }
    )*};
}
real!(f32, f64);

/// `a + b`.
#[inline]
pub fn add<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
#[inline]
pub fn sub<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Component by component, `(a₀b₀, a₁b₁, a₂b₂)` (colours).
#[inline]
pub fn mul<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}

/// `s · a`, each component `aᵢ · s`.
#[inline]
pub fn scale<T: Real>(a: [T; 3], s: T) -> [T; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `(a₀b₀ + a₁b₁) + a₂b₂`.
#[inline]
pub fn dot<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`, each component `aᵢbⱼ − aⱼbᵢ`.
#[inline]
pub fn cross<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// `|a| = √(a · a)`.
#[inline]
pub fn length<T: Real>(a: [T; 3]) -> T {
    dot(a, a).sqrt()
}

/// `|a − b|`.
#[inline]
pub fn distance<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    length(sub(a, b))
}

/// `(a + b) · ½`, component by component.
#[inline]
pub fn midpoint<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [(a[0] + b[0]) * T::HALF, (a[1] + b[1]) * T::HALF, (a[2] + b[2]) * T::HALF]
}

/// `a · (1/|a|)`, or `fallback` when the length is zero, infinite or NaN.
#[inline]
pub fn normalize_or<T: Real>(a: [T; 3], fallback: [T; 3]) -> [T; 3] {
    let l = length(a);
    if l > T::ZERO && l.is_finite() {
        scale(a, T::ONE / l)
    } else {
        fallback
    }
}

/// [`normalize_or`] falling back to `+z` (toward the viewer).
#[inline]
pub fn normalize<T: Real>(a: [T; 3]) -> [T; 3] {
    normalize_or(a, [T::ZERO, T::ZERO, T::ONE])
}

/// `a / |a|` (each component divided), or `None` when the length is zero,
/// infinite or NaN.
#[inline]
pub fn unit<T: Real>(a: [T; 3]) -> Option<[T; 3]> {
    let l = length(a);
    (l > T::ZERO && l.is_finite()).then(|| [a[0] / l, a[1] / l, a[2] / l])
}

/// An `f32` vector in `f64` (exact).
#[inline]
pub fn widen(v: Vec3f) -> Vec3 {
    [v[0] as f64, v[1] as f64, v[2] as f64]
}

/// An `f64` vector rounded to `f32`.
#[inline]
pub fn narrow(v: Vec3) -> Vec3f {
    [v[0] as f32, v[1] as f32, v[2] as f32]
}

/// `Mᵀ`.
pub fn transpose<const N: usize>(m: &[[f64; N]; N]) -> [[f64; N]; N] {
    std::array::from_fn(|r| std::array::from_fn(|c| m[c][r]))
}

/// `A · B`; each entry `Σₖ A[i][k]·B[k][j]` summed in increasing `k` (by
/// `Iterator::sum`).
pub fn mat_mul<const N: usize>(a: &[[f64; N]; N], b: &[[f64; N]; N]) -> [[f64; N]; N] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..N).map(|k| a[i][k] * b[k][j]).sum()))
}

/// The rotation about x, then y, then z by `angles_rad` (`Rz·Ry·Rx`, the
/// Euler XYZ order of placements and of Blender), each factor turning
/// counter-clockwise about its axis seen from the axis's positive end.
pub fn rotation_xyz(angles_rad: [f64; 3]) -> Mat3 {
    let (sx, cx) = angles_rad[0].sin_cos();
    let (sy, cy) = angles_rad[1].sin_cos();
    let (sz, cz) = angles_rad[2].sin_cos();
    let rx = [[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]];
    let ry = [[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]];
    let rz = [[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]];
    mat_mul(&rz, &mat_mul(&ry, &rx))
}

/// The linear part of an affine transform (its upper-left 3×3).
pub fn linear(m: &Mat4) -> Mat3 {
    [[m[0][0], m[0][1], m[0][2]], [m[1][0], m[1][1], m[1][2]], [m[2][0], m[2][1], m[2][2]]]
}

/// `M · v`: each component the [`dot`] of a row with `v`.
pub fn mat3_apply(m: &Mat3, v: Vec3) -> Vec3 {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}

/// `Mᵀ · v`: each component `(m[0][i]·v₀ + m[1][i]·v₁) + m[2][i]·v₂` (a
/// rotation's inverse, e.g. camera frame to world).
pub fn mat3_transpose_apply(m: &Mat3, v: Vec3) -> Vec3 {
    [0, 1, 2].map(|i| m[0][i] * v[0] + m[1][i] * v[1] + m[2][i] * v[2])
}

/// The point `p` moved by `m`: the linear part's row dotted with `p`, then
/// the translation added.
pub fn transform_point(m: &Mat4, p: Vec3) -> Vec3 {
    [0, 1, 2].map(|r| m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3])
}

/// The direction (or tangent) `d` turned by `m`'s linear part (no
/// translation, not renormalised).
pub fn transform_direction(m: &Mat4, d: Vec3) -> Vec3 {
    mat3_apply(&linear(m), d)
}

/// The translation of an affine transform (its last column).
pub fn translation(m: &Mat4) -> Vec3 {
    [m[0][3], m[1][3], m[2][3]]
}

/// The determinant, expanded along the first row:
/// `m₀₀(m₁₁m₂₂ − m₁₂m₂₁) − m₀₁(m₁₀m₂₂ − m₁₂m₂₀) + m₀₂(m₁₀m₂₁ − m₁₁m₂₀)`.
pub fn det3(m: &Mat3) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// The cofactor matrix, `det(M) · M⁻ᵀ`: entry `(r, c)` is
/// `m[r+1][c+1]·m[r+2][c+2] − m[r+1][c+2]·m[r+2][c+1]` (indices mod 3). It
/// maps normals as the inverse transpose does up to the factor `det(M)`,
/// and exists for singular matrices too.
pub fn cofactor3(m: &Mat3) -> Mat3 {
    std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            let (r1, r2, c1, c2) = ((r + 1) % 3, (r + 2) % 3, (c + 1) % 3, (c + 2) % 3);
            m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]
        })
    })
}

/// `M⁻ᵀ`, which maps normals: [`cofactor3`] with every entry divided by
/// [`det3`]; `None` when the determinant is zero or not finite.
pub fn inverse_transpose3(m: &Mat3) -> Option<Mat3> {
    let det = det3(m);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some(cofactor3(m).map(|row| row.map(|c| c / det)))
}

/// A plane: a point of it and its unit normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane.
    pub point: Vec3,
    /// Its unit normal.
    pub normal: Vec3,
}

impl Plane {
    /// Where the ray `origin + t·direction` (any `t`, behind the origin
    /// too) crosses the plane, or `None` where it runs parallel to it.
    pub fn crossing(&self, origin: Vec3, direction: Vec3) -> Option<Vec3> {
        let t = dot(sub(self.point, origin), self.normal) / dot(direction, self.normal);
        t.is_finite().then(|| add(origin, scale(direction, t)))
    }
}

/// The mean of points (each divided by the count first, in order).
pub fn mean(v: &[[f64; 3]]) -> [f64; 3] {
    let n = v.len().max(1) as f64;
    let mut m = [0.0; 3];
    for p in v {
        for k in 0..3 {
            m[k] += p[k] / n;
        }
    }
    m
}

/// The principal axes of points (unit, by decreasing spread), the
/// standard deviations along them, and the largest distance from their mean.
pub fn principal_axes(points: &[[f64; 3]]) -> ([[f64; 3]; 3], [f64; 3], f64) {
    let m = mean(points);
    let mut cov = [[0.0; 3]; 3];
    let mut extent = 0.0f64;
    for p in points {
        let d = sub(*p, m);
        extent = extent.max(length(d));
        for a in 0..3 {
            for b in 0..3 {
                cov[a][b] += d[a] * d[b] / points.len() as f64;
            }
        }
    }
    let (vectors, values) = symmetric_eigen(cov);
    (vectors, values.map(|x| x.max(0.0).sqrt()), extent)
}

/// Eigenvectors (rows, unit) and eigenvalues of a symmetric 3 × 3 matrix,
/// by decreasing eigenvalue: cyclic Jacobi rotations, f64, to convergence.
pub fn symmetric_eigen(mut a: [[f64; 3]; 3]) -> ([[f64; 3]; 3], [f64; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..64 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-15 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
            // A ← Jᵀ A J with J the rotation in the (p, q) plane.
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * rp[k] - s * rq[k];
                a[q][k] = s * rp[k] + c * rq[k];
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // Columns of v are the eigenvectors.
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let vectors = order.map(|i| [v[0][i], v[1][i], v[2][i]]);
    (vectors, order.map(|i| a[i][i]))
}

/// `x` with `m · x = r` by Cramer's rule, or `None` when `m` is singular
/// (its determinant NaN or below 1e-9 of its largest entry cubed).
pub fn solve3(m: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let det = det3(&m);
    let scale_m = m.iter().flatten().fold(0.0f64, |a, &b| a.max(b.abs()));
    if det.is_nan() || det.abs() <= 1e-9 * scale_m.powi(3) {
        return None;
    }
    // Cramer's rule, columns replaced by r.
    let col = |k: usize| -> f64 {
        let mut c = m;
        for i in 0..3 {
            c[i][k] = r[i];
        }
        det3(&c) / det
    };
    Some([col(0), col(1), col(2)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn random_mat3(rng: &mut impl Rng) -> Mat3 {
        std::array::from_fn(|_| std::array::from_fn(|_| rng.gen_range(-2.0..2.0)))
    }

    #[test]
    fn inverse_transpose_inverts_and_cofactors_scale_it() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        for _ in 0..1000 {
            let m = random_mat3(&mut rng);
            let Some(it) = inverse_transpose3(&m) else { continue };
            // Mᵀ · M⁻ᵀ = I.
            let product = mat_mul(&transpose(&m), &it);
            for (r, row) in product.iter().enumerate() {
                for (c, v) in row.iter().enumerate() {
                    let want = if r == c { 1.0 } else { 0.0 };
                    assert!((v - want).abs() < 1e-9 * (1.0 + 1.0 / det3(&m).abs()), "{m:?}: {product:?}");
                }
            }
            // det(A·B) = det A · det B.
            let n = random_mat3(&mut rng);
            let d = det3(&mat_mul(&m, &n));
            assert!((d - det3(&m) * det3(&n)).abs() < 1e-9 * (1.0 + d.abs()));
        }
        assert_eq!(inverse_transpose3(&[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]), None);
        assert_eq!(det3(&[[2.0, 0.0, 0.0], [0.0, -3.0, 0.0], [0.0, 0.0, 0.5]]), -3.0);
    }

    #[test]
    fn a_ray_crosses_a_plane_where_its_point_satisfies_the_plane_equation() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for _ in 0..1000 {
            let v = |rng: &mut rand_chacha::ChaCha8Rng| std::array::from_fn(|_| rng.gen_range(-2.0..2.0));
            let plane = Plane { point: v(&mut rng), normal: normalize(v(&mut rng)) };
            let (origin, direction) = (v(&mut rng), v(&mut rng));
            let Some(p) = plane.crossing(origin, direction) else { continue };
            // On the plane, and on the ray's line.
            let scale_of = 1.0 + length(p);
            assert!(
                dot(sub(p, plane.point), plane.normal).abs() < 1e-9 * scale_of,
                "{plane:?} {origin:?} {direction:?}"
            );
            assert!(length(cross(sub(p, origin), direction)) < 1e-9 * scale_of * (1.0 + length(direction)));
        }
        let floor = Plane { point: [0.0; 3], normal: [0.0, 0.0, 1.0] };
        assert_eq!(floor.crossing([1.0, 2.0, 3.0], [0.0, 0.0, -1.0]), Some([1.0, 2.0, 0.0]));
        assert_eq!(floor.crossing([1.0, 2.0, 3.0], [1.0, 0.0, 0.0]), None);
    }

    #[test]
    fn the_convention_is_row_major_with_translation_in_the_last_column() {
        let m: Mat4 = [[0.0, -1.0, 0.0, 5.0], [1.0, 0.0, 0.0, 6.0], [0.0, 0.0, 2.0, 7.0], [0.0, 0.0, 0.0, 1.0]];
        // A quarter turn about z, z doubled, then moved by (5, 6, 7).
        assert_eq!(transform_point(&m, [1.0, 0.0, 1.0]), [5.0, 7.0, 9.0]);
        assert_eq!(transform_direction(&m, [1.0, 0.0, 1.0]), [0.0, 1.0, 2.0]);
        assert_eq!(translation(&m), [5.0, 6.0, 7.0]);
        assert_eq!(mat_mul(&m, &IDENTITY4), m);
        // Composition: (A·B)·p = A·(B·p).
        let b: Mat4 = [[1.0, 0.0, 0.0, 1.0], [0.0, 3.0, 0.0, 0.0], [0.0, 0.0, 1.0, -1.0], [0.0, 0.0, 0.0, 1.0]];
        let p = [0.5, -2.0, 4.0];
        assert_eq!(transform_point(&mat_mul(&m, &b), p), transform_point(&m, transform_point(&b, p)));
        assert_eq!(mat3_transpose_apply(&linear(&m), transform_direction(&m, [1.0, 2.0, 0.0])), [1.0, 2.0, 0.0]);
    }

    #[test]
    fn the_two_normalisations_differ_only_in_rounding() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let mut differ = 0;
        for _ in 0..10_000 {
            let a: Vec3 = std::array::from_fn(|_| rng.gen_range(-10.0..10.0));
            let (r, d) = (normalize_or(a, [0.0; 3]), unit(a).unwrap());
            for k in 0..3 {
                assert!((r[k] - d[k]).abs() <= 2.0 * f64::EPSILON);
                assert_eq!(d[k], a[k] / length(a));
            }
            differ += usize::from(r != d);
        }
        // Both forms are in use; were they the same, one would do.
        assert!(differ > 0);
        assert_eq!(normalize_or([0.0; 3], [0.0, 0.0, 1.0]), [0.0, 0.0, 1.0]);
        assert_eq!(unit([f64::INFINITY, 0.0, 0.0]), None);
        assert_eq!(unit([0.0f32, 3.0, 4.0]), Some([0.0, 0.6, 0.8]));
    }
}
