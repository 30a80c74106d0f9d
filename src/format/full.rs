//! Full-parallax files (spec §8): one EXR part per (frame, view), each a
//! picture of its view whose channels are the colours alone. A frame is
//! written band by band of emitter rows, its parts' chunks side by side, so
//! neither writer nor reader needs memory for a whole frame; a read decodes
//! only the parts of the views it asks for and the chunks of its rows.

use std::path::Path;

use exr::block::chunk::Chunk;
use exr::block::writer::ChunksWriter;
use exr::block::{BlockIndex, UncompressedBlock};
use exr::math::Vec2;
use exr::meta::header::Header;

use super::channels::colour_slots;
use super::digest::RowDigest;
use super::parts::{
    canonicalize_headers, check_samples, check_writable, compress_block, first_f16_overflow, full_window, part_header,
    placeholder, written_options, WriteOptions, WriteReport,
};
use super::{SampleType, MAX_FRAMES};
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::modulation::Band;
use crate::output::AtomicFile;

/// Emitter rows a band holds when the caller does not say: enough that
/// every part's chunk of 16 (ZIP) or 32 (PIZ) rows is whole.
pub const DEFAULT_BAND_ROWS: usize = 32;

/// The part of frame `frame`, view index `view` (`k · V + h`): `p = (f · W + k) · V + h`.
pub fn part_of(g: &Geometry, frame: usize, view: usize) -> usize {
    frame * g.views_per_emitter() + view
}

/// Write `frame_count` full-parallax frames, each band by band:
/// `fill(frame, band)` fills a band of at least `band_rows` emitter rows
/// (rounded up to whole chunks), top to bottom, frame after frame. Memory
/// holds one band and its compressed chunks. Written beside `path` and
/// renamed into place when complete.
pub fn write_frames_in_bands(
    path: &Path,
    geometry: &Geometry,
    frame_count: usize,
    band_rows: usize,
    options: &WriteOptions,
    mut fill: impl FnMut(usize, &mut Band) -> Result<()>,
) -> Result<WriteReport> {
    let g = geometry;
    check_writable(path, g, 1, options)?;
    let views = g.views_per_emitter();
    let parts = (frame_count as u64).saturating_mul(views as u64);
    if frame_count == 0 || parts > MAX_FRAMES {
        return Err(Error::unsupported(
            path,
            format!(
                "{frame_count} frame(s) of {views} views are {parts} parts; a file holds 1 to {MAX_FRAMES} (write longer movies as a sequence of files)"
            ),
        ));
    }
    let options = &written_options(path, g, options)?;
    let version = options.version;
    let mut warnings = Vec::new();
    let lossy = !options.compression.is_lossless_for(options.sample_type);
    if lossy {
        warnings.push(format!(
            "compression {} is lossy for {:?} samples: values will not read back exactly",
            options.compression.name(),
            options.sample_type
        ));
    }
    let window = full_window(g);
    let headers: Vec<Header> = (0..frame_count)
        .flat_map(|f| (0..views).map(move |v| (f, v)))
        .map(|(f, v)| part_header(g, options, f, frame_count, Some(g.view_of_index(v)), &window, &placeholder()))
        .collect();
    let lines_per_block = options.compression.to_exr().scan_lines_per_block();
    let band_rows = band_rows.max(1).div_ceil(lines_per_block) * lines_per_block;
    let slots = colour_slots(g);
    let mut temp = AtomicFile::create(path)?;
    let mut digests: Vec<RowDigest> = (0..parts).map(|_| RowDigest::default()).collect();
    let mut failure: Option<Error> = None;
    let written = exr::block::write(&mut temp, headers.into(), true, |meta, chunk_writer| {
        for f in 0..frame_count {
            let mut top = 0;
            while top < g.hololines {
                let lines = top..(top + band_rows).min(g.hololines);
                let band = match filled_band(path, g, options, f, lines.clone(), &mut fill) {
                    Ok(band) => band,
                    Err(e) => {
                        failure = Some(e);
                        return Err(exr::error::Error::Aborted);
                    }
                };
                let frame_digests = &mut digests[f * views..(f + 1) * views];
                let by_view = band_by_view(&band, g, &slots, lines.clone());
                let per_view = lines.len() * slots.len() * g.emitters;
                let built: Vec<exr::error::Result<Vec<(usize, Chunk)>>> = {
                    use rayon::prelude::*;
                    frame_digests
                        .par_iter_mut()
                        .zip(by_view.par_chunks_exact(per_view))
                        .enumerate()
                        .map(|(v, (digest, view_band))| {
                            let mut chunks = Vec::new();
                            for y in lines.clone().step_by(lines_per_block) {
                                let rows = lines_per_block.min(lines.end - y);
                                let row_len = slots.len() * g.emitters;
                                let first = (y - lines.start) * row_len;
                                let le = samples_le(&view_band[first..first + rows * row_len], options.sample_type);
                                digest.update(&le);
                                let block = UncompressedBlock {
                                    index: BlockIndex {
                                        layer: part_of(g, f, v),
                                        pixel_position: Vec2(0, y),
                                        pixel_size: Vec2(g.emitters, rows),
                                        level: Vec2(0, 0),
                                    },
                                    data: native_endian(le, options.sample_type),
                                };
                                let (chunk, _) = compress_block(block, &meta.headers, false)?;
                                chunks.push((y / lines_per_block, chunk));
                            }
                            Ok(chunks)
                        })
                        .collect()
                };
                for chunks in built {
                    for (index, chunk) in chunks? {
                        chunk_writer.write_chunk(index, chunk)?;
                    }
                }
                top = lines.end;
            }
        }
        Ok(())
    });
    if let Some(e) = failure {
        return Err(e);
    }
    written.map_err(|e| Error::exr(temp.destination(), e))?;
    std::io::Write::flush(&mut temp).map_err(|e| Error::io(temp.destination(), e))?;
    let digests: Vec<String> = if lossy {
        // What a reader decodes, not what was asked for (spec §7.1).
        decoded_digests(temp.temporary_path(), g, frame_count, options.sample_type)?
    } else {
        digests.into_iter().map(RowDigest::finish).collect()
    };
    canonicalize_headers(temp.temporary_path(), &digests, version.is_sealed())?;
    let file_bytes = temp.commit(options.overwrite)?;
    Ok(WriteReport { path: path.to_path_buf(), file_bytes, digests, warnings })
}

