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
//! The kernel runs as without gains; afterwards [`HololineGains::apply`]
//! makes the few samples that take gains again (from the plan's terms,
//! outside the kernel: about 3 % of a Mark III zone), multiplies them and encodes
//! them over what the kernel wrote. The kernel's hot loop stays as it is: a
//! sink that picked the gained samples out of its blocks cost far more than
//! the samples themselves.
//!
//! A layout may carry a second table for flat fields: beside a run whose
//! neighbouring elements are evenly lit, the interference the gains rely on
//! is known exactly, and a table chosen for it alone brings the seam back
//! further. Which table a run takes depends on the hololine's modulation,
//! so it is decided here, run by run, from the elements (of every zone)
//! whose segments lie within the flat-field table's reach.

use std::ops::Range;

use super::basis::ColourBasis;
use super::pack::{AfterKernel, Encoder, FringeSample};
use super::plan::{BlockSink, PaddedWeights, Plan};
use crate::layout::{BlankingGains, Fringe};

/// One table of gains laid out beside the runs: per zone, the complex gains
/// (`2K` of them), and `K`.
#[derive(Clone, Debug)]
struct Table {
    samples_each_side: usize,
    gains: Vec<Vec<(f64, f64)>>,
}

impl Table {
    fn new(samples_each_side: usize, zones: &[Vec<[f64; 2]>]) -> Self {
        Table { samples_each_side, gains: zones.iter().map(|z| z.iter().map(|&[re, im]| (re, im)).collect()).collect() }
    }

    /// The stretches beside `run` (of a hololine of `samples`) that take
    /// gains: `(first, len, index of the first gain)`, before the run (those
    /// left of sample 0 are not there), then after it.
    fn stretches(&self, run: &Range<usize>, samples: usize) -> [(usize, usize, usize); 2] {
        let k = self.samples_each_side;
        let before = run.start.saturating_sub(k);
        let after_end = (run.end + k).min(samples);
        [(before, run.start - before, k - (run.start - before)), (run.end, after_end - run.end, k)]
    }
}

/// The flat-field table and where it applies.
#[derive(Clone, Debug)]
struct FlatField {
    table: Table,
    max_spread: f64,
    /// Per colour, per direction a line is sent (forwards, backwards), per
    /// run: the elements (`e · views + v`, every zone's) whose segments lie
    /// within the table's reach of the run.
    neighbours: Vec<[Vec<Vec<usize>>; 2]>,
}

/// A layout's blanking gains, laid out over one hololine.
#[derive(Clone, Debug)]
pub(crate) struct BlankingCompensation {
    general: Table,
    flat: Option<FlatField>,
    /// The blanked runs of a line sent forwards and of one sent backwards,
    /// in signal order.
    runs: [Vec<Range<usize>>; 2],
    samples: usize,
}

/// Which gains the run with neighbours `elements` takes for `hololine`'s
/// modulation (spec/layouts.md §5.5): the flat-field table when the
/// elements' radiances differ by at most `max_spread` of the largest, which
/// is not zero.
fn evenly_lit(hololine: &[f32], elements: impl IntoIterator<Item = usize>, max_spread: f64) -> bool {
    let (mut lo, mut hi) = (f64::INFINITY, 0f64);
    for i in elements {
        let m = f64::from(hololine[i]).max(0.0);
        (lo, hi) = (lo.min(m), hi.max(m));
        // The spread only grows (max_spread < 1): uneven once, uneven at the end.
        if hi - lo > max_spread * hi {
            return false;
        }
    }
    hi > 0.0
}

/// The samples within `reach` of `run` (of a hololine of `samples`): where a
/// table that reaches that far takes gains.
fn neighbourhood(run: &Range<usize>, reach: usize, samples: usize) -> Range<usize> {
    run.start.saturating_sub(reach)..(run.end + reach).min(samples)
}

impl BlankingCompensation {
    /// The gains of `fringe` (None when it has none), for hololines of its
    /// frame buffer and the colours of `bases`. The fringe's problems are
    /// checked already: the runs are at least two tables' reach apart.
    pub fn new(fringe: &Fringe, bases: &[&ColourBasis]) -> Option<Self> {
        let g: &BlankingGains = fringe.blanking_gains.as_ref()?;
        let samples = fringe.samples_per_hololine;
        let runs = [false, true].map(|reversed| fringe.frame_buffer.blanked_runs(samples, reversed));
        let flat = g.flat_field.as_ref().map(|f| {
            let neighbours = bases
                .iter()
                .map(|basis| {
                    runs.clone().map(|runs| {
                        let mut lists = vec![Vec::new(); runs.len()];
                        for e in 0..basis.emitters {
                            for v in 0..basis.views {
                                let s = basis.segment(e, v);
                                for (list, run) in lists.iter_mut().zip(&runs) {
                                    let near = neighbourhood(run, f.samples_each_side, samples);
                                    if s.start < near.end && near.start < s.start + s.len {
                                        list.push(e * basis.views + v);
                                    }
                                }
                            }
                        }
                        lists
                    })
                })
                .collect();
            FlatField { table: Table::new(f.samples_each_side, &f.zones), max_spread: f.max_spread, neighbours }
        });
        Some(BlankingCompensation { general: Table::new(g.samples_each_side, &g.zones), flat, runs, samples })
    }

