//! Writing `.holo` files: one EXR part per frame, frames pulled one at a time
//! from the caller (memory does not grow with the frame count), written beside
//! the destination and renamed into place only when complete.

use std::borrow::Cow;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use exr::block::chunk::{Chunk, CompressedBlock, CompressedScanLineBlock};
use exr::block::writer::ChunksWriter;
use exr::block::{BlockIndex, UncompressedBlock};
use exr::math::Vec2;
use exr::meta::attribute::{ChannelDescription, IntegerBounds, LineOrder, Text};
use exr::meta::header::{Header, LayerAttributes};
use exr::meta::BlockDescription;
use smallvec::SmallVec;

use super::attributes::{self, geometry_attributes, name, Radiometry};
use super::channels::{view_digits, ChannelOrder};
use super::digest::{frame_digest, row_bytes, stored_row, BlockDigest, RowDigest};
use super::header_digest;
use super::record::ConversionRecord;
use super::{Compression, SampleType, Window, MAX_CHANNELS, MAX_FRAMES, MAX_SIDE};
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::modulation::{Band, Modulation};
use crate::output::{AtomicFile, Spool};

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

/// Write one frame.
pub fn write(path: impl AsRef<Path>, modulation: &Modulation, options: &WriteOptions) -> Result<WriteReport> {
    write_frames(path, modulation.geometry(), 1, options, |_| Ok(Cow::Borrowed(modulation)))
}

