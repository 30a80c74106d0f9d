//! Hogels of gratings (Lucente 1994; docs/optics.md §3, §6): abutting pieces of
//! the hologram, each an emitter on the hologram plane, in which every view is
//! a sum of gratings.
//!
//! A grating of `b` cycles per hogel (`b / W` cycles per sample) sends its
//! first order to `sin θ = (b / W − carrier) · λ / pitch` (the grating
//! equation with the reference beam's carrier removed). View `v` takes every
//! grating whose direction falls in its angular interval, so the view's
//! light fills the interval instead of leaving gaps between views; the
//! gratings sit on the hogel's own frequency grid, so different views are
//! orthogonal over the hogel. Each grating has a pseudo-random phase (a fixed
//! hash of `b`, so fringes are reproducible) that keeps the views' sum from
//! piling up into peaks, and each view is normalised to the same power.

use std::f64::consts::PI;

use holo_fft::Complex64;

use crate::layout::SignalKind;

/// The gratings of every view of a hogel, for one wavelength.
#[derive(Clone, Debug, PartialEq)]
pub struct HogelGratings {
    /// Samples per hogel.
    pub hogel_samples: usize,
    /// Per view: the grating frequencies (cycles per hogel) and phases (radians).
    pub gratings: Vec<Vec<(i64, f64)>>,
}

/// A pseudo-random phase for index `b`, `2π · splitmix64(b) / 2⁶⁴`: the
/// phase of the grating of `b` cycles per hogel (spec/layouts.md §4.3), and of
/// emitter `b` with random emitter phases (§4.6).
pub fn pseudo_random_phase_rad(b: i64) -> f64 {
    let mut z = (b as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    2.0 * PI * (z as f64 / 2f64.powi(64))
}

impl HogelGratings {
    /// Gratings for views whose angular intervals are `view_sin_edges[v] =
    /// (sin θ_lo, sin θ_hi)`, at `pitch_m` and `wavelength_m`, with the
    /// in-signal carrier `carrier` (cycles per sample). Real signals may use
    /// frequencies strictly between 0 and half the sampling rate, I/Q signals
    /// strictly between ± half. Errors name a view no grating falls in.
    pub fn new(
        hogel_samples: usize,
        pitch_m: f64,
        wavelength_m: f64,
        carrier: f64,
        signal: SignalKind,
        view_sin_edges: &[(f64, f64)],
    ) -> crate::error::Result<Self> {
        let w = hogel_samples as i64;
        let bins = match signal {
            SignalKind::Real => 1..(w + 1) / 2,
            SignalKind::Iq => -(w - 1) / 2..(w + 1) / 2,
        };
        let mut gratings = Vec::with_capacity(view_sin_edges.len());
        for (v, &(lo, hi)) in view_sin_edges.iter().enumerate() {
            let in_view: Vec<(i64, f64)> = bins
                .clone()
                .filter(|&b| {
                    let sin = (b as f64 / w as f64 - carrier) * wavelength_m / pitch_m;
                    sin >= lo && sin < hi
                })
                .map(|b| (b, pseudo_random_phase_rad(b)))
                .collect();
            if in_view.is_empty() {
                let f = |s: f64| s * pitch_m / wavelength_m + carrier;
                return Err(crate::error::Error::argument(
                    "hogel",
                    format!(
                        "view {v} (sin θ {lo:.4} to {hi:.4}, {:.4} to {:.4} cycles per sample at {:.0} nm) holds no \
                     grating of a {hogel_samples}-sample hogel inside the signal's band",
                        f(lo),
                        f(hi),
                        wavelength_m * 1e9
                    ),
                ));
            }
            gratings.push(in_view);
        }
        Ok(HogelGratings { hogel_samples, gratings })
    }

    /// View `v`'s basis at sample `u` of the hogel, in f64:
    /// `Σ_b exp(i(2π b u / W + ψ_b)) / sqrt(count)` (a real signal uses the
    /// real part).
    pub fn value(&self, v: usize, u: usize) -> Complex64 {
        let w = self.hogel_samples as f64;
        let list = &self.gratings[v];
        let sum: Complex64 = list
            .iter()
            .map(|&(b, psi)| {
                // Reduce the cycles exactly in integers before scaling.
                let cycles = (b * u as i64).rem_euclid(self.hogel_samples as i64) as f64 / w;
                Complex64::from_polar(1.0, 2.0 * PI * cycles + psi)
            })
            .sum();
        sum / (list.len() as f64).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_get_disjoint_gratings_inside_their_intervals() {
        // Five views over ±8° at 0.6 µm pitch and 633 nm, carrier 0.25.
        let edges: Vec<(f64, f64)> = (0..5)
            .map(|v| {
                let t = |k: f64| (8f64.to_radians().tan() * (2.0 * k / 5.0 - 1.0)).atan().sin();
                (t(v as f64), t(v as f64 + 1.0))
            })
            .collect();
        let h = HogelGratings::new(128, 0.6e-6, 633e-9, 0.25, SignalKind::Real, &edges).unwrap();
        let mut seen = std::collections::HashSet::new();
        for (v, list) in h.gratings.iter().enumerate() {
            assert!(!list.is_empty());
            for &(b, _) in list {
                assert!(seen.insert(b), "bin {b} in two views");
                let sin = (b as f64 / 128.0 - 0.25) * 633e-9 / 0.6e-6;
                assert!(sin >= edges[v].0 && sin < edges[v].1);
            }
        }
        // Each view's basis has unit mean power over the hogel (complex form).
        for v in 0..5 {
            let p: f64 = (0..128).map(|u| h.value(v, u).norm_sqr()).sum::<f64>() / 128.0;
            assert!((p - 1.0).abs() < 1e-12, "view {v}: {p}");
        }
        // A hogel too short to resolve the views is refused, naming the view.
        let err = HogelGratings::new(8, 0.6e-6, 633e-9, 0.25, SignalKind::Real, &edges).unwrap_err();
        assert!(
            matches!(&err, crate::error::Error::Argument { what: "hogel", .. }) && err.to_string().contains("view"),
            "{err}"
        );
    }
}
