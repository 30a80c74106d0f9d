//! Normals as compressed geometry codes them: a sextant (which of six
//! triangles of an octant), an octant (the signs of x, y, z) and a point
//! `(u, v)` of a triangular grid of 64 steps per side, plus 14 special
//! normals (the 6 axes and the 8 diagonals). The representation is
//! Deering's (M. Deering, "Geometry Compression", SIGGRAPH 1995, its
//! section on normals: the sphere folded by the octant's signs and the
//! sextant's ordering of |x|, |y|, |z| onto one small patch, addressed by
//! (u, v) angles).
//!
//! The decoding table and the unfolding are Java 3D's
//! (`GeometryDecompressor`: static initialiser, `indexNormal`); the encoder's
//! search for the nearest code is ours.

use std::sync::OnceLock;

/// Java 3D's `NORMAL_MAX_Y_ANG` (rad): the largest `y` angle of sextant 0,
/// asin(1/√3).
pub(crate) const MAX_Y_ANGLE_RAD: f64 = 0.615479709;

/// A normal code as the decoder keeps it (`curSex`, `curOct`, `curU`, `curV`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct NormalCode {
    /// Sextant 0..=5; 6 and 7 mark the special normals.
    pub sextant: u8,
    /// Octant: bit 2 = x negative, bit 1 = y negative, bit 0 = z negative.
    pub octant: u8,
    /// Grid coordinate along the sextant's theta direction, 0..=64 (6-bit units).
    pub u: i32,
    /// Grid coordinate along the sextant's psi (y) direction, 0..=64.
    pub v: i32,
}

/// The 65 × 65 table, `[v][u]`, of sextant-0 normals truncated to s1.14
/// fixed point; entries with `u + v > 64` are zero, as in Java.
fn table() -> &'static [[[f64; 3]; 65]; 65] {
    static TABLE: OnceLock<Box<[[[f64; 3]; 65]; 65]>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut t = Box::new([[[0.0f64; 3]; 65]; 65]);
        let s1_14 = |c: f64| f64::from((c * 16384.0) as i32) / 16384.0;
        for (i, row) in t.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                if i + j > 64 {
                    continue;
                }
                let psi = MAX_Y_ANGLE_RAD * (i as f64 / 64.0);
                let th = (MAX_Y_ANGLE_RAD * ((64 - j) as f64 / 64.0)).tan().asin();
                *entry = [s1_14(th.cos() * psi.cos()), s1_14(psi.sin()), s1_14(th.sin() * psi.cos())];
            }
        }
        t
    })
}

/// Java 3D's table cast to f32 as `indexNormal` casts each entry, `[v][u]`.
pub(crate) type NormalTable = [[[f32; 3]; 65]; 65];

/// The f32 table, made once.
pub(crate) fn normal_table() -> &'static NormalTable {
    static TABLE32: OnceLock<Box<NormalTable>> = OnceLock::new();
    TABLE32.get_or_init(|| {
        let t = table();
        let mut f = Box::new([[[0.0f32; 3]; 65]; 65]);
        for (row, src) in f.iter_mut().zip(t.iter()) {
            for (e, s) in row.iter_mut().zip(src.iter()) {
                *e = [s[0] as f32, s[1] as f32, s[2] as f32];
            }
        }
        f
    })
}

