//! glTF 2.0 (`.gltf` with external or embedded buffers, `.glb`).
//!
//! The `gltf` crate parses and validates the JSON (and splits a `.glb`);
//! buffers, images and accessors are read here, so that every size and
//! offset is checked against the bytes present and every message names the
//! mesh, primitive, accessor, material or texture concerned.
//!
//! [`GltfSource::open`] reads the geometry in each mesh's own space, the
//! materials, the textures and the animation curves once;
//! [`GltfSource::scene_at`] poses the node hierarchy at a time and moves the
//! geometry to world space.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use gltf::accessor::{DataType, Dimensions};
use gltf::animation::{Interpolation, Property};
use gltf::khr_lights_punctual::Kind as LightKind;
use gltf::mesh::{Mode, Semantic};

mod animation;
mod buffers;

use self::animation::{trs, Channel};
use self::buffers::{percent_decode, read_buffers, read_uri, Buffers};
use super::texture::{decode, generate_tangents};
use super::{file_name, finish_scene, Extent, LoadLimits, Referenced};
use crate::error::{Error, Result};
use crate::math::{
    cofactor3, det3, linear, mat3_apply, mat_mul, transform_direction, transform_point, translation, transpose, unit,
    Mat3, Mat4, IDENTITY4,
};
use crate::mesh::{
    AlphaMode, Light, Material, MetallicRoughness, Object, Scene, Texture, TextureRef, UvTransform, Wrap,
};

/// An opened glTF file, ready to be posed.
#[derive(Debug)]
pub(crate) struct GltfSource {
    textures: Vec<Texture>,
    materials: Vec<Material>,
    meshes: Vec<MeshData>,
    nodes: Vec<NodeData>,
    /// Nodes of the scene in parent-before-child order, with their parent.
    order: Vec<(usize, Option<usize>)>,
    channels: Vec<Channel>,
    lights: Vec<LightDef>,
    skins: Vec<SkinData>,
    duration: Option<f64>,
    /// Warnings found while opening, repeated in every scene.
    warnings: Vec<String>,
}

#[derive(Debug)]
struct MeshData {
    label: String,
    name: Option<String>,
    weights: Vec<f32>,
    prims: Vec<Prim>,
}

#[derive(Debug, Default)]
struct Prim {
    /// Why the primitive is not drawn (points, lines, no positions).
    skip: Option<String>,
    material: Option<usize>,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    tangents: Vec<[f32; 4]>,
    uv_sets: Vec<Vec<[f32; 2]>>,
    colours: Vec<[f32; 4]>,
    triangles: Vec<[u32; 3]>,
    targets: Vec<MorphTarget>,
    /// Per vertex, each influence set `JOINTS_n` / `WEIGHTS_n`: four joints
    /// (indices into the skin's list) and their weights.
    joints: Vec<Vec<[f32; 4]>>,
    joint_weights: Vec<Vec<[f32; 4]>>,
}

/// A skin (glTF 2.0 §3.7.3): its joint nodes and their inverse bind
/// matrices (row-major; identity where the file gives none).
#[derive(Debug)]
struct SkinData {
    joints: Vec<usize>,
    inverse_bind: Vec<Mat4>,
}

#[derive(Debug, Default)]
struct MorphTarget {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    tangents: Vec<[f32; 3]>,
}

#[derive(Debug)]
struct NodeData {
    name: Option<String>,
    /// Row-major, transposed from the file's column-major list.
    matrix: Option<Mat4>,
    translation: [f64; 3],
    rotation: [f64; 4],
    scale: [f64; 3],
    mesh: Option<usize>,
    skin: Option<usize>,
    weights: Option<Vec<f32>>,
    light: Option<usize>,
    animated: bool,
}

#[derive(Debug, Clone, Copy)]
enum LightType {
    Point,
    Directional,
    Spot,
}

#[derive(Debug)]
struct LightDef {
    name: String,
    kind: LightType,
    rgb: [f32; 3],
}

/// Cofactor matrix of the linear part (`det · M⁻ᵀ`) with the sign of the
/// determinant: it maps normals like the inverse transpose up to a positive
/// factor, and exists even for singular matrices.
fn normal_matrix(m: &Mat4) -> Mat3 {
    let lin = linear(m);
    let s = if det3(&lin) < 0.0 { -1.0 } else { 1.0 };
    cofactor3(&lin).map(|row| row.map(|v| v * s))
}

fn mode_name(m: Mode) -> &'static str {
    match m {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

fn wrap_of(m: gltf::texture::WrappingMode) -> Wrap {
    match m {
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
    }
}

/// Context for reading one file.
struct Reader<'a> {
    path: &'a Path,
    dir: PathBuf,
    buffers: Buffers,
    limits: &'a LoadLimits,
    files: &'a mut Referenced,
    textures: Vec<Texture>,
    /// (image, sRGB, wrap) → index in `textures`.
    texture_cache: HashMap<(usize, bool, [u8; 2]), usize>,
}

