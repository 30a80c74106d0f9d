//! A full-parallax frame written as an HCI 4D light field benchmark folder
//! (`holo::cameras::hci`), read back as the benchmark's tools read one: its
//! python-tools `file_io.read_lightfield` lists the `input_*.png` files in
//! sorted order and puts picture `idx` at camera row `idx / num_cams_x`,
//! column `idx % num_cams_y`; `read_parameters` reads `parameters.cfg` with
//! an INI parser, section by section. And read as holo reads the
//! benchmark's folders (`read_hci`, the Blender add-on's cameras), whose
//! pinholes must see what the views show.

use std::collections::HashMap;
use std::path::Path;

use holo::cameras::hci::{camera_of_view, export_hci_file, view_of_camera, HciManifest, MANIFEST, PARAMETERS};
use holo::cameras::read::read_hci;
use holo::format::{write, WriteOptions};
use holo::geometry::{mono_channel, rgb_channels, Geometry, Views};
use holo::picture::{decode, Bits, Tone, White};
use holo::Modulation;

/// `rows × columns` emitters 0.5 mm apart, `v × w` views tan-spaced over
/// ±0.1 rad (both axes alike, as the benchmark's one baseline needs).
fn geometry(rows: usize, columns: usize, v: usize, w: usize, rgb: bool) -> Geometry {
    Geometry::centred(
        rows,
        columns,
        Views::tan_spaced(v, -0.1, 0.1),
        5e-4,
        5e-4,
        0.002,
        0.4,
        if rgb { rgb_channels() } else { mono_channel() },
    )
    .with_vertical_views(Views::tan_spaced(w, -0.1, 0.1))
}

/// A sample that names its channel, emitter and view, up to 0.9.
fn content(c: usize, j: usize, e: usize, h: usize, k: usize) -> f32 {
    0.9 * ((c * 5 + j * 7 + e * 3 + h * 11 + k * 17) % 29) as f32 / 28.0
}

/// `parameters.cfg` as an INI parser reads it: (section, key) → value.
fn read_parameters(path: &Path) -> HashMap<(String, String), String> {
    let mut section = String::new();
    let mut out = HashMap::new();
    for line in std::fs::read_to_string(path).unwrap().lines() {
        if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            section = name.to_string();
        } else if let Some((key, value)) = line.split_once('=') {
            out.insert((section.clone(), key.trim().to_string()), value.trim().to_string());
        }
    }
    out
}

/// The light field as `read_lightfield` builds it: `[row][column]` of
/// 8-bit RGB pictures, `height × width × 3`.
fn read_lightfield(dir: &Path) -> Vec<Vec<Vec<u8>>> {
    let p = read_parameters(&dir.join(PARAMETERS));
    let number = |section: &str, key: &str| -> usize { p[&(section.to_string(), key.to_string())].parse().unwrap() };
    let (nx, ny) = (number("extrinsics", "num_cams_x"), number("extrinsics", "num_cams_y"));
    let (width, height) =
        (number("intrinsics", "image_resolution_x_px"), number("intrinsics", "image_resolution_y_px"));
    // Every key read_parameters asks for is there, as a number where it takes one.
    for key in ["focal_length_mm", "sensor_size_mm", "fstop"] {
        p[&("intrinsics".to_string(), key.to_string())].parse::<f64>().unwrap();
    }
    for key in ["baseline_mm", "focus_distance_m", "center_cam_x_m", "center_cam_y_m", "center_cam_z_m"]
        .into_iter()
        .chain(["center_cam_rx_rad", "center_cam_ry_rad", "center_cam_rz_rad"])
    {
        p[&("extrinsics".to_string(), key.to_string())].parse::<f64>().unwrap();
    }
    for key in ["disp_min", "disp_max", "frustum_disp_min", "frustum_disp_max", "depth_map_scale"] {
        p[&("meta".to_string(), key.to_string())].parse::<f64>().unwrap();
    }
    for key in ["scene", "category", "date", "version", "authors", "contact"] {
        assert!(p.contains_key(&("meta".to_string(), key.to_string())), "[meta] {key}");
    }
    let mut views: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("input_") && n.ends_with(".png"))
        .collect();
    views.sort();
    assert_eq!(views.len(), nx * ny);
    let mut field = vec![vec![Vec::new(); ny]; nx];
    for (idx, name) in views.iter().enumerate() {
        let picture = decode::decode(std::io::Cursor::new(std::fs::read(dir.join(name)).unwrap())).unwrap();
        assert_eq!((picture.width, picture.height, picture.channels, picture.bits()), (width, height, 3, Bits::Eight));
        field[idx / nx][idx % ny] = picture.rgb8();
    }
    field
}

