//! Camera arrays to modulation: the resampler on synthetic captures whose
//! every pixel is known (textured planes photographed analytically), so
//! each modulation ray has a known answer.

use holo::cameras::image::Picture;
use holo::cameras::resample::{resample_rig, Blend, CameraOptions, CameraView, Framing, Parallax, PlacementRequest};
use holo::cameras::{look_rotation, Camera, ImageSource, Intrinsics, Pose, Rig};
use holo::geometry::{rgb_channels, Geometry, Views};

/// A small display: 21 hololines, 48 emitters of 1 mm, 32 views over ±20°,
/// emitter plane at 0, viewer at 500 mm.
fn display() -> Geometry {
    Geometry::centred(
        21,
        48,
        Views::tan_spaced(32, -20f64.to_radians(), 20f64.to_radians()),
        1e-3,
        1e-3,
        0.0,
        0.5,
        rgb_channels(),
    )
}

/// A smooth colour pattern on the plane z = const (capture metres).
fn pattern(x: f64, y: f64) -> [f32; 3] {
    let a = (2.0 * std::f64::consts::PI * x / 0.37).sin();
    let b = (2.0 * std::f64::consts::PI * y / 0.29).cos();
    [(0.5 + 0.3 * a * b) as f32, (0.4 + 0.2 * a) as f32, (0.6 - 0.25 * b) as f32]
}

const W: usize = 200;
const H: usize = 120;

/// A camera at `centre` looking along −z (picture up = +y), 200 × 120
/// pixels, f = 200 px: 1 m wide at 1 m.
fn camera(name: String, centre: [f64; 3]) -> Camera {
    Camera {
        name: name.clone(),
        image: ImageSource::File(format!("{name}.png").into()),
        width: W,
        height: H,
        intrinsics: Intrinsics { fx: 200.0, fy: 200.0, cx: (W as f64 - 1.0) / 2.0, cy: (H as f64 - 1.0) / 2.0 },
        pose: Pose { rotation: look_rotation([0.0, 0.0, -1.0], [0.0, -1.0, 0.0]), centre },
        depth: None,
    }
}

/// What `cam` photographs of the pattern on the plane z = `plane_z`, and
/// the depth (camera z) of every pixel.
fn photograph(cam: &Camera, plane_z: f64) -> CameraView {
    let mut rgb = Vec::with_capacity(W * H);
    let mut depth = Vec::with_capacity(W * H);
    for v in 0..H {
        for u in 0..W {
            let d = cam.ray(u as f64, v as f64);
            let t = (plane_z - cam.pose.centre[2]) / d[2];
            let p = [cam.pose.centre[0] + t * d[0], cam.pose.centre[1] + t * d[1]];
            rgb.push(pattern(p[0], p[1]));
            depth.push((cam.pose.centre[2] - plane_z) as f32);
        }
    }
    CameraView { picture: Picture { width: W, height: H, rgb }, depth_z: Some(depth) }
}

/// A rail of `n` cameras from x = −0.9 to 0.9 at z = 1, focus distance 1.
fn rail(n: usize) -> Rig {
    let cameras =
        (0..n).map(|i| camera(format!("rail{i}"), [-0.9 + 1.8 * i as f64 / (n - 1) as f64, 0.0, 1.0])).collect();
    Rig { source: "synthetic rail".into(), cameras, metres_per_unit: 1.0, focus_distance: Some(1.0), linear: true }
}

/// The pattern seen along display ray (j, e, v) on the capture plane z = `plane_z`,
/// with the placement the resampler reports (identity rotation here).
fn expected(g: &Geometry, scale: f64, centre: [f64; 3], plane_z: f64, j: usize, e: usize, v: usize) -> [f32; 3] {
    let (x, y) = (g.emitter_x_m(e), g.hololine_y_m(j));
    let sx = g.views.theta_rad(v).tan();
    let sy = (g.viewer_height_m - y) / (g.viewer_distance_m - g.emitter_z_m);
    // Capture ray: origin centre + (x, y, 0)/scale, direction (sx, sy, 1).
    let o = [centre[0] + x / scale, centre[1] + y / scale, centre[2]];
    let t = plane_z - o[2];
    pattern(o[0] + sx * t, o[1] + sy * t)
}

/// (mean |error| over seen rays / mean value, fraction unseen).
fn error_against_plane(n: usize, blend: Blend, plane_z: f64, use_depth: bool) -> (f64, f64, f64) {
    error_with(n, blend, plane_z, use_depth, physical())
}

