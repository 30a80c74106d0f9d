//! Baking the view-independent light into vertex colours (Deering, *HoloFlicks* §8: the
//! "geometry shader" lights micropolygons once; only specular is left for
//! each view). Each vertex gets emission + ambient + Σ lights E·cos·ρ/π, with
//! ρ the base colour (factor × vertex colour × texture at the vertex) and
//! the normal as the reference shader sees it there (normal maps included),
//! and, on request, each light's term only where the light reaches the
//! vertex (shadows, by a ray through the scene).
//!
//! The terms are the reference shader's own ([`crate::mesh::shade::radiance`] with
//! the specular reflectance set to zero, one light at a time), so a baked
//! vertex plus the deferred specular term is exactly what direct shading
//! gives at that vertex.

use rayon::prelude::*;

use crate::math::{add, dot, length, scale, sub, unit};
use crate::mesh::bvh::Bvh;
use crate::mesh::shade::{face_normal, radiance, Hit, Lighting};
use crate::mesh::{Light, Scene};

/// How to bake.
#[derive(Clone, Copy, Debug, Default)]
pub struct BakeOptions {
    /// Leave out each light's term where the scene blocks it.
    pub shadows: bool,
}

/// What baking did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BakeReport {
    /// Vertices lit.
    pub vertices: usize,
    /// (vertex, light) pairs found in shadow.
    pub shadowed: usize,
}

/// Linear RGBA per vertex of every object of `scene` under `lights` (alpha:
/// the material's base alpha times the vertex colour's). An object whose
/// material chooses lights ([`crate::mesh::Material::lights`], indices into
/// `lights`) gets only those. Vertices no triangle uses get zero.
pub fn bake_diffuse(scene: &Scene, lights: &[Light], options: &BakeOptions) -> (Vec<Vec<[f32; 4]>>, BakeReport) {
    bake_diffuse_reporting(scene, lights, options, &crate::progress::Silent)
}

/// Vertices lit per progress report: enough that reporting costs nothing.
const BAKE_CHUNK: usize = 4096;

/// [`bake_diffuse`], counting the vertices lit in the phase `vertices lit`
/// of `progress`.
pub fn bake_diffuse_reporting(
    scene: &Scene,
    lights: &[Light],
    options: &BakeOptions,
    progress: &dyn crate::progress::Progress,
) -> (Vec<Vec<[f32; 4]>>, BakeReport) {
    progress.phase("vertices lit", scene.objects.iter().map(|o| o.positions.len() as u64).sum());
    let lit = std::sync::atomic::AtomicU64::new(0);
    // The reference shader with specular reflectance zero: view-independent.
    let mut matte = scene.clone();
    for o in &mut matte.objects {
        o.material.specular = [0.0; 3];
        // Each light is shaded alone below; the material's choice of lights is applied there.
        o.material.lights = None;
    }
    let bvh = options.shadows.then(|| Bvh::new(scene));
    let extent =
        scene.bounds().map_or(1.0, |(lo, hi)| (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max).max(1e-300));
    let unlit = Lighting { lights: Vec::new(), model: Default::default() };
    let one: Vec<Lighting> =
        lights.iter().map(|l| Lighting { lights: vec![l.clone()], model: Default::default() }).collect();
    let mut report = BakeReport::default();
    let colours = matte
        .objects
        .iter()
        .enumerate()
        .map(|(oi, o)| {
            // One triangle (and corner) per vertex: where to evaluate it.
            let mut corner: Vec<Option<(u32, usize)>> = vec![None; o.positions.len()];
            for (t, tri) in o.triangles.iter().enumerate() {
                for (k, &i) in tri.iter().enumerate() {
                    if let Some(slot) = corner.get_mut(i as usize) {
                        slot.get_or_insert((t as u32, k));
                    }
                }
            }
            let per_vertex: Vec<([f32; 4], usize)> = corner
                .par_chunks(BAKE_CHUNK)
                .enumerate()
                .flat_map_iter(|(chunk, corners)| {
                    let done = lit.fetch_add(corners.len() as u64, std::sync::atomic::Ordering::Relaxed);
                    progress.advance(done + corners.len() as u64);
                    corners.iter().enumerate().map(move |(k, c)| (chunk * BAKE_CHUNK + k, c))
                })
                .map(|(i, c)| {
                    let Some((t, k)) = *c else { return ([0.0; 4], 0) };
                    let hit = Hit { object: oi as u32, triangle: t, b1: f64::from(k == 1), b2: f64::from(k == 2) };
                    let Some(view) = unit(face_normal(o, t as usize)) else { return ([0.0; 4], 0) };
                    let emitted = radiance(&matte, &unlit, &hit, view);
                    let mut sum = emitted;
                    let mut shadowed = 0;
                    let receives = &scene.objects[oi].material;
                    for (index, (light, lighting)) in lights.iter().zip(&one).enumerate() {
                        if !receives.receives_light(index) {
                            continue;
                        }
                        let lit = radiance(&matte, lighting, &hit, view);
                        let term = sub(lit, emitted);
                        if term == [0.0; 3] {
                            continue;
                        }
                        if let Some(bvh) = &bvh {
                            if blocked(bvh, o.positions[i], view, light, extent) {
                                shadowed += 1;
                                continue;
                            }
                        }
                        sum = add(sum, term);
                    }
                    let alpha = o.material.base_colour[3] * o.colours.get(i).map_or(1.0, |c| c[3]);
                    ([sum[0] as f32, sum[1] as f32, sum[2] as f32, alpha], shadowed)
                })
                .collect();
            report.vertices += per_vertex.len();
            report.shadowed += per_vertex.iter().map(|v| v.1).sum::<usize>();
            per_vertex.into_iter().map(|v| v.0).collect()
        })
        .collect();
    (colours, report)
}

/// Whether the scene blocks `light` from `position` (a point on a surface
/// whose front is `normal`): a ray from just off the surface toward it.
fn blocked(bvh: &Bvh, position: [f64; 3], normal: [f64; 3], light: &Light, extent: f64) -> bool {
    let (dir, reach) = match light {
        Light::Ambient { .. } => return false,
        Light::Directional { direction, .. } => (direction.map(|x| -x), f64::INFINITY),
        Light::Point { position: p, .. } => {
            let d = sub(*p, position);
            (d, length(d))
        }
    };
    let Some(dir) = unit(dir) else { return false };
    // Start just off the surface, on the side the light is (the term is
    // non-zero, so that is the side the shader lit).
    let side = if dot(normal, dir) >= 0.0 { 1.0 } else { -1.0 };
    let eps = 1e-7 * extent;
    let origin = add(position, scale(normal, side * eps));
    bvh.nearest(origin, dir, eps, |_, _| true).is_some_and(|h| h.t < reach - eps)
}
