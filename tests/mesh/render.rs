//! The mesh renderers: the fast EPI rasteriser against the reference ray
//! caster on random and real scenes, occlusion with a known answer per view,
//! and specular highlights where the formulas put them.

use holo::geometry::{rgb_channels, Geometry, Views};
use holo::mesh::render::{render, Engine, RenderOptions, RenderStats, Supersample};
use holo::mesh::shade::{Lighting, SpecularModel};
use holo::mesh::{Light, Material, Object, Scene};
use holo::Modulation;

use crate::common;
use common::shared_data;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A small display: 21 hololines, 48 emitters of 1 mm, 32 views over ±20°,
/// emitter plane at 0, viewer at 500 mm.
pub(crate) fn small_geometry(emitter_z_m: f64) -> Geometry {
    Geometry::centred(
        21,
        48,
        Views::tan_spaced(32, -20f64.to_radians(), 20f64.to_radians()),
        1e-3,
        1e-3,
        emitter_z_m,
        0.5,
        rgb_channels(),
    )
}

pub(crate) fn both(scene: &Scene, g: &Geometry, options: &RenderOptions) -> (Modulation, Modulation, RenderStats) {
    let fast =
        render(scene, g, &RenderOptions { engine: Engine::Fast, ..options.clone() }, &holo::progress::Silent).unwrap();
    let reference =
        render(scene, g, &RenderOptions { engine: Engine::Reference, ..options.clone() }, &holo::progress::Silent)
            .unwrap();
    (fast.0, reference.0, fast.1)
}

/// Both engines on a random scene that must cover a tenth of the display:
/// the reference, and [`compare`]'s figures for the fast path, printed.
pub(crate) fn fast_against_reference(
    seed: u64,
    scene: &Scene,
    g: &Geometry,
    options: &RenderOptions,
) -> (Modulation, f64, f64) {
    let (fast, reference, stats) = both(scene, g, options);
    let (off, mean) = compare(&fast, &reference);
    println!(
        "seed {seed}: {:.3}% of samples off by >1% of peak, mean |diff| {:.2e} of mean; {stats:?}",
        off * 100.0,
        mean
    );
    assert!(
        reference.samples().iter().filter(|&&v| v > 0.0).count() > reference.samples().len() / 10,
        "seed {seed}: scene covers the display"
    );
    (reference, off, mean)
}

/// (fraction of samples differing by more than 1% of the peak, mean |difference| / mean value).
pub(crate) fn compare(fast: &Modulation, reference: &Modulation) -> (f64, f64) {
    let peak = reference.samples().iter().fold(0.0f32, |a, &b| a.max(b)) as f64;
    let mean = reference.samples().iter().map(|&v| v as f64).sum::<f64>() / reference.samples().len() as f64;
    let mut off = 0usize;
    let mut sum = 0.0;
    for (a, b) in fast.samples().iter().zip(reference.samples()) {
        let d = (*a as f64 - *b as f64).abs();
        sum += d;
        if d > 0.01 * peak {
            off += 1;
        }
    }
    let n = fast.samples().len() as f64;
    (off as f64 / n, sum / n / mean.max(1e-30))
}

pub(crate) fn random_scene(rng: &mut ChaCha8Rng, triangles: usize) -> Scene {
    let mut objects = Vec::new();
    for o in 0..3 {
        let mut obj = Object {
            name: format!("random {o}"),
            material: Material {
                base_colour: [rng.gen_range(0.2..1.0), rng.gen_range(0.2..1.0), rng.gen_range(0.2..1.0), 1.0],
                specular: [0.3; 3],
                shininess: rng.gen_range(5.0..60.0),
                double_sided: o == 2,
                // Vertex colours as baked light, lights adding specular only.
                prelit: o == 1,
                ..Material::default()
            },
            ..Object::default()
        };
        for _ in 0..triangles / 3 {
            // Centres spread over the display volume, across the emitter plane.
            let c = [rng.gen_range(-0.02..0.02), rng.gen_range(-0.01..0.01), rng.gen_range(-0.03..0.03)];
            let size = rng.gen_range(0.002..0.02);
            let base = obj.positions.len() as u32;
            for _ in 0..3 {
                obj.positions.push([
                    c[0] + rng.gen_range(-size..size),
                    c[1] + rng.gen_range(-size..size),
                    c[2] + rng.gen_range(-size..size),
                ]);
                obj.colours.push([rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0), 1.0]);
            }
            obj.triangles.push([base, base + 1, base + 2]);
        }
        objects.push(obj);
    }
    Scene { source: "random".into(), objects, ..Scene::default() }
}

