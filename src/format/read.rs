//! Reading `.holo` files lazily: [`HoloFile::open`] reads and checks the
//! headers only; [`HoloFile::read_frame`] and [`HoloFile::read_region`] then
//! decode only the chunks that hold the frame or region asked for.

use std::ops::Range;
use std::path::{Path, PathBuf};

use exr::block::chunk::TileCoordinates;
use exr::block::reader::ChunksReader;
use exr::block::BlockIndex;
use exr::meta::MetaData;

use super::channels::ChannelOrder;
use half::slice::HalfFloatSliceExt;

use super::digest::{frame_digest, BlockDigest};
use super::header::{file_info, FileInfo};
use super::{SampleType, MAX_SAMPLES_PER_FRAME};
use crate::geometry::{Geometry, ViewSpacing};
use crate::{Error, Modulation, Result};

/// Files smaller than this are decompressed on the calling thread.
const PARALLEL_DECODE_MIN_BYTES: u64 = 1 << 20;

/// A part of a frame: hololines × emitters × views (all colours).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Region {
    /// Hololines (rows) to read.
    pub hololines: Range<usize>,
    /// Emitters (columns) to read.
    pub emitters: Range<usize>,
    /// Views to read.
    pub views: Range<usize>,
}

impl Region {
    /// The whole of a geometry.
    pub fn all(g: &Geometry) -> Self {
        Region { hololines: 0..g.hololines, emitters: 0..g.emitters, views: 0..g.views.count }
    }
}

/// An open `.holo` file whose headers have been read and checked.
#[derive(Debug)]
pub struct HoloFile {
    info: FileInfo,
}

/// Read frame 0 of a file whole, checking its digest.
pub fn read(path: impl AsRef<Path>) -> Result<Modulation> {
    HoloFile::open(path)?.read_frame(0)
}

impl HoloFile {
    /// Read and check the headers, each against its digest (spec §7.2); no
    /// pixel data is touched.
    pub fn open(path: impl AsRef<Path>) -> Result<Self> {
        let (info, _) = file_info(path.as_ref(), true)?;
        Ok(HoloFile { info })
    }

    /// Open a file whose header digests are not yet filled in: the writer's
    /// own, read back before it is finished.
    pub(crate) fn open_unsealed(path: &Path) -> Result<Self> {
        let (info, _) = file_info(path, false)?;
        Ok(HoloFile { info })
    }

    /// What the headers say.
    pub fn info(&self) -> &FileInfo {
        &self.info
    }

    /// The geometry of every frame.
    pub fn geometry(&self) -> &Geometry {
        &self.info.geometry
    }

    /// The path it was opened from.
    pub fn path(&self) -> &PathBuf {
        &self.info.path
    }

    /// Read frame `index` (0-based part order) whole and verify its digest.
    pub fn read_frame(&self, index: usize) -> Result<Modulation> {
        let frame = self.info.frames.get(index);
        // The digest is taken from the decoded blocks' own bytes as they come
        // (they are the stored rows), not from the samples afterwards.
        // (Blocks hold native-endian samples, the digest little-endian ones.)
        let from_blocks = cfg!(target_endian = "little");
        let mut digest = frame
            .filter(|f| f.digest.is_some() && from_blocks)
            .map(|f| BlockDigest::new(&self.info.geometry, self.info.sample_type, f.data_window));
        let mut m = self.read_blocks(index, &Region::all(&self.info.geometry), digest.as_mut())?;
        let frame = &self.info.frames[index];
        if let Some(stored) = &frame.digest {
            let computed = match digest.and_then(BlockDigest::finish) {
                Some(computed) => computed,
                None => frame_digest(&m, self.info.sample_type),
            };
            if &computed != stored {
                return Err(Error::DigestMismatch {
                    path: self.info.path.clone(),
                    frame: index,
                    stored: stored.clone(),
                    computed,
                });
            }
        }
        if self.is_lossy() {
            clamp_undershoot(&mut m);
        }
        Ok(m)
    }

    /// Read one region of frame `index`; only the chunks holding its hololines
    /// are read and decompressed. The digest cannot be checked on a part.
    pub fn read_region(&self, index: usize, region: &Region) -> Result<Modulation> {
        let mut m = self.read_decoded(index, region)?;
        if self.is_lossy() {
            clamp_undershoot(&mut m);
        }
        Ok(m)
    }

