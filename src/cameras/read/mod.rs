//! Readers for the conventions captures come in, each giving a [`Rig`], and
//! [`open_rig`], which tells them apart: a rig file (spec/rig.md), the HCI
//! 4D light field benchmark, the Stanford light field archive, Middlebury
//! multi-view stereo, Looking Glass quilts and plain folders of images.
//! spec/rig.md, "Conventions read", gives each one's geometry and sources.

use std::cmp::Ordering;
use std::path::{Path, PathBuf};

use super::image::image_size;
use super::rig_file::read_rig_file;
use super::Rig;
use crate::error::{Error, Result};

mod folder;
mod hci;
mod middlebury;
mod quilt;
mod stanford;

pub use folder::read_folder;
pub use hci::{read_hci, read_hci_grid};
pub use middlebury::read_middlebury;
pub use quilt::{quilt_layout, read_quilt, QuiltLayout};
pub use stanford::{read_stanford, stanford_position};

/// What the captures that do not record their whole geometry need told.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OpenOptions {
    /// For a plain folder of images.
    pub folder: FolderOptions,
    /// For a Stanford light field archive folder.
    pub stanford: StanfordOptions,
    /// For a Looking Glass quilt.
    pub quilt: QuiltCaptureOptions,
}

/// What a capture's files do not say about its cameras, as the user gives
/// it: the focal length (in pixels, or as a field of view) and the distance
/// at which the views converge (the plane of zero parallax). The formats
/// that need it ([`FolderOptions`], [`StanfordOptions`]) say which parts
/// they require.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CameraHints {
    /// Focal length in pixels (this or `horizontal_fov_deg` is required).
    pub focal_length_px: Option<f64>,
    /// Horizontal field of view, degrees, edge to edge of the picture.
    pub horizontal_fov_deg: Option<f64>,
    /// Distance from the cameras' plane to the plane of zero parallax, in
    /// the capture's units.
    pub focus_distance: Option<f64>,
}

/// A plain folder of images is a horizontal rail, first image (by name,
/// numbers compared as numbers) leftmost; its files hold no geometry. With
/// a focus distance the cameras' sensors are shifted so that the views
/// converge there; without one they are parallel with centred principal
/// points.
#[derive(Clone, Debug, PartialEq)]
pub struct FolderOptions {
    /// Distance between neighbouring cameras, world units (required when
    /// there is more than one image).
    pub baseline: Option<f64>,
    /// Focal length and focus distance (world units).
    pub camera: CameraHints,
    /// Metres per world unit (default 1).
    pub metres_per_unit: f64,
}

impl Default for FolderOptions {
    fn default() -> Self {
        FolderOptions { baseline: None, camera: CameraHints::default(), metres_per_unit: 1.0 }
    }
}

/// The Stanford archive's file names give each camera's position (up to a
/// scale), but not the focal length nor the distance to the plane the
/// images are rectified to: both are required here.
#[derive(Clone, Debug, PartialEq)]
pub struct StanfordOptions {
    /// Focal length, and the distance to the plane the images are rectified
    /// to, in the file names' units.
    pub camera: CameraHints,
    /// Metres per unit of the file names' positions (default 0.001: the
    /// archive gives gantry positions in millimetres; the Lego gantry's are
    /// only known up to scale).
    pub metres_per_unit: f64,
}

impl Default for StanfordOptions {
    fn default() -> Self {
        StanfordOptions { camera: CameraHints::default(), metres_per_unit: 0.001 }
    }
}

/// A quilt holds no geometry; these are the HoloPlay defaults the views are
/// rendered with.
#[derive(Clone, Debug, PartialEq)]
pub struct QuiltCaptureOptions {
    /// Angle between the first and last camera as seen from the centre of
    /// the focal plane, degrees (HoloPlay: 35).
    pub view_cone_deg: f64,
    /// Vertical field of view of every view, degrees (HoloPlay: 14).
    pub vertical_fov_deg: f64,
}