pub(crate) fn lighting(model: SpecularModel) -> Lighting {
    Lighting {
        lights: vec![
            Light::Directional { direction: [0.3, -0.5, -1.0], irradiance: [2.0, 2.0, 2.0], name: "key".into() },
            Light::Point { position: [0.05, 0.03, 0.1], intensity: [0.02, 0.015, 0.01], name: "fill".into() },
            Light::Ambient { radiance: [0.05; 3] },
        ],
        model,
    }
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn fast_equals_reference_on_random_scenes() {
    for (seed, z_e, model, ss) in [
        (1, 0.0, SpecularModel::Blinn, Supersample::new(1, 1)),
        (2, 0.01, SpecularModel::Phong, Supersample::new(2, 3)),
        (3, -0.02, SpecularModel::Blinn, Supersample::new(3, 1)),
        (9, 0.01, SpecularModel::Blinn, Supersample { emitter: 2, view: 1, hololine: 3 }),
    ] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let scene = random_scene(&mut rng, 60);
        let g = small_geometry(z_e);
        let options =
            RenderOptions { supersample: ss, engine: Engine::Fast, ..RenderOptions::lit_exactly(lighting(model)) };
        let (_, off, mean) = fast_against_reference(seed, &scene, &g, &options);
        assert!(off < 0.005 && mean < 0.005, "seed {seed}: fast path differs from the reference");
    }
}

/// Two emissive squares: red at z = +20 mm over x ∈ [2, 12] mm, green at
/// z = −20 mm over x ∈ [−12, 12] mm. From the centre emitter (x = 0), the
/// ray of slope s meets red at x = 20s and green at x = −20s: red is seen for
/// s ∈ [0.1, 0.6], green for other |s| ≤ 0.6, nothing beyond.
#[test]
fn occlusion_has_the_known_answer_in_every_view() {
    let square = |name: &str, z: f64, x0: f64, x1: f64, emissive: [f32; 3]| Object {
        name: name.into(),
        positions: vec![[x0, -0.02, z], [x1, -0.02, z], [x1, 0.02, z], [x0, 0.02, z]],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material: Material { base_colour: [0.0; 4], emissive, specular: [0.0; 3], ..Material::default() },
        ..Object::default()
    };
    let scene = Scene {
        objects: vec![
            square("red", 0.02, 0.002, 0.012, [1.0, 0.0, 0.0]),
            square("green", -0.02, -0.012, 0.012, [0.0, 1.0, 0.0]),
        ],
        ..Scene::default()
    };
    // One emitter at x = 0, one hololine at the viewer's height, views over ±40°.
    let g = Geometry::centred(
        1,
        1,
        Views::tan_spaced(81, -40f64.to_radians(), 40f64.to_radians()),
        1e-3,
        1e-4,
        0.0,
        0.5,
        rgb_channels(),
    );
    let options = RenderOptions {
        supersample: Supersample::new(1, 1),
        engine: Engine::Fast,
        ..RenderOptions::lit_exactly(Lighting { lights: vec![], model: SpecularModel::Blinn })
    };
    for engine in [Engine::Fast, Engine::Reference] {
        let (m, _) = render(&scene, &g, &RenderOptions { engine, ..options.clone() }, &holo::progress::Silent).unwrap();
        let mut seen = [0; 3];
        for v in 0..81 {
            let s = g.views.theta_rad(v).tan();
            let expected = if (0.1..=0.6).contains(&s) {
                [1.0, 0.0]
            } else if s.abs() <= 0.6 {
                [0.0, 1.0]
            } else {
                [0.0, 0.0]
            };
            // Skip views within rounding of an edge.
            if [0.1f64, 0.6, -0.6].iter().any(|edge| (s - edge).abs() < 1e-9) {
                continue;
            }
            let got = [m.get(0, 0, 0, v) as f64, m.get(1, 0, 0, v) as f64];
            assert_eq!(got, expected, "{engine:?}: view {v}, tan θ = {s:.3}");
            seen[if got[0] > 0.0 {
                0
            } else if got[1] > 0.0 {
                1
            } else {
                2
            }] += 1;
        }
        assert!(seen.iter().all(|&n| n > 3), "every case occurs: {seen:?}");
    }
}

