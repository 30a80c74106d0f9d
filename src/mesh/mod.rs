//! Meshes to modulation: scenes of triangles with materials and
//! lights, loaded from glTF, OBJ and PLY ([`load`]), placed in the display's
//! volume ([`place`]), shaded per view ([`shade`]) and rendered for every ray
//! (hololine, emitter, view) by a reference ray caster ([`trace`]) and by the
//! fast epipolar-plane rasteriser (`epi.rs`);
//! `cameras::mesh_picture` renders what a calibrated camera would
//! photograph of the same scene.
//!
//! A [`Scene`] is plain data in one space: the loaders give it in the file's
//! own units with every node transform applied ("world"); [`place`] maps
//! world onto display metres (docs/optics.md §1.2: `x` right, `y` up, `z` toward the
//! viewer, hologram at `z = 0`). Colours are linear: loaders decode sRGB.

pub(crate) mod bvh;
pub mod convert;
pub(crate) mod epi;
mod fastshade;
pub mod load;
pub mod normals;
pub mod place;
pub(crate) mod rays;
mod record;
pub mod render;
pub mod shade;
pub mod trace;
pub mod write;

/// A whole scene: objects, the textures they use, and lights.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Where the scene came from (file name), for messages.
    pub source: String,
    /// The objects, each with its own material.
    pub objects: Vec<Object>,
    /// Decoded textures, indexed by [`TextureRef::texture`].
    pub textures: Vec<Texture>,
    /// Lights the file defines (glTF `KHR_lights_punctual`). A render uses
    /// them, then any the user adds, unless its options say otherwise
    /// ([`render::RenderOptions::lighting_for`]).
    pub lights: Vec<Light>,
    /// Things the user should know that did not stop the load (a primitive
    /// that is not triangles, a texture that could not be decoded, ...),
    /// each naming the object.
    pub warnings: Vec<String>,
}

/// One object: a triangle mesh with one material, in world space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Object {
    /// Name for messages: the node/mesh/group name, or `#index`.
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Unit vertex normals; empty means flat shading from the face normals.
    pub normals: Vec<[f32; 3]>,
    /// Vertex tangents `xyz` with the bitangent sign in `w` (glTF convention);
    /// empty unless the material has a normal map.
    pub tangents: Vec<[f32; 4]>,
    /// Texture coordinate sets (`TEXCOORD_n`); each empty or one per vertex.
    pub uv_sets: Vec<Vec<[f32; 2]>>,
    /// Linear RGBA vertex colours multiplying the base colour; empty for none.
    pub colours: Vec<[f32; 4]>,
    /// Triangles as vertex indices, counter-clockwise seen from the front.
    pub triangles: Vec<[u32; 3]>,
    /// The material.
    pub material: Material,
}

/// A material in the terms the shader uses (see [`shade`] for the formulas).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name for messages.
    pub name: String,
    /// Linear RGBA base (diffuse) colour factor; its alpha is used as
    /// [`Material::alpha_mode`] says.
    pub base_colour: [f32; 4],
    /// Texture multiplying the base colour (sRGB-decoded).
    pub base_colour_texture: Option<TextureRef>,
    /// Tangent-space normal map (linear), and its scale.
    pub normal_texture: Option<TextureRef>,
    /// Scale of the normal map's x and y (glTF `normalTexture.scale`).
    pub normal_scale: f32,
    /// Emitted linear radiance factor.
    pub emissive: [f32; 3],
    /// Texture multiplying the emissive factor (sRGB-decoded).
    pub emissive_texture: Option<TextureRef>,
    /// Specular reflectance `k_s` (linear RGB); with
    /// [`Material::metallic_roughness`], that of the surface where it is not
    /// metal.
    pub specular: [f32; 3],
    /// Specular exponent `n` of `(R·V)^n` / `(N·H)^n`; with
    /// [`Material::metallic_roughness`], unused by the renderers (the
    /// roughness of each point gives it).
    pub shininess: f32,
    /// Metalness and roughness that vary over the surface (a glTF
    /// metallic-roughness texture); `None`: the surface is what
    /// `base_colour`, `specular` and `shininess` say everywhere. See
    /// [`shade`] for how a point's metalness and roughness become its
    /// diffuse colour, `k_s` and `n`.
    pub metallic_roughness: Option<MetallicRoughness>,
    /// How the alpha of a point (the base colour factor's × the vertex
    /// colour's × the base colour texture's) is used: ignored (opaque), cut
    /// at a threshold, or as the coverage through which what is behind
    /// shows (glTF `alphaMode`).
    pub alpha_mode: AlphaMode,
    /// Seen from both sides (glTF `doubleSided`); otherwise back faces are invisible.
    pub double_sided: bool,
    /// Pre-lit (a HoloFlick's micropolygons, Deering, *HoloFlicks* §8): the base colour
    /// (factor × vertex colour × texture) is the radiance the surface sends
    /// whatever the view — emission, ambient and diffuse light already baked
    /// in — and lights add only their specular term.
    pub prelit: bool,
    /// The specular lobe of this material; `None`: the render's
    /// ([`shade::Lighting::model`]).
    pub specular_model: Option<shade::SpecularModel>,
    /// The lights this material receives, as indices into the render's
    /// lights ([`render::RenderOptions::lighting_for`]: the scene's own
    /// first, then the options'; a set: order and repeats do not matter); `None`: all of them. Ambient lights are chosen like the
    /// others: with a selection, only the ambient lights it lists apply (a
    /// pre-lit material takes no ambient light either way). An index past
    /// the render's lights makes the render an error
    /// ([`shade::Lighting::problem_with`]).
    pub lights: Option<Vec<u32>>,
}

