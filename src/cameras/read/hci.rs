//! The HCI 4D light field benchmark (Honauer, Johannsen, Kondermann and
//! Goldluecke, ACCV 2016): a folder with `parameters.cfg` and
//! `input_CamNNN.png`, rendered by the benchmark's Blender add-on
//! (lightfield-analysis/blender-addon, `lightfield_simulator.py`):
//!
//! - a grid of `num_cams_x × num_cams_y` cameras, parented to one object at
//!   `center_cam_{x,y,z}_m` with Blender Euler XYZ rotation
//!   `center_cam_{rx,ry,rz}_rad`; every camera has that rotation (Blender
//!   cameras look along local −Z with +Y up);
//! - camera `NNN = num_cams_x · row + col` sits at local
//!   `x = (col − (n_x − 1)/2)·b`, `y = ((n_y − 1)/2 − row)·b`: columns step
//!   right, rows step down the picture;
//! - sensors shifted by `shift = −position · f / (sensor · F)` (in units of
//!   the larger picture side), so every view is centred on the point at the
//!   focus distance `F` in front of the centre camera: disparity 0 there;
//! - `f_px = focal_length_mm / sensor_size_mm · max(width, height)` (the
//!   add-on sets the sensor size on the larger side, as the toolkit's
//!   `disp2depth` assumes), square pixels;
//! - the ground truth of camera NNN (centre camera: also without suffix) is
//!   `gt_disp_lowres[_CamNNN].pfm`, disparity `d` with depth
//!   `z = b·f / (d + b·f/F)` (evaluation-toolkit `disp2depth`), or
//!   `gt_depth_lowres[_CamNNN].pfm`, camera `z` in metres.

use std::collections::HashMap;
use std::path::Path;

use super::super::array::ArrayFrame;
use super::super::{DepthKind, DepthSource, ImageSource, Rig};
use super::{bare, finish, list_files, CameraHints};
use crate::cameras::image::image_size;
use crate::error::{Error, Result};
use crate::math;

/// Read an HCI benchmark folder: a camera for each `input_CamNNN.png`
/// present (some copies hold only part of the grid), in index order.
pub fn read_hci(folder: &Path) -> Result<Rig> {
    let cfg_path = folder.join("parameters.cfg");
    let text = std::fs::read_to_string(&cfg_path).map_err(|e| Error::io(&cfg_path, e))?;
    let ini = parse_ini(&text);
    let bad = |problem: String| Error::rig(&cfg_path, problem);
    let value = |section: &str, key: &str| -> Result<f64> {
        let Some(text) = ini.get(&(section.to_string(), key.to_string())) else {
            return Err(bad(format!("[{section}] {key} is missing")));
        };
        let v: f64 = text.parse().map_err(|_| bad(format!("[{section}] {key} = \"{text}\" is not a number")))?;
        if !v.is_finite() {
            return Err(bad(format!("[{section}] {key} = {v} is not finite")));
        }
        Ok(v)
    };
    let positive = |section: &str, key: &str| -> Result<f64> {
        let v = value(section, key)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(bad(format!("[{section}] {key} must be positive (got {v})")))
        }
    };
    let count = |section: &str, key: &str| -> Result<usize> {
        let v = positive(section, key)?;
        if v.fract() != 0.0 || v > 1e6 {
            return Err(bad(format!("[{section}] {key} must be a whole number (got {v})")));
        }
        Ok(v as usize)
    };
    let focal_mm = positive("intrinsics", "focal_length_mm")?;
    let sensor_mm = positive("intrinsics", "sensor_size_mm")?;
    let (width, height) =
        (count("intrinsics", "image_resolution_x_px")?, count("intrinsics", "image_resolution_y_px")?);
    let (nx, ny) = (count("extrinsics", "num_cams_x")?, count("extrinsics", "num_cams_y")?);
    let baseline = positive("extrinsics", "baseline_mm")? / 1000.0;
    let focus = positive("extrinsics", "focus_distance_m")?;
    let centre = [
        value("extrinsics", "center_cam_x_m")?,
        value("extrinsics", "center_cam_y_m")?,
        value("extrinsics", "center_cam_z_m")?,
    ];
    let euler = [
        value("extrinsics", "center_cam_rx_rad")?,
        value("extrinsics", "center_cam_ry_rad")?,
        value("extrinsics", "center_cam_rz_rad")?,
    ];
    let f = focal_mm / sensor_mm * width.max(height) as f64;
    let grid = Grid { nx, ny, size: (width, height), f, baseline, focus, said_by: "parameters.cfg" };
    hci_grid(folder, &grid, ArrayFrame { centre, rotation: blender_camera_rotation(euler) })
}

