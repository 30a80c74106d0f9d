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
    /// `back · views − view`: the weight is `weights[base · views − key]`.
    key: i64,
}

/// The terms of one (zone, phase), with the range of their `back`: a block
/// whose every term names an existing emitter needs no checks.
#[derive(Clone, Debug, Default)]
struct Terms {
    list: Vec<Term>,
    min_back: usize,
    max_back: usize,
}

/// Where the kernel puts each block of a zone's signal: `put(lane, first
/// sample, values)`, lane 0 the real part and 1 the imaginary part (I/Q
/// only), values already normalised; every block once, in increasing order.
/// Implementations mark `put` `#[inline(always)]`: it is compiled into the
/// kernel, with the kernel's vector instructions.
pub trait BlockSink {
    /// Take one block.
    fn put(&mut self, lane: usize, first: usize, values: &[f32]);
}

/// Blocks copied into the real and imaginary rows.
impl BlockSink for [&mut [f32]; 2] {
    #[inline(always)]
    fn put(&mut self, lane: usize, first: usize, values: &[f32]) {
        self[lane][first..first + values.len()].copy_from_slice(values);
    }
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
    terms: Vec<Vec<Terms>>,
    norm: f32,
}

#[inline(always)]
fn weights_into(hololine: &[f32], out: &mut Vec<f32>) -> bool {
    if hololine.iter().fold(true, |dark, x| dark & (*x == 0.0)) {
        return false;
    }
    out.clear();
    out.extend(hololine.iter().map(|x| x.sqrt()));
    true
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn weights_into_avx2(hololine: &[f32], out: &mut Vec<f32>) -> bool {
    weights_into(hololine, out)
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
        let mut terms = vec![vec![Terms::default(); period]; basis.zones()];
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
                        terms[s.zone][phase].list.push(Term {
                            back: back as u32,
                            view: v as u32,
                            at: (offset + t0 as usize) as u32,
                            key: (back * basis.views) as i64 - v as i64,
                        });
                    }
                }
            }
        }
        for t in terms.iter_mut().flatten() {
            t.min_back = t.list.iter().map(|t| t.back as usize).min().unwrap_or(0);
            t.max_back = t.list.iter().map(|t| t.back as usize).max().unwrap_or(0);
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
        self.terms.iter().flatten().map(|t| t.list.len()).max().unwrap_or(0)
    }

    /// The basis weights `sqrt(m)` of one hololine's modulation (emitter-major,
    /// as stored, already checked finite and non-negative), or `None` when the
    /// hololine is dark.
    pub fn weights(hololine: &[f32]) -> Option<Vec<f32>> {
        let mut out = Vec::new();
        Self::weights_into(hololine, &mut out).then_some(out)
    }

    /// [`Plan::weights`] into a buffer kept between hololines (a hololine's
    /// weights are large enough that a fresh allocation each time costs page
    /// faults); `false` when the hololine is dark.
    pub fn weights_into(hololine: &[f32], out: &mut Vec<f32>) -> bool {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the feature the function is compiled for is present.
            return unsafe { weights_into_avx2(hololine, out) };
        }
        weights_into(hololine, out)
    }

    /// Zone `zone` of one hololine from its [`Plan::weights`]: the real part
    /// (I, or the real signal) into `re`, the imaginary part (Q) into `im`
    /// for I/Q signals (`im` is ignored for real signals). Both hold one
    /// hololine's samples.
    pub fn zone(&self, weights: &[f32], zone: usize, re: &mut [f32], im: &mut [f32]) {
        self.zone_blocks(weights, zone, &mut [re, im]);
    }

    /// Zone `zone` of one hololine, handed to `sink` block by block (see
    /// [`BlockSink`]).
    pub fn zone_blocks(&self, weights: &[f32], zone: usize, store: &mut impl BlockSink) {
        let iq = self.basis.signal == SignalKind::Iq;
        macro_rules! fixed {
            ($b:literal) => {
                if iq {
                    self.dispatch::<$b, 2, _>(weights, zone, store)
                } else {
                    self.dispatch::<$b, 1, _>(weights, zone, store)
                }
            };
        }
        match self.block {
            64 => fixed!(64),
            32 => fixed!(32),
            16 => fixed!(16),
            8 => fixed!(8),
            _ => self.run_dynamic(weights, zone, store),
        }
    }

    /// Blocks of `B` samples and `L` lanes with fixed-size accumulators,
    /// compiled for AVX2 + FMA when the processor has them (checked at run time).
    fn dispatch<const B: usize, const L: usize, F: BlockSink>(&self, weights: &[f32], zone: usize, store: &mut F) {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            // SAFETY: the features the function is compiled for are present.
            unsafe { self.run_avx2::<B, L, F>(weights, zone, store) };
            return;
        }
        self.run_fixed::<B, L, false, F>(weights, zone, store);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn run_avx2<const B: usize, const L: usize, F: BlockSink>(
        &self,
        weights: &[f32],
        zone: usize,
        store: &mut F,
    ) {
        self.run_fixed::<B, L, true, F>(weights, zone, store);
    }

    /// The kernel. `FUSED`: use fused multiply-adds (only where the hardware
    /// has them; elsewhere `mul_add` is a slow library call).
    #[inline(always)]
    fn run_fixed<const B: usize, const L: usize, const FUSED: bool, F: BlockSink>(
        &self,
        weights: &[f32],
        zone: usize,
        store: &mut F,
    ) {
        let tables: [&[f32]; 2] = [&self.table_re, &self.table_im];
        let views = self.basis.views;
        for b in 0..self.basis.samples / B {
            let (base, phase) = (b / self.period, b % self.period);
            let terms = &self.terms[zone][phase];
            let mut acc = [[0f32; B]; L];
            // A macro, not a closure: the accumulator must stay in registers.
            macro_rules! add {
                ($w:expr, $at:expr) => {{
                    let (w, at) = ($w, $at);
                    for lane in 0..L {
                        let t: &[f32; B] = tables[lane][at..at + B].try_into().expect("segment inside the table");
                        for i in 0..B {
                            acc[lane][i] = if FUSED { w.mul_add(t[i], acc[lane][i]) } else { acc[lane][i] + w * t[i] };
                        }
                    }
                }};
            }
            if terms.max_back <= base && base - terms.min_back < self.basis.emitters {
                // Every term names an emitter of the hololine: no checks.
                let row = (base * views) as i64;
                for t in &terms.list {
                    let w = weights[(row - t.key) as usize];
                    if w != 0.0 {
                        add!(w, t.at as usize);
                    }
                }
            } else {
                for t in &terms.list {
                    if let Some(e) = base.checked_sub(t.back as usize).filter(|e| *e < self.basis.emitters) {
                        let w = weights[e * views + t.view as usize];
                        if w != 0.0 {
                            add!(w, t.at as usize);
                        }
                    }
                }
            }
            for (lane, acc) in acc.iter().enumerate() {
                // A copy, so that the accumulator itself never escapes.
                let mut values = [0f32; B];
                values.iter_mut().zip(acc).for_each(|(v, a)| *v = a * self.norm);
                store.put(lane, b * B, &values);
            }
        }
    }

    fn run_dynamic(&self, weights: &[f32], zone: usize, store: &mut impl BlockSink) {
        let bl = self.block;
        let lanes = self.basis.lanes();
        let tables: [&[f32]; 2] = [&self.table_re, &self.table_im];
        let mut acc = vec![0f32; bl];
        for b in 0..self.basis.samples / bl {
            let (base, phase) = (b / self.period, b % self.period);
            for (lane, table) in tables.iter().enumerate().take(lanes) {
                acc.fill(0.0);
                for t in &self.terms[zone][phase].list {
                    if let Some(e) = base.checked_sub(t.back as usize).filter(|e| *e < self.basis.emitters) {
                        let w = weights[e * self.basis.views + t.view as usize];
                        let at = t.at as usize;
                        acc.iter_mut().zip(&table[at..at + bl]).for_each(|(a, t)| *a += w * t);
                    }
                }
                acc.iter_mut().for_each(|a| *a *= self.norm);
                store.put(lane, b * bl, &acc);
            }
        }
    }

    /// The adjoint of [`Plan::zone`]: for every element of zone `zone`, the
    /// inner product of its (normalised) basis with the signals, added to
    /// `out[e · views + v]` (`im` is ignored for real signals). With the
    /// forward map it solves for the weights that made a signal.
    pub fn zone_adjoint(&self, zone: usize, re: &[f32], im: &[f32], out: &mut [f64]) {
        let iq = self.basis.signal == SignalKind::Iq;
        let bl = self.block;
        for b in 0..self.basis.samples / bl {
            let (base, phase) = (b / self.period, b % self.period);
            let (r, q) = (&re[b * bl..(b + 1) * bl], if iq { &im[b * bl..(b + 1) * bl] } else { &[][..] });
            for t in &self.terms[zone][phase].list {
                let Some(e) = base.checked_sub(t.back as usize).filter(|e| *e < self.basis.emitters) else {
                    continue;
                };
                let at = t.at as usize;
                let mut dot: f64 = r.iter().zip(&self.table_re[at..at + bl]).map(|(s, t)| f64::from(s * t)).sum();
                if iq {
                    dot += q.iter().zip(&self.table_im[at..at + bl]).map(|(s, t)| f64::from(s * t)).sum::<f64>();
                }
                out[e * self.basis.views + t.view as usize] += dot * f64::from(self.norm);
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
            for t in &self.terms[zone][phase].list {
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
