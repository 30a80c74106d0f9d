//! From a hololine's signals to the complex field the display makes on the
//! hologram plane, in the geometric frame: a plane wave leaving at `θ` is
//! `exp(i 2π x sin θ / λ)` (the reference beam and every carrier undone).
//!
//! Each zone's signal becomes its analytic form `a(n)`: `I + iQ` for an I/Q
//! pair (the display's single-sideband modulator keeps one side), the
//! positive-frequency half of a real signal (the first diffracted order; the
//! other order and the undiffracted light leave elsewhere, docs/optics.md §3, §8.1).
//! `a(n)` is interpolated between samples by its band-limited (sinc)
//! interpolation, the display's ideal DAC reconstruction, onto a grid `M`
//! times finer, fine enough for the whole fan of directions; then it is
//! shifted by the zone's signal carrier `c`: `E(x) = Σ_zones a(x) · exp(−i 2π c x / pitch)`.
//! For Mark III that is the Weaver up-conversion that puts each zone back at
//! its own angles (Smithwick et al. 2009 §5.1).

use std::f64::consts::PI;

use holo_fft::Complex64;

use super::propagate::Field1d;
use crate::assemble::ColourBasis;
use crate::layout::SignalKind;

/// The fine grid's factor: the smallest `M` whose band `±M/2` cycles per
/// sample holds every direction of the fan (`|sin θ| · pitch / λ`) with a
/// 10% margin.
pub fn oversampling(basis: &ColourBasis) -> usize {
    let largest = basis.view_sin_edges.iter().flat_map(|&(a, b)| [a.abs(), b.abs()]).fold(0f64, f64::max);
    let cycles = largest * basis.pitch_m / basis.wavelength_m;
    ((2.0 * cycles * 1.1).floor() as usize + 1).max(1)
}

/// The hologram-plane field of one hololine from its signals (one slice per
/// signal, in the layout's order), sampled `M` = [`oversampling`] times
/// finer than the signal, sample `k` at `x = (k / M + ½ − N/2) · pitch`.
#[cfg(test)]
pub fn hologram_field(basis: &ColourBasis, signals: &[&[f32]]) -> Field1d {
    FieldPlan::new(basis, None).field(signals)
}

/// The hologram-plane field of a hololine (`hologram_field`) planned once per layout and colour: the carriers'
/// phasors on the fine grid are computed once, in f64 (their phase reduced
/// exactly before scaling), and reused for every hololine.
#[derive(Clone, Debug)]
pub struct FieldPlan {
    samples: usize,
    oversampling: usize,
    signal: SignalKind,
    pitch_m: f64,
    /// Per zone, `exp(−i 2π c k / M)` on the fine grid.
    carriers: Vec<Vec<Complex64>>,
    /// Per zone, the signal frequencies kept (cycles per sample, `[lo, hi)`).
    pass: Vec<(f64, f64)>,
}

impl FieldPlan {
    /// The plan for `basis`, keeping only the signal frequencies inside
    /// `pass[zone]` when given: the band this colour's wavelength reads when
    /// colours share a signal (frequency-division colour).
    pub fn new(basis: &ColourBasis, pass: Option<&[(f64, f64)]>) -> Self {
        let (n, m) = (basis.samples, oversampling(basis));
        let carriers = (0..basis.zones())
            .map(|zone| {
                let c = basis.signal_carrier(zone);
                (0..n * m)
                    .map(|k| {
                        let cycles = (c * (k / m) as f64).rem_euclid(1.0) + c * (k % m) as f64 / m as f64;
                        Complex64::from_polar(1.0, -2.0 * PI * cycles)
                    })
                    .collect()
            })
            .collect();
        let pass =
            (0..basis.zones()).map(|zone| pass.map_or((f64::NEG_INFINITY, f64::INFINITY), |p| p[zone])).collect();
        FieldPlan { samples: n, oversampling: m, signal: basis.signal, pitch_m: basis.pitch_m, carriers, pass }
    }

    /// The grid of the fields made: (samples, pitch in metres, `x` of sample 0).
    pub fn grid(&self) -> (usize, f64, f64) {
        let m = self.oversampling;
        (self.samples * m, self.pitch_m / m as f64, (0.5 - self.samples as f64 / 2.0) * self.pitch_m)
    }

