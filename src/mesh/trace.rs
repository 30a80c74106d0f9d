//! The reference renderer: every sub-ray is cast on its own through a BVH,
//! in f64, from the viewer line back along `−d`; the surfaces met that face
//! the viewer (or are double-sided) are shaded one after another, nearest
//! first, each weighted by its [`coverage`] and by what the ones in front let
//! through, until an opaque one ends the ray (`along_ray`). Obviously
//! correct and slow; the fast rasteriser (`epi.rs`) is tested against it.

use super::bvh::{Bvh, Triangle};
use super::rays::{HololineRenderer, RenderStats, Shading};
use super::shade::{coverage, radiance, Hit, Lighting};
use super::Scene;
use crate::geometry::Ray;
use crate::math::{add, dot, normalize, scale};

/// What a ray from `origin` along `dir` sees of `scene`: the radiance sent
/// back along it (toward `origin`; `view` is the unit vector that way) and
/// the ray parameter of the nearest
/// surface that covers any of it, or `None` when no surface does. The
/// surfaces `shown(triangle, geometric normal)` allows are met nearest
/// first; each adds its radiance × its [`coverage`] `α` × what the ones in
/// front let through, `Π (1 − α_k)`, and an opaque one (`α = 1`) ends the
/// ray (glTF 2.0 §3.9.4, `alphaMode`). A surface no further than `1e-12`
/// (in units of the ray parameter) behind the last is the same surface met
/// again (the shared edge of two triangles), not another.
pub(crate) fn along_ray(
    scene: &Scene,
    lighting: &Lighting,
    bvh: &Bvh,
    origin: [f64; 3],
    dir: [f64; 3],
    view: [f64; 3],
    shown: impl Fn(&Triangle, [f64; 3]) -> bool,
) -> Option<([f64; 3], f64)> {
    let (mut sum, mut through, mut first, mut t_min) = ([0.0; 3], 1.0, None, 0.0);
    while let Some(hit) = bvh.nearest(origin, dir, t_min, &shown) {
        let h = Hit { object: hit.object, triangle: hit.triangle, b1: hit.b1, b2: hit.b2 };
        let alpha = coverage(scene, &h);
        if alpha > 0.0 {
            first = first.or(Some(hit.t));
            let l = radiance(scene, lighting, &h, view);
            sum = add(sum, scale(l, through * alpha));
            through *= 1.0 - alpha;
            if through <= 0.0 {
                break;
            }
        }
        t_min = hit.t + 1e-12;
    }
    first.map(|t| (sum, t))
}

pub(crate) struct TraceRenderer<'a> {
    s: Shading<'a>,
    bvh: Bvh,
}

impl<'a> TraceRenderer<'a> {
    pub(crate) fn new(s: Shading<'a>) -> Self {
        let bvh = Bvh::new(s.scene);
        TraceRenderer { s, bvh }
    }

    /// Linear RGB radiance along the ray through `(x, y_j, z_e)` with
    /// direction `(slope, k, 1)`, or `None` when it meets nothing.
    pub(crate) fn trace(&self, x: f64, y: f64, slope: f64, k: f64) -> Option<[f64; 3]> {
        let r = self.s.rays;
        let ray = Ray { origin_m: [x, y, r.emitter_z_m], slope_x: slope, slope_y: k };
        let (d, origin) = (ray.direction(), ray.at_z(r.viewer_distance_m));
        let back = scale(d, -1.0);
        let scene = self.s.scene;
        // Front faces face the viewer: their normal has a positive component along d.
        let shown = |tri: &Triangle, n| scene.objects[tri.object as usize].material.double_sided || dot(n, d) > 0.0;
        along_ray(scene, self.s.lighting, &self.bvh, origin, back, normalize(d), shown).map(|(l, _)| l)
    }
}