impl Material {
    /// Whether the material receives light `index` of the render's
    /// [`shade::Lighting::lights`] (see [`Material::lights`]).
    #[inline]
    pub fn receives_light(&self, index: usize) -> bool {
        self.lights.as_ref().map_or(true, |chosen| chosen.iter().any(|&i| i as usize == index))
    }
}

impl Default for Material {
    /// A white, matte, one-sided material: glTF's default material, and
    /// what OBJ and PLY objects without a material get.
    fn default() -> Self {
        Material {
            name: "default".into(),
            base_colour: [1.0; 4],
            base_colour_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            emissive: [0.0; 3],
            emissive_texture: None,
            specular: [0.04; 3],
            shininess: 10.0,
            metallic_roughness: None,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            prelit: false,
            specular_model: None,
            lights: None,
        }
    }
}

/// What a material does with the alpha of its points (glTF 2.0 §3.9.4,
/// `alphaMode`). The alpha of a point is the base colour factor's alpha ×
/// the vertex colour's × the base colour texture's.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface is opaque (OBJ and PLY materials, and
    /// glTF's default).
    #[default]
    Opaque,
    /// Opaque where alpha ≥ `cutoff`, wholly transparent elsewhere.
    Mask {
        /// glTF `alphaCutoff` (0.5 when the file gives none).
        cutoff: f32,
    },
    /// Alpha is how much of a ray the surface covers: a ray's radiance is
    /// the front-to-back composite of the surfaces it crosses,
    /// `L = Σ_i L_i α_i Π_{k<i} (1 − α_k)`, an opaque surface ending it.
    Blend,
}

/// Metalness and roughness over a surface, as glTF's metallic-roughness
/// material gives them (glTF 2.0 §3.9.2): each the factor × the texture's
/// channel (roughness in G, metalness in B; linear), clamped to `[0, 1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct MetallicRoughness {
    /// Metalness factor.
    pub metallic: f32,
    /// Roughness factor.
    pub roughness: f32,
    /// The texture (linear); `None`: the factors alone.
    pub texture: Option<TextureRef>,
}

/// A material's use of a texture.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`Scene::textures`].
    pub texture: usize,
    /// Which of the object's [`Object::uv_sets`] to use.
    pub uv_set: usize,
    /// `KHR_texture_transform`, applied to the coordinates before lookup.
    pub transform: UvTransform,
}

/// An affine transform of texture coordinates (glTF `KHR_texture_transform`):
/// `uv' = T(offset) · R(rotation) · S(scale) · uv`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Translation.
    pub offset: [f32; 2],
    /// Rotation in radians, counter-clockwise in UV space.
    pub rotation_rad: f32,
    /// Scale.
    pub scale: [f32; 2],
}

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform { offset: [0.0; 2], rotation_rad: 0.0, scale: [1.0; 2] }
    }
}

impl UvTransform {
    /// Apply to a coordinate (matrix of the KHR_texture_transform spec).
    #[inline]
    pub fn apply(&self, uv: [f32; 2]) -> [f32; 2] {
        if *self == UvTransform::default() {
            return uv;
        }
        let (s, c) = self.rotation_rad.sin_cos();
        let (x, y) = (uv[0] * self.scale[0], uv[1] * self.scale[1]);
        [c * x + s * y + self.offset[0], -s * x + c * y + self.offset[1]]
    }
}

/// How texture coordinates outside `[0, 1]` wrap (glTF sampler modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Wrap {
    /// Tile.
    #[default]
    Repeat,
    /// Tile, mirroring every other copy.
    MirroredRepeat,
    /// Hold the edge texel.
    ClampToEdge,
}