    /// The gains of hololine `hololine` (its modulation) of colour `colour`.
    pub fn for_hololine<'a>(&'a self, colour: usize, hololine: &'a [f32]) -> HololineGains<'a> {
        HololineGains { gains: self, colour, hololine }
    }
}

/// A layout's blanking gains for one hololine of one colour: which table
/// each run takes follows from the hololine's modulation.
#[derive(Clone, Copy)]
pub(crate) struct HololineGains<'a> {
    gains: &'a BlankingCompensation,
    colour: usize,
    hololine: &'a [f32],
}

impl AfterKernel for HololineGains<'_> {
    fn after<T: FringeSample>(self, plan: &Plan, weights: &PaddedWeights, zone: usize, sink: &mut Encoder<'_, T>) {
        self.apply(plan, weights, zone, sink);
    }
}

impl<'a> HololineGains<'a> {
    /// The table run `r` takes (in every zone: the tables are found for the
    /// three zones at once) on a line sent backwards if `reversed`.
    fn table(&self, reversed: bool, r: usize) -> &'a Table {
        let b = self.gains;
        match &b.flat {
            Some(f)
                if evenly_lit(
                    self.hololine,
                    f.neighbours[self.colour][usize::from(reversed)][r].iter().copied(),
                    f.max_spread,
                ) =>
            {
                &f.table
            }
            _ => &b.general,
        }
    }

    /// Each stretch of zone `zone`'s samples that takes gains, on a line
    /// sent backwards if `reversed`: its first sample and its gains, one a
    /// sample.
    fn stretches(self, zone: usize, reversed: bool) -> impl Iterator<Item = (usize, &'a [(f64, f64)])> {
        let b = self.gains;
        b.runs[usize::from(reversed)].iter().enumerate().flat_map(move |(r, run)| {
            let table = self.table(reversed, r);
            table
                .stretches(run, b.samples)
                .into_iter()
                .filter(|&(_, len, _)| len > 0)
                .map(move |(first, len, at)| (first, &table.gains[zone][at..at + len]))
        })
    }

    /// Send zone `zone`'s samples beside the blanked runs with their gains:
    /// made again from `weights` (this hololine's), multiplied, and encoded
    /// by `sink` over what the kernel wrote there. `sink`'s clipped count,
    /// which the kernel's pass made for these samples without their gains,
    /// is corrected to count them as sent.
    pub fn apply<T: FringeSample>(self, plan: &Plan, weights: &PaddedWeights, zone: usize, sink: &mut Encoder<'_, T>) {
        let (mut re, mut im) = (Vec::new(), Vec::new());
        for (first, gains) in self.stretches(zone, sink.reversed) {
            re.resize(gains.len(), 0.0);
            im.resize(gains.len(), 0.0);
            plan.iq_samples(weights, zone, first, &mut re, &mut im);
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
            for ((x, y), g) in re.iter_mut().zip(im.iter_mut()).zip(gains) {
                let (a, b) = (f64::from(*x), f64::from(*y));
                (*x, *y) = ((g.0 * a - g.1 * b) as f32, (g.0 * b + g.1 * a) as f32);
            }
            sink.put(0, first, &re);
            sink.put(1, first, &im);
        }
    }

    /// Divide zone `zone`'s samples of this hololine by the gains they were
    /// sent with, in place: the basis's samples again (up to rounding), for
    /// recovering the modulation from what was sent. `reversed` says, per
    /// lane (I, Q), whether its line is sent backwards: a pair split across
    /// two lines sent opposite ways took each lane's gains from its own
    /// line's runs (`I' = Re(g_I s)`, `Q' = Im(g_Q s)`).
    pub fn undo(self, zone: usize, reversed: [bool; 2], re: &mut [f32], im: &mut [f32]) {
        if reversed[0] == reversed[1] {
            for (first, gains) in self.stretches(zone, reversed[0]) {
                for (n, g) in (first..).zip(gains) {
                    let (x, y) = (f64::from(re[n]), f64::from(im[n]));
                    let d = g.0 * g.0 + g.1 * g.1;
                    (re[n], im[n]) = (((g.0 * x + g.1 * y) / d) as f32, ((g.0 * y - g.1 * x) / d) as f32);
                }
            }
            return;
        }
        // Each lane's gain at every sample (1 where it took none), then per
        // sample the 2 × 2 system I' = a_I I − b_I Q, Q' = a_Q Q + b_Q I.
        let lane_gains = |reversed: bool| {
            let mut g = vec![(1.0, 0.0); re.len()];
            for (first, gains) in self.stretches(zone, reversed) {
                g[first..first + gains.len()].copy_from_slice(gains);
            }
            g
        };
        let (g_i, g_q) = (lane_gains(reversed[0]), lane_gains(reversed[1]));
        for n in 0..re.len() {
            let ((ai, bi), (aq, bq)) = (g_i[n], g_q[n]);
            if (ai, bi, aq, bq) == (1.0, 0.0, 1.0, 0.0) {
                continue;
            }
            let (x, y) = (f64::from(re[n]), f64::from(im[n]));
            let d = ai * aq + bi * bq;
            (re[n], im[n]) = (((aq * x + bi * y) / d) as f32, ((ai * y - bq * x) / d) as f32);
        }
    }
}
