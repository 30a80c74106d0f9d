//! The optics core of the reconstruction: a 1-D complex field on one hololine
//! (horizontal parallax only), its free-space propagation, and its angular
//! spectrum (docs/optics.md §8.2).
//!
//! Start at [`Field1d`], then [`propagate`] / [`propagate_to`] (band-limited
//! angular spectrum method of Matsushima & Shimobaba 2009) and
//! [`angular_spectrum`] (where the light in a window of the field goes).
//! [`intensity_peak`] measures a focus.
//!
//! Conventions: `x` along the hololine, `z` toward the viewer, hologram at
//! `z = 0`, all lengths in metres. A plane wave travelling at angle `θ`
//! (positive toward `+x`) is `exp(i 2π x sin θ / λ)`; with the time factor
//! `exp(−iωt)`, propagating by `+z` multiplies the angular spectrum by
//! `exp(+i 2π z sqrt(1/λ² − f²))`. Everything is f64: phases reach 10⁵ rad.

use std::f64::consts::PI;

use holo_fft::Complex64;

use crate::error::{Error, Result};

/// Most samples a propagation or a spectrum may need before its FFT length is
/// rounded up to a fast one (2²⁶ complex samples are 1 GiB); more is refused.
pub const MAX_FFT_SAMPLES: usize = 1 << 26;

/// A complex field sampled along one hololine.
#[derive(Clone, Debug, PartialEq)]
pub struct Field1d {
    /// Complex amplitude; sample `k` is at `x = x0_m + k · pitch_m`.
    pub samples: Vec<Complex64>,
    /// Distance between samples, metres.
    pub pitch_m: f64,
    /// `x` of sample 0, metres.
    pub x0_m: f64,
}

impl Field1d {
    /// `count` samples of `field_at(x_m)` starting at `x0_m`, `pitch_m` apart.
    pub fn sampled(x0_m: f64, pitch_m: f64, count: usize, field_at: impl Fn(f64) -> Complex64) -> Field1d {
        let samples = (0..count).map(|k| field_at(x0_m + k as f64 * pitch_m)).collect();
        Field1d { samples, pitch_m, x0_m }
    }

    /// `x` of sample `k`, metres.
    pub fn x_m(&self, k: usize) -> f64 {
        self.x0_m + k as f64 * self.pitch_m
    }

    fn check(&self) -> Result<()> {
        check_positive("field pitch_m", self.pitch_m)?;
        check_finite("field x0_m", self.x0_m)?;
        if self.samples.is_empty() {
            return Err(Error::argument("field", "the field has no samples"));
        }
        match self.samples.iter().position(|s| !(s.re.is_finite() && s.im.is_finite())) {
            Some(k) => Err(Error::argument("field", format!("field sample {k} is not finite"))),
            None => Ok(()),
        }
    }
}

/// The field after free-space propagation by `distance_m` (negative: backward),
/// on the same samples as `field`. See [`propagate_to`].
pub fn propagate(field: &Field1d, wavelength_m: f64, distance_m: f64) -> Result<Field1d> {
    propagate_to(field, wavelength_m, distance_m, field.x0_m, field.pitch_m, field.samples.len())
}

