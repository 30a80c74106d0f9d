//! The coherent eye (spec/layouts.md §9.2): an eye focused on the plane of a
//! field forms an image of it through its pupil, and the light of
//! neighbouring points adds as amplitudes, so it interferes.
//!
//! Paraxial about each source's chief ray (Goodman, *Introduction to Fourier
//! Optics*, §6.1 on coherent imaging): light leaving the field's plane at `x'`
//! toward the pupil's centre `(X, d)` has the local spatial frequency
//! `sin θ_c / λ`, `sin θ_c = (X − x') / r`, `r = sqrt((X − x')² + d²)`.
//! Multiplying the field by `exp(+i k (r − d))` takes that direction to
//! frequency 0, and the pupil `[X − a/2, X + a/2]` becomes a band of
//! frequencies `[(sin θ₋ − sin θ_c) / λ, (sin θ₊ − sin θ_c) / λ)`, `sin θ±` the
//! exact directions from `x'` to the pupil's edges. The eye's ideal lens then
//! images the band-limited field onto the retina; measured back on the
//! field's plane (magnification 1, the inversion dropped) the image amplitude
//! is the field so multiplied and filtered to that band. The band depends
//! slowly on `x'` (its width goes as `cos³ θ_c`): each source's own band is
//! used for the light that reaches its own window, exactly.

use std::f64::consts::PI;

use holo_fft::Complex64;

use super::propagate::{fast_len, Field1d, MAX_FFT_SAMPLES};
use crate::error::{Error, Result};

/// An eye focused on the plane of a field, in that plane's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FocusedEye {
    /// Horizontal position of the pupil's centre, metres.
    pub x_m: f64,
    /// Distance from the field's plane to the pupil, metres (positive).
    pub distance_m: f64,
    /// Pupil width, metres (a horizontal segment: horizontal parallax only).
    pub pupil_m: f64,
}

impl FocusedEye {
    /// The band of spatial frequencies (cycles per metre, `[lo, hi)`) in
    /// which light leaving the field's plane at `source_x_m` enters the
    /// pupil, once the chief ray's phase is removed.
    pub fn band(&self, source_x_m: f64, wavelength_m: f64) -> (f64, f64) {
        let d = self.distance_m;
        let sin = |x: f64| (x - source_x_m) / ((x - source_x_m).powi(2) + d * d).sqrt();
        let centre = sin(self.x_m);
        (
            (sin(self.x_m - self.pupil_m / 2.0) - centre) / wavelength_m,
            (sin(self.x_m + self.pupil_m / 2.0) - centre) / wavelength_m,
        )
    }
}

/// A field prepared for coherent imaging by one eye: its spectrum after the
/// chief ray's phase is removed, and its image through the union of the
/// bands of the sources that will be asked for.
pub struct CoherentImage {
    /// Spectrum of the phase-corrected field, zero-padded to `len`,
    /// divided by `len` (so an inverse transform gives the field back).
    spectrum: Vec<Complex64>,
    /// Spacing of the spectrum's bins, cycles per metre.
    bin_step: f64,
    /// The union band, cycles per metre.
    union: (f64, f64),
    /// The image amplitude through the union band, one per field sample.
    image: Vec<Complex64>,
}

impl CoherentImage {
    /// Prepare `field` for an eye `eye` at `wavelength_m`, imaging through
    /// the band `union` (cycles per metre): the union of the [`FocusedEye::band`]s
    /// of every source [`CoherentImage::power`] will be asked for.
    pub fn new(field: &Field1d, eye: &FocusedEye, wavelength_m: f64, union: (f64, f64)) -> Result<CoherentImage> {
        let sensible = eye.distance_m.is_finite() && eye.distance_m > 0.0 && eye.pupil_m > 0.0 && eye.x_m.is_finite();
        if !sensible || field.samples.is_empty() || union.0.partial_cmp(&union.1) != Some(std::cmp::Ordering::Less) {
            return Err(Error::argument(
                "eye",
                format!(
                    "a coherent eye at x = {} m, {} m from the field with a {} m pupil cannot image it",
                    eye.x_m, eye.distance_m, eye.pupil_m
                ),
            ));
        }
        let count = field.samples.len();
        // Twice the field, so the image's long (sinc) tails do not wrap.
        if 2 * count > MAX_FFT_SAMPLES {
            return Err(Error::argument("field", format!("cannot image a field of {count} samples")));
        }
        let len = fast_len(2 * count);
        let k = 2.0 * PI / wavelength_m;
        let d = eye.distance_m;
        let mut buf = vec![Complex64::new(0.0, 0.0); len];
        for (i, (b, e)) in buf.iter_mut().zip(&field.samples).enumerate() {
            let u = field.x_m(i) - eye.x_m;
            // r − d without cancellation.
            let path = u * u / ((u * u + d * d).sqrt() + d);
            *b = e * Complex64::from_polar(1.0, k * path);
        }
        holo_fft::forward(len).process(&mut buf);
        let scale = 1.0 / len as f64;
        buf.iter_mut().for_each(|b| *b *= scale);
        let bin_step = 1.0 / (len as f64 * field.pitch_m);
        let mut image = vec![Complex64::new(0.0, 0.0); len];
        for (j, w) in weights(union, bin_step, len) {
            let at = j.rem_euclid(len as i64) as usize;
            image[at] = buf[at] * w;
        }
        holo_fft::inverse(len).process(&mut image);
        image.truncate(count);
        Ok(CoherentImage { spectrum: buf, bin_step, union, image })
    }

