//! Camera rigs read from the conventions captures come in: the
//! geometry each reader builds is checked against what the capture's own
//! documentation says (HCI: zero disparity at the focus distance, 60 mm
//! steps; Middlebury: a ring of cameras aimed at the temple; quilts: view 0
//! bottom left and leftmost), rig files in both syntaxes, picture decoding,
//! and bad input, each refused with an error naming the file and camera.

use crate::common;

use std::path::{Path, PathBuf};

use common::shared_data;
use holo::cameras::image::{image_size, load_picture};
use holo::cameras::pfm::{load_depth, write_pfm};
use holo::cameras::read::{open_rig_with, CameraHints, FolderOptions, OpenOptions, StanfordOptions};
use holo::cameras::rig_file::read_rig_file;
use holo::cameras::{open_rig, Camera, DepthKind, ImageSource, Intrinsics, Pose, Rig};

fn data() -> Option<PathBuf> {
    let d = shared_data();
    if d.is_none() {
        println!("SKIPPED: ../shared/data not present");
    }
    d
}

fn near3(a: [f64; 3], b: [f64; 3], tolerance: f64) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() <= tolerance)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add_scaled(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn camera<'a>(rig: &'a Rig, name: &str) -> &'a Camera {
    rig.cameras.iter().find(|c| c.name == name).unwrap_or_else(|| panic!("no camera {name}"))
}

/// An 8-bit RGB PNG of `w`×`h` with a gradient.
fn png(path: &Path, w: u32, h: u32) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let samples = common::pixels(w, h, |x, y| [(x * 20) as u8, (y * 30) as u8, 7]);
    std::fs::write(path, common::png8(w, h, 3, &samples)).unwrap();
}

fn error_of(r: holo::Result<Rig>) -> String {
    match r {
        Ok(rig) => panic!("expected an error, got a rig of {} cameras", rig.cameras.len()),
        Err(e) => e.to_string(),
    }
}

/// The exact sRGB EOTF (IEC 61966-2-1), written out again here.
fn eotf(v: f64) -> f64 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

// ---------------------------------------------------------------- HCI

/// parameters.cfg's Blender Euler XYZ (X applied first, then Y, then Z),
/// applied to a vector: independent of the reader's matrix code.
fn blender_rotate(v: [f64; 3], [rx, ry, rz]: [f64; 3]) -> [f64; 3] {
    let (s, c) = rx.sin_cos();
    let v = [v[0], c * v[1] - s * v[2], s * v[1] + c * v[2]];
    let (s, c) = ry.sin_cos();
    let v = [c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]];
    let (s, c) = rz.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
}

#[test]
fn hci_dino_geometry() {
    let Some(d) = data() else { return };
    let rig = open_rig(&d.join("lightfield_hci_dino")).unwrap();
    assert_eq!(rig.cameras.len(), 33, "the copy holds 33 of the 81 views");
    assert_eq!(rig.metres_per_unit, 1.0);
    let focus = 6.900000095367432;
    assert_eq!(rig.focus_distance, Some(focus));
    let name = |n: usize| format!("input_Cam{n:03}.png");

    // The centre camera is parameters.cfg's.
    let euler = [1.3526215553283691, 0.016077132895588875, -0.22883984446525574];
    let centre = camera(&rig, &name(40));
    assert_eq!(centre.pose.centre, [-1.4951000213623047, -6.506796836853027, 2.3541150093078613]);
    let view = blender_rotate([0.0, 0.0, -1.0], euler);
    let up = blender_rotate([0.0, 1.0, 0.0], euler);
    let right = blender_rotate([1.0, 0.0, 0.0], euler);
    assert!(near3(centre.axis(), view, 1e-12), "{:?} vs {view:?}", centre.axis());
    assert!(near3(centre.pose.rotation[0], right, 1e-12));
    assert!(near3(centre.pose.rotation[1], up.map(|x| -x), 1e-12), "picture down is Blender's −Y");
    let f = 100.0 / 35.0 * 512.0;
    assert!((centre.intrinsics.fx - f).abs() < 1e-9 && centre.intrinsics.fy == centre.intrinsics.fx);
    assert_eq!((centre.width, centre.height), (512, 512));
    assert!((centre.intrinsics.cx - 255.5).abs() < 1e-9 && (centre.intrinsics.cy - 255.5).abs() < 1e-9);

    // Centre row: columns step 60 mm along the camera's x; centre column:
    // rows step 60 mm down the picture; all cameras parallel.
    for j in 36..44 {
        let step = sub(camera(&rig, &name(j + 1)).pose.centre, camera(&rig, &name(j)).pose.centre);
        assert!(near3(step, right.map(|x| 0.06 * x), 1e-9), "Cam{j:03}→{}: {step:?}", j + 1);
    }
    for i in 0..8 {
        let step = sub(camera(&rig, &name(9 * i + 13)).pose.centre, camera(&rig, &name(9 * i + 4)).pose.centre);
        assert!(near3(step, up.map(|x| -0.06 * x), 1e-9), "row {i}→{}: {step:?}", i + 1);
    }
    let top_left = add_scaled(add_scaled(centre.pose.centre, right, -0.24), up, 0.24);
    assert!(near3(camera(&rig, &name(0)).pose.centre, top_left, 1e-9), "Cam000 is 4 columns left, 4 rows up");
    assert!(rig.cameras.iter().all(|c| c.pose.rotation == centre.pose.rotation));

    // Zero disparity at the focus distance: the point F in front of the
    // centre camera is at the picture's centre in every view.
    let focus_point = add_scaled(centre.pose.centre, view, focus);
    for c in &rig.cameras {
        let (px, z) = c.project(focus_point).unwrap();
        assert!((px[0] - 255.5).abs() < 1e-6 && (px[1] - 255.5).abs() < 1e-6, "{}: {px:?}", c.name);
        assert!((z - focus).abs() < 1e-9);
    }
    // Nearer points shift left as the camera steps right, by the
    // benchmark's disparity d = b·f·(1/z − 1/F) per step (toolkit disp2depth).
    let near_point = add_scaled(centre.pose.centre, view, 5.0);
    let d = 0.06 * f * (1.0 / 5.0 - 1.0 / focus);
    let u40 = centre.project(near_point).unwrap().0[0];
    for j in 36..=44 {
        let u = camera(&rig, &name(j)).project(near_point).unwrap().0[0];
        assert!((u - u40 + (j as f64 - 40.0) * d).abs() < 1e-6, "Cam{j:03}: {u} vs {u40} − {}·{d}", j - 40);
    }

    let picture = load_picture(centre, rig.linear).unwrap();
    assert_eq!((picture.width, picture.height, picture.rgb.len()), (512, 512, 512 * 512));
    assert!(picture.rgb.iter().flatten().all(|&v| (0.0..=1.0).contains(&v)));
}