/// An HCI folder's `input_CamNNN.png` grid without its `parameters.cfg`
/// (copies of the benchmark's scenes often leave it out): the grid is the
/// square that the highest camera number fills (9 × 9 for `Cam080`), the
/// picture size the centre camera's, and what the file would have said —
/// the focal length (`hints`, in pixels or as a field of view), the
/// baseline and the focus distance, in any one unit — is given by the user.
/// The cameras are the add-on's: parallel, in the plane `z = 0` looking
/// along −z, sensors shifted to converge at the focus.
pub fn read_hci_grid(folder: &Path, baseline: Option<f64>, hints: &CameraHints) -> Result<Rig> {
    let names = list_files(folder)?;
    let highest = names.iter().filter_map(|n| camera_index(n)).max();
    let Some(highest) = highest else {
        return Err(Error::rig(folder, "holds no input_CamNNN.png images"));
    };
    let n = (1..=1000).find(|n| n * n > highest).unwrap_or(1001);
    let missing = |what: &str, flag: &str| {
        Error::rig(
            folder,
            format!(
                "an HCI light field without parameters.cfg does not say {what}: give it ({flag}), \
                 or put the scene's parameters.cfg beside the pictures"
            ),
        )
    };
    let baseline = baseline.ok_or_else(|| missing("how far apart its cameras are", "--baseline"))?;
    let focus = hints.focus_distance.ok_or_else(|| missing("where its views converge", "--focus"))?;
    for (what, v) in [("baseline", baseline), ("focus distance", focus)] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(Error::argument(what, format!("the {what} must be positive, not {v}")));
        }
    }
    let centre = folder.join(format!("input_Cam{:03}.png", n * n / 2));
    let middle = if centre.is_file() {
        centre
    } else {
        folder.join(names.iter().find(|n| camera_index(n).is_some()).expect("a camera, above"))
    };
    let size = image_size(&middle).map_err(|e| Error::rig(&middle, bare(&e, &middle)))?;
    let f = super::focal_px(hints.focal_length_px, hints.horizontal_fov_deg, size.0)
        .map_err(|problem| Error::rig(folder, problem))?;
    let grid = Grid { nx: n, ny: n, size, f, baseline, focus, said_by: "the centre picture" };
    hci_grid(folder, &grid, ArrayFrame { centre: [0.0; 3], rotation: blender_camera_rotation([0.0; 3]) })
}

/// An HCI grid's geometry, from its `parameters.cfg` or from the user.
struct Grid {
    nx: usize,
    ny: usize,
    /// Picture size, pixels.
    size: (usize, usize),
    /// Focal length, pixels.
    f: f64,
    baseline: f64,
    focus: f64,
    /// Where the size and grid came from, for the messages.
    said_by: &'static str,
}

/// The cameras of `grid` whose pictures `folder` holds, in index order.
fn hci_grid(folder: &Path, grid: &Grid, frame: ArrayFrame) -> Result<Rig> {
    let Grid { nx, ny, size: (width, height), f, baseline, focus, said_by } = *grid;
    let centre_index = nx * ny / 2;
    let names = list_files(folder)?;
    let mut cameras = Vec::new();
    for name in &names {
        let Some(index) = camera_index(name) else { continue };
        let path = folder.join(name);
        if index >= nx * ny {
            return Err(Error::rig(&path, format!("camera {index} is outside the {nx}×{ny} grid of {said_by}")));
        }
        let size = image_size(&path).map_err(|e| Error::rig(&path, format!("camera {name}: {}", bare(&e, &path))))?;
        if size != (width, height) {
            return Err(Error::rig(
                &path,
                format!("camera {name}: the image is {}×{}, {said_by} says {width}×{height}", size.0, size.1),
            ));
        }
        let (row, col) = (index / nx, index % nx);
        let offset = math::add(
            math::scale(frame.right(), (col as f64 - (nx as f64 - 1.0) / 2.0) * baseline),
            math::scale(frame.down(), (row as f64 - (ny as f64 - 1.0) / 2.0) * baseline),
        );
        let mut camera = frame
            .camera(name.clone(), ImageSource::File(path), size, (f, f), offset, Some(focus))
            .map_err(|e| Error::rig(folder, e))?;
        camera.depth = ground_truth(folder, index, index == centre_index, baseline * f, focus);
        cameras.push((index, camera));
    }
    if cameras.is_empty() {
        return Err(Error::rig(folder, "holds parameters.cfg but no input_CamNNN.png images"));
    }
    cameras.sort_by_key(|c| c.0);
    finish(Rig {
        source: folder.display().to_string(),
        cameras: cameras.into_iter().map(|c| c.1).collect(),
        metres_per_unit: 1.0,
        focus_distance: Some(focus),
        linear: false,
    })
}

