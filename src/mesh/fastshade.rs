//! The rasteriser's shader: the formulas of [`super::shade`] in f32, on
//! surface attributes interpolated linearly along a segment instead of
//! looked up per hit. Along one hololine's segment every attribute is affine
//! in the segment parameter, so this is exact up to f32 rounding; the tests
//! compare the two renderers, which holds the two shaders together.
//!
//! A material with a metallic-roughness texture gets its diffuse colour,
//! `k_s` and exponent point by point ([`PointTerms`]), in the batch and in
//! [`shade_run`] alike; [`coverage`] is the alpha of a point of a
//! see-through material, which the rasteriser composites with.

use std::collections::HashMap;

use super::shade::{sample, Lighting, SpecularModel};
use super::{AlphaMode, Light, Material, MetallicRoughness, Object, Scene, Texture, TextureRef};
use crate::math::{add, cross, dot, mul, narrow, normalize, normalize_or, scale, sub};
use crate::sampling::bilerp;

/// A material in the form the per-pixel loop wants.
pub(crate) struct FastMaterial {
    base: [f32; 3],
    emissive: [f32; 3],
    ks: [f32; 3],
    exponent: f32,
    /// Lobe normalisation, `(n+2)/2π` or `(n+8)/8π`.
    lobe_norm: f32,
    specular: bool,
    /// See [`Material::prelit`].
    prelit: bool,
    base_texture: Option<TextureRef>,
    emissive_texture: Option<TextureRef>,
    normal_texture: Option<TextureRef>,
    normal_scale: f32,
    /// Lobe arguments `x` at or below this give a lobe under
    /// [`LOBE_FLOOR`]`/π/max(k_s)` and are skipped.
    x_min: f32,
    /// Metalness and roughness over the surface, making the diffuse colour,
    /// `k_s` and exponent per point ([`PointTerms`]).
    metallic_roughness: Option<MetallicRoughness>,
    /// The lobe (for the normalisation of a point's exponent).
    model: SpecularModel,
    /// See [`Material::alpha_mode`], and the base colour factor's alpha.
    alpha_mode: AlphaMode,
    alpha: f32,
}

impl FastMaterial {
    pub(crate) fn new(m: &Material, model: SpecularModel) -> Self {
        let n = m.shininess.max(0.0);
        let lobe_norm = lobe_norm(model, n);
        FastMaterial {
            base: [m.base_colour[0], m.base_colour[1], m.base_colour[2]],
            emissive: m.emissive,
            ks: m.specular,
            exponent: n,
            lobe_norm,
            specular: m.specular.iter().any(|&k| k > 0.0),
            prelit: m.prelit,
            base_texture: m.base_colour_texture.clone(),
            emissive_texture: m.emissive_texture.clone(),
            normal_texture: m.normal_texture.clone(),
            normal_scale: m.normal_scale,
            x_min: lobe_threshold(lobe_norm as f64, m.specular.iter().fold(0.0f32, |a, &b| a.max(b)) as f64, n as f64),
            metallic_roughness: m.metallic_roughness.clone(),
            model,
            alpha_mode: m.alpha_mode,
            alpha: m.base_colour[3],
        }
    }

    /// Whether what is behind the surface can show through it (its
    /// [`AlphaMode`] is not opaque).
    pub(crate) fn see_through(&self) -> bool {
        self.alpha_mode != AlphaMode::Opaque
    }

    /// The terms of a point of base colour `base` (factor × vertex colour ×
    /// texture): a metallic-roughness material's from the texel of its
    /// texture there (`None`: the factors alone), any other's its own.
    #[inline]
    fn point_terms(&self, base: [f32; 3], texel: Option<[f32; 4]>) -> PointTerms {
        match &self.metallic_roughness {
            None => PointTerms {
                albedo: base,
                ks: self.ks,
                exponent: self.exponent,
                lobe_norm: self.lobe_norm,
                x_min: self.x_min,
                specular: self.specular,
            },
            Some(mr) => PointTerms::metallic_roughness(mr, self.ks, self.model, base, texel),
        }
    }
}

/// The normalisation of a lobe of exponent `n`: `(n + 2)/2π` (Phong) or
/// `(n + 8)/8π` (Blinn).
#[inline(always)]
fn lobe_norm(model: SpecularModel, n: f32) -> f32 {
    match model {
        SpecularModel::Phong => (n + 2.0) / (2.0 * std::f32::consts::PI),
        SpecularModel::Blinn => (n + 8.0) / (8.0 * std::f32::consts::PI),
    }
}

/// [`super::shade::exponent_of_roughness`] in f32 (the glTF loader's
/// factor-only mapping uses it too).
#[inline(always)]
pub(crate) fn exponent_of_roughness(roughness: f32) -> f32 {
    let alpha = (roughness * roughness).max(0.01);
    2.0 / (alpha * alpha) - 2.0
}

/// The shading terms of one point: diffuse colour, `k_s`, exponent and
/// lobe normalisation, the lobe argument at or below which the lobe is
/// skipped, and whether there is a specular term.
#[derive(Clone, Copy)]
pub(crate) struct PointTerms {
    albedo: [f32; 3],
    ks: [f32; 3],
    exponent: f32,
    lobe_norm: f32,
    x_min: f32,
    specular: bool,
}

impl PointTerms {
    /// [`super::shade`]'s metallic-roughness mapping: `m` and `r` the
    /// factors × the texel's B and G, clamped; `ρ = base·(1 − m)`,
    /// `k_s = k_d + (base − k_d)·m`, `n` from `r`. No lobe is skipped
    /// (`x_min` 0: finding the threshold per point would cost more than it
    /// saves).
    #[inline(always)]
    fn metallic_roughness(
        mr: &MetallicRoughness,
        dielectric: [f32; 3],
        model: SpecularModel,
        base: [f32; 3],
        texel: Option<[f32; 4]>,
    ) -> PointTerms {
        let (mut metal, mut rough) = (mr.metallic, mr.roughness);
        if let Some(t) = texel {
            metal *= t[2];
            rough *= t[1];
        }
        let metal = metal.clamp(0.0, 1.0);
        let exponent = exponent_of_roughness(rough.clamp(0.0, 1.0));
        PointTerms {
            albedo: std::array::from_fn(|c| base[c] * (1.0 - metal)),
            ks: std::array::from_fn(|c| dielectric[c] + (base[c] - dielectric[c]) * metal),
            exponent,
            lobe_norm: lobe_norm(model, exponent),
            x_min: 0.0,
            specular: true,
        }
    }

    /// The lobe `lobe_norm · x^n`, or 0 where it cannot matter: below
    /// `x_min` the specular term is under [`LOBE_FLOOR`] of the diffuse
    /// radiance a white surface gets from the same light, `E·cos_i/π`.
    #[inline]
    fn lobe(&self, x: f32) -> f32 {
        if x > self.x_min {
            self.lobe_norm * pow01(x, self.exponent)
        } else {
            0.0
        }
    }
}