/// A decoded texture: linear RGBA texels, row 0 at `v = 0` (the top of the
/// image, glTF convention; OBJ's `v` points up and its loader flips it).
#[derive(Clone, Debug, Default)]
pub struct Texture {
    /// Name for messages (the image's file name or glTF name).
    pub name: String,
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// `width × height` linear RGBA texels, row by row.
    pub texels: Vec<[f32; 4]>,
    /// Wrap in `u` and `v`.
    pub wrap: [Wrap; 2],
}

/// A light. Intensities are linear RGB; the shading formulas are in [`shade`].
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// A point light: `E = I / d²` at distance `d`.
    Point {
        /// Position.
        position: [f64; 3],
        /// Intensity `I` (glTF: candela).
        intensity: [f32; 3],
        /// Name for messages.
        name: String,
    },
    /// A directional light: irradiance `E` on a surface facing it.
    Directional {
        /// Unit direction the light travels in (glTF: the node's −z).
        direction: [f64; 3],
        /// Irradiance `E` (glTF: lux).
        irradiance: [f32; 3],
        /// Name for messages.
        name: String,
    },
    /// Ambient light: radiance `L_a` reflected by the base colour.
    Ambient {
        /// `L_a`.
        radiance: [f32; 3],
    },
}

impl Light {
    /// Its kind, as a light spec (`crate::mesh::shade::parse_light`) and
    /// `holo.convert.light<i>.kind` name it.
    pub fn kind(&self) -> &'static str {
        match self {
            Light::Point { .. } => "point",
            Light::Directional { .. } => "directional",
            Light::Ambient { .. } => "ambient",
        }
    }
}

impl Scene {
    /// Number of triangles in all objects.
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.triangles.len()).sum()
    }

    /// The first thing that makes the scene unrenderable (a vertex index
    /// out of range, a non-finite position or light, an attribute array of
    /// the wrong length, a texture reference to nothing), naming the object.
    pub fn problem(&self) -> Option<String> {
        for (oi, o) in self.objects.iter().enumerate() {
            let name = if o.name.is_empty() { format!("#{oi}") } else { o.name.clone() };
            let n = o.positions.len();
            if let Some(v) = o.positions.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
                return Some(format!("object {name:?}: vertex {v} has a non-finite position"));
            }
            if let Some(t) = o.triangles.iter().position(|t| t.iter().any(|&i| i as usize >= n)) {
                return Some(format!("object {name:?}: triangle {t} uses a vertex past the {n} it has"));
            }
            for (what, len) in
                [("normals", o.normals.len()), ("tangents", o.tangents.len()), ("colours", o.colours.len())]
            {
                if len != 0 && len != n {
                    return Some(format!("object {name:?}: {len} {what} for {n} vertices"));
                }
            }
            if o.uv_sets.iter().any(|s| !s.is_empty() && s.len() != n) {
                return Some(format!("object {name:?}: a texture coordinate set does not have one entry per vertex"));
            }
            let m = &o.material;
            if let AlphaMode::Mask { cutoff } = m.alpha_mode {
                if !cutoff.is_finite() {
                    return Some(format!("object {name:?}: material {:?} has the alpha cutoff {cutoff}", m.name));
                }
            }
            if let Some(mr) = &m.metallic_roughness {
                if !(mr.metallic.is_finite() && mr.roughness.is_finite()) {
                    return Some(format!(
                        "object {name:?}: material {:?} has the metalness {} and roughness {}",
                        m.name, mr.metallic, mr.roughness
                    ));
                }
            }
            let metallic_roughness = m.metallic_roughness.as_ref().and_then(|mr| mr.texture.as_ref());
            for r in [
                m.base_colour_texture.as_ref(),
                m.normal_texture.as_ref(),
                m.emissive_texture.as_ref(),
                metallic_roughness,
            ]
            .into_iter()
            .flatten()
            {
                if r.texture >= self.textures.len() {
                    return Some(format!(
                        "object {name:?}: material {:?} uses texture {} of {}",
                        m.name,
                        r.texture,
                        self.textures.len()
                    ));
                }
            }
        }
        for (i, t) in self.textures.iter().enumerate() {
            if t.texels.len() != t.width * t.height {
                return Some(format!(
                    "texture {i} ({:?}): {} texels for {}x{}",
                    t.name,
                    t.texels.len(),
                    t.width,
                    t.height
                ));
            }
        }
        None
    }

    /// The axis-aligned box of every vertex a triangle uses, or `None` for
    /// a scene without triangles.
    pub fn bounds(&self) -> Option<([f64; 3], [f64; 3])> {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut any = false;
        for o in &self.objects {
            for t in &o.triangles {
                for &i in t {
                    let p = o.positions[i as usize];
                    for k in 0..3 {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                    any = true;
                }
            }
        }
        any.then_some((lo, hi))
    }
}
