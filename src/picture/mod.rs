//! Pictures for people: linear samples tone-mapped to sRGB PNG, and back.
//!
//! One tone mapping serves every picture `holo` writes (the views of
//! [`crate::views`], Looking Glass quilts, what an eye sees in
//! [`crate::reconstruct`], a camera's picture of a mesh scene): a sample `s`
//! becomes `linear = clamp(s / white, 0, 1)` (the quotient taken in f64, so
//! `white = 1` leaves the sample exact), then the sRGB transfer function of
//! IEC 61966-2-1 ([`srgb_encode`]), then a code rounded to nearest at 8 or
//! 16 bits ([`Tone::code`]). NaN becomes black. [`Tone::sample`] inverts
//! the last two steps exactly, so a sample at or below `white` comes back
//! within half a code step of the encoded value. Which sample value is full
//! white is a [`White`]: a number, [`White::Max`] (nothing clips: the
//! export inverts exactly) or [`White::Auto`] (the 99.9th percentile, so a
//! few specular glints do not darken everything else).
//!
//! The pixels become PNG bytes in memory ([`encode_png`],
//! [`encode_png_samples`]); callers write them with the crate's file writer.
//! A tone-mapped PNG carries an `sRGB` chunk (its codes are sRGB-encoded),
//! and, where its pixels are not square on the display, a `pHYs` chunk with
//! their physical size, so viewers that honour it show the right shape.
//! Pictures are read back, PNG or JPEG, by [`decode`].

use std::fmt;
use std::str::FromStr;

use rayon::prelude::*;

use crate::error::{Error, Result};

pub mod decode;

/// The percentile of the samples that [`White::Auto`] shows as full white.
pub const AUTO_WHITE_PERCENTILE: f64 = 99.9;

/// Which sample value is shown as full white.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum White {
    /// This sample value (finite and positive).
    Value(f32),
    /// The 99.9th percentile of the finite samples shown ([`AUTO_WHITE_PERCENTILE`]; nearest rank,
    /// the sorted sample at index `round((n − 1) · 0.999)`): robust to a few specular glints, at the
    /// price of clipping the brightest 0.1 %. If that is not positive, the largest sample; if no sample
    /// is positive, 1.
    #[default]
    Auto,
    /// The largest finite sample shown (1 if none is positive): nothing clips, so an export at this
    /// white inverts within half a quantization step everywhere.
    Max,
}

impl White {
    /// The sample value shown as full white among `samples` (every sample
    /// of the picture, all components). A [`White::Value`] is returned as it is.
    pub fn level(&self, samples: impl IntoIterator<Item = f32>) -> f32 {
        match *self {
            White::Value(white) => white,
            White::Max => positive_or_one(largest(samples)),
            White::Auto => {
                let mut finite: Vec<f32> = samples.into_iter().filter(|x| x.is_finite()).collect();
                if finite.is_empty() {
                    return 1.0;
                }
                let rank = ((finite.len() - 1) as f64 * AUTO_WHITE_PERCENTILE / 100.0).round() as usize;
                let (_, &mut at_rank, _) = finite.select_nth_unstable_by(rank, f32::total_cmp);
                if at_rank > 0.0 {
                    at_rank
                } else {
                    positive_or_one(largest(finite))
                }
            }
        }
    }

    /// What is wrong with a [`White::Value`], if anything.
    pub fn problem(&self) -> Option<String> {
        match *self {
            White::Value(white) if !(white.is_finite() && white > 0.0) => {
                Some(format!("the white level {white} is not a finite positive sample value"))
            }
            _ => None,
        }
    }
}

/// The largest finite sample, or 0 with none.
fn largest(samples: impl IntoIterator<Item = f32>) -> f32 {
    samples.into_iter().filter(|x| x.is_finite()).fold(0.0, f32::max)
}

fn positive_or_one(x: f32) -> f32 {
    if x > 0.0 {
        x
    } else {
        1.0
    }
}

impl fmt::Display for White {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            White::Value(white) => write!(f, "{white}"),
            White::Auto => f.write_str("auto"),
            White::Max => f.write_str("max"),
        }
    }
}

/// A text that is not `auto`, `max` or a finite positive number.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseWhiteError {
    text: String,
}

impl fmt::Display for ParseWhiteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?} is not a white level: give auto, max or a finite positive number", self.text)
    }
}

impl std::error::Error for ParseWhiteError {}

