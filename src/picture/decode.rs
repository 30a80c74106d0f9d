//! Pictures read back: PNG and JPEG decoded to their codes, and the pixel
//! conversions their readers need (to RGB, RGBA or grey, at 8 or 16 bits or
//! as f32 fractions).
//!
//! The format is found from the first bytes, whatever the file is called:
//! the PNG signature `89 50 4E 47 0D 0A 1A 0A` (PNG specification, 5.2), or
//! a JPEG's start-of-image marker `FF D8` followed by the `FF` of its next
//! marker (ITU-T T.81, B.1.1.3).
//!
//! A PNG is decoded by the `png` crate to 8 or 16 bits a sample: a palette
//! becomes RGB, a `tRNS` chunk an alpha channel, grey of 1, 2 or 4 bits is
//! scaled to 8 (its `EXPAND` transformation); 16-bit samples stay 16-bit.
//! A JPEG is decoded by `zune-jpeg`, leniently (not strict: camera files
//! often break the standard in ways that do not matter) and with no size
//! limit but JPEG's own 65535: grey stays grey, every other colour space
//! (YCbCr, CMYK, YCCK) becomes RGB.
//!
//! These are the settings and conversions of the `image` crate (0.25),
//! which decoded holo's pictures before: camera captures, textures and the
//! pictures tests compare give the very same samples.

use std::fmt;
use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use zune_jpeg::zune_core::bytestream::ZCursor;
use zune_jpeg::zune_core::colorspace::ColorSpace;
use zune_jpeg::zune_core::options::DecoderOptions;

use super::{Bits, Samples};
use crate::signature::{JPEG as JPEG_SIGNATURE, PNG as PNG_SIGNATURE};

/// The most bytes a decoded picture (or a PNG's chunks besides its pixels)
/// may take, 512 MiB: a damaged or hostile header cannot make the reader
/// allocate more. It is the limit `image` had; a 16-bit RGB picture of
/// 44 megapixels fits.
pub const MAX_DECODED_BYTES: usize = 512 << 20;

/// The formats pictures are read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// PNG.
    Png,
    /// JPEG (JFIF, Exif or bare).
    Jpeg,
}

impl Format {
    /// The format whose signature `start` (a file's first bytes) begins with.
    pub fn of(start: &[u8]) -> Option<Format> {
        if start.starts_with(&PNG_SIGNATURE) {
            Some(Format::Png)
        } else if start.starts_with(&JPEG_SIGNATURE) {
            Some(Format::Jpeg)
        } else {
            None
        }
    }
}

/// Why a picture could not be read.
#[derive(Debug)]
pub enum DecodeError {
    /// Its first bytes are neither the PNG nor the JPEG signature.
    NotPngOrJpeg,
    /// Reading the bytes failed.
    Io(std::io::Error),
    /// The bytes are damaged, of a kind not decoded, or too large.
    Invalid(String),
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DecodeError::NotPngOrJpeg => f.write_str("not a PNG or JPEG image"),
            DecodeError::Io(e) => write!(f, "{e}"),
            DecodeError::Invalid(problem) => f.write_str(problem),
        }
    }
}

impl std::error::Error for DecodeError {}

impl From<std::io::Error> for DecodeError {
    fn from(e: std::io::Error) -> DecodeError {
        DecodeError::Io(e)
    }
}

/// A decoded picture: `width × height` pixels of `channels` samples each
/// (1 grey, 2 grey and alpha, 3 RGB, 4 RGBA), row by row from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Decoded {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Samples a pixel: 1 to 4.
    pub channels: usize,
    codes: Codes,
}

#[derive(Clone, Debug, PartialEq)]
enum Codes {
    Eight(Vec<u8>),
    Sixteen(Vec<u16>),
}

/// Width and height of a PNG or JPEG, from its header: a PNG is read up to
/// its first image data, a JPEG up to its frame header.
pub fn dimensions(mut reader: impl BufRead + Seek) -> Result<(usize, usize), DecodeError> {
    match sniff(&mut reader)? {
        Some(Format::Png) => {
            let (w, h) = png_reader(reader)?.info().size();
            Ok((w as usize, h as usize))
        }
        Some(Format::Jpeg) => {
            let (w, h, _) = jpeg_header(&read_all(reader)?)?;
            Ok((w, h))
        }
        None => Err(DecodeError::NotPngOrJpeg),
    }
}