/// The placement whose rays the test's `expected` traces: the cameras at the
/// viewer's distance, ray directions as captured.
fn physical() -> PlacementRequest {
    PlacementRequest { framing: Framing::CamerasAtViewer, parallax: Parallax::True, ..PlacementRequest::default() }
}

fn error_with(n: usize, blend: Blend, plane_z: f64, use_depth: bool, placement: PlacementRequest) -> (f64, f64, f64) {
    let g = display();
    let rig = rail(n);
    let views: Vec<CameraView> = rig.cameras.iter().map(|c| photograph(c, plane_z)).collect();
    let fill = placement.framing == Framing::FillWidth;
    let options = CameraOptions { blend, use_depth, want_mask: true, placement, ..CameraOptions::default() };
    let (m, report) = resample_rig(&rig, &views, &g, &options, &holo::progress::Silent).unwrap();
    // Auto placement: the focus point (0, 0, 0) at the emitter plane, the
    // cameras (1 m away) at the viewer's 500 mm.
    let scale = report.scale;
    assert!((scale - if fill { 0.048 } else { 0.5 }).abs() < 1e-12 && report.centre.iter().all(|c| c.abs() < 1e-12));
    let mask = report.mask.as_ref().unwrap();
    let (mut err, mut sum, mut seen) = (0.0, 0.0, 0usize);
    let (e_n, v_n) = (g.emitters, g.views.count);
    for j in 0..g.hololines {
        for e in 0..e_n {
            for v in 0..v_n {
                if mask[(j * e_n + e) * v_n + v] {
                    continue;
                }
                let want = expected(&g, scale, [0.0; 3], plane_z, j, e, v);
                for (c, want) in want.iter().enumerate() {
                    let got = m.samples()[((c * g.hololines + j) * e_n + e) * v_n + v];
                    err += (got - want).abs() as f64;
                    sum += *want as f64;
                }
                seen += 1;
            }
        }
    }
    assert!(seen > 0);
    let unseen = report.unseen as f64 / report.rays as f64;
    (err / sum, unseen, seen as f64)
}

#[test]
fn a_plane_at_the_focus_is_reproduced_by_every_blend() {
    for blend in [Blend::Nearest, Blend::Linear, Blend::NaturalNeighbour] {
        let (err, unseen, _) = error_against_plane(9, blend, 0.0, false);
        println!(
            "{}: plane at the focus, 9 cameras: mean error {err:.2e}, {:.1}% unseen",
            blend.name(),
            unseen * 100.0
        );
        assert!(err < 2e-3, "{blend:?}: {err}");
        assert!(unseen < 0.05, "the rail covers the view fan: {unseen}");
    }
}

#[test]
fn off_focus_planes_need_many_cameras_or_depth() {
    // A plane 0.1 m behind the focus: blending without depth ghosts, less with more cameras; with depth maps it is exact.
    let mut last = f64::INFINITY;
    for n in [5, 9, 17, 33] {
        let (err, _, _) = error_against_plane(n, Blend::Linear, -0.1, false);
        let (err_depth, _, _) = error_against_plane(n, Blend::Linear, -0.1, true);
        // Filling the width puts the cameras nearer than the viewer line: the vertical
        // perspective of off-focus content then differs from the display's.
        let fill = PlacementRequest { framing: Framing::FillWidth, ..physical() };
        let (err_fill, _, _) = error_with(n, Blend::Linear, -0.1, false, fill);
        println!("{n} cameras, plane 0.1 m off focus: linear {err:.2e}, depth-aware {err_depth:.2e}; cameras nearer than the viewer: {err_fill:.2e}");
        assert!(err < last, "more cameras, less error");
        assert!(err_depth < 2e-3 && err_depth < err, "depth maps put every ray on the plane");
        assert!(n < 17 || err_fill > 5.0 * err, "cameras at the viewer distance keep the vertical perspective");
        last = err;
    }
}

