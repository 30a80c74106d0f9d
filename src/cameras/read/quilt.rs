//! Looking Glass quilts: one image holding `columns × rows` views of a
//! horizontal camera rail, named `*_qs{columns}x{rows}a{aspect}.png`. View 0
//! is the bottom-left tile, then left to right, rows upward; view 0 is the
//! leftmost camera. The geometry is HoloPlay's (its Unity `LookingGlassUtil`):
//! cameras `D = size / tan(fov/2)` from the focal plane, view `v` at angle
//! `θ_v = −cone/2 + v/(N − 1)·cone` and offset `D tan θ_v` sideways, with
//! the projection shifted so every view frames the same focal-plane window.
//! Here `D = 1` (the world unit), the focal plane is `z = 0`, the cameras
//! look along −z from `z = 1`, and `aspect` is the width/height each view is
//! shown at (the tile's pixel aspect when the name has none).

use std::path::Path;

use super::super::array::ArrayFrame;
use super::super::{ImageSource, Rig};
use super::{bare, finish, QuiltCaptureOptions};
use crate::cameras::image::image_size;
use crate::error::{Error, Result};

/// What a quilt's name says about its tiles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuiltLayout {
    /// Tiles across.
    pub columns: usize,
    /// Tiles down.
    pub rows: usize,
    /// Width/height each view is shown at, when the name gives it.
    pub aspect: Option<f64>,
}

/// A quilt's layout from its file name, `None` when the name is not a
/// quilt's (no `_qs` suffix, not PNG/JPEG), an error when the suffix is
/// malformed or counts zero tiles (the caller names the file).
///
/// A malformed suffix is an [`Error::Argument`] quoting the name.
pub fn quilt_layout(file_name: &str) -> Option<Result<QuiltLayout>> {
    layout_from_name(file_name).map(|r| r.map_err(|problem| Error::argument("quilt name", problem)))
}

/// [`quilt_layout`], its error a phrase for the caller to put after the file's name.
fn layout_from_name(file_name: &str) -> Option<std::result::Result<QuiltLayout, String>> {
    let (stem, extension) = file_name.rsplit_once('.')?;
    if !["png", "jpg", "jpeg"].contains(&extension.to_ascii_lowercase().as_str()) {
        return None;
    }
    let (_, suffix) = stem.rsplit_once("_qs")?;
    let malformed = || "a quilt's name ends in _qs{columns}x{rows}a{aspect}, e.g. _qs8x6a0.75".to_string();
    let (counts, aspect) = match suffix.split_once('a') {
        Some((c, a)) => (c, Some(a)),
        None => (suffix, None),
    };
    let Some((columns, rows)) = counts.split_once('x') else { return Some(Err(malformed())) };
    let whole = |s: &str| if s.bytes().all(|b| b.is_ascii_digit()) { s.parse::<usize>().ok() } else { None };
    let (Some(columns), Some(rows)) = (whole(columns), whole(rows)) else { return Some(Err(malformed())) };
    if columns == 0 || rows == 0 {
        return Some(Err(format!("a quilt of {columns} columns × {rows} rows holds no views")));
    }
    let aspect = match aspect.map(str::parse::<f64>) {
        None => None,
        Some(Ok(a)) if a > 0.0 && a.is_finite() => Some(a),
        Some(_) => return Some(Err("the quilt's aspect (after 'a') must be a positive number".into())),
    };
    Some(Ok(QuiltLayout { columns, rows, aspect }))
}

/// Read a quilt: one camera per tile, in view order.
pub fn read_quilt(path: &Path, options: &QuiltCaptureOptions) -> Result<Rig> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let QuiltLayout { columns, rows, aspect } = layout_from_name(&name)
        .unwrap_or_else(|| {
            Err(format!("\"{name}\" is not named like a quilt (*_qs{{columns}}x{{rows}}a{{aspect}}.png)"))
        })
        .map_err(|e| Error::rig(path, e))?;
    let (cone, fov) = (options.view_cone_deg, options.vertical_fov_deg);
    if !((0.0..180.0).contains(&cone) && fov > 0.0 && fov < 180.0) {
        return Err(Error::argument("quilt options", format!(
            "{}: the quilt options need a view cone in [0°, 180°) and a field of view in (0°, 180°) (got {cone}°, {fov}°)",
            path.display()
        )));
    }
    let (width, height) = image_size(path).map_err(|e| Error::rig(path, bare(&e, path)))?;
    // Leftover pixels (sizes not divisible) are at the right and top, as
    // HoloPlay lays tiles from the bottom-left corner.
    let (w, h) = (width / columns, height / rows);
    if w == 0 || h == 0 {
        return Err(Error::rig(path, format!("a {width}×{height} image cannot hold {columns}×{rows} tiles")));
    }
    let aspect = aspect.unwrap_or(w as f64 / h as f64);
    let half_height = (fov.to_radians() / 2.0).tan();
    let (fx, fy) = (w as f64 / 2.0 / (aspect * half_height), h as f64 / 2.0 / half_height);
    let frame = ArrayFrame::new([0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]).map_err(|e| Error::rig(path, e))?;
    let views = columns * rows;
    let mut cameras = Vec::with_capacity(views);
    for v in 0..views {
        let angle = if views == 1 { 0.0 } else { -cone / 2.0 + v as f64 / (views as f64 - 1.0) * cone };
        let (col, row_up) = (v % columns, v / columns);
        let tile = ImageSource::Tile {
            file: path.to_path_buf(),
            x: col * w,
            y: height - (row_up + 1) * h,
            width: w,
            height: h,
        };
        let offset = [angle.to_radians().tan(), 0.0, 0.0];
        let camera = frame
            .camera(format!("view {v}"), tile, (w, h), (fx, fy), offset, Some(1.0))
            .map_err(|e| Error::rig(path, e))?;
        cameras.push(camera);
    }
    finish(Rig {
        source: path.display().to_string(),
        cameras,
        metres_per_unit: 1.0,
        focus_distance: Some(1.0),
        linear: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        let layout = |columns, rows, aspect| Some(Ok(QuiltLayout { columns, rows, aspect }));
        assert_eq!(layout_from_name("a_qs4x8a1.6.png"), layout(4, 8, Some(1.6)));
        assert_eq!(layout_from_name("photo_qs8x6a0.75.JPG"), layout(8, 6, Some(0.75)));
        assert_eq!(layout_from_name("b_qs5x9.png"), layout(5, 9, None));
        assert_eq!(layout_from_name("view_01.png"), None);
        assert_eq!(layout_from_name("a_qs4x8a1.6.txt"), None);
        assert!(layout_from_name("a_qs0x8a1.6.png").unwrap().unwrap_err().contains("no views"));
        assert!(layout_from_name("a_qs4by8.png").unwrap().unwrap_err().contains("_qs{columns}x{rows}"));
        let e = quilt_layout("a_qs4x8a-1.png").unwrap().unwrap_err();
        assert!(matches!(&e, Error::Argument { what: "quilt name", .. }) && e.to_string().contains("aspect"), "{e}");
    }
}
