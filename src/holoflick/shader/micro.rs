//! The "geometry shader" of Deering, *HoloFlicks* §8: a scene made into lit
//! micropolygons. Every surface is diced ([`super::dice`]) to the budget
//! given (for a display, [`super::dice::display_budget`]), the
//! view-independent light is baked into the vertex colours
//! ([`super::bake`]), and each object keeps only what varies with the view:
//! its specular reflectance and exponent, under a pre-lit material
//! ([`crate::mesh::Material::prelit`]). Rendered under the scene's lights without
//! the ambient ones, the micropolygons give what the scene gives, up to
//! the micropolygons' linear interpolation of the baked light (which shrinks
//! with them) and the shadows, which direct rendering does not compute.
//!
//! Normal maps are baked into the diffuse light and then dropped: the
//! deferred specular term sees the interpolated vertex normals.

use super::bake::{bake_diffuse_reporting, BakeOptions, BakeReport};
use super::dice::{dice_reporting, with_flat_normals, DiceOptions, DiceReport};
use crate::error::Result;
use crate::mesh::{Light, Material, Scene};

/// What making micropolygons did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MicroReport {
    /// Dicing.
    pub dice: DiceReport,
    /// Baking.
    pub bake: BakeReport,
}

/// The scene as pre-lit micropolygons (one object per object, same names
/// and order), and the lights that still apply to it: the specular ones
/// (every light but ambient; a material's choice of lights is renumbered
/// into them).
pub fn micropolygons(
    scene: &Scene,
    lights: &[Light],
    max_edge_m: &(dyn Fn([f64; 3]) -> f64 + Sync),
    dice_options: &DiceOptions,
    bake_options: &BakeOptions,
    progress: &dyn crate::progress::Progress,
) -> Result<(Scene, Vec<Light>, MicroReport)> {
    let flat: Vec<_> = scene.objects.iter().map(with_flat_normals).collect();
    let (objects, dice_report) = dice_reporting(&flat, max_edge_m, dice_options, progress)?;
    let diced = Scene { objects, ..scene.clone() };
    let (colours, bake_report) = bake_diffuse_reporting(&diced, lights, bake_options, progress);
    let mut out = Scene { source: scene.source.clone(), warnings: scene.warnings.clone(), ..Scene::default() };
    // Each light's index among the specular lights returned (ambient ones are dropped).
    let mut kept = 0u32;
    let specular_index: Vec<Option<u32>> = lights
        .iter()
        .map(|l| {
            (!matches!(l, Light::Ambient { .. })).then(|| {
                kept += 1;
                kept - 1
            })
        })
        .collect();
    for (mut o, colours) in diced.objects.into_iter().zip(colours) {
        let m = &o.material;
        o.material = Material {
            name: m.name.clone(),
            base_colour: [1.0; 4],
            specular: m.specular,
            shininess: m.shininess,
            double_sided: m.double_sided,
            prelit: true,
            specular_model: m.specular_model,
            lights: m.lights.as_ref().map(|chosen| {
                chosen.iter().filter_map(|&i| specular_index.get(i as usize).copied().flatten()).collect()
            }),
            ..Material::default()
        };
        o.colours = colours;
        o.tangents.clear();
        o.uv_sets.clear();
        out.objects.push(o);
    }
    let specular_lights = lights.iter().filter(|l| !matches!(l, Light::Ambient { .. })).cloned().collect();
    Ok((out, specular_lights, MicroReport { dice: dice_report, bake: bake_report }))
}