/// Decode a PNG or JPEG, whichever its first bytes say it is.
pub fn decode(mut reader: impl BufRead + Seek) -> Result<Decoded, DecodeError> {
    match sniff(&mut reader)? {
        Some(Format::Png) => decode_png(reader),
        Some(Format::Jpeg) => decode_jpeg(&read_all(reader)?),
        None => Err(DecodeError::NotPngOrJpeg),
    }
}

/// Decode the PNG or JPEG file at `path`, whichever its first bytes say.
pub fn open(path: &Path) -> Result<Decoded, DecodeError> {
    decode(BufReader::new(File::open(path)?))
}

/// Decode a PNG (anything else is refused: the PNG decoder checks the
/// signature).
pub fn decode_png(reader: impl BufRead + Seek) -> Result<Decoded, DecodeError> {
    let mut reader = png_reader(reader)?;
    let (colour, depth) = reader.output_color_type();
    let bytes_per_sample = match depth {
        png::BitDepth::Eight => 1,
        png::BitDepth::Sixteen => 2,
        // EXPAND widens every depth below 8.
        other => return Err(DecodeError::Invalid(format!("PNG samples of {other:?} bits were not expanded"))),
    };
    let (w, h) = reader.info().size();
    let (width, height, channels) = (w as usize, h as usize, colour.samples());
    reserve(width, height, channels * bytes_per_sample)?;
    let length = reader.output_buffer_size().ok_or_else(|| too_large(u64::MAX))?;
    let mut bytes = vec![0; length];
    reader.next_frame(&mut bytes).map_err(png_error)?;
    bytes.truncate(width * height * channels * bytes_per_sample);
    let codes = match bytes_per_sample {
        1 => Codes::Eight(bytes),
        // PNG stores 16-bit samples most significant byte first.
        _ => Codes::Sixteen(bytes.chunks_exact(2).map(|b| u16::from_be_bytes([b[0], b[1]])).collect()),
    };
    Ok(Decoded { width, height, channels, codes })
}

/// A PNG reader past the header chunks, set to expand to 8 or 16 bits.
fn png_reader<R: BufRead + Seek>(reader: R) -> Result<png::Reader<R>, DecodeError> {
    let mut decoder = png::Decoder::new_with_limits(reader, png::Limits { bytes: MAX_DECODED_BYTES });
    decoder.set_transformations(png::Transformations::EXPAND);
    decoder.read_info().map_err(png_error)
}

fn png_error(e: png::DecodingError) -> DecodeError {
    match e {
        png::DecodingError::IoError(e) => DecodeError::Io(e),
        e => DecodeError::Invalid(format!("PNG: {e}")),
    }
}

/// Lenient decoding (not strict), and no size limit but the format's.
fn jpeg_options() -> DecoderOptions {
    DecoderOptions::default().set_strict_mode(false).set_max_width(usize::MAX).set_max_height(usize::MAX)
}

/// Width, height and colour space of a JPEG, from its headers.
fn jpeg_header(bytes: &[u8]) -> Result<(usize, usize, ColorSpace), DecodeError> {
    let mut decoder = zune_jpeg::JpegDecoder::new_with_options(ZCursor::new(bytes), jpeg_options());
    decoder.decode_headers().map_err(jpeg_error)?;
    let dimensions = decoder.dimensions();
    let colour = decoder.input_colorspace();
    let ((w, h), colour) =
        dimensions.zip(colour).ok_or_else(|| DecodeError::Invalid("JPEG: no frame header".into()))?;
    Ok((w, h, colour))
}

fn decode_jpeg(bytes: &[u8]) -> Result<Decoded, DecodeError> {
    let (width, height, stored) = jpeg_header(bytes)?;
    // Grey and RGB (with or without alpha) as they are; YCbCr, CMYK and
    // YCCK converted to RGB by the decoder.
    let colour = match stored {
        ColorSpace::Luma | ColorSpace::LumaA | ColorSpace::RGB | ColorSpace::RGBA => stored,
        _ => ColorSpace::RGB,
    };
    let channels = colour.num_components();
    reserve(width, height, channels)?;
    let options = jpeg_options().jpeg_set_out_colorspace(colour);
    let codes = zune_jpeg::JpegDecoder::new_with_options(ZCursor::new(bytes), options).decode().map_err(jpeg_error)?;
    if codes.len() != width * height * channels {
        return Err(DecodeError::Invalid(format!(
            "JPEG: {} samples decoded, a {width}×{height} picture of {channels} channels has {}",
            codes.len(),
            width * height * channels
        )));
    }
    Ok(Decoded { width, height, channels, codes: Codes::Eight(codes) })
}

