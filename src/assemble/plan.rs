//! The fast path: a [`ColourBasis`] tabulated once, and the kernel that
//! assembles hololines from the tables.
//!
//! Every element is a segment of a table: element (`e`, `v`) starts
//! `e · step` samples after element (0, `v`) and has the same values
//! (the bases are shift-invariant). Each zone's signal is cut into blocks of
//! `B` samples, `B` dividing the step and every segment's start and length, so
//! that within a block every element is either absent or covers it whole with
//! one weight. The elements covering a block depend only on the block's
//! position within the emitter step ("phase"), so one short list of
//! (emitter offset, view, table offset) terms per phase describes the whole
//! hololine. A block is then `Σ_terms w · table[at .. at + B]`: an axpy into
//! a register-sized accumulator, which vectorises (seed 004 §3.4's dot
//! product, turned around so the weight is reused across the block).

use super::basis::ColourBasis;
use crate::layout::SignalKind;

/// One element covering a block: emitter `base − back` (where `base` is the
/// block's emitter step), view `view`, table values from `at`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Term {
    back: u32,
    view: u32,
    at: u32,
}

/// A tabulated basis and its term lists.
#[derive(Clone, Debug)]
pub struct Plan {
    basis: ColourBasis,
    block: usize,
    /// Blocks per emitter step.
    period: usize,
    table_re: Vec<f32>,
    table_im: Vec<f32>,
    /// `terms[zone][phase]`.
    terms: Vec<Vec<Vec<Term>>>,
    norm: f32,
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

impl Plan {
    /// Tabulate `basis` (values computed in f64, stored as f32).
    pub fn new(basis: ColourBasis) -> Self {
        // The block: the largest power of two up to 64 that divides the step,
        // the hololine and every element's start and length.
        let mut g = gcd(basis.step, basis.samples);
        let mut offsets = Vec::with_capacity(basis.views);
        let (mut table_re, mut table_im) = (Vec::new(), Vec::new());
        for v in 0..basis.views {
            let s = basis.segment(0, v);
            g = gcd(gcd(g, s.start), s.len);
            offsets.push(table_re.len());
            for n in s.start..s.start + s.len {
                let x = basis.value(0, v, n);
                table_re.push(x.re as f32);
                if basis.signal == SignalKind::Iq {
                    table_im.push(x.im as f32);
                }
            }
        }
        let block = gcd(g, 64);
        let period = basis.step / block;
        let mut terms = vec![vec![Vec::new(); period]; basis.zones()];
        for (phase, slot) in (0..period).map(|ph| (ph, ph * block)) {
            for (v, &offset) in offsets.iter().enumerate() {
                let s = basis.segment(0, v);
                // Element (base − back, v) starts at (base − back)·step + start;
                // the block starts at base·step + slot.
                for back in 0.. {
                    let t0 = (back * basis.step + slot) as i64 - s.start as i64;
                    if t0 > (s.len - block) as i64 {
                        break;
                    }
                    if t0 >= 0 {
                        terms[s.zone][phase].push(Term {
                            back: back as u32,
                            view: v as u32,
                            at: (offset + t0 as usize) as u32,
                        });
                    }
                }
            }
        }
        let norm = (1.0 / basis.normalisation()) as f32;
        Plan { basis, block, period, table_re, table_im, terms, norm }
    }

    /// The basis.
    pub fn basis(&self) -> &ColourBasis {
        &self.basis
    }
    /// Samples per block of the kernel.
    pub fn block(&self) -> usize {
        self.block
    }
    /// The most elements covering one block of one zone.
    pub fn max_terms(&self) -> usize {
        self.terms.iter().flatten().map(Vec::len).max().unwrap_or(0)
    }

    /// The basis weights `sqrt(m)` of one hololine's modulation (emitter-major,
    /// as stored), or `None` when the hololine is dark.
    pub fn weights(hololine: &[f32]) -> Option<Vec<f32>> {
        if hololine.iter().all(|x| *x == 0.0) {
            return None;
        }
        Some(hololine.iter().map(|x| x.max(0.0).sqrt()).collect())
    }

    /// The (weight, table offset) of every element with a non-zero weight
    /// covering block `b` of zone `zone`.
    #[inline]
    fn gather(&self, weights: &[f32], zone: usize, b: usize, out: &mut Vec<(f32, usize)>) {
        out.clear();
        let (base, phase) = (b / self.period, b % self.period);
        for t in &self.terms[zone][phase] {
            let Some(e) = base.checked_sub(t.back as usize).filter(|e| *e < self.basis.emitters) else {
                continue;
            };
            let w = weights[e * self.basis.views + t.view as usize];
            if w != 0.0 {
                out.push((w, t.at as usize));
            }
        }
    }