#[test]
fn an_hci_export_reads_back_by_the_benchmark_s_conventions_camera_row_0_the_highest_view() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(6, 8, 3, 3, true);
    let m = Modulation::from_fn(g.clone(), |c, j, e, view| {
        let (h, k) = g.view_of_index(view);
        content(c, j, e, h, k)
    })
    .unwrap();
    let file = dir.path().join("scene.holo");
    write(&file, &m, &WriteOptions::default()).unwrap();
    let out = dir.path().join("hci");
    let export = export_hci_file(&file, 0, &out, White::Value(1.0), false).unwrap();
    assert!(export.warnings.is_empty(), "{:?}", export.warnings);
    // Centre camera of 3 × 3: 4; row 0 holds the highest vertical views.
    assert_eq!(camera_of_view(&g, 1, 1), 4);
    assert_eq!((camera_of_view(&g, 0, 2), camera_of_view(&g, 2, 0)), (0, 8));
    let stored = holo::read(&file).unwrap();
    let tone = Tone::new(1.0, Bits::Eight).unwrap();
    let field = read_lightfield(&out);
    for (row, cameras) in field.iter().enumerate() {
        for (column, picture) in cameras.iter().enumerate() {
            let (h, k) = (column, 2 - row);
            assert_eq!(view_of_camera(&g, row * 3 + column), (h, k));
            for j in 0..g.hololines {
                for e in 0..g.emitters {
                    for c in 0..3 {
                        let want = tone.code(stored.get(c, j, e, g.view_index(h, k)));
                        assert_eq!(u16::from(picture[(j * g.emitters + e) * 3 + c]), want, "camera ({row}, {column})");
                    }
                }
            }
        }
    }
    let manifest: HciManifest = serde_json::from_slice(&std::fs::read(out.join(MANIFEST)).unwrap()).unwrap();
    assert_eq!(manifest.cameras[0].view, [0, 2]);
    assert_eq!(manifest.files.len(), 10);
    holo::output::verify_set(&out, MANIFEST, &manifest.files, "again").unwrap();

    // The add-on's cameras, as holo reads the benchmark: each where its view
    // points from the emitters' centre at the viewer's distance (row 0 above,
    // rows stepping down), all focused on the emitter plane, where every
    // emitter is at its own pixel in every picture.
    let rig = read_hci(&out).unwrap();
    assert_eq!(rig.cameras.len(), 9);
    let s = g.viewer_distance_m - g.emitter_z_m;
    let emitter = |j: usize, e: usize, dz: f64| [g.emitter_x_m(e), g.hololine_y_m(j), g.emitter_z_m + dz];
    for (index, camera) in rig.cameras.iter().enumerate() {
        let (h, k) = view_of_camera(&g, index);
        let want = [s * g.views.theta_rad(h).tan(), s * g.vertical_views.as_ref().unwrap().theta_rad(k).tan(), 0.4];
        for (got, want) in camera.pose.centre.iter().zip(want) {
            assert!((got - want).abs() < 1e-12, "camera {index}: {:?} vs {want:?}", camera.pose.centre);
        }
        for (j, e) in [(0, 0), (5, 7), (2, 3)] {
            let (pixel, _) = camera.project(emitter(j, e, 0.0)).unwrap();
            assert!((pixel[0] - e as f64).abs() < 1e-9 && (pixel[1] - j as f64).abs() < 1e-9, "{index}: {pixel:?}");
        }
        // A point 2 mm in front of emitter (2, 3): the view along (tan θ_h,
        // tan φ_k) shows it moved by that slope times its depth, against
        // x and with y (rows count down). The camera's rays fan out where the
        // view's are parallel: it agrees but for the point's offset from the
        // picture's centre (a) times depth over distance, and the camera's own
        // offset (t) times its square.
        let dz = 0.002;
        let slopes = [g.views.theta_rad(h).tan(), -g.vertical_views.as_ref().unwrap().theta_rad(k).tan()];
        let (at, centre) = ([3.0, 2.0], [3.5, 2.5]);
        let (pixel, _) = camera.project(emitter(2, 3, dz)).unwrap();
        for i in 0..2 {
            let shown = at[i] - dz * slopes[i] / 5e-4;
            let (a, t) = ((at[i] - centre[i]).abs(), (s * slopes[i] / 5e-4).abs());
            let bound = a * dz / (s - dz) + t * dz * dz / (s * (s - dz));
            assert!((pixel[i] - shown).abs() <= 1.01 * bound + 1e-9, "camera {index}: {pixel:?}, the view {shown}");
        }
    }
}

