//! Ground truth for camera arrays: the bundled Spot is photographed by rigs
//! of cameras (rendered with the mesh renderer's own shading, so the
//! pictures are exactly what those cameras would see), the pictures are
//! converted to modulation, and the result is compared with converting the
//! mesh directly. Printed: error against the number of cameras and the
//! blending, for a rail, a grid, scattered positions and a ring.

use holo::cameras::image::Picture;
use holo::cameras::mesh_picture::camera_picture;
use holo::cameras::resample::{resample_rig, Blend, CameraOptions, CameraView, Parallax, PlacementRequest};
use holo::cameras::{look_rotation, Camera, ImageSource, Intrinsics, Pose, Rig};
use holo::geometry::{rgb_channels, Geometry, Views};
use holo::mesh::place::{place, Placement};
use holo::mesh::render::{render, RenderOptions, Supersample};
use holo::mesh::shade::Lighting;
use holo::mesh::Scene;
use holo::Modulation;
use rand::{Rng, SeedableRng};

/// 40 hololines × 96 emitters of 0.5 mm, 48 views over ±15°, emitter plane at
/// 0, viewer at 500 mm.
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
    let placement = Placement { rotate_deg: [0.0, -60.0, 0.0], ..Placement::default() };
    place(&mut scene, g, &placement).unwrap();
    scene
}

/// A camera at `centre` (display metres) looking at `target` (toed in);
/// pictures of 2 pixels per emitter pitch at the target's distance, a
/// little wider than the emitters.
fn camera(name: String, g: &Geometry, centre: [f64; 3], target: [f64; 3]) -> Camera {
    let d = [target[0] - centre[0], target[1] - centre[1], target[2] - centre[2]];
    let dist = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let f = 4.0 * dist / g.emitter_pitch_m;
    let (w, h) = (4 * g.emitters + 32, 4 * g.hololines + 32);
    Camera {
        name: name.clone(),
        image: ImageSource::File(format!("{name}.png").into()),
        width: w,
        height: h,
        intrinsics: Intrinsics { fx: f, fy: f, cx: (w as f64 - 1.0) / 2.0, cy: (h as f64 - 1.0) / 2.0 },
        pose: Pose { rotation: look_rotation(d, [0.0, -1.0, 0.0]), centre },
        depth: None,
    }
}

/// Each camera's picture of the scene, as the mesh renderer shades it.
/// `taken` holds the pictures already made, by the camera's centre and
/// rotation (bit for bit): the rails of 5, 9 and 17 stand where cameras of
/// the rail of 33 stand, and the grid's middle row is the rail of 17 (their
/// positions are `reach` scaled by powers of two, so the same bits); one
/// picture serves them all.
fn photograph(
    scene: &Scene,
    lighting: &Lighting,
    rig: &Rig,
    taken: &mut std::collections::HashMap<[u64; 12], CameraView>,
) -> Vec<CameraView> {
    rig.cameras
        .iter()
        .map(|c| {
            let mut key = [0u64; 12];
            for (k, v) in key.iter_mut().zip(c.pose.centre.iter().chain(c.pose.rotation.iter().flatten())) {
                *k = v.to_bits();
            }
            taken
                .entry(key)
                .or_insert_with(|| {
                    let p = camera_picture(scene, lighting, c, 2).unwrap();
                    CameraView {
                        picture: Picture { width: p.width, height: p.height, rgb: p.rgb },
                        depth_z: Some(p.depth_z),
                    }
                })
                .clone()
        })
        .collect()
}