#[test]
fn rays_beyond_the_rail_are_unseen_and_zero() {
    // Three cameras close together see only the middle views.
    let g = display();
    let mut rig = rail(3);
    for (i, c) in rig.cameras.iter_mut().enumerate() {
        c.pose.centre[0] = -0.05 + 0.05 * i as f64;
    }
    let views: Vec<CameraView> = rig.cameras.iter().map(|c| photograph(c, 0.0)).collect();
    let options = CameraOptions { want_mask: true, placement: physical(), ..CameraOptions::default() };
    let (m, report) = resample_rig(&rig, &views, &g, &options, &holo::progress::Silent).unwrap();
    let mask = report.mask.unwrap();
    assert!(report.unseen > report.rays / 2, "{} of {}", report.unseen, report.rays);
    assert_eq!(mask.iter().filter(|&&u| u).count() as u64, report.unseen);
    let plane = g.hololines * g.emitters * g.views.count;
    for c in 0..3 {
        for (i, &u) in mask.iter().enumerate() {
            if u {
                assert_eq!(m.samples()[c * plane + i], 0.0);
            }
        }
    }
    println!("{}; {}", report.surface, report.placement);
}

/// The error of a resampling that must fail (without printing a frame if it does not).
fn error_of(rig: &Rig, views: &[CameraView], g: &Geometry) -> String {
    match resample_rig(rig, views, g, &CameraOptions::default(), &holo::progress::Silent) {
        Ok(_) => panic!("{}: expected an error", rig.source),
        Err(e) => e.to_string(),
    }
}

#[test]
fn coincident_cameras_and_missing_focus_are_errors_naming_them() {
    let g = display();
    // Two cameras at one place looking different ways: the triangulation cannot separate them.
    let mut rig = rail(4);
    rig.cameras[2].pose.centre = rig.cameras[1].pose.centre;
    rig.cameras[2].pose.rotation = look_rotation([0.05, 0.0, -1.0], [0.0, -1.0, 0.0]);
    let views: Vec<CameraView> = rig.cameras.iter().map(|c| photograph(c, 0.0)).collect();
    let e = error_of(&rig, &views, &g);
    assert!(e.contains("rail1") && e.contains("rail2"), "{e}");
    // The same camera listed twice (as Middlebury's temple ring does) is used once, with a warning.
    let mut rig = rail(4);
    rig.cameras[2].pose = rig.cameras[1].pose;
    let (_, report) = resample_rig(&rig, &views, &g, &CameraOptions::default(), &holo::progress::Silent).unwrap();
    assert!(report.warnings.iter().any(|w| w.contains("rail1") && w.contains("rail2")), "{:?}", report.warnings);
    let mut rig = rail(4);
    rig.focus_distance = None;
    let e = error_of(&rig, &views, &g);
    assert!(e.contains("focus distance") && !e.contains("--"), "{e}");
    // Cameras whose pictures hold nothing of what the display would show.
    let mut rig = rail(4);
    for c in &mut rig.cameras {
        c.intrinsics.cx += 5000.0;
    }
    let e = error_of(&rig, &views, &g);
    assert!(e.contains("no camera sees") && e.contains("rail0"), "{e}");
    let mut rig = rail(4);
    rig.cameras[3].intrinsics.cx = f64::NAN;
    let e = error_of(&rig, &views, &g);
    assert!(e.contains("rail3") && e.contains("not finite"), "{e}");
    // Collinear cameras are a rail: across the horizontal parallax (even
    // slanted by 30°) they convert; running up and down they cannot fill
    // the views, and the error names the line's end cameras.
    for (degrees, ok) in [(30.0f64, true), (60.0, false), (90.0, false)] {
        let (c, s) = (degrees.to_radians().cos(), degrees.to_radians().sin());
        let cameras =
            (0..5).map(|i| camera(format!("line{i}"), [0.2 * c * (i as f64 - 2.0), 0.2 * s * (i as f64 - 2.0), 1.0]));
        let rig = Rig { source: format!("rail at {degrees}°"), cameras: cameras.collect(), ..rail(2) };
        let views: Vec<CameraView> = rig.cameras.iter().map(|c| photograph(c, 0.0)).collect();
        if ok {
            let (_, report) =
                resample_rig(&rig, &views, &g, &CameraOptions::default(), &holo::progress::Silent).unwrap();
            assert!(report.surface.contains("rail"), "{}", report.surface);
        } else {
            let e = error_of(&rig, &views, &g);
            assert!(e.contains("collinear") && e.contains("line0") && e.contains("line4"), "{e}");
        }
    }
}

