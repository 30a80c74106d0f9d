//! Baking diffuse light into vertex colours: the reference shader's
//! view-independent terms at every vertex (textured Spot under the default
//! lights), and shadows where an occluder hides a light (a floor under a
//! square, lit by a directional and by a point light).

use holo::holoflick::shader::bake::{bake_diffuse, BakeOptions};
use holo::mesh::load::SceneSource;
use holo::mesh::shade::{face_normal, radiance, Hit, Lighting};
use holo::mesh::{Light, Material, Object, Scene};

#[test]
fn baked_colours_are_the_reference_shaders_diffuse_terms() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/mesh/spot/spot.obj");
    let mut scene = SceneSource::open(&path).unwrap().scene_at(0.0).unwrap();
    // Spot is shaded flat: one vertex per corner, so a vertex has one normal.
    for o in &mut scene.objects {
        *o = holo::holoflick::shader::dice::with_flat_normals(o);
        o.material.specular = [0.3, 0.3, 0.3];
    }
    let lights = Lighting::default_lights();
    let (baked, report) = bake_diffuse(&scene, &lights, &BakeOptions::default());
    assert_eq!(report.vertices, scene.objects.iter().map(|o| o.positions.len()).sum::<usize>());
    let mut matte = scene.clone();
    matte.objects.iter_mut().for_each(|o| o.material.specular = [0.0; 3]);
    let lighting = Lighting { lights: lights.clone(), model: Default::default() };
    let mut checked = 0;
    for (oi, o) in matte.objects.iter().enumerate() {
        for (t, tri) in o.triangles.iter().enumerate() {
            for (k, &i) in tri.iter().enumerate() {
                let hit = Hit { object: oi as u32, triangle: t as u32, b1: f64::from(k == 1), b2: f64::from(k == 2) };
                let f = face_normal(o, t);
                let l = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
                let want = radiance(&matte, &lighting, &hit, f.map(|x| x / l));
                let got = baked[oi][i as usize];
                for c in 0..3 {
                    assert!(
                        (got[c] as f64 - want[c]).abs() <= 1e-6 * want[c].abs().max(1e-3),
                        "vertex {i}: {got:?} vs {want:?}"
                    );
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 1000);
    assert!(baked[0].iter().any(|c| c[0] > 0.2), "lit somewhere");
}

/// A grid of `n × n` vertices over [−s, s]² at height `z`, facing +z.
fn square(name: &str, n: usize, s: f64, z: f64) -> Object {
    let mut o = Object { name: name.into(), ..Object::default() };
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (-s + 2.0 * s * i as f64 / (n - 1) as f64, -s + 2.0 * s * j as f64 / (n - 1) as f64);
            o.positions.push([x, y, z]);
            o.normals.push([0.0, 0.0, 1.0]);
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            let (b, c, d) = (a + 1, a + n as u32, a + n as u32 + 1);
            o.triangles.extend([[a, b, d], [a, d, c]]);
        }
    }
    o.material = Material { base_colour: [0.8, 0.6, 0.4, 1.0], specular: [0.0; 3], ..Material::default() };
    o
}

#[test]
fn occluded_lights_leave_shadows() {
    let floor = square("floor", 41, 2.0, 0.0);
    let roof = square("roof", 2, 0.5, 1.0);
    let scene = Scene { source: "shadow test".into(), objects: vec![floor, roof], ..Scene::default() };
    let ambient = Light::Ambient { radiance: [0.1, 0.1, 0.1] };
    let rho = [0.8f64, 0.6, 0.4];
    for (light, half_width) in [
        (Light::Directional { direction: [0.0, 0.0, -1.0], irradiance: [2.0; 3], name: "sun".into() }, 0.5),
        // From 3 above the floor a square 1 above it casts a shadow 3/2 as wide.
        (Light::Point { position: [0.0, 0.0, 3.0], intensity: [18.0; 3], name: "lamp".into() }, 0.75),
    ] {
        let lights = vec![ambient.clone(), light.clone()];
        let (shadowed, report) = bake_diffuse(&scene, &lights, &BakeOptions { shadows: true });
        let (unshadowed, _) = bake_diffuse(&scene, &lights, &BakeOptions { shadows: false });
        let mut dark = 0;
        for (i, p) in scene.objects[0].positions.iter().enumerate() {
            let inside = p[0].abs() < half_width - 1e-9 && p[1].abs() < half_width - 1e-9;
            let outside = p[0].abs() > half_width + 1e-9 || p[1].abs() > half_width + 1e-9;
            let (got, open) = (shadowed[0][i], unshadowed[0][i]);
            for c in 0..3 {
                let ambient_only = 0.1 * rho[c];
                if inside {
                    assert!((got[c] as f64 - ambient_only).abs() < 1e-6, "{p:?} should be in shadow: {got:?}");
                } else if outside {
                    assert_eq!(got[c], open[c], "{p:?} should be lit");
                    assert!(got[c] as f64 > ambient_only + 0.05);
                }
            }
            dark += usize::from(inside);
        }
        assert!(dark > 50, "{dark} floor vertices under the roof");
        assert!(report.shadowed >= dark);
        // The roof's top is lit, not shadowed by itself.
        assert!(shadowed[1].iter().all(|c| c[0] as f64 > 0.1 * rho[0] + 0.05), "{:?}", shadowed[1]);
    }
}

/// An object whose material chooses some of the lights is baked under
/// those alone (ambient included), as the renderers would shade it.
#[test]
fn chosen_lights_alone_are_baked() {
    let sun = Light::Directional { direction: [0.3, 0.0, -1.0], irradiance: [2.0; 3], name: "sun".into() };
    let lamp = Light::Point { position: [0.5, 0.2, 3.0], intensity: [18.0; 3], name: "lamp".into() };
    let ambient = Light::Ambient { radiance: [0.1, 0.2, 0.3] };
    let lights = [sun, lamp.clone(), ambient.clone()];
    let mut chooser = square("chooser", 5, 1.0, 0.0);
    chooser.material.lights = Some(vec![2, 1]);
    let scene = Scene { source: "chosen".into(), objects: vec![chooser.clone()], ..Scene::default() };
    let (baked, _) = bake_diffuse(&scene, &lights, &BakeOptions::default());
    chooser.material.lights = None;
    let alone = Scene { objects: vec![chooser], ..scene };
    let (want, _) = bake_diffuse(&alone, &[lamp, ambient], &BakeOptions::default());
    assert_eq!(baked, want);
    let (every, _) = bake_diffuse(&alone, &lights, &BakeOptions::default());
    assert_ne!(baked, every, "the sun is left out");
}