/// The field after free-space propagation by `distance_m` (negative: backward),
/// sampled at `count` points `x0_m + i · pitch_m`. The output window may be
/// anywhere, e.g. wider than the input to watch a focus; its pitch must be the
/// input's times or divided by a whole number (finer samples are the exact
/// band-limited interpolation).
///
/// Band-limited angular spectrum method: the input is zero-padded to at least
/// twice the union of both windows, so light does not wrap around; components
/// with `|f| > 1 / (λ sqrt((2 Δf z)² + 1))`, `Δf` = 1 / padded length, are
/// dropped (beyond it the sampled transfer function aliases), and with them
/// all evanescent ones. Propagating forward then backward by the same
/// distance therefore returns any field whose spectrum lies within that band
/// and whose light stays inside the window.
pub fn propagate_to(
    field: &Field1d,
    wavelength_m: f64,
    distance_m: f64,
    x0_m: f64,
    pitch_m: f64,
    count: usize,
) -> Result<Field1d> {
    field.check()?;
    check_positive("wavelength_m", wavelength_m)?;
    check_finite("distance_m", distance_m)?;
    check_finite("output x0_m", x0_m)?;
    check_positive("output pitch_m", pitch_m)?;
    if count == 0 {
        return Err(Error::argument("output window", "the output window has no samples"));
    }
    let p = field.pitch_m;
    // Output pitch = p · down / up with one of them 1: compute on a grid `up`
    // times finer than the input, keep every `down`-th sample.
    let ratio = pitch_m / p;
    let (up, down) = if ratio >= 1.0 { (1.0, ratio.round()) } else { ((1.0 / ratio).round(), 1.0) };
    if (down / up - ratio).abs() > 1e-9 * ratio {
        return Err(Error::argument(
            "output pitch",
            format!("output pitch {pitch_m} m is not a whole multiple or fraction of the field's pitch {p} m"),
        ));
    }
    // The padded grid starts a whole number of input samples before the input
    // and covers both windows, with a sample to spare against rounding.
    let lo = x0_m.min(field.x0_m);
    let hi = (x0_m + count as f64 * pitch_m).max(field.x_m(field.samples.len()));
    let before = ((field.x0_m - lo) / p).ceil();
    let grid_x0_m = field.x0_m - before * p;
    let union_samples = ((hi - grid_x0_m) / p).ceil() + 1.0;
    if 2.0 * union_samples * up > MAX_FFT_SAMPLES as f64 {
        return Err(Error::argument(
            "distance",
            format!("propagating over {:.3e} m at pitch {p} m needs more than {MAX_FFT_SAMPLES} samples", hi - lo),
        ));
    }
    let (up, down, before) = (up as usize, down as usize, before as usize);
    let len = fast_len(2 * union_samples as usize);
    let fine_len = len * up;

    let mut spectrum = vec![Complex64::new(0.0, 0.0); len];
    spectrum[before..before + field.samples.len()].copy_from_slice(&field.samples);
    holo_fft::forward(len).process(&mut spectrum);

    // Output sample 0 lies `frac` fine samples past fine sample `first`; the
    // remainder is a phase ramp on the spectrum (a sub-sample shift).
    let p_fine = p / up as f64;
    let t = ((x0_m - grid_x0_m) / p_fine).max(0.0);
    let first = t.floor() as usize;
    let frac = t - t.floor();
    let df = 1.0 / (len as f64 * p);
    let f_limit = 1.0 / (wavelength_m * ((2.0 * df * distance_m).powi(2) + 1.0).sqrt());
    let inv_wavelength2 = wavelength_m.powi(-2);
    let mut fine = vec![Complex64::new(0.0, 0.0); fine_len];
    for (k, s) in spectrum.iter().enumerate() {
        let signed = if k < len.div_ceil(2) { k as isize } else { k as isize - len as isize };
        let f = signed as f64 * df;
        if f.abs() > f_limit {
            continue;
        }
        let kz = (inv_wavelength2 - f * f).max(0.0).sqrt();
        let phase = 2.0 * PI * (distance_m * kz + signed as f64 * frac / fine_len as f64);
        fine[signed.rem_euclid(fine_len as isize) as usize] = s * Complex64::from_polar(1.0, phase) / len as f64;
    }
    holo_fft::inverse(fine_len).process(&mut fine);
    let samples: Vec<Complex64> = fine.into_iter().skip(first).step_by(down).take(count).collect();
    debug_assert_eq!(samples.len(), count, "the padded grid covers the output window");
    Ok(Field1d { samples, pitch_m, x0_m })
}

/// [`propagate`] planned once for fields of one window (length, pitch and
/// position), as every hololine of a layout has: the transfer function is
/// computed once and each call costs two FFTs.
#[derive(Clone, Debug)]
pub struct Propagator {
    count: usize,
    pitch_m: f64,
    x0_m: f64,
    /// Transfer function, divided by the FFT length, per FFT bin.
    transfer: Vec<Complex64>,
}