    /// Whether the samples come back from the codec only approximately
    /// (spec §3.4: then a negative sample is the codec's undershoot, read
    /// as +0).
    pub fn is_lossy(&self) -> bool {
        !self.info.compression.is_lossless_for(self.info.sample_type)
    }

    /// A region's samples exactly as the codec decodes them (what the frame
    /// digest covers): non-finite values are refused, and negative ones too
    /// unless the compression is lossy, when they are returned as decoded
    /// (for measuring a codec; [`HoloFile::read_region`] is what a reader
    /// wants).
    pub fn read_decoded(&self, index: usize, region: &Region) -> Result<Modulation> {
        self.read_blocks(index, region, None)
    }

    /// [`HoloFile::read_decoded`], handing every decoded block's bytes to
    /// `digest` too (whole frames only).
    fn read_blocks(&self, index: usize, region: &Region, mut digest: Option<&mut BlockDigest>) -> Result<Modulation> {
        let path = &self.info.path;
        let g = &self.info.geometry;
        let frame = self.info.frames.get(index).ok_or_else(|| Error::no_frame(path, index, self.info.frames.len()))?;
        let ok = |r: &Range<usize>, n: usize| r.start < r.end && r.end <= n;
        if !ok(&region.hololines, g.hololines) || !ok(&region.emitters, g.emitters) || !ok(&region.views, g.views.count)
        {
            return Err(Error::argument(
                "region",
                format!(
                    "{}: region hololines {:?}, emitters {:?}, views {:?} is empty or outside {}×{}×{}",
                    path.display(),
                    region.hololines,
                    region.emitters,
                    region.views,
                    g.hololines,
                    g.emitters,
                    g.views.count
                ),
            ));
        }
        let sub = sub_geometry(g, region);
        if sub.samples_per_frame() > MAX_SAMPLES_PER_FRAME {
            return Err(Error::TooLarge {
                path: path.clone(),
                what: "samples in the region",
                value: sub.samples_per_frame(),
                limit: MAX_SAMPLES_PER_FRAME,
            });
        }
        let mut out = Modulation::zeros(sub)?;
        let order = ChannelOrder::new(g);
        let part = frame.part;
        let dw = frame.data_window;
        let wanted_rows = region.hololines.clone();
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let file_bytes = file.metadata().map_err(|e| Error::io(path, e))?.len();
        let reader = exr::block::read(std::io::BufReader::new(file), false).map_err(|e| Error::exr(path, e))?;
        let chunks = reader
            .filter_chunks(false, |_meta: &MetaData, _tile: TileCoordinates, block: BlockIndex| {
                let top = dw.y + block.pixel_position.1;
                block.layer == part
                    && block.level == exr::math::Vec2(0, 0)
                    && top < wanted_rows.end
                    && top + block.pixel_size.1 > wanted_rows.start
            })
            .map_err(|e| Error::exr(path, e))?;
        let mut place = |block: exr::block::UncompressedBlock| -> Result<()> {
            place_block(&mut out, &block, &order, self.info.sample_type, dw.x, dw.y, region)
                .map_err(|problem| Error::invalid(path, problem))?;
            if let Some(digest) = digest.as_deref_mut() {
                digest.push(dw.y + block.index.pixel_position.1, block.index.pixel_size.1, block.data);
            }
            Ok(())
        };
        // exr starts a thread pool per parallel read; below a megabyte that
        // costs more than it saves (and its threads outlive the call).
        let parallel =
            if file_bytes >= PARALLEL_DECODE_MIN_BYTES { chunks.parallel_decompressor(false) } else { Err(chunks) };
        // The exr crate's decoders can panic on hostile compressed data (its
        // B44 decoder subtracts with overflow on some blocks); that is a
        // damaged file, said as one, not a crash.
        let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| -> Result<()> {
            match parallel {
                Ok(mut decompressor) => {
                    while let Some(block) = decompressor.decompress_next_block() {
                        place(block.map_err(|e| Error::exr(path, e))?)?;
                    }
                }
                Err(chunks) => {
                    let mut decompressor = chunks.sequential_decompressor(false);
                    while let Some(block) = decompressor.decompress_next_block() {
                        place(block.map_err(|e| Error::exr(path, e))?)?;
                    }
                }
            }
            Ok(())
        }));
        decoded.unwrap_or_else(|_| {
            Err(Error::invalid(path, format!("frame {index}: a compressed block could not be decoded (it is damaged)")))
        })?;
        let bad = if self.is_lossy() { first_non_finite(&out) } else { out.first_bad_sample() };
        if let Some((c, j, e, v, value, why)) = bad {
            return Err(Error::BadSample {
                path: path.clone(),
                frame: index,
                hololine: region.hololines.start + j,
                emitter: region.emitters.start + e,
                view: region.views.start + v,
                channel: g.channels[c].name.clone(),
                value,
                why,
            });
        }
        Ok(out)
    }
}