/// A parameters.cfg of a 3 × 3 grid of 8 × 6 pictures: 100 mm apart,
/// converging 2 m away, f = 50/36 · 8 px, its centre camera unrotated at
/// height `z` metres.
fn hci_parameters(z: f64) -> String {
    format!(
        "[intrinsics]\nfocal_length_mm = 50\nimage_resolution_x_px = 8\nimage_resolution_y_px = 6\n\
         sensor_size_mm = 36\n[extrinsics]\nnum_cams_x = 3\nnum_cams_y = 3\nbaseline_mm = 100\n\
         focus_distance_m = 2\ncenter_cam_x_m = 0\ncenter_cam_y_m = 0\ncenter_cam_z_m = {z}\n\
         center_cam_rx_rad = 0\ncenter_cam_ry_rad = 0\ncenter_cam_rz_rad = 0\n"
    )
}

#[test]
fn hci_ground_truth_becomes_depth() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("parameters.cfg"), hci_parameters(1.0)).unwrap();
    for n in [3, 4, 5] {
        png(&d.join(format!("input_Cam{n:03}.png")), 8, 6);
    }
    let mut disparity = vec![0.0f32; 48];
    disparity[47] = 1.0;
    write_pfm(&d.join("gt_disp_lowres.pfm"), 8, 6, &disparity).unwrap();
    write_pfm(&d.join("gt_depth_lowres_Cam003.pfm"), 8, 6, &[1.5; 48]).unwrap();
    let rig = open_rig(d).unwrap();
    assert_eq!(rig.cameras.len(), 3);
    let f = 50.0 / 36.0 * 8.0;
    let centre = camera(&rig, "input_Cam004.png");
    let bf = 0.1 * f;
    let depth = centre.depth.as_ref().unwrap();
    assert_eq!(depth.kind, DepthKind::Disparity { numerator: bf, offset: bf / 2.0 });
    let z = load_depth(centre).unwrap().unwrap();
    assert!((z[0] - 2.0).abs() < 1e-6, "disparity 0 is the focus distance");
    assert!((f64::from(z[47]) - bf / (1.0 + bf / 2.0)).abs() < 1e-6);
    let left = camera(&rig, "input_Cam003.png");
    assert_eq!(left.depth.as_ref().unwrap().kind, DepthKind::Z { scale: 1.0 });
    assert_eq!(load_depth(left).unwrap().unwrap()[5], 1.5);
    assert!(camera(&rig, "input_Cam005.png").depth.is_none());
    // Unrotated Blender cameras look down world −Z; Cam003 is 0.1 m left.
    assert!(near3(left.pose.centre, [-0.1, 0.0, 1.0], 1e-12) && near3(left.axis(), [0.0, 0.0, -1.0], 1e-12));

    png(&d.join("input_Cam009.png"), 8, 6);
    let e = error_of(open_rig(d));
    assert!(e.contains("input_Cam009.png") && e.contains("outside the 3×3 grid"), "{e}");
    std::fs::remove_file(d.join("input_Cam009.png")).unwrap();
    png(&d.join("input_Cam005.png"), 8, 7);
    let e = error_of(open_rig(d));
    assert!(e.contains("camera input_Cam005.png") && e.contains("8×7, parameters.cfg says 8×6"), "{e}");
}