/// The fast path (each view's triangle stepped along a hololine, the
/// cameras' samples shared by the views of an emitter) gives the brute-force
/// reference's frame (every ray on its own, located by trying every triangle
/// or interval; natural-neighbour weights come from spade in both) on a
/// jittered grid, a rail and a ring, for every blending and placement
/// that takes a different path: eye-mapped and true parallax, a centre moved
/// along the focus plane or off it, several rays per emitter, depth maps.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn fast_path_equals_the_brute_force_reference() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let g = display();
    let mut grid = Vec::new();
    for r in 0..4 {
        for c in 0..5 {
            let x = -0.4 + 0.2 * c as f64 + rng.gen_range(-0.05..0.05);
            let y = -0.15 + 0.1 * r as f64 + rng.gen_range(-0.03..0.03);
            grid.push(camera(format!("grid{r}{c}"), [x, y, 1.0]));
        }
    }
    // A ring of 9 cameras 1 m from the scene's centre over ±40°, looking at it.
    let ring = (0..9).map(|i| {
        let a = (-40.0 + 10.0 * i as f64 + rng.gen_range(-2.0..2.0)).to_radians();
        let centre = [a.sin(), rng.gen_range(-0.02..0.02), a.cos()];
        let down = [0.0, -1.0, 0.0];
        Camera {
            pose: Pose { rotation: look_rotation(centre.map(|c| -c), down), centre },
            ..camera(format!("ring{i}"), centre)
        }
    });
    let rig = |source: &str, cameras: Vec<Camera>| Rig {
        source: source.into(),
        cameras,
        metres_per_unit: 1.0,
        focus_distance: Some(1.0),
        linear: true,
    };
    let rigs = [rig("jittered grid", grid), rig("rail", rail(6).cameras), rig("ring", ring.collect())];
    // (Centres off round numbers: a ray whose focus point lands exactly on a
    // picture's edge is seen or not by a rounding.)
    let placements = [
        ("eye-mapped", PlacementRequest::default(), None),
        ("true parallax", PlacementRequest { parallax: Parallax::True, ..PlacementRequest::default() }, None),
        (
            "centre moved along the focus plane",
            PlacementRequest { centre: Some([0.0317, -0.0213, 0.0]), ..PlacementRequest::default() },
            None,
        ),
        (
            "centre off the focus plane",
            PlacementRequest { centre: Some([0.0051, 0.0, 0.0437]), ..PlacementRequest::default() },
            None,
        ),
        ("3 rays per emitter", PlacementRequest::default(), Some(3)),
    ];
    for rig in &rigs {
        for depth in [false, true] {
            let views: Vec<CameraView> = rig.cameras.iter().map(|c| photograph(c, -0.05)).collect();
            for placement in &placements {
                fast_equals_reference(rig, &views, &g, placement, depth, 4);
            }
        }
    }
}

/// The fast path against the brute-force reference for one rig, its
/// pictures, one placement and ray count, every blend: the same unseen rays
/// and samples to 1e-5; at least `1/seen_at_least` of the rays seen.
fn fast_equals_reference(
    rig: &Rig,
    views: &[CameraView],
    g: &Geometry,
    (words, placement, taps): &(&str, PlacementRequest, Option<usize>),
    depth: bool,
    seen_at_least: u64,
) {
    for blend in Blend::ALL {
        let fast = CameraOptions {
            blend,
            use_depth: depth,
            want_mask: true,
            placement: placement.clone(),
            emitter_taps: *taps,
            ..CameraOptions::default()
        };
        let reference = CameraOptions { reference: true, ..fast.clone() };
        let (a, ra) = resample_rig(rig, views, g, &fast, &holo::progress::Silent).unwrap();
        let (b, rb) = resample_rig(rig, views, g, &reference, &holo::progress::Silent).unwrap();
        let case = format!("{}, {words}, {}, depth {depth}", rig.source, blend.name());
        assert_eq!(ra.unseen, rb.unseen, "{case}");
        assert_eq!(ra.mask, rb.mask, "{case}");
        let worst = a.samples().iter().zip(b.samples()).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
        let seen = ra.rays - ra.unseen;
        println!("{case}: {}; {seen} of {} rays seen, largest difference {worst:.2e}", ra.surface, ra.rays);
        assert!(seen > ra.rays / seen_at_least, "{case}: the rig sees a good part of the display");
        assert!(worst < 1e-5, "{case}: {worst}");
    }
}

/// A picture of one flat colour: which camera a ray came from.
fn flat(value: f32) -> CameraView {
    CameraView { picture: Picture { width: W, height: H, rgb: vec![[value; 3]; W * H] }, depth_z: None }
}