#[test]
fn what_the_benchmark_cannot_hold_is_said_and_horizontal_parallax_refused() {
    let dir = tempfile::tempdir().unwrap();
    // 4 × 2 views over ±0.1 and ±0.05 rad, pixels twice as tall as wide, one wavelength.
    let mut g = geometry(3, 5, 4, 2, false).with_vertical_views(Views::tan_spaced(2, -0.05, 0.05));
    g.hololine_pitch_m = 1e-3;
    let m = Modulation::from_fn(g.clone(), |_, j, e, view| {
        let (h, k) = g.view_of_index(view);
        content(0, j, e, h, k)
    })
    .unwrap();
    let file = dir.path().join("odd.holo");
    write(&file, &m, &WriteOptions::default()).unwrap();
    let export = export_hci_file(&file, 0, &dir.path().join("hci"), White::Max, false).unwrap();
    let said = export.warnings.join("\n");
    for needle in ["one baseline", "square", "4 × 2 cameras"] {
        assert!(said.contains(needle), "{needle}: {said}");
    }
    // Grey in all three components; camera 0 the leftmost of the upper row.
    let png = std::fs::read(dir.path().join("hci/input_Cam000.png")).unwrap();
    let picture = decode::decode(std::io::Cursor::new(png)).unwrap();
    assert_eq!(picture.channels, 3);
    let rgb = picture.rgb8();
    let tone = Tone::new(export.tone.white, Bits::Eight).unwrap();
    let stored = holo::read(&file).unwrap();
    assert_eq!(u16::from(rgb[3 * 6 + 1]), tone.code(stored.get(0, 1, 1, g.view_index(0, 1))));
    assert_eq!((rgb[3 * 6], rgb[3 * 6 + 1]), (rgb[3 * 6 + 2], rgb[3 * 6 + 1]));
    let flat = Geometry { vertical_views: None, parallax: holo::geometry::Parallax::Horizontal, ..g.clone() };
    let flat_file = dir.path().join("flat.holo");
    write(&flat_file, &Modulation::zeros(flat).unwrap(), &WriteOptions::default()).unwrap();
    let err = export_hci_file(&flat_file, 0, &dir.path().join("no"), White::Max, false).unwrap_err().to_string();
    assert!(err.contains("flat.holo") && err.contains("horizontal parallax"), "{err}");
    assert!(!dir.path().join("no").exists());
}