/// The float normal of a code, with Java 3D's `indexNormal` arithmetic
/// (table in f64, cast to f32, then swaps and sign flips).
/// `None` when a regular code's `u` or `v` lies outside 0..=64, where Java
/// indexes past its table (ArrayIndexOutOfBoundsException).
#[inline]
pub(crate) fn index_normal(table: &NormalTable, code: NormalCode) -> Option<[f32; 3]> {
    let (mut nx, mut ny, mut nz);
    let mut oct = code.octant;
    if code.sextant > 5 {
        if oct & 1 == 0 {
            // The six axes.
            (nx, ny, nz) = match ((code.sextant & 1) << 1) | ((oct & 4) >> 2) {
                0 => (1.0f32, 0.0f32, 0.0f32),
                1 => (0.0, 1.0, 0.0),
                _ => (0.0, 0.0, 1.0),
            };
            let s = (oct & 2) >> 1;
            oct = (s << 2) | (s << 1) | s;
        } else {
            // The eight diagonals.
            oct = ((code.sextant & 1) << 2) | (oct >> 1);
            let c = (1.0f64 / 3.0f64.sqrt()) as f32;
            (nx, ny, nz) = (c, c, c);
        }
    } else {
        let u = usize::try_from(code.u).ok().filter(|&u| u <= 64)?;
        let v = usize::try_from(code.v).ok().filter(|&v| v <= 64)?;
        let e = table[v][u];
        (nx, ny, nz) = (e[0], e[1], e[2]);
        if code.sextant & 4 != 0 {
            std::mem::swap(&mut nx, &mut nz);
        }
        if code.sextant & 2 != 0 {
            std::mem::swap(&mut ny, &mut nz);
        }
        if code.sextant & 1 != 0 {
            std::mem::swap(&mut nx, &mut ny);
        }
    }
    if oct & 1 != 0 {
        nz = -nz;
    }
    if oct & 2 != 0 {
        ny = -ny;
    }
    if oct & 4 != 0 {
        nx = -nx;
    }
    Some([nx, ny, nz])
}

/// The code of the grid point nearest `n` (any length > 0) on the grid of
/// `2^bits` steps per side (`bits` in 0..=6), as decoded by
/// [`index_normal`]: the search covers the cells around the continuous
/// inverse of the table's mapping and keeps the largest dot product. Grid
/// corners that a 6-bit absolute `u`/`v` cannot hold become the special
/// axis and diagonal codes, as Java 3D's compressor does
/// (`CompressionStreamNormal.quantize`).
pub(crate) fn quantize_normal(n: [f32; 3], bits: u32) -> NormalCode {
    let (x, y, z) = (f64::from(n[0]), f64::from(n[1]), f64::from(n[2]));
    let len = (x * x + y * y + z * z).sqrt();
    let (mut x, mut y, mut z) =
        if len > 0.0 && len.is_finite() { (x / len, y / len, z / len) } else { (0.0, 1.0, 0.0) };
    let mut octant = 0u8;
    if x < 0.0 {
        octant |= 4;
        x = -x;
    }
    if y < 0.0 {
        octant |= 2;
        y = -y;
    }
    if z < 0.0 {
        octant |= 1;
        z = -z;
    }
    // Fold into sextant 0 (x >= z >= y) in the order the decoder undoes last-first.
    let mut sextant = 0u8;
    if x < y {
        std::mem::swap(&mut x, &mut y);
        sextant |= 1;
    }
    if z < y {
        std::mem::swap(&mut y, &mut z);
        sextant |= 2;
    }
    if x < z {
        std::mem::swap(&mut x, &mut z);
        sextant |= 4;
    }
    let steps = 1i32 << bits.min(6);
    let unit = 64 / steps;
    // Continuous inverse of the table: psi = asin(y), tan(MAXY (1 - u/64)) = sin(theta).
    let psi = y.clamp(-1.0, 1.0).asin();
    let theta = z.atan2(x);
    let vf = psi / MAX_Y_ANGLE_RAD * f64::from(steps);
    let uf = (1.0 - theta.sin().atan() / MAX_Y_ANGLE_RAD) * f64::from(steps);
    let (u0, v0) = (uf.floor() as i32, vf.floor() as i32);
    let mut best = (f64::NEG_INFINITY, 0, 0);
    let table = table();
    for j in (v0 - 1)..=(v0 + 2) {
        for i in (u0 - 1)..=(u0 + 2) {
            if i < 0 || j < 0 || i + j > steps {
                continue;
            }
            let e = table[(j * unit) as usize][(i * unit) as usize];
            let dot = e[0] * x + e[1] * y + e[2] * z;
            if dot > best.0 {
                best = (dot, i, j);
            }
        }
    }
    let (u, v) = (best.1 * unit, best.2 * unit);
    if u == 64 && v == 0 {
        // An axis: the largest component of the folded normal is x, which the
        // sextant's swaps send back to x, y or z.
        return match sextant {
            0 | 2 => NormalCode { sextant: 6, octant: if octant & 4 != 0 { 2 } else { 0 }, u: 0, v: 0 },
            1 | 3 => NormalCode { sextant: 6, octant: 4 | if octant & 2 != 0 { 2 } else { 0 }, u: 0, v: 0 },
            _ => NormalCode { sextant: 7, octant: if octant & 1 != 0 { 2 } else { 0 }, u: 0, v: 0 },
        };
    }
    if u == 0 && v == 64 {
        return NormalCode { sextant: 6 | (octant >> 2), octant: ((octant & 3) << 1) | 1, u: 0, v: 0 };
    }
    NormalCode { sextant, octant, u, v }
}