/// A shiny plane in the emitter plane lit by a point light: each emitter's
/// brightest view is the mirror direction, tan θ* = (x_e − x_L)/(z_L − z_e),
/// for both lobes, and the lobe falls off as its formula says.
#[test]
fn highlights_move_across_views_as_the_formulas_say() {
    let plane = Object {
        name: "plane".into(),
        positions: vec![[-0.1, -0.1, 0.0], [0.1, -0.1, 0.0], [0.1, 0.1, 0.0], [-0.1, 0.1, 0.0]],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material: Material {
            base_colour: [0.0, 0.0, 0.0, 1.0],
            specular: [1.0; 3],
            shininess: 200.0,
            ..Material::default()
        },
        ..Object::default()
    };
    let scene = Scene { objects: vec![plane], ..Scene::default() };
    let light_x = -0.01;
    let light_z = 0.1;
    let g = Geometry::centred(
        1,
        41,
        Views::tan_spaced(161, -30f64.to_radians(), 30f64.to_radians()),
        1e-3,
        1e-3,
        0.0,
        0.5,
        rgb_channels(),
    );
    for model in [SpecularModel::Phong, SpecularModel::Blinn] {
        let options = RenderOptions {
            supersample: Supersample::new(1, 1),
            engine: Engine::Fast,
            ..RenderOptions::lit_exactly(Lighting {
                lights: vec![Light::Point { position: [light_x, 0.0, light_z], intensity: [1.0; 3], name: "p".into() }],
                model,
            })
        };
        let (m, _) = render(&scene, &g, &options, &holo::progress::Silent).unwrap();
        let mut moved = Vec::new();
        for e in 0..g.emitters {
            let x = g.emitter_x_m(e);
            let views = m.views_of(0, 0, e);
            let peak = (0..views.len()).max_by(|&a, &b| views[a].total_cmp(&views[b])).unwrap();
            let expected = ((x - light_x) / light_z).atan();
            let spacing = (g.views.theta_rad(1) - g.views.theta_rad(0)).abs();
            assert!(
                (g.views.theta_rad(peak) - expected).abs() <= spacing,
                "{model:?} emitter {e}: peak at view {peak}"
            );
            moved.push(peak);
            // The lobe one view either side of the peak, from the formula.
            let to_light = {
                let d = [light_x - x, 0.0, light_z];
                let l = (d[0] * d[0] + d[2] * d[2]).sqrt();
                [d[0] / l, 0.0, d[2] / l]
            };
            let e_irr = 1.0 / ((light_x - x).powi(2) + light_z * light_z);
            for v in [peak.saturating_sub(3), (peak + 3).min(160)] {
                let t = g.views.theta_rad(v);
                let view = [t.sin(), 0.0, t.cos()];
                let n = 200.0f64;
                let lobe = match model {
                    SpecularModel::Phong => {
                        let r = [-to_light[0], 0.0, to_light[2]];
                        (n + 2.0) / (2.0 * std::f64::consts::PI) * (r[0] * view[0] + r[2] * view[2]).max(0.0).powf(n)
                    }
                    SpecularModel::Blinn => {
                        let h = [to_light[0] + view[0], 0.0, to_light[2] + view[2]];
                        let l = (h[0] * h[0] + h[2] * h[2]).sqrt();
                        (n + 8.0) / (8.0 * std::f64::consts::PI) * (h[2] / l).powf(n)
                    }
                };
                let expected = e_irr * to_light[2] * lobe;
                let got = m.get(0, 0, e, v) as f64;
                assert!(
                    (got - expected).abs() <= 2e-4 * expected.max(1.0),
                    "{model:?} e {e} v {v}: {got} vs {expected}"
                );
            }
        }
        assert!(
            moved.windows(2).all(|w| w[1] >= w[0]) && moved[40] > moved[0] + 20,
            "{model:?}: highlight moves: {moved:?}"
        );
    }
}

