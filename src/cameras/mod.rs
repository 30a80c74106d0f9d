//! Camera arrays to modulation: rigs of calibrated pinhole
//! cameras, the readers for the conventions captures come in, and the
//! resampling of every modulation ray from the cameras' pictures.
//!
//! Conventions (the same as OpenCV's and Middlebury's `K [R | t]`): a
//! camera looks along its `+z`, with `+x` right and `+y` down in the
//! picture; a world point `X` is at `x_c = R (X − C)` in the camera, and at
//! pixel `(f_x x_c/z_c + c_x, f_y y_c/z_c + c_y)`, where pixel `(0, 0)` is
//! the *centre* of the top-left pixel. World ("capture") units are whatever
//! the rig says; [`Rig::metres_per_unit`] converts them to metres.

pub mod convert;
pub mod hci;
pub mod resample;

use std::path::PathBuf;

use crate::math::{self, cross, det3, dot, mat3_apply, mat3_transpose_apply, unit, Mat3};

mod array;
pub mod image;
pub mod mesh_picture;
pub mod pfm;
pub mod quilt;
pub mod read;
mod record;
pub mod rig_file;

pub use read::{open_rig, open_rig_with};

/// Pinhole intrinsics in pixels (no lens distortion: captures are expected
/// undistorted, as the benchmark data sets are).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    /// Focal length in pixels, horizontally and vertically.
    pub fx: f64,
    /// Vertical focal length in pixels.
    pub fy: f64,
    /// Principal point in pixels (pixel centres at integers, `(0, 0)` top left).
    pub cx: f64,
    /// Vertical principal point in pixels.
    pub cy: f64,
}

/// Where a camera is and where it looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// World to camera: the rows are the camera's `x` (right), `y` (down)
    /// and `z` (viewing direction) axes in world coordinates (row-major,
    /// [`Mat3`]).
    pub rotation: Mat3,
    /// Centre of projection, world units.
    pub centre: [f64; 3],
}

/// Where a camera's picture comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum ImageSource {
    /// A whole image file (PNG, JPEG; 8 or 16 bits, sRGB-encoded unless the
    /// rig says linear).
    File(PathBuf),
    /// A rectangle of an image file (a quilt tile): `x`, `y` of its top-left
    /// pixel, and its size.
    Tile {
        /// The image file.
        file: PathBuf,
        /// Left column of the tile.
        x: usize,
        /// Top row of the tile.
        y: usize,
        /// Tile width in pixels.
        width: usize,
        /// Tile height in pixels.
        height: usize,
    },
}

/// What a depth map's samples mean.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DepthKind {
    /// Camera `z` (distance along the viewing direction) = sample × `scale`,
    /// in world units.
    Z {
        /// World units per sample unit.
        scale: f64,
    },
    /// Disparity in pixels: camera `z = numerator / (sample + offset)`, world
    /// units (for parallel cameras focused at distance `F` with baseline `b`
    /// and focal length `f` pixels: `numerator = b·f`, `offset = b·f/F`).
    Disparity {
        /// `b·f`, world units × pixels.
        numerator: f64,
        /// `b·f/F`, pixels.
        offset: f64,
    },
}

/// A per-pixel depth or disparity map of one camera (PFM, same size as the
/// picture).
#[derive(Clone, Debug, PartialEq)]
pub struct DepthSource {
    /// The PFM file.
    pub file: PathBuf,
    /// What its samples mean.
    pub kind: DepthKind,
}

/// One camera of a rig.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// For messages: the file name or the rig's name for it.
    pub name: String,
    /// Where its picture is.
    pub image: ImageSource,
    /// The picture's size in pixels.
    pub width: usize,
    /// Picture height in pixels.
    pub height: usize,
    /// Focal lengths and principal point.
    pub intrinsics: Intrinsics,
    /// Position and orientation.
    pub pose: Pose,
    /// A depth or disparity map, where the capture has one.
    pub depth: Option<DepthSource>,
}

