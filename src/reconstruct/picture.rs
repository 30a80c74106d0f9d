//! What a viewer sees, as a picture: linear brightness per emitter and
//! hololine, and its PNG with the pixels at the display's aspect ratio.

use std::path::Path;

use crate::error::Result;
use crate::picture::{encode_png, Bits, Colour, Tone};

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

    /// The picture as an 8-bit sRGB PNG (grey for one channel, RGB for R,
    /// G, B; a missing colour is black), tone-mapped as every picture is
    /// ([`crate::picture`]): brightness `white` is full white, at the
    /// display's proportions ([`Picture::square_pixels`]).
    pub fn png(&self, white: f32) -> Result<Vec<u8>> {
        let tone = Tone::new(white, Bits::Eight)?;
        let square = self.square_pixels();
        let colour = if self.channels.len() == 1 { Colour::Grey } else { Colour::Rgb };
        encode_png(square.width, square.height, colour, &tone, None, |x, y| square.at(x, y))
    }

    /// The picture in pixels square on the display: the smaller pitch is one
    /// pixel, and the other axis is widened to the pitches' exact ratio,
    /// each pixel showing the emitter or hololine under its centre (so
    /// every emitter and hololine keeps at least one pixel, and no value is
    /// made up).
    pub fn square_pixels(&self) -> SquarePixels<'_> {
        let (width, height) = if self.column_aspect >= 1.0 {
            ((self.emitters as f64 * self.column_aspect).round().max(1.0) as usize, self.hololines)
        } else {
            (self.emitters, (self.hololines as f64 / self.column_aspect).round().max(1.0) as usize)
        };
        let slots = if self.channels.len() == 1 {
            [Some(0); 3]
        } else {
            ["R", "G", "B"].map(|name| self.channels.iter().position(|n| n == name))
        };
        SquarePixels { picture: self, width, height, slots }
    }

    /// Write [`Picture::png`] to `path`; an existing file is kept unless `overwrite`.
    pub fn write_png(&self, path: &Path, white: f32, overwrite: bool) -> Result<()> {
        let png = self.png(white).map_err(|e| e.naming(path))?;
        crate::output::write_bytes_beside(path, &png, overwrite)
    }
}

/// A [`Picture`] at the display's proportions: see [`Picture::square_pixels`].
#[derive(Clone, Copy, Debug)]
pub struct SquarePixels<'a> {
    picture: &'a Picture,
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// The picture's channel shown as red, green and blue (grey: the one
    /// channel in all three).
    slots: [Option<usize>; 3],
}

impl SquarePixels<'_> {
    /// Linear red, green and blue of pixel `(x, y)` from the top left (a
    /// grey picture's brightness in all three; a missing colour is 0).
    pub fn at(&self, x: usize, y: usize) -> [f32; 3] {
        let p = self.picture;
        let e = ((x as f64 + 0.5) * p.emitters as f64 / self.width as f64) as usize;
        let j = ((y as f64 + 0.5) * p.hololines as f64 / self.height as f64) as usize;
        let (e, j) = (e.min(p.emitters - 1), j.min(p.hololines - 1));
        self.slots.map(|c| c.map_or(0.0, |c| p.at(j, e, c)))
    }
}
