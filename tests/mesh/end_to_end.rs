//! End to end: a textured mesh → `.holo` (fast renderer) → fringes (the
//! assembler) → what a viewer sees (scalar diffraction, `holo view`),
//! against a direct ray-traced render of the same mesh from the same eye.

use std::path::PathBuf;

use holo::layout::Layout;
use holo::mesh::convert::{convert_mesh, ConvertOptions};
use holo::mesh::load::SceneSource;
use holo::mesh::place::apply;
use holo::mesh::shade::Lighting;
use holo::mesh::trace::eye_picture;
use holo::reconstruct::files::{view_file, EyeAt};

fn fixture(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures").join(path)
}

/// (relative L2 error, ratio of mean brightness) of a picture against the direct render.
fn compare(seen: &[f32], direct: &[f32]) -> (f64, f64) {
    let (mut err2, mut ref2, mut sum_seen, mut sum_direct) = (0.0, 0.0, 0.0, 0.0);
    for (a, b) in seen.iter().zip(direct) {
        let (a, b) = (*a as f64, *b as f64);
        err2 += (a - b) * (a - b);
        ref2 += b * b;
        sum_seen += a;
        sum_direct += b;
    }
    ((err2 / ref2).sqrt(), sum_seen / sum_direct)
}

fn end_to_end(layout: &Layout, bound: f64) {
    let scene_path = fixture("mesh/spot/spot.obj");
    let dir = tempfile::tempdir().unwrap();
    let holo_path = dir.path().join("spot.holo");
    let options = ConvertOptions::default();
    let report = convert_mesh(&scene_path, &layout.geometry, &holo_path, &options, &holo::progress::Silent).unwrap();
    println!("{}: {}", layout.name, report.placed);

    let mut scene = SceneSource::open(&scene_path).unwrap().scene_at(0.0).unwrap();
    apply(&mut scene, &report.placed.matrix);
    let lighting = Lighting { lights: report.lights.clone(), model: options.render.lighting.model };

    let pupil_m = 4e-3;
    let eyes_mm = [-30.0, 0.0, 30.0];
    let eyes: Vec<EyeAt> =
        eyes_mm.iter().map(|x| EyeAt { x_m: x * 1e-3, y_m: 0.0, distance_m: None, pupil_m, coherent: false }).collect();
    let pictures = view_file(&holo_path, Some(layout), 0, &eyes, &holo::progress::Silent).unwrap();
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("mesh-end-to-end");
    std::fs::create_dir_all(&out).unwrap();
    for (x_mm, picture) in eyes_mm.iter().zip(&pictures) {
        let direct = eye_picture(&scene, &lighting, &layout.geometry, x_mm * 1e-3, pupil_m, 8).unwrap();
        let (rel, mean_ratio) = compare(&picture.data, &direct);
        println!(
            "{} eye at x = {x_mm:+.0} mm: relative L2 error of the reconstructed view against the direct render {:.3} (bound {bound}), mean brightness ratio {:.3}",
            layout.name, rel, mean_ratio
        );
        picture.write_png(&out.join(format!("{}-view-x{x_mm:+.0}mm.png", layout.name)), 1.0, true).unwrap();
        let direct_picture = holo::reconstruct::picture::Picture { data: direct, ..picture.clone() };
        direct_picture.write_png(&out.join(format!("{}-direct-x{x_mm:+.0}mm.png", layout.name)), 1.0, true).unwrap();
        assert!(rel < bound, "{}: eye {x_mm} mm: error {rel} over {bound}", layout.name);
        assert!((mean_ratio - 1.0).abs() < 0.1, "{}: eye {x_mm} mm: brightness ratio {mean_ratio}", layout.name);
    }
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn reconstructed_views_match_a_direct_render_mark1() {
    end_to_end(&holo::layout::mark1(), 0.25);
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn reconstructed_views_match_a_direct_render_mark3() {
    end_to_end(&holo::layout::mark3(), 0.12);
}
