//! Shading: the linear radiance a surface point sends toward the viewer
//! along one ray, from ambient, diffuse and specular terms (Nelson 1993 ch. 4),
//! with Phong `(R·V)^n` or Blinn `(N·H)^n` lobes.
//!
//! For a point with base colour `ρ`, emission `L_e`, specular reflectance
//! `k_s` and exponent `n`, seen along unit view vector `V` (from the point
//! toward the viewer) with shading normal `N`:
//!
//! ```text
//! L = L_e + ρ·L_a + Σ_lights E_i · max(N·L_i, 0) · (ρ/π + k_s · lobe)
//! Phong: lobe = (n + 2)/(2π) · max(R_i·V, 0)^n,   R_i = 2(N·L_i)N − L_i
//! Blinn: lobe = (n + 8)/(8π) · max(N·H_i, 0)^n,   H_i = (L_i + V)/|L_i + V|
//! ```
//!
//! `E_i` is the irradiance the light gives a surface facing it (`I/d²` for a
//! point light) and `L_i` the unit vector toward the light. The lobes carry
//! their usual normalisations, so a white diffuse surface under `E = π`
//! has radiance 1 and raising `n` narrows a highlight without changing its
//! energy. No shadows (the seeds' renderers had none either). The sum (the
//! ambient `L_a` included) runs over the lights the material receives, with
//! the material's lobe when it names one ([`super::Material::lights`],
//! [`super::Material::specular_model`]; by default every light and the
//! render's lobe).
//!
//! A material with [`super::Material::metallic_roughness`] (glTF's
//! metallic-roughness texture) has at each point a metalness `m` and a
//! roughness `r` (factor × texture channel, clamped to `[0, 1]`). With `ρ_b`
//! the base colour there (factor × vertex colour × texture) and `k_d` the
//! material's `specular` (the reflectance where it is not metal: glTF's
//! 0.04), the terms above are those the glTF 2.0 specification's BRDF
//! (Appendix B) gives a metallic-roughness material:
//!
//! ```text
//! ρ = ρ_b·(1 − m),   k_s = k_d + (ρ_b − k_d)·m,   n = 2/α² − 2,  α = max(r², 0.01)
//! ```
//!
//! A metal has no diffuse part and reflects its base colour; a dielectric
//! reflects 4 % of the light, white. The exponent: glTF's microfacet
//! distribution is GGX of width `α = r²`, and a Blinn lobe `(N·H)^n` is a
//! Beckmann distribution of width `α` when `n = 2/α² − 2` (Walter et al.
//! 2007); GGX and Beckmann agree near the peak, which is what a highlight
//! shows ([`exponent_of_roughness`]). `α` is clamped at 0.01 so a
//! mirror-smooth surface gets a finite exponent (19 998). Fresnel's rise at
//! grazing angles and the masking term are left out, as in the mapping the
//! glTF loader makes of materials without the texture.
//!
//! [`coverage`] is the alpha of a point as [`super::Material::alpha_mode`]
//! uses it; the renderers composite the surfaces a ray crosses with it.
//!
//! Everything here is f64 and table-free: the reference ray caster and the
//! fast rasteriser shade with the same function, so comparing them tests
//! visibility, and the tests below test the formulas.

use super::{AlphaMode, Light, Object, Scene, Texture, TextureRef, Wrap};
use crate::math::{add, cross, dot, mul, narrow, normalize, normalize_or, scale, sub, widen};
use crate::sampling::bilerp;

/// Which specular lobe.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum SpecularModel {
    /// `(R·V)^n`, Phong 1975.
    Phong,
    /// `(N·H)^n`, Blinn 1977 (the default: it is what glTF roughness maps to).
    #[default]
    Blinn,
}

impl SpecularModel {
    /// Every lobe.
    pub const ALL: [SpecularModel; 2] = [SpecularModel::Blinn, SpecularModel::Phong];

    /// Name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            SpecularModel::Phong => "phong",
            SpecularModel::Blinn => "blinn",
        }
    }
}

/// The lights of a render and the lobe they use. A material may take its
/// own lobe ([`Material::specular_model`](super::Material::specular_model))
/// and receive only some of the lights
/// ([`Material::lights`](super::Material::lights)).
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// Lights (ambient ones summed).
    pub lights: Vec<Light>,
    /// Specular lobe of materials that do not choose their own.
    pub model: SpecularModel,
}