/// (relative mean abs error over the rays the rig sees, fraction unseen).
fn compare(m: &Modulation, truth: &Modulation, mask: &[bool]) -> (f64, f64) {
    let plane = mask.len();
    let (mut err, mut sum) = (0.0, 0.0);
    for c in 0..3 {
        for (i, &unseen) in mask.iter().enumerate() {
            if !unseen {
                err += (m.samples()[c * plane + i] - truth.samples()[c * plane + i]).abs() as f64;
                sum += truth.samples()[c * plane + i] as f64;
            }
        }
    }
    (err / sum, mask.iter().filter(|&&u| u).count() as f64 / plane as f64)
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn camera_arrays_of_a_mesh_match_direct_conversion() {
    let g = display();
    let scene = spot(&g);
    let lighting = Lighting { lights: Lighting::default_lights(), model: Default::default() };
    let render_options =
        RenderOptions { supersample: Supersample::new(4, 4), lighting: lighting.clone(), ..RenderOptions::default() };
    let (truth, _) = render(&scene, &g, &render_options, &holo::progress::Silent).unwrap();
    let (d, y_v) = (g.viewer_distance_m, g.viewer_height_m);
    let target = [0.0, 0.0, g.emitter_z_m];
    // Cameras cover the view fan from every emitter: ±(24 mm + 500 mm × tan 15°).
    let reach = 0.024 + d * 15f64.to_radians().tan() + 0.005;
    let mut rigs: Vec<(String, Rig)> = Vec::new();
    let rig = |name: &str, cameras: Vec<Camera>| Rig {
        source: name.into(),
        cameras,
        metres_per_unit: 1.0,
        focus_distance: Some(d - g.emitter_z_m),
        linear: true,
    };
    for n in [5, 9, 17, 33] {
        let cams = (0..n)
            .map(|i| camera(format!("rail{i}"), &g, [-reach + 2.0 * reach * i as f64 / (n - 1) as f64, y_v, d], target))
            .collect();
        rigs.push((format!("rail of {n}"), rig("rail", cams)));
    }
    // A 17 × 3 grid, rows 20 mm apart around the viewer line.
    let mut cams = Vec::new();
    for r in 0..3 {
        for i in 0..17 {
            let x = -reach + 2.0 * reach * i as f64 / 16.0;
            let y = y_v + 0.02 * (r as f64 - 1.0);
            cams.push(camera(format!("grid{r}_{i}"), &g, [x, y, d], target));
        }
    }
    rigs.push(("grid 17 × 3".into(), rig("grid", cams)));
    // Scattered over the same area, with the corners held so the hull covers it.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let mut cams = Vec::new();
    for i in 0..51 {
        let (x, y) = match i {
            0 => (-reach, y_v - 0.02),
            1 => (reach, y_v - 0.02),
            2 => (-reach, y_v + 0.02),
            3 => (reach, y_v + 0.02),
            _ => (rng.gen_range(-reach..reach), y_v + rng.gen_range(-0.02..0.02)),
        };
        cams.push(camera(format!("scattered{i}"), &g, [x, y, d], target));
    }
    rigs.push(("scattered 51".into(), rig("scattered", cams)));
    // A ring (arc) at the viewer distance, every camera looking at the display centre.
    let half = (reach / d).atan();
    let cams = (0..33)
        .map(|i| {
            let a = -half + 2.0 * half * i as f64 / 32.0;
            camera(format!("ring{i}"), &g, [d * a.sin(), y_v, g.emitter_z_m + d * a.cos()], target)
        })
        .collect();
    rigs.push(("ring of 33".into(), rig("ring", cams)));

    let mut table = std::collections::HashMap::new();
    println!("| rig | surface | blend | depth maps | mean abs error / mean | unseen |");
    println!("|---|---|---|---|---|---|");
    let mut taken = std::collections::HashMap::new();
    for (name, rig) in &rigs {
        let views = photograph(&scene, &lighting, rig, &mut taken);
        for (blend, depth) in
            [(Blend::Nearest, false), (Blend::Linear, false), (Blend::NaturalNeighbour, false), (Blend::Linear, true)]
        {
            let options = CameraOptions {
                blend,
                use_depth: depth,
                want_mask: true,
                placement: PlacementRequest {
                    scale: Some(1.0),
                    centre: Some(target),
                    parallax: Parallax::True,
                    ..PlacementRequest::default()
                },
                ..CameraOptions::default()
            };
            let (m, report) = resample_rig(rig, &views, &g, &options, &holo::progress::Silent).unwrap();
            let (err, unseen) = compare(&m, &truth, report.mask.as_ref().unwrap());
            println!(
                "| {name} | {} | {} | {} | {err:.3} | {:.1}% |",
                report.surface,
                blend.name(),
                if depth { "yes" } else { "no" },
                unseen * 100.0
            );
            assert_eq!(unseen, 0.0, "{name}: every rig covers the view fan");
            table.insert((name.clone(), blend, depth), err);
        }
    }
    // 199 cameras, 146 places: the rails of 5, 9 and 17 and the grid's
    // middle row took no picture of their own, nor the scattered cameras'
    // four corners (the grid's) and the ring's middle (the rail's).
    assert_eq!(taken.len(), 33 + 2 * 17 + (51 - 4) + (33 - 1), "pictures shared by cameras in the same place");
    // Bounds. The floor (~0.04) is sampling: the direct conversion averages
    // 4 × 4 rays over each emitter's aperture and view interval, the
    // cameras' path averages rays over the aperture in pictures of finite
    // resolution, interpolated bilinearly; Spot's texture is detailed.
    let at = |rig: &str, blend, depth| table[&(rig.to_string(), blend, depth)];
    for rig in ["rail of 33", "grid 17 × 3", "scattered 51", "ring of 33"] {
        for (blend, depth) in
            [(Blend::Nearest, false), (Blend::Linear, false), (Blend::NaturalNeighbour, false), (Blend::Linear, true)]
        {
            assert!(at(rig, blend, depth) < 0.07, "{rig} {blend:?} depth {depth}: {}", at(rig, blend, depth));
        }
    }
    assert!(at("rail of 33", Blend::Linear, false) < at("rail of 5", Blend::Linear, false), "more cameras, less error");
    assert!(
        at("rail of 5", Blend::Linear, true) < 0.7 * at("rail of 5", Blend::Linear, false),
        "depth maps help sparse rails"
    );
    assert!(
        at("rail of 5", Blend::Linear, false) < at("rail of 5", Blend::Nearest, false),
        "blending beats the nearest camera"
    );
}
