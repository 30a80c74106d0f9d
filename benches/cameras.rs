//! Camera arrays to modulation: a 9 × 9 grid of 512 × 512 pictures
//! resampled to Mark III geometry (440 × 336 × 96 views), the fast path
//! against the brute-force reference in the same run (the reference timed on
//! a band of central hololines and scaled up to a frame, labelled so), with
//! true parallax for every blending and with the default parallax, fitted
//! across the eyes, for linear and natural-neighbour blending.
//! `cargo bench --bench cameras` (`-- --test`: one quick pass, as CI runs it).
//!
//! The pictures are photographs, computed exactly, of a textured plane
//! behind the focus, so the frame has a known answer; the table prints its
//! error too.

use std::time::Instant;

mod common;
use common::{band, time};

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use holo::cameras::image::Picture;
use holo::cameras::resample::{resample_rig, Blend, CameraOptions, CameraView, Framing, Parallax, PlacementRequest};
use holo::cameras::{look_rotation, Camera, ImageSource, Intrinsics, Pose, Rig};

const SIZE: usize = 512;
const GRID: usize = 9;
/// Capture metres: cameras 0.5 m from the focus plane, the textured plane 0.05 m behind it.
const FOCUS: f64 = 0.5;
const PLANE_Z: f64 = -0.05;

fn pattern(x: f64, y: f64) -> [f32; 3] {
    let a = (2.0 * std::f64::consts::PI * x / 0.031).sin();
    let b = (2.0 * std::f64::consts::PI * y / 0.023).cos();
    [(0.5 + 0.3 * a * b) as f32, (0.4 + 0.2 * a) as f32, (0.6 - 0.25 * b) as f32]
}

/// The grid: 9 × 9 cameras 35 mm apart (they cover Mark III's view fan), f = 1024 px (a 0.25 m view at the focus).
fn rig() -> (Rig, Vec<CameraView>) {
    let mut cameras = Vec::new();
    for r in 0..GRID {
        for c in 0..GRID {
            let (x, y) = ((c as f64 - 4.0) * 0.035, (4.0 - r as f64) * 0.035);
            cameras.push(Camera {
                name: format!("cam_{r}_{c}"),
                image: ImageSource::File(format!("cam_{r}_{c}.png").into()),
                width: SIZE,
                height: SIZE,
                intrinsics: Intrinsics { fx: 1024.0, fy: 1024.0, cx: 255.5, cy: 255.5 },
                pose: Pose { rotation: look_rotation([0.0, 0.0, -1.0], [0.0, -1.0, 0.0]), centre: [x, y, FOCUS] },
                depth: None,
            });
        }
    }
    let views = cameras
        .iter()
        .map(|cam| {
            let mut rgb = Vec::with_capacity(SIZE * SIZE);
            for v in 0..SIZE {
                for u in 0..SIZE {
                    let d = cam.ray(u as f64, v as f64);
                    let t = (PLANE_Z - cam.pose.centre[2]) / d[2];
                    rgb.push(pattern(cam.pose.centre[0] + t * d[0], cam.pose.centre[1] + t * d[1]));
                }
            }
            CameraView { picture: Picture { width: SIZE, height: SIZE, rgb }, depth_z: None }
        })
        .collect();
    let rig =
        Rig { source: "9 × 9 grid".into(), cameras, metres_per_unit: 1.0, focus_distance: Some(FOCUS), linear: true };
    (rig, views)
}

fn tables(quick: bool, rig: &Rig, views: &[CameraView]) {
    let g = holo::layout::mark3().geometry;
    let runs = if quick { 1 } else { 3 };
    const BAND: usize = 8;
    let scale = g.hololines as f64 / BAND as f64;
    let b = band(&g, BAND);
    println!(
        "\n## 9 × 9 grid of 512 × 512 pictures → Mark III ({} × {} × {} views)",
        g.hololines, g.emitters, g.views.count
    );
    println!("Reference: brute-force location of every ray, on {BAND} central hololines, time × {scale:.0}. Best of {runs}; {} threads.\n", rayon::current_num_threads());
    println!("| blend | parallax | fast s/frame | reference s/frame (band × {scale:.0}) | speed-up | unseen rays | fast = reference on the band (largest difference) |");
    println!("|---|---|---|---|---|---|---|");
    // True parallax (every ray seen), then the default, fitted across the
    // eyes, where a ray's weights are the same on every hololine.
    let runs_of = [
        (Blend::Nearest, covering()),
        (Blend::Linear, covering()),
        (Blend::NaturalNeighbour, covering()),
        (Blend::Linear, eye_mapped()),
        (Blend::NaturalNeighbour, eye_mapped()),
    ];
    for (blend, placement) in runs_of {
        let parallax = placement.parallax.name();
        let fast = CameraOptions { blend, use_depth: false, placement, ..CameraOptions::default() };
        let reference = CameraOptions { reference: true, ..fast.clone() };
        let mut unseen = 0.0;
        let t_fast = time(runs, || {
            let (_, r) = resample_rig(rig, views, &g, &fast, &holo::progress::Silent).expect("resample");
            unseen = r.unseen as f64 / r.rays as f64;
        });
        let mut band_ref = None;
        let t_ref = time(runs, || {
            band_ref = Some(resample_rig(rig, views, &b, &reference, &holo::progress::Silent).expect("resample").0)
        }) * scale;
        let band_fast = resample_rig(rig, views, &b, &fast, &holo::progress::Silent).expect("resample").0;
        let worst = band_fast
            .samples()
            .iter()
            .zip(band_ref.unwrap().samples())
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max);
        println!(
            "| {} | {parallax} | {t_fast:.3} | {t_ref:.2} | {:.1}× | {:.1}% | {worst:.1e} |",
            blend.name(),
            t_ref / t_fast,
            unseen * 100.0
        );
    }
    println!();
}

fn bench(c: &mut Criterion) {
    let quick = std::env::args().any(|a| a == "--test");
    let t = Instant::now();
    let (rig, views) = rig();
    println!("pictures made in {:.2} s", t.elapsed().as_secs_f64());
    tables(quick, &rig, &views);
    let g = holo::layout::mark3().geometry;
    let mut group = c.benchmark_group("mark3_cameras_9x9_512");
    group.sample_size(10).measurement_time(std::time::Duration::from_secs(10));
    group.throughput(Throughput::Elements(1));
    for blend in [Blend::Linear, Blend::NaturalNeighbour] {
        let o = CameraOptions { blend, use_depth: false, placement: covering(), ..CameraOptions::default() };
        group.bench_function(format!("fast_frame_{}", blend.name()), |bch| {
            bch.iter(|| resample_rig(&rig, &views, &g, &o, &holo::progress::Silent).expect("resample"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

/// The cameras at the viewer's distance, ray directions as captured: the
/// display then shows the middle of the pictures and every ray is resampled
/// (the default fit frames the whole picture, whose borders the outer
/// cameras do not see, and those rays cost nothing).
fn covering() -> PlacementRequest {
    PlacementRequest { framing: Framing::CamerasAtViewer, parallax: Parallax::True, ..PlacementRequest::default() }
}

/// The cameras at the viewer's distance, parallax fitted across the eyes
/// (the default): each eye position sees from one place among the cameras.
fn eye_mapped() -> PlacementRequest {
    PlacementRequest { framing: Framing::CamerasAtViewer, ..PlacementRequest::default() }
}
