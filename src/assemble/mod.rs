//! Fringe assembly: from a stored modulation to the images a display's frame
//! buffer takes.
//!
//! [`Assembler`] drives a layout's basis ([`zone::ZoneAssembler`] for zoned
//! chirps) over every hololine and colour channel, and deals the resulting
//! signals into the frame buffer ([`crate::layout::FrameBuffer`]): one task
//! per frame-buffer line, each writing only its own rows, so the bytes do not
//! depend on the thread count. [`Assembler::unpack`] is the inverse, used to
//! check and view fringes already written.

pub mod chirp;
pub mod output;
pub mod zone;

use rayon::prelude::*;

use crate::layout::{FrameBuffer, Layout, Quantization};
use crate::{Error, Modulation, Result};
pub use zone::{mark3_assembler, ZoneAssembler, ZoneSignals};

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

/// A frame-buffer sample type: 8-bit codes, or the float signal itself.
pub trait FringeSample: Copy + Send + Sync + 'static {
    /// The stored value of signal `x`, and whether it was clipped.
    fn encode(x: f32, q: &Quantization) -> (Self, bool);
    /// The signal a stored value stands for.
    fn decode(self, q: &Quantization) -> f32;
    /// The value of pixels no signal reaches.
    fn blank(q: &Quantization) -> Self;
}

impl FringeSample for u8 {
    #[inline(always)]
    fn encode(x: f32, q: &Quantization) -> (u8, bool) {
        let code = (q.offset as f32 + q.gain as f32 * x).round();
        (code.clamp(0.0, 255.0) as u8, !(0.0..=255.0).contains(&code))
    }
    fn decode(self, q: &Quantization) -> f32 {
        ((f64::from(self) - q.offset) / q.gain) as f32
    }
    fn blank(q: &Quantization) -> u8 {
        q.offset.round().clamp(0.0, 255.0) as u8
    }
}

impl FringeSample for f32 {
    #[inline(always)]
    fn encode(x: f32, _: &Quantization) -> (f32, bool) {
        (x, false)
    }
    fn decode(self, _: &Quantization) -> f32 {
        self
    }
    fn blank(_: &Quantization) -> f32 {
        0.0
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
    /// One basis per colour channel (the wavelength differs).
    colours: Vec<ZoneAssembler>,
}

impl Assembler {
    /// An assembler for `layout`, which must have a fringe side.
    pub fn new(layout: &Layout) -> Result<Self> {
        let problems = layout.problems();
        if !problems.is_empty() {
            return Err(Error::Usage(format!("layout {}: {}", layout.name, problems.join("; "))));
        }
        let colours =
            (0..layout.geometry.channels.len()).map(|c| zone::for_layout(layout, c)).collect::<Result<Vec<_>>>()?;
        Ok(Assembler { layout: layout.clone(), colours })
    }

    /// The layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The basis of colour channel `c`.
    pub fn colour(&self, c: usize) -> &ZoneAssembler {
        &self.colours[c]
    }

    fn frame_buffer(&self) -> &FrameBuffer {
        &self.layout.fringe.as_ref().expect("checked in new").frame_buffer
    }
    fn quantization(&self) -> &Quantization {
        &self.layout.fringe.as_ref().expect("checked in new").quantization
    }
    fn signals_per_colour(&self) -> usize {
        2 * self.colours[0].basis().zones
    }

