//! A camera's picture as linear RGB: decoded from PNG (8 or 16 bits) or
//! JPEG, grey or colour (alpha ignored), cropped to the camera's tile, and
//! taken from sRGB to linear with the exact sRGB EOTF (IEC 61966-2-1) unless
//! the rig says its pictures are linear already.

use std::io::BufReader;
use std::path::Path;

use super::{Camera, ImageSource};
use crate::error::{Error, Result};
use crate::picture::decode::{self, DecodeError};
use crate::picture::{srgb_decode, Bits};
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
    decode::dimensions(reader).map_err(|e| Error::rig(path, format!("unreadable image header: {e}")))
}

fn open(path: &Path) -> Result<BufReader<std::fs::File>, String> {
    crate::output::regular_file(path)?;
    let file = std::fs::File::open(path).map_err(|e| format!("cannot open the image: {e}"))?;
    Ok(BufReader::new(file))
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
    let image = decode::decode(open(file).map_err(fail)?).map_err(|e| match e {
        DecodeError::NotPngOrJpeg => fail("is not a PNG or JPEG image".into()),
        e => fail(format!("cannot decode the image: {e}")),
    })?;
    let (iw, ih) = (image.width, image.height);
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
    let transfer = |x: f64| if linear { x } else { srgb_decode(x) } as f32;
    // Grey becomes RGB and alpha is dropped; 16-bit samples keep their 16 bits.
    let region = (x0, y0, w, h);
    let rgb = match image.bits() {
        Bits::Sixteen => {
            let lut: Vec<f32> = (0..=u16::MAX).map(|q| transfer(f64::from(q) / 65535.0)).collect();
            crop(&image.rgb16(), iw, region, &lut)
        }
        Bits::Eight => {
            let lut: Vec<f32> = (0..=u8::MAX).map(|q| transfer(f64::from(q) / 255.0)).collect();
            crop(&image.rgb8(), iw, region, &lut)
        }
    };
    Ok(Picture { width: w, height: h, rgb })
}

/// The `w × h` tile at `(x0, y0)` of RGB `samples` `width` pixels wide,
/// each code looked up in `lut`.
fn crop<T: Copy + Into<usize>>(
    samples: &[T],
    width: usize,
    (x0, y0, w, h): (usize, usize, usize, usize),
    lut: &[f32],
) -> Vec<[f32; 3]> {
    let pixel = |x: usize, y: usize| [0, 1, 2].map(|c| lut[samples[3 * (y * width + x) + c].into()]);
    (y0..y0 + h).flat_map(|y| (x0..x0 + w).map(move |x| pixel(x, y))).collect()
}

#[cfg(test)]
mod tests {
    use super::super::{Intrinsics, Pose};
    use super::*;
    use crate::picture::{encode_png_samples, Colour, PngTags, Samples};

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
        let codes: Vec<u8> = (0..12).map(|i| (i % 4 * 10 + i / 4 * 100) as u8).collect();
        let png = encode_png_samples(4, 3, Colour::Grey, Samples::Eight(&codes), PngTags::default()).unwrap();
        std::fs::write(&path, png).unwrap();
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
