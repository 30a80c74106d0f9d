//! Rendering a placed scene into modulation: the rays of a geometry (with
//! supersampling), and the driver that runs an engine over every hololine.
//!
//! Ray `(j, e, v)` ([`Geometry::ray`], spec/holo-format.md §2) passes
//! through `(x_e, y_j, z_e)` with direction `d = (tan θ_v, k_j, 1)`, where
//! `k_j = (y_v − y_j)/(D − z_e)` takes it through the viewer line
//! (`y = y_v, z = D`). Its visible point is
//! the first surface met walking back from the viewer line along `−d`
//! (nearest the viewer, in front of or behind the emitter plane, never behind
//! the viewer). The radiance stored is what that point sends along `d`.
//!
//! Supersampling averages `S_e × S_v` rays per sample: emitters at
//! `x_e + pitch·((i + ½)/S_e − ½)` across the emitter's aperture, and views
//! at fractional view indices `v + (i + ½)/S_v − ½` mapped through the
//! file's spacing rule ([`Geometry::ray_at`]), so the sub-rays tile each
//! view's angular interval.
//!
//! The lights are the scene's own unless the options say otherwise
//! ([`RenderOptions::lighting_for`]).

use rayon::prelude::*;

use super::shade::Lighting;
use super::Scene;
use crate::geometry::{channel_weights, Geometry};
use crate::progress::{Progress, Steps};
use crate::{Error, Modulation, Result};

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

/// Which renderer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Engine {
    /// The per-hololine epipolar-plane rasteriser (`epi.rs`).
    #[default]
    Fast,
    /// One ray per sub-ray through a BVH ([`super::trace`]).
    Reference,
}

impl Engine {
    /// Every engine.
    pub const ALL: [Engine; 2] = [Engine::Fast, Engine::Reference];

    /// Its name, as `holo.convert.engine` stores it.
    pub fn name(self) -> &'static str {
        match self {
            Engine::Fast => "fast",
            Engine::Reference => "reference",
        }
    }
}

/// Everything a render needs besides the scene and geometry.
///
/// The lights a render uses are decided in one place,
/// [`RenderOptions::lighting_for`]: by default the scene's own lights, or
/// [`Lighting::default_lights`] when the scene has none.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Sub-rays per sample.
    pub supersample: Supersample,
    /// The specular lobe, and lights added after the scene's own.
    pub lighting: Lighting,
    /// Light with the scene's own lights ([`Scene::lights`]), before
    /// `lighting.lights`.
    pub scene_lights: bool,
    /// When the scene's lights (if used) and `lighting.lights` are none at
    /// all, light with [`Lighting::default_lights`]; when false, such a
    /// render shows emission and pre-lit colours only.
    pub default_lights: bool,
    /// Which renderer.
    pub engine: Engine,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            supersample: Supersample::default(),
            lighting: Lighting { lights: Vec::new(), model: Default::default() },
            scene_lights: true,
            default_lights: true,
            engine: Engine::Fast,
        }
    }
}

impl RenderOptions {
    /// Options that light every scene with exactly `lighting`: not the
    /// scene's own lights, and no default lights when it has none.
    pub fn lit_exactly(lighting: Lighting) -> RenderOptions {
        RenderOptions { lighting, scene_lights: false, default_lights: false, ..RenderOptions::default() }
    }

    /// The lights (and lobe) a render of `scene` with these options uses:
    /// the scene's own lights when `scene_lights`, then `lighting.lights`,
    /// and the default lights when that makes none and `default_lights`.
    /// A material's light indices ([`super::Material::lights`]) count in
    /// this list.
    pub fn lighting_for(&self, scene: &Scene) -> Lighting {
        let mut lights = if self.scene_lights { scene.lights.clone() } else { Vec::new() };
        lights.extend(self.lighting.lights.iter().cloned());
        if lights.is_empty() && self.default_lights {
            lights = Lighting::default_lights();
        }
        Lighting { lights, model: self.lighting.model }
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
    /// `k = dy/dz` per sub-hololine.
    pub hololine_slope: Vec<f64>,
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
        let hololine_slope = hololine_y_m.iter().map(|&y| g.ray_slope_y(y)).collect();
        Ok(Rays {
            sub_emitter_x_m,
            sub_view_slope,
            hololine_y_m,
            hololine_slope,
            emitter_z_m: g.emitter_z_m,
            viewer_distance_m: g.viewer_distance_m,
            viewer_height_m: g.viewer_height_m,
            supersample: s,
        })
    }
}

/// What an engine does for one hololine: fill `rows` completely (one per
/// channel, each `E × V` in the modulation's order) and count its work.
pub(crate) trait HololineRenderer: Sync {
    fn render_hololine(&self, j: usize, rows: &mut [&mut [f32]]) -> RenderStats;
}