/// An HCI folder without its parameters.cfg (as copies of the benchmark's
/// scenes often come) is the same grid when the user gives what the file
/// would have said; without those numbers it is refused, naming the flag.
#[test]
fn an_hci_grid_without_parameters_takes_them_from_the_user() {
    let dir = tempfile::tempdir().unwrap();
    let (with, without) = (dir.path().join("with"), dir.path().join("without"));
    std::fs::create_dir_all(&with).unwrap();
    std::fs::write(with.join("parameters.cfg"), hci_parameters(0.0)).unwrap();
    for n in 0..9 {
        png(&with.join(format!("input_Cam{n:03}.png")), 8, 6);
        png(&without.join(format!("input_Cam{n:03}.png")), 8, 6);
    }
    let reference = open_rig(&with).unwrap();
    let mut options = OpenOptions::default();
    let e = error_of(open_rig_with(&without, &options));
    assert!(e.contains("without parameters.cfg") && e.contains("--baseline"), "{e}");
    options.folder.baseline = Some(0.1);
    let e = error_of(open_rig_with(&without, &options));
    assert!(e.contains("--focus"), "{e}");
    options.folder.camera.focus_distance = Some(2.0);
    let e = error_of(open_rig_with(&without, &options));
    assert!(e.contains("focal length"), "{e}");
    options.folder.camera.focal_length_px = Some(50.0 / 36.0 * 8.0);
    let rig = open_rig_with(&without, &options).unwrap();
    assert_eq!(rig.cameras.len(), 9);
    assert_eq!(rig.focus_distance, Some(2.0));
    for (a, b) in rig.cameras.iter().zip(&reference.cameras) {
        assert_eq!(a.name, b.name);
        assert!(near3(a.pose.centre, b.pose.centre, 1e-12), "{}", a.name);
        assert_eq!((a.intrinsics, a.pose.rotation), (b.intrinsics, b.pose.rotation), "{}", a.name);
    }
    // Row 0 is the top: Cam001 is above the centre, Cam003 left of it.
    assert!(near3(camera(&rig, "input_Cam001.png").pose.centre, [0.0, 0.1, 0.0], 1e-12));
    assert!(near3(camera(&rig, "input_Cam003.png").pose.centre, [-0.1, 0.0, 0.0], 1e-12));
}

// ---------------------------------------------------------- Middlebury

/// The point nearest (least squares) to all the cameras' axes.
fn closest_approach(cameras: &[Camera]) -> [f64; 3] {
    let mut a = [[0.0; 3]; 3];
    let mut b = [0.0; 3];
    for c in cameras {
        let d = c.axis();
        for i in 0..3 {
            for j in 0..3 {
                let m = f64::from(u8::from(i == j)) - d[i] * d[j];
                a[i][j] += m;
                b[i] += m * c.pose.centre[j];
            }
        }
    }
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let whole = det(a);
    [0, 1, 2].map(|k| {
        let mut m = a;
        for i in 0..3 {
            m[i][k] = b[i];
        }
        det(m) / whole
    })
}

#[test]
fn middlebury_temple_ring_aims_at_the_temple() {
    let Some(d) = data() else { return };
    let folder = d.join("multiview_middlebury_templeSparseRing/templeSparseRing");
    let rig = open_rig(&folder).unwrap();
    let same = open_rig(&folder.join("templeSR_par.txt")).unwrap();
    assert_eq!(rig.cameras, same.cameras, "the folder and its _par.txt are one capture");
    assert_eq!(rig.cameras.len(), 16);
    assert!(rig.cameras.iter().all(|c| (c.width, c.height) == (640, 480)));
    let first = &rig.cameras[0];
    assert_eq!(first.name, "templeSR0001.png");
    assert_eq!(first.intrinsics, Intrinsics { fx: 1520.4, fy: 1525.9, cx: 302.32, cy: 246.87 });
    // P = K [R | t]: a world point projects as the file's matrices say.
    let (r, t) = (first.pose.rotation, [-0.0726637729648, 0.0223360353405, 0.614604845959]);
    let x = [-0.02, 0.1, 0.02];
    let c = [0, 1, 2].map(|i| dot(r[i], x) + t[i]);
    let (px, _) = first.project(x).unwrap();
    assert!((px[0] - (1520.4 * c[0] / c[2] + 302.32)).abs() < 1e-9);
    assert!((px[1] - (1525.9 * c[1] / c[2] + 246.87)).abs() < 1e-9);

    // The axes meet near the temple's bounding box (README) ...
    let p = closest_approach(&rig.cameras);
    let (lo, hi) = ([-0.073568, 0.021728, -0.012445], [0.028855, 0.181892, 0.062736]);
    assert!((0..3).all(|i| p[i] > lo[i] - 0.01 && p[i] < hi[i] + 0.01), "axes meet at {p:?}");
    // ... every axis passes within 2 cm of that point, which every camera
    // sees inside its picture, from about the same distance (a ring).
    let distances: Vec<f64> =
        rig.cameras.iter().map(|c| dot(sub(p, c.pose.centre), sub(p, c.pose.centre)).sqrt()).collect();
    let mean = distances.iter().sum::<f64>() / 16.0;
    for (c, distance) in rig.cameras.iter().zip(&distances) {
        let along = dot(sub(p, c.pose.centre), c.axis());
        let off_axis = (distance * distance - along * along).max(0.0).sqrt();
        assert!(off_axis < 0.02, "{}: axis passes {off_axis} m from {p:?}", c.name);
        let (px, _) = c.project(p).unwrap();
        assert!(px[0] > 0.0 && px[0] < 640.0 && px[1] > 0.0 && px[1] < 480.0, "{}: {px:?}", c.name);
        assert!((distance / mean - 1.0).abs() < 0.1, "{}: {distance} m vs mean {mean}", c.name);
    }
    // The data photograph one viewpoint twice (longitude −180° and 180°):
    // kept, and findable.
    assert_eq!(rig.coincident_cameras(), Some((0, 10)));
}

// --------------------------------------------------------------- Quilt

