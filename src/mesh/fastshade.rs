//! The rasteriser's shader: the formulas of [`super::shade`] in f32, on
//! surface attributes interpolated linearly along a segment instead of
//! looked up per hit. Along one hololine's segment every attribute is affine
//! in the segment parameter, so this is exact up to f32 rounding; the tests
//! compare the two renderers, which holds the two shaders together.
#![allow(clippy::needless_range_loop)] // RGB loops read best with the index

use super::shade::{sample, Lighting, SpecularModel};
use super::{Light, Material, Object, Scene, TextureRef};

/// A material in the form the per-pixel loop wants.
pub(crate) struct FastMaterial {
    base: [f32; 3],
    emissive: [f32; 3],
    ks: [f32; 3],
    exponent: f32,
    /// Lobe normalisation, `(n+2)/2π` or `(n+8)/8π`.
    lobe_norm: f32,
    specular: bool,
    base_texture: Option<TextureRef>,
    emissive_texture: Option<TextureRef>,
    normal_texture: Option<TextureRef>,
    normal_scale: f32,
}

impl FastMaterial {
    pub(crate) fn new(m: &Material, model: SpecularModel) -> Self {
        let n = m.shininess.max(0.0);
        let lobe_norm = match model {
            SpecularModel::Phong => (n + 2.0) / (2.0 * std::f32::consts::PI),
            SpecularModel::Blinn => (n + 8.0) / (8.0 * std::f32::consts::PI),
        };
        FastMaterial {
            base: [m.base_colour[0], m.base_colour[1], m.base_colour[2]],
            emissive: m.emissive,
            ks: m.specular,
            exponent: n,
            lobe_norm,
            specular: m.specular.iter().any(|&k| k > 0.0),
            base_texture: m.base_colour_texture.clone(),
            emissive_texture: m.emissive_texture.clone(),
            normal_texture: m.normal_texture.clone(),
            normal_scale: m.normal_scale,
        }
    }
}

/// Lights in f32, ambient summed.
pub(crate) struct FastLights {
    directional: Vec<([f32; 3], [f32; 3])>,
    point: Vec<([f32; 3], [f32; 3])>,
    ambient: [f32; 3],
    model: SpecularModel,
}

impl FastLights {
    pub(crate) fn new(l: &Lighting) -> Self {
        let mut out = FastLights { directional: vec![], point: vec![], ambient: [0.0; 3], model: l.model };
        for light in &l.lights {
            match light {
                Light::Directional { direction, irradiance, .. } => {
                    let to = [-direction[0] as f32, -direction[1] as f32, -direction[2] as f32];
                    out.directional.push((normalize(to), *irradiance));
                }
                Light::Point { position, intensity, .. } => {
                    out.point.push(([position[0] as f32, position[1] as f32, position[2] as f32], *intensity));
                }
                Light::Ambient { radiance } => {
                    for c in 0..3 {
                        out.ambient[c] += radiance[c];
                    }
                }
            }
        }
        out
    }
}

/// Surface attributes at one end of a segment.
#[derive(Clone, Copy, Default)]
pub(crate) struct Attrs {
    pub pos: [f32; 3],
    /// Interpolated vertex normal (not unit), or the face normal.
    pub normal: [f32; 3],
    pub colour: [f32; 3],
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
            for q in 0..3 {
                pos[q] += o.positions[i][q] * w[k];
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
        a.pos = [pos[0] as f32, pos[1] as f32, pos[2] as f32];
        if o.normals.is_empty() {
            a.normal = [unit_face[0] as f32, unit_face[1] as f32, unit_face[2] as f32];
        }
        if o.colours.is_empty() {
            a.colour = [1.0; 3];
        }
        a
    }

    #[inline]
    pub(crate) fn lerp(&self, b: &Attrs, t: f32) -> Attrs {
        let l = |x: f32, y: f32| x + (y - x) * t;
        let l3 = |x: [f32; 3], y: [f32; 3]| [l(x[0], y[0]), l(x[1], y[1]), l(x[2], y[2])];
        Attrs {
            pos: l3(self.pos, b.pos),
            normal: l3(self.normal, b.normal),
            colour: l3(self.colour, b.colour),
            uv: [
                [l(self.uv[0][0], b.uv[0][0]), l(self.uv[0][1], b.uv[0][1])],
                [l(self.uv[1][0], b.uv[1][0]), l(self.uv[1][1], b.uv[1][1])],
            ],
            tangent: [
                l(self.tangent[0], b.tangent[0]),
                l(self.tangent[1], b.tangent[1]),
                l(self.tangent[2], b.tangent[2]),
                l(self.tangent[3], b.tangent[3]),
            ],
        }
    }
}

