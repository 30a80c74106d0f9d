//! A camera's picture as linear RGB: decoded from PNG (8 or 16 bits) or
//! JPEG, grey or colour (alpha ignored), cropped to the camera's tile, and
//! taken from sRGB to linear with the exact sRGB EOTF (IEC 61966-2-1) unless
//! the rig says its pictures are linear already.

use std::path::Path;

use ::image::{ColorType, ImageReader};

use super::{Camera, ImageSource};
use crate::error::{Error, Result};
use crate::picture::srgb_decode;
use crate::sampling::bilerp;

/// A picture in linear RGB, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `width × height` pixels, `rgb[y * width + x]`.
    pub rgb: Vec<[f32; 3]>,
}

impl Picture {
    /// The pixel in column `x`, row `y` (0 = top).
    pub fn get(&self, x: usize, y: usize) -> [f32; 3] {
        self.rgb[y * self.width + x]
    }

    /// Size in pixels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The picture at pixel position `(u, v)` (pixel centres at integers),
    /// bilinear with the edges held; `None` when `(u, v)` is more than half
    /// a pixel outside the edge centres, or not finite.
    pub fn sample(&self, u: f64, v: f64) -> Option<[f32; 3]> {
        let (w, h) = (self.width, self.height);
        let inside = u >= -0.5 && v >= -0.5 && u <= w as f64 - 0.5 && v <= h as f64 - 0.5;
        if !inside || w == 0 || h == 0 {
            return None;
        }
        let x = u.clamp(0.0, (w - 1) as f64);
        let y = v.clamp(0.0, (h - 1) as f64);
        // Both are ≥ 0, so truncation is the floor (without a call to libm's
        // `floor`, which the baseline x86-64 target has no instruction for).
        let (x0, y0) = (x as usize, y as usize);
        let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
        let (fx, fy) = ((x - x0 as f64) as f32, (y - y0 as f64) as f32);
        let corners = [self.get(x0, y0), self.get(x1, y0), self.get(x0, y1), self.get(x1, y1)];
        Some(bilerp(corners, fx, fy))
    }
}

/// Width and height of an image file, from its header only (no decoding),
/// so readers can size cameras cheaply. The format is found from the bytes,
/// not the extension.
pub fn image_size(path: &Path) -> Result<(usize, usize)> {
    let reader = open(path).map_err(|problem| Error::rig(path, problem))?;
    let (w, h) = reader.into_dimensions().map_err(|e| Error::rig(path, format!("unreadable image header: {e}")))?;
    Ok((w as usize, h as usize))
}

fn open(path: &Path) -> Result<ImageReader<std::io::BufReader<std::fs::File>>, String> {
    crate::output::regular_file(path)?;
    let reader = ImageReader::open(path)
        .map_err(|e| format!("cannot open the image: {e}"))?
        .with_guessed_format()
        .map_err(|e| format!("cannot read the image: {e}"))?;
    if reader.format().is_none() {
        return Err("is not a PNG or JPEG image".into());
    }
    Ok(reader)
}