/// Write `frame_count` frames, asking `frame(i)` for each in turn.
///
/// A single frame's data window is shrunk to the region with non-zero samples
/// (spec §3.3); with several frames every data window is the display window,
/// since all headers precede the first frame. Each frame's digest is written
/// as a placeholder of fixed size and filled in once the frame is known.
pub fn write_frames<'a>(
    path: impl AsRef<Path>,
    geometry: &Geometry,
    frame_count: usize,
    options: &WriteOptions,
    mut frame: impl FnMut(usize) -> Result<Cow<'a, Modulation>>,
) -> Result<WriteReport> {
    let path = path.as_ref();
    if geometry.vertical_views.is_some() {
        // Full parallax (spec §8): written band by band, each band cut from the frame.
        let mut current: Option<(usize, Cow<'a, Modulation>)> = None;
        return super::full::write_frames_in_bands(
            path,
            geometry,
            frame_count,
            super::full::DEFAULT_BAND_ROWS,
            options,
            |f, band| {
                if current.as_ref().map(|(i, _)| *i) != Some(f) {
                    let m = frame(f)?;
                    if m.geometry() != geometry {
                        return Err(Error::argument(
                            "geometry",
                            format!("{}: frame {f} has a different geometry from the file", path.display()),
                        ));
                    }
                    current = Some((f, m));
                }
                let (_, m) = current.as_ref().expect("set above");
                band.copy_rows_from(m);
                Ok(())
            },
        );
    }
    let options = &written_options(path, geometry, options)?;
    check_writable(path, geometry, frame_count, options)?;
    // One frame: look at it first, so the header can carry its data window and digest.
    let mut first = None;
    let mut windows = vec![full_window(geometry); frame_count];
    if frame_count == 1 {
        let m = frame(0)?;
        check_frame(path, geometry, &m, options, 0)?;
        windows[0] = covered_window(&m);
        first = Some((None, Rows::Whole(m)));
    }
    // Each frame's digest is taken from its blocks as they are built.
    write_parts(path, geometry, options, windows, first, |part| {
        let m = frame(part)?;
        check_frame(path, geometry, &m, options, part)?;
        Ok((None, Rows::Whole(m)))
    })
}

/// Write one frame produced band by band: `fill(band)` fills each band of at
/// most `band_hololines` hololines, top to bottom. Memory is bounded by a band
/// (and a few compressed blocks), not by the frame: the bands are checked,
/// hashed and kept in stored form in a spool file beside the destination
/// until the data window is known. The bytes written are exactly those
/// [`write()`] writes for the same samples.
pub fn write_frame_in_bands(
    path: impl AsRef<Path>,
    geometry: &Geometry,
    band_hololines: usize,
    options: &WriteOptions,
    mut fill: impl FnMut(&mut Band) -> Result<()>,
) -> Result<WriteReport> {
    let path = path.as_ref();
    if geometry.vertical_views.is_some() {
        return super::full::write_frames_in_bands(path, geometry, 1, band_hololines, options, |_, band| fill(band));
    }
    let options = &written_options(path, geometry, options)?;
    check_writable(path, geometry, 1, options)?;
    if band_hololines == 0 {
        return Err(Error::argument(
            "band height",
            format!("{}: bands must hold at least one hololine", path.display()),
        ));
    }
    let order = ChannelOrder::new(geometry);
    let row_len = row_bytes(geometry, options.sample_type);
    let spool = Spool::create(path)?;
    let mut spool_out = BufWriter::with_capacity(1 << 20, spool.file());
    let mut digest = RowDigest::default();
    let mut row = vec![0u8; row_len];
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    let mut top = 0;
    while top < geometry.hololines {
        let lines = top..(top + band_hololines).min(geometry.hololines);
        let mut band = Band::zeros(geometry.clone(), lines.clone())?;
        fill(&mut band)?;
        if band.geometry() != geometry || band.hololines() != lines {
            return Err(Error::argument(
                "band",
                format!("{}: band of hololines {lines:?} came back with a different shape", path.display()),
            ));
        }
        check_samples(path, geometry, options, 0, band.first_bad_sample(), || {
            first_f16_overflow(geometry, band.samples(), lines.clone())
        })?;
        for j in lines.clone() {
            stored_row(geometry, &order, options.sample_type, |c| band.hololine(c, j), &mut row);
            digest.update(&row);
            spool_out.write_all(&row).map_err(|e| Error::io(path, e))?;
            if let Some((e0, e1)) = row_coverage(geometry, |c| band.hololine(c, j)) {
                (x0, x1, y0, y1) = (x0.min(e0), x1.max(e1), y0.min(j), y1.max(j));
            }
        }
        top = lines.end;
    }
    spool_out.flush().map_err(|e| Error::io(path, e))?;
    drop(spool_out);
    let window = window_from(x0, y0, x1, y1);
    let rows = Rows::Spooled { file: std::sync::Mutex::new(spool.file().try_clone().map_err(|e| Error::io(path, e))?) };
    write_parts(path, geometry, options, vec![window], Some((Some(digest.finish()), rows)), |_| {
        Err(Error::argument("frame count", "internal: a one-frame write asked for a second frame"))
    })
}

/// Where one frame's stored rows come from while its blocks are written.
// One per part being written: its size does not matter.
#[allow(clippy::large_enum_variant)]
enum Rows<'a> {
    /// A whole frame in memory: rows are made as blocks ask for them.
    Whole(Cow<'a, Modulation>),
    /// Rows already in stored form (little-endian, display-window wide) in a spool file.
    Spooled { file: std::sync::Mutex<std::fs::File> },
}

impl Rows<'_> {
    /// Stored rows `first..first + out.len() / row_bytes` into `out`.
    fn read(
        &self,
        g: &Geometry,
        order: &ChannelOrder,
        sample_type: SampleType,
        first: usize,
        out: &mut [u8],
    ) -> std::io::Result<()> {
        let row_len = row_bytes(g, sample_type);
        match self {
            Rows::Whole(m) => {
                for (k, row) in out.chunks_exact_mut(row_len).enumerate() {
                    stored_row(g, order, sample_type, |c| m.hololine(c, first + k), row);
                }
                Ok(())
            }
            Rows::Spooled { file } => {
                let mut file = file.lock().map_err(|_| std::io::Error::other("spool lock poisoned"))?;
                file.seek(SeekFrom::Start((first * row_len) as u64))?;
                file.read_exact(out)
            }
        }
    }
}