impl Lighting {
    /// The first material of `scene` that chooses a light these lights do
    /// not have, described; `None` when there is none.
    pub fn problem_with(&self, scene: &Scene) -> Option<String> {
        scene.objects.iter().find_map(|o| {
            let chosen = o.material.lights.as_ref()?;
            let bad = chosen.iter().find(|&&i| i as usize >= self.lights.len())?;
            Some(format!(
                "object {:?}: its material {:?} receives light {bad}, but the render has {} lights",
                o.name,
                o.material.name,
                self.lights.len()
            ))
        })
    }

    /// [`Lighting::default_lights`] as [`parse_light`] specs, for a user who
    /// gives lights of their own (which replace these) and wants to keep them.
    pub const DEFAULT_SPECS: [&'static str; 2] = ["dir:1,-1,-1", "ambient:0.08,0.08,0.08"];

    /// The lights used when neither the scene nor the user gives any
    /// ([`super::render::RenderOptions::default_lights`]): one
    /// white directional key light from the upper left, in front, travelling
    /// along `(1, −1, −1)` (so a white surface facing it has radiance 1), and
    /// a dim ambient of 0.08 ([`Lighting::DEFAULT_SPECS`]). Any light given
    /// replaces both: a surface turned from the key light is then as dark as
    /// the lights given leave it.
    pub fn default_lights() -> Vec<Light> {
        let d = normalize([1.0, -1.0, -1.0]);
        vec![
            Light::Directional {
                direction: d,
                irradiance: [std::f32::consts::PI; 3],
                name: "default key light".into(),
            },
            Light::Ambient { radiance: [0.08; 3] },
        ]
    }
}

/// A light from the command line or a light file, in display coordinates
/// (`x` right, `y` up, `z` toward the viewer; docs/optics.md §1.2):
///
/// - `dir:DX,DY,DZ[:R,G,B]`: a directional light travelling along
///   `(DX, DY, DZ)`, the direction its light goes, not the direction toward
///   the light (`dir:0,0,-1` shines from the viewer's side onto the scene's
///   front), giving irradiance `R,G,B` (default π: a white surface facing it
///   has radiance 1);
/// - `point:X,Y,Z[:R,G,B]`: a point light at `(X, Y, Z)` millimetres, giving
///   irradiance `R,G,B` (default π) at `centre_m`, the middle of the display
///   volume (so its intensity is `E·d²`);
/// - `ambient:R,G,B`: ambient radiance.
///
/// A malformed spec is an [`Error::Argument`](crate::error::Error::Argument) whose
/// sentence quotes it.
pub fn parse_light(spec: &str, centre_m: [f64; 3]) -> crate::error::Result<Light> {
    light_from_spec(spec, centre_m).map_err(|problem| crate::error::Error::argument("light", problem))
}

/// [`parse_light`], its error the phrase that quotes the spec.
fn light_from_spec(spec: &str, centre_m: [f64; 3]) -> Result<Light, String> {
    let bad = |why: &str| {
        format!("light {spec:?}: {why}; expected dir:DX,DY,DZ[:R,G,B], point:X,Y,Z[:R,G,B] or ambient:R,G,B")
    };
    let numbers = |t: &str| -> Result<[f64; 3], String> {
        let v: Vec<f64> = t
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad("not numbers"))?;
        match v.as_slice() {
            [a, b, c] if v.iter().all(|x| x.is_finite()) => Ok([*a, *b, *c]),
            _ => Err(bad("three finite numbers needed")),
        }
    };
    let mut parts = spec.splitn(3, ':');
    let kind = parts.next().unwrap_or("").trim();
    let first = parts.next().ok_or_else(|| bad("no values"))?;
    let colour = match parts.next() {
        Some(c) => {
            let c = numbers(c)?;
            if c.iter().any(|&x| x < 0.0) {
                return Err(bad("negative brightness"));
            }
            c
        }
        None => [std::f64::consts::PI; 3],
    };
    match kind {
        "dir" | "directional" => {
            let d = numbers(first)?;
            if dot(d, d) == 0.0 {
                return Err(bad("zero direction"));
            }
            Ok(Light::Directional { direction: normalize(d), irradiance: narrow(colour), name: spec.to_string() })
        }
        "point" => {
            let p = scale(numbers(first)?, 1e-3);
            let d = sub(p, centre_m);
            let d2 = dot(d, d);
            if d2 == 0.0 {
                return Err(bad("the light is at the centre of the display volume"));
            }
            Ok(Light::Point { position: p, intensity: narrow(scale(colour, d2)), name: spec.to_string() })
        }
        "ambient" => {
            let c = numbers(first)?;
            if c.iter().any(|&x| x < 0.0) {
                return Err(bad("negative brightness"));
            }
            Ok(Light::Ambient { radiance: narrow(c) })
        }
        _ => Err(bad("unknown kind")),
    }
}

