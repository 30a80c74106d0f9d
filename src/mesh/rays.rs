//! What the two mesh renderers share: the rays of a geometry at a
//! supersampling factor, what a renderer is given and fills in for one
//! hololine, and what it counts. The fast EPI rasteriser
//! ([`super::epi`]) and the reference ray caster ([`super::trace`]) build on
//! this; [`super::render`], above both, picks one and runs it over a frame.
//!
//! Ray `(j, e, v)` ([`Geometry::ray`], spec/holo-format.md §2) passes
//! through `(x_e, y_j, z_e)` with direction `d = (tan θ_v, k_j, 1)`, where
//! `k_j = (y_v − y_j)/(D − z_e)` takes it through the viewer line
//! (`y = y_v, z = D`). Supersampling averages `S_e × S_v` rays per sample:
//! emitters at `x_e + pitch·((i + ½)/S_e − ½)` across the emitter's
//! aperture, and views at fractional view indices `v + (i + ½)/S_v − ½`
//! mapped through the file's spacing rule ([`Geometry::ray_at`]), so the
//! sub-rays tile each view's angular interval.
//!
//! Every ray of one hololine lies in one plane, `y − y_j = k_j (z − z_e)`,
//! and the renderers draw a scene plane by plane ([`Rays::plane`]). A
//! full-parallax geometry (spec §8) has one such plane per hololine and
//! vertical view `w`: its rays have `dy/dz = tan φ_w` whatever their
//! horizontal view ([`Geometry::ray_at_views`]), so `(j, w)`'s rays lie in
//! `y − y_j = tan φ_w (z − z_e)`. Vertical views are supersampled as
//! horizontal ones are, `S_v` sub-views across each vertical view's
//! interval, and hololines by `S_h` sub-hololines in both kinds.

use super::shade::Lighting;
use super::Scene;
use crate::error::{Error, Result};
use crate::geometry::Geometry;

/// Sub-rays per sample: across each emitter's aperture and each view's
/// angular interval.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Supersample {
    /// Sub-rays across an emitter's pitch.
    pub emitter: usize,
    /// Sub-rays across a view's angular interval.
    pub view: usize,
    /// Sub-hololines across a hololine's height, averaged: antialiasing of
    /// edges near the horizontal (a hololine otherwise samples the scene on
    /// one line at its centre).
    pub hololine: usize,
}

impl Supersample {
    /// `emitter × view` sub-rays, one line per hololine.
    pub const fn new(emitter: usize, view: usize) -> Supersample {
        Supersample { emitter, view, hololine: 1 }
    }
}

impl Default for Supersample {
    /// 2 × 2: the supersampling table of BENCHMARKS.md shows it removes
    /// most of the aliasing of 1 × 1 at 2–3 times the cost. Geometry finer
    /// than the emitters (cooling fins, grilles, hair) still aliases into
    /// moiré at 2 × 2, and some factors beat with it (fins 0.25 mm apart on
    /// Mark III: 3 × 3 is worse than 2 × 2); such scenes want 4 × 4 or more.
    fn default() -> Self {
        Supersample::new(2, 2)
    }
}

/// Counters of the work a render did (the tests check culls with these).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Triangle-hololine pairs whose cut segment was rasterised.
    pub segments: u64,
    /// Triangle-hololine pairs dropped because the triangle faces away from every view.
    pub back_face_culled: u64,
    /// Sub-rays shaded.
    pub shaded: u64,
}

impl std::ops::AddAssign for RenderStats {
    fn add_assign(&mut self, o: Self) {
        self.segments += o.segments;
        self.back_face_culled += o.back_face_culled;
        self.shaded += o.shaded;
    }
}

/// The rays of a geometry at a supersampling factor, in the form both
/// engines use.
#[derive(Clone, Debug)]
pub struct Rays {
    /// `x` of every sub-emitter, `E·S_e` of them, increasing.
    pub sub_emitter_x_m: Vec<f64>,
    /// `tan θ` of every sub-view, `V·S_v` of them.
    pub sub_view_slope: Vec<f64>,
    /// `y` of every sub-hololine, `H·S_h` of them, evenly spaced downward:
    /// sub-hololine `j·S_h + t` is at `y_j + pitch · (½ − (t + ½)/S_h)`
    /// (`y_j` itself when `S_h` is 1).
    pub hololine_y_m: Vec<f64>,
    /// `k = dy/dz` per sub-hololine: toward the viewer line (horizontal
    /// parallax only; empty for full parallax, whose slopes are
    /// [`Rays::vertical_view_slope`]).
    pub hololine_slope: Vec<f64>,
    /// Full parallax: `tan φ` of every sub-vertical-view, `W·S_v` of them,
    /// at fractional vertical view indices `w + (i + ½)/S_v − ½`; empty for
    /// horizontal parallax.
    pub vertical_view_slope: Vec<f64>,
    /// `z_e`.
    pub emitter_z_m: f64,
    /// `D`.
    pub viewer_distance_m: f64,
    /// `y_v`.
    pub viewer_height_m: f64,
    /// The factor.
    pub supersample: Supersample,
}