impl FromStr for White {
    type Err = ParseWhiteError;

    /// `auto`, `max` (any case) or a finite positive number.
    fn from_str(text: &str) -> std::result::Result<White, ParseWhiteError> {
        match text.trim().to_ascii_lowercase().as_str() {
            "auto" => Ok(White::Auto),
            "max" => Ok(White::Max),
            number => match number.parse::<f32>() {
                Ok(white) if White::Value(white).problem().is_none() => Ok(White::Value(white)),
                _ => Err(ParseWhiteError { text: text.to_string() }),
            },
        }
    }
}

/// Bits per PNG component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bits {
    /// Codes 0 to 255.
    Eight,
    /// Codes 0 to 65535.
    Sixteen,
}

impl Bits {
    /// 8 or 16; anything else is refused.
    pub fn from_count(bits: u8) -> Result<Bits> {
        match bits {
            8 => Ok(Bits::Eight),
            16 => Ok(Bits::Sixteen),
            other => Err(Error::argument("bits", format!("{other} bits per component: choose 8 or 16"))),
        }
    }

    /// 8 or 16.
    pub fn count(self) -> u8 {
        match self {
            Bits::Eight => 8,
            Bits::Sixteen => 16,
        }
    }

    /// The code of full white: 255 or 65535.
    pub fn max_code(self) -> u16 {
        match self {
            Bits::Eight => u16::from(u8::MAX),
            Bits::Sixteen => u16::MAX,
        }
    }
}

/// A white level and a bit depth: how samples become codes and back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tone {
    white: f32,
    bits: Bits,
}

impl Tone {
    /// Sample value `white` shown as full white, at `bits` per component;
    /// `white` must be finite and positive.
    pub fn new(white: f32, bits: Bits) -> Result<Tone> {
        match White::Value(white).problem() {
            Some(problem) => Err(Error::argument("white level", problem)),
            None => Ok(Tone { white, bits }),
        }
    }

    /// A sample of 1 shown as full white (exposure 1).
    pub const fn unit(bits: Bits) -> Tone {
        Tone { white: 1.0, bits }
    }

    /// The sample value shown as full white.
    pub fn white(&self) -> f32 {
        self.white
    }

    /// Bits per component.
    pub fn bits(&self) -> Bits {
        self.bits
    }

    /// The code of `sample`: `clamp(sample / white, 0, 1)`, sRGB-encoded,
    /// scaled to the bit depth and rounded to nearest (NaN gives 0).
    pub fn code(&self, sample: f32) -> u16 {
        let linear = (f64::from(sample) / f64::from(self.white)).clamp(0.0, 1.0);
        // `as` maps NaN to 0; the value is within [0, max] otherwise.
        (srgb_encode(linear) * f64::from(self.bits.max_code())).round() as u16
    }

    /// The sample value of `code` (codes above the depth's maximum are
    /// full white): the exact inverse of the transfer, so
    /// `sample(code(s))` is `s` up to the rounding of the code for `s` in `[0, white]`.
    pub fn sample(&self, code: u16) -> f32 {
        (srgb_decode(f64::from(code) / f64::from(self.bits.max_code())) * f64::from(self.white)) as f32
    }
}

