//! Fringe assembly: from a stored modulation to the images a display's frame
//! buffer takes.
//!
//! [`Assembler`] drives a layout's basis (tabulated in a [`Plan`] per colour
//! channel, from the physics in [`basis`]) over every hololine and colour channel, and deals the resulting
//! signals into the frame buffer ([`crate::layout::FrameBuffer`]): one task
//! per frame-buffer line, each writing only its own rows, so the bytes do not
//! depend on the thread count. [`Assembler::unpack`] is the inverse, used to
//! check and view fringes already written.

pub mod basis;
mod blanking;
pub(crate) mod chirp;
pub(crate) mod hogel;
pub mod output;
mod pack;
pub(crate) mod plan;
mod profile;
pub mod retarget;

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::layout::{ColourSignals, FrameBuffer, Layout, Quantization};
use crate::modulation::Modulation;
use crate::simd::Simd;
pub use basis::ColourBasis;
use blanking::BlankingCompensation;
pub use chirp::ZonedChirp;
pub use hogel::HogelGratings;
pub use pack::FringeSample;
use pack::{interleave, Adder, Encoder, LineScratch};
use plan::PaddedWeights;
pub use plan::{BlockSink, Plan};
pub use profile::{load_layout, problems};

/// The float signals of every hololine of one colour channel, before they
/// are dealt into the frame buffer: `data[(j · signals + s) · samples + n]`
/// for signal `s` (in the layout's signal order) of hololine `j`.
#[derive(Clone, Debug, PartialEq)]
pub struct Signals {
    /// Signals per hololine.
    pub signals: usize,
    /// Hololines.
    pub hololines: usize,
    /// Samples per hololine and signal.
    pub samples: usize,
    /// The samples.
    pub data: Vec<f32>,
}

impl Signals {
    /// Zero signals.
    pub fn zeros(signals: usize, hololines: usize, samples: usize) -> Self {
        Signals { signals, hololines, samples, data: vec![0.0; signals * hololines * samples] }
    }
    /// Signal `s` of hololine `j`.
    pub fn row(&self, s: usize, j: usize) -> &[f32] {
        let at = (j * self.signals + s) * self.samples;
        &self.data[at..at + self.samples]
    }
    /// Signal `s` of hololine `j`, mutable.
    pub fn row_mut(&mut self, s: usize, j: usize) -> &mut [f32] {
        let at = (j * self.signals + s) * self.samples;
        &mut self.data[at..at + self.samples]
    }
}

/// The images of one frame, `images[i][(row · width + column) · components + component]`.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameImages<T> {
    /// Visible columns.
    pub width: usize,
    /// Visible rows.
    pub height: usize,
    /// Components per pixel.
    pub components: usize,
    /// One buffer per image.
    pub images: Vec<Vec<T>>,
}

impl<T: Copy> FrameImages<T> {
    /// Pixel `(row, column)` component `component` of image `image`.
    pub fn at(&self, image: usize, row: usize, column: usize, component: usize) -> T {
        self.images[image][(row * self.width + column) * self.components + component]
    }
}

/// What assembling one frame found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Samples clipped by the quantization.
    pub clipped: u64,
    /// Hololine signals that were all zero (skipped).
    pub dark_hololines: u64,
}

/// Assembles frames for one layout.
#[derive(Clone, Debug)]
pub struct Assembler {
    layout: Layout,
    /// One tabulated basis per colour channel (the wavelength differs).
    plans: Vec<Plan>,
    /// Which kernels the processor may run (the portable ones when forced).
    simd: Simd,
    /// The layout's blanking gains, laid out over a hololine.
    blanking: Option<BlankingCompensation>,
}