/// A set of calibrated cameras that photographed one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Rig {
    /// Where it came from (rig file, folder, quilt), for messages.
    pub source: String,
    /// The cameras, in the capture's order.
    pub cameras: Vec<Camera>,
    /// Metres per world unit (1 for a rig in metres, 0.001 in millimetres).
    pub metres_per_unit: f64,
    /// The distance from the cameras at which the capture is in focus, world
    /// units, when the capture says (HCI `focus_distance_m`, a quilt's focal
    /// plane); the resampler's default focus depth.
    pub focus_distance: Option<f64>,
    /// The pictures hold linear values already (not sRGB-encoded).
    pub linear: bool,
}

impl Camera {
    /// Pixel coordinates of world point `p` and its camera `z`, or `None`
    /// when `p` is not in front of the camera.
    pub fn project(&self, p: [f64; 3]) -> Option<([f64; 2], f64)> {
        let d = [p[0] - self.pose.centre[0], p[1] - self.pose.centre[1], p[2] - self.pose.centre[2]];
        let r = &self.pose.rotation;
        let c = [0, 1, 2].map(|i| r[i][0] * d[0] + r[i][1] * d[1] + r[i][2] * d[2]);
        if c[2].is_nan() || c[2] <= 0.0 {
            return None;
        }
        let k = &self.intrinsics;
        Some(([k.fx * c[0] / c[2] + k.cx, k.fy * c[1] / c[2] + k.cy], c[2]))
    }

    /// Whether world point `p` lies in front of the camera and inside its
    /// picture (pixel centres at whole numbers, edges half a pixel out).
    pub fn sees(&self, p: [f64; 3]) -> bool {
        self.project(p).is_some_and(|(px, _)| {
            px[0] >= -0.5 && px[1] >= -0.5 && px[0] <= self.width as f64 - 0.5 && px[1] <= self.height as f64 - 0.5
        })
    }

    /// The viewing direction (unit, world).
    pub fn axis(&self) -> [f64; 3] {
        self.pose.rotation[2]
    }