impl Rays {
    /// The rays of `g` at factor `s`.
    pub fn new(g: &Geometry, s: Supersample) -> Result<Rays> {
        if [s.emitter, s.view, s.hololine].iter().any(|&k| k == 0 || k > 64) {
            return Err(Error::argument(
                "supersampling",
                format!(
                    "supersampling {}x{} with {} per hololine is out of range: each factor must be 1 to 64",
                    s.emitter, s.view, s.hololine
                ),
            ));
        }
        let problems = g.problems();
        if !problems.is_empty() {
            return Err(Error::argument("geometry", format!("invalid geometry: {}", problems.join("; "))));
        }
        let span = g.viewer_distance_m - g.emitter_z_m;
        if span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(Error::argument("geometry", "the viewer line must be in front of the emitter plane"));
        }
        let sub_emitter_x_m = (0..g.emitters * s.emitter)
            .map(|i| {
                let (e, k) = (i / s.emitter, i % s.emitter);
                g.emitter_x_m(e) + g.emitter_pitch_m * ((k as f64 + 0.5) / s.emitter as f64 - 0.5)
            })
            .collect();
        let sub_view_slope = (0..g.views.count * s.view)
            .map(|i| {
                let (v, k) = (i / s.view, i % s.view);
                g.ray_slope_x(v as f64 + (k as f64 + 0.5) / s.view as f64 - 0.5)
            })
            .collect();
        let hololine_y_m: Vec<f64> = (0..g.hololines * s.hololine)
            .map(|i| {
                let (j, t) = (i / s.hololine, i % s.hololine);
                g.hololine_y_m(j) + g.hololine_pitch_m * (0.5 - (t as f64 + 0.5) / s.hololine as f64)
            })
            .collect();
        let (hololine_slope, vertical_view_slope) = match &g.vertical_views {
            None => (hololine_y_m.iter().map(|&y| g.ray_slope_y(y)).collect(), Vec::new()),
            Some(vertical) => (
                Vec::new(),
                (0..vertical.count * s.view)
                    .map(|i| {
                        let (w, k) = (i / s.view, i % s.view);
                        vertical.theta_at(w as f64 + (k as f64 + 0.5) / s.view as f64 - 0.5).tan()
                    })
                    .collect(),
            ),
        };
        Ok(Rays {
            sub_emitter_x_m,
            sub_view_slope,
            hololine_y_m,
            hololine_slope,
            vertical_view_slope,
            emitter_z_m: g.emitter_z_m,
            viewer_distance_m: g.viewer_distance_m,
            viewer_height_m: g.viewer_height_m,
            supersample: s,
        })
    }
}

impl Rays {
    /// Sub-hololines, `H·S_h`.
    pub fn sub_hololines(&self) -> usize {
        self.hololine_y_m.len()
    }

    /// Families of parallel-or-concurrent planes: 1 for horizontal parallax
    /// (every hololine's plane passes through the viewer line), `W·S_v` for
    /// full parallax (one family of parallel planes per sub-vertical-view).
    pub fn plane_families(&self) -> usize {
        self.vertical_view_slope.len().max(1)
    }

    /// Planes the renderers draw: [`Rays::sub_hololines`] per family.
    pub fn planes(&self) -> usize {
        self.sub_hololines() * self.plane_families()
    }

    /// Plane `p`'s `(y, k)`: its rays leave the emitter plane at height `y`
    /// with `dy/dz = k`, so they lie in `y' − y = k (z − z_e)`. Plane
    /// `p = f · H·S_h + i` is sub-hololine `i` of family `f`.
    pub fn plane(&self, p: usize) -> (f64, f64) {
        let n = self.sub_hololines();
        let (f, i) = (p / n, p % n);
        match self.vertical_view_slope.get(f) {
            Some(&k) => (self.hololine_y_m[i], k),
            None => (self.hololine_y_m[i], self.hololine_slope[i]),
        }
    }
}

/// What an engine does for one plane of rays ([`Rays::plane`]): fill
/// `rows` completely (one per channel, each `E × V`, emitter by emitter,
/// horizontal views within) and count its work.
pub(crate) trait HololineRenderer: Sync {
    fn render_hololine(&self, plane: usize, rows: &mut [&mut [f32]]) -> RenderStats;
}

/// What both engines share.
pub(crate) struct Shading<'a> {
    pub scene: &'a Scene,
    pub lighting: &'a Lighting,
    pub weights: &'a [[f64; 3]],
    pub rays: &'a Rays,
    pub geometry: &'a Geometry,
}