#[test]
fn bad_scenes_are_errors_naming_the_object() {
    let g = small_geometry(0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut scene = random_scene(&mut rng, 9);
    scene.objects[1].positions[2][1] = f64::NAN;
    let e = render(&scene, &g, &RenderOptions::default(), &holo::progress::Silent).unwrap_err().to_string();
    assert!(e.contains("random 1") && e.contains("vertex 2"), "{e}");
    let mut scene = random_scene(&mut rng, 9);
    scene.objects[0].triangles[0][2] = 1000;
    let e = render(&scene, &g, &RenderOptions::default(), &holo::progress::Silent).unwrap_err().to_string();
    assert!(e.contains("random 0") && e.contains("triangle 0"), "{e}");
    let mut empty = Scene { source: "empty.obj".into(), ..Scene::default() };
    let e = holo::mesh::place::place(&mut empty, &g, &Default::default()).unwrap_err().to_string();
    assert!(e.contains("empty.obj") && e.contains("no triangles"), "{e}");
    let options = RenderOptions { supersample: Supersample::new(0, 1), ..RenderOptions::default() };
    assert!(render(&random_scene(&mut rng, 9), &g, &options, &holo::progress::Silent).is_err());
}

/// The layouts' own emitter and view geometry, on a band of `rows`
/// hololines through the middle (the reference is slow).
fn band(layout: &holo::layout::Layout, rows: usize) -> Geometry {
    let mut g = layout.geometry.clone();
    let mid = g.hololines / 2;
    g.hololine_top_y_m = g.hololine_y_m(mid.saturating_sub(rows / 2));
    g.hololines = rows;
    g
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn fast_equals_reference_on_real_models_at_several_layouts() {
    use holo::mesh::load::SceneSource;
    use holo::mesh::place::{place, Placement};
    let mut models =
        vec![std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/mesh/spot/spot.obj"))];
    match shared_data() {
        Some(d) => {
            models.push(d.join("gltf_khronos_BoxTextured/glTF-Binary/BoxTextured.glb"));
            models.push(d.join("mesh_utah_teapot/teapot.obj"));
            models.push(d.join("gltf_khronos_ClearCoatTest_normalmaps/glTF/ClearCoatTest.gltf"));
        }
        None => println!("SKIPPED (partly): ../shared/data not present; only the bundled spot model ran"),
    }
    let layouts = [holo::layout::mark3(), holo::layout::mark1(), holo::layout::mark4()];
    for path in &models {
        let found = if path.exists() {
            path.clone()
        } else {
            // Find the model by extension in its folder (names differ between samples).
            let dir = path.parent().unwrap();
            let ext = path.extension().unwrap().to_owned();
            match std::fs::read_dir(dir)
                .ok()
                .and_then(|r| r.flatten().map(|e| e.path()).find(|p| p.extension() == Some(&ext)))
            {
                Some(p) => p,
                None => panic!("no {:?} model in {}", ext, dir.display()),
            }
        };
        let source = SceneSource::open(&found).unwrap();
        for (li, layout) in layouts.iter().enumerate() {
            // Mark IV is large: fewer hololines there.
            let g = band(layout, if li == 2 { 2 } else { 6 });
            let mut scene = source.scene_at(0.0).unwrap();
            let placement = Placement { rotate_deg: [10.0, 30.0 * li as f64, 0.0], ..Placement::default() };
            // Fit to the whole layout, then render the band.
            place(&mut scene, &layout.geometry, &placement).unwrap();
            let options = RenderOptions {
                supersample: Supersample::new(1, 1),
                engine: Engine::Fast,
                ..RenderOptions::lit_exactly(lighting(SpecularModel::Blinn))
            };
            let (fast, reference, stats) = both(&scene, &g, &options);
            let (off, mean) = compare(&fast, &reference);
            println!(
                "{} on {}: {:.3}% of samples off by >1% of peak, mean |diff| {:.2e} of mean ({} segments)",
                found.file_name().unwrap().to_string_lossy(),
                layout.name,
                off * 100.0,
                mean,
                stats.segments
            );
            assert!(reference.samples().iter().any(|&v| v > 0.0), "the band sees the model");
            assert!(off < 0.005 && mean < 0.005, "{} on {}", found.display(), layout.name);
        }
    }
}

/// Directional lights only (no point lights, no textures): the rasteriser
/// shades whole view columns through its vectorised batch, here with smooth
/// vertex normals and with flat faces, both lobes, several supersamplings.
#[test]
fn fast_equals_reference_with_directional_lights_and_vertex_normals() {
    for (seed, z_e, model, ss, smooth) in [
        (4, 0.0, SpecularModel::Blinn, Supersample::new(1, 1), true),
        (5, 0.01, SpecularModel::Phong, Supersample::new(2, 3), true),
        (6, -0.02, SpecularModel::Blinn, Supersample::new(3, 1), false),
    ] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut scene = random_scene(&mut rng, 60);
        if smooth {
            for o in &mut scene.objects {
                // Each vertex normal: the face normal tilted at random (up to ~35°).
                let mut normals = vec![[0.0f32; 3]; o.positions.len()];
                for t in &o.triangles {
                    let p = t.map(|i| o.positions[i as usize]);
                    let (a, b) = ([0, 1, 2].map(|k| p[1][k] - p[0][k]), [0, 1, 2].map(|k| p[2][k] - p[0][k]));
                    let n = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
                    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                    for &i in t {
                        let v = [0, 1, 2].map(|k| n[k] / l + rng.gen_range(-0.4..0.4));
                        let lv = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                        normals[i as usize] = v.map(|x| (x / lv) as f32);
                    }
                }
                o.normals = normals;
            }
        }
        let g = small_geometry(z_e);
        let lights = Lighting {
            lights: vec![
                Light::Directional { direction: [0.3, -0.5, -1.0], irradiance: [2.0, 2.0, 2.0], name: "key".into() },
                Light::Directional { direction: [-0.6, 0.2, -0.5], irradiance: [0.5, 0.7, 0.9], name: "fill".into() },
                Light::Ambient { radiance: [0.05; 3] },
            ],
            model,
        };
        let options = RenderOptions { supersample: ss, engine: Engine::Fast, ..RenderOptions::lit_exactly(lights) };
        let (_, off, mean) = fast_against_reference(seed, &scene, &g, &options);
        assert!(off < 0.005 && mean < 0.005, "seed {seed}: fast path differs from the reference");
    }
}

/// Random textures on random scenes with directional lights: base-colour
/// textures go through the vectorised batch (lookups located column-wide),
/// an emissive texture and a transformed texture through the per-pixel
/// shader, both kinds of segment in one hololine. Texture coordinates run
/// past [0, 1] so every wrap mode is used.
#[test]
fn fast_equals_reference_with_textures_in_and_out_of_the_batch() {
    use holo::mesh::{Texture, TextureRef, UvTransform, Wrap};
    for (seed, model, ss) in
        [(7, SpecularModel::Blinn, Supersample::new(1, 1)), (8, SpecularModel::Phong, Supersample::new(2, 2))]
    {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut scene = random_scene(&mut rng, 90);
        let wraps =
            [[Wrap::Repeat, Wrap::MirroredRepeat], [Wrap::ClampToEdge, Wrap::Repeat], [Wrap::MirroredRepeat; 2]];
        for (k, wrap) in wraps.into_iter().enumerate() {
            let (width, height) = [(37, 23), (64, 64), (5, 3)][k];
            let texels = (0..width * height)
                .map(|_| [rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0), 1.0])
                .collect();
            scene.textures.push(Texture { name: format!("random {k}"), width, height, texels, wrap });
        }
        for (k, o) in scene.objects.iter_mut().enumerate() {
            o.uv_sets =
                vec![(0..o.positions.len()).map(|_| [rng.gen_range(-0.3..1.3), rng.gen_range(-0.3..1.3)]).collect()];
            let plain = TextureRef { texture: k, uv_set: 0, transform: UvTransform::default() };
            match k {
                0 => o.material.base_colour_texture = Some(plain),
                1 => {
                    o.material.base_colour_texture = Some(plain.clone());
                    o.material.emissive = [0.3, 0.2, 0.1];
                    o.material.emissive_texture = Some(plain);
                }
                _ => {
                    let transform = UvTransform { offset: [0.1, -0.2], rotation_rad: 0.3, scale: [1.5, 0.8] };
                    o.material.base_colour_texture = Some(TextureRef { transform, ..plain });
                }
            }
        }
        let g = small_geometry(0.005);
        let lights = Lighting {
            lights: vec![
                Light::Directional { direction: [0.3, -0.5, -1.0], irradiance: [2.0, 2.0, 2.0], name: "key".into() },
                Light::Ambient { radiance: [0.05; 3] },
            ],
            model,
        };
        let options = RenderOptions { supersample: ss, engine: Engine::Fast, ..RenderOptions::lit_exactly(lights) };
        let (_, off, mean) = fast_against_reference(seed, &scene, &g, &options);
        assert!(off < 0.005 && mean < 0.005, "seed {seed}: fast path differs from the reference");
    }
}

/// `render_into` overwrites every sample of the frame it is given.
#[test]
fn render_into_a_used_frame_equals_a_fresh_render() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let scene = random_scene(&mut rng, 30);
    let g = small_geometry(0.0);
    let options = RenderOptions { lighting: lighting(SpecularModel::Blinn), ..RenderOptions::default() };
    let (fresh, _) = render(&scene, &g, &options, &holo::progress::Silent).unwrap();
    let mut used = Modulation::zeros(g.clone()).unwrap();
    used.samples_mut().iter_mut().enumerate().for_each(|(i, v)| *v = (i % 7) as f32 + 0.5);
    holo::mesh::render::render_into(&scene, &options, &holo::progress::Silent, &mut used).unwrap();
    assert_eq!(fresh.samples(), used.samples());
}

