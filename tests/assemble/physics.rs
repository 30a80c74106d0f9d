//! Physics checked against physics (docs/optics.md §8.5): fringes assembled by the
//! fast path, reconstructed by scalar diffraction, against closed forms.
//!
//! - One chirp focuses to a diffraction-limited spot at its emitter.
//! - One hogel view's gratings send their light at `asin(sin θ_r + λ f)`.
//! - Each view of one emitter lights its own direction (crosstalk printed).
//! - Reconstructed intensity is proportional to stored radiance.

use holo::assemble::Assembler;
use holo::layout::{builtin, Layout};
use holo::reconstruct::propagate::{intensity_peak, propagate_to};
use holo::reconstruct::viewer::ColourOptics;
use holo::Modulation;
use rayon::prelude::*;

fn one_hololine(name: &str) -> Layout {
    let mut l = builtin(name).unwrap();
    l.geometry.hololines = 1;
    let fb = &mut l.fringe.as_mut().unwrap().frame_buffer;
    fb.height = fb.first_row + fb.rows_per_hololine;
    l
}

/// The hologram-plane field of one hololine lit by `lit(e, v)` in colour
/// `c`, through the frame buffer (float samples, every colour's signals as
/// the display gets them) and the optics of that colour.
fn field_of(a: &Assembler, c: usize, lit: impl Fn(usize, usize) -> f32) -> holo::reconstruct::propagate::Field1d {
    let g = a.layout().geometry.clone();
    let m = Modulation::from_fn(g, |cc, _, e, v| if cc == c { lit(e, v) } else { 0.0 }).unwrap();
    let (images, _) = a.assemble::<f32>(&m).unwrap();
    let unpacked = a.unpack(&images, 1).unwrap();
    let s = &unpacked[c.min(unpacked.len() - 1)];
    let rows: Vec<&[f32]> = (0..s.signals).map(|k| s.row(k, 0)).collect();
    let optics = ColourOptics::new(a, c).unwrap();
    let field = optics.emitter_plane(&rows).unwrap();
    // Back to the hologram plane (hogels live there already).
    if a.layout().geometry.emitter_z_m == 0.0 {
        field
    } else {
        let lambda = a.plan(c).basis().wavelength_m;
        holo::reconstruct::propagate::propagate(&field, lambda, -a.layout().geometry.emitter_z_m).unwrap()
    }
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn one_chirp_focuses_to_a_diffraction_limited_spot_at_its_emitter() {
    // Mark III (three zones joined by the Weaver up-conversion), Mark I in
    // every colour and Mark II (real signals with a carrier).
    for (name, colour) in [("mark3", 0), ("mark1", 0), ("mark1", 2), ("mark2", 0)] {
        let layout = one_hololine(name);
        let a = Assembler::new(&layout).unwrap();
        let g = &layout.geometry;
        let e = g.emitters / 3;
        let field = field_of(&a, colour, |k, _| if k == e { 1.0 } else { 0.0 });
        let lambda = g.channels[colour].wavelength_m;
        let (x_e, z_e) = (g.emitter_x_m(e), g.emitter_z_m);
        // Half the fan: the chirp's edges leave at ±θ.
        let edges = &a.plan(colour).basis().view_sin_edges;
        let na = edges.iter().map(|(lo, hi)| lo.abs().max(hi.abs())).fold(0.0, f64::max);
        let expected_fwhm = 0.886 * lambda / (2.0 * na);
        let depth_of_focus = lambda / (na * na);
        // Peak intensity along z, on a grid 1/8 of the field's pitch around x_e.
        let pitch = field.pitch_m / 8.0;
        let count = (8.0 * expected_fwhm / pitch) as usize;
        let x0 = x_e - count as f64 / 2.0 * pitch;
        let at = |z: f64| {
            let f = propagate_to(&field, lambda, z, x0, pitch, count).unwrap();
            let peak = f.samples.iter().map(|s| s.norm_sqr()).fold(0.0, f64::max);
            (peak, f)
        };
        // The brightest of `steps` (each depth an independent propagation:
        // on every core), and the peaks there.
        let scan = |steps: &[f64]| {
            let peaks: Vec<f64> = steps.par_iter().map(|&z| at(z).0).collect();
            let k = peaks.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap().0;
            assert!(k > 0 && k < steps.len() - 1, "{name}: the focus is outside the scan {steps:?}");
            (k, peaks)
        };
        // ±3 depths of focus in half depths, then ±½ around the brightest
        // in tenths (the focus's peak is about a depth of focus wide).
        let coarse: Vec<f64> = (-6..=6).map(|k| z_e + k as f64 * depth_of_focus / 2.0).collect();
        let (k, _) = scan(&coarse);
        let steps: Vec<f64> = (-5..=5).map(|j| coarse[k] + j as f64 * depth_of_focus / 10.0).collect();
        let (k, peaks) = scan(&steps);
        // Parabola through the three samples around the maximum.
        let (p0, p1, p2) = (peaks[k - 1], peaks[k], peaks[k + 1]);
        let z_focus = steps[k] + 0.5 * (p0 - p2) / (p0 - 2.0 * p1 + p2) * depth_of_focus / 10.0;
        let (x_focus, fwhm) = intensity_peak(&at(z_focus).1).unwrap();
        eprintln!(
            "{name} colour {colour}: focus at x_e {:+.3} µm, z_e {:+.2} µm (depth of focus {:.1} µm); FWHM {:.3} µm vs \
             diffraction limit {:.3} µm",
            (x_focus - x_e) * 1e6,
            (z_focus - z_e) * 1e6,
            depth_of_focus * 1e6,
            fwhm * 1e6,
            expected_fwhm * 1e6
        );
        assert!((x_focus - x_e).abs() < 0.05 * fwhm, "{name}: x off by {} m", x_focus - x_e);
        assert!((z_focus - z_e).abs() < 0.1 * depth_of_focus, "{name}: z off by {} m", z_focus - z_e);
        assert!((fwhm / expected_fwhm - 1.0).abs() < 0.1, "{name}: FWHM {fwhm} vs {expected_fwhm}");
    }
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn hogel_gratings_send_light_at_asin_lambda_f_for_every_view() {
    use holo::reconstruct::propagate::{angular_spectrum, Taper, Window};
    use holo_fft::Complex64;
    for name in ["mark1-hogel", "mark4"] {
        let layout = one_hololine(name);
        let a = Assembler::new(&layout).unwrap();
        let g = &layout.geometry;
        let f = layout.fringe.as_ref().unwrap();
        let holo::layout::Basis::Hogel { hogel_samples: w } = f.basis else { unreachable!() };
        let e = g.emitters / 2;
        let mut checked = 0;
        let mut least_inside = 1f64;
        for colour in 0..g.channels.len() {
            let basis = a.plan(colour).basis();
            let lambda = basis.wavelength_m;
            let holo::assemble::basis::Elements::Hogel(gratings) = &basis.elements else { unreachable!() };
            for v in 0..g.views.count {
                let field = field_of(&a, colour, |k, u| f32::from(k == e && u == v));
                let x_lo = g.emitter_x_m(e) - g.emitter_pitch_m / 2.0;
                // The light in direction sin θ, straight from the field around
                // the hogel (taking the first diffracted order of a real signal
                // spreads the hogel's field a little beyond its edges).
                let reach = 16.0 * g.emitter_pitch_m;
                let hogel: Vec<(f64, Complex64)> = (0..field.samples.len())
                    .map(|k| (field.x_m(k), field.samples[k]))
                    .filter(|(x, _)| *x >= x_lo - reach && *x < x_lo + g.emitter_pitch_m + reach)
                    .collect();
                let power = |sin: f64| {
                    let sum: Complex64 = hogel
                        .iter()
                        .map(|(x, s)| s * Complex64::from_polar(1.0, -2.0 * std::f64::consts::PI * sin / lambda * x))
                        .sum();
                    sum.norm_sqr()
                };
                // Grating b of the view, at sin θ = (b/W − carrier)·λ/pitch (the
                // grating equation with the reference beam's carrier undone),
                // has all of its power there: the hogel's other gratings sit on
                // its own frequency grid and vanish in that direction. Each of
                // the view's n gratings has amplitude 1/(sqrt(n) · 3 sqrt(V)).
                let list = &gratings.gratings[v];
                let expected = (w as f64).powi(2) / (list.len() as f64 * 9.0 * g.views.count as f64);
                for &(b, _) in list {
                    let sin = (b as f64 / w as f64 - f.carrier(colour)) * lambda / f.sample_pitch_m;
                    let p = power(sin);
                    assert!(
                        (p / expected - 1.0).abs() < 0.01,
                        "{name} colour {colour} view {v} grating {b}: {p} vs {expected}"
                    );
                    checked += 1;
                }
                // And the view's light is centred on the view's direction.
                let mut window = Window::new(x_lo, x_lo + g.emitter_pitch_m, Taper::Rect);
                window.zero_pad = 16;
                let spectrum = angular_spectrum(&field, window, lambda).unwrap();
                let (lo, hi) = basis.view_sin_edges[v];
                let inside = spectrum.power_between(lo, hi) / spectrum.total_power();
                let centroid: f64 = spectrum.sin_theta.iter().zip(&spectrum.power).map(|(s, p)| s * p).sum::<f64>()
                    / spectrum.total_power();
                // A view is a few gratings wide and each grating's light spreads
                // by one hogel's diffraction (λ / W·pitch): most, not all, of it
                // stays inside.
                assert!(inside > 0.6, "{name} colour {colour} view {v}: {inside:.3} of the light inside");
                least_inside = least_inside.min(inside);
                assert!((centroid - g.views.theta_rad(v).sin()).abs() < (hi - lo) / 4.0, "{name} view {v}");
            }
        }
        eprintln!(
            "{name}: {checked} gratings at asin(λ f) to 1% of their power; every view keeps at least {:.0}% of its \
             light inside its interval",
            100.0 * least_inside
        );
    }
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn each_view_of_one_emitter_lights_its_own_direction() {
    eprintln!("view crosstalk (one view of one emitter lit; share of the reconstructed light):");
    eprintln!("  layout        own view   ±1 view   further   next emitter");
    for (name, own_min) in [("mark3", 0.7), ("mark1", 0.9), ("mark1-hogel", 0.85), ("mark2", 0.8), ("mark4", 0.85)] {
        let layout = one_hololine(name);
        let a = Assembler::new(&layout).unwrap();
        let optics = ColourOptics::new(&a, 0).unwrap();
        let views = layout.geometry.views.count;
        let e = layout.geometry.emitters / 3;
        let (mut own, mut near, mut far, mut next) = (0.0, 0.0, 0.0, 0.0);
        let tested: Vec<usize> = (0..views).step_by((views / 8).max(1)).collect();
        for &v in &tested {
            let m = Modulation::from_fn(layout.geometry.clone(), |c, _, k, w| f32::from(c == 0 && k == e && w == v))
                .unwrap();
            let s = a.signals(&m, 0).unwrap();
            let rows: Vec<&[f32]> = (0..s.signals).map(|k| s.row(k, 0)).collect();
            let field = optics.emitter_plane(&rows).unwrap();
            let got = optics.views(&optics.spectrum(&field, e));
            let total: f64 = got.iter().sum();
            let share = |w: usize| got[w] / total;
            own += share(v);
            near += [v.wrapping_sub(1), v + 1].iter().filter(|w| **w < views).map(|w| share(*w)).sum::<f64>();
            far += (0..views).filter(|w| w.abs_diff(v) > 1).map(share).sum::<f64>();
            next += optics.views(&optics.spectrum(&field, e + 1)).iter().sum::<f64>() / total;
            // The brightest view is the one lit.
            let brightest = (0..views).max_by(|a, b| got[*a].total_cmp(&got[*b])).unwrap();
            assert_eq!(brightest, v, "{name}: view {v} lit, view {brightest} brightest");
        }
        let n = tested.len() as f64;
        let (own, near, far, next) = (own / n, near / n, far / n, next / n);
        eprintln!("  {name:<12}  {own:>8.3}  {near:>8.3}  {far:>8.3}  {next:>12.3}");
        assert!(own > own_min, "{name}: {own}");
        assert!(far < 0.05 && next < 0.05, "{name}: {far} beyond the neighbours, {next} in the next emitter");
    }
}

#[test]
fn reconstructed_intensity_is_proportional_to_stored_radiance() {
    // Weights are sqrt(m) (docs/optics.md §4.3): doubling a view's radiance must
    // double its reconstructed intensity.
    for name in ["mark3", "mark1-hogel"] {
        let layout = one_hololine(name);
        let a = Assembler::new(&layout).unwrap();
        let optics = ColourOptics::new(&a, 0).unwrap();
        let e = layout.geometry.emitters / 2;
        let v = layout.geometry.views.count / 3;
        let seen = |level: f32| {
            let m = Modulation::from_fn(
                layout.geometry.clone(),
                |c, _, k, w| {
                    if c == 0 && k == e && w == v {
                        level
                    } else {
                        0.0
                    }
                },
            )
            .unwrap();
            let s = a.signals(&m, 0).unwrap();
            let rows: Vec<&[f32]> = (0..s.signals).map(|k| s.row(k, 0)).collect();
            optics.views(&optics.spectrum(&optics.emitter_plane(&rows).unwrap(), e))[v]
        };
        let (one, two) = (seen(0.25), seen(0.5));
        assert!((two / one - 2.0).abs() < 1e-6, "{name}: {two} / {one}");
    }
}
