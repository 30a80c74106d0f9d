//! Camera pictures of a mesh scene against the quilt of its modulation: the
//! cameras of a quilt ([`quilt_rig`]) photograph the scene
//! ([`camera_picture`]) and the quilt resamples the modulation the display
//! renderer made of it; away from edges (where the quilt interpolates
//! between the display's rays) they must agree.

use holo::cameras::mesh_picture::camera_picture;
use holo::cameras::quilt::{quilt_from_modulation, quilt_rig, QuiltSpec};
use holo::geometry::{rgb_channels, Geometry, Views};
use holo::mesh::render::{render, Engine, RenderOptions, Supersample};
use holo::mesh::shade::{Lighting, SpecularModel};
use holo::mesh::{Material, Object, Scene};

fn quad(name: &str, x: [f64; 2], y: [f64; 2], z: f64, glow: [f32; 3]) -> Object {
    Object {
        name: name.into(),
        positions: vec![[x[0], y[0], z], [x[1], y[0], z], [x[1], y[1], z], [x[0], y[1], z]],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material: Material {
            base_colour: [0.0, 0.0, 0.0, 1.0],
            specular: [0.0; 3],
            emissive: glow,
            ..Material::default()
        },
        ..Object::default()
    }
}

#[test]
fn quilt_tiles_agree_with_camera_pictures_of_the_scene() {
    // 30 hololines and 40 emitters of 0.5 mm, 64 views over ±20°, viewer at 500 mm.
    let mut g = Geometry::centred(
        30,
        40,
        Views::tan_spaced(64, -20f64.to_radians(), 20f64.to_radians()),
        0.5e-3,
        0.5e-3,
        0.002,
        0.5,
        rgb_channels(),
    );
    g.viewer_height_m = 0.003;
    let mm = 1e-3;
    let scene = Scene {
        source: "three planes".into(),
        objects: vec![
            quad("back", [-0.05, 0.05], [-0.05, 0.05], -5.0 * mm, [0.1, 0.1, 0.3]),
            quad("middle", [-6.0 * mm, 2.0 * mm], [-4.0 * mm, 5.0 * mm], 2.0 * mm, [0.9, 0.2, 0.1]),
            quad("front", [-mm, 7.0 * mm], [-6.0 * mm, 1.0 * mm], 5.0 * mm, [0.1, 0.8, 0.2]),
        ],
        ..Scene::default()
    };
    let lighting = Lighting { lights: vec![], model: SpecularModel::Blinn };
    let options = RenderOptions {
        supersample: Supersample::new(1, 1),
        engine: Engine::Reference,
        ..RenderOptions::lit_exactly(lighting.clone())
    };
    let (m, _) = render(&scene, &g, &options, &holo::progress::Silent).unwrap();
    // 20 mm × 15 mm at aspect 4/3: the tiles frame exactly the emitters and
    // hololines; with 40 × 30 tiles a tile pixel is an emitter and a hololine
    // (only views are interpolated), with 37 × 29 it falls between them.
    for (tile, want_same, want_mean) in [((40, 30), 0.98, 0.003), ((37, 29), 0.85, 0.02)] {
        let spec = QuiltSpec {
            columns: 4,
            rows: 3,
            tile_width: tile.0,
            tile_height: tile.1,
            aspect: 4.0 / 3.0,
            ..QuiltSpec::portrait()
        };
        let quilt = quilt_from_modulation(&m, &spec).unwrap();
        assert_eq!(quilt.outside, 0);
        let rig = quilt_rig(&g, &spec, std::path::Path::new("three_planes_qs4x3a1.3333.png")).unwrap();
        let (mut same, mut total, mut diff_sum) = (0usize, 0usize, 0f64);
        for (i, cam) in rig.cameras.iter().enumerate() {
            let pic = camera_picture(&scene, &lighting, cam, 1).unwrap();
            let (x0, y0) = spec.tile_origin(i);
            for v in 0..spec.tile_height {
                for u in 0..spec.tile_width {
                    let a = pic.rgb[v * pic.width + u];
                    let b = quilt.rgb[(y0 + v) * quilt.width + x0 + u];
                    for c in 0..3 {
                        let d = f64::from((a[c] - b[c]).abs());
                        total += 1;
                        same += usize::from(d < 1e-5);
                        diff_sum += d;
                    }
                }
            }
            // The front plane covers the centre of the frame in every view.
            let centre = pic.rgb[(spec.tile_height / 2) * pic.width + spec.tile_width / 2];
            assert_eq!(centre, [0.1, 0.8, 0.2], "view {i}");
        }
        let (same, mean) = (same as f64 / total as f64, diff_sum / total as f64);
        println!("tiles {tile:?}: same {same:.3}, mean |difference| {mean:.4}");
        assert!(same > want_same, "tiles {tile:?}: only {same:.3} of the components agree");
        assert!(mean < want_mean, "tiles {tile:?}: mean difference {mean}");
    }
}