impl HololineRenderer for TraceRenderer<'_> {
    fn render_hololine(&self, plane: usize, rows: &mut [&mut [f32]]) -> RenderStats {
        let r = self.s.rays;
        let g = self.s.geometry;
        let (e_count, v_count) = (g.emitters, g.views.count);
        let (se, sv) = (r.supersample.emitter, r.supersample.view);
        let (y, k) = r.plane(plane);
        let norm = 1.0 / (se * sv) as f64;
        let mut stats = RenderStats::default();
        for e in 0..e_count {
            for v in 0..v_count {
                let mut sum = [0.0; 3];
                for a in 0..se {
                    for b in 0..sv {
                        let x = r.sub_emitter_x_m[e * se + a];
                        let slope = r.sub_view_slope[v * sv + b];
                        if let Some(rgb) = self.trace(x, y, slope, k) {
                            stats.shaded += 1;
                            for c in 0..3 {
                                sum[c] += rgb[c];
                            }
                        }
                    }
                }
                for (ch, w) in self.s.weights.iter().enumerate() {
                    let value = (w[0] * sum[0] + w[1] * sum[1] + w[2] * sum[2]) * norm;
                    rows[ch][e * v_count + v] = value as f32;
                }
            }
        }
        stats
    }
}

/// A direct ray-traced picture of the scene as an eye on the viewer line
/// sees it through the display: for each hololine `j` and emitter `e`, the
/// radiance along the ray from `(x_e, y_j, z_e)` to the eye, averaged over
/// `pupil_samples` eye positions across a pupil `pupil_m` wide. Returned as
/// `(hololine, emitter, channel)` with the geometry's channels, the layout
/// of [`crate::reconstruct::picture::Picture::data`]. This is what a perfect display
/// would show that eye; the tests compare `holo view` with it. The scene is
/// lit by exactly `lighting` ([`super::render::RenderOptions::lighting_for`]
/// gives the lights a render of the scene uses).
pub fn eye_picture(
    scene: &super::Scene,
    lighting: &super::shade::Lighting,
    geometry: &crate::geometry::Geometry,
    eye_x_m: f64,
    pupil_m: f64,
    pupil_samples: usize,
) -> crate::error::Result<Vec<f32>> {
    let n = pupil_samples.max(1);
    let pupil: Vec<[f64; 3]> = (0..n)
        .map(|p| {
            let x = eye_x_m + pupil_m * ((p as f64 + 0.5) / n as f64 - 0.5);
            [x, geometry.viewer_height_m, geometry.viewer_distance_m]
        })
        .collect();
    picture_through(scene, lighting, geometry, &pupil)
}

/// [`eye_picture`] for an eye anywhere in front of the display, at
/// `eye_m = (x, y, z)`, a pinhole: for each hololine `j` and emitter `e`, the
/// radiance along the ray from `(x_e, y_j, z_e)` to the eye. What a perfect
/// full-parallax display shows that eye (a horizontal-parallax display shows
/// it only on the viewer line).
pub fn eye_picture_at(
    scene: &super::Scene,
    lighting: &super::shade::Lighting,
    geometry: &crate::geometry::Geometry,
    eye_m: [f64; 3],
) -> crate::error::Result<Vec<f32>> {
    picture_through(scene, lighting, geometry, &[eye_m])
}

/// The picture of [`eye_picture`]: each sample the mean radiance along the
/// rays from its emitter to each point of `pupil`.
fn picture_through(
    scene: &super::Scene,
    lighting: &super::shade::Lighting,
    geometry: &crate::geometry::Geometry,
    pupil: &[[f64; 3]],
) -> crate::error::Result<Vec<f32>> {
    use rayon::prelude::*;
    let rays = super::rays::Rays::new(geometry, super::rays::Supersample::new(1, 1))?;
    let names: Vec<&str> = geometry.channels.iter().map(|c| c.name.as_str()).collect();
    let weights = crate::geometry::channel_weights(&names);
    let s = Shading { scene, lighting, weights: &weights, rays: &rays, geometry };
    let tracer = TraceRenderer::new(s);
    let n = pupil.len() as f64;
    let z_e = geometry.emitter_z_m;
    let rows: Vec<Vec<f32>> = (0..geometry.hololines)
        .into_par_iter()
        .map(|j| {
            let mut row = Vec::with_capacity(geometry.emitters * weights.len());
            let y = geometry.hololine_y_m(j);
            for e in 0..geometry.emitters {
                let x = geometry.emitter_x_m(e);
                let mut sum = [0.0; 3];
                for eye in pupil {
                    let span = eye[2] - z_e;
                    if let Some(rgb) = tracer.trace(x, y, (eye[0] - x) / span, (eye[1] - y) / span) {
                        for c in 0..3 {
                            sum[c] += rgb[c] / n;
                        }
                    }
                }
                for w in &weights {
                    row.push((w[0] * sum[0] + w[1] * sum[1] + w[2] * sum[2]) as f32);
                }
            }
            row
        })
        .collect();
    Ok(rows.concat())
}
