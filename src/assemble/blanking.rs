//! Blanking gains (spec/layouts.md §5.5): the shown samples beside each run
//! of horizontally blanked samples, multiplied as complex baseband samples
//! `I + iQ` by their zone's gains, before quantization.
//!
//! Why gains and not a plain raise: the blanked run is a hole a few samples
//! wide in every chirp that crosses it, and its missing light leaves as one
//! coherent fan wider than an eye's pupil. Raising the neighbouring samples
//! puts light back into the eyes that look through the hole, but also into
//! the eyes beside them; complex gains let the raised pieces of the many
//! chirps crossing the hole interfere so that, over the pupils, distances and
//! contents the table was chosen for, the dark column comes back most of
//! the way without bright ones beside it (`docs/seams/`, a numerical study,
//! says how far and why no table can do it completely).
//!
//! The frame assembler hands the vector kernel's blocks through
//! [`Compensated`], which passes every block that misses the compensated
//! samples straight on (from the kernel's registers, as before) and holds
//! the compensated samples of a block until both lanes have come.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::__m256;

use super::plan::{BlockSink, LaneSink};
use crate::layout::Fringe;

/// A stretch of samples that take gains: samples `first .. first + len` of
/// the hololine take the zone's gains from index `table` on, and are held
/// from `held` on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stretch {
    first: usize,
    len: usize,
    table: usize,
    held: usize,
}

/// Samples per entry of [`LineStretches::touched_before`]: the vector kernel's
/// blocks are whole vectors of 8.
const CHUNK: usize = 8;

/// The stretches of a line sent one way.
#[derive(Clone, Debug)]
struct LineStretches {
    /// The stretches that take gains, in increasing order.
    stretches: Vec<Stretch>,
    /// How many samples they hold.
    held: usize,
    /// `touched_before[c]`: how many of chunks `0 … c − 1` of [`CHUNK`]
    /// samples hold a sample that takes a gain (so that whether a block of
    /// the kernel does is two loads, not a search).
    touched_before: Vec<u32>,
}

impl LineStretches {
    /// Whether samples `first .. first + len` include one that takes a gain.
    #[inline(always)]
    fn touches(&self, first: usize, len: usize) -> bool {
        let (from, to) = (first / CHUNK, (first + len).div_ceil(CHUNK));
        self.touched_before[to] != self.touched_before[from]
    }
}

/// A layout's blanking gains, laid out over one hololine.
#[derive(Clone, Debug)]
pub(crate) struct BlankingCompensation {
    /// Per zone, the complex gains.
    gains: Vec<Vec<(f64, f64)>>,
    /// For a line sent forwards and one sent backwards.
    lines: [LineStretches; 2],
}

impl BlankingCompensation {
    /// The gains of `fringe` (None when it has none), for hololines of its
    /// frame buffer. The fringe's problems are checked already: the runs are
    /// at least two tables' reach apart.
    pub fn new(fringe: &Fringe) -> Option<Self> {
        let table = fringe.blanking_gains.as_ref()?;
        let k = table.samples_each_side;
        let samples = fringe.samples_per_hololine;
        let lay_out = |reversed: bool| {
            let mut stretches = Vec::new();
            let mut held = 0;
            for run in fringe.frame_buffer.blanked_runs(samples, reversed) {
                // Before the run (those left of sample 0 are not there), then after it.
                let before = run.start.saturating_sub(k);
                let after_end = (run.end + k).min(samples);
                for (first, end, table) in [(before, run.start, k - (run.start - before)), (run.end, after_end, k)] {
                    if end > first {
                        stretches.push(Stretch { first, len: end - first, table, held });
                        held += end - first;
                    }
                }
            }
            let chunks = samples.div_ceil(CHUNK);
            let mut touched_before = vec![0u32; chunks + 1];
            for c in 0..chunks {
                let (a, b) = (c * CHUNK, (c + 1) * CHUNK);
                let touched = stretches.iter().any(|s: &Stretch| s.first < b && a < s.first + s.len);
                touched_before[c + 1] = touched_before[c] + u32::from(touched);
            }
            LineStretches { stretches, held, touched_before }
        };
        Some(BlankingCompensation {
            gains: table.zones.iter().map(|z| z.iter().map(|&[re, im]| (re, im)).collect()).collect(),
            lines: [lay_out(false), lay_out(true)],
        })
    }