    /// `Ok` when `m` has the geometry this layout expects; otherwise an error
    /// that says plainly which numbers differ.
    pub fn check_geometry(&self, m: &Modulation) -> Result<()> {
        let (got, want) = (m.geometry(), &self.layout.geometry);
        let mut differences = Vec::new();
        let mut counts = |what: &str, a: usize, b: usize| {
            if a != b {
                differences.push(format!("{a} {what} (the layout has {b})"));
            }
        };
        counts("hololines", got.hololines, want.hololines);
        counts("emitters", got.emitters, want.emitters);
        counts("views", got.views.count, want.views.count);
        let names = |g: &crate::Geometry| g.channels.iter().map(|c| c.name.clone()).collect::<Vec<_>>().join(",");
        if names(got) != names(want) {
            differences.push(format!("channels {} (the layout has {})", names(got), names(want)));
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
        Err(Error::Usage(format!(
            "the modulation does not fit layout {}: it has {}. Resample it to the layout first \
             (for example export-views, then import-views --geometry {})",
            self.layout.name,
            differences.join(", "),
            self.layout.name
        )))
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
    pub fn assemble_into<T: FringeSample>(&self, m: &Modulation, out: &mut FrameImages<T>) -> Result<FrameStats> {
        self.check_geometry(m)?;
        if let Some((c, j, e, v, value, why)) = m.first_bad_sample() {
            return Err(Error::BadSample {
                path: "modulation".into(),
                frame: 0,
                hololine: j,
                emitter: e,
                view: v,
                channel: m.geometry().channels[c].name.clone(),
                value,
                why,
            });
        }
        let fb = self.frame_buffer();
        if (out.width, out.height, out.components, out.images.len())
            != (fb.width, fb.height, fb.components, fb.image_names.len())
        {
            *out = self.blank_images();
        }
        let q = *self.quantization();
        let hololines = m.geometry().hololines;
        let per_colour = self.signals_per_colour();
        let signals = per_colour * self.colours.len();
        let samples = self.colours[0].samples_per_hololine();
        let lines = fb.lines(hololines, signals);
        let row_len = fb.width * fb.components;

        // Split every image into the disjoint row blocks of each line.
        let mut blocks: Vec<Vec<&mut [T]>> = (0..lines).map(|_| Vec::new()).collect();
        for image in out.images.iter_mut() {
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

        let stats = blocks
            .into_par_iter()
            .enumerate()
            .map(|(line, mut images)| {
                let mut stats = FrameStats::default();
                let mut scratch_i = vec![0f32; samples];
                let mut scratch_q = vec![0f32; samples];
                let mut cached: Option<(usize, usize, usize)> = None;
                let mut weights: Option<(usize, usize, Option<Vec<f32>>)> = None;
                for (c, slot) in fb.channels.iter().enumerate() {
                    let k = line * fb.channels.len() + c;
                    if k >= hololines * signals {
                        break;
                    }
                    let (j, s) = (k / signals, k % signals);
                    let (colour, zone, sine) = (s / per_colour, (s % per_colour) / 2, s % 2 == 1);
                    if cached != Some((j, colour, zone)) {
                        if !matches!(&weights, Some((wj, wc, _)) if (*wj, *wc) == (j, colour)) {
                            weights = Some((j, colour, ZoneAssembler::weights(m.hololine(colour, j))));
                        }
                        match &weights.as_ref().expect("just set").2 {
                            Some(w) => self.colours[colour].zone_row(w, zone, &mut scratch_i, &mut scratch_q),
                            None => {
                                scratch_i.fill(0.0);
                                scratch_q.fill(0.0);
                                stats.dark_hololines += 1;
                            }
                        }
                        cached = Some((j, colour, zone));
                    }
                    let signal = if sine { &scratch_q } else { &scratch_i };
                    let reversed = fb.reverse_odd_lines && line % 2 == 1;
                    stats.clipped += write_signal(fb, &q, signal, reversed, images[slot.image], slot.component);
                }
                stats
            })
            .reduce(FrameStats::default, |a, b| FrameStats {
                clipped: a.clipped + b.clipped,
                dark_hololines: a.dark_hololines + b.dark_hololines,
            });
        Ok(stats)
    }

    /// Assemble one frame into new images.
    pub fn assemble<T: FringeSample>(&self, m: &Modulation) -> Result<(FrameImages<T>, FrameStats)> {
        let mut out = self.blank_images();
        let stats = self.assemble_into(m, &mut out)?;
        Ok((out, stats))
    }

    /// The signals held in frame-buffer images: per colour channel, every
    /// zone's I/Q signal of every hololine, decoded to floats. Samples that
    /// fell in the horizontal blanking come back as zero: they never reach
    /// the display.
    pub fn unpack<T: FringeSample>(&self, images: &FrameImages<T>, hololines: usize) -> Result<Vec<ZoneSignals>> {
        let fb = self.frame_buffer();
        if (images.width, images.height, images.components, images.images.len())
            != (fb.width, fb.height, fb.components, fb.image_names.len())
        {
            return Err(Error::Usage(format!(
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
            )));
        }
        let q = self.quantization();
        let per_colour = self.signals_per_colour();
        let signals = per_colour * self.colours.len();
        let samples = self.colours[0].samples_per_hololine();
        let zones = per_colour / 2;
        let mut out: Vec<ZoneSignals> = (0..self.colours.len())
            .map(|_| ZoneSignals {
                zones,
                hololines,
                samples,
                i: vec![0.0; zones * hololines * samples],
                q: vec![0.0; zones * hololines * samples],
            })
            .collect();
        for j in 0..hololines {
            for s in 0..signals {
                let (colour, zone, sine) = (s / per_colour, (s % per_colour) / 2, s % 2 == 1);
                let target = &mut out[colour];
                let row = (zone * hololines + j) * samples;
                let dest = if sine { &mut target.q[row..row + samples] } else { &mut target.i[row..row + samples] };
                for (n, d) in dest.iter_mut().enumerate() {
                    if let Some(p) = fb.place(j, s, n, signals, samples) {
                        let at = (p.row * images.width + p.column) * images.components + p.component;
                        *d = images.images[p.image][at].decode(q);
                    }
                }
            }
        }
        Ok(out)
    }
}

/// Write one signal into its component of a line's row block; returns the
/// number of clipped samples.
fn write_signal<T: FringeSample>(
    fb: &FrameBuffer,
    q: &Quantization,
    signal: &[f32],
    reversed: bool,
    block: &mut [T],
    component: usize,
) -> u64 {
    let mut clipped = 0;
    let samples = signal.len();
    for r in 0..fb.rows_per_hololine {
        let row = &mut block[r * fb.width * fb.components..(r + 1) * fb.width * fb.components];
        let first = r * fb.line_samples;
        for (x, px) in row.chunks_exact_mut(fb.components).enumerate() {
            let sent = first + x;
            let n = if reversed { samples - 1 - sent } else { sent };
            let (v, clip) = T::encode(signal[n], q);
            px[component] = v;
            clipped += u64::from(clip);
        }
    }
    clipped
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::mark3;
    use rand::{Rng, SeedableRng};

    fn random(hololines: usize, seed: u64) -> Modulation {
        let mut g = mark3().geometry;
        g.hololines = hololines;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        Modulation::from_fn(g, |_, _, _, _| rng.gen_range(0.0..1.0)).unwrap()
    }

    #[test]
    fn mark3_channels_carry_the_right_zone_and_component() {
        // Every (head, colour) of the frame buffer, read back through the
        // paper's own words, holds the matching zone signal of the reference.
        let mut layout = mark3();
        layout.geometry.hololines = 2;
        let a = Assembler::new(&layout).unwrap();
        let m = random(2, 7);
        let (images, _) = a.assemble::<f32>(&m).unwrap();
        let reference = a.colour(0).assemble_reference(&m, 0).unwrap();
        // (head, component, zone, sine): "Head 1 RG channels produce the
        // sine/cosine pair of zone 1. Head 1 B channel produces the sine of
        // zone 2. Head 2 RG … zone 3. Head 2 B channel produces cosine of zone 2."
        let paper =
            [(0, 0, 0, true), (0, 1, 0, false), (0, 2, 1, true), (1, 0, 2, true), (1, 1, 2, false), (1, 2, 1, false)];
        for (head, component, zone, sine) in paper {
            for j in 0..2 {
                for n in [0usize, 1, 4079, 4096, 10000, 24575 - 16] {
                    let (row, column) = (6 * j + n / 4096, n % 4096);
                    let got = images.images[head][(row * 4080 + column) * 3 + component];
                    let at = (zone * 2 + j) * 24576 + n;
                    let want = if sine { reference.q[at] } else { reference.i[at] };
                    assert!((got - want).abs() < 2e-6, "head {head} comp {component} j {j} n {n}: {got} vs {want}");
                }
            }
        }
        // Rows below the hololines stay blank.
        assert!(images.images[0][12 * 4080 * 3..].iter().all(|x| *x == 0.0));
    }

    #[test]
    fn unpack_inverts_assembly_except_for_blanking_and_quantization() {
        let mut layout = mark3();
        layout.geometry.hololines = 3;
        let a = Assembler::new(&layout).unwrap();
        let m = random(3, 8);
        let direct = a.colour(0).assemble(&m, 0).unwrap();
        let (floats, _) = a.assemble::<f32>(&m).unwrap();
        let (bytes, stats) = a.assemble::<u8>(&m).unwrap();
        assert_eq!(stats.clipped, 0);
        let from_floats = a.unpack(&floats, 3).unwrap().remove(0);
        let from_bytes = a.unpack(&bytes, 3).unwrap().remove(0);
        for idx in 0..direct.i.len() {
            let n = idx % 24576;
            let blank = n % 4096 >= 4080;
            let want = if blank { 0.0 } else { direct.i[idx] };
            assert_eq!(from_floats.i[idx], want, "sample {idx}");
            assert!((from_bytes.i[idx] - want).abs() <= 0.5 / 127.0 + 1e-6, "sample {idx}");
        }
    }

    #[test]
    fn bytes_do_not_depend_on_the_thread_count() {
        let mut layout = mark3();
        layout.geometry.hololines = 8;
        let a = Assembler::new(&layout).unwrap();
        let m = random(8, 9);
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let (single, _) = one.install(|| a.assemble::<u8>(&m)).unwrap();
        let (many, _) = a.assemble::<u8>(&m).unwrap();
        assert!(single == many);
    }

    #[test]
    fn nan_and_inf_are_errors_naming_hololine_emitter_and_view() {
        let mut layout = mark3();
        layout.geometry.hololines = 4;
        let a = Assembler::new(&layout).unwrap();
        for bad in [f32::NAN, f32::INFINITY, -1.0] {
            let mut m = random(4, 10);
            m.set(0, 3, 200, 17, bad);
            let err = a.assemble::<u8>(&m).unwrap_err().to_string();
            assert!(err.contains("hololine 3, emitter 200, view 17"), "{err}");
        }
    }

    #[test]
    fn a_modulation_of_another_shape_is_refused_plainly() {
        let a = Assembler::new(&mark3()).unwrap();
        let m = Modulation::zeros(crate::layout::mark1().geometry).unwrap();
        let err = a.assemble::<u8>(&m).unwrap_err().to_string();
        assert!(err.contains("64 hololines (the layout has 440)") && err.contains("256 emitters"), "{err}");
    }
}