impl Default for QuiltCaptureOptions {
    fn default() -> Self {
        QuiltCaptureOptions {
            view_cone_deg: crate::cameras::quilt::DEFAULT_VIEW_CONE_DEG,
            vertical_fov_deg: crate::cameras::quilt::DEFAULT_VERTICAL_FOV_DEG,
        }
    }
}

/// Open a capture with default options (see [`open_rig_with`]).
pub fn open_rig(path: &Path) -> Result<Rig> {
    open_rig_with(path, &OpenOptions::default())
}

/// Open a capture, telling its convention from what `path` is: a `.toml`
/// or `.json` rig file; a `*_par.txt` Middlebury file; a quilt image named
/// `*_qs{columns}x{rows}a{aspect}.png` (or `.jpg`); a folder holding
/// `parameters.cfg` (HCI), `rig.toml` or `rig.json`, one `*_par.txt`,
/// `out_RR_CC_Y_X.png` images (Stanford), `input_CamNNN.png` images (an HCI
/// grid without its parameters.cfg: [`read_hci_grid`]), or any images (a
/// plain rail).
pub fn open_rig_with(path: &Path, options: &OpenOptions) -> Result<Rig> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        if path.join("parameters.cfg").is_file() {
            return read_hci(path);
        }
        for name in ["rig.toml", "rig.json"] {
            if path.join(name).is_file() {
                return read_rig_file(&path.join(name));
            }
        }
        let names = list_files(path)?;
        let pars: Vec<&String> = names.iter().filter(|n| n.ends_with("_par.txt")).collect();
        match pars.as_slice() {
            [one] => return read_middlebury(&path.join(one)),
            [] => {}
            several => {
                let list: Vec<&str> = several.iter().map(|s| s.as_str()).collect();
                return Err(Error::rig(
                    path,
                    format!("holds several Middlebury camera files ({}): open one of them", list.join(", ")),
                ));
            }
        }
        if names.iter().any(|n| stanford_position(n).is_some()) {
            return read_stanford(path, &options.stanford);
        }
        if names.iter().any(|n| hci::camera_index(n).is_some()) {
            return read_hci_grid(path, options.folder.baseline, &options.folder.camera);
        }
        if names.iter().any(|n| is_image(n)) {
            return read_folder(path, &options.folder);
        }
        return Err(Error::rig(
            path,
            "no capture found: expected a rig file (rig.toml, rig.json), parameters.cfg (HCI), a *_par.txt \
             (Middlebury), out_RR_CC_Y_X.png images (Stanford) or a folder of PNG/JPEG images",
        ));
    }
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let lower = name.to_ascii_lowercase();
    if lower.ends_with(".toml") || lower.ends_with(".json") {
        read_rig_file(path)
    } else if lower.ends_with("_par.txt") {
        read_middlebury(path)
    } else if lower == "parameters.cfg" {
        read_hci(path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new(".")))
    } else if quilt_layout(&name).is_some() {
        read_quilt(path, &options.quilt)
    } else {
        Err(Error::rig(
            path,
            "not a capture this reader knows: expected a .toml or .json rig file, a Middlebury *_par.txt, \
             a quilt named *_qs{columns}x{rows}a{aspect}.png, or a folder",
        ))
    }
}

/// The rig, or its first problem as an error.
fn finish(rig: Rig) -> Result<Rig> {
    rig.check()?;
    Ok(rig)
}

/// The names of the files in `dir`, in natural order.
fn list_files(dir: &Path) -> Result<Vec<String>> {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        if entry.file_type().map_err(|e| Error::io(entry.path(), e))?.is_dir() {
            continue;
        }
        // Names that are not UTF-8 cannot be matched against a convention.
        if let Ok(name) = entry.file_name().into_string() {
            names.push(name);
        }
    }
    names.sort_by(|a, b| natural_order(a, b));
    Ok(names)
}

/// PNG or JPEG by extension.
fn is_image(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    [".png", ".jpg", ".jpeg"].iter().any(|e| lower.ends_with(e))
}