/// Lights from a file: one [`parse_light`] spec per line; `#` starts a comment.
pub fn read_lights(path: &std::path::Path, centre_m: [f64; 3]) -> crate::error::Result<Vec<Light>> {
    let text = std::fs::read_to_string(path).map_err(|e| crate::error::Error::io(path, e))?;
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        out.push(
            light_from_spec(line, centre_m)
                .map_err(|e| crate::error::Error::scene(path, format!("line {}: {e}", n + 1)))?,
        );
    }
    Ok(out)
}

/// A point where a ray meets a triangle: the object, the triangle and the
/// barycentric weights of its second and third vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Index into [`Scene::objects`].
    pub object: u32,
    /// Index into the object's triangles.
    pub triangle: u32,
    /// Weight of vertex 1.
    pub b1: f64,
    /// Weight of vertex 2.
    pub b2: f64,
}

/// The unnormalised geometric normal of a triangle (counter-clockwise front).
#[inline]
pub fn face_normal(o: &Object, t: usize) -> [f64; 3] {
    let [a, b, c] = o.triangles[t];
    let (p0, p1, p2) = (o.positions[a as usize], o.positions[b as usize], o.positions[c as usize]);
    cross(sub(p1, p0), sub(p2, p0))
}

/// The Blinn exponent of glTF roughness `r` (see the module's text):
/// `n = 2/α² − 2` with `α = max(r², 0.01)`.
pub fn exponent_of_roughness(roughness: f64) -> f64 {
    let alpha = (roughness * roughness).max(0.01);
    2.0 / (alpha * alpha) - 2.0
}

/// The barycentric weights of `hit`.
fn weights(hit: &Hit) -> [f64; 3] {
    [1.0 - hit.b1 - hit.b2, hit.b1, hit.b2]
}

/// The coordinates texture `r` is looked up at, at weights `w` of triangle
/// `tri` of `o` (`[0, 0]` when the object lacks the set).
fn uv_at(o: &Object, tri: [u32; 3], w: [f64; 3], r: &TextureRef) -> [f32; 2] {
    let set = match o.uv_sets.get(r.uv_set) {
        Some(s) if !s.is_empty() => s,
        _ => return [0.0, 0.0],
    };
    let mut uv = [0.0f64; 2];
    for (k, &i) in tri.iter().enumerate() {
        let c = set[i as usize];
        uv[0] += c[0] as f64 * w[k];
        uv[1] += c[1] as f64 * w[k];
    }
    r.transform.apply([uv[0] as f32, uv[1] as f32])
}

/// How much of a ray the point `hit` covers, as its material's
/// [`AlphaMode`] says: 1 for an opaque material; for a masked one 1 where
/// the point's alpha (base colour factor × vertex colour × base colour
/// texture) reaches the cutoff and 0 elsewhere; for a blended one that
/// alpha, clamped to `[0, 1]`.
pub fn coverage(scene: &Scene, hit: &Hit) -> f64 {
    let o = &scene.objects[hit.object as usize];
    let m = &o.material;
    let cutoff = match m.alpha_mode {
        AlphaMode::Opaque => return 1.0,
        AlphaMode::Mask { cutoff } => Some(cutoff as f64),
        AlphaMode::Blend => None,
    };
    let (tri, w) = (o.triangles[hit.triangle as usize], weights(hit));
    let mut alpha = m.base_colour[3] as f64;
    if !o.colours.is_empty() {
        alpha *= tri.iter().enumerate().map(|(k, &i)| o.colours[i as usize][3] as f64 * w[k]).sum::<f64>();
    }
    if let Some(r) = &m.base_colour_texture {
        alpha *= sample(&scene.textures[r.texture], uv_at(o, tri, w, r))[3] as f64;
    }
    match cutoff {
        Some(c) => f64::from(u8::from(alpha >= c)),
        None => alpha.clamp(0.0, 1.0),
    }
}