impl Reader<'_> {
    fn err(&self, problem: String) -> Error {
        Error::scene(self.path, problem)
    }

    /// Read an accessor that must have `comps` components per element, as
    /// `f32` vectors, all finite. `ctx` names the mesh, primitive and
    /// attribute for messages.
    fn floats<const N: usize>(&self, acc: &gltf::Accessor, ctx: &str, max_count: usize) -> Result<Vec<[f32; N]>> {
        let (v, comps) =
            self.buffers.read(acc, max_count).map_err(|e| self.err(format!("{ctx} accessor {} {e}", acc.index())))?;
        if comps != N {
            return Err(
                self.err(format!("{ctx} accessor {} has {comps} components per element; {N} are needed", acc.index()))
            );
        }
        let mut out = Vec::with_capacity(v.len() / N);
        for (i, ch) in v.chunks_exact(N).enumerate() {
            let mut e = [0.0f32; N];
            for (k, x) in ch.iter().enumerate() {
                let f = *x as f32;
                if !f.is_finite() {
                    return Err(self.err(format!("{ctx} accessor {} holds {x} at vertex {i}", acc.index())));
                }
                e[k] = f;
            }
            out.push(e);
        }
        Ok(out)
    }

    /// Every material, its metallic-roughness terms turned into the
    /// shader's Phong terms, with the textures it uses.
    fn materials(&mut self, doc: &gltf::Document) -> Result<Vec<Material>> {
        doc.materials().map(|m| self.material(doc, &m)).collect()
    }

    fn material(&mut self, doc: &gltf::Document, m: &gltf::Material) -> Result<Material> {
        let name = m.name().map(str::to_string).unwrap_or_else(|| format!("#{}", m.index().unwrap_or(0)));
        let pbr = m.pbr_metallic_roughness();
        let base = pbr.base_color_factor();
        let metallic = pbr.metallic_factor().clamp(0.0, 1.0);
        let roughness = pbr.roughness_factor().clamp(0.0, 1.0);
        // Metallic-roughness to the shader's Phong terms. A metal
        // reflects its base colour specularly and has no diffuse part; a
        // dielectric reflects 4 % specularly (F0 = 0.04):
        //   specular = lerp(0.04, base.rgb, metallic)
        //   diffuse  = base.rgb · (1 − metallic)
        // The GGX lobe of width α = roughness² matches a Blinn-Phong
        // lobe (N·H)^n with n = 2/α² − 2 (Walter et al. 2007, the
        // Beckmann/Phong equivalence); α is clamped to ≥ 0.01 so a
        // mirror-smooth material gets a finite exponent (19 998). With a
        // metallic-roughness texture the same is done point by point
        // (crate::mesh::shade), from the factors × the texture.
        let specular = [0, 1, 2].map(|k| 0.04 + (base[k] - 0.04) * metallic);
        let mut mat = Material {
            name: name.clone(),
            base_colour: [base[0] * (1.0 - metallic), base[1] * (1.0 - metallic), base[2] * (1.0 - metallic), base[3]],
            specular,
            shininess: crate::mesh::fastshade::exponent_of_roughness(roughness),
            emissive: m.emissive_factor(),
            double_sided: m.double_sided(),
            ..Material::default()
        };
        if let Some(s) = m.emissive_strength() {
            mat.emissive = mat.emissive.map(|e| e * s);
        }
        if let Some(info) = pbr.base_color_texture() {
            let t = self.texture(doc, info.texture(), true, &name, "base colour")?;
            mat.base_colour_texture = Some(texture_ref(&info, t));
        }
        if let Some(info) = m.emissive_texture() {
            let t = self.texture(doc, info.texture(), true, &name, "emissive")?;
            mat.emissive_texture = Some(texture_ref(&info, t));
        }
        if let Some(nt) = m.normal_texture() {
            let t = self.texture(doc, nt.texture(), false, &name, "normal")?;
            let (transform, tc) = uv_transform_json(nt.extension_value("KHR_texture_transform"));
            mat.normal_texture =
                Some(TextureRef { texture: t, uv_set: tc.unwrap_or(nt.tex_coord()) as usize, transform });
            mat.normal_scale = nt.scale();
        }
        if let Some(info) = pbr.metallic_roughness_texture() {
            // Metalness in B, roughness in G (linear), each × its factor:
            // the terms are found point by point, from the base colour as
            // the file gives it and the dielectric's reflectance.
            let t = self.texture(doc, info.texture(), false, &name, "metallic-roughness")?;
            mat.base_colour = base;
            mat.specular = [0.04; 3];
            mat.metallic_roughness =
                Some(MetallicRoughness { metallic, roughness, texture: Some(texture_ref(&info, t)) });
        }
        mat.alpha_mode = match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
            gltf::material::AlphaMode::Mask => {
                let cutoff = m.alpha_cutoff().unwrap_or(0.5);
                if cutoff.is_nan() || cutoff < 0.0 {
                    return Err(self.err(format!(
                        "material \"{name}\": its alphaCutoff is {cutoff}; glTF 2.0 requires a cutoff of 0 or more"
                    )));
                }
                AlphaMode::Mask { cutoff }
            }
        };
        Ok(mat)
    }

    /// Every skin's joints and inverse bind matrices, checked.
    fn skins(&self, doc: &gltf::Document) -> Result<Vec<SkinData>> {
        let nodes = doc.nodes().count();
        let mut skins = Vec::new();
        for s in doc.skins() {
            let joints: Vec<usize> = s.joints().map(|j| j.index()).collect();
            if let Some(&bad) = joints.iter().find(|&&j| j >= nodes) {
                return Err(
                    self.err(format!("skin {} names joint node {bad}, but the file has {nodes} nodes", s.index()))
                );
            }
            let inverse_bind = match s.inverse_bind_matrices() {
                Some(acc) => {
                    let ctx = format!("skin {} inverseBindMatrices", s.index());
                    let m = self.floats::<16>(&acc, &ctx, joints.len())?;
                    if m.len() != joints.len() {
                        return Err(self.err(format!("{ctx} holds {} matrices for {} joints", m.len(), joints.len())));
                    }
                    // glTF lists a matrix column by column.
                    m.iter()
                        .map(|c| {
                            transpose(&std::array::from_fn(|col| std::array::from_fn(|row| c[col * 4 + row] as f64)))
                        })
                        .collect()
                }
                None => vec![IDENTITY4; joints.len()],
            };
            skins.push(SkinData { joints, inverse_bind });
        }
        Ok(skins)
    }

    /// Every mesh's primitives, in the mesh's own space.
    fn meshes(
        &mut self,
        doc: &gltf::Document,
        materials: &[Material],
        warnings: &mut Vec<String>,
    ) -> Result<Vec<MeshData>> {
        let max_vertices = self.limits.max_triangles.saturating_mul(3).max(3);
        let mut meshes = Vec::new();
        for m in doc.meshes() {
            let label = mesh_label(&m);
            let mut prims = Vec::new();
            for p in m.primitives() {
                let ctx = format!("mesh {label} primitive {}:", p.index());
                let prim = read_primitive(self, &p, &ctx, max_vertices, materials, warnings)?;
                prims.push(prim);
            }
            meshes.push(MeshData {
                label,
                name: m.name().map(str::to_string),
                weights: m.weights().map(<[f32]>::to_vec).unwrap_or_default(),
                prims,
            });
        }
        Ok(meshes)
    }

    /// Every animation channel's curve, checked, and the time of the last
    /// key of any of them; the nodes they move are marked animated.
    fn animations(&self, doc: &gltf::Document, nodes: &mut [NodeData]) -> Result<(Vec<Channel>, Option<f64>)> {
        let mut channels = Vec::new();
        let mut duration: Option<f64> = None;
        for a in doc.animations() {
            let aname = a.name().map(|s| format!("\"{s}\"")).unwrap_or_else(|| format!("#{}", a.index()));
            for ch in a.channels() {
                let ctx = format!("animation {aname} channel {}:", ch.index());
                // The target is read from the JSON: the `gltf` crate does
                // not validate it and would panic on a bad node index.
                let target = doc
                    .as_json()
                    .animations
                    .get(a.index())
                    .and_then(|aj| aj.channels.get(ch.index()))
                    .map(|c| &c.target);
                let Some(target) = target else { continue };
                let channel = self.channel(&ch, target, &ctx, nodes.len())?;
                if let Some(nd) = nodes.get_mut(channel.node) {
                    if channel.property != Property::MorphTargetWeights {
                        nd.animated = true;
                    }
                }
                let last = *channel.times.last().unwrap_or(&0.0) as f64;
                duration = Some(duration.map_or(last, |d| d.max(last)));
                channels.push(channel);
            }
        }
        Ok((channels, duration))
    }

    /// One channel: its target node and property, key times that do not go
    /// backwards, and finite values, as many as its keys need.
    fn channel(
        &self,
        ch: &gltf::animation::Channel,
        target: &gltf::json::animation::Target,
        ctx: &str,
        n_nodes: usize,
    ) -> Result<Channel> {
        let path = self.path;
        let node = target.node.value();
        if node >= n_nodes {
            return Err(Error::scene(path, format!("{ctx} targets node {node}, but the file has {n_nodes} nodes")));
        }
        let property = match target.path {
            gltf::json::validation::Checked::Valid(p) => p,
            gltf::json::validation::Checked::Invalid => {
                return Err(Error::scene(path, format!("{ctx} targets an unknown property")))
            }
        };
        let sampler = ch.sampler();
        let interpolation = sampler.interpolation();
        let times: Vec<f32> = self
            .floats::<1>(&sampler.input(), &format!("{ctx} input"), usize::MAX)?
            .into_iter()
            .map(|x| x[0])
            .collect();
        if times.is_empty() {
            return Err(Error::scene(
                path,
                format!("{ctx} input accessor {} has no key times", sampler.input().index()),
            ));
        }
        if let Some(k) = times.windows(2).position(|w| w[1] < w[0]) {
            return Err(Error::scene(
                path,
                format!("{ctx} input accessor {}: key times go backwards at key {}", sampler.input().index(), k + 1),
            ));
        }
        let out = sampler.output();
        let (vals, comps) = self
            .buffers
            .read(&out, usize::MAX)
            .map_err(|e| Error::scene(path, format!("{ctx} output accessor {} {e}", out.index())))?;
        if let Some(i) = vals.iter().position(|v| !v.is_finite()) {
            return Err(Error::scene(
                path,
                format!("{ctx} output accessor {} holds {} at value {i}", out.index(), vals[i]),
            ));
        }
        let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 } * times.len();
        let width = match property {
            Property::Translation | Property::Scale => 3,
            Property::Rotation => 4,
            Property::MorphTargetWeights => {
                if comps != 1 {
                    0
                } else {
                    vals.len() / per_key
                }
            }
        };
        if width == 0 || vals.len() != per_key * width || (property != Property::MorphTargetWeights && comps != width) {
            return Err(Error::scene(
                path,
                format!(
                    "{ctx} output accessor {} holds {} numbers, which does not fit {} keys of this property",
                    out.index(),
                    vals.len(),
                    times.len()
                ),
            ));
        }
        Ok(Channel {
            node,
            property,
            interpolation,
            times,
            values: vals.into_iter().map(|v| v as f32).collect(),
            width,
        })
    }

    /// The texture for a texture info, decoded once per (image, colour space, wrap).
    fn texture(
        &mut self,
        doc: &gltf::Document,
        tex: gltf::texture::Texture,
        srgb: bool,
        material: &str,
        slot: &str,
    ) -> Result<usize> {
        let img = tex.source();
        let sampler = tex.sampler();
        let wrap = [wrap_of(sampler.wrap_s()), wrap_of(sampler.wrap_t())];
        let key = (img.index(), srgb, wrap.map(|w| w as u8));
        if let Some(&i) = self.texture_cache.get(&key) {
            return Ok(i);
        }
        // The image's JSON is read directly: `Image::source` panics on an
        // image with a buffer view but no MIME type, or with neither.
        let json = doc.as_json().images.get(img.index());
        let view = json.and_then(|j| j.buffer_view).map(|v| v.value());
        let uri = json.and_then(|j| j.uri.as_deref());
        let (name, bytes) = match (view, uri) {
            (Some(v), _) => {
                let name = img.name().map(str::to_string).unwrap_or_else(|| format!("image {}", img.index()));
                let bytes = match doc.views().nth(v) {
                    Some(view) => self.buffers.view(&view).map(|b| b.to_vec()),
                    None => Err(format!("uses buffer view {v}, which does not exist")),
                };
                (name, bytes)
            }
            (None, None) => (format!("image {}", img.index()), Err("has neither a uri nor a bufferView".to_string())),
            (None, Some(uri)) => {
                let name = img.name().map(str::to_string).unwrap_or_else(|| {
                    if uri.starts_with("data:") {
                        format!("image {}", img.index())
                    } else {
                        percent_decode(uri)
                    }
                });
                let extent = Extent::AtMost { bytes: super::texture_file_bytes(self.limits), what: "texture" };
                (name, read_uri(&self.dir, uri, self.files, extent))
            }
        };
        let what = format!("material \"{material}\": {slot} texture {} (\"{name}\")", tex.index());
        let bytes = bytes.map_err(|e| self.err(format!("{what} {e}")))?;
        let t = decode(&bytes, &name, srgb, wrap, self.limits).map_err(|e| self.err(format!("{what} {e}")))?;
        self.textures.push(t);
        let i = self.textures.len() - 1;
        self.texture_cache.insert(key, i);
        Ok(i)
    }
}

