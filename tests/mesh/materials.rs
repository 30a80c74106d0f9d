//! glTF materials as their authors meant them, rendered by both engines:
//! `alphaMode` MASK cut at `alphaCutoff`, BLEND composited front to back
//! over what each ray crosses, and the metallic-roughness texture read
//! (metalness in B, roughness in G). The scenes are glTF files written here,
//! in display metres, so what each ray should see is known.

use std::path::{Path, PathBuf};

use holo::geometry::Geometry;
use holo::mesh::load::SceneSource;
use holo::mesh::render::{render, Engine, RenderOptions, Supersample};
use holo::mesh::shade::{Lighting, SpecularModel};
use holo::Modulation;
use serde_json::{json, Value};

use super::render::small_geometry;
use crate::common;

/// A quad facing +z over `x × y` at depth `z` (metres), with texture
/// coordinates `u` from 0 at `x[0]` to 1 at `x[1]` and `v` from 0 at the
/// top to 1 at the bottom, and optionally RGBA vertex colours.
struct Quad {
    x: [f64; 2],
    y: [f64; 2],
    z: f64,
    material: usize,
    colour: Option<[f32; 4]>,
}

impl Quad {
    fn new(x: [f64; 2], y: [f64; 2], z: f64, material: usize) -> Quad {
        Quad { x, y, z, material, colour: None }
    }
}

/// An 8-bit RGBA PNG of `w × h` pixels, `pixel(x, y)` each.
fn rgba(w: u32, h: u32, pixel: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
    common::png8(w, h, 4, &common::pixels(w, h, pixel))
}

/// A glTF file of `quads` with `materials` (JSON) and `images` (PNG bytes,
/// embedded; texture `i` shows image `i`, clamped at its edges).
fn write_gltf(dir: &Path, name: &str, quads: &[Quad], materials: Value, images: &[Vec<u8>]) -> PathBuf {
    let mut buf: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut meshes, mut nodes) = (vec![], vec![], vec![], vec![]);
    let mut push = |buf: &mut Vec<u8>, bytes: Vec<u8>, count: usize, kind: &str, component: u32| {
        views.push(json!({"buffer": 0, "byteOffset": buf.len(), "byteLength": bytes.len()}));
        let mut a = json!({"bufferView": views.len() - 1, "componentType": component, "count": count, "type": kind});
        if kind == "VEC3" {
            // POSITION needs its bounds.
            let f: Vec<f32> = bytes.chunks_exact(4).map(|c| f32::from_le_bytes(c.try_into().unwrap())).collect();
            let (lo, hi): (Vec<f32>, Vec<f32>) = (0..3)
                .map(|k| {
                    let it = f.iter().skip(k).step_by(3);
                    (it.clone().fold(f32::INFINITY, |a, &b| a.min(b)), it.fold(f32::NEG_INFINITY, |a, &b| a.max(b)))
                })
                .unzip();
            a["min"] = json!(lo);
            a["max"] = json!(hi);
        }
        buf.extend(bytes);
        accessors.push(a);
        accessors.len() - 1
    };
    let f32s = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    for (i, q) in quads.iter().enumerate() {
        let (x, y, z) = (q.x.map(|v| v as f32), q.y.map(|v| v as f32), q.z as f32);
        let positions = [x[0], y[0], z, x[1], y[0], z, x[1], y[1], z, x[0], y[1], z];
        let p = push(&mut buf, f32s(&positions), 4, "VEC3", 5126);
        let uv = push(&mut buf, f32s(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]), 4, "VEC2", 5126);
        let indices: Vec<u8> = [0u32, 1, 2, 0, 2, 3].iter().flat_map(|x| x.to_le_bytes()).collect();
        let ix = push(&mut buf, indices, 6, "SCALAR", 5125);
        let mut attributes = json!({"POSITION": p, "TEXCOORD_0": uv});
        if let Some(c) = q.colour {
            attributes["COLOR_0"] = json!(push(&mut buf, f32s(&[c, c, c, c].concat()), 4, "VEC4", 5126));
        }
        meshes.push(json!({"name": format!("quad {i}"),
            "primitives": [{"attributes": attributes, "indices": ix, "material": q.material}]}));
        nodes.push(json!({"mesh": i, "name": format!("quad {i}")}));
    }
    let images: Vec<Value> =
        images.iter().map(|png| json!({"uri": format!("data:image/png;base64,{}", base64(png))})).collect();
    let textures: Vec<Value> = (0..images.len()).map(|i| json!({"source": i, "sampler": 0})).collect();
    let file = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": (0..quads.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "textures": textures,
        "images": images,
        "samplers": [{"wrapS": 33071, "wrapT": 33071}],
        "buffers": [{"byteLength": buf.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64(&buf))}],
        "bufferViews": views,
        "accessors": accessors,
    });
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(&file).unwrap()).unwrap();
    path
}

fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            s.push(if k <= c.len() { A[(n >> (18 - 6 * k) & 63) as usize] as char } else { '=' });
        }
    }
    s
}

/// The scene of a file as loaded (no placement: its coordinates are display metres).
fn scene(path: &Path) -> holo::mesh::Scene {
    let s = SceneSource::open(path).and_then(|s| s.scene_at(0.0)).unwrap();
    for w in &s.warnings {
        println!("warning: {w}");
    }
    s
}

/// Both engines' renders of `scene`.
fn renders(scene: &holo::mesh::Scene, g: &Geometry, options: &RenderOptions) -> [(Engine, Modulation); 2] {
    [Engine::Fast, Engine::Reference].map(|engine| {
        let (m, _) = render(scene, g, &RenderOptions { engine, ..options.clone() }, &holo::progress::Silent).unwrap();
        (engine, m)
    })
}

/// No lights: emissive surfaces only, so every sample's value is known.
fn unlit(supersample: Supersample) -> RenderOptions {
    RenderOptions {
        supersample,
        ..RenderOptions::lit_exactly(Lighting { lights: vec![], model: SpecularModel::Blinn })
    }
}

/// An emissive material: black base colour (alpha `alpha`), emission `rgb`.
fn emissive(name: &str, rgb: [f32; 3], alpha: f32) -> Value {
    json!({"name": name, "emissiveFactor": rgb,
        "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, alpha], "metallicFactor": 0.0}})
}

/// The (R, G, B) of a sample of an RGB render.
fn rgb(m: &Modulation, j: usize, e: usize, v: usize) -> [f64; 3] {
    [0, 1, 2].map(|c| f64::from(m.get(c, j, e, v)))
}

/// MASK quads (cutoffs 0.25, 0.5, 0.75) on the emitter plane, emitting red,
/// whose texture's alpha rises from 0 at u ≤ ¼ to 1 at u ≥ ¾ (a 2 × 1
/// texture, clamped, bilinear): each is opaque where alpha ≥ its cutoff, at
/// u ≥ ¼ + cutoff/2, and wholly transparent elsewhere, where the green
/// backdrop behind shows. An OPAQUE quad with the same texture hides the
/// backdrop everywhere (alpha ignored), and a MASK quad without `alphaCutoff`
/// cuts at 0.5.
#[test]
fn mask_cuts_at_the_alpha_cutoff() {
    let dir = tempfile::tempdir().unwrap();
    let ramp = rgba(2, 1, |x, _| [255, 255, 255, if x == 0 { 0 } else { 255 }]);
    let textured = |name: &str, mode: &str, cutoff: Option<f64>| {
        let mut m = emissive(name, [1.0, 0.0, 0.0], 1.0);
        m["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
        m["alphaMode"] = json!(mode);
        if let Some(c) = cutoff {
            m["alphaCutoff"] = json!(c);
        }
        m
    };
    let materials = json!([
        textured("cut 0.25", "MASK", Some(0.25)),
        textured("cut 0.5", "MASK", None),
        textured("cut 0.75", "MASK", Some(0.75)),
        textured("opaque", "OPAQUE", Some(0.75)),
        emissive("backdrop", [0.0, 1.0, 0.0], 1.0),
    ]);
    // Hololine j is at y = 10 − j mm; each quad covers a band of hololines.
    let bands: [(usize, [f64; 2], Option<f64>); 4] = [
        (0, [5.5e-3, 10.5e-3], Some(0.25)),
        (1, [0.5e-3, 5.5e-3], Some(0.5)),
        (2, [-4.5e-3, 0.5e-3], Some(0.75)),
        (3, [-10.5e-3, -4.5e-3], None),
    ];
    let mut quads: Vec<Quad> = bands.iter().map(|&(m, y, _)| Quad::new([-0.02, 0.02], y, 0.0, m)).collect();
    quads.push(Quad::new([-0.04, 0.04], [-0.03, 0.03], -0.01, 4));
    let path = write_gltf(dir.path(), "mask.gltf", &quads, materials, &[ramp]);
    let s = scene(&path);
    let g = small_geometry(0.0);
    for (engine, m) in renders(&s, &g, &unlit(Supersample::new(1, 1))) {
        let mut seen = [0usize; 2];
        for (band, &(_, y, cutoff)) in bands.iter().enumerate() {
            let rows = (0..g.hololines).filter(|&j| {
                let yj = g.hololine_y_m(j);
                yj > y[0] && yj < y[1]
            });
            for j in rows {
                for e in 0..g.emitters {
                    let u = (g.emitter_x_m(e) + 0.02) / 0.04;
                    let quad_seen = (0.0..=1.0).contains(&u)
                        && match cutoff {
                            Some(c) => u >= 0.25 + c / 2.0,
                            None => true,
                        };
                    let want = if quad_seen { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
                    for v in 0..g.views.count {
                        assert_eq!(
                            rgb(&m, j, e, v),
                            want,
                            "{engine:?}: band {band}, hololine {j}, emitter {e} (u {u:.3}), view {v}"
                        );
                    }
                    seen[usize::from(quad_seen)] += 1;
                }
            }
        }
        assert!(seen.iter().all(|&n| n > 100), "both cases occur: {seen:?}");
    }
}

/// Three BLEND quads in front of an opaque green backdrop, each emitting
/// one colour, their alpha from each source glTF names: the base colour
/// factor (red, 0.5), the base colour texture's alpha times the vertex
/// colours' (blue, 128/255 × 0.5) and both (cyan-free magenta, 0.8 × 0.5).
/// Where rays cross several, the radiance is the front-to-back composite
/// `Σ L_i α_i Π_{k<i} (1 − α_k)`; swapping which is in front changes it.
#[test]
fn blend_composites_what_each_ray_crosses_front_to_back() {
    let dir = tempfile::tempdir().unwrap();
    let half = rgba(2, 2, |_, _| [255, 255, 255, 128]);
    let mut blue = emissive("blue", [0.0, 0.0, 1.0], 1.0);
    blue["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    blue["alphaMode"] = json!("BLEND");
    let mut red = emissive("red", [1.0, 0.0, 0.0], 0.5);
    red["alphaMode"] = json!("BLEND");
    let mut magenta = emissive("magenta", [1.0, 0.0, 1.0], 0.8);
    magenta["alphaMode"] = json!("BLEND");
    let materials = json!([red, blue, magenta, emissive("backdrop", [0.0, 1.0, 0.0], 1.0)]);
    let alpha_red = 0.5f64;
    let alpha_blue = 128.0 / 255.0 * 0.5;
    let alpha_magenta = 0.8 * 0.5;
    let with_colour = |mut q: Quad, a: f32| {
        q.colour = Some([1.0, 1.0, 1.0, a]);
        q
    };
    // Top band (hololines 0..=9): red in front of blue. Bottom band: blue in
    // front of red, and the magenta quad (vertex alpha 0.5) in front of both
    // over the right half. Left of x = −15 mm only the backdrop.
    let quads = vec![
        Quad::new([-0.015, 0.03], [0.5e-3, 0.03], 0.005, 0),
        with_colour(Quad::new([-0.015, 0.03], [0.5e-3, 0.03], 0.0, 1), 0.5),
        with_colour(Quad::new([-0.015, 0.03], [-0.03, 0.5e-3], 0.005, 1), 0.5),
        Quad::new([-0.015, 0.03], [-0.03, 0.5e-3], 0.0, 0),
        with_colour(Quad::new([0.004, 0.03], [-0.03, 0.5e-3], 0.01, 2), 0.5),
        Quad::new([-0.06, 0.06], [-0.04, 0.04], -0.01, 3),
    ];
    let path = write_gltf(dir.path(), "blend.gltf", &quads, materials, &[half]);
    let s = scene(&path);
    let g = small_geometry(0.0);
    let over = |front: ([f64; 3], f64), behind: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|c| front.0[c] * front.1 + (1.0 - front.1) * behind[c])
    };
    let (r, gr, b, mg) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 1.0]);
    let red_over_blue = over((r, alpha_red), over((b, alpha_blue), gr));
    let blue_over_red = over((b, alpha_blue), over((r, alpha_red), gr));
    let magenta_over = over((mg, alpha_magenta), blue_over_red);
    let mid = g.views.count / 2;
    for (engine, m) in renders(&s, &g, &unlit(Supersample::new(1, 1))) {
        let mut checked = 0;
        for j in [2usize, 7, 13, 18] {
            for e in 0..g.emitters {
                let x = g.emitter_x_m(e);
                // The central view's rays are nearly along z: well inside a region.
                let want = if x < -0.016 {
                    gr
                } else if x > -0.014 && j < 10 {
                    red_over_blue
                } else if x > -0.014 && x < 0.0 {
                    blue_over_red
                } else if x > 0.006 {
                    magenta_over
                } else {
                    continue;
                };
                let got = rgb(&m, j, e, mid);
                for c in 0..3 {
                    assert!(
                        (got[c] - want[c]).abs() < 2e-6,
                        "{engine:?}: hololine {j}, emitter {e}: {got:?}, expected {want:?}"
                    );
                }
                checked += 1;
            }
        }
        assert!(checked > 150, "{checked} samples checked");
        assert!((red_over_blue[0] - blue_over_red[0]).abs() > 0.1, "the order matters");
    }
}

/// A bed whose metal lives only in its metallic-roughness texture: the
/// factors are glTF's defaults (metallic 1, roughness 1), the texture says
/// B = 0 (no metal) and G = 200/255 (roughness) on the left and B = 1 on the
/// right. Honoured, the left is a dielectric of roughness 200/255, exactly
/// what a material with those factors and no texture gives (not 1.5 times
/// as bright, white metal), and the right is a metal coloured by the base
/// colour (F0 = base colour), not white.
#[test]
fn the_metallic_roughness_texture_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let wood = rgba(2, 2, |_, _| [200, 150, 100, 255]);
    let metal_right = rgba(2, 1, |x, _| [255, 200, if x == 0 { 0 } else { 255 }, 255]);
    let plain = rgba(2, 2, |_, _| [255, 200, 0, 255]);
    let bed = |mr: Option<usize>, factors: Option<(f64, f64)>| {
        let mut pbr = json!({"baseColorTexture": {"index": 0}});
        if let Some(t) = mr {
            pbr["metallicRoughnessTexture"] = json!({"index": t});
        }
        if let Some((metallic, roughness)) = factors {
            pbr["metallicFactor"] = json!(metallic);
            pbr["roughnessFactor"] = json!(roughness);
        }
        json!([{"name": "bed", "pbrMetallicRoughness": pbr}])
    };
    let quad = [Quad::new([-0.02, 0.02], [-0.012, 0.012], 0.0, 0)];
    let textured = write_gltf(dir.path(), "bed.gltf", &quad, bed(Some(1), None), &[wood.clone(), plain]);
    let honoured = write_gltf(
        dir.path(),
        "factors.gltf",
        &quad,
        bed(None, Some((0.0, 200.0 / 255.0))),
        std::slice::from_ref(&wood),
    );
    let half_metal = write_gltf(dir.path(), "half.gltf", &quad, bed(Some(1), None), &[wood, metal_right]);
    let g = small_geometry(0.0);
    // The default lights: a key light from the upper left and a dim ambient.
    let options = RenderOptions { supersample: Supersample::new(1, 1), ..RenderOptions::default() };
    let [textured, honoured, half_metal] = [textured, honoured, half_metal].map(|p| renders(&scene(&p), &g, &options));
    for k in 0..2 {
        let (engine, (a, b)) = (textured[k].0, (&textured[k].1, &honoured[k].1));
        let (sum_a, sum_b) = (total(a), total(b));
        let diff: f64 = a.samples().iter().zip(b.samples()).map(|(x, y)| (x - y).abs() as f64).sum();
        println!(
            "{engine:?}: the bed's light {:.4} of the honoured factors', mean |diff| {:.2e} of it",
            sum_a / sum_b,
            diff / sum_b
        );
        assert!(sum_b > 0.0 && sum_a <= sum_b * 1.0001, "{engine:?}: the bed is brighter ({sum_a} vs {sum_b})");
        assert!(diff < 1e-4 * sum_b, "{engine:?}: the bed differs from its factors ({diff} of {sum_b})");
        // The metal on the right (u ≥ ¾) takes its colour from the base colour.
        let m = &half_metal[k].1;
        let base = [200.0, 150.0, 100.0].map(|c: f64| holo::picture::srgb_decode(c / 255.0));
        let mut samples = 0;
        for j in 0..g.hololines {
            for e in (0..g.emitters).filter(|&e| g.emitter_x_m(e) > 0.011) {
                for v in 0..g.views.count {
                    let c = rgb(m, j, e, v);
                    if c[0] > 1e-3 {
                        for k in 1..3 {
                            let want = base[k] / base[0];
                            assert!((c[k] / c[0] - want).abs() < 1e-3 * want, "{engine:?}: metal {c:?}, base {base:?}");
                        }
                        samples += 1;
                    }
                }
            }
        }
        assert!(samples > 1000, "{engine:?}: the metal is lit ({samples} samples)");
    }
}

