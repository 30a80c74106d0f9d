//! Micropolygons (Deering, *HoloFlicks* §8) render like the scene they come from: the
//! bundled Spot, diced to fractions of the display's resolution, lit once
//! (diffuse baked into vertex colours) and rendered with only the specular
//! term per view, against rendering the mesh directly. The error shrinks
//! with the micropolygons; a highlight moves across views as directly.

use holo::geometry::{rgb_channels, Geometry, Views};
use holo::holoflick::shader::bake::BakeOptions;
use holo::holoflick::shader::dice::{display_budget, DiceOptions};
use holo::holoflick::shader::micro::micropolygons;
use holo::mesh::place::{place, Placement};
use holo::mesh::render::{render, Engine, RenderOptions, Supersample};
use holo::mesh::shade::{Lighting, SpecularModel};
use holo::mesh::{Light, Scene};
use holo::Modulation;

fn display() -> Geometry {
    Geometry::centred(
        40,
        96,
        Views::tan_spaced(48, -15f64.to_radians(), 15f64.to_radians()),
        0.5e-3,
        0.5e-3,
        0.0,
        0.5,
        rgb_channels(),
    )
}

fn spot(g: &Geometry) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/mesh/spot/spot.obj");
    let mut scene = holo::mesh::load::SceneSource::open(&path).and_then(|s| s.scene_at(0.0)).unwrap();
    place(&mut scene, g, &Placement { rotate_deg: [0.0, -60.0, 0.0], ..Placement::default() }).unwrap();
    for o in &mut scene.objects {
        o.material.specular = [0.25; 3];
        o.material.shininess = 40.0;
    }
    scene
}

fn lights() -> Vec<Light> {
    vec![
        Light::Directional { direction: [0.4, -0.5, -1.0], irradiance: [2.5; 3], name: "key".into() },
        Light::Directional { direction: [-0.6, 0.2, -1.0], irradiance: [0.8, 0.9, 1.0], name: "fill".into() },
        Light::Ambient { radiance: [0.08; 3] },
    ]
}

fn options(lights: Vec<Light>) -> RenderOptions {
    RenderOptions {
        supersample: Supersample::new(2, 2),
        engine: Engine::Fast,
        ..RenderOptions::lit_exactly(Lighting { lights, model: SpecularModel::Blinn })
    }
}

/// Mean |a − b| / mean b.
fn relative_error(a: &Modulation, b: &Modulation) -> f64 {
    let d: f64 = a.samples().iter().zip(b.samples()).map(|(x, y)| (*x as f64 - *y as f64).abs()).sum();
    d / b.samples().iter().map(|&y| y as f64).sum::<f64>()
}

#[test]
fn micropolygons_render_like_the_mesh_and_converge() {
    let g = display();
    let scene = spot(&g);
    let (direct, _) = render(&scene, &g, &options(lights()), &holo::progress::Silent).unwrap();
    println!("micropolygon edge (× display resolution) | micropolygons | error vs direct");
    let mut errors = Vec::new();
    for factor in [4.0, 2.0, 1.0, 0.5] {
        let budget = display_budget(&g, factor);
        let (micro, specular_lights, report) = micropolygons(
            &scene,
            &lights(),
            &budget,
            &DiceOptions::default(),
            &BakeOptions::default(),
            &holo::progress::Silent,
        )
        .unwrap();
        assert!(specular_lights.iter().all(|l| !matches!(l, Light::Ambient { .. })));
        let (m, _) = render(&micro, &g, &options(specular_lights), &holo::progress::Silent).unwrap();
        let e = relative_error(&m, &direct);
        println!("{factor:>4} | {:>7} | {e:.4}", report.dice.triangles_out);
        errors.push(e);
    }
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "error must shrink with the micropolygons: {errors:?}");
    assert!(errors[3] < 0.02, "{errors:?}");
}

/// With a mirror-like lobe and no diffuse light, all that is left is the
/// deferred specular: the highlight's view per emitter is where direct
/// rendering puts it.
#[test]
fn deferred_specular_moves_across_views_like_direct_rendering() {
    let g = display();
    let mut scene = spot(&g);
    for o in &mut scene.objects {
        o.material.specular = [1.0; 3];
        o.material.shininess = 300.0;
    }
    let sun = vec![Light::Directional { direction: [0.1, -0.2, -1.0], irradiance: [3.0; 3], name: "sun".into() }];
    let (direct, _) = render(&scene, &g, &options(sun.clone()), &holo::progress::Silent).unwrap();
    let (micro, specular_lights, _) = micropolygons(
        &scene,
        &sun,
        &display_budget(&g, 0.5),
        &DiceOptions::default(),
        &BakeOptions::default(),
        &holo::progress::Silent,
    )
    .unwrap();
    let (m, _) = render(&micro, &g, &options(specular_lights), &holo::progress::Silent).unwrap();
    let (mut same, mut compared) = (0, 0);
    for j in 0..g.hololines {
        for e in 0..g.emitters {
            // Brightest view of the green channel, where it stands out.
            let peak = |f: &Modulation| {
                let v = f.views_of(1, j, e);
                let k = (0..v.len()).max_by(|&a, &b| v[a].total_cmp(&v[b])).unwrap();
                (k, v[k], v.iter().sum::<f32>() / v.len() as f32)
            };
            let (kd, pd, md) = peak(&direct);
            if pd > 4.0 * md && pd > 0.2 {
                let (km, _, _) = peak(&m);
                compared += 1;
                same += usize::from(km.abs_diff(kd) <= 1);
            }
        }
    }
    println!("highlights compared {compared}; peak view within one view of direct: {same}");
    assert!(compared > 30, "a highlight must be seen");
    assert!(same as f64 >= 0.9 * compared as f64, "{same} of {compared}");
}

/// A material's choice of lobe and lights survives into the micropolygons,
/// its light indices renumbered into the specular lights returned (the
/// ambient ones are baked and dropped).
#[test]
fn chosen_lights_are_renumbered_into_the_specular_lights() {
    let g = display();
    let mut scene = spot(&g);
    let ambient = Light::Ambient { radiance: [0.1; 3] };
    let sun = Light::Directional { direction: [0.3, -0.5, -1.0], irradiance: [2.0; 3], name: "sun".into() };
    let lamp = Light::Point { position: [0.0, 0.05, 0.2], intensity: [0.05; 3], name: "lamp".into() };
    let lights = [sun.clone(), ambient, lamp.clone()];
    scene.objects[0].material.lights = Some(vec![2, 1]);
    scene.objects[0].material.specular_model = Some(SpecularModel::Phong);
    let (micro, specular, _) = micropolygons(
        &scene,
        &lights,
        &display_budget(&g, 4.0),
        &DiceOptions::default(),
        &BakeOptions::default(),
        &holo::progress::Silent,
    )
    .unwrap();
    assert_eq!(specular, vec![sun, lamp]);
    assert_eq!(micro.objects[0].material.lights, Some(vec![1]), "lamp: 2 → 1; the ambient, baked, is dropped");
    assert_eq!(micro.objects[0].material.specular_model, Some(SpecularModel::Phong));
}