/// Blocks built ahead of the compressor: enough to keep every core busy, few
/// enough that memory stays a small multiple of one block.
const BATCH_BYTES: usize = 4 << 20;

/// A part's rows, and its digest when the caller knows it (else it is taken
/// from the blocks as they are built).
type PartRows<'a> = (Option<String>, Rows<'a>);

/// The writer proper: headers for `windows` (each digest a placeholder, filled
/// in at the end), then every part's blocks from `first` (part 0, when the
/// caller already has it) and `next(part)`, written beside `path` and renamed
/// into place.
fn write_parts<'a>(
    path: &Path,
    geometry: &Geometry,
    options: &WriteOptions,
    windows: Vec<IntegerBounds>,
    mut first: Option<PartRows<'a>>,
    mut next: impl FnMut(usize) -> Result<PartRows<'a>>,
) -> Result<WriteReport> {
    let mut digests = vec![placeholder(); windows.len()];
    let frame_count = windows.len();
    let mut warnings = Vec::new();
    if !options.compression.is_lossless_for(options.sample_type) {
        warnings.push(format!(
            "compression {} is lossy for {:?} samples: values will not read back exactly",
            options.compression.name(),
            options.sample_type
        ));
    }
    let headers: Vec<Header> = (0..frame_count)
        .map(|i| part_header(geometry, options, i, frame_count, None, &windows[i], &digests[i]))
        .collect();

    let mut temp = AtomicFile::create(path)?;

    let mut failure: Option<Error> = None;
    let order = ChannelOrder::new(geometry);
    let row_len = row_bytes(geometry, options.sample_type);
    let written = {
        exr::block::write(&mut temp, headers.into(), true, |meta, chunk_writer| {
            for (part, digest) in digests.iter_mut().enumerate() {
                let (given, rows) = match first.take().map_or_else(|| next(part), Ok) {
                    Ok(part_rows) => part_rows,
                    Err(e) => {
                        failure = Some(e);
                        return Err(exr::error::Error::Aborted);
                    }
                };
                let header = &meta.headers[part];
                // The blocks' bytes are native-endian, the digest's little-endian.
                let window = Window {
                    x: header.own_attributes.layer_position.x() as usize,
                    y: header.own_attributes.layer_position.y() as usize,
                    width: header.layer_size.width(),
                    height: header.layer_size.height(),
                };
                // A lossy file's digest is taken from what it decodes to, below.
                let lossy = !options.compression.is_lossless_for(options.sample_type);
                let mut hasher = match (&given, cfg!(target_endian = "little") && !lossy) {
                    (None, true) => Some(BlockDigest::new(geometry, options.sample_type, window)),
                    _ => None,
                };
                // Build and compress blocks in parallel batches, then write
                // them in increasing y: what is in flight is one batch.
                let tiles: Vec<_> = header.blocks_increasing_y_order().enumerate().collect();
                let block_bytes = row_len * header.compression.scan_lines_per_block();
                // At least a block per thread, so large blocks still build in parallel.
                let per_batch = (BATCH_BYTES / block_bytes.max(1)).max(rayon::current_num_threads()).clamp(1, 64);
                let hashing = hasher.is_some();
                for batch in tiles.chunks(per_batch) {
                    type Built = (usize, Chunk, Option<(usize, usize, Vec<u8>)>);
                    let chunks: Vec<exr::error::Result<Built>> = {
                        use rayon::prelude::*;
                        batch
                            .par_iter()
                            .map(|(index, tile)| {
                                let bounds = header.get_absolute_block_pixel_coordinates(tile.location)?;
                                let block = block(&rows, geometry, &order, header, part, bounds, options.sample_type)?;
                                let lines =
                                    (window.y + block.index.pixel_position.y(), block.index.pixel_size.height());
                                let (chunk, data) = compress_block(block, &meta.headers, hashing)?;
                                Ok((*index, chunk, data.map(|d| (lines.0, lines.1, d))))
                            })
                            .collect()
                    };
                    for c in chunks {
                        let (index, chunk, data) = c?;
                        if let (Some(h), Some((top, count, data))) = (hasher.as_mut(), data) {
                            h.push(top, count, data);
                        }
                        chunk_writer.write_chunk(index, chunk)?;
                    }
                }
                *digest = match (given, hasher.and_then(BlockDigest::finish), &rows) {
                    (Some(d), _, _) | (None, Some(d), _) => d,
                    (None, None, _) if lossy => placeholder(),
                    (None, None, Rows::Whole(m)) => frame_digest(m.as_ref(), options.sample_type),
                    (None, None, Rows::Spooled { .. }) => unreachable!("a spooled frame comes with its digest"),
                };
            }
            Ok(())
        })
    };
    if let Some(e) = failure {
        return Err(e);
    }
    // Named by the file asked for (the temporary is an implementation
    // detail): `x.holo: No space left on device`.
    written.map_err(|e| Error::exr(temp.destination(), e))?;
    temp.flush().map_err(|e| Error::io(temp.destination(), e))?;
    if !options.compression.is_lossless_for(options.sample_type) {
        // The digest must describe what a reader will decode, not what was
        // asked for; read back band by band, so memory stays bounded.
        let stored = super::read::HoloFile::open_unsealed(temp.temporary_path())?;
        let mut row = vec![0u8; row_len];
        for (i, d) in digests.iter_mut().enumerate() {
            let mut digest = RowDigest::default();
            for top in (0..geometry.hololines).step_by(64) {
                let lines = top..(top + 64).min(geometry.hololines);
                let region = super::read::Region { hololines: lines.clone(), ..super::read::Region::all(geometry) };
                let band = stored.read_decoded(i, &region)?;
                for j in 0..lines.len() {
                    stored_row(geometry, &order, options.sample_type, |c| band.hololine(c, j), &mut row);
                    digest.update(&row);
                }
            }
            *d = digest.finish();
        }
    }
    canonicalize_headers(temp.temporary_path(), &digests, options.version.is_sealed())?;
    let file_bytes = temp.commit(options.overwrite)?;
    Ok(WriteReport { path: path.to_path_buf(), file_bytes, digests, warnings })
}