/// The `x` below which `lobe_norm·max_ks·x^n < LOBE_FLOOR/π`.
fn lobe_threshold(lobe_norm: f64, max_ks: f64, n: f64) -> f32 {
    let scale = lobe_norm * max_ks * std::f64::consts::PI;
    if n <= 0.0 || scale <= 0.0 {
        return 0.0;
    }
    // Rounded down, so nothing that matters is skipped.
    ((LOBE_FLOOR / scale).powf(1.0 / n).min(1.0) * (1.0 - 1e-6)) as f32
}

/// Lights in f32 (all of a render's, or those a group of materials
/// receives), ambient summed, and their lobe.
pub(crate) struct FastLights {
    directional: Vec<([f32; 3], [f32; 3])>,
    point: Vec<([f32; 3], [f32; 3])>,
    ambient: [f32; 3],
    model: SpecularModel,
    /// The CPU has AVX2 and FMA.
    avx2: bool,
}

impl FastLights {
    /// The CPU has AVX2 and FMA.
    pub(crate) fn avx2(&self) -> bool {
        self.avx2
    }

    /// The specular lobe.
    pub(crate) fn model(&self) -> SpecularModel {
        self.model
    }

    /// Take the portable (SSE2) loops even where AVX2 is there.
    #[cfg(test)]
    pub(crate) fn portable(&mut self) {
        self.avx2 = false;
    }

    /// The lights of `l` that `chosen` lists (in `l`'s order; `None`: all),
    /// with lobe `model`.
    pub(crate) fn chosen(l: &Lighting, chosen: Option<&[u32]>, model: SpecularModel) -> Self {
        let mut out = FastLights { directional: vec![], point: vec![], ambient: [0.0; 3], model, avx2: false };
        out.avx2 = crate::simd::Simd::Detect.avx2_fma();
        for (index, light) in l.lights.iter().enumerate() {
            if chosen.is_some_and(|c| !c.contains(&(index as u32))) {
                continue;
            }
            match light {
                Light::Directional { direction, irradiance, .. } => {
                    let to = narrow(*direction).map(|x| -x);
                    out.directional.push((normalize(to), *irradiance));
                }
                Light::Point { position, intensity, .. } => {
                    out.point.push((narrow(*position), *intensity));
                }
                Light::Ambient { radiance } => {
                    for (a, r) in out.ambient.iter_mut().zip(radiance) {
                        *a += r;
                    }
                }
            }
        }
        out
    }
}

/// What each material of a render receives, computed once per render: one
/// [`FastLights`] per distinct (light selection, lobe) among the materials,
/// group 0 being the render's own (every light, its lobe). A render whose
/// materials choose neither has that one group, so it shades exactly as if
/// materials could not choose.
pub(crate) struct LightGroups {
    /// Group 0: every light, the render's lobe.
    pub groups: Vec<FastLights>,
    /// The group of each object of the scene.
    pub of_object: Vec<u32>,
}

impl LightGroups {
    pub(crate) fn new(scene: &Scene, l: &Lighting) -> Self {
        // Keys: the chosen indices sorted without repeats (`None`: all of
        // them, however listed), and the lobe.
        let mut keys: Vec<(Option<Vec<u32>>, SpecularModel)> = vec![(None, l.model)];
        let mut index: HashMap<(Option<Vec<u32>>, SpecularModel), u32> = HashMap::new();
        index.insert(keys[0].clone(), 0);
        let n = l.lights.len() as u32;
        let of_object = scene
            .objects
            .iter()
            .map(|o| {
                let m = &o.material;
                let chosen = m.lights.as_ref().map(|c| {
                    let mut c: Vec<u32> = c.iter().copied().filter(|&i| i < n).collect();
                    c.sort_unstable();
                    c.dedup();
                    c
                });
                let chosen = chosen.filter(|c| c.len() as u32 != n);
                let key = (chosen, m.specular_model.unwrap_or(l.model));
                *index.entry(key.clone()).or_insert_with(|| {
                    keys.push(key);
                    keys.len() as u32 - 1
                })
            })
            .collect();
        let groups = keys.iter().map(|(chosen, model)| FastLights::chosen(l, chosen.as_deref(), *model)).collect();
        LightGroups { groups, of_object }
    }
}

/// Surface attributes at one end of a segment.
#[derive(Clone, Copy, Default)]
pub(crate) struct Attrs {
    pub pos: [f32; 3],
    /// Interpolated vertex normal (not unit), or the face normal.
    pub normal: [f32; 3],
    pub colour: [f32; 3],
    /// The vertex colours' alpha (1 without vertex colours).
    pub alpha: f32,
    /// Texture coordinates of up to two sets.
    pub uv: [[f32; 2]; 2],
    pub tangent: [f32; 4],
}

impl Attrs {
    /// The attributes of object `o`'s triangle `t` at barycentric weights `w`.
    pub(crate) fn at(o: &Object, t: usize, w: [f64; 3], unit_face: [f64; 3]) -> Attrs {
        let tri = o.triangles[t];
        let mut a = Attrs::default();
        let mut pos = [0.0f64; 3];
        for (k, &i) in tri.iter().enumerate() {
            let i = i as usize;
            for (p, x) in pos.iter_mut().zip(o.positions[i]) {
                *p += x * w[k];
            }
            let wk = w[k] as f32;
            if !o.normals.is_empty() {
                for q in 0..3 {
                    a.normal[q] += o.normals[i][q] * wk;
                }
            }
            if !o.colours.is_empty() {
                for q in 0..3 {
                    a.colour[q] += o.colours[i][q] * wk;
                }
                a.alpha += o.colours[i][3] * wk;
            }
            for (set, uv) in o.uv_sets.iter().take(2).enumerate() {
                if !uv.is_empty() {
                    a.uv[set][0] += uv[i][0] * wk;
                    a.uv[set][1] += uv[i][1] * wk;
                }
            }
            if !o.tangents.is_empty() {
                for q in 0..4 {
                    a.tangent[q] += o.tangents[i][q] * wk;
                }
            }
        }
        a.pos = narrow(pos);
        if o.normals.is_empty() {
            a.normal = narrow(unit_face);
        }
        if o.colours.is_empty() {
            a.colour = [1.0; 3];
            a.alpha = 1.0;
        }
        a
    }

    /// `b − self`, field by field: with it, `self + t·delta` is the lerp.
    pub(crate) fn delta(&self, b: &Attrs) -> Attrs {
        let d3 = |x: [f32; 3], y: [f32; 3]| [y[0] - x[0], y[1] - x[1], y[2] - x[2]];
        Attrs {
            pos: d3(self.pos, b.pos),
            normal: d3(self.normal, b.normal),
            colour: d3(self.colour, b.colour),
            alpha: b.alpha - self.alpha,
            uv: [
                [b.uv[0][0] - self.uv[0][0], b.uv[0][1] - self.uv[0][1]],
                [b.uv[1][0] - self.uv[1][0], b.uv[1][1] - self.uv[1][1]],
            ],
            tangent: [
                b.tangent[0] - self.tangent[0],
                b.tangent[1] - self.tangent[1],
                b.tangent[2] - self.tangent[2],
                b.tangent[3] - self.tangent[3],
            ],
        }
    }
}

