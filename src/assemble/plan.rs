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
//! a register-sized accumulator, which vectorises (Smithwick et al. 2009 §3.4's dot
//! product, turned around so the weight is reused across the block).
//!
//! Blocks of one phase in consecutive emitter steps have the same terms and
//! the same table values, only their weights differ. The vector kernel
//! (x86-64 with AVX2 and FMA, chosen at run time) sums a few of them
//! together, so that each table value loaded serves several blocks; the
//! frame assembler pads the weights with zeros beyond the hololine's ends,
//! so that no block needs checks.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::{
    __m256, _mm256_broadcast_ss, _mm256_fmadd_ps, _mm256_loadu_ps, _mm256_mul_ps, _mm256_set1_ps, _mm256_setzero_ps,
    _mm256_storeu_ps,
};

use holo_fft::Complex64;

use super::basis::ColourBasis;
use crate::layout::SignalKind;
use crate::simd::Simd;

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

/// A [`Term`] as the vector kernel reads it: the weight is
/// `weights[base · views + weight]`, the values are `lanes[table ..]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Tap {
    weight: i32,
    table: u32,
}

/// The terms of one (zone, phase), with the range of their `back`: a block
/// whose every term names an existing emitter needs no checks.
#[derive(Clone, Debug, Default)]
struct Terms {
    list: Vec<Term>,
    /// `list` as the vector kernel reads it, in the same order.
    taps: Vec<Tap>,
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

/// The crate's own sinks, which may take blocks in any order and, from the
/// vector kernel, straight from its registers.
pub(crate) trait LaneSink: BlockSink {
    /// Whether blocks may come in any order (the vector kernel then works on
    /// several emitter steps at once).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    const ANY_ORDER: bool;

    /// Lane `lane` of the block at sample `first`, from the vector kernel's
    /// accumulators, not yet multiplied by `norm`. By default the normalised
    /// values go to [`BlockSink::put`].
    ///
    /// # Safety
    /// Only for processors with AVX2 (the vector kernel's callers check).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn put_vectors<const V: usize>(&mut self, lane: usize, first: usize, acc: &[__m256; V], norm: f32) {
        // SAFETY: only the AVX2 + FMA kernel calls this; each store writes 8 floats
        // into an array of 8.
        unsafe {
            let mut values = [[0f32; 8]; V];
            for (values, acc) in values.iter_mut().zip(acc) {
                _mm256_storeu_ps(values.as_mut_ptr(), _mm256_mul_ps(*acc, _mm256_set1_ps(norm)));
            }
            self.put(lane, first, values.as_flattened());
        }
    }
}

impl LaneSink for [&mut [f32]; 2] {
    const ANY_ORDER: bool = true;
}

/// Any [`BlockSink`], as a [`LaneSink`] that takes blocks in any order if
/// `ANY` (otherwise in increasing order, as [`BlockSink`] promises).
pub(crate) struct Blocks<'a, S, const ANY: bool>(pub &'a mut S);

impl<S: BlockSink, const ANY: bool> BlockSink for Blocks<'_, S, ANY> {
    #[inline(always)]
    fn put(&mut self, lane: usize, first: usize, values: &[f32]) {
        self.0.put(lane, first, values);
    }
}

impl<S: BlockSink, const ANY: bool> LaneSink for Blocks<'_, S, ANY> {
    const ANY_ORDER: bool = ANY;
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
    /// The tables block by block, the lanes of each block side by side (the
    /// block at `at` of the tables is at `at · L` for `L` lanes): one term's
    /// values are one contiguous run, for the vector kernel.
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    lanes: Vec<f32>,
    /// `terms[zone][phase]`.
    terms: Vec<Vec<Terms>>,
    norm: f32,
    /// Emitters of zero weights before emitter 0 and after the last that
    /// the blocks reach (see [`Plan::padded_weights_into`]).
    padding: (usize, usize),
    /// Which kernels the processor may run (the portable one when forced).
    simd: Simd,
    /// `(cos ψ_e, sin ψ_e)` of every emitter's phase (spec/layouts.md §4.6);
    /// empty when every phase is 0.
    phases: Vec<(f32, f32)>,
    /// For real signals with emitter phases: the same plan tabulating the
    /// imaginary parts of the basis (`Re(−i B) = Im B`), which a phase mixes
    /// into the real signal.
    quadrature: Option<Box<Plan>>,
}

