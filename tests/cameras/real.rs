//! Real captures through `holo convert cameras`: HCI `dino` (its geometry
//! from `parameters.cfg`), the Middlebury temple ring and the Looking Glass
//! quilt convert without error; the quilt → `.holo` → quilt round trip keeps
//! the views (error printed and bounded); a reconstructed `holo view`
//! picture of `dino` is written as a test artefact.

use std::path::PathBuf;

use holo::cameras::convert::{convert_camera_files, load_view, CameraConvertOptions};
use holo::cameras::quilt::{quilt_from_modulation, QuiltSpec};
use holo::cameras::resample::{resample_rig, CameraOptions, CameraView, Parallax, PlacementRequest};
use holo::geometry::{rgb_channels, Geometry, Views};
use holo::reconstruct::files::{view_file, EyeAt};

use crate::common;
use common::shared_data;

fn artefacts() -> PathBuf {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cameras-real");
    std::fs::create_dir_all(&out).unwrap();
    out
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn real_captures_convert_and_dino_is_seen_through_the_display() {
    let Some(data) = shared_data() else { return };
    let layout = holo::layout::mark3();
    let dir = tempfile::tempdir().unwrap();
    for (name, input) in [
        ("dino", data.join("lightfield_hci_dino")),
        ("temple", data.join("multiview_middlebury_templeSparseRing/templeSparseRing")),
        ("quilt", data.join("quilt_lookingglass_4x8/example02_qs4x8a1.6.png")),
    ] {
        let output = dir.path().join(format!("{name}.holo"));
        let report = convert_camera_files(
            &input,
            &layout.geometry,
            &output,
            &CameraConvertOptions::default(),
            &holo::progress::Silent,
        )
        .unwrap();
        let r = &report.resample;
        println!(
            "{name}: {} cameras, {}; {}; {:.1}% of rays unseen",
            report.cameras,
            r.surface,
            r.placement,
            100.0 * r.unseen as f64 / r.rays as f64
        );
        for w in &r.warnings {
            println!("  warning: {w}");
        }
        // By default the capture fills the display: what is unseen is the
        // border a capture of another shape leaves, not missing views.
        assert!(100 * (r.unseen - r.unseen_outside_frame) < r.rays, "{name}: {} of {} unseen", r.unseen, r.rays);
        assert!(4 * r.unseen_outside_frame < r.rays, "{name}: {} outside the frame", r.unseen_outside_frame);
        let m = holo::read(&output).unwrap();
        assert!(m.samples().iter().any(|&v| v > 0.0), "{name}: not black");
        if name == "dino" {
            // What an eye at the middle of the viewer line sees on Mark III.
            let eyes = [EyeAt { x_m: 0.0, y_m: 0.0, distance_m: None, pupil_m: 4e-3, coherent: false }];
            let picture = &view_file(&output, Some(&layout), 0, &eyes, &holo::progress::Silent).unwrap()[0];
            let path = artefacts().join("dino-mark3-view-x0mm.png");
            picture.write_png(&path, picture.data.iter().fold(0.0f32, |a, &b| a.max(b)).max(1e-6), true).unwrap();
            println!("  reconstructed view: {}", path.display());
            assert!(
                picture.data.iter().filter(|&&v| v > 0.0).count() > picture.data.len() / 2,
                "the view shows the scene"
            );
        }
    }
}

/// The quilt's 32 cameras put on a display whose emitter plane is the
/// quilt's focal rectangle and whose viewer line is where the cameras are:
/// quilt → `.holo` → quilt gives the views back.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn quilt_round_trip_keeps_the_views() {
    let Some(data) = shared_data() else { return };
    let input = data.join("quilt_lookingglass_4x8/example02_qs4x8a1.6.png");
    let rig = holo::cameras::open_rig(&input).unwrap();
    let (tile_w, tile_h) = (rig.cameras[0].width, rig.cameras[0].height);
    // 512 × 256 emitters × hololines, 102.4 mm × 64 mm; the cameras' 14°
    // vertical field of view frames 64 mm at 260.6 mm.
    let (width_m, height_m) = (0.1024, 0.064);
    let distance_m = 0.5 * height_m / 7f64.to_radians().tan();
    let fan = 31f64.to_radians();
    let mut g = Geometry::centred(
        tile_h,
        tile_w,
        Views::tan_spaced(256, -fan, fan),
        height_m / tile_h as f64,
        width_m / tile_w as f64,
        0.0,
        distance_m,
        rgb_channels(),
    );
    g.viewer_height_m = 0.0;
    let views: Vec<CameraView> = rig.cameras.iter().map(|c| load_view(c, rig.linear, false).unwrap()).collect();
    let options = CameraOptions {
        placement: PlacementRequest {
            scale: Some(distance_m),
            centre: Some([0.0; 3]),
            parallax: Parallax::True,
            ..PlacementRequest::default()
        },
        use_depth: false,
        ..CameraOptions::default()
    };
    let (m, report) = resample_rig(&rig, &views, &g, &options, &holo::progress::Silent).unwrap();
    // The display's rays beyond the outer cameras are unseen; the quilt's own rays are all held.
    println!("{:.1}% of the display's rays unseen", 100.0 * report.unseen as f64 / report.rays as f64);
    let spec = QuiltSpec {
        columns: 4,
        rows: 8,
        tile_width: tile_w,
        tile_height: tile_h,
        aspect: 1.6,
        view_cone_deg: 35.0,
        vertical_fov_deg: 14.0,
    };
    let quilt = quilt_from_modulation(&m, &spec).unwrap();
    // The original quilt, linear, tile by tile in the rig's order.
    let original = holo::cameras::image::load_picture(
        &holo::cameras::Camera {
            image: holo::cameras::ImageSource::File(input.clone()),
            width: quilt.width,
            height: quilt.height,
            ..rig.cameras[0].clone()
        },
        false,
    )
    .unwrap();
    let (mut err, mut sum) = (0.0f64, 0.0f64);
    for (a, b) in quilt.rgb.iter().zip(&original.rgb) {
        for c in 0..3 {
            err += (a[c] - b[c]).abs() as f64;
            sum += b[c] as f64;
        }
    }
    let rel = err / sum;
    println!(
        "quilt → .holo ({} × {} × {} views) → quilt: mean abs error / mean {rel:.4}",
        g.hololines, g.emitters, g.views.count
    );
    let round = artefacts().join("example02_roundtrip_qs4x8a1.6.png");
    quilt.write_png(&round, quilt.white_level(holo::picture::White::Auto), true).unwrap();
    assert!(rel < 0.05, "round trip error {rel}");
}