    /// The field of one hololine from its signals.
    pub fn field(&self, signals: &[&[f32]]) -> Field1d {
        let (n, m) = (self.samples, self.oversampling);
        let forward = holo_fft::forward(n);
        let inverse = holo_fft::inverse(n * m);
        let mut total = vec![Complex64::new(0.0, 0.0); n * m];
        let mut fine = vec![Complex64::new(0.0, 0.0); n * m];
        for (zone, carrier) in self.carriers.iter().enumerate() {
            let mut a: Vec<Complex64> = match self.signal {
                SignalKind::Iq => signals[2 * zone]
                    .iter()
                    .zip(signals[2 * zone + 1])
                    .map(|(i, q)| Complex64::new(f64::from(*i), f64::from(*q)))
                    .collect(),
                SignalKind::Real => signals[zone].iter().map(|s| Complex64::new(f64::from(*s), 0.0)).collect(),
            };
            forward.process(&mut a);
            // Spectrum onto the fine grid: bins 0..N/2 are positive
            // frequencies, N/2..N negative. A real signal keeps its positive
            // half, doubled; only the pass band goes through.
            let (lo, hi) = self.pass[zone];
            fine.fill(Complex64::new(0.0, 0.0));
            for (k, x) in a.iter().enumerate() {
                let f = if k < n.div_ceil(2) { k as i64 } else { k as i64 - n as i64 };
                let cycles = f as f64 / n as f64;
                if cycles < lo || cycles >= hi {
                    continue;
                }
                let x = match self.signal {
                    SignalKind::Iq => *x,
                    SignalKind::Real if f > 0 => *x * 2.0,
                    SignalKind::Real => continue,
                };
                let at = if f >= 0 { f } else { (n * m) as i64 + f } as usize;
                fine[at] = x;
            }
            inverse.process(&mut fine);
            let scale = 1.0 / n as f64;
            total.iter_mut().zip(&fine).zip(carrier).for_each(|((t, x), c)| *t += x * c * scale);
        }
        Field1d { samples: total, pitch_m: self.pitch_m / m as f64, x0_m: (0.5 - n as f64 / 2.0) * self.pitch_m }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{mark1, mark3, Layout};

    /// The field of a single element, from the fast signals, against the
    /// element's own geometric phase: a chirp segment's local frequency must
    /// be `sin θ / λ` of its view (no carrier left).
    fn check_view_direction(layout: Layout, colour: usize, e: usize, v: usize) {
        let mut layout = layout;
        layout.geometry.hololines = 1;
        let a = crate::assemble::Assembler::new(&layout).unwrap();
        let mut m = crate::modulation::Modulation::zeros(layout.geometry.clone()).unwrap();
        m.set(colour, 0, e, v, 1.0);
        let s = a.signals(&m, colour).unwrap();
        let basis = a.plan(colour).basis();
        let rows: Vec<&[f32]> = (0..s.signals).map(|k| s.row(k, 0)).collect();
        let field = hologram_field(basis, &rows);
        // Phase slope across the middle of the element's segment.
        let seg = basis.segment(e, v);
        let mm = oversampling(basis);
        let (k0, k1) = ((seg.start + seg.len / 4) * mm, (seg.start + 3 * seg.len / 4) * mm);
        let mut unwrapped = 0.0;
        for k in k0..k1 {
            unwrapped += (field.samples[k + 1] / field.samples[k]).arg();
        }
        let cycles_per_m = unwrapped / (2.0 * PI) / ((k1 - k0) as f64 * field.pitch_m);
        let sin = cycles_per_m * basis.wavelength_m;
        let (lo, hi) = basis.view_sin_edges[v];
        assert!(sin > lo - 1e-3 && sin < hi + 1e-3, "{}: view {v} at sin {sin}, interval {lo}..{hi}", layout.name);
    }

    #[test]
    fn every_carrier_is_undone_and_views_leave_at_their_angles() {
        for v in [0, 31, 32, 47, 64, 95] {
            check_view_direction(mark3(), 0, 100, v);
        }
        for colour in 0..3 {
            for v in 0..5 {
                check_view_direction(mark1(), colour, 17, v);
            }
        }
    }
}