/// The most emitter steps the vector kernel takes at a time (its `G`).
const GROUP: usize = 8;

/// What a hololine's samples were found to be while weighing them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Scan {
    /// Some sample is not zero.
    pub lit: bool,
    /// Every sample is finite and not negative (as
    /// [`crate::modulation::Modulation::first_bad_sample`] checks).
    pub valid: bool,
}

/// A hololine's weights with zero weights before and after them, as the
/// crate's kernels read them (see [`Plan::padded_weights_into`]); kept
/// between hololines, so that the zeros are written once.
#[derive(Clone, Debug, Default)]
pub(crate) struct PaddedWeights {
    values: Vec<f32>,
    /// Emitters of zeros before emitter 0, emitters of the hololine,
    /// emitters of zeros after it, and views per emitter.
    shape: [usize; 4],
}

/// `out[i] = sqrt(hololine[i])`, and what the samples are: one pass,
/// branch-free (it vectorises).
#[inline(always)]
fn sqrt_into(hololine: &[f32], out: &mut [f32]) -> Scan {
    let (mut lit, mut valid) = (false, true);
    for (out, x) in out.iter_mut().zip(hololine) {
        lit |= *x != 0.0;
        valid &= (*x >= 0.0) & (*x <= f32::MAX);
        *out = x.sqrt();
    }
    Scan { lit, valid }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sqrt_into_avx2(hololine: &[f32], out: &mut [f32]) -> Scan {
    sqrt_into(hololine, out)
}

/// [`sqrt_into`], vectorised for AVX2 when the processor has it (the
/// square root is correctly rounded either way: the results are the same).
fn sqrt_into_dispatch(hololine: &[f32], out: &mut [f32]) -> Scan {
    #[cfg(target_arch = "x86_64")]
    if Simd::Detect.avx2() {
        // SAFETY: the feature the function is compiled for is present.
        return unsafe { sqrt_into_avx2(hololine, out) };
    }
    sqrt_into(hololine, out)
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
        let mut plan = Plan::tabulate(basis, false);
        if !plan.basis.emitter_phases_rad.is_empty() {
            plan.phases = (0..plan.basis.emitters)
                .map(|e| {
                    let (sin, cos) = plan.basis.emitter_phase_rad(e).sin_cos();
                    (cos as f32, sin as f32)
                })
                .collect();
            if plan.basis.signal == SignalKind::Real {
                plan.quadrature = Some(Box::new(Plan::tabulate(plan.basis.clone(), true)));
            }
        }
        plan
    }

    /// The plan of `basis` without emitter phases, its values turned by
    /// `−π/2` when `quarter` (so a real signal's table holds `Im B`).
    fn tabulate(basis: ColourBasis, quarter: bool) -> Self {
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
                let x = basis.unphased_value(0, v, n);
                let x = if quarter { Complex64::new(x.im, -x.re) } else { x };
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
        let lanes: Vec<f32> = table_re
            .chunks_exact(block)
            .enumerate()
            .flat_map(|(k, re)| re.iter().chain(table_im.get(k * block..(k + 1) * block).unwrap_or(&[])))
            .copied()
            .collect();
        for t in terms.iter_mut().flatten() {
            t.min_back = t.list.iter().map(|t| t.back as usize).min().unwrap_or(0);
            t.max_back = t.list.iter().map(|t| t.back as usize).max().unwrap_or(0);
            t.taps = t
                .list
                .iter()
                .map(|t| Tap {
                    weight: i32::try_from(-t.key).expect("weight offsets fit in i32"),
                    table: u32::try_from(t.at as usize * basis.lanes()).expect("table offsets fit in u32"),
                })
                .collect();
        }
        // The vector kernel reads each tap's values unchecked.
        let run = basis.lanes() * block;
        assert!(terms.iter().flatten().flat_map(|t| &t.taps).all(|t| t.table as usize + run <= lanes.len()));
        let norm = (1.0 / basis.normalisation()) as f32;
        // Blocks reach `back` emitters before their own, and the last group
        // of emitter steps runs up to GROUP − 1 steps past the last step.
        let lists = || terms.iter().flatten().filter(|t| !t.list.is_empty());
        let before = lists().map(|t| t.max_back).max().unwrap_or(0);
        let min_back = lists().map(|t| t.min_back).min().unwrap_or(0);
        let steps = (basis.samples / block).div_ceil(period);
        let padding = (before, (steps + GROUP - 1).saturating_sub(min_back + basis.emitters));
        Plan {
            basis,
            block,
            period,
            table_re,
            table_im,
            lanes,
            terms,
            norm,
            padding,
            simd: Simd::Detect,
            phases: Vec::new(),
            quadrature: None,
        }
    }

    /// The same plan, its kernel chosen by `simd` ([`Simd::Portable`]: the
    /// portable kernel even where AVX2 is present, for checking it).
    pub fn with_simd(mut self, simd: Simd) -> Self {
        self.simd = simd;
        self.quadrature = self.quadrature.map(|q| Box::new(q.with_simd(simd)));
        self
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
    #[cfg(test)]
    pub(crate) fn max_terms(&self) -> usize {
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
        out.resize(hololine.len(), 0.0);
        sqrt_into_dispatch(hololine, out).lit
    }

    /// [`Plan::weights_into`] with zero weights for the emitters beyond the
    /// hololine's ends that its blocks reach: no block then needs checks.
    /// The samples need not have been checked: the scan says whether they
    /// were fit to weigh.
    pub(crate) fn padded_weights_into(&self, hololine: &[f32], out: &mut PaddedWeights) -> Scan {
        let (views, emitters) = (self.basis.views, self.basis.emitters);
        assert_eq!(hololine.len(), emitters * views, "one sample per element");
        let shape = [self.padding.0, emitters, self.padding.1, views];
        if out.shape != shape {
            // Only the hololine's part is written below: the rest stays zero.
            out.values.clear();
            out.values.resize((shape[0] + shape[1] + shape[2]) * views, 0.0);
            out.shape = shape;
        }
        sqrt_into_dispatch(hololine, &mut out.values[shape[0] * views..(shape[0] + emitters) * views])
    }

    /// [`Plan::zone_blocks`] from [`Plan::padded_weights_into`] into one of
    /// the crate's sinks.
    pub(crate) fn zone_padded<S: LaneSink>(&self, weights: &PaddedWeights, zone: usize, sink: &mut S) {
        let [before, emitters, after, views] = weights.shape;
        assert_eq!(
            (before, emitters, after, views),
            (self.padding.0, self.basis.emitters, self.padding.1, self.basis.views)
        );
        self.zone_into(&weights.values, before, zone, sink);
    }

    /// Samples `first .. first + re.len()` of zone `zone`'s I/Q signal, as
    /// the kernels make them (emitter phases included) but outside them, from
    /// [`Plan::padded_weights_into`]: a few samples made again after the
    /// kernel has run (the blanking gains, spec/layouts.md §5.5), so that the
    /// kernel itself stays as it is.
    pub(crate) fn iq_samples(
        &self,
        weights: &PaddedWeights,
        zone: usize,
        first: usize,
        re: &mut [f32],
        im: &mut [f32],
    ) {
        assert_eq!(self.basis.signal, SignalKind::Iq, "I/Q signals only");
        assert_eq!(re.len(), im.len());
        let (before, views, bl) = (weights.shape[0], self.basis.views, self.block);
        re.fill(0.0);
        im.fill(0.0);
        let end = first + re.len();
        let mut n = first;
        // Block by block (the elements are the same across a block), each
        // element added into the whole run (measured faster than summing
        // eight samples at a time in registers: fewer bounds checks).
        while n < end {
            let b = n / bl;
            let (from, to) = (n, end.min((b + 1) * bl));
            let (base, phase) = (b / self.period, b % self.period);
            let (r, i) = (&mut re[from - first..to - first], &mut im[from - first..to - first]);
            for t in &self.terms[zone][phase].list {
                let Some(e) = base.checked_sub(t.back as usize).filter(|e| *e < self.basis.emitters) else {
                    continue;
                };
                let w = weights.values[(before + e) * views + t.view as usize];
                let at = t.at as usize + from - b * bl;
                let (tr, ti) = (&self.table_re[at..at + to - from], &self.table_im[at..at + to - from]);
                match self.phases.get(e) {
                    None => {
                        r.iter_mut().zip(tr).for_each(|(r, t)| *r += w * t);
                        i.iter_mut().zip(ti).for_each(|(i, t)| *i += w * t);
                    }
                    // With phases the weight is w e^{iψ}: s = Σ w (cos ψ + i sin ψ) B.
                    Some(&(cos, sin)) => {
                        let (c, s) = (w * cos, w * sin);
                        for (((r, i), tr), ti) in r.iter_mut().zip(i.iter_mut()).zip(tr).zip(ti) {
                            *r += c * tr - s * ti;
                            *i += c * ti + s * tr;
                        }
                    }
                }
            }
            n = to;
        }
        re.iter_mut().chain(im.iter_mut()).for_each(|x| *x *= self.norm);
    }

    /// Zone `zone` of one hololine from its [`Plan::weights`]: the real part
    /// (I, or the real signal) into `re`, the imaginary part (Q) into `im`
    /// for I/Q signals (`im` is ignored for real signals). Both hold one
    /// hololine's samples.
    pub fn zone(&self, weights: &[f32], zone: usize, re: &mut [f32], im: &mut [f32]) {
        self.zone_into(weights, 0, zone, &mut [re, im]);
    }

    /// Zone `zone` of one hololine, handed to `sink` block by block (see
    /// [`BlockSink`]).
    pub fn zone_blocks(&self, weights: &[f32], zone: usize, store: &mut impl BlockSink) {
        self.zone_into(weights, 0, zone, &mut Blocks::<_, false>(store));
    }

    /// [`Plan::zone_blocks`] into one of the crate's sinks, from weights
    /// that start `before` emitters of zeros before emitter 0: the vector
    /// kernel when the processor has AVX2 and FMA (checked at run time),
    /// otherwise the portable one.
    fn zone_into<S: LaneSink>(&self, weights: &[f32], before: usize, zone: usize, sink: &mut S) {
        // The kernels read weights unchecked where every term names a weight of the buffer.
        assert!(weights.len() >= (before + self.basis.emitters) * self.basis.views, "one weight per element");
        if self.phases.is_empty() {
            return self.zone_unphased(weights, before, zone, sink);
        }
        // With emitter phases the weights are complex, `w e^{iψ}`: the
        // kernel runs once with `w cos ψ` and once with `w sin ψ`, and
        // `s = Σ w cos ψ B + i Σ w sin ψ B` is put together from the two,
        // then handed on block by block, in order.
        let samples = self.basis.samples;
        let views = self.basis.views;
        let (mut cos_w, mut sin_w) = (vec![0f32; weights.len()], vec![0f32; weights.len()]);
        for (e, &(cos, sin)) in self.phases.iter().enumerate() {
            let at = (before + e) * views;
            for v in at..at + views {
                cos_w[v] = weights[v] * cos;
                sin_w[v] = weights[v] * sin;
            }
        }
        let pass = |plan: &Plan, w: &[f32]| {
            let (mut re, mut im) = (vec![0f32; samples], vec![0f32; samples]);
            plan.zone_unphased(w, before, zone, &mut [&mut re[..], &mut im[..]]);
            (re, im)
        };
        let (mut re, mut im) = pass(self, &cos_w);
        match &self.quadrature {
            // Real: Re(e^{iψ} B) = cos ψ Re B − sin ψ Im B.
            Some(q) => {
                let (im_b, _) = pass(q, &sin_w);
                re.iter_mut().zip(&im_b).for_each(|(r, x)| *r -= x);
            }
            // I/Q: the real part takes −(sin-pass Q), the imaginary part +(sin-pass I).
            None => {
                let (re_s, im_s) = pass(self, &sin_w);
                re.iter_mut().zip(&im_s).for_each(|(r, x)| *r -= x);
                im.iter_mut().zip(&re_s).for_each(|(i, x)| *i += x);
            }
        }
        let lanes = self.basis.lanes();
        let bl = self.block;
        for b in 0..samples / bl {
            sink.put(0, b * bl, &re[b * bl..(b + 1) * bl]);
            if lanes == 2 {
                sink.put(1, b * bl, &im[b * bl..(b + 1) * bl]);
            }
        }
    }

    /// [`Plan::zone_into`] with every emitter at phase 0: the kernels.
    fn zone_unphased<S: LaneSink>(&self, weights: &[f32], before: usize, zone: usize, sink: &mut S) {
        let iq = self.basis.signal == SignalKind::Iq;
        #[cfg(target_arch = "x86_64")]
        if self.simd.avx2_fma() {
            // V vectors of 8 samples per lane and block; P vectors of G
            // blocks at a time, for 10 to 12 accumulators and no spills
            // (measured best). Blocks come in increasing order only with
            // whole lanes of one block at a time.
            macro_rules! vector {
                ($v:literal, $l:literal, $p:literal, $g:literal) => {
                    // SAFETY: the features the kernel is compiled for are present.
                    unsafe {
                        if S::ANY_ORDER {
                            self.run_avx2::<$v, $l, $p, $g, S>(weights, before, zone, sink)
                        } else {
                            self.run_avx2::<$v, $l, $v, 1, S>(weights, before, zone, sink)
                        }
                    }
                };
            }
            match (self.block, iq) {
                (64, true) => return vector!(8, 2, 4, 3),
                (64, false) => return vector!(8, 1, 4, 3),
                (32, true) => return vector!(4, 2, 4, 3),
                (32, false) => return vector!(4, 1, 4, 3),
                (16, true) => return vector!(2, 2, 2, 5),
                (16, false) => return vector!(2, 1, 2, 5),
                (8, true) => return vector!(1, 2, 1, 6),
                (8, false) => return vector!(1, 1, 1, 6),
                _ => {}
            }
        }
        let weights = &weights[before * self.basis.views..];
        macro_rules! fixed {
            ($b:literal) => {
                if iq {
                    self.run_fixed::<$b, 2, _>(weights, zone, sink)
                } else {
                    self.run_fixed::<$b, 1, _>(weights, zone, sink)
                }
            };
        }
        match self.block {
            64 => fixed!(64),
            32 => fixed!(32),
            16 => fixed!(16),
            8 => fixed!(8),
            _ => self.run_dynamic(weights, zone, sink),
        }
    }

    /// The vector kernel, for blocks of `V` vectors of 8 samples per lane and
    /// `L` lanes. Blocks of one phase in consecutive emitter steps have the
    /// same terms and table values, only the weights differ: the kernel sums
    /// `P` vectors of `G` such blocks at a time, so that each table load
    /// serves `G` multiply-adds (one block at a time, the loads limited it)
    /// and `P · G` accumulators hide the latency of the multiply-adds.
    /// `weights` start `before` emitters of zeros before emitter 0. Callers
    /// check the processor's features and that the buffer reaches the last
    /// emitter.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn run_avx2<const V: usize, const L: usize, const P: usize, const G: usize, S: LaneSink>(
        &self,
        weights: &[f32],
        before: usize,
        zone: usize,
        sink: &mut S,
    ) {
        // SAFETY: AVX2 and FMA are present (the caller checked them through
        // `Simd::avx2_fma`). `sum_taps` runs only where `inside` holds, so every
        // weight its taps name lies in `weights`; `sum_checked` checks each weight.
        unsafe {
            const { assert!(V % P == 0 && G <= GROUP) };
            let (views, period, block) = (self.basis.views, self.period, self.block);
            let (blocks, stored) = (self.basis.samples / block, weights.len() / views);
            for base in (0..blocks.div_ceil(period)).step_by(G) {
                let last = base + G - 1;
                for (phase, terms) in self.terms[zone].iter().enumerate() {
                    // Whether every weight the terms of these blocks name is in the buffer.
                    let inside = terms.max_back <= base + before && last + before < stored + terms.min_back;
                    for part in (0..L * V).step_by(P) {
                        let (lane, first) = (part / V, (part % V) * 8);
                        if inside {
                            // Past the buffer's end when all terms reach back:
                            // the taps' offsets bring it back inside, as checked.
                            let row = weights.as_ptr().wrapping_add((base + before) * views);
                            for (k, acc) in self.sum_taps::<P, G>(&terms.taps, row, part * 8).iter().enumerate() {
                                let b = (base + k) * period + phase;
                                if b < blocks {
                                    sink.put_vectors(lane, b * block + first, acc, self.norm);
                                }
                            }
                        } else {
                            for b in (base..=last).map(|base| base * period + phase).filter(|b| *b < blocks) {
                                let acc = self.sum_checked::<P, L>(&terms.list, weights, before, b / period, part * 8);
                                sink.put_vectors(lane, b * block + first, &acc, self.norm);
                            }
                        }
                    }
                }
            }
        }
    }

    /// `P` vectors from `offset` in each term's values, summed for `G` blocks
    /// of one phase in consecutive emitter steps, the first step's weights
    /// from `row` (the weights of emitter `base` if it were in the buffer).
    /// Zero weights are not skipped: with `G` blocks at a time a test costs
    /// more than it saves. Callers guarantee that every weight the taps name
    /// is in the buffer and that the processor has AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn sum_taps<const P: usize, const G: usize>(
        &self,
        taps: &[Tap],
        row: *const f32,
        offset: usize,
    ) -> [[__m256; P]; G] {
        // SAFETY: the caller guarantees AVX2 and FMA and that every weight the taps
        // name is in the buffer; tap table offsets were checked against `lanes` in
        // `Plan::new`, so each 8-float load at `tap.table + offset + 8p` is inside.
        unsafe {
            let views = self.basis.views;
            let mut acc = [[_mm256_setzero_ps(); G]; P];
            for tap in taps {
                let w = row.wrapping_offset(tap.weight as isize);
                let w: [__m256; G] = std::array::from_fn(|k| _mm256_broadcast_ss(&*w.add(k * views)));
                // Inside the table: checked in `Plan::new`.
                let values = self.lanes.as_ptr().add(tap.table as usize + offset);
                // One vector of values at a time, for all G blocks: few registers live.
                for (p, acc) in acc.iter_mut().enumerate() {
                    let x = _mm256_loadu_ps(values.add(p * 8));
                    for (acc, w) in acc.iter_mut().zip(&w) {
                        *acc = _mm256_fmadd_ps(*w, x, *acc);
                    }
                }
            }
            std::array::from_fn(|k| std::array::from_fn(|p| acc[p][k]))
        }
    }

    /// One block whose terms may name emitters beyond the hololine's ends:
    /// the same sums as [`Plan::sum_taps`], with every weight checked.
    /// Callers guarantee that the processor has AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn sum_checked<const P: usize, const L: usize>(
        &self,
        terms: &[Term],
        weights: &[f32],
        before: usize,
        base: usize,
        offset: usize,
    ) -> [__m256; P] {
        // SAFETY: the caller guarantees AVX2 and FMA; each load reads 8 floats from
        // `values[8p..]`, a slice of `8P` floats.
        unsafe {
            let mut acc = [_mm256_setzero_ps(); P];
            for t in terms {
                let Some(e) = base.checked_sub(t.back as usize).filter(|e| *e < self.basis.emitters) else {
                    continue;
                };
                let w = weights[(before + e) * self.basis.views + t.view as usize];
                let values = &self.lanes[t.at as usize * L + offset..][..P * 8];
                for (p, acc) in acc.iter_mut().enumerate() {
                    *acc = _mm256_fmadd_ps(_mm256_set1_ps(w), _mm256_loadu_ps(values[p * 8..].as_ptr()), *acc);
                }
            }
            acc
        }
    }

    /// The portable kernel: blocks of `B` samples and `L` lanes with
    /// fixed-size accumulators (which vectorise).
    fn run_fixed<const B: usize, const L: usize, F: BlockSink>(&self, weights: &[f32], zone: usize, store: &mut F) {
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
                            acc[lane][i] += w * t[i];
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
        if self.phases.is_empty() {
            return self.zone_adjoint_unphased(zone, re, im, out);
        }
        // The forward map is `w ↦ Σ w (cos ψ B + i sin ψ B)`, so its adjoint
        // is `cos ψ ⟨B, s⟩ + sin ψ ⟨i B, s⟩`: for I/Q, `⟨i B, (I, Q)⟩ =
        // ⟨B, (Q, −I)⟩`; for real signals `⟨Re(i B), s⟩ = −⟨Im B, s⟩`.
        let views = self.basis.views;
        let mut with_cos = vec![0f64; out.len()];
        let mut with_sin = vec![0f64; out.len()];
        self.zone_adjoint_unphased(zone, re, im, &mut with_cos);
        match &self.quadrature {
            Some(q) => {
                q.zone_adjoint_unphased(zone, re, im, &mut with_sin);
                with_sin.iter_mut().for_each(|x| *x = -*x);
            }
            None => {
                let minus_re: Vec<f32> = re.iter().map(|x| -x).collect();
                self.zone_adjoint_unphased(zone, im, &minus_re, &mut with_sin);
            }
        }
        for (e, &(cos, sin)) in self.phases.iter().enumerate() {
            for k in e * views..(e + 1) * views {
                out[k] += f64::from(cos) * with_cos[k] + f64::from(sin) * with_sin[k];
            }
        }
    }

    fn zone_adjoint_unphased(&self, zone: usize, re: &[f32], im: &[f32], out: &mut [f64]) {
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
        assert!(
            self.phases.is_empty(),
            "the straightforward loop is the kernel's reference with every emitter phase 0"
        );
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
