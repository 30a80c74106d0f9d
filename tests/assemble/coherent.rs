//! The coherent eye (spec/layouts.md §9.2): an eye focused on the emitter
//! plane images it through its pupil, so the light of neighbouring emitters
//! interferes.
//!
//! - Two point sources imaged through a slit pupil give the two-point
//!   interference pattern of coherent imaging (Goodman, *Introduction to
//!   Fourier Optics*, §6.1): each point's image is the pupil's transform, and
//!   the two add with the phase their paths to the pupil give them. Checked
//!   against that formula, evaluated independently here, for sources in
//!   phase, in antiphase and seen from off axis.
//! - On Mark III a lone fully lit emitter reads 1 wherever it is and from any
//!   eye (the calibration), and the ripple a coherent eye sees along a
//!   uniformly lit hololine is measured.

use std::f64::consts::PI;

use holo::assemble::Assembler;
use holo::layout::{builtin, EmitterPhases};
use holo::reconstruct::coherent::{CoherentImage, FocusedEye};
use holo::reconstruct::propagate::Field1d;
use holo::reconstruct::viewer::{ColourOptics, Eye};
use holo::Modulation;
use holo_fft::Complex64;

const WAVELENGTH_M: f64 = 633e-9;

/// A narrow Gaussian source's spectrum, normalised to 1 at frequency 0.
fn gaussian_spectrum(sigma_m: f64, f: f64) -> f64 {
    (-2.0 * PI * PI * sigma_m * sigma_m * f * f).exp()
}