impl Propagator {
    /// A propagation by `distance_m` at `wavelength_m` for fields of `count`
    /// samples `pitch_m` apart from `x0_m`.
    pub fn new(count: usize, pitch_m: f64, x0_m: f64, wavelength_m: f64, distance_m: f64) -> Result<Propagator> {
        check_positive("field pitch_m", pitch_m)?;
        check_positive("wavelength_m", wavelength_m)?;
        check_finite("distance_m", distance_m)?;
        if count == 0 || 2 * (count + 1) > MAX_FFT_SAMPLES {
            return Err(Error::argument("field", format!("cannot propagate a field of {count} samples")));
        }
        // As in `propagate_to` with the output window the input's (the same
        // rounding, so the same padding).
        let union_samples = ((count as f64 * pitch_m) / pitch_m).ceil() + 1.0;
        let len = fast_len(2 * union_samples as usize);
        let df = 1.0 / (len as f64 * pitch_m);
        let f_limit = 1.0 / (wavelength_m * ((2.0 * df * distance_m).powi(2) + 1.0).sqrt());
        let inv_wavelength2 = wavelength_m.powi(-2);
        let transfer = (0..len)
            .map(|k| {
                let signed = if k < len.div_ceil(2) { k as isize } else { k as isize - len as isize };
                let f = signed as f64 * df;
                if f.abs() > f_limit {
                    return Complex64::new(0.0, 0.0);
                }
                let kz = (inv_wavelength2 - f * f).max(0.0).sqrt();
                Complex64::from_polar(1.0 / len as f64, 2.0 * PI * distance_m * kz)
            })
            .collect();
        Ok(Propagator { count, pitch_m, x0_m, transfer })
    }

    /// `field` (sampled like the one this was planned for) propagated.
    pub fn apply(&self, field: &Field1d) -> Result<Field1d> {
        if field.samples.len() != self.count || field.pitch_m != self.pitch_m || field.x0_m != self.x0_m {
            return Err(Error::argument(
                "field",
                "the field is not sampled like the one the propagation was planned for",
            ));
        }
        let len = self.transfer.len();
        let mut buf = vec![Complex64::new(0.0, 0.0); len];
        buf[..self.count].copy_from_slice(&field.samples);
        holo_fft::forward(len).process(&mut buf);
        buf.iter_mut().zip(&self.transfer).for_each(|(b, t)| *b *= t);
        holo_fft::inverse(len).process(&mut buf);
        buf.truncate(self.count);
        Ok(Field1d { samples: buf, pitch_m: self.pitch_m, x0_m: self.x0_m })
    }
}

/// The taper applied to a [`Window`] before its spectrum is taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Taper {
    /// No taper: narrowest peaks, sidelobes falling as 1/f.
    Rect,
    /// `sin²(π (x − x_lo) / (x_hi − x_lo))`: low leakage between directions.
    Hann,
}

/// A sub-range `[x_lo_m, x_hi_m)` of a field, its taper and its zero padding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    /// Start of the range, metres (inclusive).
    pub x_lo_m: f64,
    /// End of the range, metres (exclusive).
    pub x_hi_m: f64,
    /// Taper over the range.
    pub taper: Taper,
    /// The FFT is at least this many times the window's length (finer
    /// sampling in `sin θ`); at least 1.
    pub zero_pad: usize,
}

impl Window {
    /// Zero padding of [`Window::new`].
    pub const DEFAULT_ZERO_PAD: usize = 8;

    /// The range `[x_lo_m, x_hi_m)` with `taper`, zero-padded 8×.
    pub fn new(x_lo_m: f64, x_hi_m: f64, taper: Taper) -> Window {
        Window { x_lo_m, x_hi_m, taper, zero_pad: Self::DEFAULT_ZERO_PAD }
    }
}

/// Where the light of a window goes: power per direction.
#[derive(Clone, Debug, PartialEq)]
pub struct AngularSpectrum {
    /// `sin θ` of each bin, increasing by `sin_theta_step`; bins with
    /// `|sin θ| > 1` are evanescent.
    pub sin_theta: Vec<f64>,
    /// Power of each bin, `|FFT|² · pitch / padded length` in field² · metres,
    /// so that the sum over all bins equals `Σ |E · taper|² · pitch` over the
    /// window (Parseval).
    pub power: Vec<f64>,
    /// Spacing of `sin_theta`: `λ / (padded length in metres)`.
    pub sin_theta_step: f64,
}

impl AngularSpectrum {
    /// Power of the directions with `sin θ` in `[sin_lo, sin_hi)`. Each bin
    /// spreads its power evenly over `±step/2` around its centre, so the
    /// result is continuous in both limits; an empty or reversed range gives 0,
    /// a NaN limit NaN.
    pub fn power_between(&self, sin_lo: f64, sin_hi: f64) -> f64 {
        if sin_lo.is_nan() || sin_hi.is_nan() {
            return f64::NAN;
        }
        let (Some(&s0), n) = (self.sin_theta.first(), self.power.len().min(self.sin_theta.len())) else {
            return 0.0;
        };
        // In units of bins, bin k covers [k, k + 1).
        let u = |s: f64| ((s - s0) / self.sin_theta_step + 0.5).clamp(0.0, n as f64);
        let (u_lo, u_hi) = (u(sin_lo), u(sin_hi));
        if u_hi <= u_lo {
            return 0.0;
        }
        let k_hi = (u_hi.ceil() as usize).min(n);
        (u_lo.floor() as usize..k_hi).map(|k| self.power[k] * (u_hi.min(k as f64 + 1.0) - u_lo.max(k as f64))).sum()
    }