fn total(m: &Modulation) -> f64 {
    m.samples().iter().map(|&v| f64::from(v)).sum()
}

/// Random scenes whose objects are masked, blended and metallic-rough:
/// the fast renderer (fragments composited over the depth-tested opaque
/// surfaces, in the batch and the per-run shader) against the reference ray
/// caster (every surface on the ray, nearest first). Alpha comes from the
/// factor, random vertex alphas and a random texture's alpha; the masked
/// object's alpha straddles its cutoff and the blended ones are neither
/// clear nor opaque, so each changes the picture against the same scene
/// opaque and against the scene without it.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn fast_equals_reference_with_see_through_and_metallic_rough_materials() {
    use super::render::{compare, fast_against_reference, random_scene};
    use holo::mesh::{AlphaMode, Light, MetallicRoughness, Texture, TextureRef, UvTransform, Wrap};
    use rand::{Rng, SeedableRng};
    let key = Light::Directional { direction: [0.3, -0.5, -1.0], irradiance: [2.0; 3], name: "key".into() };
    let point = Light::Point { position: [0.05, 0.03, 0.1], intensity: [0.02, 0.015, 0.01], name: "point".into() };
    let ambient = Light::Ambient { radiance: [0.05; 3] };
    // (seed, lights, lobe, supersampling): directional lights only (the
    // batch), and with a point light (the per-run shader).
    let cases = [
        (31, vec![key.clone(), ambient.clone()], SpecularModel::Blinn, Supersample::new(1, 1)),
        (32, vec![key.clone(), point.clone(), ambient.clone()], SpecularModel::Phong, Supersample::new(2, 2)),
        (33, vec![key, point, ambient], SpecularModel::Blinn, Supersample { emitter: 2, view: 1, hololine: 2 }),
    ];
    for (seed, lights, model, ss) in cases {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let opaque = {
            let mut s = random_scene(&mut rng, 90);
            for k in 0..2 {
                let (width, height) = [(13, 7), (6, 9)][k];
                let texels = (0..width * height).map(|_| std::array::from_fn(|_| rng.gen_range(0.0f32..1.0))).collect();
                let wrap = [Wrap::Repeat, Wrap::MirroredRepeat];
                s.textures.push(Texture { name: format!("random {k}"), width, height, texels, wrap });
            }
            for o in &mut s.objects {
                o.uv_sets = vec![(0..o.positions.len())
                    .map(|_| [rng.gen_range(-0.3..1.3), rng.gen_range(-0.3..1.3)])
                    .collect()];
                for c in &mut o.colours {
                    c[3] = rng.gen_range(0.3..1.0);
                }
            }
            let texture = |k: usize| Some(TextureRef { texture: k, uv_set: 0, transform: UvTransform::default() });
            // Metallic-rough: one textured (the batch's lookups), one by the factors.
            let m = &mut s.objects[0].material;
            m.base_colour_texture = texture(0);
            m.metallic_roughness = Some(MetallicRoughness { metallic: 0.9, roughness: 0.8, texture: texture(1) });
            s.objects[2].material.metallic_roughness =
                Some(MetallicRoughness { metallic: 0.5, roughness: 0.3, texture: None });
            s.objects[1].material.base_colour_texture = texture(1);
            s
        };
        let mut scene = opaque.clone();
        scene.objects[0].material.alpha_mode = AlphaMode::Blend;
        scene.objects[0].material.base_colour[3] = 0.8;
        scene.objects[1].material.alpha_mode = AlphaMode::Mask { cutoff: 0.4 };
        scene.objects[2].material.alpha_mode = AlphaMode::Blend;
        scene.objects[2].material.base_colour[3] = 0.6;
        let g = small_geometry(0.005);
        let options = RenderOptions {
            supersample: ss,
            engine: Engine::Fast,
            ..RenderOptions::lit_exactly(Lighting { lights, model })
        };
        let (reference, off, mean) = fast_against_reference(seed, &scene, &g, &options);
        assert!(off < 0.005 && mean < 0.005, "seed {seed}: fast path differs from the reference");
        let reference_of = |s: &holo::mesh::Scene| {
            render(s, &g, &RenderOptions { engine: Engine::Reference, ..options.clone() }, &holo::progress::Silent)
                .unwrap()
                .0
        };
        let (_, against_opaque) = compare(&reference, &reference_of(&opaque));
        assert!(against_opaque > 0.05, "seed {seed}: alpha changes the picture ({against_opaque:.3})");
        for k in 0..3 {
            let mut without = scene.clone();
            without.objects[k].triangles.clear();
            let mut solid = scene.clone();
            solid.objects[k].material.alpha_mode = AlphaMode::Opaque;
            let (_, against_none) = compare(&reference, &reference_of(&without));
            let (_, against_solid) = compare(&reference, &reference_of(&solid));
            println!("seed {seed}, object {k}: against the scene without it {against_none:.3}, with it opaque {against_solid:.3}");
            assert!(against_none > 0.005 && against_solid > 0.005, "seed {seed}: object {k} is partly seen");
        }
    }
}