    /// The unit world direction of the ray through pixel `(u, v)`.
    pub fn ray(&self, u: f64, v: f64) -> [f64; 3] {
        let k = &self.intrinsics;
        let c = [(u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0];
        // NaN for a broken rotation, which `problem` reports.
        unit(mat3_transpose_apply(&self.pose.rotation, c)).unwrap_or([f64::NAN; 3])
    }

    /// What is wrong with this camera's numbers, if anything (names it).
    pub fn problem(&self) -> Option<String> {
        self.problem_detail().map(|p| format!("camera {}: {p}", self.name))
    }

    /// What is wrong with this camera's numbers, without its name (for
    /// readers that name cameras their own way, e.g. with their index).
    pub fn problem_detail(&self) -> Option<String> {
        let k = &self.intrinsics;
        let finite = [k.fx, k.fy, k.cx, k.cy]
            .iter()
            .chain(self.pose.centre.iter())
            .chain(self.pose.rotation.iter().flatten())
            .all(|x| x.is_finite());
        if !finite {
            return Some("calibration is not finite (NaN or infinite)".into());
        }
        if !(k.fx > 0.0 && k.fy > 0.0) {
            return Some(format!("focal length must be positive (fx {}, fy {})", k.fx, k.fy));
        }
        if self.width == 0 || self.height == 0 {
            return Some(format!("the picture is empty ({}×{})", self.width, self.height));
        }
        // Rotation: orthonormal to a tolerance that calibration files (printed
        // to 6–8 digits) meet.
        let r = &self.pose.rotation;
        for i in 0..3 {
            for j in 0..3 {
                let d = dot(r[i], r[j]);
                let want = if i == j { 1.0 } else { 0.0 };
                if (d - want).abs() > 1e-4 {
                    return Some(format!("the rotation is not orthonormal (row {i}·row {j} = {d:.6})"));
                }
            }
        }
        let det = det3(r);
        if det < 0.0 {
            return Some(format!("the rotation is a reflection (determinant {det:.3})"));
        }
        None
    }

    /// Shift the principal point so that world point `p` is pictured at the
    /// centre of the picture, `((w − 1)/2, (h − 1)/2)`: the shifted sensor of
    /// a parallel camera array converging at `p` (HCI, quilts, rectified
    /// gantry captures). False, and the camera unchanged, when `p` is not in
    /// front of the camera.
    pub fn centre_on(&mut self, p: [f64; 3]) -> bool {
        let d = math::sub(p, self.pose.centre);
        let c = mat3_apply(&self.pose.rotation, d);
        if c[2].is_nan() || c[2] <= 0.0 {
            return false;
        }
        let k = &mut self.intrinsics;
        k.cx = (self.width as f64 - 1.0) / 2.0 - k.fx * c[0] / c[2];
        k.cy = (self.height as f64 - 1.0) / 2.0 - k.fy * c[1] / c[2];
        true
    }
}

impl Intrinsics {
    /// Focal lengths `fx`, `fy` with the principal point at the centre of a
    /// `width`×`height` picture, `((w − 1)/2, (h − 1)/2)`.
    pub fn centred(width: usize, height: usize, fx: f64, fy: f64) -> Intrinsics {
        Intrinsics { fx, fy, cx: (width as f64 - 1.0) / 2.0, cy: (height as f64 - 1.0) / 2.0 }
    }
}

/// The rotation whose camera looks along `forward` with `down` as near the
/// picture's `+y` as it can be (both world vectors, not necessarily unit).
pub fn look_rotation(forward: [f64; 3], down: [f64; 3]) -> Mat3 {
    // NaN for parallel or zero vectors, which the camera checks report.
    let unit = |v: [f64; 3]| unit(v).unwrap_or([f64::NAN; 3]);
    let z = unit(forward);
    let x = unit(cross(down, z));
    let y = cross(z, x);
    [x, y, z]
}

impl Rig {
    /// Every file the rig's pictures and depth maps are read from, each
    /// once, in the cameras' order: an output may be none of them.
    pub fn files(&self) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = Vec::new();
        for camera in &self.cameras {
            let picture = match &camera.image {
                ImageSource::File(file) | ImageSource::Tile { file, .. } => file,
            };
            for file in std::iter::once(picture).chain(camera.depth.as_ref().map(|d| &d.file)) {
                if !files.contains(file) {
                    files.push(file.clone());
                }
            }
        }
        files
    }

    /// The first thing wrong with the rig, naming the camera: no cameras,
    /// bad units or focus distance, bad calibration.
    pub fn problem(&self) -> Option<String> {
        self.problem_detail().map(|p| format!("{}: {p}", self.source))
    }

    /// [`Rig::problem`] as the error a reader or converter refuses the rig
    /// with: an [`Error::Rig`](crate::error::Error::Rig) naming its source.
    pub fn check(&self) -> crate::error::Result<()> {
        match self.problem_detail() {
            Some(p) => Err(crate::error::Error::rig(&self.source, p)),
            None => Ok(()),
        }
    }

    /// What is wrong with the rig, without its source.
    fn problem_detail(&self) -> Option<String> {
        if self.cameras.is_empty() {
            return Some("the rig has no cameras".into());
        }
        if !(self.metres_per_unit > 0.0 && self.metres_per_unit.is_finite()) {
            return Some(format!("units must be a positive length (metres per unit {})", self.metres_per_unit));
        }
        if let Some(f) = self.focus_distance {
            if !(f > 0.0 && f.is_finite()) {
                return Some(format!("the focus distance must be positive (got {f})"));
            }
        }
        self.cameras.iter().find_map(Camera::problem)
    }