    /// Power of all bins.
    pub fn total_power(&self) -> f64 {
        self.power.iter().sum()
    }
}

/// The angular spectrum of the samples of `field` inside `window`, tapered
/// and zero-padded; bin `s` holds spatial frequency `f = s / (padded length)`,
/// direction `sin θ = λ f` (the phase reference is irrelevant to power).
pub fn angular_spectrum(field: &Field1d, window: Window, wavelength_m: f64) -> Result<AngularSpectrum> {
    field.check()?;
    check_positive("wavelength_m", wavelength_m)?;
    check_finite("window x_lo_m", window.x_lo_m)?;
    check_finite("window x_hi_m", window.x_hi_m)?;
    let width_m = window.x_hi_m - window.x_lo_m;
    // Both limits are finite, so the width is not NaN.
    if width_m <= 0.0 || window.zero_pad == 0 {
        return Err(Error::argument("window", "a window needs x_lo_m < x_hi_m and a zero_pad of at least 1"));
    }
    // Samples with x_lo ≤ x < x_hi; the tolerance keeps a limit placed on a
    // sample from losing it to rounding.
    let n = field.samples.len();
    let index = |x: f64| ((x - field.x0_m) / field.pitch_m - 1e-9).ceil().clamp(0.0, n as f64) as usize;
    let (k_lo, k_hi) = (index(window.x_lo_m), index(window.x_hi_m));
    if k_lo >= k_hi {
        return Err(Error::argument(
            "window",
            format!("window [{}, {}) m holds no sample of the field", window.x_lo_m, window.x_hi_m),
        ));
    }
    let len = match (k_hi - k_lo).checked_mul(window.zero_pad) {
        Some(m) if m <= MAX_FFT_SAMPLES => fast_len(m),
        _ => {
            return Err(Error::argument("window", format!("window spectrum needs more than {MAX_FFT_SAMPLES} samples")))
        }
    };
    let mut buf = vec![Complex64::new(0.0, 0.0); len];
    for (b, k) in buf.iter_mut().zip(k_lo..k_hi) {
        let weight = match window.taper {
            Taper::Rect => 1.0,
            Taper::Hann => (PI * (field.x_m(k) - window.x_lo_m) / width_m).sin().powi(2),
        };
        *b = field.samples[k] * weight;
    }
    holo_fft::forward(len).process(&mut buf);
    // Reorder to increasing frequency: s from −⌊len/2⌋ to ⌈len/2⌉ − 1.
    let sin_theta_step = wavelength_m / (len as f64 * field.pitch_m);
    let (sin_theta, power) = (0..len)
        .map(|i| {
            let s = i as isize - (len / 2) as isize;
            let bin = buf[s.rem_euclid(len as isize) as usize];
            (s as f64 * sin_theta_step, bin.norm_sqr() * field.pitch_m / len as f64)
        })
        .unzip();
    Ok(AngularSpectrum { sin_theta, power, sin_theta_step })
}

/// Position of the intensity maximum, refined between samples by a parabola
/// through the three samples around it, and the full width at half of that
/// refined maximum, with linear interpolation between samples: `(x_m, fwhm_m)`.
/// A field that is zero, or whose peak does not fall below half on both sides
/// within the samples, is refused.
pub fn intensity_peak(field: &Field1d) -> Result<(f64, f64)> {
    field.check()?;
    let intensity: Vec<f64> = field.samples.iter().map(|s| s.norm_sqr()).collect();
    let Some((k, &i_max)) = intensity.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).filter(|m| *m.1 > 0.0)
    else {
        return Err(Error::argument("field", "the field is zero: it has no intensity peak"));
    };
    let (offset, peak) = match (k.checked_sub(1).map(|j| intensity[j]), intensity.get(k + 1)) {
        (Some(a), Some(&c)) if a - 2.0 * i_max + c < 0.0 => {
            let d = 0.5 * (a - c) / (a - 2.0 * i_max + c);
            (d, i_max - 0.25 * (a - c) * d)
        }
        _ => (0.0, i_max),
    };
    let half = 0.5 * peak;
    // First samples below half on each side; the neighbour toward the peak is
    // at or above half, so the interpolations divide by a positive number.
    let left = (0..k).rev().find(|&j| intensity[j] < half);
    let right = (k + 1..intensity.len()).find(|&j| intensity[j] < half);
    let (Some(l), Some(r)) = (left, right) else {
        return Err(Error::argument("field", "the intensity peak does not fall to half within the field"));
    };
    let x_left = l as f64 + (half - intensity[l]) / (intensity[l + 1] - intensity[l]);
    let x_right = r as f64 - (half - intensity[r]) / (intensity[r - 1] - intensity[r]);
    Ok((field.x_m(k) + offset * field.pitch_m, (x_right - x_left) * field.pitch_m))
}