#[test]
fn quilt_views_run_from_bottom_left() {
    let Some(d) = data() else { return };
    let path = d.join("quilt_lookingglass_4x8/example02_qs4x8a1.6.png");
    let rig = open_rig(&path).unwrap();
    assert_eq!(rig.cameras.len(), 32);
    assert_eq!(rig.focus_distance, Some(1.0));
    let tile = |c: &Camera| match &c.image {
        ImageSource::Tile { x, y, width, height, .. } => (*x, *y, *width, *height),
        other => panic!("{other:?}"),
    };
    assert_eq!(tile(&rig.cameras[0]), (0, 1792, 512, 256), "view 0 is the bottom-left tile");
    assert_eq!(tile(&rig.cameras[3]), (1536, 1792, 512, 256));
    assert_eq!(tile(&rig.cameras[4]), (0, 1536, 512, 256), "rows run upward");
    assert_eq!(tile(&rig.cameras[31]), (1536, 0, 512, 256), "the last view is the top-right tile");
    let xs: Vec<f64> = rig.cameras.iter().map(|c| c.pose.centre[0]).collect();
    assert!(xs.windows(2).all(|w| w[0] < w[1]), "camera 0 leftmost, then rightward: {xs:?}");
    assert!((xs[0] + 17.5f64.to_radians().tan()).abs() < 1e-12 && (xs[0] + xs[31]).abs() < 1e-12);
    let t = 7f64.to_radians().tan();
    for c in &rig.cameras {
        assert!((c.intrinsics.fy - 128.0 / t).abs() < 1e-9 && (c.intrinsics.fx - 256.0 / (1.6 * t)).abs() < 1e-9);
        let (px, z) = c.project([0.0, 0.0, 0.0]).unwrap();
        assert!((px[0] - 255.5).abs() < 1e-9 && (px[1] - 127.5).abs() < 1e-9 && (z - 1.0).abs() < 1e-12, "{px:?}");
    }
    let picture = load_picture(&rig.cameras[0], true).unwrap();
    let full = holo::picture::decode::open(&path).unwrap();
    let rgb = full.rgb8();
    for (x, y) in [(0, 0), (511, 255), (100, 50)] {
        let at = 3 * ((1792 + y) * full.width + x);
        let want = [rgb[at], rgb[at + 1], rgb[at + 2]].map(|q| f32::from(q) / 255.0);
        assert_eq!(picture.get(x, y), want);
    }
}

// ----------------------------------------------------------- Rig files

const RAIL_TOML: &str = r#"
units = "mm"
focus_distance = 500
horizontal_fov_deg = 40

[rail]
count = 3
baseline = 20
images = "views/view_{i}.png"
depth = { file = "views/depth_{i}.pfm", kind = "disparity" }
"#;

const RAIL_JSON: &str = r#"{
  "units": "mm",
  "focus_distance": 500,
  "horizontal_fov_deg": 40,
  "rail": {
    "count": 3,
    "baseline": 20,
    "images": ["views\\view_0.png", "views/view_1.png", "views/view_2.png"],
    "depth": { "file": "views/depth_{i}.pfm", "kind": "disparity" }
  }
}"#;

#[test]
fn rail_in_toml_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for i in 0..3 {
        png(&d.join(format!("views/view_{i}.png")), 8, 6);
    }
    std::fs::write(d.join("rail.toml"), RAIL_TOML).unwrap();
    std::fs::write(d.join("rail.json"), RAIL_JSON).unwrap();
    let rig = open_rig(&d.join("rail.toml")).unwrap();
    let json = open_rig(&d.join("rail.json")).unwrap();
    assert_eq!(rig.metres_per_unit, 0.001);
    assert_eq!(rig.focus_distance, Some(500.0));
    let fx = 4.0 / 20f64.to_radians().tan();
    for (i, c) in rig.cameras.iter().enumerate() {
        assert_eq!(c.name, format!("views/view_{i}.png"));
        assert_eq!(c.image, ImageSource::File(d.join(format!("views/view_{i}.png"))));
        // Default placement: the plane in focus is the world's z = 0.
        assert!(near3(c.pose.centre, [20.0 * (i as f64 - 1.0), 0.0, 500.0], 1e-12), "{:?}", c.pose.centre);
        assert!(near3(c.axis(), [0.0, 0.0, -1.0], 0.0) && c.pose.rotation[1] == [0.0, -1.0, 0.0]);
        assert!((c.intrinsics.fx - fx).abs() < 1e-12 && c.intrinsics.fy == c.intrinsics.fx);
        let (px, _) = c.project([0.0, 0.0, 0.0]).unwrap();
        assert!((px[0] - 3.5).abs() < 1e-12 && (px[1] - 2.5).abs() < 1e-12, "converges at the focus: {px:?}");
        let depth = c.depth.as_ref().unwrap();
        assert_eq!(depth.file, d.join(format!("views/depth_{i}.pfm")));
        assert_eq!(depth.kind, DepthKind::Disparity { numerator: 20.0 * fx, offset: 20.0 * fx / 500.0 });
    }
    // The same rig in the other syntax, with a Windows separator.
    assert_eq!(json.cameras.len(), 3);
    for (a, b) in rig.cameras.iter().zip(&json.cameras) {
        assert_eq!((a.pose, a.intrinsics, &a.depth), (b.pose, b.intrinsics, &b.depth));
        assert_eq!(
            image_size(match &b.image {
                ImageSource::File(p) => p,
                other => panic!("{other:?}"),
            })
            .unwrap(),
            (8, 6)
        );
    }
}