    /// Divide zone `zone`'s samples of a hololine (sent backwards if
    /// `reversed`) by their gains, in place: the basis's samples again (up to
    /// rounding), for recovering the modulation from what was sent.
    pub fn undo(&self, zone: usize, reversed: bool, re: &mut [f32], im: &mut [f32]) {
        let gains = &self.gains[zone];
        for s in &self.lines[usize::from(reversed)].stretches {
            for i in 0..s.len {
                let (n, g) = (s.first + i, gains[s.table + i]);
                let (x, y) = (f64::from(re[n]), f64::from(im[n]));
                let d = g.0 * g.0 + g.1 * g.1;
                (re[n], im[n]) = (((g.0 * x + g.1 * y) / d) as f32, ((g.0 * y - g.1 * x) / d) as f32);
            }
        }
    }

    /// A sink that multiplies zone `zone`'s blocks by their gains on the way
    /// to `inner`.
    pub fn sink<'a, S: LaneSink>(&'a self, zone: usize, reversed: bool, inner: &'a mut S) -> Compensated<'a, S> {
        let line = &self.lines[usize::from(reversed)];
        Compensated {
            inner,
            gains: &self.gains[zone],
            line,
            held: [vec![0.0; line.held], vec![0.0; line.held]],
            have: vec![0; line.held],
            out: [Vec::new(), Vec::new()],
        }
    }
}

/// Blocks of an I/Q zone on their way to `inner`, the samples beside the
/// blanked runs multiplied by their gains: a block that misses them goes
/// straight on; one that covers some has the rest passed on at once and
/// those held until the block's other lane comes.
pub(crate) struct Compensated<'a, S> {
    inner: &'a mut S,
    gains: &'a [(f64, f64)],
    line: &'a LineStretches,
    /// Per lane, the compensated samples that have come.
    held: [Vec<f32>; 2],
    /// Per held sample: bit `lane` set when that lane has come, bit 2 when
    /// the sample has been passed on.
    have: Vec<u8>,
    /// Per lane, the compensated samples being passed on.
    out: [Vec<f32>; 2],
}

impl<S: LaneSink> Compensated<'_, S> {
    /// Pass on the held samples `first .. end` of stretch `s` whose lanes
    /// have both come, multiplied by their gains.
    fn pass_on(&mut self, s: Stretch, first: usize, end: usize) {
        let mut n = first;
        while n < end {
            let ready = |n: usize| self.have[s.held + n - s.first] == 0b011;
            if !ready(n) {
                n += 1;
                continue;
            }
            let start = n;
            while n < end && ready(n) {
                n += 1;
            }
            let [re, im] = &mut self.out;
            re.clear();
            im.clear();
            for m in start..n {
                let h = s.held + m - s.first;
                let g = self.gains[s.table + m - s.first];
                let (x, y) = (f64::from(self.held[0][h]), f64::from(self.held[1][h]));
                re.push((g.0 * x - g.1 * y) as f32);
                im.push((g.0 * y + g.1 * x) as f32);
                self.have[h] |= 0b100;
            }
            self.inner.put(0, start, &self.out[0]);
            self.inner.put(1, start, &self.out[1]);
        }
    }
}

impl<S: LaneSink> BlockSink for Compensated<'_, S> {
    #[inline(always)]
    fn put(&mut self, lane: usize, first: usize, values: &[f32]) {
        let end = first + values.len();
        if !self.line.touches(first, values.len()) {
            return self.inner.put(lane, first, values);
        }
        let mut n = first;
        for i in 0..self.line.stretches.len() {
            let s = self.line.stretches[i];
            let (a, b) = (s.first.max(first), (s.first + s.len).min(end));
            if a >= b {
                continue;
            }
            if n < a {
                self.inner.put(lane, n, &values[n - first..a - first]);
            }
            for m in a..b {
                let h = s.held + m - s.first;
                self.held[lane][h] = values[m - first];
                self.have[h] |= 1 << lane;
            }
            self.pass_on(s, a, b);
            n = b;
        }
        if n < end {
            self.inner.put(lane, n, &values[n - first..]);
        }
    }
}

impl<S: LaneSink> LaneSink for Compensated<'_, S> {
    const ANY_ORDER: bool = S::ANY_ORDER;

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn put_vectors<const V: usize>(&mut self, lane: usize, first: usize, acc: &[__m256; V], norm: f32) {
        if self.line.touches(first, 8 * V) {
            // SAFETY: the caller's promise (AVX2 present) is passed on.
            unsafe {
                let mut values = [[0f32; 8]; V];
                for (values, acc) in values.iter_mut().zip(acc) {
                    std::arch::x86_64::_mm256_storeu_ps(values.as_mut_ptr(), *acc);
                }
                let values = values.as_flattened_mut();
                values.iter_mut().for_each(|v| *v *= norm);
                self.put(lane, first, values);
            }
        } else {
            // SAFETY: as above.
            unsafe { self.inner.put_vectors(lane, first, acc, norm) }
        }
    }
}