/// NNN of `input_CamNNN.png`.
pub(super) fn camera_index(name: &str) -> Option<usize> {
    let digits = name.strip_prefix("input_Cam")?.strip_suffix(".png")?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) || digits.len() > 6 {
        return None;
    }
    digits.parse().ok()
}

/// The disparity (preferred) or depth map of camera `index`, if present.
fn ground_truth(folder: &Path, index: usize, centre: bool, bf: f64, focus: f64) -> Option<DepthSource> {
    let suffixes = [format!("_Cam{index:03}"), String::new()];
    let suffixes = if centre { &suffixes[..] } else { &suffixes[..1] };
    for suffix in suffixes {
        let disparity = folder.join(format!("gt_disp_lowres{suffix}.pfm"));
        if disparity.is_file() {
            return Some(DepthSource {
                file: disparity,
                kind: DepthKind::Disparity { numerator: bf, offset: bf / focus },
            });
        }
        let depth = folder.join(format!("gt_depth_lowres{suffix}.pfm"));
        if depth.is_file() {
            return Some(DepthSource { file: depth, kind: DepthKind::Z { scale: 1.0 } });
        }
    }
    None
}

/// World-to-camera rotation (OpenCV axes) of a Blender camera with Euler
/// XYZ angles: the object matrix is `Rz·Ry·Rx`; the camera's right, up and
/// backward are its columns, so the rows are right, −up, −backward.
pub(crate) fn blender_camera_rotation(euler_xyz_rad: [f64; 3]) -> math::Mat3 {
    let m = math::rotation_xyz(euler_xyz_rad);
    let column = |j: usize, sign: f64| [m[0][j] * sign, m[1][j] * sign, m[2][j] * sign];
    [column(0, 1.0), column(1, -1.0), column(2, -1.0)]
}

/// `(section, key) → value` of an INI file (`;` and `#` comments).
fn parse_ini(text: &str) -> HashMap<(String, String), String> {
    let mut section = String::new();
    let mut out = HashMap::new();
    for line in text.lines() {
        let line = line.trim();
        if line.is_empty() || line.starts_with(';') || line.starts_with('#') {
            continue;
        }
        if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            section = name.trim().to_string();
        } else if let Some((key, value)) = line.split_once('=').or_else(|| line.split_once(':')) {
            out.insert((section.clone(), key.trim().to_string()), value.trim().to_string());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blender_identity_camera_looks_down() {
        // An unrotated Blender camera looks along world −Z with +Y up.
        let r = blender_camera_rotation([0.0; 3]);
        assert_eq!(r, [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]);
        // Rotated 90° about X it looks along +Y with +Z up.
        let r = blender_camera_rotation([std::f64::consts::FRAC_PI_2, 0.0, 0.0]);
        let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12);
        assert!(near(r[2], [0.0, 1.0, 0.0]) && near(r[1], [0.0, 0.0, -1.0]), "{r:?}");
    }

    #[test]
    fn names_and_ini() {
        assert_eq!(camera_index("input_Cam040.png"), Some(40));
        assert_eq!(camera_index("input_Cam.png"), None);
        assert_eq!(camera_index("gt_disp_lowres.pfm"), None);
        let ini = parse_ini("[a]\nx = 1\n; note\n[b]\nx=2\n");
        assert_eq!(ini[&("b".to_string(), "x".to_string())], "2");
    }
}