fn jpeg_error(e: zune_jpeg::errors::DecodeErrors) -> DecodeError {
    DecodeError::Invalid(format!("JPEG: {e}"))
}

/// Refuse a picture whose samples would take more than [`MAX_DECODED_BYTES`].
fn reserve(width: usize, height: usize, bytes_per_pixel: usize) -> Result<(), DecodeError> {
    let bytes = (width as u64).saturating_mul(height as u64).saturating_mul(bytes_per_pixel as u64);
    if bytes > MAX_DECODED_BYTES as u64 {
        return Err(too_large(bytes));
    }
    Ok(())
}

fn too_large(bytes: u64) -> DecodeError {
    DecodeError::Invalid(format!("its samples take {bytes} bytes, more than the {MAX_DECODED_BYTES} allowed"))
}

/// The format the first bytes say, the reader put back where it was.
fn sniff(reader: &mut (impl BufRead + Seek)) -> Result<Option<Format>, DecodeError> {
    let at = reader.stream_position()?;
    let mut start = Vec::with_capacity(PNG_SIGNATURE.len());
    reader.by_ref().take(PNG_SIGNATURE.len() as u64).read_to_end(&mut start)?;
    reader.seek(SeekFrom::Start(at))?;
    Ok(Format::of(&start))
}

fn read_all(mut reader: impl Read) -> Result<Vec<u8>, DecodeError> {
    let mut bytes = Vec::new();
    reader.read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// The weights of red, green and blue in grey read from a colour picture
/// (applied to the fractions of the codes as they are, sRGB-encoded): the Y
/// row of the RGB → XYZ matrix of the BT.709 primaries and D65 white (ITU-T
/// H.273, equations 39 and 40) as `image` 0.25's colour library worked it
/// out in f32. Kept to the bit, so grey from colour has the codes it always
/// had; 0.2126, 0.7152 and 0.0722 would differ in the last bits.
const LUMINANCE: [f32; 3] = [0.212_647_84, 0.715_179_2, 0.072_173_04];

impl Decoded {
    /// Bits a sample: 8 (every JPEG, PNGs of 8 bits or fewer) or 16.
    pub fn bits(&self) -> Bits {
        match self.codes {
            Codes::Eight(_) => Bits::Eight,
            Codes::Sixteen(_) => Bits::Sixteen,
        }
    }

    /// The samples as decoded.
    pub fn samples(&self) -> Samples<'_> {
        match &self.codes {
            Codes::Eight(codes) => Samples::Eight(codes),
            Codes::Sixteen(codes) => Samples::Sixteen(codes),
        }
    }

    /// 8-bit RGB, 3 samples a pixel.
    pub fn rgb8(&self) -> Vec<u8> {
        self.convert(3)
    }

    /// 8-bit RGBA, 4 samples a pixel.
    pub fn rgba8(&self) -> Vec<u8> {
        self.convert(4)
    }

    /// 8-bit grey, 1 sample a pixel.
    pub fn grey8(&self) -> Vec<u8> {
        self.convert(1)
    }

    /// 16-bit RGB, 3 samples a pixel.
    pub fn rgb16(&self) -> Vec<u16> {
        self.convert(3)
    }

    /// 16-bit grey, 1 sample a pixel.
    pub fn grey16(&self) -> Vec<u16> {
        self.convert(1)
    }

    /// RGBA as fractions of full scale, 4 samples a pixel.
    pub fn rgba_f32(&self) -> Vec<f32> {
        self.convert(4)
    }

    fn convert<T: Sample>(&self, channels: usize) -> Vec<T> {
        match &self.codes {
            Codes::Eight(codes) => convert(codes, self.channels, channels),
            Codes::Sixteen(codes) => convert(codes, self.channels, channels),
        }
    }
}

