//! Middlebury multi-view stereo (Seitz, Curless, Diebel, Scharstein and
//! Szeliski, CVPR 2006): a `*_par.txt` file whose first line is the number
//! of images and each further line
//! `name k11 k12 k13 k21 k22 k23 k31 k32 k33 r11 … r33 t1 t2 t3`, the
//! projection being `K [R | t]` with the image origin top left: exactly this
//! crate's convention, `x_c = R X + t`, so the centre is `−Rᵀ t`. The
//! data sets are in metres.

use std::path::Path;

use super::super::{Camera, ImageSource, Intrinsics, Pose, Rig};
use super::{bare, finish};
use crate::cameras::image::image_size;
use crate::error::{Error, Result};
use crate::math;

/// Read a Middlebury `*_par.txt`; images are found next to it.
pub fn read_middlebury(par: &Path) -> Result<Rig> {
    let text = std::fs::read_to_string(par).map_err(|e| Error::io(par, e))?;
    let dir = par.parent().unwrap_or(Path::new("."));
    let bad = |problem: String| Error::rig(par, problem);
    let mut lines = text.lines().enumerate().map(|(n, l)| (n + 1, l.trim())).filter(|(_, l)| !l.is_empty());
    let Some((_, first)) = lines.next() else { return Err(bad("the file is empty".into())) };
    let count: usize = first
        .parse()
        .map_err(|_| bad(format!("line 1 should be the number of cameras, not \"{}\"", first.escape_debug())))?;
    let lines: Vec<(usize, &str)> = lines.collect();
    if lines.len() != count {
        return Err(bad(format!("line 1 says {count} cameras, the file lists {}", lines.len())));
    }
    let mut cameras = Vec::with_capacity(count);
    for (n, line) in lines {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let name = fields[0];
        let who = format!("line {n} (camera {name})");
        if fields.len() != 22 {
            return Err(bad(format!(
                "{who}: expected 22 fields (image name, K 3×3, R 3×3, t 3), found {}",
                fields.len()
            )));
        }
        let mut v = [0.0; 21];
        for (x, field) in v.iter_mut().zip(&fields[1..]) {
            *x = field.parse().map_err(|_| bad(format!("{who}: \"{}\" is not a number", field.escape_debug())))?;
        }
        let m = |at: usize| {
            [[v[at], v[at + 1], v[at + 2]], [v[at + 3], v[at + 4], v[at + 5]], [v[at + 6], v[at + 7], v[at + 8]]]
        };
        let (k, r, t) = (m(0), m(9), [v[18], v[19], v[20]]);
        let intrinsics = intrinsics(k).map_err(|e| bad(format!("{who}: {e}")))?;
        let written = if cfg!(windows) { name.to_string() } else { name.replace('\\', "/") };
        let path = dir.join(written);
        let (width, height) =
            image_size(&path).map_err(|e| bad(format!("{who}: {}: {}", path.display(), bare(&e, &path))))?;
        let camera = Camera {
            name: name.to_string(),
            image: ImageSource::File(path),
            width,
            height,
            intrinsics,
            pose: Pose { rotation: r, centre: math::scale(math::mat3_transpose_apply(&r, t), -1.0) },
            depth: None,
        };
        if let Some(p) = camera.problem_detail() {
            return Err(bad(format!("{who}: {p}")));
        }
        cameras.push(camera);
    }
    finish(Rig {
        source: par.display().to_string(),
        cameras,
        metres_per_unit: 1.0,
        focus_distance: None,
        linear: false,
    })
}

/// Pinhole intrinsics from an upper-triangular `K` (normalised by `k33`;
/// skew refused).
fn intrinsics(k: [[f64; 3]; 3]) -> Result<Intrinsics, String> {
    if k[1][0] != 0.0 || k[2][0] != 0.0 || k[2][1] != 0.0 || k[2][2] == 0.0 {
        return Err("K must be upper triangular with k33 ≠ 0".into());
    }
    let k = k.map(|row| row.map(|x| x / k[2][2]));
    if k[0][1].abs() > 1e-6 * k[0][0].abs() {
        return Err(format!("K has skew {}: skewed pixels are not supported", k[0][1]));
    }
    Ok(Intrinsics { fx: k[0][0], fy: k[1][1], cx: k[0][2], cy: k[1][2] })
}