    /// Zone `zone` of one hololine from its [`Plan::weights`]: the real part
    /// (I, or the real signal) into `re`, the imaginary part (Q) into `im`
    /// for I/Q signals (`im` is ignored for real signals). Both hold one
    /// hololine's samples.
    pub fn zone(&self, weights: &[f32], zone: usize, re: &mut [f32], im: &mut [f32]) {
        let iq = self.basis.signal == SignalKind::Iq;
        macro_rules! fixed {
            ($b:literal) => {
                if iq {
                    self.dispatch::<$b, 2>(weights, zone, [re, im])
                } else {
                    self.dispatch::<$b, 1>(weights, zone, [re])
                }
            };
        }
        match self.block {
            64 => fixed!(64),
            32 => fixed!(32),
            16 => fixed!(16),
            8 => fixed!(8),
            _ => self.run_dynamic(weights, zone, re, if iq { Some(im) } else { None }),
        }
    }

    /// Blocks of `B` samples and `L` lanes with fixed-size accumulators,
    /// compiled for AVX2 + FMA when the processor has them (checked at run time).
    fn dispatch<const B: usize, const L: usize>(&self, weights: &[f32], zone: usize, out: [&mut [f32]; L]) {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            // SAFETY: the features the function is compiled for are present.
            unsafe { self.run_avx2::<B, L>(weights, zone, out) };
            return;
        }
        self.run_fixed::<B, L, false>(weights, zone, out);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn run_avx2<const B: usize, const L: usize>(&self, weights: &[f32], zone: usize, out: [&mut [f32]; L]) {
        self.run_fixed::<B, L, true>(weights, zone, out);
    }

    /// `FUSED`: use fused multiply-adds (only where the hardware has them;
    /// elsewhere `mul_add` is a slow library call).
    #[inline(always)]
    fn run_fixed<const B: usize, const L: usize, const FUSED: bool>(
        &self,
        weights: &[f32],
        zone: usize,
        out: [&mut [f32]; L],
    ) {
        let tables: [&[f32]; 2] = [&self.table_re, &self.table_im];
        let mut gathered = Vec::with_capacity(self.max_terms());
        for b in 0..self.basis.samples / B {
            self.gather(weights, zone, b, &mut gathered);
            let mut acc = [[0f32; B]; L];
            for &(w, at) in &gathered {
                for (lane, acc) in acc.iter_mut().enumerate() {
                    let t: &[f32; B] = tables[lane][at..at + B].try_into().expect("segment inside the table");
                    for i in 0..B {
                        acc[i] = if FUSED { w.mul_add(t[i], acc[i]) } else { acc[i] + w * t[i] };
                    }
                }
            }
            for (lane, acc) in acc.iter().enumerate() {
                let o: &mut [f32; B] = (&mut out[lane][b * B..(b + 1) * B]).try_into().expect("block inside the row");
                for i in 0..B {
                    o[i] = acc[i] * self.norm;
                }
            }
        }
    }

    fn run_dynamic(&self, weights: &[f32], zone: usize, re: &mut [f32], mut im: Option<&mut [f32]>) {
        let bl = self.block;
        let mut gathered = Vec::new();
        for b in 0..self.basis.samples / bl {
            self.gather(weights, zone, b, &mut gathered);
            let r = &mut re[b * bl..(b + 1) * bl];
            r.fill(0.0);
            for &(w, at) in &gathered {
                r.iter_mut().zip(&self.table_re[at..at + bl]).for_each(|(a, t)| *a += w * t);
            }
            r.iter_mut().for_each(|a| *a *= self.norm);
            if let Some(im) = im.as_deref_mut() {
                let q = &mut im[b * bl..(b + 1) * bl];
                q.fill(0.0);
                for &(w, at) in &gathered {
                    q.iter_mut().zip(&self.table_im[at..at + bl]).for_each(|(a, t)| *a += w * t);
                }
                q.iter_mut().for_each(|a| *a *= self.norm);
            }
        }
    }

    /// The straightforward loop the benchmark measures the kernel against:
    /// for every output sample, gather its elements from the tables, one
    /// sample at a time, no zero skipping.
    pub fn zone_straightforward(&self, weights: &[f32], zone: usize, re: &mut [f32], im: &mut [f32]) {
        let iq = self.basis.signal == SignalKind::Iq;
        for n in 0..self.basis.samples {
            let (b, u) = (n / self.block, n % self.block);
            let (base, phase) = (b / self.period, b % self.period);
            let (mut si, mut sq) = (0f32, 0f32);
            for t in &self.terms[zone][phase] {
                let Some(e) = base.checked_sub(t.back as usize).filter(|e| *e < self.basis.emitters) else {
                    continue;
                };
                let w = weights[e * self.basis.views + t.view as usize];
                si += w * self.table_re[t.at as usize + u];
                if iq {
                    sq += w * self.table_im[t.at as usize + u];
                }
            }
            re[n] = si * self.norm;
            if iq {
                im[n] = sq * self.norm;
            }
        }
    }
}