#[test]
fn grid_rows_step_down() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (r, c) in [(1, 1), (1, 2), (1, 3), (2, 1), (2, 2), (2, 3)] {
        png(&d.join(format!("r{r}_c{c}.png")), 8, 6);
    }
    std::fs::write(
        d.join("grid.toml"),
        "focus_distance = 2.0\nfocal_length_px = 10\nlinear = true\n\n[grid]\ncolumns = 3\nrows = 2\n\
         baseline_x = 0.1\nbaseline_y = 0.2\nimages = \"r{row}_c{col}.png\"\nstart = 1\n",
    )
    .unwrap();
    let rig = read_rig_file(&d.join("grid.toml")).unwrap();
    assert!(rig.linear);
    let names: Vec<&str> = rig.cameras.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["r1_c1.png", "r1_c2.png", "r1_c3.png", "r2_c1.png", "r2_c2.png", "r2_c3.png"]);
    assert!(near3(rig.cameras[0].pose.centre, [-0.1, 0.1, 2.0], 1e-12), "top left is up and left");
    assert!(near3(rig.cameras[5].pose.centre, [0.1, -0.1, 2.0], 1e-12));
    for c in &rig.cameras {
        let (px, _) = c.project([0.0, 0.0, 0.0]).unwrap();
        assert!((px[0] - 3.5).abs() < 1e-12 && (px[1] - 2.5).abs() < 1e-12);
    }
    // Without converging, principal points stay centred.
    let text =
        std::fs::read_to_string(d.join("grid.toml")).unwrap().replace("start = 1", "start = 1\nconverge = false");
    std::fs::write(d.join("flat.toml"), text).unwrap();
    let flat = read_rig_file(&d.join("flat.toml")).unwrap();
    assert!(flat.cameras.iter().all(|c| c.intrinsics == Intrinsics { fx: 10.0, fy: 10.0, cx: 3.5, cy: 2.5 }));
}

#[test]
fn explicit_cameras_look_at_and_k_r_t() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for n in ["a", "b"] {
        png(&d.join(format!("{n}.png")), 8, 6);
    }
    write_pfm(&d.join("b.pfm"), 8, 6, &[3.0; 48]).unwrap();
    std::fs::write(
        d.join("look.json"),
        r#"{ "units": "cm", "focal_length_mm": 35, "sensor_width_mm": 36,
             "cameras": [
               { "image": "a.png", "position": [-10, 0, 100], "look_at": [0, 0, 0] },
               { "image": "b.png", "name": "right", "position": [10, 0, 100], "look_at": [0, 0, 0], "up": [0, 1, 0],
                 "principal_point_px": [3, 2], "depth": { "file": "b.pfm", "kind": "z", "scale": 0.5 } }
             ] }"#,
    )
    .unwrap();
    let rig = open_rig(&d.join("look.json")).unwrap();
    assert_eq!(rig.metres_per_unit, 0.01);
    let (a, b) = (&rig.cameras[0], &rig.cameras[1]);
    assert_eq!((a.name.as_str(), b.name.as_str()), ("a.png", "right"));
    let l = (100.0f64 + 10000.0).sqrt();
    assert!(near3(a.axis(), [10.0 / l, 0.0, -100.0 / l], 1e-12));
    assert!(a.pose.rotation[0][1].abs() < 1e-12 && a.pose.rotation[1][1] < -0.99, "level, picture up = world up");
    assert!((a.intrinsics.fx - 35.0 / 36.0 * 8.0).abs() < 1e-12);
    let (pa, _) = a.project([0.0, 0.0, 0.0]).unwrap();
    let (pb, _) = b.project([0.0, 0.0, 0.0]).unwrap();
    assert!((pa[0] - 3.5).abs() < 1e-9 && (pa[1] - 2.5).abs() < 1e-9);
    assert!((pb[0] - 3.0).abs() < 1e-9 && (pb[1] - 2.0).abs() < 1e-9);
    assert_eq!(load_depth(b).unwrap().unwrap(), vec![1.5; 48]);

    std::fs::write(
        d.join("krt.toml"),
        "[[cameras]]\nimage = \"a.png\"\nk = [[100, 0, 3.5], [0, 90, 2.5], [0, 0, 1]]\n\
         r = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\nt = [0, 0, 1]\n\n\
         [[cameras]]\nimage = \"b.png\"\nk = [[100, 0, 4], [0, 100, 3], [0, 0, 1]]\n\
         r = [[0, 0, -1], [0, 1, 0], [1, 0, 0]]\nt = [0.5, 0, 2]\n",
    )
    .unwrap();
    let rig = open_rig(&d.join("krt.toml")).unwrap();
    assert_eq!(rig.cameras[0].pose.centre, [0.0, 0.0, -1.0]);
    assert_eq!(rig.cameras[1].pose.centre, [-2.0, 0.0, 0.5], "C = −Rᵀ t");
    assert_eq!(rig.cameras[0].intrinsics, Intrinsics { fx: 100.0, fy: 90.0, cx: 3.5, cy: 2.5 });
    let x = [0.3, -0.2, 0.7];
    let c = &rig.cameras[1];
    let xc = [-x[2] + 0.5, x[1], x[0] + 2.0];
    let (px, z) = c.project(x).unwrap();
    assert!(
        (px[0] - (100.0 * xc[0] / xc[2] + 4.0)).abs() < 1e-12 && (px[1] - (100.0 * xc[1] / xc[2] + 3.0)).abs() < 1e-12
    );
    assert!((z - xc[2]).abs() < 1e-12);
}