/// `options` with the version a file of `g` is written as
/// ([`FormatVersion::written_for`]).
pub(super) fn written_options(path: &Path, g: &Geometry, options: &WriteOptions) -> Result<WriteOptions> {
    let version = options.version.written_for(g).map_err(|e| Error::unsupported(path, e))?;
    Ok(WriteOptions { version, ..options.clone() })
}

pub(super) fn check_writable(path: &Path, g: &Geometry, frame_count: usize, options: &WriteOptions) -> Result<()> {
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

fn check_frame(path: &Path, g: &Geometry, m: &Modulation, options: &WriteOptions, part: usize) -> Result<()> {
    if m.geometry() != g {
        return Err(Error::argument(
            "geometry",
            format!("{}: frame {part} has a different geometry from the file", path.display()),
        ));
    }
    check_samples(path, g, options, part, m.first_bad_sample(), || first_f16_overflow(g, m.samples(), 0..g.hololines))
}

type BadSample = (usize, usize, usize, usize, f32, &'static str);

/// An error for the first bad sample, or for the first too large for f16
/// when f16 is what is stored.
pub(super) fn check_samples(
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
            view: v,
            channel: g.channels[c].name.clone(),
            value,
            why,
        }),
    }
}

/// The first sample of (channel, hololine, emitter, view)-ordered `samples`
/// over `hololines` that f16 cannot hold.
pub(super) fn first_f16_overflow(
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

pub(super) fn placeholder() -> String {
    header_digest::placeholder()
}

pub(super) fn full_window(g: &Geometry) -> IntegerBounds {
    IntegerBounds::new(Vec2(0, 0), Vec2(g.emitters, g.hololines))
}

/// The smallest rectangle holding every non-zero sample (1×1 at the origin if none).
fn covered_window(m: &Modulation) -> IntegerBounds {
    let g = m.geometry();
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for j in 0..g.hololines {
        if let Some((e0, e1)) = row_coverage(g, |c| m.hololine(c, j)) {
            (x0, x1, y0, y1) = (x0.min(e0), x1.max(e1), y0.min(j), y1.max(j));
        }
    }
    window_from(x0, y0, x1, y1)
}

/// The first and last emitter of a hololine with a non-zero sample in any
/// channel; `line(c)` gives colour `c`'s (emitter, view) samples.
fn row_coverage<'a>(g: &Geometry, line: impl Fn(usize) -> &'a [f32]) -> Option<(usize, usize)> {
    let views = g.views.count;
    let mut covered: Option<(usize, usize)> = None;
    for c in 0..g.channels.len() {
        let line = line(c);
        for e in 0..g.emitters {
            if line[e * views..(e + 1) * views].iter().any(|x| *x != 0.0) {
                covered = Some(covered.map_or((e, e), |(a, b)| (a.min(e), b.max(e))));
            }
        }
    }
    covered
}