/// By default a narrow rail's cameras are spread across the eye positions
/// that see the display: every ray an eye sees comes from one place on the
/// rail, left eyes from left cameras, and no ray inside the capture's frame
/// is unseen.
#[test]
fn the_default_spreads_a_narrow_rail_across_the_eyes() {
    let g = display();
    let mut rig = rail(5);
    for (i, c) in rig.cameras.iter_mut().enumerate() {
        c.pose.centre[0] = -0.04 + 0.02 * i as f64;
    }
    let views: Vec<CameraView> = (0..5).map(|i| flat(i as f32 + 1.0)).collect();
    let options = CameraOptions { blend: Blend::Nearest, want_mask: true, ..CameraOptions::default() };
    let (m, report) = resample_rig(&rig, &views, &g, &options, &holo::progress::Silent).unwrap();
    println!(
        "{}; {} of {} unseen, {} outside the frame",
        report.placement, report.unseen, report.rays, report.unseen_outside_frame
    );
    // Unseen: the frame's borders, and a sliver at its sides the outer cameras' pictures miss.
    assert!(report.unseen - report.unseen_outside_frame < report.rays / 50, "{}", report.unseen);
    // The pictures (200 × 120, 1 m × 0.6 m at the focus) fit the 48 × 21 mm display by its height.
    assert!((report.scale - 0.021 / 0.6).abs() < 1e-12, "{}", report.scale);
    let d = g.viewer_distance_m - g.emitter_z_m;
    let (e_n, v_n) = (g.emitters, g.views.count);
    let j = g.hololines / 2;
    let mut by_eye: Vec<(f64, f32)> = Vec::new();
    for e in 0..e_n {
        for v in 0..v_n {
            let i = (j * e_n + e) * v_n + v;
            if !report.mask.as_ref().unwrap()[i] {
                by_eye.push((g.emitter_x_m(e) + d * g.ray_slope_x(v as f64), m.samples()[i]));
            }
        }
    }
    by_eye.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(by_eye.windows(2).all(|w| w[0].1 <= w[1].1), "each eye position sees from one camera, in order");
    assert_eq!((by_eye[0].1, by_eye[by_eye.len() - 1].1), (1.0, 5.0), "the outer eyes see from the outer cameras");
    // With true parallax the same rail covers only the middle views.
    let true_parallax = CameraOptions {
        placement: PlacementRequest { parallax: Parallax::True, ..PlacementRequest::default() },
        ..options
    };
    let (_, report) = resample_rig(&rig, &views, &g, &true_parallax, &holo::progress::Silent).unwrap();
    assert!(report.unseen > report.rays / 2, "{} of {}", report.unseen, report.rays);
}

/// A ring of cameras rolled a quarter turn (their right is the ring's axis,
/// as in Middlebury's temple): the display's up is the ring's axis and its
/// horizontal runs along the ring, so the views see round the scene.
#[test]
fn a_ring_of_rolled_cameras_is_shown_upright_around_its_axis() {
    let g = display();
    let cameras: Vec<Camera> = (0..12)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 12.0;
            let centre = [a.sin(), 0.0, a.cos()];
            let forward = [-a.sin(), 0.0, -a.cos()];
            // Rolled: picture right = +y (up), picture down = the ring's tangent.
            let down = [a.cos(), 0.0, -a.sin()];
            let mut c = camera(format!("ring{i}"), centre);
            c.pose.rotation = look_rotation(forward, down);
            c
        })
        .collect();
    assert!((cameras[3].pose.rotation[0][1] - 1.0).abs() < 1e-9, "the cameras' right is +y");
    let rig =
        Rig { source: "synthetic ring".into(), cameras, metres_per_unit: 1.0, focus_distance: None, linear: true };
    let views: Vec<CameraView> = (0..12).map(|i| flat(i as f32 + 1.0)).collect();
    let (m, report) = resample_rig(&rig, &views, &g, &CameraOptions::default(), &holo::progress::Silent).unwrap();
    println!("{}; {}; {} of {} rays unseen", report.surface, report.placement, report.unseen, report.rays);
    assert!(report.placement.contains("cameras on a ring: up along its axis (the rig's +y)"), "{}", report.placement);
    assert!(report.placement.contains("the display facing camera ring0"), "{}", report.placement);
    assert!(report.placement.contains("true angles"), "a closed ring keeps its angles: {}", report.placement);
    assert!(report.unseen - report.unseen_outside_frame < report.rays / 20, "{}", report.unseen);
    // Across the views of the middle emitter the eye moves round the ring:
    // camera 0 in the middle, blended toward camera 11 (value 12) on the
    // display's left and camera 1 (value 2) on its right, 30° away.
    let (e_n, v_n) = (g.emitters, g.views.count);
    let at = |v: usize| m.samples()[((g.hololines / 2) * e_n + e_n / 2) * v_n + v];
    let seen: Vec<f32> = (0..v_n).map(at).collect();
    assert!((seen[v_n / 2 - 1] - 1.0).abs() < 0.3 && (seen[v_n / 2] - 1.0).abs() < 0.3, "{seen:?}");
    assert!(seen[0] > 4.0 && seen[0] < 12.0, "left eyes see toward camera 11: {seen:?}");
    assert!(seen[v_n - 1] > 1.3 && seen[v_n - 1] < 2.0, "right eyes see toward camera 1: {seen:?}");
}