/// Pixels of `from` channels as pixels of `to` channels (1 to 4 each).
///
/// Between layouts of the same kind (grey and grey with alpha, RGB and
/// RGBA) each sample is converted on its own ([`Code::to`]), and a missing
/// alpha is opaque. Between grey and colour the samples go through f32
/// fractions of full scale ([`Code::fraction`]): grey is copied to red,
/// green and blue; colour becomes its luminance ([`LUMINANCE`]); then each
/// is rounded to the nearest code ([`Sample::from_fraction`]).
fn convert<C: Code, T: Sample>(codes: &[C], from: usize, to: usize) -> Vec<T> {
    let colour = |n: usize| n >= 3;
    let alpha = |n: usize| n == 2 || n == 4;
    let mut out = Vec::with_capacity(codes.len() / from * to);
    for p in codes.chunks_exact(from) {
        if colour(from) == colour(to) {
            let kinds = if colour(to) { 3 } else { 1 };
            out.extend(p[..kinds].iter().map(|&q| q.to::<T>()));
            if alpha(to) {
                out.push(if alpha(from) { p[from - 1].to() } else { T::OPAQUE });
            }
        } else {
            if colour(from) {
                let [r, g, b] = [p[0], p[1], p[2]].map(Code::fraction);
                out.push(T::from_fraction(r * LUMINANCE[0] + g * LUMINANCE[1] + b * LUMINANCE[2]));
            } else {
                let grey = T::from_fraction(p[0].fraction());
                out.extend([grey; 3]);
            }
            if alpha(to) {
                out.push(T::from_fraction(if alpha(from) { p[from - 1].fraction() } else { 1.0 }));
            }
        }
    }
    out
}

/// A decoded code: 8 or 16 bits.
trait Code: Copy {
    /// The code as a fraction of full scale: `q · (1/max)` in f32, the
    /// reciprocal rounded first (which is not always `q / max` in f32).
    fn fraction(self) -> f32;

    /// The code as a sample of another type ([`Sample::from_u8`],
    /// [`Sample::from_u16`]).
    fn to<T: Sample>(self) -> T;
}

impl Code for u8 {
    fn fraction(self) -> f32 {
        f32::from(self) * (1.0 / 255.0)
    }

    fn to<T: Sample>(self) -> T {
        T::from_u8(self)
    }
}

impl Code for u16 {
    fn fraction(self) -> f32 {
        f32::from(self) * (1.0 / 65535.0)
    }

    fn to<T: Sample>(self) -> T {
        T::from_u16(self)
    }
}

/// A sample type pictures are converted to.
trait Sample: Copy {
    /// Full scale: alpha where the picture has none.
    const OPAQUE: Self;

    /// An 8-bit code: itself, `257·q` at 16 bits (the same fraction of
    /// full scale), `q / 255` as a fraction.
    fn from_u8(q: u8) -> Self;

    /// A 16-bit code: the nearest 8-bit code, itself, `q / 65535` as a
    /// fraction.
    fn from_u16(q: u16) -> Self;

    /// The nearest code to a fraction of full scale, clamped to the codes
    /// (NaN is 0); the fraction itself in f32.
    fn from_fraction(x: f32) -> Self;
}

impl Sample for u8 {
    const OPAQUE: u8 = u8::MAX;

    fn from_u8(q: u8) -> u8 {
        q
    }

    fn from_u16(q: u16) -> u8 {
        // round(q · 255 / 65535) exactly, in integers.
        ((u32::from(q) + 128) / 257) as u8
    }

    fn from_fraction(x: f32) -> u8 {
        (x * 255.0).round() as u8
    }
}

impl Sample for u16 {
    const OPAQUE: u16 = u16::MAX;

    fn from_u8(q: u8) -> u16 {
        u16::from(q) * 257
    }

    fn from_u16(q: u16) -> u16 {
        q
    }

    fn from_fraction(x: f32) -> u16 {
        (x * 65535.0).round() as u16
    }
}

impl Sample for f32 {
    const OPAQUE: f32 = 1.0;

    fn from_u8(q: u8) -> f32 {
        f32::from(q) / 255.0
    }

    fn from_u16(q: u16) -> f32 {
        f32::from(q) / 65535.0
    }

    fn from_fraction(x: f32) -> f32 {
        x
    }
}

#[cfg(test)]
mod tests {
    use std::io::Cursor;

    use super::*;

    fn eight(width: usize, channels: usize, codes: &[u8]) -> Decoded {
        Decoded { width, height: 1, channels, codes: Codes::Eight(codes.to_vec()) }
    }

    fn sixteen(width: usize, channels: usize, codes: &[u16]) -> Decoded {
        Decoded { width, height: 1, channels, codes: Codes::Sixteen(codes.to_vec()) }
    }