/// What the lights look like from one view column of one hololine: every
/// ray of the column has the same direction, so the view vector, and with it
/// each directional light's Blinn half vector `H` and Phong `L·V`, are
/// computed once per column instead of once per pixel.
#[derive(Default)]
pub(crate) struct Column {
    view: [f32; 3],
    directional: Vec<DirectionalInColumn>,
}

#[derive(Clone, Copy)]
struct DirectionalInColumn {
    to_light: [f32; 3],
    irradiance: [f32; 3],
    /// Unit `(L + V)/|L + V|` (Blinn), or zero when `L = −V`.
    half: [f32; 3],
    /// `L·V` (Phong: `R·V = 2(N·L)(N·V) − L·V`).
    lv: f32,
}

impl Column {
    /// Set up for unit view vector `view`.
    pub(crate) fn set(&mut self, lights: &FastLights, view: [f32; 3]) {
        self.view = view;
        self.directional.clear();
        for &(to_light, irradiance) in &lights.directional {
            let h = add(to_light, view);
            let l2 = dot(h, h);
            let half = if l2 > 0.0 { scale(h, 1.0 / l2.sqrt()) } else { [0.0; 3] };
            self.directional.push(DirectionalInColumn { to_light, irradiance, half, lv: dot(to_light, view) });
        }
    }
}

/// One run of pixels of a view column that all show the same segment.
pub(crate) struct Run<'a> {
    pub material: &'a FastMaterial,
    /// Attributes at the segment's start and their change to its end.
    pub a: &'a Attrs,
    pub delta: &'a Attrs,
    /// Unit face normal facing the viewer.
    pub face: [f32; 3],
    /// A back face (double-sided): the vertex normal flips.
    pub flip: bool,
    pub has_normals: bool,
    pub has_tangents: bool,
    /// [`normals_nonzero`] of the segment.
    pub normals_nonzero: bool,
}

/// Shade a run: for each segment parameter in `params` (clamped to
/// `[0, 1]`), add the radiance to the matching entry of `acc`.
///
/// The formulas are [`super::shade`]'s; what differs is where the work is
/// done: per column ([`Column`]), per run (the material's switches, the
/// attribute deltas) and per pixel only what depends on the point.
pub(crate) fn shade_run(
    scene: &Scene,
    lights: &FastLights,
    column: &Column,
    run: &Run,
    params: &[f64],
    acc: [&mut [f32]; 3],
) {
    let m = run.material;
    let (a, d) = (run.a, run.delta);
    let normal_map = match &m.normal_texture {
        Some(r) if run.has_tangents => Some(r),
        _ => None,
    };
    let needs_pos = !lights.point.is_empty();
    let sign = if run.flip { -1.0 } else { 1.0 };
    let view = column.view;
    let lerp3 = |x: [f32; 3], dx: [f32; 3], t: f32| [x[0] + dx[0] * t, x[1] + dx[1] * t, x[2] + dx[2] * t];
    let [acc_r, acc_g, acc_b] = acc;
    for (px, &t) in params.iter().enumerate() {
        let t = t.clamp(0.0, 1.0) as f32;
        let mut normal =
            if run.has_normals { scale(normalize_or(lerp3(a.normal, d.normal, t), run.face), sign) } else { run.face };
        let uv = |r: &TextureRef| -> [f32; 2] {
            let c = if r.uv_set < 2 {
                [a.uv[r.uv_set][0] + d.uv[r.uv_set][0] * t, a.uv[r.uv_set][1] + d.uv[r.uv_set][1] * t]
            } else {
                [0.0; 2]
            };
            r.transform.apply(c)
        };
        if let Some(r) = normal_map {
            let tg = lerp3([a.tangent[0], a.tangent[1], a.tangent[2]], [d.tangent[0], d.tangent[1], d.tangent[2]], t);
            let w = a.tangent[3] + d.tangent[3] * t;
            let tangent = sub(tg, scale(normal, dot(normal, tg)));
            let len2 = dot(tangent, tangent);
            if len2 > 0.0 && len2.is_finite() {
                let tangent = scale(tangent, 1.0 / len2.sqrt());
                let bitangent = scale(cross(normal, tangent), if w < 0.0 { -1.0 } else { 1.0 });
                let texel = sample_fast(&scene.textures[r.texture], uv(r));
                let nx = (texel[0] * 2.0 - 1.0) * m.normal_scale;
                let ny = (texel[1] * 2.0 - 1.0) * m.normal_scale;
                let nz = texel[2] * 2.0 - 1.0;
                let mapped = add(add(scale(tangent, nx), scale(bitangent, ny)), scale(normal, nz));
                normal = normalize_or(mapped, normal);
            }
        }
        let colour = lerp3(a.colour, d.colour, t);
        let mut base = mul(m.base, colour);
        if let Some(r) = &m.base_texture {
            let texel = sample_fast(&scene.textures[r.texture], uv(r));
            base = mul(base, [texel[0], texel[1], texel[2]]);
        }
        let texel = m.metallic_roughness.as_ref().and_then(|mr| mr.texture.as_ref());
        let terms = m.point_terms(base, texel.map(|r| sample_fast(&scene.textures[r.texture], uv(r))));
        let mut base = terms.albedo;
        let mut emitted = m.emissive;
        if let Some(r) = &m.emissive_texture {
            let texel = sample_fast(&scene.textures[r.texture], uv(r));
            emitted = mul(emitted, [texel[0], texel[1], texel[2]]);
        }
        if m.prelit {
            emitted = add(emitted, base);
            base = [0.0; 3];
        }
        // Σ E·cos_i (diffuse) and Σ E·cos_i·lobe (specular).
        let mut diffuse = [0.0f32; 3];
        let mut specular = [0.0f32; 3];
        let nv = dot(normal, view);
        for l in &column.directional {
            let cos_i = dot(normal, l.to_light);
            if cos_i <= 0.0 {
                continue;
            }
            let ec = scale(l.irradiance, cos_i);
            diffuse = add(diffuse, ec);
            if terms.specular {
                let x = match lights.model {
                    SpecularModel::Phong => 2.0 * cos_i * nv - l.lv,
                    SpecularModel::Blinn => dot(normal, l.half),
                };
                let lobe = terms.lobe(x);
                if lobe > 0.0 {
                    specular = add(specular, scale(ec, lobe));
                }
            }
        }
        if needs_pos {
            let pos = lerp3(a.pos, d.pos, t);
            for &(p, i) in &lights.point {
                let dl = sub(p, pos);
                let d2 = dot(dl, dl);
                if d2 <= 0.0 {
                    continue;
                }
                let inv = 1.0 / d2;
                let to_light = scale(dl, inv.sqrt());
                let cos_i = dot(normal, to_light);
                if cos_i <= 0.0 {
                    continue;
                }
                let ec = scale(i, inv * cos_i);
                diffuse = add(diffuse, ec);
                if terms.specular {
                    let x = match lights.model {
                        SpecularModel::Phong => 2.0 * cos_i * nv - dot(to_light, view),
                        SpecularModel::Blinn => {
                            let h = add(to_light, view);
                            let l2 = dot(h, h);
                            if l2 > 0.0 {
                                dot(normal, h) / l2.sqrt()
                            } else {
                                0.0
                            }
                        }
                    };
                    let lobe = terms.lobe(x);
                    if lobe > 0.0 {
                        specular = add(specular, scale(ec, lobe));
                    }
                }
            }
        }
        let rgb: [f32; 3] = std::array::from_fn(|c| {
            emitted[c]
                + base[c] * (lights.ambient[c] + diffuse[c] * std::f32::consts::FRAC_1_PI)
                + terms.ks[c] * specular[c]
        });
        acc_r[px] += rgb[0];
        acc_g[px] += rgb[1];
        acc_b[px] += rgb[2];
    }
}

