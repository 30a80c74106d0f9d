//! What streams holds a band, not the frame, by peak heap measured with a
//! counting allocator: far below one frame, and not growing with the frame.
//!
//! - `convert cameras` holds the pictures and a band of hololines, while
//!   resampling a whole frame in memory needs at least the frame; the banded
//!   conversion writes exactly the frame the whole-frame resampler makes.
//!   Full parallax too: a band of emitter rows with all their views; and
//!   `convert mesh`, whose full-parallax frames are rendered band by band.
//! - A full-parallax file (spec §8) is written, validated and read by the
//!   view band by band of emitter rows.
//!
//! One test in this binary, each part in turn: the allocator counts every
//! thread, so nothing else may run beside it.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use holo::cameras::convert::{convert_cameras, CameraConvertOptions};
use holo::cameras::image::Picture;
use holo::cameras::resample::{resample_rig, Blend, CameraOptions, CameraView};
use holo::cameras::{look_rotation, Camera, ImageSource, Intrinsics, Pose, Rig};
use holo::format::{Compression, HoloFile, Region, SampleType, WriteOptions};
use holo::geometry::{mono_channel, rgb_channels, Geometry, ViewSpacing, Views};

struct Counting;

static NOW: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            let now = NOW.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        NOW.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Peak heap above what was live when `f` started.
fn peak_during<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let base = NOW.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let out = f();
    (out, PEAK.load(Ordering::Relaxed) - base)
}

/// A display 192 mm tall of `hololines`, 96 emitters of 1 mm, 48 views.
fn display(hololines: usize) -> Geometry {
    Geometry::centred(
        hololines,
        96,
        Views::tan_spaced(48, -15f64.to_radians(), 15f64.to_radians()),
        0.192 / hololines as f64,
        1e-3,
        0.0,
        0.5,
        rgb_channels(),
    )
}

