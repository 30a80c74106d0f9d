//! The `.holo` file (spec/holo-format.md): an OpenEXR 2 file whose pixel
//! (x, y) is (emitter, hololine), whose channels `v000.R`, `v000.G`, … are the
//! views, and whose `holo.*` attributes carry the geometry.
//!
//! Start reading at [`HoloFile::open`] (lazy reading) and [`write_frames`]
//! (streaming writes); [`read()`] and [`write()`] are the one-call shortcuts.

pub(crate) mod attributes;
mod channels;
pub(crate) mod digest;
pub mod full;
mod header;
mod header_digest;
mod parts;
mod read;
mod record;
pub mod sequence;
mod validate;
mod write;
pub mod zip;

/// Write a small file whole, atomically: [`crate::output::write_bytes_beside`].
pub use crate::output::write_bytes_beside;
pub use attributes::{is_known as is_known_attribute, name as attribute, Attributes, Radiometry, VERSION};
pub use channels::{channel_name, parse_channel_name, view_digits, ChannelOrder};
pub use digest::frame_digest;
pub use header::{FileInfo, FrameInfo, ViewPart};
pub use parts::{FormatVersion, WriteOptions, WriteReport};
pub use read::{read, FrameSample, HoloFile, Region};
pub use record::{Checked, ConversionRecord, RecordHead, RecordReader, RecordWriter};
pub use sequence::{Frames, Sequence};
pub use validate::{validate_format, Validation};
pub use write::{write, write_frame_in_bands, write_frames};

use serde::Serialize;

pub use crate::geometry::MAX_SAMPLES_PER_FRAME;
/// Largest number of EXR channels (views × colours) accepted.
pub const MAX_CHANNELS: u64 = 1 << 16;
/// Largest hololine or emitter count accepted.
pub const MAX_SIDE: u64 = 1 << 20;
/// Largest number of frames (parts) in one file.
pub const MAX_FRAMES: u64 = 1 << 16;

/// A rectangle of pixels: `x` emitters, `y` hololines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Window {
    /// First emitter.
    pub x: usize,
    /// First hololine.
    pub y: usize,
    /// Emitters covered.
    pub width: usize,
    /// Hololines covered.
    pub height: usize,
}

/// How samples are stored on disk.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SampleType {
    /// IEEE 754 binary16 (EXR `HALF`), the default.
    F16,
    /// IEEE 754 binary32 (EXR `FLOAT`).
    F32,
}

impl SampleType {
    /// Bytes per sample.
    pub fn bytes(self) -> usize {
        match self {
            SampleType::F16 => 2,
            SampleType::F32 => 4,
        }
    }
    pub(crate) fn to_exr(self) -> exr::meta::attribute::SampleType {
        match self {
            SampleType::F16 => exr::meta::attribute::SampleType::F16,
            SampleType::F32 => exr::meta::attribute::SampleType::F32,
        }
    }
}

/// EXR compression methods a `.holo` file may use (spec §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Compression {
    /// No compression.
    None,
    /// Run-length encoding (lossless).
    Rle,
    /// Deflate per scan line (lossless).
    Zips,
    /// Deflate per 16 scan lines (lossless), the default.
    Zip,
    /// Wavelet + Huffman (lossless).
    Piz,
    /// Lossy for f32 (rounds to 24 bits), lossless for f16.
    Pxr24,
    /// Lossy 4×4 blocks, f16 only.
    B44,
    /// B44 with flat-area optimisation.
    B44a,
    /// Lossy DCT, 32 scan lines.
    Dwaa,
    /// Lossy DCT, 256 scan lines.
    Dwab,
}

impl Compression {
    /// Every method, in the order the CLI lists them.
    pub const ALL: [Compression; 10] = [
        Compression::None,
        Compression::Rle,
        Compression::Zips,
        Compression::Zip,
        Compression::Piz,
        Compression::Pxr24,
        Compression::B44,
        Compression::B44a,
        Compression::Dwaa,
        Compression::Dwab,
    ];

    /// The name used on the command line and in `info`.
    pub fn name(self) -> &'static str {
        match self {
            Compression::None => "none",
            Compression::Rle => "rle",
            Compression::Zips => "zips",
            Compression::Zip => "zip",
            Compression::Piz => "piz",
            Compression::Pxr24 => "pxr24",
            Compression::B44 => "b44",
            Compression::B44a => "b44a",
            Compression::Dwaa => "dwaa",
            Compression::Dwab => "dwab",
        }
    }

    /// Parse a name from [`Compression::name`].
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.name().eq_ignore_ascii_case(name))
    }

    /// Whether samples of this type come back bit-exact.
    pub fn is_lossless_for(self, sample_type: SampleType) -> bool {
        self.to_exr().is_lossless_for(sample_type.to_exr())
    }

    pub(crate) fn to_exr(self) -> exr::compression::Compression {
        use exr::compression::Compression as E;
        match self {
            Compression::None => E::Uncompressed,
            Compression::Rle => E::RLE,
            Compression::Zips => E::ZIP1,
            Compression::Zip => E::ZIP16,
            Compression::Piz => E::PIZ,
            Compression::Pxr24 => E::PXR24,
            Compression::B44 => E::B44,
            Compression::B44a => E::B44A,
            Compression::Dwaa => E::DWAA(None),
            Compression::Dwab => E::DWAB(None),
        }
    }

    pub(crate) fn from_exr(c: exr::compression::Compression) -> Option<Self> {
        use exr::compression::Compression as E;
        Some(match c {
            E::Uncompressed => Compression::None,
            E::RLE => Compression::Rle,
            E::ZIP1 => Compression::Zips,
            E::ZIP16 => Compression::Zip,
            E::PIZ => Compression::Piz,
            E::PXR24 => Compression::Pxr24,
            E::B44 => Compression::B44,
            E::B44A => Compression::B44a,
            E::DWAA(_) => Compression::Dwaa,
            E::DWAB(_) => Compression::Dwab,
            _ => return None,
        })
    }
}
