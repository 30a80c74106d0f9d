//! The demo's pictures before they are PNGs: linear red, green and blue
//! per pixel, square pixels, into which pictures are pasted and labels
//! drawn; then tone-mapped and encoded by [`holo::picture`].

use holo::picture::{encode_apng, encode_png, Animation, Bits, Colour, Tone};
use holo::reconstruct::picture::Picture;
use holo::Result;

use super::font;

/// A picture in linear light, row by row from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Every pixel grey (the three components equal): written as a grey PNG.
    pub grey: bool,
    /// Linear red, green and blue.
    pub rgb: Vec<[f32; 3]>,
}

/// The colour of labels: full white.
pub const WHITE: [f32; 3] = [1.0; 3];
/// Each font pixel of a label is this many pixels.
pub const LABEL_SCALE: usize = 2;

impl Canvas {
    /// A black canvas.
    pub fn new(width: usize, height: usize, grey: bool) -> Canvas {
        Canvas { width, height, grey, rgb: vec![[0.0; 3]; width * height] }
    }

    /// What an eye sees, at the display's proportions, each pixel the mean of
    /// `shrink × shrink` square pixels of [`Picture::square_pixels`] (so the
    /// proportions stay; a remainder of fewer than `shrink` is left out).
    pub fn from_picture(picture: &Picture, shrink: usize) -> Canvas {
        let square = picture.square_pixels();
        let shrink = shrink.max(1);
        let (width, height) = ((square.width / shrink).max(1), (square.height / shrink).max(1));
        let mut canvas = Canvas::new(width, height, picture.channels.len() == 1);
        let area = (shrink * shrink) as f32;
        for y in 0..height {
            for x in 0..width {
                let mut sum = [0f32; 3];
                for (dx, dy) in (0..shrink).flat_map(|dy| (0..shrink).map(move |dx| (dx, dy))) {
                    let p =
                        square.at((x * shrink + dx).min(square.width - 1), (y * shrink + dy).min(square.height - 1));
                    sum.iter_mut().zip(p).for_each(|(s, v)| *s += v);
                }
                canvas.rgb[y * width + x] = sum.map(|s| s / area);
            }
        }
        canvas
    }

    /// Pixel `(x, y)` set to `colour`, if it is on the canvas.
    pub fn set(&mut self, x: usize, y: usize, colour: [f32; 3]) {
        if x < self.width && y < self.height {
            self.rgb[y * self.width + x] = colour;
            self.grey &= colour[0] == colour[1] && colour[1] == colour[2];
        }
    }

    /// A `width × height` rectangle at `(x, y)` filled with `colour`.
    pub fn fill(&mut self, x: usize, y: usize, width: usize, height: usize, colour: [f32; 3]) {
        for yy in y..y + height {
            for xx in x..x + width {
                self.set(xx, yy, colour);
            }
        }
    }

    /// `other` pasted with its top left at `(x, y)` (what falls outside is cut).
    pub fn paste(&mut self, x: usize, y: usize, other: &Canvas) {
        for yy in 0..other.height {
            for xx in 0..other.width {
                self.set(x + xx, y + yy, other.rgb[yy * other.width + xx]);
            }
        }
    }

    /// `text` in the built-in font ([`font`]) with its top left at `(x, y)`,
    /// each font pixel `scale × scale` pixels.
    pub fn text(&mut self, x: usize, y: usize, scale: usize, text: &str, colour: [f32; 3]) {
        for (fx, fy) in font::lit(text) {
            self.fill(x + fx * scale, y + fy * scale, scale, scale, colour);
        }
    }

    /// The canvas as an 8-bit sRGB PNG, sample 1 full white.
    pub fn png(&self) -> Result<Vec<u8>> {
        let colour = if self.grey { Colour::Grey } else { Colour::Rgb };
        encode_png(self.width, self.height, colour, &Tone::unit(Bits::Eight), None, |x, y| self.rgb[y * self.width + x])
    }
}

/// `frames` (all the size of the first) as an animated 8-bit sRGB PNG, each
/// shown `frame_seconds`, played `plays` times (0: forever).
pub fn apng(frames: &[Canvas], frame_seconds: f64, plays: u32) -> Result<Vec<u8>> {
    let Some(first) = frames.first() else {
        return Err(holo::Error::Argument {
            what: "picture",
            problem: "an animated PNG needs at least one frame".into(),
        });
    };
    if let Some(odd) = frames.iter().find(|f| (f.width, f.height) != (first.width, first.height)) {
        return Err(holo::Error::Argument {
            what: "picture",
            problem: format!(
                "an animated PNG's frames are one size: {}×{} and {}×{}",
                first.width, first.height, odd.width, odd.height
            ),
        });
    }
    let colour = if frames.iter().all(|f| f.grey) { Colour::Grey } else { Colour::Rgb };
    let (width, height) = (first.width, first.height);
    let animation = Animation { frames: frames.len(), frame_seconds, plays };
    encode_apng(width, height, colour, &Tone::unit(Bits::Eight), None, animation, |k, x, y| {
        frames[k].rgb[y * width + x]
    })
}