impl Assembler {
    /// An assembler for `layout`, which must have a fringe side that fits its
    /// geometry: otherwise an error with every reason of [`problems`].
    pub fn new(layout: &Layout) -> Result<Self> {
        let reasons = problems(layout);
        if !reasons.is_empty() {
            return Err(Error::layout(&layout.name, reasons.join("; ")));
        }
        let plans = (0..layout.geometry.channels.len())
            .map(|c| ColourBasis::new(layout, c).map(Plan::new))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|p| Error::layout(&layout.name, p.join("; ")))?;
        let bases: Vec<&ColourBasis> = plans.iter().map(Plan::basis).collect();
        let blanking = layout.fringe.as_ref().and_then(|f| BlankingCompensation::new(f, &bases));
        Ok(Assembler { layout: layout.clone(), plans, simd: Simd::Detect, blanking })
    }

    /// The same assembler, its kernels chosen by `simd` ([`Simd::Portable`]:
    /// the portable block kernel and pixel interleave even where AVX2 and
    /// SSSE3 are present, for checking them).
    pub fn with_simd(mut self, simd: Simd) -> Self {
        self.plans = self.plans.into_iter().map(|p| p.with_simd(simd)).collect();
        self.simd = simd;
        self
    }

    /// The layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The tabulated basis of colour channel `c`.
    pub fn plan(&self, c: usize) -> &Plan {
        &self.plans[c]
    }

    fn frame_buffer(&self) -> &FrameBuffer {
        &self.layout.fringe.as_ref().expect("checked in new").frame_buffer
    }
    fn quantization(&self) -> &Quantization {
        &self.layout.fringe.as_ref().expect("checked in new").quantization
    }
    fn signals_per_colour(&self) -> usize {
        self.plans[0].basis().signals()
    }
    fn colours_summed(&self) -> bool {
        self.layout.fringe.as_ref().expect("checked in new").colours == ColourSignals::Summed
    }
    fn samples(&self) -> usize {
        self.plans[0].basis().samples
    }

    /// `Ok` when `m` has the geometry this layout expects; otherwise an error
    /// that says plainly which numbers differ.
    pub fn check_geometry(&self, m: &Modulation) -> Result<()> {
        self.check_fits(m.geometry())
    }

    /// [`Assembler::check_geometry`] of a geometry alone (a file's, before
    /// any frame of it is read).
    pub fn check_fits(&self, got: &crate::geometry::Geometry) -> Result<()> {
        let want = &self.layout.geometry;
        let mut differences = Vec::new();
        let mut counts = |what: &str, a: usize, b: usize| {
            if a != b {
                differences.push(format!("{a} {what} (the layout has {b})"));
            }
        };
        counts("hololines", got.hololines, want.hololines);
        counts("emitters", got.emitters, want.emitters);
        counts("views", got.views.count, want.views.count);
        let names =
            |g: &crate::geometry::Geometry| g.channels.iter().map(|c| c.name.clone()).collect::<Vec<_>>().join(",");
        if names(got) != names(want) {
            differences.push(format!("channels {} (the layout has {})", names(got), names(want)));
        }
        if got.vertical_views.is_some() {
            return Err(Error::argument(
                "modulation",
                format!(
                    "the modulation is full parallax ({} × {} views) and layout {} is horizontal parallax; holo does not yet assemble full-parallax fringes",
                    got.views.count,
                    got.vertical_view_count(),
                    self.layout.name
                ),
            ));
        }
        let near = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b.abs().max(1e-9);
        for (what, a, b) in [
            ("emitter pitch", got.emitter_pitch_m, want.emitter_pitch_m),
            ("hololine pitch", got.hololine_pitch_m, want.hololine_pitch_m),
            ("emitter plane z", got.emitter_z_m, want.emitter_z_m),
        ] {
            if !near(a, b) {
                differences.push(format!("{what} {a} m (the layout has {b} m)"));
            }
        }
        for v in 0..got.views.count.min(want.views.count) {
            if !near(got.views.theta_rad(v), want.views.theta_rad(v)) {
                differences.push(format!(
                    "view {v} at {:.4}° (the layout has {:.4}°)",
                    got.views.theta_rad(v).to_degrees(),
                    want.views.theta_rad(v).to_degrees()
                ));
                break;
            }
        }
        if differences.is_empty() {
            return Ok(());
        }
        Err(Error::argument(
            "modulation",
            format!(
                "the modulation does not fit layout {}: it has {}; resample it onto the layout first",
                self.layout.name,
                differences.join(", ")
            ),
        ))
    }

    fn check_samples(m: &Modulation) -> Result<()> {
        if let Some((c, j, e, v, value, why)) = m.first_bad_sample() {
            return Err(Error::BadSample {
                path: "modulation".into(),
                frame: 0,
                hololine: j,
                emitter: e,
                view: m.geometry().view_of_index(v).0,
                vertical_view: m.geometry().vertical_views.as_ref().map(|_| m.geometry().view_of_index(v).1),
                channel: m.geometry().channels[c].name.clone(),
                value,
                why,
            });
        }
        Ok(())
    }

    /// The float signals of colour channel `colour` for every hololine (fast
    /// path, hololines in parallel), before quantization and packing.
    pub fn signals(&self, m: &Modulation, colour: usize) -> Result<Signals> {
        self.check_geometry(m)?;
        Self::check_samples(m)?;
        let plan = &self.plans[colour];
        let (zones, lanes, samples) = (plan.basis().zones(), plan.basis().lanes(), self.samples());
        let hololines = m.geometry().hololines;
        let mut out = Signals::zeros(zones * lanes, hololines, samples);
        out.data.par_chunks_mut(zones * lanes * samples).enumerate().for_each(|(j, rows)| {
            let Some(w) = Plan::weights(m.hololine(colour, j)) else { return };
            let mut spare = Vec::new();
            for (zone, zone_rows) in rows.chunks_mut(lanes * samples).enumerate() {
                let (re, im) = zone_rows.split_at_mut(samples);
                let im = if im.is_empty() {
                    spare.resize(samples, 0.0);
                    &mut spare[..]
                } else {
                    im
                };
                plan.zone(&w, zone, re, im);
            }
        });
        Ok(out)
    }

    /// spec/layouts.md §5.5 read straight, in f64, on `signals` (hololine
    /// `j` of colour `colour` of `m`, as [`Assembler::signals_reference`]
    /// gives them): the blanking gains applied, each run's table chosen from
    /// the radiances of every element whose segment lies near it. Slow, for
    /// tests; see [`Layout::blanking_gains_reference`].
    pub fn blanking_gains_reference(&self, m: &Modulation, j: usize, colour: usize, signals: &mut [Vec<f64>]) {
        let basis = self.plan(colour).basis();
        let hololine = m.hololine(colour, j);
        let radiance_range = |samples: std::ops::Range<usize>| {
            let (mut lo, mut hi) = (f64::INFINITY, 0f64);
            for e in 0..basis.emitters {
                for v in 0..basis.views {
                    let s = basis.segment(e, v);
                    if s.start < samples.end && samples.start < s.start + s.len {
                        let radiance = f64::from(hololine[e * basis.views + v]).max(0.0);
                        (lo, hi) = (lo.min(radiance), hi.max(radiance));
                    }
                }
            }
            (lo, hi)
        };
        self.layout.blanking_gains_reference(j, colour, signals, &radiance_range);
    }

    /// The f64 reference of [`Assembler::signals`] for hololines `hololines`
    /// (see [`ColourBasis::reference`]); slow, for tests.
    pub fn signals_reference(
        &self,
        m: &Modulation,
        colour: usize,
        hololines: std::ops::Range<usize>,
    ) -> Result<Vec<Vec<Vec<f64>>>> {
        self.check_geometry(m)?;
        Self::check_samples(m)?;
        Ok(hololines.map(|j| self.plans[colour].basis().reference(m.hololine(colour, j))).collect())
    }

    /// Blank images of the layout's frame buffer.
    pub fn blank_images<T: FringeSample>(&self) -> FrameImages<T> {
        let fb = self.frame_buffer();
        let len = fb.width * fb.height * fb.components;
        FrameImages {
            width: fb.width,
            height: fb.height,
            components: fb.components,
            images: vec![vec![T::blank(self.quantization()); len]; fb.image_names.len()],
        }
    }

    /// Assemble one frame into `out` (from [`Assembler::blank_images`] or an
    /// earlier frame: rows outside the hololines' blocks are not touched).
    /// The samples are checked as they are weighed (one pass over the
    /// modulation, not two): after an error for a bad sample, `out` may hold
    /// part of the frame.
    pub fn assemble_into<T: FringeSample>(&self, m: &Modulation, out: &mut FrameImages<T>) -> Result<FrameStats> {
        self.check_geometry(m)?;
        let fb = self.frame_buffer();
        if (out.width, out.height, out.components, out.images.len())
            != (fb.width, fb.height, fb.components, fb.image_names.len())
        {
            *out = self.blank_images();
        }
        let q = *self.quantization();
        let hololines = m.geometry().hololines;
        let per_colour = self.signals_per_colour();
        let summed = self.colours_summed();
        let signals = self.layout.signals_per_hololine();
        let samples = self.samples();
        let lines = fb.lines(hololines, signals);
        let row_len = fb.width * fb.components;
        let blocks = line_blocks(fb, lines, &mut out.images);
        // For each image and component, the channel that feeds it.
        let feeds: Vec<Vec<Option<usize>>> = (0..fb.image_names.len())
            .map(|image| {
                (0..fb.components)
                    .map(|comp| fb.channels.iter().position(|s| s.image == image && s.component == comp))
                    .collect()
            })
            .collect();
        let (stats, valid) = blocks
            .into_par_iter()
            .enumerate()
            .map_init(
                || LineScratch::new(samples, fb.channels.len(), T::blank(&q)),
                |scratch, (line, mut images)| {
                    let LineScratch { zeros, codes, weights, sum } = scratch;
                    let mut stats = FrameStats::default();
                    // Whether every sample weighed so far was fit to weigh.
                    let mut valid = true;
                    // The (hololine, colour) whose weights are in `weights`, and whether it is lit.
                    let mut weights_of: Option<(usize, usize, bool)> = None;
                    let reversed = fb.line_reversed(line);
                    // What channel `c` of this line carries: (hololine, colours, zone, lane).
                    let item = |c: usize| {
                        let k = line * fb.channels.len() + c;
                        (c < fb.channels.len() && k < hololines * signals).then(|| {
                            let (j, s) = (k / signals, k % signals);
                            let (colours, within) = if summed {
                                (0..self.plans.len(), s)
                            } else {
                                (s / per_colour..s / per_colour + 1, s % per_colour)
                            };
                            let lanes = self.plans[colours.start].basis().lanes();
                            (j, colours, within / lanes, within % lanes)
                        })
                    };
                    let mut filled = vec![false; fb.channels.len()];
                    let mut c = 0;
                    while let Some((j, colours, zone, _)) = item(c) {
                        // The channels from c on that carry lanes of this zone.
                        let mut lane_channel = [None, None];
                        while let Some((j2, colours2, zone2, lane)) = item(c) {
                            if (j2, &colours2, zone2) != (j, &colours, zone) {
                                break;
                            }
                            lane_channel[lane] = Some(c);
                            filled[c] = true;
                            c += 1;
                        }
                        // Load colour's weights of hololine j (unless they are
                        // already there); false when that hololine is dark.
                        let mut lit_weights = |colour: usize, weights: &mut PaddedWeights| match weights_of {
                            Some((wj, wc, lit)) if (wj, wc) == (j, colour) => lit,
                            _ => {
                                let scan = self.plans[colour].padded_weights_into(m.hololine(colour, j), weights);
                                valid &= scan.valid;
                                weights_of = Some((j, colour, scan.lit));
                                scan.lit
                            }
                        };
                        if colours.len() == 1 {
                            let colour = colours.start;
                            if lit_weights(colour, weights) {
                                let sink = Encoder { lane_channel, codes, samples, reversed, q: &q, clipped: 0 };
                                let blanking =
                                    self.blanking.as_ref().map(|b| b.for_hololine(colour, m.hololine(colour, j)));
                                stats.clipped += sink.encode(&self.plans[colour], weights, zone, blanking);
                                continue;
                            }
                        } else {
                            // Colours summed into one signal: each colour's zone
                            // added into `sum`, then encoded.
                            let mut any = false;
                            sum.iter_mut().for_each(|lane| lane.fill(0.0));
                            for colour in colours {
                                if lit_weights(colour, weights) {
                                    any = true;
                                    let mut adder = Adder(&mut sum[..]);
                                    self.plans[colour].zone_padded(weights, zone, &mut adder);
                                }
                            }
                            if any {
                                for (lane, ch) in lane_channel.into_iter().enumerate() {
                                    if let Some(ch) = ch {
                                        stats.clipped += T::encode_line(&sum[lane], reversed, &mut codes[ch], &q);
                                    }
                                }
                                continue;
                            }
                        }
                        for ch in lane_channel.into_iter().flatten() {
                            T::encode_line(zeros, false, &mut codes[ch], &q);
                        }
                        stats.dark_hololines += 1;
                    }
                    for (block, feeds) in images.iter_mut().zip(&feeds) {
                        let sources: Vec<Option<&[T]>> =
                            feeds.iter().map(|f| f.filter(|c| filled[*c]).map(|c| &codes[c][..])).collect();
                        if sources.iter().all(Option::is_none) {
                            continue;
                        }
                        for (r, row) in block.chunks_exact_mut(row_len).enumerate() {
                            interleave(row, &sources, r * fb.line_samples, self.simd);
                        }
                    }
                    (stats, valid)
                },
            )
            .reduce(
                || (FrameStats::default(), true),
                |(a, a_valid), (b, b_valid)| {
                    let stats = FrameStats {
                        clipped: a.clipped + b.clipped,
                        dark_hololines: a.dark_hololines + b.dark_hololines,
                    };
                    (stats, a_valid && b_valid)
                },
            );
        if !valid {
            // Name the first bad sample of the frame.
            Self::check_samples(m)?;
        }
        Ok(stats)
    }

    /// Assemble one frame into new images.
    pub fn assemble<T: FringeSample>(&self, m: &Modulation) -> Result<(FrameImages<T>, FrameStats)> {
        let mut out = self.blank_images();
        let stats = self.assemble_into(m, &mut out)?;
        Ok((out, stats))
    }

    /// Divide the blanking gains (spec/layouts.md §5.5) out of the signals
    /// of hololine `j` in unpacked group `group` (`rows`: its signals, as
    /// [`Assembler::unpack`] gives them): the basis's samples again, for
    /// recovering the modulation from what was sent. `m` is the frame they
    /// were made from: which gains a run took depends on it (§5.5's flat
    /// fields).
    pub(crate) fn undo_blanking_gains(&self, m: &Modulation, group: usize, j: usize, rows: &mut [Vec<f32>]) {
        let Some(b) = &self.blanking else { return };
        let fb = self.frame_buffer();
        let signals = self.layout.signals_per_hololine();
        let per_group = rows.len();
        // Gains need I/Q signals: zone `z` is the pair 2z, 2z + 1.
        for zone in 0..per_group / 2 {
            // Each lane's line: a pair may be split across two lines.
            let reversed = [0, 1].map(|lane| {
                let (_, line) = fb.channel_and_line(j, group * per_group + 2 * zone + lane, signals);
                fb.line_reversed(line)
            });
            let (re, im) = rows.split_at_mut(2 * zone + 1);
            // Gains need colours with signals of their own: group = colour.
            b.for_hololine(group, m.hololine(group, j)).undo(zone, reversed, &mut re[2 * zone], &mut im[0]);
        }
    }

    /// The signals held in frame-buffer images, decoded to floats: one
    /// [`Signals`] per colour channel, or a single one holding every colour
    /// when the layout sums colours into one signal. Samples that fell in the
    /// horizontal blanking come back as zero: they never reach the display;
    /// those beside them, with their blanking gains (as the display shows
    /// them; signal recovery divides them out first, spec/layouts.md §5.5).
    pub fn unpack<T: FringeSample>(&self, images: &FrameImages<T>, hololines: usize) -> Result<Vec<Signals>> {
        let fb = self.frame_buffer();
        if (images.width, images.height, images.components, images.images.len())
            != (fb.width, fb.height, fb.components, fb.image_names.len())
        {
            return Err(Error::argument(
                "fringe images",
                format!(
                    "fringe images of {} × {} × {} ({} images) do not match layout {} ({} × {} × {}, {} images)",
                    images.width,
                    images.height,
                    images.components,
                    images.images.len(),
                    self.layout.name,
                    fb.width,
                    fb.height,
                    fb.components,
                    fb.image_names.len()
                ),
            ));
        }
        let q = self.quantization();
        let per_colour = self.signals_per_colour();
        let signals = self.layout.signals_per_hololine();
        let samples = self.samples();
        let groups = if self.colours_summed() { 1 } else { self.plans.len() };
        let mut out: Vec<Signals> = (0..groups).map(|_| Signals::zeros(per_colour, hololines, samples)).collect();
        for j in 0..hololines {
            for s in 0..signals {
                let dest = out[s / per_colour].row_mut(s % per_colour, j);
                for (n, d) in dest.iter_mut().enumerate() {
                    if let Some(p) = fb.place(j, s, n, signals, samples) {
                        *d = images.at(p.image, p.row, p.column, p.component).decode(q);
                    }
                }
            }
        }
        Ok(out)
    }
}