/// Materials choosing their lobe and a subset of the render's lights: the
/// fast path (a batch and column set-up per group of materials with the
/// same lights and lobe, point lights through the per-run shader) against
/// the reference, with directional lights only (everything batched, several
/// groups in one column) and with a point light (groups with it shaded run
/// by run beside batched ones). The choices must matter, and choosing every
/// light and the render's lobe must change no bit.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn fast_equals_reference_with_per_material_lobes_and_lights() {
    let key = Light::Directional { direction: [0.3, -0.5, -1.0], irradiance: [2.0, 2.0, 2.0], name: "key".into() };
    let fill = Light::Directional { direction: [-0.6, 0.2, -0.5], irradiance: [0.5, 0.7, 0.9], name: "fill".into() };
    let point = Light::Point { position: [0.05, 0.03, 0.1], intensity: [0.02, 0.015, 0.01], name: "point".into() };
    let ambient = Light::Ambient { radiance: [0.05; 3] };
    // Per object: the lights chosen and the lobe.
    type Choices = [(Option<Vec<u32>>, Option<SpecularModel>); 3];
    // (seed, lights, render lobe, supersampling, choices)
    let cases: [(u64, Vec<Light>, SpecularModel, Supersample, Choices); 3] = [
        (
            10,
            vec![key.clone(), fill.clone(), ambient.clone()],
            SpecularModel::Blinn,
            Supersample::new(1, 1),
            [(Some(vec![0, 2]), Some(SpecularModel::Phong)), (Some(vec![1]), None), (None, Some(SpecularModel::Phong))],
        ),
        (
            11,
            vec![key.clone(), point.clone(), fill.clone(), ambient.clone()],
            SpecularModel::Phong,
            Supersample::new(2, 2),
            [
                (Some(vec![1, 3]), Some(SpecularModel::Blinn)),
                (Some(vec![0]), Some(SpecularModel::Phong)),
                (Some(vec![2, 1, 2]), None),
            ],
        ),
        (
            12,
            vec![point, key, ambient, fill],
            SpecularModel::Blinn,
            Supersample::new(3, 1),
            [(Some(vec![3, 2]), None), (Some(vec![]), Some(SpecularModel::Phong)), (Some(vec![1]), None)],
        ),
    ];
    for (seed, lights, model, ss, choices) in cases {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let plain = random_scene(&mut rng, 60);
        let mut scene = plain.clone();
        for (o, (chosen, lobe)) in scene.objects.iter_mut().zip(choices) {
            o.material.lights = chosen;
            o.material.specular_model = lobe;
        }
        let g = small_geometry(0.005);
        let options = RenderOptions {
            supersample: ss,
            engine: Engine::Fast,
            ..RenderOptions::lit_exactly(Lighting { lights, model })
        };
        let (reference, off, mean) = fast_against_reference(seed, &scene, &g, &options);
        // Tighter than the tests above: no texture or normal map here, only f32 against f64 rounding.
        assert!(off < 0.001 && mean < 1e-4, "seed {seed}: fast path differs from the reference");
        let (_, every_light, _) = both(&plain, &g, &options);
        let (_, changed) = compare(&reference, &every_light);
        assert!(changed > 0.05, "seed {seed}: the choices change the picture ({changed:.3})");
        // Every light (in any order, repeated) and the render's lobe: today's render, bit for bit.
        let mut all = plain.clone();
        let n = options.lighting.lights.len() as u32;
        for o in &mut all.objects {
            o.material.lights = Some((0..n).rev().chain([0]).collect());
            o.material.specular_model = Some(model);
        }
        let (fast_all, _) = render(&all, &g, &options, &holo::progress::Silent).unwrap();
        let (fast_plain, _) = render(&plain, &g, &options, &holo::progress::Silent).unwrap();
        assert!(fast_all == fast_plain, "seed {seed}: choosing everything changed a sample");
    }
}