/// The placement a camera conversion records: the capture's focus point at
/// the middle of the emitter plane, capture units scaled to display metres.
#[test]
fn the_recorded_placement_puts_the_focus_point_on_the_emitter_plane() {
    let g = display();
    let rig = rail(5);
    let views: Vec<CameraView> = rig.cameras.iter().map(|c| photograph(c, 0.0)).collect();
    let resampler = holo::cameras::resample::RigResampler::new(&rig, &views, &g, &CameraOptions::default()).unwrap();
    let m = resampler.display_from_capture();
    let report = resampler.report(Default::default(), None);
    let at =
        |p: [f64; 3]| -> [f64; 3] { std::array::from_fn(|i| (0..3).map(|k| m[i][k] * p[k]).sum::<f64>() + m[i][3]) };
    let centre = at(report.centre);
    assert!(
        centre[0].abs() < 1e-12 && centre[1].abs() < 1e-12 && (centre[2] - g.emitter_z_m).abs() < 1e-12,
        "{centre:?}"
    );
    // One capture unit along x is `scale` display metres.
    let step = at([report.centre[0] + 1.0, report.centre[1], report.centre[2]]);
    assert!(((step[0] - centre[0]).abs() - report.scale).abs() < 1e-12, "{step:?} {}", report.scale);
    assert_eq!(m[3], [0.0, 0.0, 0.0, 1.0]);
}

/// A small full-parallax display: [`display`] with 5 vertical views over
/// ±10° (spec §8: rays `(tan θ_h, tan φ_k, 1)` from the emitter).
fn full_parallax_display() -> Geometry {
    display().with_vertical_views(Views::tan_spaced(5, -10f64.to_radians(), 10f64.to_radians()))
}

/// A planar grid of `columns × rows` cameras at z = 1 over x ∈ ±`half_width`,
/// y ∈ ±0.25 (a camera sees 0.3 m above and below its own height at 1 m, so
/// the outer rows still see the middle of the scene).
fn planar_grid(columns: usize, rows: usize, half_width: f64) -> Rig {
    let mut cameras = Vec::new();
    for r in 0..rows {
        for c in 0..columns {
            let x = half_width * (2.0 * c as f64 / (columns - 1) as f64 - 1.0);
            let y = -0.25 + 0.5 * r as f64 / (rows - 1) as f64;
            cameras.push(camera(format!("grid{r}_{c}"), [x, y, 1.0]));
        }
    }
    Rig { source: "synthetic grid".into(), cameras, ..rail(2) }
}