/// The image amplitude at `x` of point sources `(x_i, amplitude_i)` through
/// the eye, by the coherent-imaging formula: each source's image is the
/// inverse transform of its pupil band, `∫ e^{i2πf(x − x_i)} df` over the
/// band, weighted by its (Gaussian) spectrum at the frequencies it sends
/// into the pupil, with the phase `k (r_i − d)` of its path to the pupil's
/// centre. Integrated by the midpoint rule, not by an FFT.
fn two_point_image(sources: &[(f64, Complex64)], sigma_m: f64, eye: &FocusedEye, x: f64) -> Complex64 {
    let k = 2.0 * PI / WAVELENGTH_M;
    sources
        .iter()
        .map(|&(x_i, a)| {
            let (lo, hi) = eye.band(x_i, WAVELENGTH_M);
            let r = ((x_i - eye.x_m).powi(2) + eye.distance_m.powi(2)).sqrt();
            let sin_c = (eye.x_m - x_i) / r;
            let steps = 4000;
            let df = (hi - lo) / steps as f64;
            let integral: Complex64 = (0..steps)
                .map(|s| {
                    let f = lo + (s as f64 + 0.5) * df;
                    // The source sends frequency f + sin θ_c / λ of its own spectrum there.
                    gaussian_spectrum(sigma_m, f + sin_c / WAVELENGTH_M)
                        * Complex64::from_polar(df, 2.0 * PI * f * (x - x_i))
                })
                .sum();
            a * Complex64::from_polar(1.0, k * (r - eye.distance_m)) * integral
        })
        .sum()
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn two_points_interfere_as_coherent_imaging_says() {
    let sigma = 0.4e-6;
    let pitch = 0.25e-6;
    // The eye's resolution λd/a: 86 µm at Mark III's viewer distance.
    let (distance, pupil) = (0.546, 4e-3);
    let separation = 100e-6;
    // 20 mm of field: the FFT resolves the pupil's band to 1/(40 mm), 0.2 %
    // of its width.
    let count = 80_000;
    let x0 = -10e-3;
    for (eye_x, relative_phase, what) in
        [(0.0, 0.0, "in phase"), (0.0, PI, "in antiphase"), (0.0, PI / 2.0, "in quadrature"), (0.04, 0.0, "off axis")]
    {
        let eye = FocusedEye { x_m: eye_x, distance_m: distance, pupil_m: pupil };
        let sources = [
            (-separation / 2.0, Complex64::new(1.0, 0.0)),
            (separation / 2.0, Complex64::from_polar(0.8, relative_phase)),
        ];
        // Each Gaussian has unit peak; its spectrum's area is sigma·sqrt(2π).
        let field = Field1d::sampled(x0, pitch, count, |x| {
            sources.iter().map(|&(x_i, a)| a * (-(x - x_i).powi(2) / (2.0 * sigma * sigma)).exp()).sum()
        });
        let bands: Vec<(f64, f64)> = sources.iter().map(|s| eye.band(s.0, WAVELENGTH_M)).collect();
        let union = (bands[0].0.min(bands[1].0), bands[0].1.max(bands[1].1));
        let image = CoherentImage::new(&field, &eye, WAVELENGTH_M, union).unwrap();
        let scale = sigma * (2.0 * PI).sqrt();
        // The per-source band: the power over a window around each source.
        for (i, &(x_i, _)) in sources.iter().enumerate() {
            let half = 60e-6;
            let first = ((x_i - half - x0) / pitch).round() as i64;
            let samples = (2.0 * half / pitch).round() as usize;
            let got = image.power(first, samples, bands[i], pitch);
            let want: f64 = (0..samples)
                .map(|s| {
                    let x = x0 + (first + s as i64) as f64 * pitch;
                    (two_point_image(&sources, sigma, &eye, x) * scale).norm_sqr() * pitch
                })
                .step_by(1)
                .sum();
            // The window takes all its light through its own source's band;
            // the formula gives the other source's light its own band, which
            // differs by 1e-5 of the width on axis, 1e-4 off it.
            eprintln!("{what}: window around source {i}: {:.1e} from the formula", got / want - 1.0);
            assert!((got / want - 1.0).abs() < 2e-4, "{what}: window around source {i}: {got:e} against {want:e}");
        }
        // The whole pattern through one band (the pair's mean: the two differ
        // by 1e-5 of the band on axis).
        let band = ((bands[0].0 + bands[1].0) / 2.0, (bands[0].1 + bands[1].1) / 2.0);
        let intensity = image.intensity(band);
        let peak = intensity.iter().cloned().fold(0.0, f64::max);
        let mut worst: f64 = 0.0;
        for s in (0..count).step_by(20) {
            let x = x0 + s as f64 * pitch;
            if x.abs() > 400e-6 {
                continue;
            }
            let want = (two_point_image(&sources, sigma, &eye, x) * scale).norm_sqr();
            worst = worst.max((intensity[s] - want).abs() / peak);
        }
        eprintln!("{what}: largest difference from the two-point formula {worst:.1e} of the peak");
        assert!(worst < 1e-4, "{what}: {worst:e}");
        // The physics the pattern shows: between two sources in antiphase
        // the light cancels; in phase it adds.
        let mid = ((0.0 - x0) / pitch).round() as usize;
        if what == "in antiphase" {
            assert!(intensity[mid] < 0.03 * peak, "antiphase midpoint {} of peak", intensity[mid] / peak);
        }
        if what == "in phase" {
            assert!(intensity[mid] > 0.5 * peak, "in-phase midpoint {} of peak", intensity[mid] / peak);
        }
    }
}

/// Mark III with one hololine.
fn mark3_one_line() -> holo::layout::Layout {
    let mut layout = builtin("mark3").unwrap();
    layout.geometry.hololines = 1;
    layout
}

fn coherent_eye(layout: &holo::layout::Layout, x_m: f64) -> Eye {
    Eye { x_m, y_m: 0.0, z_m: layout.geometry.viewer_distance_m, pupil_m: 4e-3, coherent: true }
}

/// What coherent eyes see of `lit(e)` (every view of emitter `e` at that
/// value) on one Mark III hololine, from its float signals (no rounding, no
/// blanking).
fn seen_coherently(layout: &holo::layout::Layout, lit: impl Fn(usize) -> f32, eyes: &[Eye]) -> Vec<Vec<f64>> {
    let a = Assembler::new(layout).unwrap();
    let m = Modulation::from_fn(layout.geometry.clone(), |_, _, e, _| lit(e)).unwrap();
    let signals = a.signals(&m, 0).unwrap();
    let rows: Vec<&[f32]> = (0..signals.signals).map(|s| signals.row(s, 0)).collect();
    let optics = ColourOptics::new(&a, 0).unwrap();
    let field = optics.emitter_plane(&rows).unwrap();
    eyes.iter()
        .map(|eye| {
            let calibration = optics.coherent_calibration(eye).unwrap();
            optics.seen_coherently(&field, eye, &calibration).unwrap()
        })
        .collect()
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn a_lone_emitter_reads_one_to_a_coherent_eye_wherever_it_is() {
    let layout = mark3_one_line();
    let emitters = layout.geometry.emitters;
    let eyes: Vec<Eye> = [-0.04, 0.0, 0.04].iter().map(|&x| coherent_eye(&layout, x)).collect();
    for e in [emitters / 5, emitters / 2 + 7, 4 * emitters / 5] {
        let seen = seen_coherently(&layout, |k| if k == e { 1.0 } else { 0.0 }, &eyes);
        for (eye, row) in eyes.iter().zip(&seen) {
            eprintln!("lone emitter {e}, eye at {} mm: {:.5}", eye.x_m * 1e3, row[e]);
            assert!((row[e] - 1.0).abs() < 1e-3, "emitter {e}, eye {} mm: {}", eye.x_m * 1e3, row[e]);
        }
    }
}

/// Standard deviation over mean of `row[range]`.
fn ripple(row: &[f64]) -> f64 {
    let mean = row.iter().sum::<f64>() / row.len() as f64;
    (row.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / row.len() as f64).sqrt() / mean
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn coherent_eye_sees_neighbouring_emitters_interfere() {
    let layout = mark3_one_line();
    let emitters = layout.geometry.emitters;
    let eyes: Vec<Eye> = [-0.04, 0.0, 0.04].iter().map(|&x| coherent_eye(&layout, x)).collect();
    // Away from the hololine's ends, where a chirp is cut short.
    let inner = emitters / 8..emitters - emitters / 8;
    let all = seen_coherently(&layout, |_| 0.5, &eyes);
    let sparse = seen_coherently(&layout, |e| if e % 4 == 0 { 0.5 } else { 0.0 }, &eyes);
    for (k, eye) in eyes.iter().enumerate() {
        let all_lit: Vec<f64> = all[k][inner.clone()].to_vec();
        let every_4th: Vec<f64> = inner.clone().filter(|e| e % 4 == 0).map(|e| sparse[k][e]).collect();
        let (r_all, r_4th) = (ripple(&all_lit), ripple(&every_4th));
        let (lo, hi) = all_lit.iter().fold((f64::INFINITY, 0f64), |(l, h), &x| (l.min(x), h.max(x)));
        eprintln!(
            "eye at {:+} mm: uniformly lit ripple {:.1} % (range {lo:.3}–{hi:.3}), every 4th emitter lit {:.1} %",
            eye.x_m * 1e3,
            100.0 * r_all,
            100.0 * r_4th
        );
        // Neighbours 238 µm apart through a pupil resolving 86 µm overlap
        // and interfere; emitters four apart barely do.
        assert!(r_all > 2.0 * r_4th, "eye {} mm: {r_all} against {r_4th}", eye.x_m * 1e3);
    }
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn emitter_phases_set_the_ripple_a_coherent_eye_sees() {
    let eyes_mm = [-40.0, 0.0, 40.0];
    let mut ripples = Vec::new();
    for phases in [EmitterPhases::Zero, EmitterPhases::Random, EmitterPhases::Quadrature, EmitterPhases::Viewer] {
        let mut layout = mark3_one_line();
        layout.fringe.as_mut().unwrap().emitter_phases = phases;
        let emitters = layout.geometry.emitters;
        let inner = emitters / 8..emitters - emitters / 8;
        let eyes: Vec<Eye> = eyes_mm.iter().map(|&x| coherent_eye(&layout, x * 1e-3)).collect();
        let seen = seen_coherently(&layout, |_| 0.5, &eyes);
        let per_eye: Vec<f64> = seen.iter().map(|row| ripple(&row[inner.clone()])).collect();
        if std::env::var("HOLO_RIPPLE").is_ok() {
            for row in &seen {
                eprintln!(
                    "{:?}",
                    row[inner.clone()]
                        .chunks(8)
                        .map(|c| format!("{:.2}", c.iter().sum::<f64>() / 4.0))
                        .collect::<Vec<_>>()
                        .join(" ")
                );
            }
        }
        eprintln!(
            "emitter phases {phases:?}: ripple {} (eyes at {eyes_mm:?} mm)",
            per_eye.iter().map(|r| format!("{:.1} %", 100.0 * r)).collect::<Vec<_>>().join(", ")
        );
        ripples.push(per_eye);
    }
    // Viewer phases make every emitter's neighbours interfere alike: from
    // the centre (and −40 mm) the ripple all but goes; from +40 mm a slow
    // swell over the right third of the line is left (0.89–1.46 of the
    // uniform level over blocks of 8 emitters, HOLO_RIPPLE=1 prints them).
    for k in 0..eyes_mm.len() {
        assert!(ripples[3][k] < ripples[0][k], "eye {} mm: {:?}", eyes_mm[k], ripples);
        assert!(ripples[2][k] < ripples[0][k], "eye {} mm: {:?}", eyes_mm[k], ripples);
    }
    assert!(ripples[3][1] < 0.2 * ripples[0][1], "{ripples:?}");
}