/// The window of inclusive emitter and hololine extents (1×1 at the origin
/// when nothing was covered: `x0 == usize::MAX`).
fn window_from(x0: usize, y0: usize, x1: usize, y1: usize) -> IntegerBounds {
    if x0 == usize::MAX {
        return IntegerBounds::new(Vec2(0, 0), Vec2(1, 1));
    }
    IntegerBounds::new(Vec2(x0 as i32, y0 as i32), Vec2(x1 - x0 + 1, y1 - y0 + 1))
}

/// The header of one part: frame `frame` of `frame_count`, and for full
/// parallax (spec §8) the view `(h, k)` it holds, whose channels are the
/// colours alone.
pub(super) fn part_header(
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
pub(super) fn compress_block(
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

/// The uncompressed bytes of one block: line by line, channel by channel in
/// list order, emitter by emitter, native-endian; cut from the stored rows.
fn block(
    rows: &Rows,
    g: &Geometry,
    order: &ChannelOrder,
    header: &Header,
    part: usize,
    bounds: IntegerBounds,
    sample_type: SampleType,
) -> exr::error::Result<UncompressedBlock> {
    let (x0, y0) = (header.own_attributes.layer_position.0 as usize, header.own_attributes.layer_position.1 as usize);
    let (bx, by) = (bounds.position.0 as usize, bounds.position.1 as usize);
    let (w, h) = (bounds.size.0, bounds.size.1);
    let (bytes, row_len) = (sample_type.bytes(), row_bytes(g, sample_type));
    let mut stored = vec![0u8; row_len * h];
    rows.read(g, order, sample_type, y0 + by, &mut stored)?;
    let mut data = Vec::with_capacity(w * h * order.len() * bytes);
    for row in stored.chunks_exact(row_len) {
        for slot in 0..order.len() {
            let at = (slot * g.emitters + x0 + bx) * bytes;
            data.extend_from_slice(&row[at..at + w * bytes]);
        }
    }
    if cfg!(target_endian = "big") {
        data.chunks_exact_mut(bytes).for_each(|sample| sample.reverse());
    }
    Ok(UncompressedBlock {
        index: BlockIndex { layer: part, pixel_position: Vec2(bx, by), pixel_size: Vec2(w, h), level: Vec2(0, 0) },
        data,
    })
}

/// Rewrite each header's attributes in name order (OpenEXR's own order; the
/// `exr` crate writes custom attributes in hash order, which would make bytes
/// differ from run to run), fill in the frame digests, then seal each header
/// with its digest (spec §7.2) when the version has one. Attribute lengths do
/// not change, so no offset moves.
pub(super) fn canonicalize_headers(path: &Path, digests: &[String], sealed: bool) -> Result<()> {
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