#[test]
fn spec_examples_read() {
    let spec = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/spec/rig.md")).unwrap();
    let examples = &spec[spec.find("## 4. Examples").unwrap()..spec.find("## 5. ").unwrap()];
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for i in 0..9 {
        png(&d.join(format!("views/view_{i}.png")), 64, 48);
    }
    png(&d.join("left.png"), 64, 48);
    png(&d.join("right.png"), 64, 48);
    let mut read = 0;
    for (fence, extension) in [("```toml\n", "toml"), ("```json\n", "json")] {
        for block in examples.split(fence).skip(1) {
            let path = d.join(format!("example{read}.{extension}"));
            std::fs::write(&path, &block[..block.find("```").unwrap()]).unwrap();
            let rig = read_rig_file(&path).unwrap_or_else(|e| panic!("spec example {read}: {e}"));
            assert!(rig.cameras.len() >= 2);
            read += 1;
        }
    }
    assert_eq!(read, 4, "two examples in each syntax");
}

// -------------------------------------------------- Stanford and folders

#[test]
fn stanford_names_give_positions() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for name in [
        "out_00_00_-10.0_-10.0_.png",
        "out_00_01_-10.0_10.0_.png",
        "out_01_00_10.0_-10.0_.png",
        "out_01_01_10.0_10.0_.png",
    ] {
        png(&d.join(name), 8, 6);
    }
    let e = error_of(open_rig(d));
    assert!(e.contains("focal length") && e.contains("field of view") && !e.contains("focal_length_px"), "{e}");
    let stanford = StanfordOptions {
        camera: CameraHints { focal_length_px: Some(10.0), ..CameraHints::default() },
        ..StanfordOptions::default()
    };
    let options = OpenOptions { stanford: stanford.clone(), ..OpenOptions::default() };
    let e = error_of(open_rig_with(d, &options));
    assert!(e.contains("give the focus distance") && !e.contains("Options"), "{e}");
    let options = OpenOptions {
        stanford: StanfordOptions {
            camera: CameraHints { focus_distance: Some(100.0), ..stanford.camera.clone() },
            ..stanford
        },
        ..options
    };
    let rig = open_rig_with(d, &options).unwrap();
    assert_eq!(rig.metres_per_unit, 0.001);
    // (Y, X) = (−10, −10) is row 0, column 0: top left, world y up.
    assert!(near3(rig.cameras[0].pose.centre, [-10.0, 10.0, 100.0], 1e-12), "{:?}", rig.cameras[0].pose.centre);
    assert!(near3(rig.cameras[3].pose.centre, [10.0, -10.0, 100.0], 1e-12));
    for c in &rig.cameras {
        let (px, _) = c.project([0.0, 0.0, 0.0]).unwrap();
        assert!((px[0] - 3.5).abs() < 1e-12 && (px[1] - 2.5).abs() < 1e-12, "rectified to the reference plane");
    }
}

/// File names exactly as the archive publishes them (the Lego Knights set
/// without a trailing underscore, Amethyst with one, as cited in public code
/// that reads them); the pixels are stand-ins.
#[test]
fn stanford_archive_names_as_published_are_read() {
    for (names, x) in [
        (
            ["out_00_00_-381.909271_1103.376221.png", "out_00_10_-383.248383_1017.387878.png"],
            [1103.376221, 1017.387878],
        ),
        (["out_00_00_-399.772888_671.237122_.png", "out_00_10_-399.770660_770.764648_.png"], [671.237122, 770.764648]),
    ] {
        let dir = tempfile::tempdir().unwrap();
        for name in names {
            png(&dir.path().join(name), 8, 6);
        }
        let stanford = StanfordOptions {
            camera: CameraHints { focal_length_px: Some(10.0), focus_distance: Some(500.0), ..CameraHints::default() },
            ..StanfordOptions::default()
        };
        let rig = open_rig_with(dir.path(), &OpenOptions { stanford, ..OpenOptions::default() }).unwrap();
        assert_eq!(rig.cameras.len(), 2);
        let mean = (x[0] + x[1]) / 2.0;
        for (c, x) in rig.cameras.iter().zip(x) {
            assert!((c.pose.centre[0] - (x - mean)).abs() < 1e-9, "{}: {:?}", c.name, c.pose.centre);
        }
    }
}

#[test]
fn plain_folder_is_a_rail_in_name_order() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for n in [10, 2, 1] {
        png(&d.join(format!("view{n}.png")), 8, 6);
    }
    let e = error_of(open_rig(d));
    assert!(e.contains("give the baseline") && !e.contains("Options"), "{e}");
    let folder = FolderOptions { baseline: Some(0.1), ..FolderOptions::default() };
    let e = error_of(open_rig_with(d, &OpenOptions { folder: folder.clone(), ..OpenOptions::default() }));
    assert!(e.contains("focal length") && e.contains("field of view") && !e.contains("focal_length_px"), "{e}");
    let folder =
        FolderOptions { camera: CameraHints { horizontal_fov_deg: Some(90.0), ..CameraHints::default() }, ..folder };
    let rig = open_rig_with(d, &OpenOptions { folder, ..OpenOptions::default() }).unwrap();
    let names: Vec<&str> = rig.cameras.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["view1.png", "view2.png", "view10.png"]);
    let xs: Vec<f64> = rig.cameras.iter().map(|c| c.pose.centre[0]).collect();
    assert!((xs[0] + 0.1).abs() < 1e-12 && xs[1].abs() < 1e-12 && (xs[2] - 0.1).abs() < 1e-12);
    assert!(rig.cameras.iter().all(|c| (c.intrinsics.fx - 4.0).abs() < 1e-12 && c.intrinsics.cx == 3.5));
    assert!(rig.focus_distance.is_none());
}