/// Radiance (linear RGB) sent from `hit` along the unit vector `view`
/// (pointing from the surface toward the viewer), from the lights the hit
/// object's material receives with its lobe (see [`Lighting`]).
pub fn radiance(scene: &Scene, lighting: &Lighting, hit: &Hit, view: [f64; 3]) -> [f64; 3] {
    let o = &scene.objects[hit.object as usize];
    let t = hit.triangle as usize;
    let tri = o.triangles[t];
    let w = weights(hit);
    let m = &o.material;
    let mut position = [0.0; 3];
    for (k, &i) in tri.iter().enumerate() {
        position = add(position, scale(o.positions[i as usize], w[k]));
    }
    let face = normalize(face_normal(o, t));
    let flip = dot(face, view) < 0.0; // a back face (only reached when double-sided)
    let face = if flip { scale(face, -1.0) } else { face };

    let mut normal = if o.normals.is_empty() {
        face
    } else {
        let mut n = [0.0; 3];
        for (k, &i) in tri.iter().enumerate() {
            n = add(n, scale(widen(o.normals[i as usize]), w[k]));
        }
        let n = normalize_or(n, face);
        if flip {
            scale(n, -1.0)
        } else {
            n
        }
    };

    let uv = |r: &TextureRef| uv_at(o, tri, w, r);

    if let Some(r) = &m.normal_texture {
        if !o.tangents.is_empty() {
            let mut tangent = [0.0; 3];
            let mut sign = 0.0;
            for (k, &i) in tri.iter().enumerate() {
                let tg = o.tangents[i as usize];
                tangent = add(tangent, scale(widen([tg[0], tg[1], tg[2]]), w[k]));
                sign += tg[3] as f64 * w[k];
            }
            // Gram-Schmidt against the (unflipped) normal; the bitangent's sign from w.
            let tangent = normalize_or(sub(tangent, scale(normal, dot(normal, tangent))), [0.0; 3]);
            if tangent != [0.0; 3] {
                let bitangent = scale(cross(normal, tangent), if sign < 0.0 { -1.0 } else { 1.0 });
                let texel = sample(&scene.textures[r.texture], uv(r));
                let nx = (texel[0] as f64 * 2.0 - 1.0) * m.normal_scale as f64;
                let ny = (texel[1] as f64 * 2.0 - 1.0) * m.normal_scale as f64;
                let nz = texel[2] as f64 * 2.0 - 1.0;
                let mapped = add(add(scale(tangent, nx), scale(bitangent, ny)), scale(normal, nz));
                normal = normalize_or(mapped, normal);
            }
        }
    }

    let mut base = widen([m.base_colour[0], m.base_colour[1], m.base_colour[2]]);
    if !o.colours.is_empty() {
        let mut c = [0.0; 3];
        for (k, &i) in tri.iter().enumerate() {
            c = add(
                c,
                scale(
                    {
                        let c = o.colours[i as usize];
                        widen([c[0], c[1], c[2]])
                    },
                    w[k],
                ),
            );
        }
        base = mul(base, c);
    }
    if let Some(r) = &m.base_colour_texture {
        let texel = sample(&scene.textures[r.texture], uv(r));
        base = mul(base, widen([texel[0], texel[1], texel[2]]));
    }
    let mut ks = widen(m.specular);
    let mut n_exp = m.shininess.max(0.0) as f64;
    if let Some(mr) = &m.metallic_roughness {
        let (mut metal, mut rough) = (mr.metallic as f64, mr.roughness as f64);
        if let Some(r) = &mr.texture {
            let texel = sample(&scene.textures[r.texture], uv(r));
            metal *= texel[2] as f64;
            rough *= texel[1] as f64;
        }
        let metal = metal.clamp(0.0, 1.0);
        ks = add(ks, scale(sub(base, ks), metal));
        base = scale(base, 1.0 - metal);
        n_exp = exponent_of_roughness(rough.clamp(0.0, 1.0));
    }
    let mut out = widen(m.emissive);
    if let Some(r) = &m.emissive_texture {
        let texel = sample(&scene.textures[r.texture], uv(r));
        out = mul(out, widen([texel[0], texel[1], texel[2]]));
    }
    if m.prelit {
        // Already lit: sent as it is; lights add their specular term only.
        out = add(out, base);
        base = [0.0; 3];
    }
    let diffuse = scale(base, std::f64::consts::FRAC_1_PI);
    let model = m.specular_model.unwrap_or(lighting.model);
    for (index, light) in lighting.lights.iter().enumerate() {
        if !m.receives_light(index) {
            continue;
        }
        let (to_light, e) = match light {
            Light::Ambient { radiance } => {
                out = add(out, mul(base, widen(*radiance)));
                continue;
            }
            Light::Directional { direction, irradiance, .. } => {
                (normalize(scale(*direction, -1.0)), widen(*irradiance))
            }
            Light::Point { position: p, intensity, .. } => {
                let d = sub(*p, position);
                let d2 = dot(d, d);
                if d2 <= 0.0 {
                    continue;
                }
                (scale(d, 1.0 / d2.sqrt()), scale(widen(*intensity), 1.0 / d2))
            }
        };
        let cos_i = dot(normal, to_light);
        if cos_i <= 0.0 {
            continue;
        }
        let lobe = match model {
            SpecularModel::Phong => {
                let r = sub(scale(normal, 2.0 * cos_i), to_light);
                let rv = dot(r, view).max(0.0);
                (n_exp + 2.0) / (2.0 * std::f64::consts::PI) * rv.powf(n_exp)
            }
            SpecularModel::Blinn => {
                let h = normalize_or(add(to_light, view), normal);
                let nh = dot(normal, h).max(0.0);
                (n_exp + 8.0) / (8.0 * std::f64::consts::PI) * nh.powf(n_exp)
            }
        };
        let brdf = add(diffuse, scale(ks, lobe));
        out = add(out, scale(mul(e, brdf), cos_i));
    }
    out
}

