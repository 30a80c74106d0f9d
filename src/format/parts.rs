//! What every writer of `.holo` parts shares, horizontal parallax
//! ([`super::write`]) and full ([`super::full`]): the write options and
//! format versions, the checks made before any work, each part's header,
//! a block compressed, and the headers finished (sorted, digests filled in,
//! sealed) once the samples are written.

use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use exr::block::chunk::{Chunk, CompressedBlock, CompressedScanLineBlock};
use exr::block::UncompressedBlock;
use exr::math::Vec2;
use exr::meta::attribute::{ChannelDescription, IntegerBounds, LineOrder, Text};
use exr::meta::header::{Header, LayerAttributes};
use exr::meta::BlockDescription;
use smallvec::SmallVec;

use super::attributes::{self, geometry_attributes, name, Radiometry};
use super::channels::{view_digits, ChannelOrder};
use super::header_digest;
use super::record::ConversionRecord;
use super::{Compression, SampleType, MAX_CHANNELS, MAX_FRAMES, MAX_SIDE};
use crate::error::{Error, Result};
use crate::geometry::Geometry;

/// How to write.
#[derive(Clone, Debug, PartialEq)]
pub struct WriteOptions {
    /// Stored sample type (f16 by default).
    pub sample_type: SampleType,
    /// Compression (ZIP by default).
    pub compression: Compression,
    /// Meaning of the values.
    pub radiometry: Radiometry,
    /// Provenance: what the content was made from and how (`holo.source`).
    pub source: String,
    /// Frame rate, numerator / denominator.
    pub frames_per_second: Option<(i32, u32)>,
    /// `holo.frame` of the first frame; later frames count up from it.
    pub first_frame_number: i32,
    /// Replace an existing file at the destination (default: refuse).
    pub overwrite: bool,
    /// The format version to write (spec §9): the newest (1.2 for horizontal
    /// parallax, 1.3 for full), or 1.1 or 1.0 for readers of those.
    pub version: FormatVersion,
    /// `holo.placement` (spec §4.4): the transform from the converter's input
    /// coordinates to display metres (row-major, points as columns), when
    /// the content was placed; written exactly, so the conversion can be
    /// made again.
    pub placement: Option<[[f64; 4]; 4]>,
    /// `holo.convert.*` (spec §4.4): which converter made the content, from
    /// which input, with every option it was given.
    pub conversion: Option<ConversionRecord>,
}

/// Which version of the format a writer writes (spec §9).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FormatVersion {
    /// 1.3: full parallax (spec §8); a horizontal-parallax file asked for as
    /// 1.3 is written as 1.2, which 1.3 did not change.
    V1_3,
    /// 1.2: every part's header sealed by its digest (`holo.headerDigest`,
    /// spec §7.2), so a damaged header is found before a sample is read.
    #[default]
    V1_2,
    /// 1.1: the pixel aspect ratio is the emitter grid's own (spec §3.1), so
    /// EXR viewers show it at its physical proportions; headers unsealed.
    V1_1,
    /// 1.0: square pixels, for readers of version 1.0 (which refuse any other
    /// pixel aspect ratio); the content is the same.
    V1_0,
}

impl FormatVersion {
    /// The version a writer of this library writes for a file of version
    /// `number`: the same for 1.0 and 1.1, else the newest.
    pub fn for_number(number: (i32, i32)) -> FormatVersion {
        match number {
            (1, 0) => FormatVersion::V1_0,
            (1, 1) => FormatVersion::V1_1,
            (1, 2) => FormatVersion::V1_2,
            _ => FormatVersion::V1_3,
        }
    }

    /// The version a file of geometry `g` is written as when this one is
    /// asked for: full parallax needs 1.3 (and is refused by the older ones,
    /// which cannot hold it); horizontal parallax is written as 1.2 when 1.2
    /// or 1.3 is asked for, since 1.3 changed nothing for it (spec §8).
    pub fn written_for(self, g: &Geometry) -> std::result::Result<FormatVersion, String> {
        match (g.parallax, self) {
            (crate::geometry::Parallax::Full, FormatVersion::V1_3 | FormatVersion::V1_2) => Ok(FormatVersion::V1_3),
            (crate::geometry::Parallax::Full, old) => Err(format!(
                "full parallax needs format version 1.3; version {}.{} cannot hold it",
                old.number().0,
                old.number().1
            )),
            (crate::geometry::Parallax::Horizontal, FormatVersion::V1_3) => Ok(FormatVersion::V1_2),
            (crate::geometry::Parallax::Horizontal, v) => Ok(v),
        }
    }

