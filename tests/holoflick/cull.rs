//! Culling what a frame does not need is conservative (never drops what a
//! ray meets) and saves work without changing a sample.

use holo::geometry::{rgb_channels, Geometry, Views};
use holo::holoflick::shader::cull::{cull_back_faces, display_sees_box};
use holo::mesh::render::{render, Engine, RenderOptions, Supersample};
use holo::mesh::{Material, Object, Scene};
use rand::{Rng, SeedableRng};

fn display(z_e: f64) -> Geometry {
    Geometry::centred(16, 40, Views::tan_spaced(24, -0.3, 0.25), 1e-3, 1e-3, z_e, 0.5, rgb_channels())
}

/// Whether the line through (x, y, z_e) with slopes (sx, sy) meets the box.
fn line_meets_box(o: [f64; 3], d: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> bool {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        if d[k] == 0.0 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return false;
            }
        } else {
            let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
    }
    t0 <= t1
}

/// The bounds of an object's positions (`None` without vertices).
fn object_bounds(o: &Object) -> Option<([f64; 3], [f64; 3])> {
    let mut it = o.positions.iter();
    let first = *it.next()?;
    Some(it.fold((first, first), |(lo, hi), p| {
        (std::array::from_fn(|k| lo[k].min(p[k])), std::array::from_fn(|k| hi[k].max(p[k])))
    }))
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn box_test_never_drops_a_box_a_ray_meets() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let (mut seen, mut unseen) = (0, 0);
    for z_e in [0.0, 0.02] {
        let g = display(z_e);
        for _ in 0..400 {
            let c: [f64; 3] = [rng.gen_range(-0.08..0.08), rng.gen_range(-0.03..0.03), rng.gen_range(-0.3..0.4)];
            let h: [f64; 3] = std::array::from_fn(|_| rng.gen_range(0.0005..0.02));
            let (lo, hi) = (std::array::from_fn(|k| c[k] - h[k]), std::array::from_fn(|k| c[k] + h[k]));
            // Sub-rays across each emitter, hololine and view interval.
            let mut met = false;
            'rays: for j in 0..g.hololines {
                for e in 0..g.emitters {
                    for v in 0..g.views.count {
                        for (fx, fy, fv) in
                            [(-0.49, -0.49, -0.49), (0.0, 0.0, 0.0), (0.49, 0.49, 0.49), (0.49, -0.49, 0.3)]
                        {
                            let x = g.emitter_x_m(e) + fx * g.emitter_pitch_m;
                            let y = g.hololine_y_m(j) + fy * g.hololine_pitch_m;
                            let v0 = g.views.theta_rad(v).tan();
                            let v1 = g.views.theta_rad((v + 1).min(g.views.count - 1)).tan();
                            let sx = v0 + fv * (v1 - v0);
                            let sy = (g.viewer_height_m - y) / (g.viewer_distance_m - g.emitter_z_m);
                            if line_meets_box([x, y, g.emitter_z_m], [sx, sy, 1.0], lo, hi) {
                                met = true;
                                break 'rays;
                            }
                        }
                    }
                }
            }
            let kept = display_sees_box(&g, lo, hi);
            assert!(kept || !met, "a box a ray meets was dropped: {lo:?} {hi:?}");
            seen += usize::from(met);
            unseen += usize::from(!kept);
        }
    }
    println!("boxes met by rays {seen} of 800; dropped {unseen}");
    assert!(seen > 100 && unseen > 100, "both kinds must occur");
}

fn square(name: &str, centre: [f64; 3], half: f64, double_sided: bool) -> Object {
    let c = centre;
    Object {
        name: name.into(),
        positions: vec![
            [c[0] - half, c[1] - half, c[2]],
            [c[0] + half, c[1] - half, c[2]],
            [c[0] + half, c[1] + half, c[2]],
            [c[0] - half, c[1] + half, c[2]],
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material: Material { emissive: [0.5, 0.4, 0.3], double_sided, ..Material::default() },
        ..Object::default()
    }
}

#[test]
fn culled_frames_give_the_same_samples_with_less_work() {
    let g = display(0.0);
    // Seen: a square facing the viewer. Unseen: one far to the side, and one
    // facing away from every viewpoint of a box around the viewer line.
    let mut back = square("back", [0.0, 0.0, -0.01], 0.01, false);
    back.triangles = vec![[0, 2, 1], [0, 3, 2]];
    let scene = Scene {
        objects: vec![
            square("seen", [0.0, 0.0, 0.005], 0.012, false),
            square("aside", [3.0, 0.0, 0.0], 0.05, false),
            back,
        ],
        ..Scene::default()
    };
    let options =
        RenderOptions { supersample: Supersample::new(2, 2), engine: Engine::Fast, ..RenderOptions::default() };
    let (all, all_stats) = render(&scene, &g, &options, &holo::progress::Silent).unwrap();
    let mut culled = scene.clone();
    culled.objects.retain(|o| object_bounds(o).is_some_and(|(lo, hi)| display_sees_box(&g, lo, hi)));
    assert_eq!(culled.objects.len(), 2, "the object aside is dropped");
    let couch: Vec<[f64; 3]> = [-0.2, 0.2]
        .iter()
        .flat_map(|&x| [-0.1, 0.1].into_iter().flat_map(move |y| [0.4, 0.6].into_iter().map(move |z| [x, y, z])))
        .collect();
    let dropped = cull_back_faces(&mut culled.objects, &couch);
    assert_eq!(dropped, 2, "the square facing away");
    let (fewer, fewer_stats) = render(&culled, &g, &options, &holo::progress::Silent).unwrap();
    println!("work: all {all_stats:?}; culled {fewer_stats:?}");
    assert!(all == fewer, "culling changed a sample");
    assert!(fewer_stats.segments + fewer_stats.back_face_culled < all_stats.segments + all_stats.back_face_culled);
    assert!(all.samples().iter().any(|&v| v > 0.0));
}