/// Bilinear lookup of a texture at `uv` with its wrap modes (texel centres
/// at half-integers, as in OpenGL and glTF).
pub fn sample(tex: &Texture, uv: [f32; 2]) -> [f32; 4] {
    if tex.width == 0 || tex.height == 0 || !uv[0].is_finite() || !uv[1].is_finite() {
        return [1.0; 4];
    }
    let x = uv[0] as f64 * tex.width as f64 - 0.5;
    let y = uv[1] as f64 * tex.height as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
    let at = |i: f64, j: f64| -> [f32; 4] {
        let c = wrap(i as i64, tex.width, tex.wrap[0]);
        let r = wrap(j as i64, tex.height, tex.wrap[1]);
        tex.texels[r * tex.width + c]
    };
    bilerp([at(x0, y0), at(x0 + 1.0, y0), at(x0, y0 + 1.0), at(x0 + 1.0, y0 + 1.0)], fx, fy)
}

fn wrap(i: i64, n: usize, mode: Wrap) -> usize {
    let n = n as i64;
    let r = match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let p = i.rem_euclid(2 * n);
            if p < n {
                p
            } else {
                2 * n - 1 - p
            }
        }
    };
    r as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Material, Object};

    fn plane(material: Material) -> Scene {
        // A unit square in z = 0 facing +z.
        let o = Object {
            name: "plane".into(),
            positions: vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            material,
            ..Object::default()
        };
        Scene { objects: vec![o], ..Scene::default() }
    }

    #[test]
    fn the_default_lights_are_their_specs_and_dir_is_where_the_light_goes() {
        let parsed: Vec<Light> =
            Lighting::DEFAULT_SPECS.iter().map(|s| parse_light(s, [0.0, 0.0, 0.1]).unwrap()).collect();
        let named = |l: &Light| match l {
            Light::Directional { direction, irradiance, .. } => (0, *direction, irradiance.map(f64::from)),
            Light::Ambient { radiance } => (1, [0.0; 3], radiance.map(f64::from)),
            Light::Point { position, intensity, .. } => (2, *position, intensity.map(f64::from)),
        };
        let defaults: Vec<_> = Lighting::default_lights().iter().map(named).collect();
        assert_eq!(parsed.iter().map(named).collect::<Vec<_>>(), defaults);
        // dir:0,0,-1 travels away from the viewer: it lights a face turned
        // toward the viewer (+z), not one turned away.
        let lighting =
            Lighting { lights: vec![parse_light("dir:0,0,-1", [0.0; 3]).unwrap()], model: Default::default() };
        let white = Material { specular: [0.0; 3], ..Material::default() };
        let hit = Hit { object: 0, triangle: 0, b1: 0.25, b2: 0.25 };
        let front = radiance(&plane(white.clone()), &lighting, &hit, [0.0, 0.0, 1.0]);
        assert!((front[0] - 1.0).abs() < 1e-6, "{front:?}");
        let behind = Lighting { lights: vec![parse_light("dir:0,0,1", [0.0; 3]).unwrap()], model: Default::default() };
        assert_eq!(radiance(&plane(white), &behind, &hit, [0.0, 0.0, 1.0]), [0.0; 3]);
    }

    #[test]
    fn prelit_surfaces_send_their_colour_and_only_specular_light() {
        let base = [0.3f32, 0.2, 0.1, 1.0];
        let prelit = plane(Material {
            base_colour: base,
            specular: [0.5; 3],
            shininess: 30.0,
            prelit: true,
            ..Material::default()
        });
        // The specular term alone: the same plane, black, not pre-lit.
        let black =
            plane(Material { base_colour: [0.0, 0.0, 0.0, 1.0], prelit: false, ..prelit.objects[0].material.clone() });
        let l = Lighting {
            lights: vec![
                Light::Directional { direction: normalize([0.2, 0.0, -1.0]), irradiance: [2.0; 3], name: "l".into() },
                Light::Ambient { radiance: [0.4; 3] },
            ],
            model: SpecularModel::Blinn,
        };
        let hit = Hit { object: 0, triangle: 0, b1: 0.3, b2: 0.2 };
        for view in [[0.0, 0.0, 1.0], normalize([-0.2, 0.0, 1.0]), normalize([0.6, 0.1, 1.0])] {
            let (r, spec) = (radiance(&prelit, &l, &hit, view), radiance(&black, &l, &hit, view));
            for c in 0..3 {
                assert!((r[c] - (base[c] as f64 + spec[c])).abs() < 1e-12, "{r:?} vs {spec:?}");
            }
        }
    }

    /// A material choosing light 1 of three gets exactly what a render of
    /// light 1 alone gives it (ambient included: light 2, not chosen, adds
    /// nothing); a Phong material in a Blinn render is shaded as in a Phong
    /// render.
    #[test]
    fn materials_choose_their_lights_and_lobe() {
        let material =
            Material { base_colour: [0.6, 0.5, 0.4, 1.0], specular: [0.5; 3], shininess: 30.0, ..Material::default() };
        let key = Light::Directional { direction: normalize([0.3, 0.1, -1.0]), irradiance: [2.0; 3], name: "0".into() };
        let fill = Light::Point { position: [-0.5, 0.4, 2.0], intensity: [3.0, 2.0, 1.0], name: "1".into() };
        let ambient = Light::Ambient { radiance: [0.2; 3] };
        let all = Lighting { lights: vec![key, fill.clone(), ambient], model: SpecularModel::Blinn };
        let hit = Hit { object: 0, triangle: 0, b1: 0.3, b2: 0.2 };
        let chosen = plane(Material { lights: Some(vec![1]), ..material.clone() });
        let whole = plane(material.clone());
        let only_fill = Lighting { lights: vec![fill], ..all.clone() };
        for view in [[0.0, 0.0, 1.0], normalize([-0.3, 0.0, 1.0]), normalize([0.5, -0.2, 1.0])] {
            let got = radiance(&chosen, &all, &hit, view);
            assert_eq!(got, radiance(&whole, &only_fill, &hit, view), "view {view:?}");
            assert!(got[0] < radiance(&whole, &all, &hit, view)[0] - 1e-3, "the other lights are left out");
        }
        // Ambient is chosen like any light: {2} is the ambient term alone.
        let ambient_only = plane(Material { lights: Some(vec![2]), ..material.clone() });
        let r = radiance(&ambient_only, &all, &hit, [0.0, 0.0, 1.0]);
        let expected: [f64; 3] = std::array::from_fn(|c| 0.0 + material.base_colour[c] as f64 * 0.2f32 as f64);
        assert_eq!(r, expected);
        // The lobe: Phong in a Blinn render is a Phong render.
        let phong = plane(Material { specular_model: Some(SpecularModel::Phong), ..material.clone() });
        let phong_render = Lighting { model: SpecularModel::Phong, ..all.clone() };
        for view in [[0.0, 0.0, 1.0], normalize([-0.3, 0.0, 1.0]), normalize([0.5, -0.2, 1.0])] {
            let got = radiance(&phong, &all, &hit, view);
            assert_eq!(got, radiance(&whole, &phong_render, &hit, view), "view {view:?}");
            assert_ne!(got, radiance(&whole, &all, &hit, view), "the lobes differ here");
        }
        // An index past the render's lights is the render's error, naming the object.
        let bad = plane(Material { lights: Some(vec![0, 3]), ..material });
        let e = all.problem_with(&bad).unwrap();
        assert!(e.contains("plane") && e.contains("light 3"), "{e}");
        assert_eq!(all.problem_with(&chosen), None);
    }

    #[test]
    fn white_diffuse_under_pi_irradiance_is_one() {
        let s = plane(Material { specular: [0.0; 3], ..Material::default() });
        let l = Lighting {
            lights: vec![Light::Directional {
                direction: [0.0, 0.0, -1.0],
                irradiance: [std::f32::consts::PI; 3],
                name: "l".into(),
            }],
            model: SpecularModel::Phong,
        };
        let hit = Hit { object: 0, triangle: 0, b1: 0.3, b2: 0.2 };
        for view in [[0.0, 0.0, 1.0], normalize([0.5, 0.1, 1.0])] {
            let r = radiance(&s, &l, &hit, view);
            for c in r {
                assert!((c - 1.0).abs() < 1e-6, "{r:?}"); // E is π rounded to f32
            }
        }
    }

    #[test]
    fn lobes_peak_at_the_mirror_direction_with_their_formulas() {
        let s = plane(Material {
            base_colour: [0.0, 0.0, 0.0, 1.0],
            specular: [1.0; 3],
            shininess: 40.0,
            ..Material::default()
        });
        let to_light = normalize([-0.4, 0.0, 1.0]);
        let light = Light::Directional { direction: scale(to_light, -1.0), irradiance: [1.0; 3], name: "l".into() };
        let mirror = [-to_light[0], 0.0, to_light[2]];
        let hit = Hit { object: 0, triangle: 0, b1: 0.3, b2: 0.2 };
        for model in [SpecularModel::Phong, SpecularModel::Blinn] {
            let l = Lighting { lights: vec![light.clone()], model };
            let at = |theta: f64| radiance(&s, &l, &hit, [theta.sin(), 0.0, theta.cos()])[0];
            let peak = mirror[0].atan2(mirror[2]);
            assert!(at(peak) > at(peak + 0.02) && at(peak) > at(peak - 0.02), "{model:?}");
            // An independent evaluation of the formula 0.1 rad away from the peak.
            let theta = peak + 0.1;
            let v = [theta.sin(), 0.0, theta.cos()];
            let n: f64 = 40.0;
            let expected = to_light[2]
                * match model {
                    SpecularModel::Phong => (n + 2.0) / (2.0 * std::f64::consts::PI) * dot(mirror, v).powf(n),
                    SpecularModel::Blinn => {
                        let h = normalize(add(to_light, v));
                        (n + 8.0) / (8.0 * std::f64::consts::PI) * h[2].powf(n)
                    }
                };
            assert!((at(theta) - expected).abs() < 1e-12 * expected.max(1.0), "{model:?}");
        }
    }

    #[test]
    fn texture_lookup_wraps_and_interpolates() {
        let tex = Texture {
            name: "t".into(),
            width: 2,
            height: 1,
            texels: vec![[0.0; 4], [1.0; 4]],
            wrap: [Wrap::Repeat, Wrap::ClampToEdge],
        };
        assert_eq!(sample(&tex, [0.25, 0.5])[0], 0.0);
        assert_eq!(sample(&tex, [0.75, 0.5])[0], 1.0);
        assert!((sample(&tex, [0.5, 0.5])[0] - 0.5).abs() < 1e-6);
        assert!((sample(&tex, [1.0, 0.5])[0] - 0.5).abs() < 1e-6, "repeat joins the edges");
        let clamp = Texture { wrap: [Wrap::ClampToEdge; 2], ..tex.clone() };
        assert_eq!(sample(&clamp, [1.0, 0.5])[0], 1.0);
        let mirror = Texture { wrap: [Wrap::MirroredRepeat; 2], ..tex };
        assert_eq!(sample(&mirror, [1.25, 0.5])[0], 1.0);
    }
}