/// A material choosing a light the render does not have is an error naming it.
#[test]
fn choosing_a_missing_light_is_an_error() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let mut scene = random_scene(&mut rng, 9);
    scene.objects[1].material.lights = Some(vec![0, 3]);
    let g = small_geometry(0.0);
    for engine in [Engine::Fast, Engine::Reference] {
        let options = RenderOptions { lighting: lighting(SpecularModel::Blinn), engine, ..RenderOptions::default() };
        let e = render(&scene, &g, &options, &holo::progress::Silent).unwrap_err().to_string();
        assert!(e.contains("random 1") && e.contains("light 3"), "{e}");
    }
}

/// A library render honours the scene's own lights, as `convert_mesh` does:
/// the same samples, and not those of the default lights.
#[test]
fn a_library_render_uses_the_scenes_lights_as_convert_mesh_does() {
    use holo::mesh::convert::{convert_mesh, ConvertOptions};
    use holo::mesh::load::SceneSource;
    use holo::mesh::place::{place, Placement};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/mesh/modes_lights.gltf");
    let g = band(&holo::layout::mark3(), 8);
    let mut scene = SceneSource::open(&path).unwrap().scene_at(0.0).unwrap();
    assert!(!scene.lights.is_empty(), "the fixture defines lights");
    place(&mut scene, &g, &Placement::default()).unwrap();
    let options = RenderOptions { supersample: Supersample::new(1, 1), ..RenderOptions::default() };
    let (library, _) = render(&scene, &g, &options, &holo::progress::Silent).unwrap();
    assert!(library.samples().iter().any(|&v| v > 0.0), "the band sees the scene");

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lights.holo");
    let write = holo::WriteOptions { sample_type: holo::format::SampleType::F32, ..Default::default() };
    let convert = ConvertOptions { render: options.clone(), write, ..ConvertOptions::default() };
    let report = convert_mesh(&path, &g, &out, &convert, &holo::progress::Silent).unwrap();
    assert_eq!(report.lights, scene.lights);
    assert!(holo::read(&out).unwrap() == library, "convert_mesh and a library render differ");

    let (default_lit, _) =
        render(&scene, &g, &RenderOptions { scene_lights: false, ..options }, &holo::progress::Silent).unwrap();
    assert!(default_lit.samples() != library.samples(), "the scene's lights are not the default lights");
}

