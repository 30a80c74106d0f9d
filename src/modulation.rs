//! The modulation texture of one frame in memory: f32 linear radiance, kept
//! channel by channel in the order (hololine, emitter, view), which is the
//! order the assembler walks it in. A full-parallax frame (spec §8) keeps
//! each emitter's `V × W` views together the same way, vertical view major
//! ([`Geometry::view_index`]): "hololine" is then an emitter row, and "view"
//! an index among an emitter's views.

use crate::error::{Error, Result};
use crate::geometry::{Geometry, Parallax};

/// One frame of modulation: `samples[((c·H + j)·E + e)·V + v]`, where `V`
/// is [`Geometry::views_per_emitter`].
#[derive(Clone, Debug, PartialEq)]
pub struct Modulation {
    geometry: Geometry,
    samples: Vec<f32>,
}

impl Modulation {
    /// All-zero modulation for a geometry (which must be valid).
    pub fn zeros(geometry: Geometry) -> Result<Self> {
        check_geometry(&geometry)?;
        let n = usize::try_from(geometry.samples_per_frame()).map_err(|_| too_big(&geometry))?;
        Ok(Modulation { samples: crate::memory::zeroed_f32(n), geometry })
    }

    /// Wrap samples in (channel, hololine, emitter, view) order.
    pub fn from_samples(geometry: Geometry, samples: Vec<f32>) -> Result<Self> {
        check_geometry(&geometry)?;
        if samples.len() as u64 != geometry.samples_per_frame() {
            return Err(Error::argument(
                "samples",
                format!("{} samples given for a geometry of {} samples", samples.len(), geometry.samples_per_frame()),
            ));
        }
        Ok(Modulation { geometry, samples })
    }

    /// Fill every sample from a function of (channel, hololine, emitter, view).
    pub fn from_fn(geometry: Geometry, mut f: impl FnMut(usize, usize, usize, usize) -> f32) -> Result<Self> {
        let mut m = Self::zeros(geometry)?;
        let (h, e, v) = (m.geometry.hololines, m.geometry.emitters, m.geometry.views_per_emitter());
        let mut i = 0;
        for c in 0..m.geometry.channels.len() {
            for j in 0..h {
                for k in 0..e {
                    for w in 0..v {
                        m.samples[i] = f(c, j, k, w);
                        i += 1;
                    }
                }
            }
        }
        Ok(m)
    }

    /// The geometry.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }
    /// All samples, (channel, hololine, emitter, view) order.
    pub fn samples(&self) -> &[f32] {
        &self.samples
    }
    /// All samples, mutable.
    pub fn samples_mut(&mut self) -> &mut [f32] {
        &mut self.samples
    }
    /// Give up the samples.
    pub fn into_samples(self) -> Vec<f32> {
        self.samples
    }

    /// Linear index of a sample.
    #[inline]
    pub fn index(&self, channel: usize, hololine: usize, emitter: usize, view: usize) -> usize {
        let g = &self.geometry;
        ((channel * g.hololines + hololine) * g.emitters + emitter) * g.views_per_emitter() + view
    }
    /// One sample.
    #[inline]
    pub fn get(&self, channel: usize, hololine: usize, emitter: usize, view: usize) -> f32 {
        self.samples[self.index(channel, hololine, emitter, view)]
    }
    /// Set one sample.
    #[inline]
    pub fn set(&mut self, channel: usize, hololine: usize, emitter: usize, view: usize, value: f32) {
        let i = self.index(channel, hololine, emitter, view);
        self.samples[i] = value;
    }
    /// The views of one emitter on one hololine.
    pub fn views_of(&self, channel: usize, hololine: usize, emitter: usize) -> &[f32] {
        let i = self.index(channel, hololine, emitter, 0);
        &self.samples[i..i + self.geometry.views_per_emitter()]
    }
    /// All (emitter, view) samples of one hololine: its epipolar-plane image.
    pub fn hololine(&self, channel: usize, hololine: usize) -> &[f32] {
        let i = self.index(channel, hololine, 0, 0);
        &self.samples[i..i + self.geometry.emitters * self.geometry.views_per_emitter()]
    }

    /// Smallest and largest sample (0, 0 for an empty texture).
    pub fn value_range(&self) -> (f32, f32) {
        self.samples
            .iter()
            .fold(None, |acc: Option<(f32, f32)>, &x| Some(acc.map_or((x, x), |(lo, hi)| (lo.min(x), hi.max(x)))))
            .unwrap_or((0.0, 0.0))
    }

