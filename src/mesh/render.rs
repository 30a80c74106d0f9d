//! Rendering a placed scene into modulation: the options, and the driver
//! that runs one engine (the fast EPI rasteriser, `epi.rs`, or the
//! reference ray caster, [`super::trace`]) over every hololine of a frame.
//! The rays both engines sample, and what they share, are in `rays.rs`
//! ([`Supersample`], [`Rays`], [`RenderStats`] are handed on here).
//!
//! A ray's visible point is the first surface met walking back from the
//! viewer line along it (nearest the viewer, in front of or behind the
//! emitter plane, never behind the viewer). The radiance stored is what
//! that point sends toward the viewer.
//!
//! The lights are the scene's own unless the options say otherwise
//! ([`RenderOptions::lighting_for`]).

use rayon::prelude::*;

use super::rays::{HololineRenderer, Shading};
pub use super::rays::{Rays, RenderStats, Supersample};
use super::shade::Lighting;
use super::Scene;
use crate::error::{Error, Result};
use crate::geometry::{channel_weights, Geometry};
use crate::modulation::{Band, Modulation};
use crate::progress::{Progress, Steps};

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
    render_rows(scene, options, progress, geometry, 0..geometry.hololines, frame.samples_mut())
}

/// [`render_into`] a band of a frame's hololines (emitter rows): exactly
/// the samples the whole frame's render has there, so a frame far larger
/// than memory is rendered and written band by band.
pub fn render_band_into(
    scene: &Scene,
    options: &RenderOptions,
    progress: &dyn Progress,
    band: &mut Band,
) -> Result<RenderStats> {
    let (geometry, rows) = (band.geometry().clone(), band.hololines());
    render_rows(scene, options, progress, &geometry, rows, band.samples_mut())
}

/// Rows `band` of a frame of `geometry`, into their `samples`.
fn render_rows(
    scene: &Scene,
    options: &RenderOptions,
    progress: &dyn Progress,
    geometry: &Geometry,
    band: std::ops::Range<usize>,
    samples: &mut [f32],
) -> Result<RenderStats> {
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
    let stats = match options.engine {
        Engine::Fast => run(&super::epi::EpiRenderer::new(shading), &rays, geometry, band, samples, progress),
        Engine::Reference => run(&super::trace::TraceRenderer::new(shading), &rays, geometry, band, samples, progress),
    };
    if progress.cancelled() {
        return Err(Error::Cancelled);
    }
    Ok(stats)
}

/// Every hololine of `frame` from `engine`, drawing the planes of `rays`
/// ([`Rays::plane`]): a sample is the mean over its hololine's
/// sub-hololines and, for full parallax, its vertical view's sub-views.
fn run(
    engine: &dyn HololineRenderer,
    rays: &Rays,
    g: &Geometry,
    band: std::ops::Range<usize>,
    samples: &mut [f32],
    progress: &dyn Progress,
) -> RenderStats {
    let (h, e, v, c, w_count) = (band.len(), g.emitters, g.views.count, g.channels.len(), g.vertical_view_count());
    let (per_hololine, n) = (rays.supersample.hololine, rays.sub_hololines());
    // Sub-views per vertical view: the plane families of one vertical view.
    let per_vertical = rays.plane_families() / w_count;
    // A frame's hololines are one phase, whether rendered whole or by bands.
    let steps = match band.start {
        0 => Steps::begin(progress, "hololines", g.hololines),
        done => Steps::continuing(progress, done),
    };
    // Each hololine's rows, one per channel: the samples are (C, H, E × V·W)
    // over the band's H rows. The engines write straight into them when a
    // sample is one plane's.
    let mut rows: Vec<Vec<&mut [f32]>> = (0..h).map(|_| Vec::with_capacity(c)).collect();
    for (i, row) in samples.chunks_exact_mut(e * v * w_count).enumerate() {
        rows[i % h].push(row);
    }
    rows.into_par_iter()
        .enumerate()
        .map(|(i, mut rows)| {
            let j = band.start + i;
            // A cancelled render skips what is left; its caller returns
            // `Error::Cancelled` and the frame is never written.
            if steps.cancelled() {
                return RenderStats::default();
            }
            let stats = if per_hololine * per_vertical == 1 && w_count == 1 {
                engine.render_hololine(j, &mut rows)
            } else {
                // Each plane into a scratch row, the mean of a vertical
                // view's planes into `mean`, and that into its place among
                // each emitter's views (`w·V + h`).
                let mut stats = RenderStats::default();
                let mut scratch: Vec<Vec<f32>> = (0..c).map(|_| vec![0.0; e * v]).collect();
                let mut mean: Vec<Vec<f32>> = scratch.clone();
                let share = 1.0 / (per_hololine * per_vertical) as f32;
                for w in 0..w_count {
                    if per_hololine * per_vertical == 1 {
                        // One plane a sample: drawn straight into `mean`.
                        let mut sub: Vec<&mut [f32]> = mean.iter_mut().map(|r| r.as_mut_slice()).collect();
                        stats += engine.render_hololine(w * n + j, &mut sub);
                    } else {
                        mean.iter_mut().for_each(|r| r.fill(0.0));
                        for u in 0..per_vertical {
                            for t in 0..per_hololine {
                                let plane = (w * per_vertical + u) * n + j * per_hololine + t;
                                let mut sub: Vec<&mut [f32]> = scratch.iter_mut().map(|r| r.as_mut_slice()).collect();
                                stats += engine.render_hololine(plane, &mut sub);
                                for (m, sub) in mean.iter_mut().zip(&scratch) {
                                    m.iter_mut().zip(sub).for_each(|(a, b)| *a += share * b);
                                }
                            }
                        }
                    }
                    for (row, m) in rows.iter_mut().zip(&mean) {
                        for (emitter_views, m) in row.chunks_exact_mut(v * w_count).zip(m.chunks_exact(v)) {
                            emitter_views[w * v..(w + 1) * v].copy_from_slice(m);
                        }
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