/// Angle (rad) within which the encoder's normal quantization at `bits` (0..=6)
/// reproduces any unit normal: half the diagonal of the coarsest grid cell
/// (the theta step is at most 2.13 times the psi step MAXY/2^bits, at
/// u = 0), times 1.8 because the grid is not affine in angle near u = 0
/// (measured worst case over 200 000 random normals: 1.31 at 6 bits), plus
/// the s1.14 truncation of the table.
pub fn normal_error_bound_rad(bits: u32) -> f64 {
    let step = MAX_Y_ANGLE_RAD / f64::from(1u32 << bits.min(6));
    0.5 * step * (1.0f64 + 2.13 * 2.13).sqrt() * 1.8 + 3.0 / 16384.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn angle(a: [f32; 3], b: [f32; 3]) -> f64 {
        let d: f64 = (0..3).map(|k| f64::from(a[k]) * f64::from(b[k])).sum();
        let la: f64 = (0..3).map(|k| f64::from(a[k]).powi(2)).sum::<f64>().sqrt();
        let lb: f64 = (0..3).map(|k| f64::from(b[k]).powi(2)).sum::<f64>().sqrt();
        (d / (la * lb)).clamp(-1.0, 1.0).acos()
    }

    #[test]
    fn specials_are_axes_and_diagonals() {
        // Worked from the spec text: sextant 6, octant 0 = +x; octant 2 = -x;
        // octant 4 = +y; sextant 7 octant 0 = +z; sextant 6 octant 1 = (+,+,+)/√3.
        let n = |s, o| index_normal(normal_table(), NormalCode { sextant: s, octant: o, u: 0, v: 0 }).unwrap();
        assert_eq!(n(6, 0), [1.0, 0.0, 0.0]);
        assert_eq!(n(6, 2), [-1.0, -0.0, -0.0]);
        assert_eq!(n(6, 4), [0.0, 1.0, 0.0]);
        assert_eq!(n(7, 0), [0.0, 0.0, 1.0]);
        let c = (1.0 / 3.0f64.sqrt()) as f32;
        assert_eq!(n(6, 1), [c, c, c]);
    }

    #[test]
    fn table_corners() {
        // (u, v) = (64, 0): theta = 0, psi = 0 -> +x; (0, 64): the diagonal.
        let x = index_normal(normal_table(), NormalCode { sextant: 0, octant: 0, u: 64, v: 0 }).unwrap();
        assert_eq!(x, [1.0, 0.0, 0.0]);
        let d = index_normal(normal_table(), NormalCode { sextant: 0, octant: 0, u: 0, v: 64 }).unwrap();
        for c in d {
            assert!((c - 0.57735).abs() < 2e-4, "{d:?}");
        }
        assert!(index_normal(normal_table(), NormalCode { sextant: 0, octant: 0, u: 65, v: 0 }).is_none());
    }

    #[test]
    fn quantization_within_bound() {
        let mut worst = [0.0f64; 7];
        let mut s = 12345u64;
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for _ in 0..200000 {
            let n = [rnd() as f32, rnd() as f32, rnd() as f32];
            for bits in 0..=6u32 {
                let code = quantize_normal(n, bits);
                let back = index_normal(normal_table(), code).unwrap();
                let a = angle(n, back);
                worst[bits as usize] = worst[bits as usize].max(a);
                assert!(a <= normal_error_bound_rad(bits), "bits {bits}: {n:?} -> {code:?} {back:?}: {a}");
            }
        }
        let ratio: Vec<f64> = (0..=6).map(|b| worst[b as usize] / normal_error_bound_rad(b)).collect();
        println!("worst angles {worst:?}, as a fraction of the bound {ratio:?}");
    }
}