/// Radiance of a point with attributes `a` on a surface with unit face
/// normal `face` (already facing the viewer), seen along unit `view`.
/// `flip`: the point is on a back face (double-sided), so the vertex normal flips.
#[inline]
#[allow(clippy::too_many_arguments)] // the per-pixel inputs, kept apart so nothing is recomputed
pub(crate) fn radiance(
    scene: &Scene,
    lights: &FastLights,
    m: &FastMaterial,
    has_normals: bool,
    has_tangents: bool,
    a: &Attrs,
    face: [f32; 3],
    flip: bool,
    view: [f32; 3],
) -> [f32; 3] {
    let mut normal = if has_normals { normalize_or(a.normal, face) } else { face };
    if flip && has_normals {
        normal = scale(normal, -1.0);
    }
    let uv = |r: &TextureRef| -> [f32; 2] {
        let c = if r.uv_set < 2 { a.uv[r.uv_set] } else { [0.0; 2] };
        r.transform.apply(c)
    };
    if let (Some(r), true) = (&m.normal_texture, has_tangents) {
        let tg = [a.tangent[0], a.tangent[1], a.tangent[2]];
        let tangent = sub(tg, scale(normal, dot(normal, tg)));
        let len2 = dot(tangent, tangent);
        if len2 > 0.0 && len2.is_finite() {
            let tangent = scale(tangent, 1.0 / len2.sqrt());
            let bitangent = scale(cross(normal, tangent), if a.tangent[3] < 0.0 { -1.0 } else { 1.0 });
            let texel = sample(&scene.textures[r.texture], uv(r));
            let nx = (texel[0] * 2.0 - 1.0) * m.normal_scale;
            let ny = (texel[1] * 2.0 - 1.0) * m.normal_scale;
            let nz = texel[2] * 2.0 - 1.0;
            let mapped = add(add(scale(tangent, nx), scale(bitangent, ny)), scale(normal, nz));
            normal = normalize_or(mapped, normal);
        }
    }
    let mut base = [m.base[0] * a.colour[0], m.base[1] * a.colour[1], m.base[2] * a.colour[2]];
    if let Some(r) = &m.base_texture {
        let texel = sample(&scene.textures[r.texture], uv(r));
        base = [base[0] * texel[0], base[1] * texel[1], base[2] * texel[2]];
    }
    let mut out = m.emissive;
    if let Some(r) = &m.emissive_texture {
        let texel = sample(&scene.textures[r.texture], uv(r));
        out = [out[0] * texel[0], out[1] * texel[1], out[2] * texel[2]];
    }
    for c in 0..3 {
        out[c] += base[c] * lights.ambient[c];
    }
    let diffuse = scale(base, std::f32::consts::FRAC_1_PI);
    let mut light = |to_light: [f32; 3], e: [f32; 3]| {
        let cos_i = dot(normal, to_light);
        if cos_i <= 0.0 {
            return;
        }
        let mut brdf = diffuse;
        if m.specular {
            let x = match lights.model {
                SpecularModel::Phong => {
                    let r = sub(scale(normal, 2.0 * cos_i), to_light);
                    dot(r, view)
                }
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
            if x > 0.0 {
                let lobe = m.lobe_norm * x.powf(m.exponent);
                for c in 0..3 {
                    brdf[c] += m.ks[c] * lobe;
                }
            }
        }
        for c in 0..3 {
            out[c] += e[c] * brdf[c] * cos_i;
        }
    };
    for &(to_light, e) in &lights.directional {
        light(to_light, e);
    }
    for &(p, i) in &lights.point {
        let d = sub(p, a.pos);
        let d2 = dot(d, d);
        if d2 > 0.0 {
            let inv = 1.0 / d2;
            light(scale(d, inv.sqrt()), [i[0] * inv, i[1] * inv, i[2] * inv]);
        }
    }
    out
}

#[inline]
fn add(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
#[inline]
fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
fn scale(a: [f32; 3], s: f32) -> [f32; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
#[inline]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
#[inline]
pub(crate) fn normalize(a: [f32; 3]) -> [f32; 3] {
    normalize_or(a, [0.0, 0.0, 1.0])
}
#[inline]
fn normalize_or(a: [f32; 3], fallback: [f32; 3]) -> [f32; 3] {
    let l2 = dot(a, a);
    if l2 > 0.0 && l2.is_finite() {
        scale(a, 1.0 / l2.sqrt())
    } else {
        fallback
    }
}