    /// The indices of two cameras at the same position (closer than 1e-9 of
    /// the rig's extent), if any. Not a [`Rig::problem`]: real captures
    /// photograph one viewpoint twice (Middlebury's templeSparseRing has two
    /// views with identical `K`, `R`, `t`); the rig-file reader refuses it,
    /// as there it is a copy-pasted pose.
    pub fn coincident_cameras(&self) -> Option<(usize, usize)> {
        let centres: Vec<[f64; 3]> = self.cameras.iter().map(|c| c.pose.centre).collect();
        let first = *centres.first()?;
        let extent = centres.iter().map(|&c| math::length(math::sub(c, first))).fold(0.0, f64::max);
        let tolerance = 1e-9 * extent;
        // Sorted along x, only neighbours within the tolerance in x can coincide.
        let mut order: Vec<usize> = (0..centres.len()).collect();
        order.sort_by(|&a, &b| centres[a][0].total_cmp(&centres[b][0]));
        for (n, &a) in order.iter().enumerate() {
            for &b in &order[n + 1..] {
                if centres[b][0] - centres[a][0] > tolerance {
                    break;
                }
                if math::length(math::sub(centres[a], centres[b])) <= tolerance {
                    return Some((a.min(b), a.max(b)));
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            name: "c".into(),
            image: ImageSource::File("c.png".into()),
            width: 64,
            height: 48,
            intrinsics: Intrinsics { fx: 100.0, fy: 100.0, cx: 31.5, cy: 23.5 },
            pose: Pose { rotation: look_rotation([0.0, 0.0, -1.0], [0.0, -1.0, 0.0]), centre: [0.1, 0.0, 1.0] },
            depth: None,
        }
    }

    #[test]
    fn project_and_ray_are_inverse() {
        let c = camera();
        // Looking down −z with y down-the-picture = world −y: world +x is picture right.
        let (px, z) = c.project([0.1, 0.0, 0.0]).unwrap();
        assert!((px[0] - 31.5).abs() < 1e-12 && (px[1] - 23.5).abs() < 1e-12 && (z - 1.0).abs() < 1e-12);
        let (px, _) = c.project([0.2, 0.1, 0.0]).unwrap();
        assert!(px[0] > 31.5 && px[1] < 23.5, "{px:?}");
        let d = c.ray(px[0], px[1]);
        let want = [0.1, 0.1, -1.0];
        let l = (0.02f64 + 1.0).sqrt();
        for k in 0..3 {
            assert!((d[k] - want[k] / l).abs() < 1e-12);
        }
        assert!(c.project([0.0, 0.0, 2.0]).is_none(), "behind the camera");
    }

    #[test]
    fn bad_calibration_is_named() {
        let mut c = camera();
        c.intrinsics.fx = f64::NAN;
        assert!(c.problem().unwrap().contains("camera c"));
        let mut c = camera();
        c.pose.rotation[0][0] = 2.0;
        assert!(c.problem().unwrap().contains("orthonormal"));
        let mut c = camera();
        c.pose.rotation[0] = c.pose.rotation[0].map(|x| -x);
        assert!(c.problem().unwrap().contains("reflection"));
        assert!(camera().problem().is_none());
    }

    #[test]
    fn coincident_cameras_are_named() {
        let mut b = camera();
        b.name = "d".into();
        let mut rig = Rig {
            source: "r".into(),
            cameras: vec![camera(), b.clone()],
            metres_per_unit: 1.0,
            focus_distance: None,
            linear: false,
        };
        assert_eq!(rig.coincident_cameras(), Some((0, 1)));
        rig.cameras[1].pose.centre[0] += 1e-3;
        assert_eq!(rig.coincident_cameras(), None);
        rig.cameras.push(camera());
        assert_eq!(rig.coincident_cameras(), Some((0, 2)));
    }

    #[test]
    fn centre_on_shifts_the_principal_point() {
        let mut c = camera();
        assert!(c.centre_on([0.0, 0.0, 0.0]));
        let (px, _) = c.project([0.0, 0.0, 0.0]).unwrap();
        assert!((px[0] - 31.5).abs() < 1e-12 && (px[1] - 23.5).abs() < 1e-12, "{px:?}");
        // The camera is 0.1 right of the point: its sensor shifts right, cx = 31.5 + f·0.1/1.
        assert!((c.intrinsics.cx - 41.5).abs() < 1e-12);
        assert!(!c.centre_on([0.0, 0.0, 2.0]), "behind");
    }
}