/// Negative samples set to +0: the undershoot a lossy codec (B44's 4×4
/// blocks, DWA's DCT) adds next to dark samples, which is not light (spec
/// §3.4).
fn clamp_undershoot(m: &mut Modulation) {
    for x in m.samples_mut() {
        if *x < 0.0 {
            *x = 0.0;
        }
    }
}

/// The first NaN or infinite sample, as [`Modulation::first_bad_sample`]
/// reports it; negative values pass.
fn first_non_finite(m: &Modulation) -> Option<(usize, usize, usize, usize, f32, &'static str)> {
    if m.samples().iter().all(|x| x.is_finite()) {
        return None;
    }
    let mut clamped = m.clone();
    clamp_undershoot(&mut clamped);
    clamped.first_bad_sample()
}

/// The geometry of a region: positions and view angles of what it holds.
fn sub_geometry(g: &Geometry, r: &Region) -> Geometry {
    let mut s = g.clone();
    s.hololines = r.hololines.len();
    s.emitters = r.emitters.len();
    s.hololine_top_y_m = g.hololine_y_m(r.hololines.start);
    s.emitter_left_x_m = g.emitter_x_m(r.emitters.start);
    s.views.count = r.views.len();
    s.views.first_theta_rad = g.views.theta_rad(r.views.start);
    s.views.last_theta_rad = g.views.theta_rad(r.views.end - 1);
    if let ViewSpacing::Explicit(list) = &g.views.spacing {
        s.views.spacing = ViewSpacing::Explicit(list[r.views.clone()].to_vec());
    }
    s
}

/// Copy the samples of one decoded block that fall inside the region.
fn place_block(
    out: &mut Modulation,
    block: &exr::block::UncompressedBlock,
    order: &ChannelOrder,
    sample_type: SampleType,
    data_x: usize,
    data_y: usize,
    region: &Region,
) -> std::result::Result<(), String> {
    let (bx, by) = (block.index.pixel_position.0 + data_x, block.index.pixel_position.1 + data_y);
    let (w, h) = (block.index.pixel_size.0, block.index.pixel_size.1);
    let bytes = sample_type.bytes();
    let expected = w * h * order.len() * bytes;
    if block.data.len() != expected {
        return Err(format!("a block holds {} bytes where {expected} were expected", block.data.len()));
    }
    let views = out.geometry().views.count;
    let emitters_out = out.geometry().emitters;
    let (e_lo, e_hi) = (region.emitters.start.max(bx), region.emitters.end.min(bx + w));
    let (mut halves, mut floats) = (Vec::with_capacity(w), Vec::with_capacity(w));
    let mut at = 0;
    for line in 0..h {
        let j = by + line;
        let row_wanted = region.hololines.contains(&j);
        for slot in 0..order.len() {
            let row = &block.data[at..at + w * bytes];
            at += w * bytes;
            let (v, c) = order.pair_at(slot);
            if !row_wanted || !region.views.contains(&v) || e_lo >= e_hi {
                continue;
            }
            let jj = j - region.hololines.start;
            let vv = v - region.views.start;
            let start = out.index(c, jj, 0, 0);
            let dest = &mut out.samples_mut()[start..start + emitters_out * views];
            // The wanted run of this channel's row, converted as a slice
            // (F16C where the processor has it), then spread with the
            // view stride.
            let run = &row[(e_lo - bx) * bytes..(e_hi - bx) * bytes];
            match sample_type {
                SampleType::F16 => {
                    halves.clear();
                    halves.extend(run.chunks_exact(2).map(|b| half::f16::from_ne_bytes([b[0], b[1]])));
                    floats.resize(halves.len(), 0.0);
                    halves.convert_to_f32_slice(&mut floats);
                }
                SampleType::F32 => {
                    floats.clear();
                    floats.extend(run.chunks_exact(4).map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]])));
                }
            }
            let first = e_lo - region.emitters.start;
            for (x, d) in floats.iter().zip(dest[first * views + vv..].iter_mut().step_by(views)) {
                *d = *x;
            }
        }
    }
    Ok(())
}