    #[test]
    fn the_format_is_in_the_first_bytes() {
        assert_eq!(Format::of(b"\x89PNG\r\n\x1a\nrest"), Some(Format::Png));
        assert_eq!(Format::of(&[0xFF, 0xD8, 0xFF, 0xE0]), Some(Format::Jpeg));
        assert_eq!(Format::of(&[0xFF, 0xD8]), None);
        assert_eq!(Format::of(b"GIF89a"), None);
        let e = decode(Cursor::new(b"not a png at all")).unwrap_err();
        assert!(matches!(e, DecodeError::NotPngOrJpeg) && e.to_string() == "not a PNG or JPEG image");
        assert!(matches!(dimensions(Cursor::new(b"")), Err(DecodeError::NotPngOrJpeg)));
    }

    #[test]
    fn pngs_decode_to_their_codes_and_the_header_gives_the_size() {
        // 16-bit grey and alpha, 2 × 1: big-endian in the file.
        let mut png = Vec::new();
        let mut encoder = png::Encoder::new(&mut png, 2, 1);
        encoder.set_color(png::ColorType::GrayscaleAlpha);
        encoder.set_depth(png::BitDepth::Sixteen);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&[0x01, 0x02, 0xFF, 0xFF, 0x80, 0x00, 0x00, 0x03]).unwrap();
        writer.finish().unwrap();
        assert_eq!(dimensions(Cursor::new(&png)).unwrap(), (2, 1));
        let d = decode(Cursor::new(&png)).unwrap();
        assert_eq!((d.width, d.height, d.channels, d.bits()), (2, 1, 2, Bits::Sixteen));
        assert_eq!(d.codes, Codes::Sixteen(vec![0x0102, 0xFFFF, 0x8000, 0x0003]));
        // Truncated: refused, by the decoder and by the header reader alike.
        let e = decode(Cursor::new(&png[..png.len() - 20])).unwrap_err();
        assert!(!matches!(e, DecodeError::NotPngOrJpeg), "{e}");
        assert!(dimensions(Cursor::new(&png[..20])).is_err());
    }

    #[test]
    fn layouts_of_the_same_kind_convert_sample_by_sample() {
        // 8 → 16 bits is q·257; 16 → 8 rounds to nearest; a missing alpha is opaque.
        let rgb16 = sixteen(1, 3, &[128, 32895, 65535]);
        assert_eq!(rgb16.rgb8(), [0, 128, 255]);
        assert_eq!(eight(1, 3, &[1, 2, 255]).rgb16(), [257, 514, 65535]);
        assert_eq!(eight(1, 3, &[1, 2, 3]).rgba8(), [1, 2, 3, 255]);
        assert_eq!(eight(1, 4, &[1, 2, 3, 4]).rgb8(), [1, 2, 3]);
        assert_eq!(eight(1, 2, &[7, 9]).grey16(), [7 * 257]);
        // To f32: q / max.
        assert_eq!(sixteen(1, 3, &[257, 0, 65535]).rgba_f32(), [257.0 / 65535.0, 0.0, 1.0, 1.0]);
    }

    #[test]
    fn grey_and_colour_convert_through_fractions() {
        // Grey is copied to red, green and blue.
        assert_eq!(eight(2, 1, &[3, 200]).rgb16(), [771, 771, 771, 51400, 51400, 51400]);
        assert_eq!(eight(2, 2, &[3, 40, 200, 255]).rgba8(), [3, 3, 3, 40, 200, 200, 200, 255]);
        // Colour becomes its luminance (values image 0.25 gave).
        let colours = eight(4, 3, &[255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 200, 30]);
        assert_eq!(colours.grey8(), [54, 182, 18, 147]);
        assert_eq!(colours.grey16(), [13936, 46869, 4730, 37863]);
        // A grey fraction is q times the rounded reciprocal, which for some
        // codes is not q / max in f32.
        let grey = sixteen(1, 1, &[257]).rgba_f32();
        assert_eq!(grey, [257.0 * (1.0 / 65535.0), 257.0 * (1.0 / 65535.0), 257.0 * (1.0 / 65535.0), 1.0]);
        assert_ne!(grey[0], 257.0 / 65535.0);
        for q in 0..=255u8 {
            assert_eq!(eight(1, 1, &[q]).rgb8(), [q; 3], "every 8-bit grey comes back");
        }
        for q in 0..=u16::MAX {
            assert_eq!(sixteen(1, 1, &[q]).rgb16(), [q; 3], "every 16-bit grey comes back");
        }
    }
}