/// The camera's picture in linear RGB: the whole file, or its tile of it.
/// Refuses, naming the camera and the file, a missing or undecodable file,
/// a tile outside the image, and a size other than the camera's.
pub fn load_picture(camera: &Camera, linear: bool) -> Result<Picture> {
    let (file, tile) = match &camera.image {
        ImageSource::File(file) => (file, None),
        ImageSource::Tile { file, x, y, width, height } => (file, Some((*x, *y, *width, *height))),
    };
    let fail = |problem: String| Error::rig(file, format!("camera {}: {problem}", camera.name));
    let image = open(file).map_err(fail)?.decode().map_err(|e| fail(format!("cannot decode the image: {e}")))?;
    let (iw, ih) = (image.width() as usize, image.height() as usize);
    let (x0, y0, w, h) = match tile {
        None => (0, 0, iw, ih),
        Some((x, y, w, h)) => {
            if x.checked_add(w).map_or(true, |r| r > iw) || y.checked_add(h).map_or(true, |b| b > ih) {
                return Err(fail(format!("the {w}×{h} tile at ({x}, {y}) does not fit in the {iw}×{ih} image")));
            }
            (x, y, w, h)
        }
    };
    if (w, h) != (camera.width, camera.height) {
        let what = if tile.is_some() { "the tile" } else { "the image" };
        return Err(fail(format!("{what} is {w}×{h}, the rig says {}×{}", camera.width, camera.height)));
    }
    let decode = |x: f64| if linear { x } else { srgb_decode(x) } as f32;
    let mut rgb = Vec::with_capacity(w * h);
    match image.color() {
        ColorType::L16 | ColorType::La16 | ColorType::Rgb16 | ColorType::Rgba16 => {
            let lut: Vec<f32> = (0..=u16::MAX).map(|q| decode(f64::from(q) / 65535.0)).collect();
            let buffer = image.to_rgb16();
            for y in y0..y0 + h {
                for x in x0..x0 + w {
                    rgb.push(buffer.get_pixel(x as u32, y as u32).0.map(|q| lut[q as usize]));
                }
            }
        }
        ColorType::Rgb32F | ColorType::Rgba32F => {
            let buffer = image.to_rgb32f();
            for y in y0..y0 + h {
                for x in x0..x0 + w {
                    rgb.push(buffer.get_pixel(x as u32, y as u32).0.map(|v| decode(f64::from(v))));
                }
            }
        }
        _ => {
            let lut: Vec<f32> = (0..=u8::MAX).map(|q| decode(f64::from(q) / 255.0)).collect();
            let buffer = image.to_rgb8();
            for y in y0..y0 + h {
                for x in x0..x0 + w {
                    rgb.push(buffer.get_pixel(x as u32, y as u32).0.map(|q| lut[q as usize]));
                }
            }
        }
    }
    Ok(Picture { width: w, height: h, rgb })
}

#[cfg(test)]
mod tests {
    use super::super::{Intrinsics, Pose};
    use super::*;

    fn camera(image: ImageSource, width: usize, height: usize) -> Camera {
        Camera {
            name: "t".into(),
            image,
            width,
            height,
            intrinsics: Intrinsics::centred(width, height, 10.0, 10.0),
            pose: Pose { rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], centre: [0.0; 3] },
            depth: None,
        }
    }

    #[test]
    fn bilinear_lookups_interpolate_and_stop_at_the_edges() {
        // A 4 × 2 ramp in x.
        let p = Picture { width: 4, height: 2, rgb: (0..8).map(|i| [(i % 4) as f32; 3]).collect() };
        assert_eq!(p.sample(1.5, 0.0).unwrap()[0], 1.5);
        assert_eq!(p.sample(2.25, 0.7).unwrap()[0], 2.25);
        assert_eq!(p.sample(3.4, 1.0).unwrap()[0], 3.0, "edges held");
        assert!(p.sample(-0.6, 0.0).is_none() && p.sample(0.0, 1.6).is_none());
        assert!(p.sample(f64::NAN, 0.0).is_none());
    }

    #[test]
    fn tiles_crop_and_grey_becomes_rgb() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("g.png");
        ::image::GrayImage::from_fn(4, 3, |x, y| ::image::Luma([(x * 10 + y * 100) as u8])).save(&path).unwrap();
        assert_eq!(image_size(&path).unwrap(), (4, 3));
        let tile = ImageSource::Tile { file: path.clone(), x: 1, y: 1, width: 2, height: 2 };
        let p = load_picture(&camera(tile, 2, 2), true).unwrap();
        assert_eq!(p.get(0, 0), [110.0 / 255.0; 3]);
        assert_eq!(p.get(1, 1), [220.0 / 255.0; 3]);
        let outside = ImageSource::Tile { file: path.clone(), x: 3, y: 0, width: 2, height: 2 };
        let e = load_picture(&camera(outside, 2, 2), true).unwrap_err().to_string();
        assert!(e.contains("camera t") && e.contains("does not fit") && e.contains("g.png"), "{e}");
        let e = load_picture(&camera(ImageSource::File(path), 5, 3), true).unwrap_err().to_string();
        assert!(e.contains("is 4×3, the rig says 5×3"), "{e}");
    }
}