/// [`super::shade::coverage`] in f32: how much of a ray the point at
/// parameter `t` of a segment of material `m` (attributes `a + t·d`) covers.
pub(crate) fn coverage(scene: &Scene, m: &FastMaterial, a: &Attrs, d: &Attrs, t: f32) -> f32 {
    let cutoff = match m.alpha_mode {
        AlphaMode::Opaque => return 1.0,
        AlphaMode::Mask { cutoff } => Some(cutoff),
        AlphaMode::Blend => None,
    };
    let mut alpha = m.alpha * (a.alpha + d.alpha * t);
    if let Some(r) = &m.base_texture {
        let uv = if r.uv_set < 2 {
            [a.uv[r.uv_set][0] + d.uv[r.uv_set][0] * t, a.uv[r.uv_set][1] + d.uv[r.uv_set][1] * t]
        } else {
            [0.0; 2]
        };
        alpha *= sample_fast(&scene.textures[r.texture], r.transform.apply(uv))[3];
    }
    match cutoff {
        Some(c) => f32::from(u8::from(alpha >= c)),
        None => alpha.clamp(0.0, 1.0),
    }
}

/// Below this fraction of the radiance a white diffuse surface gets from
/// the same light, a specular lobe is skipped (see [`FastMaterial::lobe`]).
const LOBE_FLOOR: f64 = 1e-6;

/// `x^n` for `0 ≤ x ≤ 1` and `n ≥ 0`, as `2^(n·log₂x)`, without libm and
/// without branches (so loops of it vectorise).
///
/// Error bound (checked by the test `pow01_is_within_its_bound` against
/// `f64::powf` on the same f32 arguments): with `y = n·log₂x`, the relative
/// error is at most `1e-6 + 3e-7·|y|` while the result is a normal f32
/// (`y ≥ −126`); below that the result is 0 (absolute error < 1.2e-38).
/// `log₂` of the mantissa `m ∈ [√½, √2)` is the atanh series
/// `2/ln2·(z + z³/3 + … + z⁹/9)`, `z = (m−1)/(m+1)`, `|z| ≤ 0.1716`
/// (truncation < 3e-9 relative, below f32 rounding); `2^f` for
/// `f ∈ [−½, ½]` is its Taylor polynomial of degree 6 (truncation
/// < 1.3e-7 relative); the rest is f32 rounding of the products, which
/// grows with `|y|`. `x > 1` (rounding) is taken as 1.
#[inline(always)]
pub(crate) fn pow01(x: f32, n: f32) -> f32 {
    let xc = x.clamp(f32::MIN_POSITIVE, 1.0); // NaN → MIN_POSITIVE
                                              // log₂ x = e + log₂ m.
    let bits = xc.to_bits();
    let e = ((bits >> 23) & 0xff) as i32 - 127;
    let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000); // [1, 2)
    let big = m > std::f32::consts::SQRT_2;
    let m = if big { m * 0.5 } else { m };
    let e = if big { e + 1 } else { e };
    let z = (m - 1.0) / (m + 1.0);
    let z2 = z * z;
    let series = 1.0 + z2 * (1.0 / 3.0 + z2 * (1.0 / 5.0 + z2 * (1.0 / 7.0 + z2 * (1.0 / 9.0))));
    let log2 = e as f32 + z * series * (2.0 * std::f32::consts::LOG2_E);
    // 2^y = 2^i · 2^f, i the nearest integer, |f| ≤ ½.
    let y = (n * log2).clamp(-127.0, 0.0);
    // Round to nearest by the 1.5·2²³ trick (no float-to-int conversion, so it vectorises).
    const MAGIC: f32 = 12_582_912.0;
    let rounded = y + MAGIC;
    let i = rounded.to_bits() as i32 - MAGIC.to_bits() as i32;
    let f = (y - (rounded - MAGIC)) * std::f32::consts::LN_2;
    let p = 1.0 + f * (1.0 + f * (0.5 + f * (1.0 / 6.0 + f * (1.0 / 24.0 + f * (1.0 / 120.0 + f * (1.0 / 720.0))))));
    let r = p * f32::from_bits(((i.max(-126) + 127) as u32) << 23);
    let r = if y < -126.0 { 0.0 } else { r };
    if x > 0.0 {
        r
    } else if n == 0.0 {
        1.0
    } else {
        0.0
    }
}

impl Run<'_> {
    /// The run can go through a [`Batch`]: no emissive texture, no normal
    /// map, no point lights and no texture transform (their per-pixel work
    /// stays in [`shade_run`]); a base-colour texture and a
    /// metallic-roughness one are looked up while gathering.
    pub(crate) fn is_simple(&self, lights: &FastLights) -> bool {
        let m = self.material;
        let plain = |r: &Option<TextureRef>| r.as_ref().map_or(true, |r| r.transform == super::UvTransform::default());
        m.emissive_texture.is_none()
            && plain(&m.base_texture)
            && m.metallic_roughness.as_ref().map_or(true, |mr| plain(&mr.texture))
            && (m.normal_texture.is_none() || !self.has_tangents)
            && lights.point.is_empty()
            && (!self.has_normals || self.normals_nonzero)
    }
}