/// Names compared with their runs of digits as numbers (`view2` before
/// `view10`), then as text.
pub(crate) fn natural_order(a: &str, b: &str) -> Ordering {
    let (mut x, mut y) = (a.as_bytes(), b.as_bytes());
    loop {
        match (x.first(), y.first()) {
            (None, None) => return a.cmp(b),
            (None, _) => return Ordering::Less,
            (_, None) => return Ordering::Greater,
            (Some(c), Some(d)) if c.is_ascii_digit() && d.is_ascii_digit() => {
                let run = |s: &[u8]| s.iter().take_while(|c| c.is_ascii_digit()).count();
                let (m, n) = (run(x), run(y));
                let trim = |s: &[u8]| {
                    let zeros = s.iter().take_while(|&&c| c == b'0').count();
                    s[zeros..].to_vec()
                };
                let (p, q) = (trim(&x[..m]), trim(&y[..n]));
                let order = p.len().cmp(&q.len()).then_with(|| p.cmp(&q));
                if order != Ordering::Equal {
                    return order;
                }
                (x, y) = (&x[m..], &y[n..]);
            }
            (Some(c), Some(d)) => {
                if c != d {
                    return c.cmp(d);
                }
                (x, y) = (&x[1..], &y[1..]);
            }
        }
    }
}

/// The size every one of `images` (name, path) has, read from the headers;
/// a different size is refused naming both images.
fn common_size(images: &[(String, PathBuf)]) -> Result<(usize, usize)> {
    let mut first: Option<(&str, (usize, usize))> = None;
    for (name, path) in images {
        let size = image_size(path).map_err(|e| Error::rig(path, format!("camera {name}: {}", bare(&e, path))))?;
        match first {
            None => first = Some((name, size)),
            Some((other, s)) if s != size => {
                return Err(Error::rig(
                    path,
                    format!(
                        "camera {name}: the image is {}×{}, camera {other}'s is {}×{}; all views must be one size",
                        size.0, size.1, s.0, s.1
                    ),
                ))
            }
            Some(_) => {}
        }
    }
    first.map(|f| f.1).ok_or_else(|| Error::argument("images", "no images to size"))
}

/// An error's message without the leading path it names (so it can be
/// re-attached with more context).
fn bare(e: &Error, path: &Path) -> String {
    let text = e.to_string();
    let prefix = format!("{}: ", path.display());
    text.strip_prefix(&prefix).map(str::to_string).unwrap_or(text)
}

/// The focal length in pixels from the one of `focal` (pixels) and `fov_deg`
/// (the horizontal field of view over `width` pixels) given, or what is
/// wrong, in words a caller maps to its own options (the quantities, never
/// the fields of [`CameraHints`]).
fn focal_px(focal: Option<f64>, fov_deg: Option<f64>, width: usize) -> Result<f64, String> {
    match (focal, fov_deg) {
        (Some(_), Some(_)) => Err("give the focal length in pixels or the horizontal field of view, not both".into()),
        (Some(f), None) if f > 0.0 && f.is_finite() => Ok(f),
        (Some(f), None) => Err(format!("the focal length must be a positive number of pixels, not {f}")),
        (None, Some(a)) if a > 0.0 && a < 180.0 => Ok(width as f64 / 2.0 / (a.to_radians() / 2.0).tan()),
        (None, Some(a)) => Err(format!("the horizontal field of view must be between 0 and 180 degrees, not {a}")),
        (None, None) => {
            Err("the files do not give the cameras' focal length: give it in pixels, or the horizontal field of view"
                .into())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn natural_order_compares_numbers_as_numbers() {
        let mut names = vec!["v10.png", "v2.png", "v1.png", "a.png", "v02.png"];
        names.sort_by(|a, b| natural_order(a, b));
        assert_eq!(names, ["a.png", "v1.png", "v02.png", "v2.png", "v10.png"]);
    }
}