    /// `(major, minor)`, as `holo.version` stores it.
    pub fn number(self) -> (i32, i32) {
        match self {
            FormatVersion::V1_3 => (1, 3),
            FormatVersion::V1_2 => (1, 2),
            FormatVersion::V1_1 => (1, 1),
            FormatVersion::V1_0 => (1, 0),
        }
    }

    /// OpenEXR's `pixelAspectRatio` for `g`: a pixel's width over its height
    /// as the display shows it (emitter pitch over hololine pitch; 1 in 1.0).
    pub fn pixel_aspect(self, g: &Geometry) -> f32 {
        match self {
            FormatVersion::V1_3 | FormatVersion::V1_2 | FormatVersion::V1_1 => {
                (g.emitter_pitch_m / g.hololine_pitch_m) as f32
            }
            FormatVersion::V1_0 => 1.0,
        }
    }

    /// Whether each header carries its digest, `holo.headerDigest` (from 1.2).
    pub fn is_sealed(self) -> bool {
        matches!(self, FormatVersion::V1_3 | FormatVersion::V1_2)
    }
}

impl Default for WriteOptions {
    fn default() -> Self {
        WriteOptions {
            sample_type: SampleType::F16,
            compression: Compression::Zip,
            radiometry: Radiometry::default(),
            source: String::new(),
            frames_per_second: None,
            first_frame_number: 0,
            overwrite: false,
            version: FormatVersion::default(),
            placement: None,
            conversion: None,
        }
    }
}

/// What a write did.
#[derive(Clone, Debug)]
pub struct WriteReport {
    /// The file written.
    pub path: PathBuf,
    /// Its size.
    pub file_bytes: u64,
    /// The digest of each frame.
    pub digests: Vec<String>,
    /// Things the user should know (lossy compression, ...).
    pub warnings: Vec<String>,
}

/// `options` with the version a file of `g` is written as
/// ([`FormatVersion::written_for`]).
pub(crate) fn written_options(path: &Path, g: &Geometry, options: &WriteOptions) -> Result<WriteOptions> {
    let version = options.version.written_for(g).map_err(|e| Error::unsupported(path, e))?;
    Ok(WriteOptions { version, ..options.clone() })
}

pub(crate) fn check_writable(path: &Path, g: &Geometry, frame_count: usize, options: &WriteOptions) -> Result<()> {
    let problems = g.problems();
    if !problems.is_empty() {
        return Err(Error::argument(
            "geometry",
            format!("{}: cannot write an invalid geometry: {}", path.display(), problems.join("; ")),
        ));
    }
    if frame_count == 0 || frame_count as u64 > MAX_FRAMES {
        return Err(Error::unsupported(path, format!("{frame_count} frames; a file holds 1 to {MAX_FRAMES}")));
    }
    if g.hololines as u64 > MAX_SIDE
        || g.emitters as u64 > MAX_SIDE
        || (g.views.count * g.channels.len()) as u64 > MAX_CHANNELS
    {
        return Err(Error::unsupported(path, "geometry exceeds the format's limits"));
    }
    if !options.overwrite && path.exists() {
        return Err(Error::Output { path: path.to_path_buf(), problem: crate::error::OutputProblem::Exists });
    }
    Ok(())
}