/// A 3×3 grid (0.3 m apart) of 64×64 cameras 1 m from a patterned focus plane.
fn rig_and_views() -> (Rig, Vec<CameraView>) {
    let (w, h) = (64usize, 64usize);
    let mut cameras = Vec::new();
    let mut views = Vec::new();
    for (k, (x, y)) in (0..9).map(|k| (k, (0.3 * (k % 3) as f64 - 0.3, 0.3 * (k / 3) as f64 - 0.3))) {
        cameras.push(Camera {
            name: format!("cam{k}"),
            image: ImageSource::File(format!("cam{k}.png").into()),
            width: w,
            height: h,
            intrinsics: Intrinsics { fx: 60.0, fy: 60.0, cx: 31.5, cy: 31.5 },
            pose: Pose { rotation: look_rotation([0.0, 0.0, -1.0], [0.0, -1.0, 0.0]), centre: [x, y, 1.0] },
            depth: None,
        });
        let rgb = (0..w * h)
            .map(|i| {
                let (u, v) = ((i % w) as f32, (i / w) as f32);
                [0.5 + 0.4 * (u * 0.3 + k as f32).sin(), 0.5 + 0.4 * (v * 0.2).cos(), 0.3 + 0.002 * (u + v)]
            })
            .collect();
        views.push(CameraView { picture: Picture { width: w, height: h, rgb }, depth_z: None });
    }
    let rig = Rig {
        source: "memory test grid".into(),
        cameras,
        metres_per_unit: 1.0,
        focus_distance: Some(1.0),
        linear: true,
    };
    (rig, views)
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn streamed_work_holds_a_band_not_the_frame() {
    converting_cameras_holds_a_band(display);
    converting_cameras_holds_a_band(full_parallax_display);
    converting_a_mesh_to_full_parallax_holds_a_band();
    full_parallax_files_stream_by_bands();
}

/// `convert mesh` to full parallax renders and writes a band of emitter
/// rows at a time: its peak heap is the scene (Spot and its texture) and a
/// band, not the frame, and the file is the whole-frame render.
fn converting_a_mesh_to_full_parallax_holds_a_band() {
    use holo::mesh::convert::{convert_mesh, ConvertOptions};
    use holo::mesh::load::SceneSource;
    use holo::mesh::place::apply;
    use holo::mesh::render::{render, RenderOptions, Supersample};
    use holo::mesh::shade::Lighting;
    let scene_path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/mesh/spot/spot.obj");
    let dir = tempfile::tempdir().unwrap();
    let mut options = ConvertOptions::default();
    options.render.supersample = Supersample::new(1, 1);
    options.write.sample_type = SampleType::F32;
    let geometry = |rows| {
        let mut g = full_parallax_display(rows);
        g.emitters = 96;
        g
    };
    // What the scene itself holds (Spot's texture): the fixed part.
    let (_, scene_peak) = peak_during(|| SceneSource::open(&scene_path).unwrap().scene_at(0.0).unwrap());
    println!("spot: the scene read and posed, peak heap {:.1} MB", scene_peak as f64 / 1e6);
    let mut peaks = Vec::new();
    for rows in [384, 768] {
        let g = geometry(rows);
        let frame_bytes = g.samples_per_frame() as usize * 4;
        let out = dir.path().join(format!("spot-{rows}.holo"));
        let (report, peak) =
            peak_during(|| convert_mesh(&scene_path, &g, &out, &options, &holo::progress::Silent).unwrap());
        println!(
            "spot, {rows} rows × 96 × 12 × 6 views: frame {:.1} MB, banded conversion peak heap {:.1} MB",
            frame_bytes as f64 / 1e6,
            peak as f64 / 1e6
        );
        peaks.push(peak);
        // The whole frame rendered at once, placed and lit as the conversion was.
        let mut scene = SceneSource::open(&scene_path).unwrap().scene_at(0.0).unwrap();
        apply(&mut scene, &report.placed.matrix);
        let lighting = Lighting { lights: report.lights.clone(), model: options.render.lighting.model };
        let whole_options =
            RenderOptions { supersample: options.render.supersample, ..RenderOptions::lit_exactly(lighting) };
        let (whole, _) = render(&scene, &g, &whole_options, &holo::progress::Silent).unwrap();
        let lit = whole.samples().iter().filter(|&&x| x > 0.0).count() as f64 / whole.samples().len() as f64;
        println!("  {:.1} % of the samples lit", 100.0 * lit);
        assert!(lit > 0.01, "Spot is seen");
        assert!(holo::format::read(&out).unwrap() == whole, "banded conversion differs from the whole frame");
    }
    let frame_growth = (geometry(768).samples_per_frame() - geometry(384).samples_per_frame()) as f64 * 4.0;
    let growth = peaks[1] as f64 - peaks[0] as f64;
    assert!(growth < 0.05 * frame_growth, "peak grew by {growth} bytes for {frame_growth} more bytes of frame");
    let frame_bytes = geometry(768).samples_per_frame() as usize * 4;
    let above_scene = peaks[1].saturating_sub(scene_peak);
    assert!(above_scene < frame_bytes / 4, "peak {above_scene} bytes beside the scene for a frame of {frame_bytes}");
}

/// [`display`]'s rows, 64 emitters, 12 views across and 6 up and down:
/// a full-parallax display whose frames (21 and 42 MB in f32) dwarf a band.
fn full_parallax_display(hololines: usize) -> Geometry {
    let mut g = display(hololines);
    g.emitters = 64;
    g.views = Views::tan_spaced(12, -15f64.to_radians(), 15f64.to_radians());
    g.with_vertical_views(Views::tan_spaced(6, -10f64.to_radians(), 10f64.to_radians()))
}

fn converting_cameras_holds_a_band(display: fn(usize) -> Geometry) {
    let (rig, views) = rig_and_views();
    let dir = tempfile::tempdir().unwrap();
    let resample = CameraOptions { blend: Blend::Nearest, emitter_taps: Some(1), ..CameraOptions::default() };
    let options = CameraConvertOptions {
        resample: resample.clone(),
        write: WriteOptions { sample_type: SampleType::F32, ..WriteOptions::default() },
        ..CameraConvertOptions::default()
    };
    let mut peaks = Vec::new();
    for hololines in [384, 768] {
        let g = display(hololines);
        let frame_bytes = g.samples_per_frame() as usize * 4;
        let out = dir.path().join(format!("{hololines}.holo"));
        let (report, peak) = peak_during(|| {
            convert_cameras(
                &rig,
                &|c: &Camera| Ok(views[rig.cameras.iter().position(|k| k.name == c.name).unwrap()].clone()),
                &g,
                &out,
                &options,
                &holo::progress::Silent,
            )
            .unwrap()
        });
        println!(
            "{hololines} hololines, {} × {} views: frame {:.1} MB, banded conversion peak heap {:.1} MB",
            g.views.count,
            g.vertical_view_count(),
            frame_bytes as f64 / 1e6,
            peak as f64 / 1e6
        );
        // Unseen: at most the border the picture's shape leaves on this tall display.
        let r = &report.resample;
        assert!(r.unseen - r.unseen_outside_frame < r.rays / 10, "{} of {} unseen", r.unseen, r.rays);
        assert!(peak < frame_bytes / 2, "peak {peak} bytes for a frame of {frame_bytes}");
        peaks.push(peak);

        // The whole-frame resampler: at least the frame, and the same samples.
        let ((whole, _), whole_peak) =
            peak_during(|| resample_rig(&rig, &views, &g, &resample, &holo::progress::Silent).unwrap());
        println!("{hololines} hololines: whole-frame resampling peak heap {:.1} MB", whole_peak as f64 / 1e6);
        assert!(whole_peak >= frame_bytes);
        assert!(holo::format::read(&out).unwrap() == whole, "banded conversion differs from the whole frame");
    }
    // Twice the hololines (and twice the frame): the peak hardly moves.
    let growth = peaks[1] as f64 - peaks[0] as f64;
    let frame_growth = (display(768).samples_per_frame() - display(384).samples_per_frame()) as f64 * 4.0;
    assert!(growth < 0.05 * frame_growth, "peak grew by {growth} bytes for {frame_growth} more bytes of frame");
}

/// `rows` emitter rows of 128 emitters, 16 × 16 views, one colour.
fn full_parallax(rows: usize) -> Geometry {
    Geometry::centred(rows, 128, Views::tan_spaced(16, -0.2, 0.2), 5e-4, 5e-4, 0.0, 0.5, mono_channel())
        .with_vertical_views(Views { count: 16, first_theta_rad: -0.2, last_theta_rad: 0.2, spacing: ViewSpacing::Tan })
}

/// Smooth content (ZIP compresses it), every sample different from its neighbours.
fn full_parallax_sample(j: usize, e: usize, v: usize) -> f32 {
    0.25 + 0.001 * (j % 97) as f32 + 0.002 * (e % 61) as f32 + 0.0005 * v as f32
}

fn full_parallax_files_stream_by_bands() {
    let dir = tempfile::tempdir().unwrap();
    let options = WriteOptions { compression: Compression::Zip, ..WriteOptions::default() };
    let mut peaks = Vec::new();
    for rows in [256, 512] {
        let g = full_parallax(rows);
        let frame_bytes = g.samples_per_frame() as usize * 4;
        let out = dir.path().join(format!("{rows}.holo"));
        let (_, write_peak) = peak_during(|| {
            holo::format::write_frame_in_bands(&out, &g, 32, &options, |band| {
                let (lines, views) = (band.hololines(), g.views_per_emitter());
                let n = g.emitters * views;
                for (jj, j) in lines.enumerate() {
                    for (i, x) in band.samples_mut()[jj * n..(jj + 1) * n].iter_mut().enumerate() {
                        *x = full_parallax_sample(j, i / views, i % views);
                    }
                }
                Ok(())
            })
            .unwrap()
        });
        let (validation, validate_peak) = peak_during(|| holo::format::validate_format(&out).unwrap());
        assert!(validation.violations.is_empty(), "{:?}", validation.violations);
        let file = HoloFile::open(&out).unwrap();
        let one_view = Region { views: 7..8, vertical_views: 11..12, ..Region::all(&g) };
        let (view, view_peak) = peak_during(|| file.read_region(0, &one_view).unwrap());
        let v = g.view_index(7, 11);
        for (i, x) in view.samples().iter().enumerate() {
            let want = half::f16::from_f32(full_parallax_sample(i / g.emitters, i % g.emitters, v)).to_f32();
            assert_eq!(*x, want, "sample {i} of view (7 11)");
        }
        println!(
            "{rows} rows × 128 × 16 × 16 views: frame {:.1} MB; peak heap: write {:.1} MB, validate {:.1} MB, one view {:.1} MB",
            frame_bytes as f64 / 1e6,
            write_peak as f64 / 1e6,
            validate_peak as f64 / 1e6,
            view_peak as f64 / 1e6
        );
        // Beside the band: every part's header, offset table and state (256 here).
        for (what, peak) in [("writing", write_peak), ("validating", validate_peak), ("one view", view_peak)] {
            assert!(rows < 512 || peak < frame_bytes / 2, "{what}: peak {peak} bytes for a frame of {frame_bytes}");
        }
        peaks.push((write_peak, validate_peak, view_peak));
    }
    // Twice the rows (and twice the frame): the peaks hardly move (a band,
    // one view's picture, and what does not depend on the frame).
    let frame_growth = (full_parallax(512).samples_per_frame() - full_parallax(256).samples_per_frame()) as f64 * 4.0;
    let [a, b] = [peaks[0], peaks[1]];
    for (what, a, b) in [("writing", a.0, b.0), ("validating", a.1, b.1), ("one view", a.2, b.2)] {
        let growth = b as f64 - a as f64;
        assert!(growth < 0.05 * frame_growth, "{what}: peak grew by {growth} bytes for {frame_growth} more of frame");
    }
}