/// The glTF extensions this loader reads. `KHR_mesh_quantization` needs
/// nothing of its own: every accessor is read in whatever component type it
/// has (normalized or not), and the node transforms undo the quantization.
const SUPPORTED_EXTENSIONS: [&str; 4] =
    ["KHR_texture_transform", "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_mesh_quantization"];

/// Refuse a file that requires an extension this loader does not read; one
/// that only uses such an extension is read with a warning naming it, since
/// what the extension changes is not drawn.
fn check_extensions(path: &Path, doc: &gltf::Document, warnings: &mut Vec<String>) -> Result<()> {
    for ext in doc.extensions_required() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            return Err(Error::scene(
                path,
                format!("requires the glTF extension {ext}, which this loader does not support"),
            ));
        }
    }
    for ext in doc.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) && !doc.extensions_required().any(|r| r == ext) {
            warnings.push(format!(
                "{}: uses the glTF extension {ext}, which holo does not read; what it changes is not drawn",
                file_name(path)
            ));
        }
    }
    Ok(())
}

/// The scene's node hierarchy, parent before child, with each node's
/// parent; a node reached twice (a cycle or a shared child) is refused.
fn node_order(path: &Path, doc: &gltf::Document) -> Result<Vec<(usize, Option<usize>)>> {
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    let all_nodes: Vec<gltf::Node> = doc.nodes().collect();
    let mut order = Vec::new();
    let mut seen = vec![false; all_nodes.len()];
    if let Some(scene) = &scene {
        let mut stack: Vec<(usize, Option<usize>)> = scene.nodes().map(|n| (n.index(), None)).collect();
        stack.reverse();
        while let Some((n, parent)) = stack.pop() {
            if std::mem::replace(&mut seen[n], true) {
                return Err(Error::scene(
                    path,
                    format!("node {n} is reached twice in scene {}: the node hierarchy must be a tree", scene.index()),
                ));
            }
            order.push((n, parent));
            if let Some(node) = all_nodes.get(n) {
                let mut kids: Vec<_> = node.children().map(|c| (c.index(), Some(n))).collect();
                kids.reverse();
                stack.extend(kids);
            }
        }
    }
    Ok(order)
}