// ------------------------------------------------------------ Pictures

fn picture_camera(path: &Path, width: usize, height: usize) -> Camera {
    Camera {
        name: "probe".into(),
        image: ImageSource::File(path.to_path_buf()),
        width,
        height,
        intrinsics: Intrinsics::centred(width, height, 10.0, 10.0),
        pose: Pose { rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], centre: [0.0; 3] },
        depth: None,
    }
}

#[test]
fn pictures_decode_srgb_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let p8 = d.join("eight.png");
    let values8 = [[0u8, 10, 128], [200, 255, 1]];
    std::fs::write(&p8, common::png8(2, 1, 3, values8.as_flattened())).unwrap();
    let picture = load_picture(&picture_camera(&p8, 2, 1), false).unwrap();
    for (got, want) in picture.rgb.iter().zip(values8) {
        for c in 0..3 {
            assert!((f64::from(got[c]) - eotf(f64::from(want[c]) / 255.0)).abs() < 1e-7, "{got:?} vs {want:?}");
        }
    }
    let raw = load_picture(&picture_camera(&p8, 2, 1), true).unwrap();
    assert_eq!(raw.rgb[0], [0.0, 10.0 / 255.0, 128.0 / 255.0]);

    let p16 = d.join("sixteen.png");
    let values16 = [[0u16, 1000, 32768], [50000, 65535, 1]];
    std::fs::write(&p16, common::png16(2, 1, 3, values16.as_flattened())).unwrap();
    let picture = load_picture(&picture_camera(&p16, 2, 1), false).unwrap();
    for (got, want) in picture.rgb.iter().zip(values16) {
        for c in 0..3 {
            assert!((f64::from(got[c]) - eotf(f64::from(want[c]) / 65535.0)).abs() < 1e-7, "{got:?} vs {want:?}");
        }
    }

    // Grey with alpha: grey in every channel, alpha ignored; RGBA 16-bit too.
    let pla = d.join("grey_alpha.png");
    std::fs::write(&pla, common::png8(1, 1, 2, &[100, 3])).unwrap();
    let v = eotf(100.0 / 255.0) as f32;
    assert_eq!(load_picture(&picture_camera(&pla, 1, 1), false).unwrap().rgb, vec![[v; 3]]);
    let prgba = d.join("rgba16.png");
    std::fs::write(&prgba, common::png16(1, 1, 4, &[65535, 0, 0, 0])).unwrap();
    assert_eq!(load_picture(&picture_camera(&prgba, 1, 1), false).unwrap().rgb, vec![[1.0, 0.0, 0.0]]);
    // JPEG, found by its bytes whatever its name.
    let jpeg = d.join("photo.jpg");
    let grey = vec![90u8; 16 * 8 * 3];
    jpeg_encoder::Encoder::new_file(&jpeg, 75).unwrap().encode(&grey, 16, 8, jpeg_encoder::ColorType::Rgb).unwrap();
    let copy = d.join("photo_without_extension");
    std::fs::copy(&jpeg, &copy).unwrap();
    assert_eq!(image_size(&copy).unwrap(), (16, 8));
    let picture = load_picture(&picture_camera(&copy, 16, 8), false).unwrap();
    assert!(picture.rgb.iter().flatten().all(|&x| (f64::from(x) - eotf(90.0 / 255.0)).abs() < 0.01));
}

// ------------------------------------------------------------ Bad input