/// The smallest `2^a · 3^b ≥ n`, a length the FFT (rustfft, through holo-fft) transforms fast.
pub(crate) fn fast_len(n: usize) -> usize {
    let mut best = n.next_power_of_two();
    let mut p3 = 3;
    while p3 < best {
        best = best.min(n.div_ceil(p3).next_power_of_two() * p3);
        p3 *= 3;
    }
    best
}

fn check_finite(what: &'static str, value: f64) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Error::argument(what, format!("{what} is {value}; it must be finite")))
    }
}

fn check_positive(what: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::argument(what, format!("{what} is {value}; it must be finite and positive")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WAVELENGTH_M: f64 = 633e-9;

    fn plane_wave(x_m: f64, z_m: f64, theta_rad: f64) -> Complex64 {
        let (sin, cos) = theta_rad.sin_cos();
        Complex64::from_polar(1.0, 2.0 * PI * (x_m * sin + z_m * cos) / WAVELENGTH_M)
    }

    /// 0 below 0, 1 above 1, and smooth (C∞) between: a taper whose
    /// diffraction does not reach far.
    fn smooth_step(t: f64) -> f64 {
        let e = |t: f64| if t > 0.0 { (-1.0 / t).exp() } else { 0.0 };
        e(t) / (e(t) + e(1.0 - t))
    }

    fn relative_l2(a: &[Complex64], b: &[Complex64]) -> f64 {
        let diff: f64 = a.iter().zip(b).map(|(a, b)| (a - b).norm_sqr()).sum();
        (diff / b.iter().map(|b| b.norm_sqr()).sum::<f64>()).sqrt()
    }

    #[test]
    fn fast_lengths_are_products_of_two_and_three() {
        assert_eq!([1, 5, 7, 10, 17, 8193].map(fast_len), [1, 6, 8, 12, 18, 8748]);
    }

    #[test]
    fn tilted_plane_wave_spectrum_peaks_at_its_direction_and_keeps_power() {
        let (theta, pitch, n) = (5f64.to_radians(), 0.5e-6, 4096);
        let field = Field1d::sampled(-1e-3, pitch, n, |x| plane_wave(x, 0.0, theta));
        let window = Window::new(field.x0_m, field.x_m(n), Taper::Hann);
        let spectrum = angular_spectrum(&field, window, WAVELENGTH_M).unwrap();
        let peak = (0..spectrum.power.len()).max_by(|&a, &b| spectrum.power[a].total_cmp(&spectrum.power[b])).unwrap();
        let miss_bins = (spectrum.sin_theta[peak] - theta.sin()).abs() / spectrum.sin_theta_step;
        assert!(miss_bins <= 0.5, "peak {miss_bins} bins from sin θ");
        let hann = |x: f64| (PI * (x - window.x_lo_m) / (window.x_hi_m - window.x_lo_m)).sin().powi(2);
        let direct: f64 = (0..n).map(|k| (field.samples[k] * hann(field.x_m(k))).norm_sqr() * pitch).sum();
        assert!((spectrum.total_power() / direct - 1.0).abs() < 1e-9);
        let near = spectrum.power_between(theta.sin() - 1e-2, theta.sin() + 1e-2);
        assert!(near > 0.999_999 * direct, "Hann window leaks {:.2e}", 1.0 - near / direct);
    }

    #[test]
    fn power_between_is_continuous_and_additive() {
        let field = Field1d::sampled(0.0, 0.5e-6, 200, |x| plane_wave(x, 0.0, 0.1) + 0.3 * plane_wave(x, 0.0, -0.2));
        let spectrum = angular_spectrum(&field, Window::new(0.0, 1e-4, Taper::Rect), WAVELENGTH_M).unwrap();
        let step = spectrum.sin_theta_step;
        let total = spectrum.total_power();
        let split = |s: f64| spectrum.power_between(-2.0, s) + spectrum.power_between(s, 2.0);
        for s in [-0.2, 0.0, 0.1 + 0.3 * step, 0.5] {
            assert!((split(s) / total - 1.0).abs() < 1e-12);
            let jump = spectrum.power_between(-2.0, s + 1e-6 * step) - spectrum.power_between(-2.0, s);
            assert!(jump.abs() < 1e-5 * total);
        }
    }

    #[test]
    fn plane_wave_gains_only_phase() {
        // C∞ tapers of 256 µm at both ends; the wave walks z tan θ = 176 µm.
        let (theta, pitch, n, z) = (10f64.to_radians(), 0.5e-6, 4096, 1e-3);
        let (x0, taper) = (-1.024e-3, 256e-6);
        let x_end = x0 + n as f64 * pitch;
        let field = Field1d::sampled(x0, pitch, n, |x| {
            plane_wave(x, 0.0, theta) * smooth_step((x - x0) / taper) * smooth_step((x_end - x) / taper)
        });
        let (lo, hi) = (-300e-6, 650e-6);
        let same = propagate(&field, WAVELENGTH_M, z).unwrap();
        let finer = propagate_to(&field, WAVELENGTH_M, z, lo + 0.37 * pitch, pitch / 3.0, 5000).unwrap();
        let coarser = propagate_to(&field, WAVELENGTH_M, z, lo - 0.21 * pitch, 2.0 * pitch, 900).unwrap();
        let mut worst: f64 = 0.0;
        for out in [&same, &finer, &coarser] {
            for (k, s) in out.samples.iter().enumerate() {
                let x = out.x_m(k);
                if (lo..hi).contains(&x) {
                    worst = worst.max((s - plane_wave(x, z, theta)).norm());
                }
            }
        }
        eprintln!("plane wave after {z} m: largest error {worst:.1e}");
        assert!(worst < 1e-6);
    }

    #[test]
    fn gaussian_beam_widens_as_closed_form() {
        let (w0, z, pitch) = (20e-6, 2e-3, 0.5e-6);
        let field = Field1d::sampled(-1.024e-3, pitch, 4096, |x| Complex64::new((-(x / w0).powi(2)).exp(), 0.0));
        let out = propagate(&field, WAVELENGTH_M, z).unwrap();
        let (x, fwhm) = intensity_peak(&out).unwrap();
        let z_rayleigh = PI * w0 * w0 / WAVELENGTH_M;
        let w = w0 * (1.0 + (z / z_rayleigh).powi(2)).sqrt();
        // Intensity exp(−2x²/w²): FWHM = w sqrt(2 ln 2); 1-D peak intensity w0 / w.
        let width_error = fwhm / (w * (2.0 * 2f64.ln()).sqrt()) - 1.0;
        let peak = out.samples.iter().map(|s| s.norm_sqr()).fold(0.0, f64::max);
        eprintln!("Gaussian beam: width error {width_error:.1e}, peak error {:.1e}", peak * w / w0 - 1.0);
        assert!(width_error.abs() < 5e-3 && (peak * w / w0 - 1.0).abs() < 5e-3);
        assert!(x.abs() < 1e-3 * w);
    }

    /// A cylindrical wave converging to (xe, ze) through an aperture of half
    /// angle 12°, sampled at λ/4, focuses to 0.886 λ / (2 sin α) at ze.
    #[test]
    fn cylindrical_wave_focuses_at_its_emitter() {
        let (alpha, xe, ze) = (12f64.to_radians(), 123.4e-6, 27e-3);
        let (pitch, half_aperture) = (WAVELENGTH_M / 4.0, ze * alpha.tan());
        let count = (2.0 * half_aperture / pitch) as usize + 16;
        let field = Field1d::sampled(xe - half_aperture - 8.0 * pitch, pitch, count, |x| {
            let r = ((x - xe).powi(2) + ze * ze).sqrt();
            let inside = (x - xe).abs() <= half_aperture;
            Complex64::from_polar(if inside { 1.0 } else { 0.0 }, -2.0 * PI * r / WAVELENGTH_M)
        });
        // Watch ±20 µm around the emitter at λ/16, off the input grid; and
        // ±1 mm at λ/4 for the defocused spots.
        let spot = |z: f64, half_width: f64, out_pitch: f64| {
            let n = (2.0 * half_width / out_pitch) as usize;
            let out = propagate_to(&field, WAVELENGTH_M, z, xe - half_width + 0.37 * out_pitch, out_pitch, n).unwrap();
            let peak = out.samples.iter().map(|s| s.norm_sqr()).fold(0.0, f64::max);
            (intensity_peak(&out).unwrap(), peak)
        };
        let ((x, fwhm), peak) = spot(ze, 20e-6, WAVELENGTH_M / 16.0);
        let expected = 0.886 * WAVELENGTH_M / (2.0 * alpha.sin());
        let [((_, wide_near), dim_near), ((_, wide_far), dim_far)] = [0.9 * ze, 1.1 * ze].map(|z| spot(z, 1e-3, pitch));
        eprintln!(
            "focus: FWHM {:.4} µm (expected {:.4}), off by {:.2} nm; at 0.9 and 1.1 ze FWHM {:.0} and {:.0} µm",
            fwhm * 1e6,
            expected * 1e6,
            (x - xe) * 1e9,
            wide_near * 1e6,
            wide_far * 1e6
        );
        assert!((x - xe).abs() < 0.02 * fwhm);
        assert!((fwhm / expected - 1.0).abs() < 0.05);
        assert!(wide_near.min(wide_far) > 5.0 * fwhm && dim_near.max(dim_far) < 0.1 * peak);
    }

    #[test]
    fn forward_then_backward_returns_the_field() {
        // A tilted, diverging Gaussian beam that stays well inside the window.
        let (pitch, n, z) = (0.5e-6, 4096, 3e-3);
        let field = Field1d::sampled(-1.024e-3, pitch, n, |x| {
            let phase = 2.0 * PI * (x * 5f64.to_radians().sin() + x * x / (2.0 * 20e-3)) / WAVELENGTH_M;
            Complex64::from_polar((-(x / 150e-6).powi(2)).exp(), phase)
        });
        let forward = propagate(&field, WAVELENGTH_M, z).unwrap();
        let back = propagate(&forward, WAVELENGTH_M, -z).unwrap();
        let error = relative_l2(&back.samples[1024..3072], &field.samples[1024..3072]);
        eprintln!("forward and back by {z} m: relative L2 {error:.1e}");
        assert!(error < 1e-9);
        // The planned propagation is the same computation.
        let plan = Propagator::new(n, pitch, field.x0_m, WAVELENGTH_M, z).unwrap();
        let d = relative_l2(&plan.apply(&field).unwrap().samples, &forward.samples);
        assert!(d < 1e-10, "{d}");
        let shorter = Field1d { samples: field.samples[..100].to_vec(), ..field.clone() };
        assert!(plan.apply(&shorter).is_err());
    }

    #[test]
    fn bad_arguments_are_usage_errors() {
        let good = Field1d::sampled(0.0, 1e-6, 64, |x| Complex64::new(x, 1.0));
        let zero_pitch = Field1d { pitch_m: 0.0, ..good.clone() };
        let empty = Field1d { samples: vec![], ..good.clone() };
        let nan = Field1d { samples: vec![Complex64::new(f64::NAN, 0.0)], ..good.clone() };
        for field in [&zero_pitch, &empty, &nan] {
            assert!(matches!(propagate(field, WAVELENGTH_M, 1e-3), Err(Error::Argument { .. })));
        }
        let usage = |r: Result<Field1d>| matches!(r, Err(Error::Argument { .. }));
        assert!(usage(propagate(&good, f64::NAN, 1e-3)) && usage(propagate(&good, WAVELENGTH_M, f64::INFINITY)));
        assert!(usage(propagate_to(&good, WAVELENGTH_M, 1e-3, 0.0, 0.7e-6, 10)));
        assert!(usage(propagate_to(&good, WAVELENGTH_M, 1e-3, 1e3, 1e-6, 10)));
        let outside = Window::new(1.0, 2.0, Taper::Rect);
        assert!(matches!(angular_spectrum(&good, outside, WAVELENGTH_M), Err(Error::Argument { .. })));
        assert!(intensity_peak(&Field1d { samples: vec![Complex64::new(1.0, 0.0); 8], ..good }).is_err());
    }
}