/// An emissive half-plane whose top edge rises 1 hololine pitch over 24
/// emitters, on the emitter plane: each hololine's footprint (a pitch tall)
/// is covered by a known fraction along the edge. One line per hololine
/// samples it as a hard step; lines across the hololine's height average
/// it toward the covered fraction.
#[test]
fn hololine_supersampling_antialiases_edges_near_the_horizontal() {
    let g = small_geometry(0.0);
    let pitch = g.hololine_pitch_m;
    let (x0, x1) = (g.emitter_x_m(0) - 0.01, g.emitter_x_m(g.emitters - 1) + 0.01);
    // Edge y = y_edge + slope · x, between two hololines' centres in the middle.
    let slope = pitch / (24.0 * g.emitter_pitch_m);
    let y_edge = g.hololine_y_m(10) - 0.5 * pitch;
    let top = |x: f64| y_edge + slope * x;
    let scene = Scene {
        objects: vec![Object {
            name: "half-plane".into(),
            positions: vec![[x0, -0.05, 0.0], [x1, -0.05, 0.0], [x1, top(x1), 0.0], [x0, top(x0), 0.0]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            material: Material { base_colour: [0.0; 4], emissive: [1.0; 3], specular: [0.0; 3], ..Material::default() },
            ..Object::default()
        }],
        ..Scene::default()
    };
    let mid_view = g.views.count / 2;
    // Mean |rendered − covered fraction| and the share of partly covered
    // samples, over the hololines the edge crosses, in the middle view.
    let measure = |hololine: usize| {
        let options = RenderOptions {
            supersample: Supersample { emitter: 1, view: 1, hololine },
            ..RenderOptions::lit_exactly(Lighting { lights: vec![], model: SpecularModel::Blinn })
        };
        let (m, _) = render(&scene, &g, &options, &holo::progress::Silent).unwrap();
        let (mut error, mut partial, mut n) = (0.0, 0, 0);
        for j in 8..13 {
            let y = g.hololine_y_m(j);
            for e in 0..g.emitters {
                let x = g.emitter_x_m(e);
                let covered = ((top(x) - (y - 0.5 * pitch)) / pitch).clamp(0.0, 1.0);
                let got = f64::from(m.get(0, j, e, mid_view));
                error += (got - covered).abs();
                partial += usize::from(got > 0.05 && got < 0.95);
                n += 1;
            }
        }
        (error / n as f64, partial as f64 / n as f64)
    };
    let (hard, hard_partial) = measure(1);
    let (smooth, smooth_partial) = measure(8);
    println!(
        "edge near the horizontal: 1 line per hololine, mean error {hard:.3}, {:.0}% partly covered; 8 lines, {smooth:.4}, {:.0}%",
        100.0 * hard_partial,
        100.0 * smooth_partial
    );
    // The edge crosses two of the five hololines measured.
    assert!(hard_partial < 0.02 && smooth_partial > 0.12, "{hard_partial} {smooth_partial}");
    assert!(smooth < hard / 4.0 && smooth < 0.02, "{hard} {smooth}");
}

/// [`small_geometry`] made full parallax: 16 × 7 views over ±20° × ±12°.
pub(crate) fn small_full_parallax_geometry(emitter_z_m: f64) -> Geometry {
    let mut g = small_geometry(emitter_z_m);
    g.views = Views::tan_spaced(16, -20f64.to_radians(), 20f64.to_radians());
    g.with_vertical_views(Views::tan_spaced(7, -12f64.to_radians(), 12f64.to_radians()))
}

/// Full parallax draws one plane of rays per hololine and vertical view: the
/// fast rasteriser against the reference ray caster, supersampled in every
/// axis, on random scenes across the emitter plane.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn fast_equals_reference_in_full_parallax() {
    for (seed, z_e, model, ss) in [
        (21, 0.0, SpecularModel::Blinn, Supersample::new(1, 1)),
        (22, 0.01, SpecularModel::Phong, Supersample::new(2, 2)),
        (23, -0.02, SpecularModel::Blinn, Supersample { emitter: 1, view: 3, hololine: 2 }),
    ] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let scene = random_scene(&mut rng, 60);
        let g = small_full_parallax_geometry(z_e);
        let options =
            RenderOptions { supersample: ss, engine: Engine::Fast, ..RenderOptions::lit_exactly(lighting(model)) };
        let (reference, off, mean) = fast_against_reference(seed, &scene, &g, &options);
        assert!(off < 0.005 && mean < 0.005, "seed {seed}: fast path differs from the reference");
        // The vertical views differ: the scene has depth.
        let (top, bottom) = (g.view_index(8, 0), g.view_index(8, 6));
        let differ = (0..g.hololines)
            .flat_map(|j| (0..g.emitters).map(move |e| (j, e)))
            .filter(|&(j, e)| reference.get(0, j, e, top) != reference.get(0, j, e, bottom))
            .count();
        assert!(differ > g.hololines * g.emitters / 10, "seed {seed}: vertical views differ at {differ} emitters");
    }
}