/// [`sample`] with the same result bit for bit, faster where it matters:
/// a lookup whose 2 × 2 texels lie inside the texture (almost all of them)
/// needs neither `floor` nor the wrap modes (for `x ≥ 0`, truncation is
/// `floor`). Everything else, NaN included, goes to [`sample`].
#[inline(always)]
pub(crate) fn sample_fast(tex: &Texture, uv: [f32; 2]) -> [f32; 4] {
    let (w, h) = (tex.width, tex.height);
    let x = uv[0] as f64 * w as f64 - 0.5;
    let y = uv[1] as f64 * h as f64 - 0.5;
    if !(x >= 0.0 && y >= 0.0 && x < w as f64 - 1.0 && y < h as f64 - 1.0) {
        return sample(tex, uv);
    }
    let (i, j) = (x as usize, y as usize);
    let (fx, fy) = ((x - i as f64) as f32, (y - j as f64) as f32);
    let at = j * w + i;
    let (top, bottom) = (&tex.texels[at..at + 2], &tex.texels[at + w..at + w + 2]);
    bilerp([top[0], top[1], bottom[0], bottom[1]], fx, fy)
}

/// The interpolated vertex normal `a + t·d` stays well away from zero (and
/// finite) for `t ∈ [0, 1]`, so the batch need not fall back to the face
/// normal: `min over t of |a + t·d|²` against a floor.
pub(crate) fn normals_nonzero(a: &Attrs, d: &Attrs) -> bool {
    let (a, d) = (a.normal, d.normal);
    let (aa, ad, dd) = (dot(a, a), dot(a, d), dot(d, d));
    let t = if dd > 0.0 { (-ad / dd).clamp(0.0, 1.0) } else { 0.0 };
    let min = aa + t * (2.0 * ad + t * dd);
    min > 1e-12 && (aa + 2.0 * ad + dd) <= 1e30 && aa <= 1e30
}

/// The shading inputs of one hololine's segments that [`Batch::gather`]
/// looks up by each pixel's segment (entries of segments that are not
/// [`Run::is_simple`] are unused).
#[derive(Default)]
pub(crate) struct SegmentTable<'m> {
    simple: Vec<bool>,
    /// Shading normal at the start and its change to the end (the face
    /// normal and zero when flat), before facing is applied.
    normal_a: Vec<[f32; 3]>,
    normal_d: Vec<[f32; 3]>,
    colour_a: Vec<[f32; 3]>,
    colour_d: Vec<[f32; 3]>,
    base: Vec<[f32; 3]>,
    emissive: Vec<[f32; 3]>,
    /// Pre-lit: the albedo is sent as it is and takes no light.
    prelit: Vec<bool>,
    /// `k_s` × lobe normalisation (zero without specular).
    ks: Vec<[f32; 3]>,
    exponent: Vec<f32>,
    x_min: Vec<f32>,
    /// Base-colour texture (`u32::MAX`: none), its size (zero: none) and
    /// its coordinates.
    texture: Vec<u32>,
    texture_size: Vec<[f64; 2]>,
    texture_width: Vec<i32>,
    uv_a: Vec<[f32; 2]>,
    uv_d: Vec<[f32; 2]>,
    /// The material of each segment, for a metallic-roughness one's terms
    /// per point ([`FastMaterial::point_terms`]), and whether it is one.
    material: Vec<&'m FastMaterial>,
    metallic_roughness: Vec<bool>,
    /// Its metallic-roughness texture's coordinates.
    mr_uv_a: Vec<[f32; 2]>,
    mr_uv_d: Vec<[f32; 2]>,
    any_metallic_roughness: bool,
    /// Per view column: +1 where the segment faces the rays, −1 where its
    /// back (double-sided) is seen.
    sign: Vec<f32>,
}

impl<'m> SegmentTable<'m> {
    /// Add the next segment, `run` as seen from its front; it is simple
    /// when [`Run::is_simple`].
    pub(crate) fn push(&mut self, scene: &Scene, lights: &FastLights, run: &Run<'m>) {
        let m = run.material;
        let (a, d) = (run.a, run.delta);
        let (na, nd) = if run.has_normals { (a.normal, d.normal) } else { (run.face, [0.0; 3]) };
        self.normal_a.push(na);
        self.normal_d.push(nd);
        self.colour_a.push(a.colour);
        self.colour_d.push(d.colour);
        self.base.push(m.base);
        self.emissive.push(m.emissive);
        self.prelit.push(m.prelit);
        self.ks.push(scale(m.ks, if m.specular { m.lobe_norm } else { 0.0 }));
        self.exponent.push(m.exponent);
        self.x_min.push(m.x_min);
        // Texel indices of the vectorised lookup must fit an i32.
        let size = m.base_texture.as_ref().map(|r| (scene.textures[r.texture].width, scene.textures[r.texture].height));
        let fits = size.map_or(true, |(w, h)| w.checked_mul(h).is_some_and(|n| n <= i32::MAX as usize));
        self.simple.push(run.is_simple(lights) && fits);
        let (w, h) = size.unwrap_or((0, 0));
        self.texture_size.push([w as f64, h as f64]);
        self.texture_width.push(w as i32);
        match &m.base_texture {
            Some(r) => {
                self.texture.push(r.texture as u32);
                let (ua, ud) = if r.uv_set < 2 { (a.uv[r.uv_set], d.uv[r.uv_set]) } else { ([0.0; 2], [0.0; 2]) };
                self.uv_a.push(ua);
                self.uv_d.push(ud);
            }
            None => {
                self.texture.push(u32::MAX);
                self.uv_a.push([0.0; 2]);
                self.uv_d.push([0.0; 2]);
            }
        }
        self.material.push(m);
        self.metallic_roughness.push(m.metallic_roughness.is_some());
        self.any_metallic_roughness |= m.metallic_roughness.is_some();
        let mr_set = m.metallic_roughness.as_ref().and_then(|mr| mr.texture.as_ref()).map_or(2, |r| r.uv_set);
        let (ua, ud) = if mr_set < 2 { (a.uv[mr_set], d.uv[mr_set]) } else { ([0.0; 2], [0.0; 2]) };
        self.mr_uv_a.push(ua);
        self.mr_uv_d.push(ud);
        self.sign.push(1.0);
    }

    /// Segment `i` goes through the batch.
    #[inline]
    pub(crate) fn simple(&self, i: usize) -> bool {
        self.simple[i]
    }

    /// Every segment's facing for the current view column, to be set: 1
    /// facing the ray, −1 not.
    pub(crate) fn facing_mut(&mut self) -> &mut [f32] {
        &mut self.sign
    }
}

