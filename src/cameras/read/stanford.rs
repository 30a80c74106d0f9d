//! The Stanford light field archive (lightfield.stanford.edu): a folder of
//! rectified views named `out_RR_CC_Y_X[_].png`. The archive's calibration
//! page says the two numbers after the row and column are the camera's
//! position "in the order (Y, X)", known up to a scale and translation (in
//! millimetres for its computer-controlled gantry). Y grows down the array:
//! the archive's readers in use take the camera at `x = X`, `y_up = −Y`
//! (Meta's neural light fields `StanfordLightfieldDataset`, Mossberg's
//! light-field-renderer). The views are rectified onto a reference plane
//! parallel to the cameras (zero parallax there), so the rig is parallel
//! cameras converging at that plane; its distance and the focal length are
//! not recorded and must be given ([`StanfordOptions`]).

use std::path::{Path, PathBuf};

use super::super::array::ArrayFrame;
use super::super::{ImageSource, Rig};
use super::{common_size, finish, focal_px, list_files, StanfordOptions};
use crate::error::{Error, Result};

/// `(row, column, y, x)` of a Stanford file name `out_RR_CC_Y_X[_].ext`, or
/// `None` for other names.
pub fn stanford_position(file_name: &str) -> Option<(usize, usize, f64, f64)> {
    let (stem, extension) = file_name.rsplit_once('.')?;
    if !["png", "jpg", "jpeg"].contains(&extension.to_ascii_lowercase().as_str()) {
        return None;
    }
    let stem = stem.strip_suffix('_').unwrap_or(stem);
    let parts: Vec<&str> = stem.split('_').collect();
    let ["out", row, col, y, x] = parts.as_slice() else { return None };
    let whole = |s: &str| if s.bytes().all(|b| b.is_ascii_digit()) { s.parse::<usize>().ok() } else { None };
    let (y, x): (f64, f64) = (y.parse().ok()?, x.parse().ok()?);
    (y.is_finite() && x.is_finite()).then_some(())?;
    Some((whole(row)?, whole(col)?, y, x))
}

/// Read a Stanford archive folder: one camera per `out_…` image, in row
/// then column order; other files are ignored.
pub fn read_stanford(folder: &Path, options: &StanfordOptions) -> Result<Rig> {
    // ((row, column, y, x), name, path)
    type View = ((usize, usize, f64, f64), String, PathBuf);
    let mut views: Vec<View> = list_files(folder)?
        .into_iter()
        .filter_map(|n| stanford_position(&n).map(|p| (p, n.clone(), folder.join(n))))
        .collect();
    if views.is_empty() {
        return Err(Error::rig(folder, "holds no out_RR_CC_Y_X.png images"));
    }
    views.sort_by_key(|v| (v.0 .0, v.0 .1));
    let named: Vec<(String, PathBuf)> = views.iter().map(|v| (v.1.clone(), v.2.clone())).collect();
    let size = common_size(&named)?;
    let f = focal_px(options.camera.focal_length_px, options.camera.horizontal_fov_deg, size.0)
        .map_err(|e| Error::rig(folder, e))?;
    let Some(focus) = options.camera.focus_distance else {
        return Err(Error::rig(
            folder,
            "the Stanford archive does not record how far its reference plane (zero parallax) is from the \
             cameras: give the focus distance (in the file names' units)",
        ));
    };
    let n = views.len() as f64;
    let mean = |pick: fn(&(usize, usize, f64, f64)) -> f64| views.iter().map(|v| pick(&v.0)).sum::<f64>() / n;
    let (my, mx) = (mean(|p| p.2), mean(|p| p.3));
    let frame =
        ArrayFrame::new([0.0, 0.0, focus], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]).map_err(|e| Error::rig(folder, e))?;
    let mut cameras = Vec::with_capacity(views.len());
    for ((_, _, y, x), name, path) in views {
        // World x right, y up: the file's Y grows downward.
        let offset = [x - mx, -(y - my), 0.0];
        let camera = frame
            .camera(name, ImageSource::File(path), size, (f, f), offset, Some(focus))
            .map_err(|e| Error::rig(folder, e))?;
        cameras.push(camera);
    }
    finish(Rig {
        source: folder.display().to_string(),
        cameras,
        metres_per_unit: options.metres_per_unit,
        focus_distance: Some(focus),
        linear: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        assert_eq!(stanford_position("out_00_16_-859.738525_1022.898010_.png"), Some((0, 16, -859.738525, 1022.89801)));
        assert_eq!(stanford_position("out_01_02_3.5_-4.png"), Some((1, 2, 3.5, -4.0)));
        assert_eq!(stanford_position("out_01_02.png"), None);
        assert_eq!(stanford_position("view_01_02_3_4.png"), None);
    }
}