type BadSample = (usize, usize, usize, usize, f32, &'static str);

/// An error for the first bad sample, or for the first too large for f16
/// when f16 is what is stored.
pub(crate) fn check_samples(
    path: &Path,
    g: &Geometry,
    options: &WriteOptions,
    part: usize,
    bad: Option<BadSample>,
    f16_overflow: impl FnOnce() -> Option<BadSample>,
) -> Result<()> {
    let bad = bad.or_else(|| if options.sample_type == SampleType::F16 { f16_overflow() } else { None });
    match bad {
        None => Ok(()),
        Some((c, j, e, v, value, why)) => Err(Error::BadSample {
            path: path.into(),
            frame: part,
            hololine: j,
            emitter: e,
            view: g.view_of_index(v).0,
            vertical_view: g.vertical_views.as_ref().map(|_| g.view_of_index(v).1),
            channel: g.channels[c].name.clone(),
            value,
            why,
        }),
    }
}

/// The first sample of (channel, hololine, emitter, view)-ordered `samples`
/// over `hololines` that f16 cannot hold.
pub(crate) fn first_f16_overflow(
    g: &Geometry,
    samples: &[f32],
    hololines: std::ops::Range<usize>,
) -> Option<BadSample> {
    let i = samples.iter().position(|&x| overflows_f16(x))?;
    let (vc, lines) = (g.views_per_emitter(), hololines.len());
    let (v, e, j, c) =
        (i % vc, (i / vc) % g.emitters, hololines.start + (i / vc / g.emitters) % lines, i / vc / g.emitters / lines);
    Some((c, j, e, v, samples[i], "too large for f16 (max 65504); write f32"))
}

/// Whether `x` becomes infinite as an f16: its magnitude at least 65520, the
/// midpoint between the largest half (65504) and 2^16, which rounds to even,
/// away from 65504. A comparison the compiler vectorises, where converting
/// every sample to test it was a serial pass of its own before each write.
fn overflows_f16(x: f32) -> bool {
    x.abs() >= F16_OVERFLOW
}

/// The smallest magnitude that rounds to infinity as an f16.
const F16_OVERFLOW: f32 = 65520.0;

pub(crate) fn placeholder() -> String {
    header_digest::placeholder()
}

pub(crate) fn full_window(g: &Geometry) -> IntegerBounds {
    IntegerBounds::new(Vec2(0, 0), Vec2(g.emitters, g.hololines))
}

/// The header of one part: frame `frame` of `frame_count`, and for full
/// parallax (spec §8) the view `(h, k)` it holds, whose channels are the
/// colours alone.
pub(crate) fn part_header(
    g: &Geometry,
    options: &WriteOptions,
    frame: usize,
    frame_count: usize,
    view: Option<(usize, usize)>,
    window: &IntegerBounds,
    digest: &str,
) -> Header {
    let names = match view {
        None => ChannelOrder::new(g).names(g),
        Some(_) => super::channels::colour_names(g),
    };
    let channels: SmallVec<[ChannelDescription; 5]> = names
        .into_iter()
        .map(|n| ChannelDescription::new(Text::new_or_panic(n), options.sample_type.to_exr(), false))
        .collect();
    let part_name = match view {
        None => format!("frame{frame:05}"),
        Some((h, k)) => {
            let (dh, dk) = (view_digits(g.views.count), view_digits(g.vertical_view_count()));
            format!("frame{frame:05}.v{h:0dh$}_{k:0dk$}")
        }
    };
    let mut own = LayerAttributes::named(Text::new_or_panic(part_name));
    own.layer_position = window.position;
    own.software_name = Some(Text::new_or_panic(format!("holo {}", env!("CARGO_PKG_VERSION"))));
    own.frames_per_second = options.frames_per_second;
    let mut put = |k: &str, v| {
        own.other.insert(Text::new_or_panic(k), v);
    };
    put(name::FRAME, exr::meta::attribute::AttributeValue::I32(options.first_frame_number + frame as i32));
    put(name::FRAME_COUNT, exr::meta::attribute::AttributeValue::I32(frame_count as i32));
    if let Some((h, k)) = view {
        put(name::VIEW, exr::meta::attribute::AttributeValue::IntVec2(Vec2(h as i32, k as i32)));
    }
    put(name::DIGEST, attributes::text(digest));
    if options.version.is_sealed() {
        put(name::HEADER_DIGEST, attributes::text(&placeholder()));
    }
    if !options.source.is_empty() {
        put(name::SOURCE, attributes::text(&options.source));
    }
    let mut header = Header::new(own.layer_name.clone().unwrap_or_default(), window.size, channels)
        .with_encoding(options.compression.to_exr(), BlockDescription::ScanLines, LineOrder::Increasing)
        .with_display_window(full_window(g))
        .with_attributes(own);
    header.shared_attributes.other = geometry_attributes(g, &options.radiometry, options.version.number());
    // A file written for 1.0 readers holds only what 1.0 defines: the
    // provenance that 1.1 added is left out with the rest of 1.1.
    if options.version != FormatVersion::V1_0 {
        let shared = &mut header.shared_attributes.other;
        if let Some(m) = &options.placement {
            shared.insert(Text::new_or_panic(name::PLACEMENT), attributes::matrix_attribute(m));
        }
        for (k, v) in options.conversion.iter().flat_map(|r| &r.0) {
            shared.insert(Text::new_or_panic(k.as_str()), v.clone());
        }
    }
    header.shared_attributes.pixel_aspect = options.version.pixel_aspect(g);
    header
}

/// One block compressed as its part's header says: ZIP and ZIPS by
/// [`super::zip`] (libdeflate), every other compression by the `exr` crate;
/// with the block's bytes when `keep` (for the digest).
pub(crate) fn compress_block(
    block: UncompressedBlock,
    headers: &[Header],
    keep: bool,
) -> exr::error::Result<(Chunk, Option<Vec<u8>>)> {
    let header = &headers[block.index.layer];
    let zip = matches!(header.compression, exr::compression::Compression::ZIP1 | exr::compression::Compression::ZIP16);
    // The block's bytes are native-endian; the file's are little-endian.
    if !zip || cfg!(target_endian = "big") {
        let data = keep.then(|| block.data.clone());
        return Ok((block.compress_to_chunk(headers)?, data));
    }
    let y = i32::try_from(block.index.pixel_position.y())
        .map_err(|_| exr::error::Error::Invalid("block position out of range".into()))?
        + header.own_attributes.layer_position.y();
    let chunk = Chunk {
        layer_index: block.index.layer,
        compressed_block: CompressedBlock::ScanLine(CompressedScanLineBlock {
            y_coordinate: y,
            compressed_pixels_le: super::zip::compress(&block.data, super::zip::LEVEL),
        }),
    };
    Ok((chunk, keep.then_some(block.data)))
}

/// Rewrite each header's attributes in name order (OpenEXR's own order; the
/// `exr` crate writes custom attributes in hash order, which would make bytes
/// differ from run to run), fill in the frame digests, then seal each header
/// with its digest (spec §7.2) when the version has one. Attribute lengths do
/// not change, so no offset moves.
pub(crate) fn canonicalize_headers(path: &Path, digests: &[String], sealed: bool) -> Result<()> {
    // Only the headers are read (not, as a read to a fixed limit would, a
    // whole file of many parts).
    let header_digest::StoredHeaders { bytes: head, parts } = header_digest::read_stored(path)?;
    let mut file = std::fs::OpenOptions::new().read(true).write(true).open(path).map_err(|e| Error::io(path, e))?;
    let internal = |what: String| Error::invalid(path, format!("internal: {what} while finishing the headers"));
    if parts.len() != digests.len() {
        return Err(internal(format!("{} headers for {} frames", parts.len(), digests.len())));
    }
    let multipart = head[5] & 0x10 != 0;
    let mut rewritten = Vec::with_capacity(head.len());
    rewritten.extend_from_slice(&head[..8]);
    for (part, digest) in parts.iter().zip(digests) {
        let mut attributes: Vec<_> = part.attributes.iter().collect();
        attributes.sort_by(|a, b| head[a.name.clone()].cmp(&head[b.name.clone()]));
        let start = rewritten.len();
        let mut own = None;
        for a in attributes {
            let value_at = rewritten.len() + (a.value.start - a.whole.start);
            rewritten.extend_from_slice(&head[a.whole.clone()]);
            let name_bytes = &head[a.name.clone()];
            if name_bytes == name::DIGEST.as_bytes() {
                rewritten[value_at..value_at + a.value.len()].copy_from_slice(digest.as_bytes());
            } else if name_bytes == name::HEADER_DIGEST.as_bytes() {
                own = Some(value_at..value_at + a.value.len());
            }
        }
        rewritten.push(0);
        if sealed {
            let own = own.ok_or_else(|| internal(format!("no {}", name::HEADER_DIGEST)))?;
            let stored = header_digest::StoredHeader { attributes: Vec::new(), bytes: start..rewritten.len() };
            let seal = header_digest::digest_of(&rewritten, &stored, Some(own.clone()));
            rewritten[own].copy_from_slice(seal.as_bytes());
        }
    }
    if multipart {
        rewritten.push(0);
    }
    file.seek(SeekFrom::Start(0)).map_err(|e| Error::io(path, e))?;
    file.write_all(&rewritten).map_err(|e| Error::io(path, e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_f16_overflow_test_is_the_conversion_s() {
        let mut x = 0x1234_5678u32;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x
        };
        let edges = [65504.0f32, 65519.99, 65520.0, 65520.01, 65535.0, 65536.0, 1e9, f32::MAX];
        let near: Vec<f32> = (0..20_000).map(|_| 65400.0 + (next() % 300_000) as f32 / 1000.0).collect();
        let wide: Vec<f32> = (0..20_000).map(|_| f32::from_bits(next() & 0x7f7f_ffff)).collect();
        for v in edges.into_iter().chain(near).chain(wide) {
            for x in [v, -v] {
                assert_eq!(overflows_f16(x), half::f16::from_f32(x).is_infinite(), "{x}");
            }
        }
    }
}