/// One view column's pixels in structure-of-arrays form, for the
/// vectorised part of the shader: the pixels of simple segments are
/// listed as they are found ([`Batch::push`]), their attributes are
/// interpolated column-wide from the [`SegmentTable`] with the
/// view-independent emissive and ambient terms added to the output straight
/// away ([`Batch::gather`]), then [`Batch::shade`] does the directional
/// lights for all of them at once. Column-wide, not run by run: with fine
/// meshes a run of one segment is a few pixels, too short to vectorise.
/// The loops run 8 lanes wide with AVX2 + FMA when the CPU has them
/// (checked at run time), SSE2 otherwise; the compiler does not contract
/// into FMA, so both give the same bits, from the same formulas as
/// [`shade_run`].
#[derive(Default)]
pub(crate) struct Batch {
    /// Pixels listed.
    count: usize,
    /// Each pixel's place in the column, segment and parameter (in `[0, 1]`).
    pixel: Vec<u32>,
    owner: Vec<u32>,
    t: Vec<f32>,
    /// The pixels were listed with weights ([`Batch::push_weighted`]):
    /// each one's radiance is added to the column × its weight.
    weighted: bool,
    weight: Vec<f32>,
    /// Interpolated (not unit) shading normal, facing the viewer.
    n: [Vec<f32>; 3],
    /// Base colour × vertex colour × texture.
    albedo: [Vec<f32>; 3],
    /// `k_s` × lobe normalisation.
    ks: [Vec<f32>; 3],
    exponent: Vec<f32>,
    x_min: Vec<f32>,
    /// Σ E·cos_i and Σ E·cos_i·lobe over the lights.
    diffuse: [Vec<f32>; 3],
    specular: [Vec<f32>; 3],
    /// Texture lookups: coordinates and texture size per pixel, then the
    /// top-left texel of the 2 × 2 footprint (−1: not wholly inside, use
    /// [`sample`]) and the bilinear weights.
    uv: [Vec<f32>; 2],
    size: [Vec<f64>; 2],
    width: Vec<i32>,
    index: Vec<i32>,
    fx: Vec<f32>,
    fy: Vec<f32>,
}

impl Batch {
    fn buffers(&mut self) -> impl Iterator<Item = &mut Vec<f32>> {
        self.n
            .iter_mut()
            .chain(&mut self.albedo)
            .chain(&mut self.ks)
            .chain([&mut self.exponent, &mut self.x_min])
            .chain(&mut self.diffuse)
            .chain(&mut self.specular)
            .chain(&mut self.uv)
            .chain([&mut self.fx, &mut self.fy])
    }

    /// Pixels listed so far in this column.
    pub(crate) fn len(&self) -> usize {
        self.count
    }

    /// List every pixel `first + i` of the column that shows a segment
    /// (`owner[i]` is not `none`): all segments of the hololine are simple. Branch-free: each
    /// pixel is written and kept by advancing the count or not.
    pub(crate) fn push_all(&mut self, first: usize, owner: &[u32], param: &[f64], none: u32) {
        let n = owner.len();
        for v in [&mut self.pixel, &mut self.owner] {
            if v.len() < self.count + n {
                v.resize(self.count + n, 0);
            }
        }
        if self.t.len() < self.count + n {
            self.t.resize(self.count + n, 0.0);
        }
        let mut at = self.count;
        let (pixel, own, ts) = (&mut self.pixel[..], &mut self.owner[..], &mut self.t[..]);
        for (i, (&o, &t)) in owner.iter().zip(param).enumerate() {
            pixel[at] = (first + i) as u32;
            own[at] = o;
            ts[at] = t.clamp(0.0, 1.0) as f32;
            at += (o != none) as usize;
        }
        self.count = at;
    }

    /// List pixel `pixel` of the column, showing simple segment `owner` at
    /// parameter `t`.
    #[inline]
    pub(crate) fn push(&mut self, pixel: usize, owner: u32, t: f64) {
        let at = self.count;
        for v in [&mut self.pixel, &mut self.owner] {
            if v.len() <= at {
                v.resize(at + 64, 0);
            }
        }
        if self.t.len() <= at {
            self.t.resize(at + 64, 0.0);
        }
        self.pixel[at] = pixel as u32;
        self.owner[at] = owner;
        self.t[at] = t.clamp(0.0, 1.0) as f32;
        self.count += 1;
    }

    /// [`Batch::push`] with a weight: a see-through surface's coverage ×
    /// what the surfaces in front of it let through. A column's pixels are
    /// listed either all with weights or all without.
    #[inline]
    pub(crate) fn push_weighted(&mut self, pixel: usize, owner: u32, t: f64, weight: f32) {
        let at = self.count;
        if self.weight.len() <= at {
            self.weight.resize(at + 64, 0.0);
        }
        self.weight[at] = weight;
        self.weighted = true;
        self.push(pixel, owner, t);
    }

    /// Interpolate the listed pixels' attributes and add their emissive and
    /// ambient terms to `acc` (the column).
    pub(crate) fn gather(&mut self, scene: &Scene, table: &SegmentTable, lights: &FastLights, acc: [&mut [f32]; 3]) {
        let need = (self.count + 7) & !7;
        if self.n[0].len() < need {
            let size = need.max(64) * 2;
            for b in self.buffers() {
                b.resize(size, 0.0);
            }
            for b in &mut self.size {
                b.resize(size, 0.0);
            }
            self.width.resize(size, 0);
            self.index.resize(size, 0);
        }
        #[cfg(target_arch = "x86_64")]
        {
            if lights.avx2 {
                // SAFETY: the CPU has AVX2 and FMA (checked in FastLights::chosen).
                unsafe { gather_avx2(self, scene, table, lights, acc) };
                return;
            }
        }
        gather_kernel(self, scene, table, lights, acc);
    }

