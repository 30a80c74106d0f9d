//! What a viewer sees, as a picture: linear brightness per emitter and
//! hololine, and its PNG with the pixels at the display's aspect ratio.

use std::path::Path;

use crate::output::write_atomically;
use crate::views::srgb_encode;
use crate::{Error, Result};

/// Linear brightness per (hololine, emitter) and colour channel,
/// `data[(j · emitters + e) · channels + c]`, 1 for a fully lit emitter.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    /// Emitters (columns).
    pub emitters: usize,
    /// Hololines (rows).
    pub hololines: usize,
    /// Colour channel names, in order (`Y` alone, or `R`, `G`, `B`).
    pub channels: Vec<String>,
    /// Emitter pitch over hololine pitch: the width of a column in rows.
    pub column_aspect: f64,
    /// The brightness.
    pub data: Vec<f32>,
}

impl Picture {
    /// Brightness of emitter `e` on hololine `j` in channel `c`.
    pub fn at(&self, j: usize, e: usize, c: usize) -> f32 {
        self.data[(j * self.emitters + e) * self.channels.len() + c]
    }

    /// Mean brightness of channel `c` over hololines `rows` and emitters `columns`.
    pub fn mean(&self, rows: std::ops::Range<usize>, columns: std::ops::Range<usize>, c: usize) -> f64 {
        let n = rows.len() * columns.len();
        rows.flat_map(|j| columns.clone().map(move |e| (j, e))).map(|(j, e)| f64::from(self.at(j, e, c))).sum::<f64>()
            / n as f64
    }

    /// Write an 8-bit sRGB PNG (grey for one channel, RGB for R, G, B; a
    /// missing colour is black): brightness `white` is full white, and each
    /// emitter and hololine becomes a block of whole pixels in proportion to
    /// their pitches, the smaller pitch one pixel. An existing file is kept
    /// unless `overwrite`.
    pub fn write_png(&self, path: &Path, white: f32, overwrite: bool) -> Result<()> {
        use image::codecs::png::PngEncoder;
        use image::{ExtendedColorType, ImageEncoder};
        if !(white.is_finite() && white > 0.0) {
            return Err(Error::argument("white level", format!("white {white} must be a positive brightness")));
        }
        let (px_e, px_j) = if self.column_aspect >= 1.0 {
            (self.column_aspect.round().max(1.0) as usize, 1)
        } else {
            (1, (1.0 / self.column_aspect).round().max(1.0) as usize)
        };
        let (width, height) = (self.emitters * px_e, self.hololines * px_j);
        let mono = self.channels.len() == 1;
        let components = if mono { 1 } else { 3 };
        let code = |x: f32| (srgb_encode(f64::from((x / white).clamp(0.0, 1.0))) * 255.0).round() as u8;
        let mut pixels = Vec::with_capacity(width * height * components);
        for y in 0..height {
            for x in 0..width {
                let (j, e) = (y / px_j, x / px_e);
                if mono {
                    pixels.push(code(self.at(j, e, 0)));
                } else {
                    for name in ["R", "G", "B"] {
                        let c = self.channels.iter().position(|n| n == name);
                        pixels.push(c.map_or(0, |c| code(self.at(j, e, c))));
                    }
                }
            }
        }
        let colour = if mono { ExtendedColorType::L8 } else { ExtendedColorType::Rgb8 };
        write_atomically(path, overwrite, |w| {
            PngEncoder::new(w)
                .write_image(&pixels, width as u32, height as u32, colour)
                .map_err(|e| Error::encode(path, "PNG", e))
        })?;
        Ok(())
    }
}