/// Full parallax: every ray `(j, e, h, k)` goes up or down at its vertical
/// view's angle, so with the capture's directions as they are (true
/// parallax, the cameras at the viewer's distance) and depth maps, each ray
/// shows the textured plane where its own line meets it; a plane off the
/// focus moves between the views above and below, as the scene's depth says.
#[test]
fn full_parallax_rays_see_the_plane_along_their_own_directions() {
    let g = full_parallax_display();
    let rig = planar_grid(9, 7, 0.9);
    let plane_z = -0.1;
    let views: Vec<CameraView> = rig.cameras.iter().map(|c| photograph(c, plane_z)).collect();
    let options = CameraOptions { want_mask: true, placement: physical(), ..CameraOptions::default() };
    let (m, report) = resample_rig(&rig, &views, &g, &options, &holo::progress::Silent).unwrap();
    assert_eq!(report.rays, (g.hololines * g.emitters * g.views.count * 5) as u64);
    let (scale, mask) = (report.scale, report.mask.as_ref().unwrap());
    let (vh, vv) = (g.views.count, 5);
    let (mut err, mut sum, mut seen, mut moved) = (0.0f64, 0.0f64, 0usize, 0.0f64);
    for j in 0..g.hololines {
        for e in 0..g.emitters {
            for k in 0..vv {
                for h in 0..vh {
                    let view = g.view_index(h, k);
                    if mask[(j * g.emitters + e) * vh * vv + view] {
                        continue;
                    }
                    let ray = g.ray(j, e, view);
                    let (x, y) = (ray.origin_m[0], ray.origin_m[1]);
                    let o = [x / scale, y / scale, 0.0];
                    let t = plane_z - o[2];
                    let want = pattern(o[0] + ray.slope_x * t, o[1] + ray.slope_y * t);
                    for (c, want) in want.iter().enumerate() {
                        let got = m.get(c, j, e, view);
                        err += (got - want).abs() as f64;
                        sum += *want as f64;
                    }
                    seen += 1;
                }
            }
            // The middle view seen from above and from below (blue varies with y).
            let (low, high) = (g.view_index(vh / 2, 0), g.view_index(vh / 2, vv - 1));
            moved = moved.max((m.get(2, j, e, low) - m.get(2, j, e, high)).abs() as f64);
        }
    }
    let unseen = report.unseen as f64 / report.rays as f64;
    println!(
        "full parallax, 9 × 7 cameras, plane 0.1 m off focus, depth maps: mean error {:.2e}, {:.1} % unseen; views above and below differ by up to {moved:.3}; {}",
        err / sum,
        unseen * 100.0,
        report.placement
    );
    assert!(seen > 0 && unseen < 0.05, "the grid covers the view cone: {unseen}");
    assert!(err / sum < 2e-3, "{}", err / sum);
    assert!(moved > 0.05, "vertical parallax: {moved}");
}

/// Full parallax's fast path (views of an emitter sharing the cameras'
/// samples, each view stepped along a hololine) equals the brute-force
/// reference, for a planar grid (whose eye map spans the eyes' heights too)
/// and a ring, every blend, with and without depth maps.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn full_parallax_fast_path_equals_the_brute_force_reference() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    // 7 hololines of 16 emitters, 12 × 5 views (the reference is slow).
    let g = Geometry::centred(
        7,
        16,
        Views::tan_spaced(12, -20f64.to_radians(), 20f64.to_radians()),
        1e-3,
        1e-3,
        0.0,
        0.5,
        rgb_channels(),
    )
    .with_vertical_views(Views::tan_spaced(5, -10f64.to_radians(), 10f64.to_radians()));
    let mut grid = planar_grid(5, 4, 0.4);
    for c in &mut grid.cameras {
        c.pose.centre[0] += rng.gen_range(-0.05..0.05);
        c.pose.centre[1] += rng.gen_range(-0.02..0.02);
    }
    let ring = (0..7).map(|i| {
        let a = (-30.0 + 10.0 * i as f64 + rng.gen_range(-2.0..2.0)).to_radians();
        let centre = [a.sin(), rng.gen_range(-0.15..0.15), a.cos()];
        Camera {
            pose: Pose { rotation: look_rotation(centre.map(|c| -c), [0.0, -1.0, 0.0]), centre },
            ..camera(format!("ring{i}"), centre)
        }
    });
    let ring = Rig { source: "ring".into(), cameras: ring.collect(), ..rail(2) };
    // (One ray per emitter unless said: by default a camera pixel here is a
    // fifth of an emitter, and 5 × 5 rays per emitter make the reference slow.)
    let placements = [
        ("eye-mapped", PlacementRequest::default(), Some(1)),
        ("true parallax", PlacementRequest { parallax: Parallax::True, ..PlacementRequest::default() }, Some(1)),
        ("2 × 2 rays per emitter", PlacementRequest::default(), Some(2)),
    ];
    for rig in [&grid, &ring] {
        for depth in [false, true] {
            let views: Vec<CameraView> = rig.cameras.iter().map(|c| photograph(c, -0.05)).collect();
            for placement in &placements {
                // (A ring at true angles sees only the views toward its cameras.)
                fast_equals_reference(rig, &views, &g, placement, depth, 8);
            }
        }
    }
}