/// A full-parallax sample is what its ray sees: each sample of a render
/// without supersampling equals the pinhole picture of an eye placed on its
/// ray ([`holo::mesh::trace::eye_picture_at`]), for views in every corner of
/// the grid, in front of and behind the emitter plane.
#[test]
fn full_parallax_samples_are_the_rays_of_their_views() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let scene = random_scene(&mut rng, 45);
    let g = small_full_parallax_geometry(0.0);
    let light = lighting(SpecularModel::Blinn);
    let options = RenderOptions {
        supersample: Supersample::new(1, 1),
        engine: Engine::Reference,
        ..RenderOptions::lit_exactly(light.clone())
    };
    let (m, _) = render(&scene, &g, &options, &holo::progress::Silent).unwrap();
    let mut lit = 0;
    for (h, w) in [(0, 0), (15, 0), (0, 6), (15, 6), (7, 3)] {
        // An eye 0.4 m in front of emitter (10, 20) along view (h, w): it sees
        // that emitter in that view; other emitters it sees at other angles.
        let (j, e) = (10, 20);
        let ray = g.ray(j, e, g.view_index(h, w));
        let eye = ray.at_z(0.4);
        let picture = holo::mesh::trace::eye_picture_at(&scene, &light, &g, eye).unwrap();
        for c in 0..3 {
            let want = picture[(j * g.emitters + e) * 3 + c];
            let got = m.get(c, j, e, g.view_index(h, w));
            assert!((got - want).abs() <= 1e-6 * want.abs().max(1e-3), "view ({h} {w}) channel {c}: {got} vs {want}");
            lit += usize::from(want > 0.0);
        }
    }
    assert!(lit >= 6, "the chosen rays meet the scene ({lit} lit)");
}