/// Every image split into the disjoint row blocks of each frame-buffer line
/// (`blocks[line][image]`), so that one task per line writes only its own rows.
fn line_blocks<'a, T>(fb: &FrameBuffer, lines: usize, images: &'a mut [Vec<T>]) -> Vec<Vec<&'a mut [T]>> {
    let row_len = fb.width * fb.components;
    let mut blocks: Vec<Vec<&mut [T]>> = (0..lines).map(|_| Vec::new()).collect();
    for image in images.iter_mut() {
        let mut rest: &mut [T] = image;
        let mut row = 0;
        for (line, block) in blocks.iter_mut().enumerate() {
            let first = fb.line_first_row(line);
            let skipped = std::mem::take(&mut rest).split_at_mut((first - row) * row_len).1;
            let (this, after) = skipped.split_at_mut(fb.rows_per_hololine * row_len);
            block.push(this);
            rest = after;
            row = first + fb.rows_per_hololine;
        }
    }
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{mark1, mark1_hogel, mark2, mark3, mark4};
    use rand::{Rng, SeedableRng};

    fn with_hololines(mut layout: Layout, hololines: usize) -> Layout {
        layout.geometry.hololines = hololines;
        layout
    }

    /// `layout` cut to `hololines`, its assembler, and a random frame for it
    /// ([`random`]).
    fn assembler_and_frame(layout: Layout, hololines: usize, seed: u64, rough: bool) -> (Assembler, Modulation) {
        let layout = with_hololines(layout, hololines);
        let m = random(&layout, seed, rough);
        (Assembler::new(&layout).unwrap(), m)
    }

    /// Rough (independent uniform) or smooth random modulation, never zero everywhere.
    fn random(layout: &Layout, seed: u64, rough: bool) -> Modulation {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let phase: f32 = rng.gen_range(0.0..6.0);
        Modulation::from_fn(layout.geometry.clone(), |c, j, e, v| {
            if rough {
                rng.gen_range(0.0..1.0)
            } else {
                0.5 + 0.5 * ((e as f32 * 0.07 + v as f32 * 0.11 + j as f32 + c as f32 + phase).sin())
            }
        })
        .unwrap()
    }

    /// Modulation for the flat-field gains: per hololine, stretches of
    /// emitters evenly lit (within `spread` of their brightest), stretches
    /// just too uneven for them, and rough ones, in an order that shifts with
    /// the hololine, so that runs and zones see all three.
    fn patchy(layout: &Layout, seed: u64, spread: f64) -> Modulation {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        Modulation::from_fn(layout.geometry.clone(), |_, j, e, _| match (e / 80 + j) % 3 {
            0 => 0.6 * (1.0 - spread as f32 * rng.gen_range(0.0..0.999)),
            1 => 0.6 * (1.0 - spread as f32 * rng.gen_range(1.2..1.6)),
            _ => rng.gen_range(0.0..1.0),
        })
        .unwrap()
    }

    #[test]
    #[ignore = "slow: the full run takes it (README, Development)"]
    fn fast_and_straightforward_agree_with_the_f64_reference_for_every_basis() {
        // One layout per core: the test is the longest of the library's.
        use rayon::prelude::*;
        [mark3(), mark1(), mark1_hogel(), mark2(), mark4()].into_par_iter().for_each(|layout| {
            let hololines = reference_hololines(&layout);
            let layout = with_hololines(layout, hololines);
            let a = Assembler::new(&layout).unwrap();
            // The portable kernel is what processors without AVX2 run: held
            // to the same bound here, where the vector kernel is the default.
            let portable = a.clone().with_simd(Simd::Portable);
            for (seed, rough) in [(1, true), (2, false)] {
                let m = random(&layout, seed, rough);
                for colour in 0..layout.geometry.channels.len() {
                    let plan = a.plan(colour);
                    let fast = a.signals(&m, colour).unwrap();
                    let fast_portable = portable.signals(&m, colour).unwrap();
                    let reference = a.signals_reference(&m, colour, 0..hololines).unwrap();
                    let samples = plan.basis().samples;
                    let mut straight = [vec![0f32; samples], vec![0f32; samples]];
                    let mut worst = [0f64; 3];
                    let mut largest = 0f64;
                    for (j, want) in reference.iter().enumerate() {
                        let w = Plan::weights(m.hololine(colour, j)).unwrap();
                        for zone in 0..plan.basis().zones() {
                            let [re, im] = &mut straight;
                            plan.zone_straightforward(&w, zone, re, im);
                            for (lane, straight) in straight.iter().take(plan.basis().lanes()).enumerate() {
                                let s = zone * plan.basis().lanes() + lane;
                                for n in 0..samples {
                                    let r = want[s][n];
                                    largest = largest.max(r.abs());
                                    worst[0] = worst[0].max((f64::from(fast.row(s, j)[n]) - r).abs());
                                    worst[1] = worst[1].max((f64::from(straight[n]) - r).abs());
                                    worst[2] = worst[2].max((f64::from(fast_portable.row(s, j)[n]) - r).abs());
                                }
                            }
                        }
                    }
                    assert!(largest > 0.05, "{}: the signal is not trivially small ({largest})", layout.name);
                    assert!(worst.iter().all(|w| *w < 2e-6), "{} colour {colour}: worst {worst:?}", layout.name);
                }
            }
        });
    }

    /// How many hololines a test against the f64 reference takes of
    /// `layout`: two check that the second lands in its own rows; Mark IV
    /// takes one, its reference over 355 200-sample hololines being most of
    /// such a test's time (13 of 14 s with two).
    fn reference_hololines(layout: &Layout) -> usize {
        if layout.name == "mark4" {
            1
        } else {
            2
        }
    }

    /// The largest difference of any of `fast` from the f64 `reference`
    /// (hololine, signal, sample), and the largest reference sample.
    fn worst_against(reference: &[Vec<Vec<f64>>], fast: &[&Signals]) -> (f64, f64) {
        let (mut worst, mut largest) = (0f64, 0f64);
        for (j, want) in reference.iter().enumerate() {
            for (s, want) in want.iter().enumerate() {
                for (n, r) in want.iter().enumerate() {
                    largest = largest.max(r.abs());
                    for f in fast {
                        worst = worst.max((f64::from(f.row(s, j)[n]) - r).abs());
                    }
                }
            }
        }
        (worst, largest)
    }

    #[test]
    #[ignore = "slow: the full run takes it (README, Development)"]
    fn emitter_phases_agree_with_the_f64_reference_in_every_path() {
        // Complex weights run the kernel twice (I/Q) or against the
        // imaginary table (real signals); the reference multiplies each
        // element by its emitter's phase. Fast, portable, frame path (floats
        // in the frame buffer, read back) and the least-squares adjoint.
        use crate::layout::EmitterPhases;
        use rayon::prelude::*;
        let cases = [
            (mark3(), EmitterPhases::Random),
            (mark1(), EmitterPhases::Quadrature),
            (mark1_hogel(), EmitterPhases::Random),
            (mark4(), EmitterPhases::Quadrature),
        ];
        cases.into_par_iter().for_each(|(layout, phases)| {
            let hololines = reference_hololines(&layout);
            let mut layout = with_hololines(layout, hololines);
            let unphased = Assembler::new(&layout).unwrap();
            layout.fringe.as_mut().unwrap().emitter_phases = phases;
            let a = Assembler::new(&layout).unwrap();
            let portable = a.clone().with_simd(Simd::Portable);
            let m = random(&layout, 5, true);
            for colour in 0..layout.geometry.channels.len() {
                let reference = a.signals_reference(&m, colour, 0..hololines).unwrap();
                let (fast, fast_portable) = (a.signals(&m, colour).unwrap(), portable.signals(&m, colour).unwrap());
                let without = unphased.signals(&m, colour).unwrap();
                let (worst, largest) = worst_against(&reference, &[&fast, &fast_portable]);
                let (changed, _) = worst_against(&reference, &[&without]);
                assert!(largest > 0.05, "{}: the signal is not trivially small ({largest})", layout.name);
                assert!(worst < 2e-6, "{} colour {colour} {phases:?}: worst {worst}", layout.name);
                assert!(changed > 0.05, "{} colour {colour}: the phases changed nothing ({changed})", layout.name);
            }
            // The frame path writes what the signals say.
            let (images, _) = a.assemble::<f32>(&m).unwrap();
            let unpacked = a.unpack(&images, hololines).unwrap();
            // With summed colours the frame buffer holds every colour's sum.
            let mut colour_signals = a.signals(&m, 0).unwrap();
            if a.colours_summed() {
                for c in 1..layout.geometry.channels.len() {
                    let more = a.signals(&m, c).unwrap();
                    colour_signals.data.iter_mut().zip(&more.data).for_each(|(x, y)| *x += y);
                }
            }
            let group = &unpacked[0];
            let fb = &layout.fringe.as_ref().unwrap().frame_buffer;
            let mut want: Vec<Vec<f64>> = (0..colour_signals.signals)
                .map(|s| colour_signals.row(s, 0).iter().map(|&x| f64::from(x)).collect())
                .collect();
            a.blanking_gains_reference(&m, 0, 0, &mut want);
            let mut worst = 0f64;
            for (s, want) in want.iter().enumerate().take(group.signals) {
                for (n, want) in want.iter().enumerate() {
                    if n % fb.line_samples < fb.width {
                        worst = worst.max((f64::from(group.row(s, 0)[n]) - want).abs());
                    }
                }
            }
            assert!(worst < 1e-6, "{}: frame path against signals {worst}", layout.name);
            // The adjoint is the forward map's: ⟨F w, s⟩ = ⟨w, F* s⟩ on random vectors.
            let plan = a.plan(0);
            let basis = plan.basis();
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
            let w: Vec<f32> = (0..basis.emitters * basis.views).map(|_| rng.gen_range(0.0..1.0)).collect();
            let s: Vec<Vec<f32>> =
                (0..2).map(|_| (0..basis.samples).map(|_| rng.gen_range(-1.0..1.0)).collect()).collect();
            for zone in 0..basis.zones() {
                let (mut re, mut im) = (vec![0f32; basis.samples], vec![0f32; basis.samples]);
                plan.zone(&w, zone, &mut re, &mut im);
                let mut forward: f64 = re.iter().zip(&s[0]).map(|(a, b)| f64::from(a * b)).sum();
                if basis.lanes() == 2 {
                    forward += im.iter().zip(&s[1]).map(|(a, b)| f64::from(a * b)).sum::<f64>();
                }
                let mut adjoint = vec![0f64; w.len()];
                plan.zone_adjoint(zone, &s[0], &s[1], &mut adjoint);
                let back: f64 = adjoint.iter().zip(&w).map(|(a, b)| a * f64::from(*b)).sum();
                assert!(
                    (forward - back).abs() < 1e-4 * forward.abs().max(1.0),
                    "{} zone {zone}: {forward} against {back}",
                    layout.name
                );
            }
        });
    }

    /// `layout` with its chirp segments cross-faded over `taper` samples,
    /// the ends of its zone pieces as well (no piece taper of their own).
    fn tapered(mut layout: Layout, taper: usize) -> Layout {
        if let crate::layout::Basis::Chirp { segment_taper_samples, piece_taper_samples, .. } =
            &mut layout.fringe.as_mut().unwrap().basis
        {
            *segment_taper_samples = taper;
            *piece_taper_samples = 0;
        }
        layout
    }

    #[test]
    #[ignore = "slow: the full run takes it (README, Development)"]
    fn tapered_segments_agree_with_the_f64_reference_and_fold_less() {
        use rayon::prelude::*;
        [mark3(), mark1(), mark2()].into_par_iter().for_each(|layout| {
            // The widest taper: a whole segment.
            let taper = {
                let a = Assembler::new(&layout).unwrap();
                let super::basis::Elements::Chirp(c) = &a.plan(0).basis().elements else { unreachable!() };
                c.samples_per_view()
            };
            let hard = Assembler::new(&with_hololines(layout.clone(), 2)).unwrap();
            let layout = with_hololines(tapered(layout, taper), 2);
            let a = Assembler::new(&layout).unwrap();
            let portable = a.clone().with_simd(Simd::Portable);
            let m = random(&layout, 3, true);
            let reference = a.signals_reference(&m, 0, 0..2).unwrap();
            let (fast, fast_portable) = (a.signals(&m, 0).unwrap(), portable.signals(&m, 0).unwrap());
            let (worst, largest) = worst_against(&reference, &[&fast, &fast_portable]);
            assert!(largest > 0.05 && worst < 2e-6, "{}: worst {worst}, largest {largest}", layout.name);
            // Inside the chirp the segments' weights add to 1, across zone
            // boundaries too (where the two pieces meet after up-conversion):
            // a fully lit emitter's chirp is the same with or without the
            // taper, but for the fades at its two ends.
            let basis = a.plan(0).basis();
            let super::basis::Elements::Chirp(c) = &basis.elements else { unreachable!() };
            // The cross-fades of chirps a slot apart add to 1 as well: the
            // normalisation stays the overlap (spec/layouts.md §4.2).
            if layout.name == "mark3" {
                assert_eq!(basis.normalisation(), 16.0);
            }
            let span = (c.zones * c.chirp_samples) as i64;
            let half = (taper / 2) as i64;
            for x in half..span - half {
                let sum: f64 = (0..c.views())
                    .filter_map(|v| {
                        let (zone, first, len) = c.element_extent(v);
                        let u = x - (zone * c.chirp_samples) as i64;
                        (u >= first && u < first + len as i64).then(|| c.window(v, u))
                    })
                    .sum();
                assert!((sum - 1.0).abs() < 1e-12, "{}: weights at chirp sample {x} add to {sum}", layout.name);
            }
            // The band-edge elements fold far less.
            let (folded_hard, v_hard) = hard.plan(0).basis().largest_folded_energy();
            let (folded, v) = basis.largest_folded_energy();
            eprintln!("{}: largest folded energy {folded_hard:.1e} (view {v_hard}) hard, {folded:.1e} (view {v}) with a {taper}-sample taper", layout.name);
            assert!(folded < folded_hard / 30.0, "{}: {folded} against {folded_hard}", layout.name);
        });
    }

    #[test]
    fn a_profile_states_the_folded_energy_it_accepts() {
        let mut layout = mark3();
        layout.fringe.as_mut().unwrap().max_folded_energy = Some(1e-3);
        let refused = Assembler::new(&layout).unwrap_err().to_string();
        assert!(refused.contains("fold") && refused.contains("view"), "{refused}");
        let layout = tapered(layout, 32);
        Assembler::new(&layout).unwrap();
        let mut wrong = layout.clone();
        wrong.fringe.as_mut().unwrap().max_folded_energy = Some(-1.0);
        assert!(Assembler::new(&wrong).unwrap_err().to_string().contains("max_folded_energy"));
        let mut odd = mark3();
        odd = tapered(odd, 31);
        assert!(Assembler::new(&odd).unwrap_err().to_string().contains("segment_taper_samples"));
        // A piece taper must be even, and a segment must hold half of it and
        // half of its other edge's fade (spec/layouts.md §4.2).
        let pieces = |segment: usize, piece: usize| {
            let mut layout = mark3();
            if let crate::layout::Basis::Chirp { segment_taper_samples, piece_taper_samples, .. } =
                &mut layout.fringe.as_mut().unwrap().basis
            {
                *segment_taper_samples = segment;
                *piece_taper_samples = piece;
            }
            Assembler::new(&layout).map(|_| ()).map_err(|e| e.to_string())
        };
        for (segment, piece) in [(0, 63), (0, 66), (32, 64), (16, 50), (0, usize::MAX)] {
            let refused = pieces(segment, piece).unwrap_err();
            assert!(refused.contains("piece_taper_samples"), "{segment}, {piece}: {refused}");
        }
        for (segment, piece) in [(0, 64), (0, 2), (32, 32), (16, 48)] {
            pieces(segment, piece).unwrap();
        }
    }

    #[test]
    fn the_kernel_blocks_are_as_wide_as_the_bases_allow() {
        let block = |l: Layout| Assembler::new(&l).unwrap().plan(0).block();
        assert_eq!(block(mark3()), 32, "32-sample view segments");
        assert_eq!(block(mark1()), 64);
        assert_eq!(block(mark1_hogel()), 64);
        assert_eq!(block(mark2()), 64);
        assert_eq!(block(mark4()), 16, "592-sample wafels");
        // 16 overlapping chirps, and beside a zone-piece boundary the
        // widened end of one more (the piece taper, spec/layouts.md §4.2).
        assert_eq!(Assembler::new(&mark3()).unwrap().plan(0).max_terms(), 17, "16 overlapping chirps and a fade");
        assert_eq!(Assembler::new(&tapered(mark3(), 0)).unwrap().plan(0).max_terms(), 16, "16 overlapping chirps");
    }

    #[test]
    fn mark3_channels_carry_the_right_zone_and_component() {
        // Every (head, colour) of the frame buffer, read back through the
        // paper's own words, holds the matching zone signal of the reference.
        let (a, m) = assembler_and_frame(mark3(), 2, 7, true);
        let (images, _) = a.assemble::<f32>(&m).unwrap();
        let reference = a.signals_reference(&m, 0, 0..2).unwrap();
        // (head, component, zone, sine): "Head 1 RG channels produce the
        // sine/cosine pair of zone 1. Head 1 B channel produces the sine of
        // zone 2. Head 2 RG … zone 3. Head 2 B channel produces cosine of zone 2."
        let paper =
            [(0, 0, 0, true), (0, 1, 0, false), (0, 2, 1, true), (1, 0, 2, true), (1, 1, 2, false), (1, 2, 1, false)];
        let mut reference = reference;
        for (j, want) in reference.iter_mut().enumerate() {
            a.blanking_gains_reference(&m, j, 0, want);
        }
        for (head, component, zone, sine) in paper {
            for (j, want) in reference.iter().enumerate() {
                for n in [0usize, 1, 4079, 4096, 10000, 24575 - 16] {
                    let (row, column) = (6 * j + n / 4096, n % 4096);
                    let got = images.at(head, row, column, component);
                    let want = want[2 * zone + usize::from(sine)][n];
                    assert!((f64::from(got) - want).abs() < 2e-6, "head {head} comp {component} j {j} n {n}");
                }
            }
        }
        // Rows below the hololines stay blank.
        assert!(images.images[0][12 * 4080 * 3..].iter().all(|x| *x == 0.0));
    }

    #[test]
    fn mark1_layers_hold_one_colour_each_in_16_rows_per_hololine() {
        let (a, m) = assembler_and_frame(mark1(), 3, 11, false);
        let (images, stats) = a.assemble::<u8>(&m).unwrap();
        assert_eq!(stats.clipped, 0);
        for colour in 0..3 {
            let want = a.signals(&m, colour).unwrap();
            for j in 0..3 {
                for n in [0usize, 2047, 2048, 32767] {
                    let got = images.at(colour, 16 * j + n / 2048, n % 2048, 0).decode(a.quantization());
                    assert!((got - want.row(0, j)[n]).abs() <= 0.5 / 127.0 + 1e-6, "colour {colour} j {j} n {n}");
                }
            }
        }
    }

    /// spec/layouts.md §5.6's mixed-directions vector: the pairs of zone 1
    /// are split across lines sent opposite ways, each lane with its own
    /// line's gains; undoing them gives the basis's samples back (where both
    /// lanes are shown), where the gains of one lane's line alone would not.
    #[test]
    fn gains_of_a_pair_split_across_lines_sent_opposite_ways_are_undone() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/layouts/mixed-directions.toml");
        let layout = Layout::load(path).unwrap();
        let hololines = layout.geometry.hololines;
        let m = random(&layout, 12, true);
        let a = Assembler::new(&layout).unwrap();
        let direct = a.signals(&m, 0).unwrap();
        let (floats, _) = a.assemble::<f32>(&m).unwrap();
        let unpacked = a.unpack(&floats, hololines).unwrap().remove(0);
        let fb = &layout.fringe.as_ref().unwrap().frame_buffer;
        let samples = direct.samples;
        let (mut worst, mut changed) = (0f32, 0usize);
        for j in 0..hololines {
            let mut rows: Vec<Vec<f32>> = (0..4).map(|s| unpacked.row(s, j).to_vec()).collect();
            changed += (0..4)
                .map(|s| rows[s].iter().zip(direct.row(s, j)).filter(|(x, y)| (*x - *y).abs() > 1e-3).count())
                .sum::<usize>();
            a.undo_blanking_gains(&m, 0, j, &mut rows);
            for (s, row) in rows.iter().enumerate() {
                // A lane's gained sample mixes in its partner's: where the
                // partner's line blanks that sample, it is not sent at all.
                let partner = s ^ 1;
                for (n, (&got, &want)) in row.iter().zip(direct.row(s, j)).enumerate() {
                    if fb.place(j, s, n, 4, samples).is_some() && fb.place(j, partner, n, 4, samples).is_some() {
                        worst = worst.max((got - want).abs());
                    }
                }
            }
        }
        assert!(changed > 100, "the gains changed {changed} samples");
        assert!(worst < 1e-5, "worst {worst}");
    }

    #[test]
    #[ignore = "slow: the full run takes it (README, Development)"]
    fn unpack_inverts_assembly_except_for_blanking_and_quantization() {
        // Mark III with its blanking gains, without them, and with odd lines
        // sent backwards (the runs then fall elsewhere in the signal, the
        // first at its very start).
        let mut raw = mark3();
        raw.fringe.as_mut().unwrap().blanking_gains = None;
        let mut reversed = mark3();
        reversed.fringe.as_mut().unwrap().frame_buffer.reverse_odd_lines = true;
        for layout in [mark3(), raw, reversed] {
            let (a, m) = assembler_and_frame(layout, 3, 8, true);
            let direct = a.signals(&m, 0).unwrap();
            let (floats, _) = a.assemble::<f32>(&m).unwrap();
            let (portable_floats, _) = a.clone().with_simd(Simd::Portable).assemble::<f32>(&m).unwrap();
            let (bytes, stats) = a.assemble::<u8>(&m).unwrap();
            let (portable_bytes, _) = a.clone().with_simd(Simd::Portable).assemble::<u8>(&m).unwrap();
            assert_eq!(stats.clipped, 0);
            let from_floats = a.unpack(&floats, 3).unwrap().remove(0);
            let from_portable = a.unpack(&portable_floats, 3).unwrap().remove(0);
            let from_bytes = a.unpack(&bytes, 3).unwrap().remove(0);
            let from_portable_bytes = a.unpack(&portable_bytes, 3).unwrap().remove(0);
            let fringe = a.layout().fringe.as_ref().unwrap();
            let fb = &fringe.frame_buffer;
            let k = fringe.blanking_gains.as_ref().map_or(0, |g| g.samples_each_side);
            let (mut compensated, mut undone_worst) = (0, 0f64);
            for j in 0..3 {
                let mut want: Vec<Vec<f64>> =
                    (0..6).map(|s| direct.row(s, j).iter().map(|&x| f64::from(x)).collect()).collect();
                a.blanking_gains_reference(&m, j, 0, &mut want);
                let mut undone: Vec<Vec<f32>> = (0..6).map(|s| from_floats.row(s, j).to_vec()).collect();
                a.undo_blanking_gains(&m, 0, j, &mut undone);
                let blanked = |n: usize| {
                    let sent = if fb.reverse_odd_lines && j % 2 == 1 { 24575 - n } else { n };
                    sent % 4096 >= 4080
                };
                for s in 0..6 {
                    for n in 0..24576 {
                        let (got, basis) = (from_floats.row(s, j)[n], direct.row(s, j)[n]);
                        let at = format!("{} hololine {j} signal {s} sample {n}", a.layout().name);
                        if blanked(n) {
                            assert_eq!(got, 0.0, "{at}");
                            continue;
                        }
                        // Within K of a blanked run the gains change every
                        // sample a chirp reaches; elsewhere samples come through exactly.
                        let near = (n.saturating_sub(k)..(n + k + 1).min(24576)).any(blanked);
                        if near && basis != 0.0 {
                            compensated += 1;
                            assert!(want[s][n] != f64::from(basis), "{at}: the reference left it");
                            assert!((f64::from(got) - want[s][n]).abs() < 1e-6, "{at}: {got} {}", want[s][n]);
                        } else {
                            assert_eq!(want[s][n], f64::from(basis), "{at}: the reference changed it");
                            assert_eq!(got, basis, "{at}");
                        }
                        let portable = f64::from(from_portable.row(s, j)[n]);
                        assert!((portable - want[s][n]).abs() < 1e-6, "{at}: portable");
                        for bytes in [&from_bytes, &from_portable_bytes] {
                            assert!((f64::from(bytes.row(s, j)[n]) - want[s][n]).abs() <= 0.5 / 127.0 + 1e-6, "{at}");
                        }
                        undone_worst = undone_worst.max((undone[s][n] - basis).abs() as f64);
                    }
                }
            }
            // Per signal and hololine, 5 runs inside the chirps with 2K samples each at least.
            assert!(compensated >= 3 * 6 * 5 * 2 * k, "{}: {compensated} samples took gains", a.layout().name);
            assert!(undone_worst < 1e-6, "{}: gains undone to {undone_worst}", a.layout().name);
        }
    }

    #[test]
    #[ignore = "slow: the full run takes it (README, Development)"]
    fn flat_field_gains_apply_where_the_neighbourhood_is_evenly_lit() {
        // Mark III with a flat-field table of another reach than its general
        // one (random gains, to tell them apart), lines sent either way, on
        // content with evenly lit, almost evenly lit and rough stretches: the
        // frame path against the reference, both tables used, and undone.
        for reverse_odd_lines in [false, true] {
            let mut layout = with_hololines(mark3(), 3);
            let fringe = layout.fringe.as_mut().unwrap();
            fringe.frame_buffer.reverse_odd_lines = reverse_odd_lines;
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(31);
            let k = 96;
            let flat = crate::layout::FlatFieldGains {
                max_spread: 0.05,
                samples_each_side: k,
                zones: (0..3)
                    .map(|_| (0..2 * k).map(|_| [rng.gen_range(0.5..1.5), rng.gen_range(-0.5..0.5)]).collect())
                    .collect(),
            };
            let mut general = layout.clone();
            general.fringe.as_mut().unwrap().blanking_gains.as_mut().unwrap().flat_field = None;
            layout.fringe.as_mut().unwrap().blanking_gains.as_mut().unwrap().flat_field = Some(flat);
            let a = Assembler::new(&layout).unwrap();
            let ag = Assembler::new(&general).unwrap();
            let m = patchy(&layout, 5, 0.05);
            let direct = a.signals(&m, 0).unwrap();
            let (floats, _) = a.assemble::<f32>(&m).unwrap();
            let (portable, _) = a.clone().with_simd(Simd::Portable).assemble::<f32>(&m).unwrap();
            let (bytes, _) = a.assemble::<u8>(&m).unwrap();
            let floats = a.unpack(&floats, 3).unwrap().remove(0);
            let portable = a.unpack(&portable, 3).unwrap().remove(0);
            let bytes = a.unpack(&bytes, 3).unwrap().remove(0);
            let (mut flat_runs, mut general_runs) = (0, 0);
            for j in 0..3 {
                let row = |s: usize| direct.row(s, j).iter().map(|&x| f64::from(x)).collect::<Vec<f64>>();
                let (mut want, mut want_general): (Vec<_>, Vec<_>) =
                    ((0..6).map(row).collect(), (0..6).map(row).collect());
                a.blanking_gains_reference(&m, j, 0, &mut want);
                ag.blanking_gains_reference(&m, j, 0, &mut want_general);
                let mut undone: Vec<Vec<f32>> = (0..6).map(|s| floats.row(s, j).to_vec()).collect();
                a.undo_blanking_gains(&m, 0, j, &mut undone);
                let reversed = reverse_odd_lines && j % 2 == 1;
                for run in layout.fringe.as_ref().unwrap().frame_buffer.blanked_runs(24576, reversed) {
                    for zone in 0..3 {
                        // The sample K + 1 before the run: only the flat-field table reaches it.
                        let Some(n) = run.start.checked_sub(k - 1) else { continue };
                        if want[2 * zone][n] != want_general[2 * zone][n] {
                            flat_runs += 1;
                        } else {
                            general_runs += 1;
                        }
                    }
                }
                for s in 0..6 {
                    for n in 0..24576 {
                        let at = format!("hololine {j} signal {s} sample {n}");
                        let sent = if reversed { 24575 - n } else { n };
                        if sent % 4096 >= 4080 {
                            continue;
                        }
                        assert!((f64::from(floats.row(s, j)[n]) - want[s][n]).abs() < 1e-6, "{at}");
                        assert!((f64::from(portable.row(s, j)[n]) - want[s][n]).abs() < 1e-6, "{at}: portable");
                        assert!(
                            (f64::from(bytes.row(s, j)[n]) - want[s][n]).abs() <= 0.5 / 127.0 + 1e-6,
                            "{at}: bytes"
                        );
                        assert!((undone[s][n] - direct.row(s, j)[n]).abs() < 1e-6, "{at}: undone");
                    }
                }
            }
            assert!(flat_runs >= 6 && general_runs >= 6, "flat {flat_runs}, general {general_runs}");
        }
    }

    #[test]
    fn clipping_is_counted_for_the_samples_as_sent_with_their_gains() {
        // A quantizer gain that clips the louder samples: the count must be
        // that of the reference's samples, gains applied where they apply
        // (the kernel's pass first counts the gained samples without them).
        for gains in [true, false] {
            let mut layout = mark3();
            let fringe = layout.fringe.as_mut().unwrap();
            fringe.quantization.gain *= 4.0;
            if !gains {
                fringe.blanking_gains = None;
            }
            let (a, m) = assembler_and_frame(layout, 3, 12, true);
            let q = *a.quantization();
            let direct = a.signals(&m, 0).unwrap();
            let (mut certain, mut borderline) = (0u64, 0u64);
            for j in 0..3 {
                let mut want: Vec<Vec<f64>> =
                    (0..6).map(|s| direct.row(s, j).iter().map(|&x| f64::from(x)).collect()).collect();
                a.blanking_gains_reference(&m, j, 0, &mut want);
                for code in want.iter().flatten().map(|x| q.offset + q.gain * x) {
                    let beyond = (-0.5 - code).max(code - 255.5);
                    certain += u64::from(beyond > 1e-3);
                    borderline += u64::from(beyond.abs() <= 1e-3);
                }
            }
            for simd in [Simd::Detect, Simd::Portable] {
                let (_, stats) = a.clone().with_simd(simd).assemble::<u8>(&m).unwrap();
                assert!(certain > 1000, "the test must clip: {certain}");
                assert!(
                    (certain..=certain + borderline).contains(&stats.clipped),
                    "gains {gains} {simd:?}: {} clipped, the reference {certain} (+{borderline} within rounding)",
                    stats.clipped
                );
            }
        }
    }

    #[test]
    fn bytes_do_not_depend_on_the_thread_count() {
        for layout in [with_hololines(mark3(), 8), with_hololines(mark1_hogel(), 4)] {
            let a = Assembler::new(&layout).unwrap();
            let m = random(&layout, 9, true);
            let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
            let (single, _) = one.install(|| a.assemble::<u8>(&m)).unwrap();
            let (many, _) = a.assemble::<u8>(&m).unwrap();
            assert!(single == many, "{}", layout.name);
        }
    }

    #[test]
    fn nan_and_inf_are_errors_naming_hololine_emitter_and_view() {
        let layout = with_hololines(mark3(), 4);
        let a = Assembler::new(&layout).unwrap();
        for bad in [f32::NAN, f32::INFINITY, -1.0] {
            let mut m = random(&layout, 10, true);
            m.set(0, 3, 200, 17, bad);
            let err = a.assemble::<u8>(&m).unwrap_err().to_string();
            assert!(err.contains("hololine 3, emitter 200, view 17"), "{err}");
            let err = a.signals(&m, 0).unwrap_err().to_string();
            assert!(err.contains("hololine 3, emitter 200, view 17"), "{err}");
        }
    }

    #[test]
    fn zeros_hot_emitters_and_f16_extremes_give_finite_counted_results() {
        let layout = with_hololines(mark3(), 3);
        let a = Assembler::new(&layout).unwrap();
        let mut m = Modulation::zeros(layout.geometry.clone()).unwrap();
        let (_, stats) = a.assemble::<u8>(&m).unwrap();
        assert_eq!(stats.dark_hololines, 3 * 3, "three zones of three dark hololines");
        // One hot emitter at the largest f16 value, one at the smallest subnormal.
        m.set(0, 1, 100, 40, 65504.0);
        m.set(0, 2, 7, 3, 6e-8);
        let (bytes, stats) = a.assemble::<u8>(&m).unwrap();
        assert!(stats.clipped > 0, "a 65504 radiance must clip at the default gain");
        assert_eq!(stats.dark_hololines, 3, "hololine 0 stays dark");
        let signals = a.signals(&m, 0).unwrap();
        assert!(signals.data.iter().all(|x| x.is_finite()));
        // The subnormal emitter's weight (2.4e-4 / 16) is below one 8-bit step: codes stay at the offset.
        assert!((0..6).any(|s| signals.row(s, 2).iter().any(|x| *x != 0.0)));
        assert!(bytes.images.iter().all(|i| !i.is_empty()));
    }

    #[test]
    fn a_modulation_of_another_shape_is_refused_plainly() {
        let a = Assembler::new(&mark3()).unwrap();
        let m = Modulation::zeros(crate::layout::mark1().geometry).unwrap();
        let err = a.assemble::<u8>(&m).unwrap_err().to_string();
        assert!(err.contains("64 hololines (the layout has 440)") && err.contains("242 emitters"), "{err}");
    }

    #[test]
    fn layouts_whose_basis_does_not_fit_are_refused_with_reasons() {
        let mut l = mark1();
        l.fringe.as_mut().unwrap().carrier_cycles_per_sample = vec![0.1];
        let p = problems(&l).join("; ");
        assert!(p.contains("between 0 and 0.5") && p.contains("445 nm"), "{p}");
        let mut l = mark3();
        l.geometry.emitter_z_m *= 1.01;
        let p = problems(&l).join("; ");
        assert!(p.contains("view 0 of the chirp points at"), "{p}");
        let mut l = mark1_hogel();
        l.geometry.emitter_z_m = 0.004;
        assert!(problems(&l).join("; ").contains("hologram plane"));
        let mut l = mark3();
        l.geometry.emitters = 338;
        assert!(problems(&l).join("; ").contains("338 emitters do not fit"), "{:?}", problems(&l));
    }
}
