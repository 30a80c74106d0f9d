//! A plain folder of images: a horizontal rail of parallel cameras, the
//! first image (in natural name order) leftmost, `baseline` apart, looking
//! along −z with +y up. With a focus distance the sensors are shifted so
//! the views converge on the point that far in front of the rail's middle,
//! and the rail is placed at `z = F` so that plane is the world's `z = 0`.

use std::path::{Path, PathBuf};

use super::super::array::ArrayFrame;
use super::super::{ImageSource, Rig};
use super::{common_size, finish, focal_px, is_image, list_files, FolderOptions};
use crate::error::{Error, Result};

/// Read a folder of PNG/JPEG images as a rail; the options give what the
/// files cannot (baseline, focal length).
pub fn read_folder(folder: &Path, options: &FolderOptions) -> Result<Rig> {
    let usage = |problem: String| Error::rig(folder, problem);
    let images: Vec<(String, PathBuf)> =
        list_files(folder)?.into_iter().filter(|n| is_image(n)).map(|n| (n.clone(), folder.join(n))).collect();
    if images.is_empty() {
        return Err(Error::rig(folder, "holds no PNG or JPEG images"));
    }
    let baseline = match options.baseline {
        Some(b) if b > 0.0 && b.is_finite() => b,
        Some(b) => return Err(usage(format!("the baseline must be positive, not {b}"))),
        None if images.len() == 1 => 0.0,
        None => {
            return Err(usage(
                "a folder of images does not say how far apart its cameras are: give the baseline (the distance \
                 between neighbouring cameras, in the capture's units)"
                    .into(),
            ))
        }
    };
    if let Some(f) = options.camera.focus_distance {
        if !(f > 0.0 && f.is_finite()) {
            return Err(usage(format!("the focus distance must be positive, not {f}")));
        }
    }
    let size = common_size(&images)?;
    let f = focal_px(options.camera.focal_length_px, options.camera.horizontal_fov_deg, size.0).map_err(usage)?;
    let centre = [0.0, 0.0, options.camera.focus_distance.unwrap_or(0.0)];
    let frame = ArrayFrame::new(centre, [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]).map_err(usage)?;
    let n = images.len() as f64;
    let mut cameras = Vec::with_capacity(images.len());
    for (i, (name, path)) in images.into_iter().enumerate() {
        let offset = [(i as f64 - (n - 1.0) / 2.0) * baseline, 0.0, 0.0];
        let camera = frame
            .camera(name, ImageSource::File(path), size, (f, f), offset, options.camera.focus_distance)
            .map_err(usage)?;
        cameras.push(camera);
    }
    finish(Rig {
        source: folder.display().to_string(),
        cameras,
        metres_per_unit: options.metres_per_unit,
        focus_distance: options.camera.focus_distance,
        linear: false,
    })
}
