//! Writing `.holo` files: one EXR part per frame, frames pulled one at a time
//! from the caller (memory does not grow with the frame count), written beside
//! the destination and renamed into place only when complete.

use std::borrow::Cow;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::Path;

use exr::block::chunk::Chunk;
use exr::block::writer::ChunksWriter;
use exr::block::{BlockIndex, UncompressedBlock};
use exr::math::Vec2;
use exr::meta::attribute::IntegerBounds;
use exr::meta::header::Header;

use super::channels::ChannelOrder;
use super::digest::{frame_digest, row_bytes, stored_row, BlockDigest, RowDigest};
use super::parts::{
    canonicalize_headers, check_samples, check_writable, compress_block, first_f16_overflow, full_window, part_header,
    placeholder, written_options, WriteOptions, WriteReport,
};
use super::{SampleType, Window};
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::modulation::{Band, Modulation};
use crate::output::{AtomicFile, Spool};

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

fn check_frame(path: &Path, g: &Geometry, m: &Modulation, options: &WriteOptions, part: usize) -> Result<()> {
    if m.geometry() != g {
        return Err(Error::argument(
            "geometry",
            format!("{}: frame {part} has a different geometry from the file", path.display()),
        ));
    }
    check_samples(path, g, options, part, m.first_bad_sample(), || first_f16_overflow(g, m.samples(), 0..g.hololines))
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
