//! Exact recovery of a hololine's modulation from its signals: the signals
//! are linear in the weights `w = sqrt(m)`, so least squares against the
//! basis gives them back (docs/optics.md §8.4). What it cannot give
//! back is what the frame buffer lost: samples in the horizontal blanking
//! (left out of the fit) and the 8-bit rounding (which becomes the error).
//!
//! The solver is conjugate gradients on the normal equations (CGNR), with
//! the fast kernel as the forward map and [`Plan::zone_adjoint`] as its
//! transpose; the basis is close to orthogonal, so it converges in tens of
//! iterations.

use crate::assemble::Plan;

/// The forward map of one hololine: the weights of a group of colours (one
/// colour, or every colour when they share one signal) to the signals, with
/// the samples the display does not show masked out.
pub struct HololineOperator<'a> {
    /// The tabulated basis of each colour of the group.
    pub plans: Vec<&'a Plan>,
    /// `shown[s][n]`: whether sample `n` of signal `s` reaches the display.
    pub shown: Vec<Vec<bool>>,
}

impl HololineOperator<'_> {
    fn unknowns(&self) -> usize {
        self.plans.iter().map(|p| p.basis().emitters * p.basis().views).sum()
    }

    /// Signals of the weights `w` (colours one after the other).
    fn forward(&self, w: &[f64], out: &mut [Vec<f32>]) {
        out.iter_mut().for_each(|s| s.fill(0.0));
        let mut at = 0;
        for plan in &self.plans {
            let b = plan.basis();
            let n = b.emitters * b.views;
            let weights: Vec<f32> = w[at..at + n].iter().map(|x| *x as f32).collect();
            at += n;
            let (mut re, mut im) = (vec![0f32; b.samples], vec![0f32; b.samples]);
            for zone in 0..b.zones() {
                plan.zone(&weights, zone, &mut re, &mut im);
                for (lane, values) in [&re, &im].into_iter().enumerate().take(b.lanes()) {
                    out[zone * b.lanes() + lane].iter_mut().zip(values).for_each(|(o, v)| *o += v);
                }
            }
        }
        for (signal, shown) in out.iter_mut().zip(&self.shown) {
            signal.iter_mut().zip(shown).filter(|(_, shown)| !**shown).for_each(|(s, _)| *s = 0.0);
        }
    }

    /// The transpose of [`HololineOperator::forward`].
    fn adjoint(&self, signals: &[Vec<f32>], out: &mut [f64]) {
        out.fill(0.0);
        let masked: Vec<Vec<f32>> = signals
            .iter()
            .zip(&self.shown)
            .map(|(s, shown)| s.iter().zip(shown).map(|(x, shown)| if *shown { *x } else { 0.0 }).collect())
            .collect();
        let mut at = 0;
        for plan in &self.plans {
            let b = plan.basis();
            let n = b.emitters * b.views;
            let empty = Vec::new();
            for zone in 0..b.zones() {
                let re = &masked[zone * b.lanes()];
                let im = if b.lanes() == 2 { &masked[zone * 2 + 1] } else { &empty };
                plan.zone_adjoint(zone, re, im, &mut out[at..at + n]);
            }
            at += n;
        }
    }

    /// The weights whose signals best match `signals` (least squares over the
    /// shown samples), colours one after the other, and the iterations used.
    pub fn solve(&self, signals: &[Vec<f32>]) -> (Vec<f64>, usize) {
        const MAX_ITERATIONS: usize = 60;
        const TOLERANCE: f64 = 1e-7;
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let n = self.unknowns();
        let mut x = vec![0f64; n];
        let mut r: Vec<Vec<f32>> = signals.to_vec();
        let mut z = vec![0f64; n];
        self.adjoint(&r, &mut z);
        let z0 = dot(&z, &z);
        if z0 == 0.0 {
            return (x, 0);
        }
        let mut p = z.clone();
        let mut zz = z0;
        let mut q: Vec<Vec<f32>> = signals.iter().map(|s| vec![0f32; s.len()]).collect();
        for iteration in 1..=MAX_ITERATIONS {
            self.forward(&p, &mut q);
            let qq: f64 = q.iter().flatten().map(|v| f64::from(*v).powi(2)).sum();
            if qq == 0.0 {
                return (x, iteration);
            }
            let alpha = zz / qq;
            x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
            for (r, q) in r.iter_mut().zip(&q) {
                r.iter_mut().zip(q).for_each(|(r, q)| *r -= (alpha * f64::from(*q)) as f32);
            }
            self.adjoint(&r, &mut z);
            let zz_new = dot(&z, &z);
            if zz_new <= TOLERANCE * TOLERANCE * z0 {
                return (x, iteration);
            }
            let beta = zz_new / zz;
            zz = zz_new;
            p.iter_mut().zip(&z).for_each(|(p, z)| *p = z + beta * *p);
        }
        (x, MAX_ITERATIONS)
    }
}