#[test]
fn bad_input_names_the_file_and_camera() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    png(&d.join("views/view_0.png"), 8, 6);
    png(&d.join("views/view_1.png"), 8, 6);
    let rig = d.join("rig.toml");
    let write = |text: &str| std::fs::write(&rig, text).unwrap();

    // A missing image.
    write(RAIL_TOML);
    let e = error_of(read_rig_file(&rig));
    assert!(
        e.contains("rig.toml") && e.contains("camera 2 (views/view_2.png)") && e.contains("view_2.png: cannot open"),
        "{e}"
    );

    // An unreadable image, at opening and at loading.
    std::fs::write(d.join("views/view_2.png"), b"not a png at all").unwrap();
    let e = error_of(read_rig_file(&rig));
    assert!(e.contains("camera 2 (views/view_2.png)") && e.contains("unreadable image header"), "{e}");
    let probe = picture_camera(&d.join("views/view_2.png"), 8, 6);
    let e = load_picture(&probe, false).unwrap_err().to_string();
    assert!(e.contains("camera probe") && e.contains("view_2.png"), "{e}");
    let e = load_picture(&picture_camera(&d.join("views/view_0.png"), 16, 6), false).unwrap_err().to_string();
    assert!(e.contains("view_0.png") && e.contains("camera probe") && e.contains("8×6, the rig says 16×6"), "{e}");

    // Images of different sizes: in a rail, and in a plain folder.
    png(&d.join("views/view_2.png"), 10, 6);
    let e = error_of(read_rig_file(&rig));
    assert!(e.contains("camera 2 (views/view_2.png)") && e.contains("10×6, camera 0 is 8×6"), "{e}");
    let camera = CameraHints { focal_length_px: Some(5.0), ..CameraHints::default() };
    let folder = FolderOptions { baseline: Some(1.0), camera, ..FolderOptions::default() };
    let e = error_of(open_rig_with(&d.join("views"), &OpenOptions { folder, ..OpenOptions::default() }));
    assert!(e.contains("view_2.png") && e.contains("camera view_0.png's is 8×6"), "{e}");
    let e = error_of(read_rig_file(&d.join("nothing.toml")));
    assert!(e.contains("nothing.toml"), "{e}");

    // NaN in calibration: a rig file, and a Middlebury file.
    write("focal_length_px = 10\n[[cameras]]\nimage = \"views/view_0.png\"\nposition = [nan, 0, 0]\nrotation = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n");
    let e = error_of(read_rig_file(&rig));
    assert!(e.contains("rig.toml") && e.contains("camera 0 (views/view_0.png): calibration is not finite"), "{e}");
    let par = d.join("views/bad_par.txt");
    std::fs::write(&par, "1\nview_0.png 10 0 3.5 0 10 2.5 0 0 1 1 0 0 0 1 0 0 0 1 0 nan 1\n").unwrap();
    let e = error_of(open_rig(&par));
    assert!(e.contains("bad_par.txt") && e.contains("camera view_0.png") && e.contains("not finite"), "{e}");
    std::fs::write(&par, "2\nview_0.png 10 0 3.5 0 10 2.5 0 0 1 1 0 0 0 1 0 0 0 1 0 0 1\n").unwrap();
    let e = error_of(open_rig(&par));
    assert!(e.contains("says 2 cameras, the file lists 1"), "{e}");

    // Coincident cameras.
    write(
        "focal_length_px = 10\n\
         [[cameras]]\nimage = \"views/view_0.png\"\nposition = [1, 2, 3]\nlook_at = [0, 0, 0]\n\
         [[cameras]]\nimage = \"views/view_1.png\"\nposition = [1, 2, 3]\ndirection = [0, 0, -1]\n",
    );
    let e = error_of(read_rig_file(&rig));
    assert!(
        e.contains("cameras 0 (views/view_0.png) and 1 (views/view_1.png) are at the same position (1, 2, 3)"),
        "{e}"
    );

    // A quilt name with 0 columns.
    let quilt = d.join("scene_qs0x8a1.6.png");
    png(&quilt, 8, 8);
    let e = error_of(open_rig(&quilt));
    assert!(e.contains("scene_qs0x8a1.6.png") && e.contains("0 columns"), "{e}");

    // Unknown units, a misspelt key, a missing focal length, two layouts.
    write(
        "units = \"furlongs\"\nfocal_length_px = 10\n[rail]\ncount = 1\nbaseline = 1\nimages = \"views/view_0.png\"\n",
    );
    let e = error_of(read_rig_file(&rig));
    assert!(e.contains("rig.toml") && e.contains("unknown units \"furlongs\""), "{e}");
    write("focal_lenght_px = 10\n[rail]\ncount = 1\nbaseline = 1\nimages = \"views/view_0.png\"\n");
    let e = error_of(read_rig_file(&rig));
    assert!(e.contains("unknown key `focal_lenght_px`"), "{e}");
    write("[rail]\ncount = 2\nbaseline = 1\nimages = \"views/view_{i}.png\"\n");
    let e = error_of(read_rig_file(&rig));
    assert!(e.contains("camera 0 (views/view_0.png): no focal length"), "{e}");
    write("focal_length_px = 10\n[rail]\ncount = 1\nbaseline = 1\nimages = \"a.png\"\n[grid]\ncolumns = 1\n");
    let e = error_of(read_rig_file(&rig));
    assert!(e.contains("only one of"), "{e}");
    write(
        "focal_length_px = 10\n[[cameras]]\nimage = \"views/view_0.png\"\nposition = [0, 0, 0]\nlook_at = [0, 0, 0]\n",
    );
    let e = error_of(read_rig_file(&rig));
    assert!(e.contains("camera 0 (views/view_0.png)") && e.contains("viewing direction is zero"), "{e}");
    std::fs::write(d.join("broken.json"), "{ \"units\": ").unwrap();
    let e = error_of(read_rig_file(&d.join("broken.json")));
    assert!(e.contains("broken.json") && e.contains("not a valid JSON rig file"), "{e}");
}

/// A caller tells the kinds of failure apart by the error's variant: a file
/// the system cannot read, a capture that cannot be used (naming its file or
/// folder), a value passed that is out of range.
#[test]
fn rig_errors_keep_their_meaning() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let missing = d.join("missing.toml");
    match open_rig(&missing) {
        Err(holo::Error::Io { path, .. }) => assert_eq!(path, missing),
        other => panic!("a missing rig file is an I/O error: {other:?}"),
    }
    std::fs::write(d.join("broken.toml"), "cameras = [").unwrap();
    match open_rig(&d.join("broken.toml")) {
        Err(holo::Error::Rig { path, problem }) => {
            assert!(path == d.join("broken.toml") && problem.contains("TOML"), "{problem}")
        }
        other => panic!("a broken rig file: {other:?}"),
    }
    // A folder of pictures that does not say how far apart they are.
    png(&d.join("views/a.png"), 8, 6);
    png(&d.join("views/b.png"), 8, 6);
    match open_rig(&d.join("views")) {
        Err(holo::Error::Rig { path, problem }) => {
            assert!(path == d.join("views") && problem.contains("baseline"), "{problem}")
        }
        other => panic!("a rail without a baseline: {other:?}"),
    }
    // A quilt's name that counts no views is the caller's value.
    match holo::cameras::read::quilt_layout("a_qs0x8a1.6.png") {
        Some(Err(holo::Error::Argument { what: "quilt name", problem })) => {
            assert!(problem.contains("no views"), "{problem}")
        }
        other => panic!("a quilt name without views: {other:?}"),
    }
}