    /// The first sample that is NaN, infinite or negative, as
    /// (channel, hololine, emitter, view, value, why).
    pub fn first_bad_sample(&self) -> Option<(usize, usize, usize, usize, f32, &'static str)> {
        first_bad(&self.geometry, &self.samples, 0..self.geometry.hololines)
    }
}

/// The horizontal-parallax frame that a full-parallax frame `m` shows a
/// viewer on its viewer line (height `viewer_height_m` at
/// `viewer_distance_m`): for emitter row `j` at height `y_j`, the row of
/// views in the vertical direction toward the viewer line,
/// `φ_j = atan((y_v − y_j)/(D − z_e))` (the direction of every
/// horizontal-parallax ray of that row, [`Geometry::ray_slope_y`]), taken
/// linearly between the two nearest vertical views
/// ([`crate::geometry::Views::index_at`]). A row whose direction is more than
/// half a view beyond the first or last vertical view is black: the display
/// sends no light toward the viewer line there ([`rows_beyond_vertical_views`]).
/// The geometry is `m`'s without its vertical views; a horizontal-parallax
/// frame comes back as it is. A band of rows (a region read) is taken as
/// well: each row by its own height.
pub fn full_to_horizontal(m: &Modulation) -> Result<Modulation> {
    let g = m.geometry();
    if g.vertical_views.is_none() {
        return Ok(m.clone());
    }
    let horizontal = Geometry { parallax: Parallax::Horizontal, vertical_views: None, ..g.clone() };
    let mut out = Modulation::zeros(horizontal)?;
    let views = g.views.count;
    for j in 0..g.hololines {
        let Some(taps) = viewer_line_taps(g, j) else { continue };
        for c in 0..g.channels.len() {
            for e in 0..g.emitters {
                let from = m.views_of(c, j, e);
                let at = out.index(c, j, e, 0);
                for (h, sample) in out.samples[at..at + views].iter_mut().enumerate() {
                    *sample = taps.iter().map(|&(k, w)| w * from[g.view_index(h, k)]).sum();
                }
            }
        }
    }
    Ok(out)
}

/// The emitter rows of `g` (full parallax) whose direction toward the
/// viewer line is more than half a view beyond its vertical views: black in
/// [`full_to_horizontal`].
pub fn rows_beyond_vertical_views(g: &Geometry) -> Vec<usize> {
    match g.vertical_views {
        None => Vec::new(),
        Some(_) => (0..g.hololines).filter(|&j| viewer_line_taps(g, j).is_none()).collect(),
    }
}

/// The vertical views (index, weight) that row `j` of full-parallax `g`
/// sends toward the viewer line, or `None` beyond them.
fn viewer_line_taps(g: &Geometry, j: usize) -> Option<[(usize, f32); 2]> {
    let vertical = g.vertical_views.as_ref()?;
    let phi = g.ray_slope_y(g.hololine_y_m(j)).atan();
    crate::sampling::linear_taps(vertical.index_at(phi), vertical.count)
}

/// Some consecutive hololines of one frame, every channel: what a converter
/// fills when the frame is produced band by band (memory bounded by the band,
/// not the frame). Samples in (channel, hololine, emitter, view) order like
/// [`Modulation`], hololines counted from the frame's first.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    geometry: Geometry,
    hololines: std::ops::Range<usize>,
    samples: Vec<f32>,
}

impl Band {
    /// All-zero band of `hololines` of a (valid) geometry.
    pub fn zeros(geometry: Geometry, hololines: std::ops::Range<usize>) -> Result<Self> {
        check_geometry(&geometry)?;
        if hololines.start >= hololines.end || hololines.end > geometry.hololines {
            return Err(Error::argument(
                "hololines",
                format!(
                    "hololines {}..{} are not a band of a geometry of {} hololines",
                    hololines.start, hololines.end, geometry.hololines
                ),
            ));
        }
        let per_line = geometry.emitters as u64 * geometry.views_per_emitter() as u64 * geometry.channels.len() as u64;
        let n = usize::try_from(per_line * hololines.len() as u64).map_err(|_| too_big(&geometry))?;
        Ok(Band { samples: vec![0.0; n], geometry, hololines })
    }