/// Render a placed scene (display metres) into one frame of modulation,
/// reporting the phase `hololines` to `progress`.
pub fn render(
    scene: &Scene,
    geometry: &Geometry,
    options: &RenderOptions,
    progress: &dyn Progress,
) -> Result<(Modulation, RenderStats)> {
    let mut frame = Modulation::zeros(geometry.clone())?;
    let stats = render_into(scene, options, progress, &mut frame)?;
    Ok((frame, stats))
}

/// [`render`] into an existing frame of the geometry wanted (every sample
/// is overwritten): a movie reuses one frame's memory for all its frames.
pub fn render_into(
    scene: &Scene,
    options: &RenderOptions,
    progress: &dyn Progress,
    frame: &mut Modulation,
) -> Result<RenderStats> {
    let geometry = &frame.geometry().clone();
    let rays = Rays::new(geometry, options.supersample)?;
    if let Some(problem) = scene.problem() {
        return Err(Error::scene(&scene.source, problem));
    }
    let lighting = options.lighting_for(scene);
    if let Some(bad) = lighting.lights.iter().find(|l| !light_is_finite(l)) {
        return Err(Error::argument("lights", format!("a light is not finite or has a negative brightness: {bad:?}")));
    }
    if let Some(problem) = lighting.problem_with(scene) {
        return Err(Error::scene(&scene.source, problem));
    }
    let names: Vec<&str> = geometry.channels.iter().map(|c| c.name.as_str()).collect();
    let weights = channel_weights(&names);
    let shading = Shading { scene, lighting: &lighting, weights: &weights, rays: &rays, geometry };
    let per_hololine = options.supersample.hololine;
    let stats = match options.engine {
        Engine::Fast => run(&super::epi::EpiRenderer::new(shading), per_hololine, frame, progress),
        Engine::Reference => run(&super::trace::TraceRenderer::new(shading), per_hololine, frame, progress),
    };
    if progress.cancelled() {
        return Err(Error::Cancelled);
    }
    Ok(stats)
}

/// What both engines share.
pub(crate) struct Shading<'a> {
    pub scene: &'a Scene,
    pub lighting: &'a Lighting,
    pub weights: &'a [[f64; 3]],
    pub rays: &'a Rays,
    pub geometry: &'a Geometry,
}

/// Every hololine of `frame` from `engine`, whose rays have `per_hololine`
/// sub-hololines per hololine ([`Rays::hololine_y_m`]): their mean.
fn run(
    engine: &dyn HololineRenderer,
    per_hololine: usize,
    frame: &mut Modulation,
    progress: &dyn Progress,
) -> RenderStats {
    let g = frame.geometry();
    let (h, e, v, c) = (g.hololines, g.emitters, g.views.count, g.channels.len());
    let steps = Steps::begin(progress, "hololines", h);
    // Each hololine's rows, one per channel: the samples are (C, H, E × V).
    // The engines write straight into them.
    let mut rows: Vec<Vec<&mut [f32]>> = (0..h).map(|_| Vec::with_capacity(c)).collect();
    for (i, row) in frame.samples_mut().chunks_exact_mut(e * v).enumerate() {
        rows[i % h].push(row);
    }
    rows.into_par_iter()
        .enumerate()
        .map(|(j, mut rows)| {
            // A cancelled render skips what is left; its caller returns
            // `Error::Cancelled` and the frame is never written.
            if steps.cancelled() {
                return RenderStats::default();
            }
            let stats = if per_hololine == 1 {
                engine.render_hololine(j, &mut rows)
            } else {
                // Each sub-hololine into a scratch row, their mean into the frame.
                let mut stats = RenderStats::default();
                let mut scratch: Vec<Vec<f32>> = rows.iter().map(|r| vec![0.0; r.len()]).collect();
                rows.iter_mut().for_each(|r| r.fill(0.0));
                let share = 1.0 / per_hololine as f32;
                for t in 0..per_hololine {
                    let mut sub: Vec<&mut [f32]> = scratch.iter_mut().map(|r| r.as_mut_slice()).collect();
                    stats += engine.render_hololine(j * per_hololine + t, &mut sub);
                    for (row, sub) in rows.iter_mut().zip(&scratch) {
                        row.iter_mut().zip(sub).for_each(|(a, b)| *a += share * b);
                    }
                }
                stats
            };
            steps.step();
            stats
        })
        .reduce(RenderStats::default, |mut a, b| {
            a += b;
            a
        })
}

pub(crate) fn light_is_finite(l: &super::Light) -> bool {
    use super::Light;
    let ok3 = |v: &[f32; 3]| v.iter().all(|x| x.is_finite() && *x >= 0.0);
    match l {
        Light::Point { position, intensity, .. } => position.iter().all(|x| x.is_finite()) && ok3(intensity),
        Light::Directional { direction, irradiance, .. } => direction.iter().all(|x| x.is_finite()) && ok3(irradiance),
        Light::Ambient { radiance } => ok3(radiance),
    }
}