/// Band `lines` of frame `frame`, filled and checked.
fn filled_band(
    path: &Path,
    g: &Geometry,
    options: &WriteOptions,
    frame: usize,
    lines: std::ops::Range<usize>,
    fill: &mut impl FnMut(usize, &mut Band) -> Result<()>,
) -> Result<Band> {
    let mut band = Band::zeros(g.clone(), lines.clone())?;
    fill(frame, &mut band)?;
    if band.geometry() != g || band.hololines() != lines {
        return Err(Error::argument(
            "band",
            format!("{}: band of emitter rows {lines:?} came back with a different shape", path.display()),
        ));
    }
    check_samples(path, g, options, frame, band.first_bad_sample(), || {
        first_f16_overflow(g, band.samples(), lines.clone())
    })?;
    Ok(band)
}

/// Emitter rows `lines` of `band`, view by view as stored (spec §7.1, §8):
/// for each view (`k·V + h`), row by row, channel by channel in list order
/// (`slots`), emitter by emitter. In memory an emitter's views are together
/// (a `V·W` run); a view's samples are one in `V·W` there, so gathering them
/// a view at a time would touch a cache line per sample. The transpose goes
/// in tiles of [`TILE_VIEWS`] views × [`TILE_EMITTERS`] emitters that stay
/// in cache on both sides, blocks of views in parallel.
fn band_by_view(band: &Band, g: &Geometry, slots: &[usize], lines: std::ops::Range<usize>) -> Vec<f32> {
    use rayon::prelude::*;
    let (views, emitters) = (g.views_per_emitter(), g.emitters);
    let per_view = lines.len() * slots.len() * emitters;
    let mut out = vec![0f32; views * per_view];
    out.par_chunks_mut(TILE_VIEWS * per_view).enumerate().for_each(|(block, out)| {
        let v0 = block * TILE_VIEWS;
        let v1 = (v0 + TILE_VIEWS).min(views);
        for (row, j) in lines.clone().enumerate() {
            for (s, &c) in slots.iter().enumerate() {
                let line = band.hololine(c, j);
                let at = (row * slots.len() + s) * emitters;
                for e0 in (0..emitters).step_by(TILE_EMITTERS) {
                    let e1 = (e0 + TILE_EMITTERS).min(emitters);
                    for v in v0..v1 {
                        let out = &mut out[(v - v0) * per_view + at..][e0..e1];
                        for (e, o) in (e0..e1).zip(out) {
                            *o = line[e * views + v];
                        }
                    }
                }
            }
        }
    });
    out
}

/// Views and emitters in a tile of [`band_by_view`]'s transpose.
const TILE_VIEWS: usize = 32;
const TILE_EMITTERS: usize = 16;

/// `samples` as stored, little-endian.
fn samples_le(samples: &[f32], sample_type: SampleType) -> Vec<u8> {
    let mut out = Vec::with_capacity(samples.len() * sample_type.bytes());
    match sample_type {
        SampleType::F16 => samples.iter().for_each(|&x| out.extend_from_slice(&half::f16::from_f32(x).to_le_bytes())),
        SampleType::F32 => samples.iter().for_each(|&x| out.extend_from_slice(&x.to_le_bytes())),
    }
    out
}

/// Little-endian samples as the `exr` crate's blocks hold them (native-endian).
fn native_endian(mut bytes: Vec<u8>, sample_type: SampleType) -> Vec<u8> {
    if cfg!(target_endian = "big") {
        bytes.chunks_exact_mut(sample_type.bytes()).for_each(|s| s.reverse());
    }
    bytes
}

/// Each part's digest of the samples a reader decodes from the file at
/// `path` (its headers not yet sealed), read band by band.
fn decoded_digests(path: &Path, g: &Geometry, frame_count: usize, sample_type: SampleType) -> Result<Vec<String>> {
    let file = super::read::HoloFile::open_unsealed(path)?;
    let slots = colour_slots(g);
    let mut out = Vec::new();
    for f in 0..frame_count {
        for v in 0..g.views_per_emitter() {
            let (h, k) = g.view_of_index(v);
            let mut digest = RowDigest::default();
            for top in (0..g.hololines).step_by(DEFAULT_BAND_ROWS) {
                let lines = top..(top + DEFAULT_BAND_ROWS).min(g.hololines);
                let region = super::read::Region {
                    hololines: lines.clone(),
                    emitters: 0..g.emitters,
                    views: h..h + 1,
                    vertical_views: k..k + 1,
                };
                // One view: each row's line is its emitters' samples.
                let band = file.read_decoded(f, &region)?;
                let band = &band;
                let rows: Vec<f32> = (0..lines.len())
                    .flat_map(|j| slots.iter().flat_map(move |&c| band.hololine(c, j).iter().copied()))
                    .collect();
                digest.update(&samples_le(&rows, sample_type));
            }
            out.push(digest.finish());
        }
    }
    Ok(out)
}
