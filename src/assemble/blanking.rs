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
//! The kernel runs as without gains; afterwards [`BlankingCompensation::apply`]
//! makes the few samples that take gains again (from the plan's terms,
//! outside the kernel: about 3 % of a Mark III zone), multiplies them and encodes
//! them over what the kernel wrote. The kernel's hot loop stays as it is: a
//! sink that picked the gained samples out of its blocks cost far more than
//! the samples themselves.

use super::pack::{Encoder, FringeSample};
use super::plan::{BlockSink, PaddedWeights, Plan};
use crate::layout::Fringe;

/// A stretch of samples that take gains: samples `first .. first + len` of
/// the hololine take the zone's gains from index `table` on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stretch {
    first: usize,
    len: usize,
    table: usize,
}

/// A layout's blanking gains, laid out over one hololine.
#[derive(Clone, Debug)]
pub(crate) struct BlankingCompensation {
    /// Per zone, the complex gains.
    gains: Vec<Vec<(f64, f64)>>,
    /// The stretches that take gains, in increasing order, for a line sent
    /// forwards and one sent backwards.
    lines: [Vec<Stretch>; 2],
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
            for run in fringe.frame_buffer.blanked_runs(samples, reversed) {
                // Before the run (those left of sample 0 are not there), then after it.
                let before = run.start.saturating_sub(k);
                let after_end = (run.end + k).min(samples);
                for (first, end, table) in [(before, run.start, k - (run.start - before)), (run.end, after_end, k)] {
                    if end > first {
                        stretches.push(Stretch { first, len: end - first, table });
                    }
                }
            }
            stretches
        };
        Some(BlankingCompensation {
            gains: table.zones.iter().map(|z| z.iter().map(|&[re, im]| (re, im)).collect()).collect(),
            lines: [lay_out(false), lay_out(true)],
        })
    }

    /// Send zone `zone`'s samples beside the blanked runs with their gains:
    /// made again from `weights`, multiplied, and encoded by `sink` over what
    /// the kernel wrote there. `sink`'s clipped count, which the kernel's
    /// pass made for these samples without their gains, is corrected to
    /// count them as sent.
    pub fn apply<T: FringeSample>(&self, plan: &Plan, weights: &PaddedWeights, zone: usize, sink: &mut Encoder<'_, T>) {
        let gains = &self.gains[zone];
        let (mut re, mut im) = (Vec::new(), Vec::new());
        for s in &self.lines[usize::from(sink.reversed)] {
            re.resize(s.len, 0.0);
            im.resize(s.len, 0.0);
            plan.iq_samples(weights, zone, s.first, &mut re, &mut im);
            // What the kernel's pass counted clipped here (the same samples,
            // made in another order: the count may differ only for a sample
            // within rounding of the quantizer's end).
            let before: u64 = [&re, &im]
                .iter()
                .zip(sink.lane_channel)
                .filter(|(_, ch)| ch.is_some())
                .map(|(lane, _)| T::count_clipped(lane, sink.q))
                .sum();
            sink.clipped = sink.clipped.saturating_sub(before);
            for (i, (x, y)) in re.iter_mut().zip(im.iter_mut()).enumerate() {
                let g = gains[s.table + i];
                let (a, b) = (f64::from(*x), f64::from(*y));
                (*x, *y) = ((g.0 * a - g.1 * b) as f32, (g.0 * b + g.1 * a) as f32);
            }
            sink.put(0, s.first, &re);
            sink.put(1, s.first, &im);
        }
    }

    /// Divide zone `zone`'s samples of a hololine (sent backwards if
    /// `reversed`) by their gains, in place: the basis's samples again (up to
    /// rounding), for recovering the modulation from what was sent.
    pub fn undo(&self, zone: usize, reversed: bool, re: &mut [f32], im: &mut [f32]) {
        let gains = &self.gains[zone];
        for s in &self.lines[usize::from(reversed)] {
            for i in 0..s.len {
                let (n, g) = (s.first + i, gains[s.table + i]);
                let (x, y) = (f64::from(re[n]), f64::from(im[n]));
                let d = g.0 * g.0 + g.1 * g.1;
                (re[n], im[n]) = (((g.0 * x + g.1 * y) / d) as f32, ((g.0 * y - g.1 * x) / d) as f32);
            }
        }
    }
}