    /// Add the directional lights' diffuse and specular terms of every
    /// listed pixel to `acc` (the column), and start a new column.
    pub(crate) fn shade(&mut self, lights: &FastLights, column: &Column, acc: [&mut [f32]; 3]) {
        if self.count > 0 {
            // The padding lanes: a valid normal and nothing to add.
            let (count, padded) = (self.count, (self.count + 7) & !7);
            for (k, b) in self.buffers().enumerate() {
                b[count..padded].fill(if k == 2 { 1.0 } else { 0.0 });
            }
            #[cfg(target_arch = "x86_64")]
            let done = if lights.avx2 {
                // SAFETY: the CPU has AVX2 and FMA (checked in FastLights::chosen).
                unsafe { shade_avx2(self, lights, column, padded) };
                true
            } else {
                false
            };
            #[cfg(not(target_arch = "x86_64"))]
            let done = false;
            if !done {
                shade_kernel(self, lights, column, padded);
            }
            // The radiance is in `diffuse`.
            let [acc_r, acc_g, acc_b] = acc;
            for (acc, rgb) in [acc_r, acc_g, acc_b].into_iter().zip(&self.diffuse) {
                if self.weighted {
                    for ((&p, x), w) in self.pixel[..count].iter().zip(&rgb[..count]).zip(&self.weight) {
                        acc[p as usize] += w * x;
                    }
                } else {
                    for (&p, x) in self.pixel[..count].iter().zip(&rgb[..count]) {
                        acc[p as usize] += x;
                    }
                }
            }
        }
        self.count = 0;
        self.weighted = false;
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn gather_avx2(b: &mut Batch, scene: &Scene, table: &SegmentTable, lights: &FastLights, acc: [&mut [f32]; 3]) {
    gather_kernel(b, scene, table, lights, acc);
}

#[inline(always)]
fn gather_kernel(b: &mut Batch, scene: &Scene, table: &SegmentTable, lights: &FastLights, acc: [&mut [f32]; 3]) {
    let len = b.count;
    let (owner, ts) = (&b.owner[..len], &b.t[..len]);
    let [nx, ny, nz] = &mut b.n;
    let (nx, ny, nz) = (&mut nx[..len], &mut ny[..len], &mut nz[..len]);
    let [alr, alg, alb] = &mut b.albedo;
    let (alr, alg, alb) = (&mut alr[..len], &mut alg[..len], &mut alb[..len]);
    let [kr, kg, kb] = &mut b.ks;
    let (kr, kg, kb) = (&mut kr[..len], &mut kg[..len], &mut kb[..len]);
    let (ex, xm) = (&mut b.exponent[..len], &mut b.x_min[..len]);
    let mut textured = false;
    for i in 0..len {
        let (o, t) = (owner[i] as usize, ts[i]);
        let (na, nd, sign) = (table.normal_a[o], table.normal_d[o], table.sign[o]);
        nx[i] = na[0] * sign + nd[0] * sign * t;
        ny[i] = na[1] * sign + nd[1] * sign * t;
        nz[i] = na[2] * sign + nd[2] * sign * t;
        let (ca, cd, base) = (table.colour_a[o], table.colour_d[o], table.base[o]);
        alr[i] = base[0] * (ca[0] + cd[0] * t);
        alg[i] = base[1] * (ca[1] + cd[1] * t);
        alb[i] = base[2] * (ca[2] + cd[2] * t);
        let ks = table.ks[o];
        kr[i] = ks[0];
        kg[i] = ks[1];
        kb[i] = ks[2];
        ex[i] = table.exponent[o];
        xm[i] = table.x_min[o];
        textured |= table.texture[o] != u32::MAX;
    }
    if textured {
        // The lookups of [`sample`], bit for bit, in three passes: the
        // coordinates and sizes fetched by segment; the footprints located
        // (f64 as in `sample`; for the non-negative coordinates kept,
        // truncation is `floor`) in a loop that vectorises; the texels
        // fetched and blended. Footprints that wrap or leave the texture
        // (and NaN) go to `sample` itself.
        let [us, vs] = &mut b.uv;
        let (us, vs) = (&mut us[..len], &mut vs[..len]);
        let [ws, hs] = &mut b.size;
        let (ws, hs, wi) = (&mut ws[..len], &mut hs[..len], &mut b.width[..len]);
        for i in 0..len {
            let (o, t) = (owner[i] as usize, ts[i]);
            let (ua, ud) = (table.uv_a[o], table.uv_d[o]);
            us[i] = ua[0] + ud[0] * t;
            vs[i] = ua[1] + ud[1] * t;
            [ws[i], hs[i]] = table.texture_size[o];
            wi[i] = table.texture_width[o];
        }
        let (index, fxs, fys) = (&mut b.index[..len], &mut b.fx[..len], &mut b.fy[..len]);
        for i in 0..len {
            let x = us[i] as f64 * ws[i] - 0.5;
            let y = vs[i] as f64 * hs[i] - 0.5;
            let inside = (x >= 0.0) & (y >= 0.0) & (x < ws[i] - 1.0) & (y < hs[i] - 1.0);
            let (xi, yi) = if inside { (x as i32, y as i32) } else { (0, 0) };
            fxs[i] = (x - xi as f64) as f32;
            fys[i] = (y - yi as f64) as f32;
            index[i] = if inside { yi * wi[i] + xi } else { -1 };
        }
        for i in 0..len {
            let texture = table.texture[owner[i] as usize];
            if texture == u32::MAX {
                continue;
            }
            let tex = &scene.textures[texture as usize];
            let texel = if index[i] >= 0 {
                let (at, w) = (index[i] as usize, tex.width);
                let (top, bottom) = (&tex.texels[at..at + 2], &tex.texels[at + w..at + w + 2]);
                bilerp([top[0], top[1], bottom[0], bottom[1]], fxs[i], fys[i])
            } else {
                sample(tex, [us[i], vs[i]])
            };
            alr[i] *= texel[0];
            alg[i] *= texel[1];
            alb[i] *= texel[2];
        }
    }
    if table.any_metallic_roughness {
        // Metallic-roughness materials: the terms per point, from the base
        // colour just found and their texture (looked up one by one).
        for i in 0..len {
            let (o, t) = (owner[i] as usize, ts[i]);
            if !table.metallic_roughness[o] {
                continue;
            }
            let m = table.material[o];
            let texel = m.metallic_roughness.as_ref().and_then(|mr| mr.texture.as_ref()).map(|r| {
                let (ua, ud) = (table.mr_uv_a[o], table.mr_uv_d[o]);
                sample_fast(&scene.textures[r.texture], [ua[0] + ud[0] * t, ua[1] + ud[1] * t])
            });
            let p = m.point_terms([alr[i], alg[i], alb[i]], texel);
            [alr[i], alg[i], alb[i]] = p.albedo;
            [kr[i], kg[i], kb[i]] = p.ks.map(|k| k * p.lobe_norm);
            ex[i] = p.exponent;
            xm[i] = p.x_min;
        }
    }
    let [acc_r, acc_g, acc_b] = acc;
    if b.weighted {
        // See-through surfaces: the same terms × each pixel's weight.
        for (i, &p) in b.pixel[..len].iter().enumerate() {
            let (p, o, w) = (p as usize, owner[i] as usize, b.weight[i]);
            let e = table.emissive[o];
            let ambient = if table.prelit[o] { [1.0; 3] } else { lights.ambient };
            acc_r[p] += w * (e[0] + alr[i] * ambient[0]);
            acc_g[p] += w * (e[1] + alg[i] * ambient[1]);
            acc_b[p] += w * (e[2] + alb[i] * ambient[2]);
            if table.prelit[o] {
                (alr[i], alg[i], alb[i]) = (0.0, 0.0, 0.0);
            }
        }
        return;
    }
    for (i, &p) in b.pixel[..len].iter().enumerate() {
        let (p, o) = (p as usize, owner[i] as usize);
        let e = table.emissive[o];
        if table.prelit[o] {
            // Sent as it is; no light reaches it but specular.
            acc_r[p] += e[0] + alr[i];
            acc_g[p] += e[1] + alg[i];
            acc_b[p] += e[2] + alb[i];
            (alr[i], alg[i], alb[i]) = (0.0, 0.0, 0.0);
        } else {
            acc_r[p] += e[0] + alr[i] * lights.ambient[0];
            acc_g[p] += e[1] + alg[i] * lights.ambient[1];
            acc_b[p] += e[2] + alb[i] * lights.ambient[2];
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn shade_avx2(b: &mut Batch, lights: &FastLights, column: &Column, len: usize) {
    shade_kernel(b, lights, column, len);
}

#[inline(always)]
fn shade_kernel(b: &mut Batch, lights: &FastLights, column: &Column, len: usize) {
    // Unit normals, in place.
    {
        let [nx, ny, nz] = &mut b.n;
        let (nx, ny, nz) = (&mut nx[..len], &mut ny[..len], &mut nz[..len]);
        for i in 0..len {
            let inv = 1.0 / (nx[i] * nx[i] + ny[i] * ny[i] + nz[i] * nz[i]).sqrt();
            nx[i] *= inv;
            ny[i] *= inv;
            nz[i] *= inv;
        }
    }
    let [nx, ny, nz] = &b.n;
    let (nx, ny, nz) = (&nx[..len], &ny[..len], &nz[..len]);
    let (exponent, x_min) = (&b.exponent[..len], &b.x_min[..len]);
    let [dr, dg, db] = &mut b.diffuse;
    let (dr, dg, db) = (&mut dr[..len], &mut dg[..len], &mut db[..len]);
    let [sr, sg, sb] = &mut b.specular;
    let (sr, sg, sb) = (&mut sr[..len], &mut sg[..len], &mut sb[..len]);
    dr.fill(0.0);
    dg.fill(0.0);
    db.fill(0.0);
    sr.fill(0.0);
    sg.fill(0.0);
    sb.fill(0.0);
    let view = column.view;
    let phong = lights.model == SpecularModel::Phong;
    for l in &column.directional {
        let (lt, e) = (l.to_light, l.irradiance);
        // x = α·(N·L)·(N·h) + β·(N·h) − γ: Blinn's N·H (h = H, α = γ = 0,
        // β = 1), Phong's R·V = 2(N·L)(N·V) − L·V (h = V, α = 2, β = 0, γ = L·V).
        let (h, alpha, beta, gamma) = if phong { (view, 2.0, 0.0, l.lv) } else { (l.half, 0.0, 1.0, 0.0) };
        for i in 0..len {
            let cos_i = nx[i] * lt[0] + ny[i] * lt[1] + nz[i] * lt[2];
            let lit = if cos_i > 0.0 { cos_i } else { 0.0 };
            dr[i] += e[0] * lit;
            dg[i] += e[1] * lit;
            db[i] += e[2] * lit;
            let nh = nx[i] * h[0] + ny[i] * h[1] + nz[i] * h[2];
            let x = alpha * cos_i * nh + beta * nh - gamma;
            let p = pow01(x, exponent[i]);
            let lobe = if x > x_min[i] { p } else { 0.0 } * lit;
            sr[i] += e[0] * lobe;
            sg[i] += e[1] * lobe;
            sb[i] += e[2] * lobe;
        }
    }
    // The radiance (directional part), into `diffuse`.
    let pi = std::f32::consts::FRAC_1_PI;
    for (c, (d, s)) in [dr, dg, db].into_iter().zip([&*sr, &*sg, &*sb]).enumerate() {
        let (al, k) = (&b.albedo[c][..len], &b.ks[c][..len]);
        for i in 0..len {
            d[i] = al[i] * d[i] * pi + k[i] * s[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn pow01_is_within_its_bound() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut worst = 0.0f64;
        for k in 0..200_000 {
            // Bases over the whole range and crowded near 1, where highlights are.
            let x: f32 = match k % 3 {
                0 => rng.gen_range(0.0..=1.0),
                1 => 1.0 - rng.gen_range(0.0f32..1e-2),
                _ => 2f32.powf(-rng.gen_range(0.0f32..40.0)),
            };
            let n: f32 = if k % 5 == 0 { rng.gen_range(0.0..4.0) } else { rng.gen_range(0.0..2000.0) };
            let exact = (x as f64).powf(n as f64);
            let got = pow01(x, n) as f64;
            let y = n as f64 * (x as f64).log2();
            if y >= -126.0 && x > 0.0 {
                let rel = (got - exact).abs() / exact;
                worst = worst.max(rel / (1e-6 + 3e-7 * y.abs()));
                assert!(rel <= 1e-6 + 3e-7 * y.abs(), "{x}^{n}: {got} vs {exact} (y = {y})");
            } else {
                assert!((got - exact).abs() < 1.2e-38, "{x}^{n}: {got} vs {exact}");
            }
        }
        println!("worst error / bound: {worst:.3}");
        assert_eq!(pow01(1.0, 500.0), 1.0);
        assert_eq!(pow01(0.0, 3.0), 0.0);
        assert_eq!(pow01(0.7, 0.0), 1.0);
    }

    #[test]
    fn fast_texture_lookup_is_the_reference_bit_for_bit() {
        use crate::mesh::Wrap;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for (w, h) in [(1, 1), (1, 7), (5, 1), (2, 2), (17, 9), (64, 64)] {
            for wrap in
                [[Wrap::Repeat, Wrap::ClampToEdge], [Wrap::MirroredRepeat, Wrap::Repeat], [Wrap::ClampToEdge; 2]]
            {
                let texels = (0..w * h).map(|_| std::array::from_fn(|_| rng.gen_range(0.0f32..1.0))).collect();
                let tex = Texture { name: "random".into(), width: w, height: h, texels, wrap };
                for k in 0..20_000 {
                    let uv: [f32; 2] = match k % 4 {
                        0 => [rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0)],
                        1 => [rng.gen_range(-3.0..3.0), rng.gen_range(-3.0..3.0)],
                        // On texel centres and edges, where floor and truncation could differ.
                        2 => [
                            (rng.gen_range(0..=2 * w) as f32) / (2 * w) as f32,
                            (rng.gen_range(0..=2 * h) as f32) / (2 * h) as f32,
                        ],
                        _ => [[f32::NAN, 1e30, -1e30, 0.5][k / 4 % 4], rng.gen_range(-1.0..1.0)],
                    };
                    let (fast, slow) = (sample_fast(&tex, uv), sample(&tex, uv));
                    assert_eq!(fast.map(f32::to_bits), slow.map(f32::to_bits), "{w}×{h} {wrap:?} at {uv:?}");
                }
            }
        }
    }

    #[test]
    fn skipped_lobes_are_below_the_floor() {
        for (n, ks) in [(1.0f32, 1.0f32), (30.0, 0.3), (200.0, 1.0), (5000.0, 0.04)] {
            for model in [SpecularModel::Phong, SpecularModel::Blinn] {
                let m = FastMaterial::new(&Material { shininess: n, specular: [ks; 3], ..Material::default() }, model);
                let x = m.x_min as f64;
                let lobe = m.lobe_norm as f64 * x.powf(n as f64) * ks as f64;
                assert!(lobe <= LOBE_FLOOR / std::f64::consts::PI, "n {n}: skipped lobe {lobe}");
                assert!(lobe >= 0.9 * LOBE_FLOOR / std::f64::consts::PI || x == 0.0, "n {n}: threshold {x} too low");
            }
        }
    }
}