/// sRGB encoding of a linear value, clamped to [0, 1] first (IEC 61966-2-1:
/// `12.92·x` up to 0.0031308, else `1.055·x^(1/2.4) − 0.055`). The reference:
/// f64, no table.
pub fn srgb_encode(linear: f64) -> f64 {
    let x = linear.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB decoding of an encoded value, clamped to [0, 1] first (IEC
/// 61966-2-1: `x/12.92` up to 0.04045, else `((x + 0.055)/1.055)^2.4`), the
/// inverse of [`srgb_encode`]. The reference: f64, no table.
pub fn srgb_decode(encoded: f64) -> f64 {
    let x = encoded.clamp(0.0, 1.0);
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

/// [`srgb_decode`] in f32 for an encoded value in [0, 1], for decoding
/// texture texels in bulk (within 1e-6 of the reference).
#[inline]
pub(crate) fn srgb_decode_f32(encoded: f32) -> f32 {
    if encoded <= 0.04045 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// Components of a PNG pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Colour {
    /// One grey component.
    Grey,
    /// Red, green, blue.
    Rgb,
}

impl Colour {
    fn components(self) -> usize {
        match self {
            Colour::Grey => 1,
            Colour::Rgb => 3,
        }
    }
}

/// PNG samples already quantized, row by row from the top, the components
/// of each pixel together.
#[derive(Clone, Copy, Debug)]
pub enum Samples<'a> {
    /// 8-bit codes.
    Eight(&'a [u8]),
    /// 16-bit codes.
    Sixteen(&'a [u16]),
}

/// What a PNG says of its pixels besides their codes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PngTags {
    /// The codes are sRGB-encoded: an `sRGB` chunk (perceptual intent).
    pub srgb: bool,
    /// Each pixel's width and height on the display, metres: a `pHYs`
    /// chunk in pixels per metre.
    pub pixel_size_m: Option<[f64; 2]>,
}

/// A `width × height` PNG of `colour` holding `samples` as they are (no tone
/// mapping), default compression, tagged as `tags` say.
pub fn encode_png_samples(
    width: usize,
    height: usize,
    colour: Colour,
    samples: Samples<'_>,
    tags: PngTags,
) -> Result<Vec<u8>> {
    encode_frames(width, height, colour, &[samples], None, tags)
}

/// The frames of an animated PNG: how many, how long each is shown, and
/// how often the animation plays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Animation {
    /// Frames.
    pub frames: usize,
    /// Seconds each frame is shown (stored as a fraction: milliseconds over 1000).
    pub frame_seconds: f64,
    /// Times the animation plays; 0 is forever.
    pub plays: u32,
}

/// An animated PNG (APNG): `animation.frames` frames of `width × height` pixels, each
/// tone-mapped by `tone` from `pixel(frame, x, y)`'s linear samples as
/// [`encode_png`] does one picture. The first frame is also the still
/// picture viewers without APNG support show.
pub fn encode_apng(
    width: usize,
    height: usize,
    colour: Colour,
    tone: &Tone,
    pixel_size_m: Option<[f64; 2]>,
    animation: Animation,
    pixel: impl Fn(usize, usize, usize) -> [f32; 3] + Sync,
) -> Result<Vec<u8>> {
    png_size(width, height)?;
    let frames = animation.frames;
    if frames == 0 {
        return Err(Error::argument("picture", "an animated PNG needs at least one frame"));
    }
    let codes: Vec<Vec<u16>> =
        (0..frames).map(|k| tone_codes(width, height, colour, tone, |x, y| pixel(k, x, y))).collect();
    let tags = PngTags { srgb: true, pixel_size_m };
    let bytes: Vec<Vec<u8>> = match tone.bits() {
        Bits::Eight => codes.iter().map(|c| to_bytes(c)).collect(),
        Bits::Sixteen => Vec::new(),
    };
    let samples: Vec<Samples<'_>> = match tone.bits() {
        Bits::Sixteen => codes.iter().map(|c| Samples::Sixteen(c)).collect(),
        Bits::Eight => bytes.iter().map(|b| Samples::Eight(b)).collect(),
    };
    encode_frames(width, height, colour, &samples, Some(animation), tags)
}

/// One PNG of one or (with `animation`) several frames of samples.
fn encode_frames(
    width: usize,
    height: usize,
    colour: Colour,
    frames: &[Samples<'_>],
    animation: Option<Animation>,
    tags: PngTags,
) -> Result<Vec<u8>> {
    let (w, h) = png_size(width, height)?;
    let n = width * height * colour.components();
    let mut depth = png::BitDepth::Eight;
    let mut data: Vec<std::borrow::Cow<'_, [u8]>> = Vec::with_capacity(frames.len());
    for samples in frames {
        let length = match samples {
            Samples::Eight(s) => s.len(),
            Samples::Sixteen(s) => s.len(),
        };
        if length != n {
            return Err(Error::argument(
                "picture",
                format!("a {width}×{height} {colour:?} picture has {n} samples, not the {length} given"),
            ));
        }
        data.push(match samples {
            Samples::Eight(s) => std::borrow::Cow::Borrowed(*s),
            Samples::Sixteen(s) => {
                // PNG stores 16-bit samples most significant byte first.
                depth = png::BitDepth::Sixteen;
                std::borrow::Cow::Owned(s.iter().flat_map(|c| c.to_be_bytes()).collect())
            }
        });
    }
    let failed =
        |e: png::EncodingError| Error::argument("picture", format!("cannot encode a {width}×{height} PNG: {e}"));
    let mut png = Vec::new();
    let mut encoder = png::Encoder::new(&mut png, w, h);
    encoder.set_color(if colour == Colour::Grey { png::ColorType::Grayscale } else { png::ColorType::Rgb });
    encoder.set_depth(depth);
    if tags.srgb {
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    }
    if let Some([x_m, y_m]) = tags.pixel_size_m {
        let per_metre = |size_m: f64| (1.0 / size_m).round().clamp(1.0, f64::from(u32::MAX)) as u32;
        encoder.set_pixel_dims(Some(png::PixelDimensions {
            xppu: per_metre(x_m),
            yppu: per_metre(y_m),
            unit: png::Unit::Meter,
        }));
    }
    if let Some(a) = animation {
        let frames = u32::try_from(data.len()).map_err(|_| Error::argument("picture", "too many frames"))?;
        encoder.set_animated(frames, a.plays).map_err(failed)?;
        // Milliseconds: the delay is a u16 fraction of a second.
        let ms = (a.frame_seconds * 1000.0).round().clamp(1.0, f64::from(u16::MAX)) as u16;
        encoder.set_frame_delay(ms, 1000).map_err(failed)?;
    }
    let mut writer = encoder.write_header().map_err(failed)?;
    for bytes in &data {
        writer.write_image_data(bytes).map_err(failed)?;
    }
    writer.finish().map_err(failed)?;
    Ok(png)
}

/// Codes of 8-bit depth as bytes (each is at most 255 there).
fn to_bytes(codes: &[u16]) -> Vec<u8> {
    codes.iter().map(|&c| c as u8).collect()
}

/// The codes of a `width × height` picture of `colour`, tone-mapped by
/// `tone` from `pixel(x, y)`'s linear samples, row by row from the top.
fn tone_codes(
    width: usize,
    height: usize,
    colour: Colour,
    tone: &Tone,
    pixel: impl Fn(usize, usize) -> [f32; 3] + Sync,
) -> Vec<u16> {
    let components = colour.components();
    let row = |y: usize, out: &mut [u16]| {
        for (x, codes) in out.chunks_exact_mut(components).enumerate() {
            let p = pixel(x, y);
            for (code, &sample) in codes.iter_mut().zip(&p) {
                *code = tone.code(sample);
            }
        }
    };
    let mut codes = vec![0u16; width * height * components];
    codes.par_chunks_mut(width * components).enumerate().for_each(|(y, out)| row(y, out));
    codes
}

/// A `width × height` PNG of `colour` tone-mapped by `tone`: `pixel(x, y)`
/// gives the linear samples of column `x`, row `y` from the top (a grey
/// picture uses the first; a colour the picture lacks is 0, black). Tagged
/// sRGB, and with each pixel's physical size where given.
pub fn encode_png(
    width: usize,
    height: usize,
    colour: Colour,
    tone: &Tone,
    pixel_size_m: Option<[f64; 2]>,
    pixel: impl Fn(usize, usize) -> [f32; 3] + Sync,
) -> Result<Vec<u8>> {
    png_size(width, height)?;
    let codes = tone_codes(width, height, colour, tone, pixel);
    let tags = PngTags { srgb: true, pixel_size_m };
    match tone.bits() {
        Bits::Sixteen => encode_png_samples(width, height, colour, Samples::Sixteen(&codes), tags),
        Bits::Eight => encode_png_samples(width, height, colour, Samples::Eight(&to_bytes(&codes)), tags),
    }
}

/// The PNG's width and height as its header stores them.
fn png_size(width: usize, height: usize) -> Result<(u32, u32)> {
    // PNG allows 1 to 2³¹ − 1 pixels a side; at most 6 bytes a pixel must fit in memory.
    let side = |n: usize| u32::try_from(n).ok().filter(|&n| n > 0 && n < 1 << 31);
    let (Some(w), Some(h)) = (side(width), side(height)) else {
        return Err(Error::argument(
            "picture size",
            format!("a {width}×{height} picture cannot be a PNG: each side must be 1 to 2³¹ − 1"),
        ));
    };
    if width.checked_mul(height).and_then(|n| n.checked_mul(6)).map_or(true, |n| n > isize::MAX as usize) {
        return Err(Error::argument("picture size", format!("a {width}×{height} picture does not fit in memory")));
    }
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn srgb_round_trips_and_meets_its_ends() {
        for i in 0..=1000 {
            let x = i as f64 / 1000.0;
            assert!((srgb_decode(srgb_encode(x)) - x).abs() < 1e-12);
        }
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-15);
        assert_eq!(srgb_encode(0.0), 0.0);
        assert_eq!(srgb_encode(-3.0), 0.0);
        assert!((srgb_encode(7.0) - 1.0).abs() < 1e-15);
        // The two pieces meet at the breakpoints (within the standard's rounding of them).
        assert!((srgb_encode(0.003_130_8) - 0.040_45).abs() < 1e-6);
        assert!((srgb_decode(0.040_45) - 0.003_130_8).abs() < 1e-6);
    }

    #[test]
    fn the_f32_decoding_follows_the_reference() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        // Random values, a quarter of them below the breakpoint region, and every 8-bit code.
        let random = (0..200_000).map(|i| if i % 4 == 0 { rng.gen_range(0.0..0.05) } else { rng.gen_range(0.0..=1.0) });
        let codes = (0..=255).map(|q| q as f32 / 255.0);
        let error = |x: f32| (f64::from(srgb_decode_f32(x)) - srgb_decode(f64::from(x))).abs();
        let worst = random.chain(codes).map(error).fold(0f64, f64::max);
        assert!(worst < 1e-6, "worst {worst}");
    }

    #[test]
    fn codes_are_the_rounded_transfer() {
        let eight = Tone::unit(Bits::Eight);
        let sixteen = Tone::unit(Bits::Sixteen);
        for (sample, code8, code16) in [(0.18, 118, 30235), (0.5, 188, 48192), (0.002, 7, 1693), (1.0, 255, 65535)] {
            assert_eq!((eight.code(sample), sixteen.code(sample)), (code8, code16), "{sample}");
        }
        // Clamped at both ends; NaN is black.
        for (sample, code) in [(2.0, 255), (f32::INFINITY, 255), (-0.5, 0), (f32::NEG_INFINITY, 0), (f32::NAN, 0)] {
            assert_eq!(eight.code(sample), code, "{sample}");
        }
        // White scales: 0.3 at white 0.6 is 0.5 at white 1.
        assert_eq!(Tone::new(0.6, Bits::Eight).unwrap().code(0.3), 188);
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let err = Tone::new(bad, Bits::Eight).unwrap_err().to_string();
            assert!(err.contains("white level"), "{err}");
        }
    }

    #[test]
    fn export_then_import_is_within_half_a_step() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
        for bits in [Bits::Eight, Bits::Sixteen] {
            let step = 1.0 / f64::from(bits.max_code());
            for white in [1.0f32, 0.37, 5.5, 1e-3] {
                let tone = Tone::new(white, bits).unwrap();
                for _ in 0..20_000 {
                    let s = rng.gen_range(0.0..=white);
                    let back = tone.sample(tone.code(s));
                    // In the encoded domain: at most half a code step, and the f32 result's own rounding.
                    let e = |x: f32| srgb_encode(f64::from(x) / f64::from(white));
                    assert!((e(back) - e(s)).abs() <= step / 2.0 + 1e-6, "{bits:?} white {white}: {s} -> {back}");
                }
                // Every code comes back to itself.
                for code in (0..=bits.max_code()).step_by(37) {
                    assert_eq!(tone.code(tone.sample(code)), code, "{bits:?} white {white}");
                }
            }
        }
    }

    #[test]
    fn white_levels() {
        let ramp: Vec<f32> = (0..1000).map(|i| i as f32).collect();
        assert_eq!(White::Auto.level(ramp.iter().copied()), 998.0);
        assert_eq!(White::Max.level(ramp.iter().copied()), 999.0);
        assert_eq!(White::Value(0.25).level(ramp.iter().copied()), 0.25);
        // Two glints above a scene up to 0.99: auto ignores them, max follows them.
        let glints: Vec<f32> =
            (0..10_000).map(|i| if i % 5000 == 7 { 40.0 } else { (i % 100) as f32 / 100.0 }).collect();
        assert_eq!(White::Auto.level(glints.iter().copied()), 0.99);
        assert_eq!(White::Max.level(glints.iter().copied()), 40.0);
        // Not finite: ignored. Nothing positive: the largest, else 1.
        let odd = [f32::NAN, f32::INFINITY, 0.5, f32::NEG_INFINITY];
        assert_eq!(White::Auto.level(odd), 0.5);
        assert_eq!(White::Max.level(odd), 0.5);
        let mostly_black: Vec<f32> = (0..10_000).map(|i| if i == 3 { 0.2 } else { 0.0 }).collect();
        assert_eq!(White::Auto.level(mostly_black.iter().copied()), 0.2);
        for nothing in [vec![], vec![0.0; 5], vec![-1.0, f32::NAN]] {
            assert_eq!(White::Auto.level(nothing.iter().copied()), 1.0);
            assert_eq!(White::Max.level(nothing.iter().copied()), 1.0);
        }
    }

    #[test]
    fn white_parses_auto_max_or_a_positive_number() {
        for (text, white) in
            [("auto", White::Auto), ("MAX", White::Max), ("0.5", White::Value(0.5)), (" 2 ", White::Value(2.0))]
        {
            assert_eq!(text.parse::<White>(), Ok(white));
            assert_eq!(white.to_string().parse::<White>(), Ok(white));
        }
        for bad in ["0", "-1", "nan", "inf", "bright", ""] {
            let err = bad.parse::<White>().unwrap_err().to_string();
            assert!(err.contains("auto, max or a finite positive number"), "{err}");
        }
        assert_eq!(White::default(), White::Auto);
    }

    #[test]
    fn pngs_hold_the_codes() {
        let (w, h) = (5, 3);
        let value = |x: usize, y: usize| [x as f32 / 4.0, y as f32 / 2.0, 0.3];
        for (colour, bits) in [(Colour::Grey, Bits::Eight), (Colour::Rgb, Bits::Eight), (Colour::Rgb, Bits::Sixteen)] {
            let tone = Tone::new(0.9, bits).unwrap();
            let png = encode_png(w, h, colour, &tone, None, value).unwrap();
            let img = decode::decode(std::io::Cursor::new(&png)).unwrap();
            let channels = colour.components();
            assert_eq!((img.width, img.height, img.channels, img.bits()), (5, 3, channels, bits));
            let img = img.rgb16();
            for y in 0..h {
                for x in 0..w {
                    let got = [0, 1, 2].map(|c| img[3 * (y * w + x) + c]);
                    let scale = 65535 / bits.max_code();
                    let v = value(x, y);
                    let want = match colour {
                        Colour::Grey => [tone.code(v[0]); 3],
                        Colour::Rgb => v.map(|s| tone.code(s)),
                    };
                    assert_eq!(got, want.map(|c| c * scale), "{colour:?} {bits:?} ({x}, {y})");
                }
            }
        }
        let err = encode_png(0, 3, Colour::Grey, &Tone::unit(Bits::Eight), None, value).unwrap_err().to_string();
        assert!(err.contains("0×3"), "{err}");
        let err =
            encode_png_samples(2, 2, Colour::Rgb, Samples::Eight(&[0; 4]), PngTags::default()).unwrap_err().to_string();
        assert!(err.contains("12 samples"), "{err}");
    }

    #[test]
    fn animated_pngs_hold_every_frame() {
        let (w, h, frames) = (4, 3, 5);
        let value = |k: usize, x: usize, y: usize| [(k * 10 + x + y) as f32 / 60.0; 3];
        let tone = Tone::unit(Bits::Eight);
        let animation = Animation { frames, frame_seconds: 0.25, plays: 0 };
        let apng = encode_apng(w, h, Colour::Grey, &tone, Some([2e-4, 1e-4]), animation, value).unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(&apng)).read_info().unwrap();
        let control = reader.info().animation_control.expect("an acTL chunk");
        assert_eq!((control.num_frames, control.num_plays), (5, 0));
        let dims = reader.info().pixel_dims.expect("a pHYs chunk");
        assert_eq!((dims.xppu, dims.yppu), (5000, 10000));
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        for k in 0..frames {
            reader.next_frame(&mut buf).unwrap();
            let fc = reader.info().frame_control.expect("an fcTL chunk");
            assert_eq!((fc.delay_num, fc.delay_den), (250, 1000));
            for y in 0..h {
                for x in 0..w {
                    assert_eq!(u16::from(buf[y * w + x]), tone.code(value(k, x, y)[0]), "frame {k} ({x}, {y})");
                }
            }
        }
        assert!(reader.next_frame(&mut buf).is_err(), "no sixth frame");
        let none = Animation { frames: 0, ..animation };
        let err = encode_apng(w, h, Colour::Grey, &tone, None, none, value).unwrap_err().to_string();
        assert!(err.contains("at least one frame"), "{err}");
    }
}
