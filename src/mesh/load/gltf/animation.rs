//! A glTF file's animation: the keyed curves of node transforms and morph
//! weights (step, linear with rotations slerped, cubic spline), and a node's
//! matrix from its translation, rotation and scale.

use gltf::animation::{Interpolation, Property};

use crate::math::{Mat4, IDENTITY4};

#[derive(Debug)]
pub(super) struct Channel {
    pub(super) node: usize,
    pub(super) property: Property,
    pub(super) interpolation: Interpolation,
    pub(super) times: Vec<f32>,
    pub(super) values: Vec<f32>,
    /// Numbers per key (3 translation/scale, 4 rotation, targets for weights).
    pub(super) width: usize,
}

impl Channel {
    /// The property's value at `t` (clamped to the key times).
    pub(super) fn sample(&self, t: f64) -> Vec<f32> {
        let w = self.width;
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let key = |k: usize, part: usize| -> &[f32] {
            let e = if cubic { 3 * k + part } else { k };
            &self.values[e * w..(e + 1) * w]
        };
        let n = self.times.len();
        let mid = usize::from(cubic);
        let t = t as f32;
        if n == 1 || t <= self.times[0] {
            return key(0, mid).to_vec();
        }
        if t >= self.times[n - 1] {
            return key(n - 1, mid).to_vec();
        }
        let k = self.times.partition_point(|&x| x <= t).saturating_sub(1).min(n - 2);
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let dt = t1 - t0;
        let s = if dt > 0.0 { (t - t0) / dt } else { 0.0 };
        let rotation = self.property == Property::Rotation;
        let mut v: Vec<f32> = match self.interpolation {
            Interpolation::Step => key(k, 0).to_vec(),
            Interpolation::Linear => {
                let (a, b) = (key(k, 0), key(k + 1, 0));
                if rotation {
                    return slerp(a, b, s);
                }
                a.iter().zip(b).map(|(x, y)| x + (y - x) * s).collect()
            }
            Interpolation::CubicSpline => {
                let (v0, b0) = (key(k, 1), key(k, 2));
                let (a1, v1) = (key(k + 1, 0), key(k + 1, 1));
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = s3 - 2.0 * s2 + s;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = s3 - s2;
                (0..w).map(|c| h00 * v0[c] + h10 * dt * b0[c] + h01 * v1[c] + h11 * dt * a1[c]).collect()
            }
        };
        if rotation {
            let l = v.iter().map(|x| x * x).sum::<f32>().sqrt();
            if l > 0.0 {
                v.iter_mut().for_each(|x| *x /= l);
            }
        }
        v
    }
}

pub(super) fn slerp(a: &[f32], b: &[f32], s: f32) -> Vec<f32> {
    let mut d: f32 = a.iter().zip(b).map(|(x, y)| x * y).sum();
    let mut b: Vec<f32> = b.to_vec();
    if d < 0.0 {
        d = -d;
        b.iter_mut().for_each(|x| *x = -*x);
    }
    let (wa, wb) = if d > 0.9995 {
        (1.0 - s, s)
    } else {
        let th = d.min(1.0).acos();
        let st = th.sin();
        (((1.0 - s) * th).sin() / st, (s * th).sin() / st)
    };
    let mut v: Vec<f32> = a.iter().zip(&b).map(|(x, y)| wa * x + wb * y).collect();
    let l = v.iter().map(|x| x * x).sum::<f32>().sqrt();
    if l > 0.0 {
        v.iter_mut().for_each(|x| *x /= l);
    }
    v
}

pub(super) fn trs(t: [f64; 3], q: [f64; 4], s: [f64; 3]) -> Mat4 {
    let [x, y, z, w] = q;
    let n = (x * x + y * y + z * z + w * w).sqrt();
    let (x, y, z, w) = if n > 0.0 { (x / n, y / n, z / n, w / n) } else { (0.0, 0.0, 0.0, 1.0) };
    let r = [
        [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + z * w), 2.0 * (x * z - y * w)],
        [2.0 * (x * y - z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + x * w)],
        [2.0 * (x * z + y * w), 2.0 * (y * z - x * w), 1.0 - 2.0 * (x * x + y * y)],
    ];
    // `r[c]` is column c of the rotation.
    let mut m = IDENTITY4;
    for c in 0..3 {
        for row in 0..3 {
            m[row][c] = r[c][row] * s[c];
        }
        m[c][3] = t[c];
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(
        interpolation: Interpolation,
        property: Property,
        times: &[f32],
        values: &[f32],
        width: usize,
    ) -> Channel {
        Channel { node: 0, property, interpolation, times: times.to_vec(), values: values.to_vec(), width }
    }

    #[test]
    fn step_linear_and_clamping() {
        let c = channel(Interpolation::Linear, Property::Translation, &[1.0, 3.0], &[0.0, 0.0, 0.0, 2.0, 4.0, 6.0], 3);
        assert_eq!(c.sample(0.0), vec![0.0, 0.0, 0.0]);
        assert_eq!(c.sample(2.0), vec![1.0, 2.0, 3.0]);
        assert_eq!(c.sample(9.0), vec![2.0, 4.0, 6.0]);
        let s = channel(Interpolation::Step, Property::Translation, &[1.0, 3.0], &[0.0, 0.0, 0.0, 2.0, 4.0, 6.0], 3);
        assert_eq!(s.sample(2.9), vec![0.0, 0.0, 0.0]);
        assert_eq!(s.sample(3.0), vec![2.0, 4.0, 6.0]);
    }

    #[test]
    fn cubic_spline_is_hermite() {
        // One weight; keys (in, value, out): at t=0 value 0 out-tangent 0, at t=2 value 1 in-tangent 0.
        let c = channel(
            Interpolation::CubicSpline,
            Property::MorphTargetWeights,
            &[0.0, 2.0],
            &[9.0, 0.0, 0.0, 0.0, 1.0, 9.0],
            1,
        );
        assert_eq!(c.sample(0.0), vec![0.0]);
        assert!((c.sample(1.0)[0] - 0.5).abs() < 1e-6);
        assert_eq!(c.sample(2.0), vec![1.0]);
        // Smoothstep at s = 0.25: 3s² − 2s³.
        assert!((c.sample(0.5)[0] - 0.15625).abs() < 1e-6);
    }

    #[test]
    fn rotation_slerps_and_stays_unit() {
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let c =
            channel(Interpolation::Linear, Property::Rotation, &[0.0, 1.0], &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, h, h], 4);
        let q = c.sample(0.5);
        let want = (std::f32::consts::PI / 8.0).sin_cos();
        assert!((q[2] - want.0).abs() < 1e-5 && (q[3] - want.1).abs() < 1e-5, "{q:?}");
    }
}