/// A negative `alphaCutoff` (glTF requires ≥ 0) is refused, naming the
/// file and the material; an `alphaMode` glTF does not define is refused
/// by the file's checks, naming the field.
#[test]
fn a_bad_alpha_mode_or_cutoff_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let quad = [Quad::new([-0.01, 0.01], [-0.01, 0.01], 0.0, 0)];
    let mut negative = emissive("leaf", [1.0; 3], 1.0);
    negative["alphaMode"] = json!("MASK");
    negative["alphaCutoff"] = json!(-0.5);
    let mut unknown = emissive("leaf", [1.0; 3], 1.0);
    unknown["alphaMode"] = json!("CUTOUT");
    for (name, material, words) in [
        ("negative.gltf", negative, ["leaf", "alphaCutoff is -0.5"]),
        ("unknown.gltf", unknown, ["alphaMode", "materials[0]"]),
    ] {
        let path = write_gltf(dir.path(), name, &quad, json!([material]), &[]);
        match SceneSource::open(&path).and_then(|s| s.scene_at(0.0)) {
            Err(e @ holo::Error::Scene { .. }) => {
                let text = e.to_string();
                assert!(text.contains(name) && words.iter().all(|w| text.contains(w)), "{text}");
            }
            other => panic!("{name}: {other:?}"),
        }
    }
}
