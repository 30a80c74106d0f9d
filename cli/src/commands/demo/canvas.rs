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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_land_where_they_are_drawn() {
        let mut c = Canvas::new(20, 12, true);
        c.text(2, 1, 1, "-", WHITE);
        // The minus sign is the glyph's fourth row, five pixels wide.
        let lit: Vec<(usize, usize)> =
            (0..12).flat_map(|y| (0..20).map(move |x| (x, y))).filter(|&(x, y)| c.rgb[y * 20 + x][0] > 0.0).collect();
        assert_eq!(lit, (2..7).map(|x| (x, 4)).collect::<Vec<_>>());
        c.text(0, 0, 2, "1", [1.0, 0.0, 0.0]);
        assert!(!c.grey, "a red label makes the canvas colour");
        assert_eq!(c.rgb[4], [1.0, 0.0, 0.0], "the 1's top, scaled by two");
    }

    #[test]
    fn pictures_shrink_keeping_their_proportions() {
        // 4 emitters twice as wide as the 3 hololines are tall: 8 × 3 square pixels.
        let picture = Picture {
            emitters: 4,
            hololines: 3,
            channels: vec!["Y".into()],
            column_aspect: 2.0,
            data: (0..12).map(|i| i as f32 / 12.0).collect(),
        };
        let full = Canvas::from_picture(&picture, 1);
        assert_eq!((full.width, full.height, full.grey), (8, 3, true));
        assert_eq!(full.rgb[8 + 3], [5.0 / 12.0; 3], "row 1, emitter 1");
        let half = Canvas::from_picture(&picture, 2);
        assert_eq!((half.width, half.height), (4, 1));
        assert!(half.rgb[0].iter().all(|v| (v - 8.0 / 48.0).abs() < 1e-6), "{:?}", half.rgb[0]);
    }

    #[test]
    fn an_animation_holds_its_frames() {
        let frames: Vec<Canvas> = (0..3)
            .map(|k| {
                let mut c = Canvas::new(6, 9, true);
                c.text(0, 1, 1, &k.to_string(), WHITE);
                c
            })
            .collect();
        let bytes = apng(&frames, 0.1, 0).unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().unwrap();
        assert_eq!(reader.info().animation_control.map(|a| a.num_frames), Some(3));
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let mut seen = Vec::new();
        while reader.next_frame(&mut buf).is_ok() {
            seen.push(buf.clone());
        }
        assert_eq!(seen.len(), 3);
        assert!(seen[0] != seen[1] && seen[1] != seen[2]);
        let err = apng(&[Canvas::new(2, 2, true), Canvas::new(3, 2, true)], 0.1, 0).unwrap_err().to_string();
        assert!(err.contains("2×2 and 3×2"), "{err}");
    }
}