    /// `∫ |U|² dx` over field samples `first .. first + count` (clamped to
    /// the field), `U` the image amplitude through `source_band`, the pupil
    /// band of the light of the source whose window this is (it must lie
    /// within the union band); in units of `|field|² · metres`.
    pub fn power(&self, first: i64, count: usize, source_band: (f64, f64), pitch_m: f64) -> f64 {
        let len = self.spectrum.len();
        let start = first.max(0) as usize;
        let end = ((first + count as i64).max(0) as usize).min(self.image.len());
        if start >= end {
            return 0.0;
        }
        let mut amplitude: Vec<Complex64> = self.image[start..end].to_vec();
        // The union's bins weighed differently in the source's own band
        // (only near the two bands' edges), taken back out.
        let own = |j: i64| overlap(source_band, j, self.bin_step);
        let edge = |band_edge: f64| (band_edge / self.bin_step).round() as i64;
        let below = edge(self.union.0) - 1..=edge(source_band.0) + 1;
        let above = edge(source_band.1) - 1..=edge(self.union.1) + 1;
        let mut done = std::collections::BTreeSet::new();
        for j in below.chain(above) {
            let extra = overlap(self.union, j, self.bin_step) - own(j);
            if extra == 0.0 || !done.insert(j) {
                continue;
            }
            let c = self.spectrum[j.rem_euclid(len as i64) as usize] * extra;
            let step = Complex64::from_polar(1.0, 2.0 * PI * j as f64 / len as f64);
            let turns = (j * start as i64).rem_euclid(len as i64);
            let mut phasor = Complex64::from_polar(1.0, 2.0 * PI * turns as f64 / len as f64);
            for a in amplitude.iter_mut() {
                *a -= c * phasor;
                phasor *= step;
            }
        }
        amplitude.iter().map(|a| a.norm_sqr()).sum::<f64>() * pitch_m
    }

    /// The image intensity `|U|²` at every field sample, through `band`
    /// (cycles per metre) for every source alike: for tests and plots.
    pub fn intensity(&self, band: (f64, f64)) -> Vec<f64> {
        let len = self.spectrum.len();
        let mut image = vec![Complex64::new(0.0, 0.0); len];
        for (j, w) in weights(band, self.bin_step, len) {
            let at = j.rem_euclid(len as i64) as usize;
            image[at] = self.spectrum[at] * w;
        }
        holo_fft::inverse(len).process(&mut image);
        image.iter().take(self.image.len()).map(|a| a.norm_sqr()).collect()
    }
}

/// The fraction of bin `j` (frequencies `[(j − ½) step, (j + ½) step)`)
/// inside `band`: a band's edges fall between bins, and weighing the edge
/// bins by their share keeps its width exact at any bin spacing.
fn overlap(band: (f64, f64), j: i64, step: f64) -> f64 {
    let lo = band.0.max((j as f64 - 0.5) * step);
    let hi = band.1.min((j as f64 + 0.5) * step);
    ((hi - lo) / step).max(0.0)
}

/// Every bin that `band` touches, with its [`overlap`], within the `±len/2`
/// an FFT of `len` points holds.
fn weights(band: (f64, f64), step: f64, len: usize) -> impl Iterator<Item = (i64, f64)> {
    let half = (len / 2) as i64;
    let first = ((band.0 / step).round() as i64 - 1).max(-half);
    let last = ((band.1 / step).round() as i64 + 1).min(half - 1);
    (first..=last).map(move |j| (j, overlap(band, j, step))).filter(|(_, w)| *w > 0.0)
}