    /// The frame's geometry.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }
    /// The hololines this band holds.
    pub fn hololines(&self) -> std::ops::Range<usize> {
        self.hololines.clone()
    }
    /// All samples, (channel, hololine, emitter, view) order.
    pub fn samples(&self) -> &[f32] {
        &self.samples
    }
    /// All samples, mutable.
    pub fn samples_mut(&mut self) -> &mut [f32] {
        &mut self.samples
    }
    /// All (emitter, view) samples of one hololine (counted from the frame's first).
    pub fn hololine(&self, channel: usize, hololine: usize) -> &[f32] {
        let n = self.geometry.emitters * self.geometry.views_per_emitter();
        let i = (channel * self.hololines.len() + hololine - self.hololines.start) * n;
        &self.samples[i..i + n]
    }
    /// Its hololines copied from the same hololines of a whole frame of the
    /// same geometry.
    pub fn copy_rows_from(&mut self, frame: &Modulation) {
        let lines = self.hololines.len();
        let n = self.geometry.emitters * self.geometry.views_per_emitter();
        for c in 0..self.geometry.channels.len() {
            let from = frame.index(c, self.hololines.start, 0, 0);
            self.samples[c * lines * n..(c + 1) * lines * n].copy_from_slice(&frame.samples()[from..from + lines * n]);
        }
    }
    /// The first sample that is NaN, infinite or negative, as
    /// (channel, hololine, emitter, view, value, why); the hololine counted
    /// from the frame's first.
    pub fn first_bad_sample(&self) -> Option<(usize, usize, usize, usize, f32, &'static str)> {
        first_bad(&self.geometry, &self.samples, self.hololines.clone())
    }
    /// Work on the band as a whole frame, without copying: for renderers
    /// that fill whole frames (the band must hold every hololine).
    pub fn as_frame<R>(&mut self, f: impl FnOnce(&mut Modulation) -> R) -> Result<R> {
        self.check_whole()?;
        let samples = std::mem::take(&mut self.samples);
        let mut frame = Modulation::from_samples(self.geometry.clone(), samples)?;
        let result = f(&mut frame);
        self.samples = frame.into_samples();
        Ok(result)
    }

    fn check_whole(&self) -> Result<()> {
        if self.hololines != (0..self.geometry.hololines) {
            return Err(Error::argument(
                "band",
                format!(
                    "a band of hololines {}..{} is not a whole frame of {}",
                    self.hololines.start, self.hololines.end, self.geometry.hololines
                ),
            ));
        }
        Ok(())
    }

    /// The band as a frame, when it holds every hololine.
    pub fn into_modulation(self) -> Result<Modulation> {
        self.check_whole()?;
        Modulation::from_samples(self.geometry, self.samples)
    }
}

/// The first bad sample of `samples` laid out (channel, hololine, emitter,
/// view) over `hololines` of `g`.
fn first_bad(
    g: &Geometry,
    samples: &[f32],
    hololines: std::ops::Range<usize>,
) -> Option<(usize, usize, usize, usize, f32, &'static str)> {
    // A branch-free scan first (it vectorises; frames are tens of millions
    // of samples), then the search for the first offender.
    let good = |x: &f32| *x >= 0.0 && *x <= f32::MAX;
    let all_good = {
        use rayon::prelude::*;
        samples.par_chunks(1 << 16).all(|chunk| chunk.iter().fold(true, |ok, x| ok & good(x)))
    };
    if all_good {
        return None;
    }
    let i = samples.iter().position(|x| !good(x))?;
    let x = samples[i];
    let lines = hololines.len();
    let views = g.views_per_emitter();
    let v = i % views;
    let e = (i / views) % g.emitters;
    let j = hololines.start + (i / (views * g.emitters)) % lines;
    let c = i / (views * g.emitters * lines);
    let why = if x.is_nan() {
        "not a number"
    } else if x.is_infinite() {
        "infinite"
    } else {
        "negative (radiance cannot be)"
    };
    Some((c, j, e, v, x, why))
}

fn too_big(g: &Geometry) -> Error {
    Error::argument("geometry", format!("a frame of {} samples does not fit in memory", g.samples_per_frame()))
}

fn check_geometry(g: &Geometry) -> Result<()> {
    let problems = g.frame_problems();
    if problems.is_empty() {
        Ok(())
    } else {
        Err(Error::argument("geometry", format!("invalid geometry: {}", problems.join("; "))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_too_large_for_a_file_is_refused_before_it_is_allocated() {
        let mut g = crate::layout::mark3().geometry;
        g.emitters = 1 << 20;
        g.hololines = 1 << 20;
        let err = Modulation::zeros(g.clone()).unwrap_err().to_string();
        assert!(err.contains("samples") && err.contains("more than"), "{err}");
        // A product that would wrap around u64 saturates instead.
        g.views.count = usize::MAX / 2;
        assert_eq!(g.samples_per_frame(), u64::MAX);
        assert!(Modulation::zeros(g).is_err());
    }
}