/// Refuse, before any geometry is read, a scene whose drawn triangles
/// (each mesh's times the nodes that draw it) exceed the limit.
fn check_triangle_budget(
    path: &Path,
    doc: &gltf::Document,
    order: &[(usize, Option<usize>)],
    limits: &LoadLimits,
) -> Result<()> {
    let all_nodes: Vec<gltf::Node> = doc.nodes().collect();
    let mut instances = vec![0usize; doc.meshes().len()];
    for &(n, _) in order {
        if let Some(m) = all_nodes.get(n).and_then(|n| n.mesh()) {
            instances[m.index()] += 1;
        }
    }
    let mut total: u128 = 0;
    for m in doc.meshes() {
        for p in m.primitives() {
            let n =
                p.indices().map(|a| a.count()).or_else(|| p.get(&Semantic::Positions).map(|a| a.count())).unwrap_or(0);
            let tris = match p.mode() {
                Mode::Triangles => n / 3,
                Mode::TriangleStrip | Mode::TriangleFan => n.saturating_sub(2),
                _ => 0,
            };
            total += tris as u128 * instances[m.index()] as u128;
            if total > limits.max_triangles as u128 {
                return Err(Error::scene(
                    path,
                    format!(
                        "mesh {} primitive {}: the scene reaches {total} triangles here, more than the limit of {}",
                        mesh_label(&m),
                        p.index(),
                        limits.max_triangles
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// A node's local transform (a matrix, or translation, rotation and
/// scale), mesh, morph weights and light, not yet animated.
fn node_data(n: &gltf::Node) -> NodeData {
    let matrix = match n.transform() {
        // glTF lists a matrix column by column.
        gltf::scene::Transform::Matrix { matrix } => Some(transpose(&matrix.map(|c| c.map(|x| x as f64)))),
        _ => None,
    };
    let (t, r, s) = n.transform().decomposed();
    NodeData {
        name: n.name().map(str::to_string),
        matrix,
        translation: t.map(|x| x as f64),
        rotation: r.map(|x| x as f64),
        scale: s.map(|x| x as f64),
        mesh: n.mesh().map(|m| m.index()),
        skin: n.skin().map(|s| s.index()),
        weights: n.weights().map(<[f32]>::to_vec),
        light: n.light().map(|l| l.index()),
        animated: false,
    }
}

/// A `KHR_lights_punctual` light: its kind and its colour times intensity.
fn light_def(l: &gltf::khr_lights_punctual::Light) -> LightDef {
    let c = l.color();
    let i = l.intensity();
    LightDef {
        name: l.name().map(str::to_string).unwrap_or_else(|| format!("light {}", l.index())),
        kind: match l.kind() {
            LightKind::Directional => LightType::Directional,
            LightKind::Point => LightType::Point,
            LightKind::Spot { .. } => LightType::Spot,
        },
        rgb: [c[0] * i, c[1] * i, c[2] * i],
    }
}

fn uv_transform_json(v: Option<&serde_json::Value>) -> (UvTransform, Option<u32>) {
    let mut t = UvTransform::default();
    let Some(v) = v else { return (t, None) };
    let pair = |k: &str, d: [f32; 2]| -> [f32; 2] {
        v.get(k)
            .and_then(|a| a.as_array())
            .filter(|a| a.len() == 2)
            .map(|a| [a[0].as_f64().unwrap_or(d[0] as f64) as f32, a[1].as_f64().unwrap_or(d[1] as f64) as f32])
            .unwrap_or(d)
    };
    t.offset = pair("offset", [0.0, 0.0]);
    t.scale = pair("scale", [1.0, 1.0]);
    t.rotation_rad = v.get("rotation").and_then(|r| r.as_f64()).unwrap_or(0.0) as f32;
    let tc = v.get("texCoord").and_then(|x| x.as_u64()).map(|x| x.min(u32::MAX as u64) as u32);
    (t, tc)
}

fn texture_ref(info: &gltf::texture::Info, texture: usize) -> TextureRef {
    let mut uv_set = info.tex_coord() as usize;
    let mut transform = UvTransform::default();
    if let Some(tt) = info.texture_transform() {
        transform = UvTransform { offset: tt.offset(), rotation_rad: tt.rotation(), scale: tt.scale() };
        if let Some(tc) = tt.tex_coord() {
            uv_set = tc as usize;
        }
    }
    TextureRef { texture, uv_set, transform }
}

impl GltfSource {
    pub(crate) fn open(path: &Path, limits: &LoadLimits, files: &mut Referenced) -> Result<GltfSource> {
        // Everything here checks what it reads; the guard is for the `gltf`
        // crate's accessors, which unwrap what its validation should have
        // checked.
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| Self::open_checked(path, limits, files)))
            .unwrap_or_else(|_| {
                Err(Error::scene(
                    path,
                    "the glTF reader failed on this file (it is malformed in a way not diagnosed more precisely)",
                ))
            })
    }

    /// Read the file in the order its parts depend on: the JSON and its
    /// required extensions, the buffers, the node tree (and the triangle
    /// budget it implies), materials with their textures, meshes, nodes,
    /// lights and animation curves.
    fn open_checked(path: &Path, limits: &LoadLimits, files: &mut Referenced) -> Result<GltfSource> {
        let bytes = files.scene_file(path)?;
        let g = parse(&bytes).map_err(|e| Error::scene(path, format!("not a valid glTF 2.0 file: {e}")))?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let doc = &g.document;
        let mut warnings = Vec::new();
        check_extensions(path, doc, &mut warnings)?;
        let data = read_buffers(path, &dir, &g, files)?;
        let mut rd = Reader {
            path,
            dir,
            buffers: Buffers { data },
            limits,
            files,
            textures: Vec::new(),
            texture_cache: HashMap::new(),
        };
        let order = node_order(path, doc)?;
        check_triangle_budget(path, doc, &order, limits)?;
        let materials = rd.materials(doc)?;
        let meshes = rd.meshes(doc, &materials, &mut warnings)?;
        let mut nodes: Vec<NodeData> = doc.nodes().map(|n| node_data(&n)).collect();
        let lights = doc.lights().map(|ls| ls.map(|l| light_def(&l)).collect()).unwrap_or_default();
        let (channels, duration) = rd.animations(doc, &mut nodes)?;
        let skins = rd.skins(doc)?;
        Ok(GltfSource {
            textures: rd.textures,
            materials,
            meshes,
            nodes,
            order,
            channels,
            lights,
            skins,
            duration,
            warnings,
        })
    }

    pub(crate) fn animation_duration_s(&self) -> Option<f64> {
        self.duration
    }

    pub(crate) fn scene_at(&self, path: &Path, time_s: f64) -> Result<Scene> {
        let file = file_name(path);
        let n = self.nodes.len();
        // Local transforms and morph weights at this time.
        let mut trs_now: Vec<([f64; 3], [f64; 4], [f64; 3])> =
            self.nodes.iter().map(|nd| (nd.translation, nd.rotation, nd.scale)).collect();
        let mut weights: Vec<Option<Vec<f32>>> = vec![None; n];
        for ch in &self.channels {
            if ch.node >= n {
                continue;
            }
            let v = ch.sample(time_s);
            match ch.property {
                Property::Translation => trs_now[ch.node].0 = [v[0], v[1], v[2]].map(|x| x as f64),
                Property::Scale => trs_now[ch.node].2 = [v[0], v[1], v[2]].map(|x| x as f64),
                Property::Rotation => trs_now[ch.node].1 = [v[0], v[1], v[2], v[3]].map(|x| x as f64),
                Property::MorphTargetWeights => weights[ch.node] = Some(v),
            }
        }
        let mut world = vec![IDENTITY4; n];
        for &(i, parent) in &self.order {
            let nd = &self.nodes[i];
            let local = match (&nd.matrix, nd.animated) {
                (Some(m), false) => *m,
                _ => trs(trs_now[i].0, trs_now[i].1, trs_now[i].2),
            };
            world[i] = match parent {
                Some(p) => mat_mul(&world[p], &local),
                None => local,
            };
        }

        let mut scene = Scene {
            source: file.clone(),
            textures: self.textures.clone(),
            warnings: self.warnings.clone(),
            ..Scene::default()
        };
        for &(i, _) in &self.order {
            let nd = &self.nodes[i];
            let m = &world[i];
            if let Some(l) = nd.light.and_then(|l| self.lights.get(l)) {
                let pos = translation(m);
                match l.kind {
                    LightType::Directional => {
                        let d = unit([-m[0][2], -m[1][2], -m[2][2]]).unwrap_or([0.0, 0.0, -1.0]);
                        scene.lights.push(Light::Directional { direction: d, irradiance: l.rgb, name: l.name.clone() });
                    }
                    LightType::Point => {
                        scene.lights.push(Light::Point { position: pos, intensity: l.rgb, name: l.name.clone() })
                    }
                    LightType::Spot => {
                        scene.warnings.push(format!(
                            "{file}: light \"{}\" is a spot light; it is treated as a point light (no cone)",
                            l.name
                        ));
                        scene.lights.push(Light::Point { position: pos, intensity: l.rgb, name: l.name.clone() })
                    }
                }
            }
            let Some(mesh) = nd.mesh.and_then(|k| self.meshes.get(k)) else { continue };
            let w: Vec<f32> = weights[i].clone().or_else(|| nd.weights.clone()).unwrap_or_else(|| mesh.weights.clone());
            for (pi, prim) in mesh.prims.iter().enumerate() {
                let base = nd.name.clone().or_else(|| mesh.name.clone()).unwrap_or_else(|| format!("#{i}"));
                let name = if mesh.prims.len() > 1 { format!("{base} primitive {pi}") } else { base };
                if let Some(why) = &prim.skip {
                    scene.warnings.push(format!(
                        "{file}: object \"{name}\" (mesh {} primitive {pi}) is skipped: {why}",
                        mesh.label
                    ));
                    continue;
                }
                let material = prim.material.and_then(|k| self.materials.get(k)).cloned().unwrap_or_default();
                let skinned = match nd.skin.and_then(|k| self.skins.get(k)) {
                    Some(skin) if !prim.joints.is_empty() => {
                        let joint_matrices: Vec<Mat4> = skin
                            .joints
                            .iter()
                            .zip(&skin.inverse_bind)
                            .map(|(&j, ibm)| mat_mul(&world[j], ibm))
                            .collect();
                        let v = vertex_skin_matrices(prim, &joint_matrices, m)
                            .map_err(|e| Error::scene(path, format!("object \"{name}\" (mesh {}): {e}", mesh.label)))?;
                        Some(v)
                    }
                    Some(_) => {
                        scene.warnings.push(format!(
                            "{file}: object \"{name}\" has a skin but no JOINTS_0 and WEIGHTS_0; it is drawn unskinned"
                        ));
                        None
                    }
                    None => None,
                };
                scene.objects.push(pose(prim, m, skinned.as_deref(), &w, name, material, &file, &mut scene.warnings));
            }
        }
        finish_scene(path, &mut scene)?;
        Ok(scene)
    }
}

/// Parse and validate a `.gltf` or `.glb`.
///
/// The `gltf` crate's own validation indexes the accessor list with a
/// primitive's POSITION index before checking it, so that index is checked
/// here first. Missing POSITION `min`/`max` (required by the spec, left out
/// by some exporters, and not needed here) is tolerated. As a last guard,
/// a panic inside the crate becomes an error.
fn parse(bytes: &[u8]) -> Result<gltf::Gltf, String> {
    use gltf::json::validation::{Checked, Validate};
    let run = || -> Result<gltf::Gltf, String> {
        let g = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| e.to_string())?;
        let root = g.document.as_json();
        for (mi, m) in root.meshes.iter().enumerate() {
            for (pi, p) in m.primitives.iter().enumerate() {
                for (sem, acc) in &p.attributes {
                    if acc.value() >= root.accessors.len() {
                        let name = match sem {
                            Checked::Valid(s) => s.to_string(),
                            Checked::Invalid => "an attribute".into(),
                        };
                        return Err(format!(
                            "mesh {mi} primitive {pi}: {name} uses accessor {}, but the file has {} accessors",
                            acc.value(),
                            root.accessors.len()
                        ));
                    }
                }
            }
        }
        let mut errors = Vec::new();
        root.validate(root, gltf::json::Path::new, &mut |path: &dyn Fn() -> gltf::json::Path, e| {
            let p = path().as_str().to_string();
            let min_max = p.ends_with(".min") || p.ends_with(".max");
            // Required extensions are judged by [`check_extensions`], against
            // what this loader reads rather than what the crate parses.
            let extension = p.starts_with("extensionsRequired");
            if !(min_max && matches!(e, gltf::json::validation::Error::Missing) || extension) {
                errors.push(format!("{p}: {e}"));
            }
        });
        if !errors.is_empty() {
            let more = if errors.len() > 5 { format!(" (and {} more)", errors.len() - 5) } else { String::new() };
            return Err(format!("{}{more}", errors[..errors.len().min(5)].join("; ")));
        }
        Ok(g)
    };
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(run))
        .unwrap_or_else(|_| Err("the glTF parser failed on this file (it is malformed)".into()))
}

fn mesh_label(m: &gltf::Mesh) -> String {
    m.name().map(|s| format!("\"{s}\"")).unwrap_or_else(|| format!("#{}", m.index()))
}

/// Read one primitive in the mesh's own space, checking everything.
fn read_primitive(
    rd: &mut Reader,
    p: &gltf::Primitive,
    ctx: &str,
    max_vertices: usize,
    materials: &[Material],
    warnings: &mut Vec<String>,
) -> Result<Prim> {
    let file = file_name(rd.path);
    let mode = p.mode();
    let material = p.material().index();
    if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Ok(Prim { skip: Some(format!("its mode is {}, not triangles", mode_name(mode))), ..Prim::default() });
    }
    let Some(pos_acc) = p.get(&Semantic::Positions) else {
        return Ok(Prim { skip: Some("it has no POSITION attribute".into()), ..Prim::default() });
    };
    let positions = rd.floats::<3>(&pos_acc, &format!("{ctx} POSITION"), max_vertices)?;
    let nv = positions.len();
    let per_vertex = |what: &str, acc: &gltf::Accessor, len: usize| -> Result<()> {
        if len != nv {
            return Err(
                rd.err(format!("{ctx} {what} accessor {} holds {len} elements, but POSITION holds {nv}", acc.index()))
            );
        }
        Ok(())
    };
    let indices: Vec<u32> = match p.indices() {
        Some(acc) => {
            let (v, comps) = rd
                .buffers
                .read(&acc, max_vertices.saturating_mul(2))
                .map_err(|e| rd.err(format!("{ctx} index accessor {} {e}", acc.index())))?;
            if comps != 1 || acc.data_type() == DataType::F32 {
                return Err(
                    rd.err(format!("{ctx} index accessor {} is not a scalar of unsigned integers", acc.index()))
                );
            }
            let mut out = Vec::with_capacity(v.len());
            for (k, &x) in v.iter().enumerate() {
                if x < 0.0 || x >= nv as f64 {
                    return Err(rd.err(format!(
                        "{ctx} index accessor {} holds index {x} at position {k}, but POSITION holds {nv} vertices",
                        acc.index()
                    )));
                }
                out.push(x as u32);
            }
            out
        }
        None => (0..nv as u32).collect(),
    };
    let mut triangles = Vec::new();
    match mode {
        Mode::Triangles => {
            triangles.extend(indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
        }
        Mode::TriangleStrip => {
            for i in 0..indices.len().saturating_sub(2) {
                let t = if i % 2 == 0 {
                    [indices[i], indices[i + 1], indices[i + 2]]
                } else {
                    [indices[i + 1], indices[i], indices[i + 2]]
                };
                triangles.push(t);
            }
        }
        _ => {
            for i in 1..indices.len().saturating_sub(1) {
                triangles.push([indices[i], indices[i + 1], indices[0]]);
            }
        }
    }
    let mut prim = Prim { material, positions, triangles, ..Prim::default() };
    if let Some(acc) = p.get(&Semantic::Normals) {
        prim.normals = rd.floats::<3>(&acc, &format!("{ctx} NORMAL"), max_vertices)?;
        per_vertex("NORMAL", &acc, prim.normals.len())?;
    }
    if let Some(acc) = p.get(&Semantic::Tangents) {
        prim.tangents = rd.floats::<4>(&acc, &format!("{ctx} TANGENT"), max_vertices)?;
        per_vertex("TANGENT", &acc, prim.tangents.len())?;
    }
    let mut set = 0u32;
    while let Some(acc) = p.get(&Semantic::TexCoords(set)) {
        let uv = rd.floats::<2>(&acc, &format!("{ctx} TEXCOORD_{set}"), max_vertices)?;
        per_vertex(&format!("TEXCOORD_{set}"), &acc, uv.len())?;
        prim.uv_sets.push(uv);
        set += 1;
    }
    if let Some(acc) = p.get(&Semantic::Colors(0)) {
        let c = match acc.dimensions() {
            Dimensions::Vec3 => rd
                .floats::<3>(&acc, &format!("{ctx} COLOR_0"), max_vertices)?
                .into_iter()
                .map(|c| [c[0], c[1], c[2], 1.0])
                .collect(),
            _ => rd.floats::<4>(&acc, &format!("{ctx} COLOR_0"), max_vertices)?,
        };
        per_vertex("COLOR_0", &acc, c.len())?;
        prim.colours = c;
    }
    let mut set = 0u32;
    while let (Some(j), Some(w)) = (p.get(&Semantic::Joints(set)), p.get(&Semantic::Weights(set))) {
        let joints = rd.floats::<4>(&j, &format!("{ctx} JOINTS_{set}"), max_vertices)?;
        per_vertex(&format!("JOINTS_{set}"), &j, joints.len())?;
        let weights = rd.floats::<4>(&w, &format!("{ctx} WEIGHTS_{set}"), max_vertices)?;
        per_vertex(&format!("WEIGHTS_{set}"), &w, weights.len())?;
        if let Some(bad) = joints.iter().flatten().find(|x| **x < 0.0 || x.fract() != 0.0) {
            return Err(rd.err(format!("{ctx} JOINTS_{set} accessor {} holds {bad}, not a joint index", j.index())));
        }
        if let Some(bad) = weights.iter().flatten().find(|x| **x < 0.0) {
            return Err(rd.err(format!("{ctx} WEIGHTS_{set} accessor {} holds the negative weight {bad}", w.index())));
        }
        prim.joints.push(joints);
        prim.joint_weights.push(weights);
        set += 1;
    }
    for (ti, t) in p.morph_targets().enumerate() {
        let mut mt = MorphTarget::default();
        if let Some(acc) = t.positions() {
            mt.positions = rd.floats::<3>(&acc, &format!("{ctx} morph target {ti} POSITION"), max_vertices)?;
            per_vertex(&format!("morph target {ti} POSITION"), &acc, mt.positions.len())?;
        }
        if let Some(acc) = t.normals() {
            mt.normals = rd.floats::<3>(&acc, &format!("{ctx} morph target {ti} NORMAL"), max_vertices)?;
            per_vertex(&format!("morph target {ti} NORMAL"), &acc, mt.normals.len())?;
        }
        if let Some(acc) = t.tangents() {
            mt.tangents = rd.floats::<3>(&acc, &format!("{ctx} morph target {ti} TANGENT"), max_vertices)?;
            per_vertex(&format!("morph target {ti} TANGENT"), &acc, mt.tangents.len())?;
        }
        prim.targets.push(mt);
    }
    // Tangents for a normal map, when the file has none.
    if let Some(nt) = material.and_then(|k| materials.get(k)).and_then(|m| m.normal_texture.as_ref()) {
        if prim.tangents.is_empty() {
            let file = &file;
            match (prim.normals.is_empty(), prim.uv_sets.get(nt.uv_set)) {
                (true, _) => warnings.push(format!(
                    "{file}: {ctx} the material has a normal map but the primitive has no normals; the normal map is not used"
                )),
                (false, None) => warnings.push(format!(
                    "{file}: {ctx} the normal map uses TEXCOORD_{} which the primitive lacks; the normal map is not used",
                    nt.uv_set
                )),
                (false, Some(uv)) => {
                    let pos: Vec<[f64; 3]> = prim.positions.iter().map(|p| p.map(|x| x as f64)).collect();
                    prim.tangents = generate_tangents(&pos, &prim.normals, uv, &prim.triangles);
                }
            }
        }
    }
    Ok(prim)
}

/// A vertex's `base` value plus each active target's displacement of it
/// (`displacement` picks it from a target), weighted, in `f64`.
fn morphed(
    base: [f32; 3],
    active: &[(f32, &MorphTarget)],
    displacement: impl Fn(&MorphTarget) -> Option<[f32; 3]>,
) -> [f64; 3] {
    let mut q = base.map(|x| x as f64);
    for (wt, t) in active {
        if let Some(d) = displacement(t) {
            for k in 0..3 {
                q[k] += *wt as f64 * d[k] as f64;
            }
        }
    }
    q
}

/// Linear-blend skinning (glTF 2.0 §3.7.3): each vertex's matrix is the sum
/// over its influences (every `JOINTS_n`/`WEIGHTS_n` set, four each) of
/// weight × joint matrix, the weights divided by their sum. The joint
/// matrices are `world(joint) · inverseBind(joint)`; the skinned node's own
/// transform is not applied (the spec: it is ignored). A vertex with no
/// weight keeps `node`, its node's transform.
fn vertex_skin_matrices(prim: &Prim, joint_matrices: &[Mat4], node: &Mat4) -> std::result::Result<Vec<Mat4>, String> {
    (0..prim.positions.len())
        .map(|i| {
            let mut sum = [[0.0f64; 4]; 4];
            let mut total = 0.0f64;
            for (set, (joints, weights)) in prim.joints.iter().zip(&prim.joint_weights).enumerate() {
                for (&j, &wt) in joints[i].iter().zip(&weights[i]) {
                    if wt == 0.0 {
                        continue;
                    }
                    let jm = joint_matrices.get(j as usize).ok_or_else(|| {
                        let n = joint_matrices.len();
                        let listed = if n == 1 { "1 joint".to_string() } else { format!("{n} joints") };
                        format!("vertex {i} is bound (JOINTS_{set}) to joint {j}, but its skin lists {listed}")
                    })?;
                    for (row, jrow) in sum.iter_mut().zip(jm) {
                        for (s, x) in row.iter_mut().zip(jrow) {
                            *s += f64::from(wt) * x;
                        }
                    }
                    total += f64::from(wt);
                }
            }
            if total > 0.0 {
                Ok(sum.map(|row| row.map(|x| x / total)))
            } else {
                Ok(*node)
            }
        })
        .collect()
}

/// A primitive morphed by `w` and moved to world space: by `m`, or where the
/// primitive is skinned by each vertex's own matrix `skinned[i]`.
#[allow(clippy::too_many_arguments)]
fn pose(
    prim: &Prim,
    m: &Mat4,
    skinned: Option<&[Mat4]>,
    w: &[f32],
    name: String,
    material: Material,
    file: &str,
    warnings: &mut Vec<String>,
) -> Object {
    let matrix = |i: usize| skinned.map_or(m, |v| &v[i]);
    // Winding follows the first vertex's matrix (a skin that mirrors some
    // vertices and not others has no one winding).
    let flip = det3(&linear(skinned.and_then(|v| v.first()).unwrap_or(m))) < 0.0;
    let nm = normal_matrix(m);
    let skinned_normals: Option<Vec<Mat3>> = skinned.map(|v| v.iter().map(normal_matrix).collect());
    let normal_matrix_of = |i: usize| skinned_normals.as_ref().map_or(&nm, |v| &v[i]);
    let active: Vec<(f32, &MorphTarget)> = prim
        .targets
        .iter()
        .zip(w.iter().copied().chain(std::iter::repeat(0.0)))
        .filter(|(_, wt)| *wt != 0.0)
        .map(|(t, wt)| (wt, t))
        .collect();
    let positions = prim
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let q = morphed(*p, &active, |t| t.positions.get(i).copied());
            transform_point(matrix(i), q)
        })
        .collect();
    // A direction that comes out zero makes the whole attribute unusable.
    let normals: Option<Vec<[f32; 3]>> = prim
        .normals
        .iter()
        .enumerate()
        .map(|(i, nrm)| {
            let q = morphed(*nrm, &active, |t| t.normals.get(i).copied());
            unit(mat3_apply(normal_matrix_of(i), q)).map(|u| u.map(|x| x as f32))
        })
        .collect();
    let normals = normals.unwrap_or_else(|| {
        warnings.push(format!("{file}: object \"{name}\": some normals are zero; the object is shaded flat"));
        Vec::new()
    });
    let s = if flip { -1.0 } else { 1.0 };
    let tangents: Option<Vec<[f32; 4]>> = prim
        .tangents
        .iter()
        .enumerate()
        .map(|(i, t4)| {
            let q = morphed([t4[0], t4[1], t4[2]], &active, |t| t.tangents.get(i).copied());
            let wsign = if t4[3] < 0.0 { -s } else { s };
            unit(transform_direction(matrix(i), q)).map(|u| [u[0] as f32, u[1] as f32, u[2] as f32, wsign])
        })
        .collect();
    let tangents = match tangents {
        Some(tangents) if !normals.is_empty() => tangents,
        _ => {
            if !prim.tangents.is_empty() {
                warnings.push(format!("{file}: object \"{name}\": tangents unusable; its normal map is not used"));
            }
            Vec::new()
        }
    };
    let triangles =
        if flip { prim.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect() } else { prim.triangles.clone() };
    Object {
        name,
        positions,
        normals,
        tangents,
        uv_sets: prim.uv_sets.clone(),
        colours: prim.colours.clone(),
        triangles,
        material,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirrored_matrix_normals() {
        let m = trs([0.0; 3], [0.0, 0.0, 0.0, 1.0], [-1.0, 2.0, 1.0]);
        assert!(det3(&linear(&m)) < 0.0);
        let n = normal_matrix(&m);
        // Inverse transpose of diag(−1, 2, 1) is diag(−1, 0.5, 1), up to a positive factor.
        assert!(n[0][0] < 0.0 && n[1][1] > 0.0 && n[2][2] > 0.0);
        assert!((n[0][0] / n[2][2] + 1.0).abs() < 1e-12 && (n[1][1] / n[2][2] - 0.5).abs() < 1e-12);
    }
}
