//! Reading `.holo` files lazily: [`HoloFile::open`] reads and checks the
//! headers only; [`HoloFile::read_frame`] and [`HoloFile::read_region`] then
//! decode only the chunks that hold the frame or region asked for.

use std::ops::Range;
use std::path::{Path, PathBuf};

use std::io::Read;

use exr::block::chunk::Chunk;
use exr::block::{BlockIndex, UncompressedBlock};
use exr::meta::MetaData;

use super::channels::{colour_slots, ChannelOrder};

use super::digest::{frame_digest, row_bytes, stored_row, BlockDigest, PartBlock, PartDigests, RowDigest};
use super::header::{file_info, FileInfo, Positioned};
use super::{SampleType, MAX_SAMPLES_PER_FRAME};
use crate::error::{Error, Result};
use crate::geometry::{Geometry, ViewSpacing};
use crate::modulation::Modulation;

/// Files smaller than this are decompressed on the calling thread.
const PARALLEL_DECODE_MIN_BYTES: u64 = 1 << 20;

/// A part of a frame: hololines (emitter rows) × emitters × a window of
/// views (all colours).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Region {
    /// Hololines (rows) to read.
    pub hololines: Range<usize>,
    /// Emitters (columns) to read.
    pub emitters: Range<usize>,
    /// (Horizontal) views to read.
    pub views: Range<usize>,
    /// Vertical views to read (full parallax, spec §8); `0..1` for
    /// horizontal parallax.
    pub vertical_views: Range<usize>,
}

impl Region {
    /// The whole of a geometry.
    pub fn all(g: &Geometry) -> Self {
        Region {
            hololines: 0..g.hololines,
            emitters: 0..g.emitters,
            views: 0..g.views.count,
            vertical_views: 0..g.vertical_view_count(),
        }
    }
}

/// An open `.holo` file whose headers have been read and checked.
#[derive(Debug)]
pub struct HoloFile {
    info: FileInfo,
    container: Container,
}

/// Read frame 0 of a file whole, checking its digest.
pub fn read(path: impl AsRef<Path>) -> Result<Modulation> {
    HoloFile::open(path)?.read_frame(0)
}

impl HoloFile {
    /// Read and check the headers, each against its digest (spec §7.2); no
    /// pixel data is touched.
    pub fn open(path: impl AsRef<Path>) -> Result<Self> {
        let (info, meta, headers_end) = file_info(path.as_ref(), true)?;
        Ok(HoloFile { info, container: Container::new(meta, headers_end) })
    }

    /// Open a file whose header digests are not yet filled in: the writer's
    /// own, read back before it is finished.
    pub(crate) fn open_unsealed(path: &Path) -> Result<Self> {
        let (info, meta, headers_end) = file_info(path, false)?;
        Ok(HoloFile { info, container: Container::new(meta, headers_end) })
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
        let samples = self.read_frame_samples::<f32>(index)?;
        Modulation::from_samples(self.info.geometry.clone(), samples)
    }

    /// Frame `index` whole as samples of type `T`, in [`Modulation`]'s order
    /// (channel, hololine, emitter, view), its digest verified: `f32`, or
    /// `half::f16` to have a file's f16 samples as they are stored, without
    /// a pass through f32 (an f32 file's samples are rounded, and one too
    /// large for f16 is refused).
    pub fn read_frame_samples<T: FrameSample>(&self, index: usize) -> Result<Vec<T>> {
        let frame = self.info.frames.get(index);
        // A full-parallax frame's view digests cover the stored samples,
        // which an f32 file's, rounded to f16, no longer are: it is read as
        // stored, checked, then narrowed.
        if narrows::<T>(self.info.sample_type) && frame.is_some_and(|f| !f.views.is_empty()) {
            let narrow: Vec<T> = self.read_frame_samples::<f32>(index)?.into_iter().map(T::from_f32).collect();
            let g = &self.info.geometry;
            self.check_samples(index, &Region::all(g), g, &narrow)?;
            return Ok(narrow);
        }
        // The digest is taken from the decoded blocks' own bytes as they come
        // (they are the stored rows), not from the samples afterwards.
        // (Blocks hold native-endian samples, the digest little-endian ones.)
        let from_blocks = cfg!(target_endian = "little") && frame.is_some_and(|f| f.views.is_empty());
        let mut digest = frame
            .filter(|f| f.digest.is_some() && from_blocks)
            .map(|f| BlockDigest::new(&self.info.geometry, self.info.sample_type, f.data_window));
        // A full-parallax frame's views' digests likewise, from each part's blocks.
        let view_digests = frame.filter(|f| !f.views.is_empty() && cfg!(target_endian = "little")).map(|f| {
            PartDigests::new(&self.info.geometry, self.info.sample_type, f.views.iter().map(|v| v.data_window))
        });
        let mut samples: Vec<T> =
            self.read_blocks(index, &Region::all(&self.info.geometry), digest.as_mut(), view_digests.as_ref())?;
        let frame = &self.info.frames[index];
        if !frame.views.is_empty() {
            match view_digests {
                Some(digests) => self.check_part_digests(index, digests.finish())?,
                None => self.check_view_digests(index, &samples)?,
            }
        }
        if let Some(stored) = &frame.digest {
            let computed = match digest.and_then(BlockDigest::finish) {
                Some(computed) => computed,
                None => {
                    // Rare (no hashing thread, or a big-endian machine): the
                    // digest of the samples, widened exactly to f32.
                    let widened = samples.iter().map(|x| x.to_f32()).collect();
                    frame_digest(&Modulation::from_samples(self.info.geometry.clone(), widened)?, self.info.sample_type)
                }
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
            clamp_undershoot(&mut samples);
        }
        Ok(samples)
    }

    /// Read one region of frame `index`; only the chunks holding its hololines
    /// are read and decompressed. The digest cannot be checked on a part.
    pub fn read_region(&self, index: usize, region: &Region) -> Result<Modulation> {
        let samples = self.read_region_samples::<f32>(index, region)?;
        Modulation::from_samples(sub_geometry(&self.info.geometry, region), samples)
    }

    /// [`HoloFile::read_region`] as samples of type `T` (see
    /// [`HoloFile::read_frame_samples`]), in the order of a [`Modulation`] of
    /// the region.
    pub fn read_region_samples<T: FrameSample>(&self, index: usize, region: &Region) -> Result<Vec<T>> {
        let mut samples = self.read_blocks(index, region, None, None)?;
        if self.is_lossy() {
            clamp_undershoot(&mut samples);
        }
        Ok(samples)
    }

    /// Frame `index` a band of `band_rows` hololines (emitter rows) at a
    /// time, top to bottom, each band handed to `each` with its rows as
    /// [`HoloFile::read_region`] gives it (every emitter, every view), so
    /// memory is a band, not the frame. Every digest of the frame (its
    /// frame digest, or each view's) is taken over the bands as they are read
    /// and checked after the last: an error then comes after every band was
    /// handed on, so a caller that makes something of the bands must not keep
    /// it until this returns `Ok`.
    pub fn read_frame_in_bands(
        &self,
        index: usize,
        band_rows: usize,
        mut each: impl FnMut(Range<usize>, Modulation) -> Result<()>,
    ) -> Result<()> {
        let info = &self.info;
        let (g, sample_type) = (&info.geometry, info.sample_type);
        let frame = info.frames.get(index).ok_or_else(|| Error::no_frame(&info.path, index, info.frames.len()))?;
        // A full-parallax frame's views' digests from their parts' blocks (on
        // a little-endian machine, where they are the stored bytes), else
        // from the samples.
        let from_blocks = !frame.views.is_empty() && cfg!(target_endian = "little");
        let part_digests =
            from_blocks.then(|| PartDigests::new(g, sample_type, frame.views.iter().map(|v| v.data_window)));
        let mut view_digests = (!frame.views.is_empty() && !from_blocks).then(|| ViewDigests::new(g, sample_type));
        let order = ChannelOrder::new(g);
        let mut row = vec![0u8; row_bytes(g, sample_type)];
        let mut digest = frame.digest.as_ref().map(|_| RowDigest::default());
        for top in (0..g.hololines).step_by(band_rows.max(1)) {
            let rows = top..(top + band_rows.max(1)).min(g.hololines);
            let region = Region { hololines: rows.clone(), ..Region::all(g) };
            // As decoded (a lossy file's undershoot included), as the digests are.
            let samples = self.read_blocks::<f32>(index, &region, None, part_digests.as_ref())?;
            let mut band = Modulation::from_samples(sub_geometry(g, &region), samples)?;
            if let Some(digests) = &mut view_digests {
                digests.push(band.samples(), rows.len());
            }
            if let Some(digest) = &mut digest {
                for line in 0..rows.len() {
                    stored_row(g, &order, sample_type, |c| band.hololine(c, line), &mut row);
                    digest.update(&row);
                }
            }
            if self.is_lossy() {
                clamp_undershoot(band.samples_mut());
            }
            each(rows, band)?;
        }
        if let Some(digests) = view_digests {
            digests.check(info, index)?;
        }
        if let Some(digests) = part_digests {
            self.check_part_digests(index, digests.finish())?;
        }
        if let (Some(stored), Some(digest)) = (&frame.digest, digest) {
            let computed = digest.finish();
            if &computed != stored {
                return Err(Error::DigestMismatch {
                    path: info.path.clone(),
                    frame: index,
                    stored: stored.clone(),
                    computed,
                });
            }
        }
        Ok(())
    }

    /// View `(h, k)` of frame `index` of a full-parallax file (`k` = 0 for
    /// horizontal parallax: then every view is read, as one part holds
    /// them), its digest checked: of a full-parallax file only that view's
    /// part is read and decoded (spec §8).
    pub fn read_view(&self, index: usize, h: usize, k: usize) -> Result<Modulation> {
        let info = &self.info;
        let g = &info.geometry;
        let frame = info.frames.get(index).ok_or_else(|| Error::no_frame(&info.path, index, info.frames.len()))?;
        if h >= g.views.count || k >= g.vertical_view_count() {
            return Err(Error::argument(
                "view",
                format!(
                    "{}: view ({h} {k}) is not one of its {} × {} views",
                    info.path.display(),
                    g.views.count,
                    g.vertical_view_count()
                ),
            ));
        }
        let region = Region { views: h..h + 1, vertical_views: k..k + 1, ..Region::all(g) };
        if frame.views.is_empty() {
            // One part holds every view: the frame is read, and its digest checked, whole.
            let m = self.read_frame(index)?;
            let (rows, emitters) = (g.hololines, g.emitters);
            let samples = (0..g.channels.len())
                .flat_map(|c| (0..rows).flat_map(move |j| (0..emitters).map(move |e| (c, j, e))))
                .map(|(c, j, e)| m.get(c, j, e, g.view_index(h, k)))
                .collect();
            return Modulation::from_samples(sub_geometry(g, &region), samples);
        }
        let mut view = self.read_decoded(index, &region)?;
        let mut digest = ViewDigests::new(view.geometry(), info.sample_type);
        digest.push(view.samples(), g.hololines);
        let computed = digest.finish().pop().expect("one view");
        if let Some(stored) = &frame.views[g.view_index(h, k)].digest {
            if &computed != stored {
                return Err(view_damaged(&info.path, index, (h, k), stored, &computed));
            }
        }
        if self.is_lossy() {
            clamp_undershoot(view.samples_mut());
        }
        Ok(view)
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
        let samples = self.read_blocks::<f32>(index, region, None, None)?;
        Modulation::from_samples(sub_geometry(&self.info.geometry, region), samples)
    }

    /// Each view's digest (spec §8, §7.1), computed from its part's blocks
    /// (in the order of the frame's views), against the one stored.
    fn check_part_digests(&self, index: usize, computed: Vec<String>) -> Result<()> {
        let (g, frame) = (&self.info.geometry, &self.info.frames[index]);
        for (v, (computed, view)) in computed.iter().zip(&frame.views).enumerate() {
            if let Some(stored) = &view.digest {
                if computed != stored {
                    return Err(view_damaged(&self.info.path, index, g.view_of_index(v), stored, computed));
                }
            }
        }
        Ok(())
    }

    /// Each view's digest (spec §8, §7.1) against the samples of a whole
    /// full-parallax frame as read.
    fn check_view_digests<T: FrameSample>(&self, index: usize, samples: &[T]) -> Result<()> {
        let mut digests = ViewDigests::new(&self.info.geometry, self.info.sample_type);
        digests.push(samples, self.info.geometry.hololines);
        digests.check(&self.info, index)
    }

    /// The samples of a region as decoded (see [`HoloFile::read_decoded`]),
    /// handing every decoded block's bytes to `digest` (a horizontal-parallax
    /// frame's) or `view_digests` (a full-parallax frame's views) too (whole
    /// frames only).
    fn read_blocks<T: FrameSample>(
        &self,
        index: usize,
        region: &Region,
        mut digest: Option<&mut BlockDigest>,
        view_digests: Option<&PartDigests>,
    ) -> Result<Vec<T>> {
        let path = &self.info.path;
        let g = &self.info.geometry;
        let frame = self.info.frames.get(index).ok_or_else(|| Error::no_frame(path, index, self.info.frames.len()))?;
        let ok = |r: &Range<usize>, n: usize| r.start < r.end && r.end <= n;
        if !ok(&region.hololines, g.hololines)
            || !ok(&region.emitters, g.emitters)
            || !ok(&region.views, g.views.count)
            || !ok(&region.vertical_views, g.vertical_view_count())
        {
            let vertical = match g.vertical_views {
                Some(_) => format!(", vertical views {:?}", region.vertical_views),
                None => String::new(),
            };
            let vertical_count = match &g.vertical_views {
                Some(v) => format!("×{}", v.count),
                None => String::new(),
            };
            return Err(Error::argument(
                "region",
                format!(
                    "{}: region hololines {:?}, emitters {:?}, views {:?}{vertical} is empty or outside {}×{}×{}{vertical_count}",
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
        let len = usize::try_from(sub.samples_per_frame()).map_err(|_| {
            Error::argument("region", format!("{}: a region of {} samples", path.display(), sub.samples_per_frame()))
        })?;
        let mut out = T::zeroed(len);
        let order = ChannelOrder::new(g);
        let wanted = Wanted::new(g, frame, region);
        let wanted_rows = region.hololines.clone();
        let colours = colour_slots(g);
        let st = self.info.sample_type;
        let mut place = |blocks: Vec<UncompressedBlock>| -> Result<()> {
            if !frame.views.is_empty() {
                // Full parallax: a part per view, placed a batch at a time.
                let blocks: Vec<(&WantedPart, UncompressedBlock)> =
                    blocks.into_iter().filter_map(|b| Some((wanted.part(b.index.layer)?, b))).collect();
                if let Some(digests) = view_digests {
                    let mut rows: Vec<PartBlock<'_>> = blocks
                        .iter()
                        .map(|(part, b)| {
                            let top = part.window.y + b.index.pixel_position.1;
                            // A whole frame's: each part's index among the region's views is its view's.
                            let view = part.sub_view.unwrap_or(usize::MAX);
                            (view, top, b.index.pixel_size.1, b.data.as_slice())
                        })
                        .collect();
                    digests.push_batch(&mut rows);
                }
                return place_view_blocks(&mut out, &sub, &blocks, &colours, st, region)
                    .map_err(|problem| Error::invalid(path, problem));
            }
            for block in blocks {
                let Some(part) = wanted.part(block.index.layer) else { continue };
                let dw = part.window;
                let target = |slot| {
                    let (v, c) = order.pair_at(slot);
                    region.views.contains(&v).then(|| (c, v - region.views.start))
                };
                place_block(&mut out, &sub, &block, order.len(), target, st, dw.x, dw.y, region)
                    .map_err(|problem| Error::invalid(path, problem))?;
                if let Some(digest) = digest.as_deref_mut() {
                    digest.push(dw.y + block.index.pixel_position.1, block.index.pixel_size.1, block.data);
                }
            }
            Ok(())
        };
        // The exr crate's decoders can panic on hostile compressed data (its
        // B44 decoder subtracts with overflow on some blocks); that is a
        // damaged file, said as one, not a crash.
        let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            self.container.decode(path, &wanted, &wanted_rows, &mut place)
        }));
        decoded.unwrap_or_else(|_| {
            Err(Error::invalid(path, format!("frame {index}: a compressed block could not be decoded (it is damaged)")))
        })?;
        self.check_samples(index, region, &sub, &out)?;
        Ok(out)
    }

    /// The first sample of `region` of frame `index` (`samples`, laid out as
    /// a [`Modulation`] of `sub`, the region's geometry) that is not finite,
    /// or (unless the compression is lossy) negative, as the error naming
    /// it in the frame.
    fn check_samples<T: FrameSample>(
        &self,
        index: usize,
        region: &Region,
        sub: &Geometry,
        samples: &[T],
    ) -> Result<()> {
        let g = &self.info.geometry;
        let Some((c, j, e, v, value, why)) = first_bad(sub, samples, self.is_lossy(), self.info.sample_type) else {
            return Ok(());
        };
        let (h, k) = sub.view_of_index(v);
        Err(Error::BadSample {
            path: self.info.path.clone(),
            frame: index,
            hololine: region.hololines.start + j,
            emitter: region.emitters.start + e,
            view: region.views.start + h,
            vertical_view: g.vertical_views.as_ref().map(|_| region.vertical_views.start + k),
            channel: g.channels[c].name.clone(),
            value,
            why,
        })
    }
}

/// A type a frame's samples can be read into ([`HoloFile::read_frame_samples`]):
/// `f32`, holo's working type, or `half::f16`, the type most files store.
/// Its methods are the reader's; the two implementations are the only ones.
pub trait FrameSample: Copy + Send + Sync + 'static {
    /// `len` zeros (+0.0), in huge pages where the buffer is large.
    #[doc(hidden)]
    fn zeroed(len: usize) -> Vec<Self>;
    /// Stored samples (native-endian bytes of `stored`) into every
    /// `stride`-th place of `dest`, from its first.
    #[doc(hidden)]
    fn scatter(run: &[u8], stored: SampleType, dest: &mut [Self], stride: usize);
    /// Stored samples (native-endian bytes of `stored`) into `dest`, one
    /// for one.
    #[doc(hidden)]
    fn convert(run: &[u8], stored: SampleType, dest: &mut [Self]);
    /// Finite and not negative (`-0` allowed); with `lossy`, only finite.
    #[doc(hidden)]
    fn is_good(self, lossy: bool) -> bool;
    /// The value, exactly.
    #[doc(hidden)]
    fn to_f32(self) -> f32;
    /// The nearest value to `x` (an f32 too large for f16 is infinite).
    #[doc(hidden)]
    fn from_f32(x: f32) -> Self;
    /// `+0` for a negative value (a lossy codec's undershoot, spec §3.4).
    #[doc(hidden)]
    fn clamped(self) -> Self;
}

impl FrameSample for f32 {
    fn zeroed(len: usize) -> Vec<f32> {
        crate::memory::zeroed_f32(len)
    }
    fn convert(run: &[u8], stored: SampleType, dest: &mut [f32]) {
        match stored {
            SampleType::F16 => halves_to_f32(run, dest, crate::simd::Simd::Detect),
            SampleType::F32 => {
                for (b, d) in run.chunks_exact(4).zip(dest) {
                    *d = f32::from_ne_bytes([b[0], b[1], b[2], b[3]]);
                }
            }
        }
    }
    fn scatter(run: &[u8], stored: SampleType, dest: &mut [f32], stride: usize) {
        let mut dest = dest.iter_mut().step_by(stride);
        match stored {
            SampleType::F16 => {
                // Converted a piece at a time on the stack, then spread
                // with the stride.
                const AT_ONCE: usize = 64;
                let mut floats = [0f32; AT_ONCE];
                for piece in run.chunks(2 * AT_ONCE) {
                    let n = piece.len() / 2;
                    halves_to_f32(piece, &mut floats[..n], crate::simd::Simd::Detect);
                    for (x, d) in floats[..n].iter().zip(dest.by_ref()) {
                        *d = *x;
                    }
                }
            }
            SampleType::F32 => {
                for (b, d) in run.chunks_exact(4).zip(dest) {
                    *d = f32::from_ne_bytes([b[0], b[1], b[2], b[3]]);
                }
            }
        }
    }
    fn is_good(self, lossy: bool) -> bool {
        if lossy {
            self.is_finite()
        } else {
            (0.0..=f32::MAX).contains(&self)
        }
    }
    fn to_f32(self) -> f32 {
        self
    }
    fn from_f32(x: f32) -> f32 {
        x
    }
    fn clamped(self) -> f32 {
        if self < 0.0 {
            0.0
        } else {
            self
        }
    }
}

impl FrameSample for half::f16 {
    fn zeroed(len: usize) -> Vec<half::f16> {
        crate::memory::zeroed_f16(len)
    }
    fn convert(run: &[u8], stored: SampleType, dest: &mut [half::f16]) {
        match stored {
            SampleType::F16 => {
                for (b, d) in run.chunks_exact(2).zip(dest) {
                    *d = half::f16::from_ne_bytes([b[0], b[1]]);
                }
            }
            SampleType::F32 => {
                for (b, d) in run.chunks_exact(4).zip(dest) {
                    *d = half::f16::from_f32(f32::from_ne_bytes([b[0], b[1], b[2], b[3]]));
                }
            }
        }
    }
    fn scatter(run: &[u8], stored: SampleType, dest: &mut [half::f16], stride: usize) {
        // Straight from the stored bytes to their places: no pass through f32.
        let dest = dest.iter_mut().step_by(stride);
        match stored {
            SampleType::F16 => {
                for (b, d) in run.chunks_exact(2).zip(dest) {
                    *d = half::f16::from_ne_bytes([b[0], b[1]]);
                }
            }
            SampleType::F32 => {
                for (b, d) in run.chunks_exact(4).zip(dest) {
                    *d = half::f16::from_f32(f32::from_ne_bytes([b[0], b[1], b[2], b[3]]));
                }
            }
        }
    }
    fn is_good(self, lossy: bool) -> bool {
        // By bits: exponent all ones is an infinity or NaN; the sign bit set
        // on anything but zero is negative.
        let bits = self.to_bits();
        let finite = bits & 0x7c00 != 0x7c00;
        finite && (lossy || bits & 0x8000 == 0 || bits == 0x8000)
    }
    fn to_f32(self) -> f32 {
        f32::from(self)
    }
    fn from_f32(x: f32) -> half::f16 {
        half::f16::from_f32(x)
    }
    fn clamped(self) -> half::f16 {
        if self.to_bits() & 0x8000 != 0 {
            half::f16::ZERO
        } else {
            self
        }
    }
}

/// Native-endian f16 samples (`run`, two bytes each) into `dest`, one for
/// one (the shorter decides): eight at a time by F16C where `simd` allows
/// it (half's slice conversion spends more on its short-slice handling
/// than on converting runs of a few dozen samples), else one by one.
fn halves_to_f32(run: &[u8], dest: &mut [f32], simd: crate::simd::Simd) {
    let n = dest.len().min(run.len() / 2);
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if simd.f16c() {
        // SAFETY: F16C and AVX are present (checked just above).
        done = unsafe { halves_to_f32_f16c(&run[..2 * n], &mut dest[..n]) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = simd;
    for (b, d) in run[2 * done..2 * n].chunks_exact(2).zip(&mut dest[done..n]) {
        *d = half::f16::from_ne_bytes([b[0], b[1]]).to_f32();
    }
}

/// The whole groups of eight of [`halves_to_f32`]; returns how many samples
/// it converted. Callers guarantee `run.len() == 2 · dest.len()`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "f16c,avx")]
unsafe fn halves_to_f32_f16c(run: &[u8], dest: &mut [f32]) -> usize {
    use std::arch::x86_64::{__m128i, _mm256_cvtph_ps, _mm256_storeu_ps, _mm_loadu_si128};
    let groups = dest.len() / 8;
    for g in 0..groups {
        // SAFETY: the load reads 16 bytes at 16g <= run.len() - 16, the store
        // writes 8 floats at 8g <= dest.len() - 8.
        unsafe {
            let halves = _mm_loadu_si128(run.as_ptr().add(16 * g).cast::<__m128i>());
            _mm256_storeu_ps(dest.as_mut_ptr().add(8 * g), _mm256_cvtph_ps(halves));
        }
    }
    8 * groups
}

/// Negative samples set to +0: the undershoot a lossy codec (B44's 4×4
/// blocks, DWA's DCT) adds next to dark samples, which is not light (spec
/// §3.4).
fn clamp_undershoot<T: FrameSample>(samples: &mut [T]) {
    for x in samples {
        *x = x.clamped();
    }
}

/// The first sample of `samples` (laid out as a [`Modulation`] of `g`) that
/// is not finite, or (unless `lossy`) negative. An f32 file's sample read
/// as f16 can be infinite only by being too large for f16.
fn first_bad<T: FrameSample>(
    g: &Geometry,
    samples: &[T],
    lossy: bool,
    stored: SampleType,
) -> Option<(usize, usize, usize, usize, f32, &'static str)> {
    // A branch-free scan first (frames are tens of millions of samples),
    // then the search for the first offender.
    let all_good = {
        use rayon::prelude::*;
        samples.par_chunks(1 << 16).all(|chunk| chunk.iter().fold(true, |ok, x| ok & x.is_good(lossy)))
    };
    if all_good {
        return None;
    }
    let i = samples.iter().position(|x| !x.is_good(lossy))?;
    let x = samples[i].to_f32();
    let views = g.views_per_emitter();
    let (v, e) = (i % views, (i / views) % g.emitters);
    let j = (i / (views * g.emitters)) % g.hololines;
    let c = i / (views * g.emitters * g.hololines);
    let why = if x.is_nan() {
        "not a number"
    } else if x.is_infinite() && narrows::<T>(stored) {
        "too large for f16 (read it as f32)"
    } else if x.is_infinite() {
        "infinite"
    } else {
        "negative (radiance cannot be)"
    };
    Some((c, j, e, v, x, why))
}

/// Whether samples stored as `stored` are rounded when read as `T` (f32
/// samples read as f16).
fn narrows<T: FrameSample>(stored: SampleType) -> bool {
    std::any::TypeId::of::<T>() == std::any::TypeId::of::<half::f16>() && stored == SampleType::F32
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
    if let (Some(all), Some(sub)) = (&g.vertical_views, &mut s.vertical_views) {
        let k = &r.vertical_views;
        sub.count = k.len();
        sub.first_theta_rad = all.theta_rad(k.start);
        sub.last_theta_rad = all.theta_rad(k.end - 1);
        if let ViewSpacing::Explicit(list) = &all.spacing {
            sub.spacing = ViewSpacing::Explicit(list[k.clone()].to_vec());
        }
    }
    s
}

/// What reading chunks needs of a file's container, kept from opening it:
/// the headers as OpenEXR's meta data, parsed once, and where each part's
/// offset table is. A read then touches only the offset tables and chunks of
/// the parts it wants: one view of a full-parallax frame (a part, spec §8)
/// costs its own chunks, not the frame's thousand headers.
#[derive(Debug)]
struct Container {
    meta: MetaData,
    /// Byte position of each part's offset table.
    table_at: Vec<u64>,
    /// Where the offset tables end: no chunk starts before.
    tables_end: u64,
}

/// Compressed chunks are read and decoded in batches of about this many
/// decoded bytes: enough to keep every core busy, bounded whatever the frame.
const DECODE_BATCH_BYTES: usize = 32 << 20;

impl Container {
    /// The meta data of a file whose headers end at byte `headers_end`
    /// (the offset tables follow, one after another in part order).
    fn new(meta: MetaData, headers_end: u64) -> Container {
        let mut at = headers_end;
        let table_at = meta
            .headers
            .iter()
            .map(|h| {
                let here = at;
                at += 8 * h.chunk_count as u64;
                here
            })
            .collect();
        Container { meta, table_at, tables_end: at }
    }

    /// Decode the chunks of the `wanted` parts that hold rows `rows`
    /// (absolute), handing each batch of decoded blocks to `place`, in file
    /// order, the batches decoded on every core for a file of a megabyte or
    /// more.
    fn decode(
        &self,
        path: &Path,
        wanted: &Wanted,
        rows: &Range<usize>,
        place: &mut dyn FnMut(Vec<UncompressedBlock>) -> Result<()>,
    ) -> Result<()> {
        let damaged = |what: String| Error::invalid(path, format!("{what}: the file is damaged"));
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let file_bytes = file.metadata().map_err(|e| Error::io(path, e))?.len();
        let mut file = Positioned::new(file);
        // (offset, block) of every chunk wanted.
        let mut chunks: Vec<(u64, BlockIndex)> = Vec::new();
        for (layer, part) in wanted.parts() {
            let header = self.meta.headers.get(layer).ok_or_else(|| damaged(format!("part {layer} has no header")))?;
            let mut table = vec![0u8; 8 * header.chunk_count];
            file.seek_to(self.table_at[layer]).map_err(|e| Error::io(path, e))?;
            file.read_exact(&mut table).map_err(|e| Error::io(path, e))?;
            let offsets = table.chunks_exact(8).map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")));
            for (offset, tile) in offsets.zip(header.blocks_increasing_y_order()) {
                if tile.location.level_index != exr::math::Vec2(0, 0) {
                    continue;
                }
                let at = header.get_absolute_block_pixel_coordinates(tile.location).map_err(|e| Error::exr(path, e))?;
                let (Ok(x), Ok(y)) = (usize::try_from(at.position.x()), usize::try_from(at.position.y())) else {
                    return Err(damaged(format!("part {layer} has a block before its data window")));
                };
                let top = part.window.y + y;
                if top >= rows.end || top + at.size.height() <= rows.start {
                    continue;
                }
                if offset >= file_bytes {
                    return Err(Error::invalid(
                        path,
                        format!(
                            "part {layer} has a chunk at byte {offset}, past the end of the {file_bytes}-byte file: the file is truncated"
                        ),
                    ));
                }
                if offset < self.tables_end {
                    return Err(damaged(format!(
                        "part {layer}'s offset table points at byte {offset}, before the chunks begin (byte {})",
                        self.tables_end
                    )));
                }
                let block = BlockIndex {
                    layer,
                    level: exr::math::Vec2(0, 0),
                    pixel_position: exr::math::Vec2(x, y),
                    pixel_size: at.size,
                };
                chunks.push((offset, block));
            }
        }
        // In file order: a whole frame is read front to back.
        chunks.sort_unstable_by_key(|&(offset, _)| offset);
        let parallel = file_bytes >= PARALLEL_DECODE_MIN_BYTES;
        let mut batch: Vec<(Chunk, BlockIndex)> = Vec::new();
        let mut batch_bytes = 0;
        let mut chunks = chunks.into_iter().peekable();
        while let Some((offset, block)) = chunks.next() {
            let layer = block.layer;
            file.seek_to(offset).map_err(|e| Error::io(path, e))?;
            let chunk = Chunk::read(&mut file, &self.meta).map_err(|e| Error::exr(path, e))?;
            if chunk.layer_index != layer {
                return Err(damaged(format!(
                    "the chunk at byte {offset} says part {}, where part {layer}'s offset table points",
                    chunk.layer_index
                )));
            }
            batch_bytes += self.meta.headers[layer].max_block_byte_size();
            batch.push((chunk, block));
            if batch_bytes >= DECODE_BATCH_BYTES || chunks.peek().is_none() {
                let decode = |(chunk, block): (Chunk, BlockIndex)| -> Result<UncompressedBlock> {
                    let decoded = UncompressedBlock::decompress_chunk(chunk, &self.meta, false)
                        .map_err(|e| Error::exr(path, e))?;
                    if decoded.index != block {
                        return Err(damaged(format!(
                            "a chunk of part {} is not the block its offset says",
                            block.layer
                        )));
                    }
                    Ok(decoded)
                };
                let decoded: Result<Vec<UncompressedBlock>> = if parallel && batch.len() > 1 {
                    use rayon::prelude::*;
                    std::mem::take(&mut batch).into_par_iter().map(decode).collect()
                } else {
                    std::mem::take(&mut batch).into_iter().map(decode).collect()
                };
                place(decoded?)?;
                batch_bytes = 0;
            }
        }
        Ok(())
    }
}

/// The parts a region read decodes, with where each one's samples go.
struct Wanted {
    /// The frame's first part.
    first: usize,
    /// By part from `first`: its data window, and for full parallax the
    /// index among the region's views of the view it holds.
    parts: Vec<Option<WantedPart>>,
}

#[derive(Clone, Copy)]
struct WantedPart {
    window: super::Window,
    sub_view: Option<usize>,
}

impl Wanted {
    fn new(g: &Geometry, frame: &super::FrameInfo, region: &Region) -> Wanted {
        if frame.views.is_empty() {
            let part = WantedPart { window: frame.data_window, sub_view: None };
            return Wanted { first: frame.part, parts: vec![Some(part)] };
        }
        let mut parts = vec![None; frame.views.len()];
        for (kk, k) in region.vertical_views.clone().enumerate() {
            for (hh, h) in region.views.clone().enumerate() {
                let view = &frame.views[g.view_index(h, k)];
                let sub_view = kk * region.views.len() + hh;
                parts[view.part - frame.part] = Some(WantedPart { window: view.data_window, sub_view: Some(sub_view) });
            }
        }
        Wanted { first: frame.part, parts }
    }

    fn part(&self, layer: usize) -> Option<&WantedPart> {
        self.parts.get(layer.checked_sub(self.first)?)?.as_ref()
    }

    /// The parts wanted, by their index among the file's parts.
    fn parts(&self) -> impl Iterator<Item = (usize, &WantedPart)> + '_ {
        self.parts.iter().enumerate().filter_map(|(i, p)| Some((self.first + i, p.as_ref()?)))
    }
}

/// Copy the samples of one decoded block that fall inside the region into
/// `out`, the region's samples laid out as a [`Modulation`] of `sub`. The
/// block holds `channels` channels; `target(slot)` says where the channel at
/// list position `slot` goes: its colour and its index among the region's
/// views (`None`: a view outside the region). A horizontal-parallax part
/// holds every view ([`ChannelOrder`]); a full-parallax part one (spec §8),
/// its channels the colours.
#[allow(clippy::too_many_arguments)]
fn place_block<T: FrameSample>(
    out: &mut [T],
    sub: &Geometry,
    block: &UncompressedBlock,
    channels: usize,
    target: impl Fn(usize) -> Option<(usize, usize)>,
    sample_type: SampleType,
    data_x: usize,
    data_y: usize,
    region: &Region,
) -> std::result::Result<(), String> {
    let (bx, by) = (block.index.pixel_position.0 + data_x, block.index.pixel_position.1 + data_y);
    let (w, h) = (block.index.pixel_size.0, block.index.pixel_size.1);
    let bytes = sample_type.bytes();
    let expected = w * h * channels * bytes;
    if block.data.len() != expected {
        return Err(format!("a block holds {} bytes where {expected} were expected", block.data.len()));
    }
    let (views, emitters_out, hololines_out) = (sub.views_per_emitter(), sub.emitters, sub.hololines);
    let (e_lo, e_hi) = (region.emitters.start.max(bx), region.emitters.end.min(bx + w));
    let mut at = 0;
    for line in 0..h {
        let j = by + line;
        let row_wanted = region.hololines.contains(&j);
        for slot in 0..channels {
            let row = &block.data[at..at + w * bytes];
            at += w * bytes;
            let Some((c, vv)) = target(slot).filter(|_| row_wanted && e_lo < e_hi) else { continue };
            let start = (c * hololines_out + j - region.hololines.start) * emitters_out * views;
            let dest = &mut out[start..start + emitters_out * views];
            // The wanted run of this channel's row, spread with the view stride.
            let first = e_lo - region.emitters.start;
            let run = &row[(e_lo - bx) * bytes..(e_hi - bx) * bytes];
            T::scatter(run, sample_type, &mut dest[first * views + vv..], views);
        }
    }
    Ok(())
}

/// Place a batch of decoded blocks of full-parallax view parts (each
/// block's channels the colours, `colours` their channel indices) into
/// `out`, the region's samples laid out as a [`Modulation`] of `sub`.
///
/// In `out` a view's samples lie one in `V·W` apart, so placing block after
/// block would bring in a cache line per sample, once for every view. The
/// batch is placed output line by output line instead (one colour of one
/// emitter row: every emitter's views), lines in parallel: a line takes
/// the runs of every block that holds its row while it stays in cache.
fn place_view_blocks<T: FrameSample>(
    out: &mut [T],
    sub: &Geometry,
    blocks: &[(&WantedPart, UncompressedBlock)],
    colours: &[usize],
    sample_type: SampleType,
    region: &Region,
) -> std::result::Result<(), String> {
    use rayon::prelude::*;
    let bytes = sample_type.bytes();
    let views = sub.views_per_emitter();
    let line_len = sub.emitters * views;
    // (output line, block, first byte of the block's row of that colour).
    let mut runs: Vec<(usize, usize, usize)> = Vec::new();
    for (i, (part, block)) in blocks.iter().enumerate() {
        let (w, h) = (block.index.pixel_size.0, block.index.pixel_size.1);
        let expected = w * h * colours.len() * bytes;
        if block.data.len() != expected {
            return Err(format!("a block holds {} bytes where {expected} were expected", block.data.len()));
        }
        if !matches!(part.sub_view, Some(v) if v < views) {
            continue;
        }
        let by = block.index.pixel_position.1 + part.window.y;
        for line in 0..h {
            let j = by + line;
            if !region.hololines.contains(&j) {
                continue;
            }
            for (slot, &c) in colours.iter().enumerate() {
                let out_line = c * sub.hololines + j - region.hololines.start;
                runs.push((out_line, i, (line * colours.len() + slot) * w * bytes));
            }
        }
    }
    let (Some(first), Some(last)) = (runs.iter().map(|r| r.0).min(), runs.iter().map(|r| r.0).max()) else {
        return Ok(());
    };
    // By output line (a counting sort: the batch comes block by block).
    let mut starts = vec![0usize; last - first + 2];
    for r in &runs {
        starts[r.0 - first + 1] += 1;
    }
    for l in 1..starts.len() {
        starts[l] += starts[l - 1];
    }
    let mut by_line = vec![(0, 0, 0); runs.len()];
    let mut next = starts.clone();
    for r in runs {
        by_line[next[r.0 - first]] = r;
        next[r.0 - first] += 1;
    }
    let lines = &mut out[first * line_len..(last + 1) * line_len];
    let scratch = || (vec![None; views], T::zeroed(0));
    lines.par_chunks_mut(line_len).enumerate().for_each_init(scratch, |(by_view, values), (l, dest)| {
        let (from, to) = (starts[l], starts[l + 1]);
        // Each view's run of this line, converted: where in `values` it
        // starts, and the emitters (of the region) it holds.
        let by_view: &mut Vec<Option<(usize, Range<usize>)>> = by_view;
        by_view.fill(None);
        values.clear();
        for &(_, i, at) in &by_line[from..to] {
            let (part, block) = &blocks[i];
            let (bx, w) = (block.index.pixel_position.0 + part.window.x, block.index.pixel_size.0);
            let (e_lo, e_hi) = (region.emitters.start.max(bx), region.emitters.end.min(bx + w));
            if e_lo < e_hi {
                let start = values.len();
                values.resize(start + e_hi - e_lo, T::from_f32(0.0));
                T::convert(
                    &block.data[at + (e_lo - bx) * bytes..at + (e_hi - bx) * bytes],
                    sample_type,
                    &mut values[start..],
                );
                let held = e_lo - region.emitters.start..e_hi - region.emitters.start;
                by_view[part.sub_view.unwrap_or_default()] = Some((start, held));
            }
        }
        // Tiles of emitters × views: the tile's part of the line (a few
        // dozen cache lines) is written whole while it is in L1.
        for e0 in (0..sub.emitters).step_by(TILE_EMITTERS) {
            let e1 = (e0 + TILE_EMITTERS).min(sub.emitters);
            for v0 in (0..views).step_by(TILE_VIEWS) {
                for (v, run) in by_view.iter().enumerate().take((v0 + TILE_VIEWS).min(views)).skip(v0) {
                    let Some((start, held)) = run else { continue };
                    let (lo, hi) = (e0.max(held.start), e1.min(held.end));
                    if lo >= hi {
                        continue;
                    }
                    let run = &values[start + lo - held.start..];
                    for (e, x) in (lo..hi).zip(run) {
                        dest[e * views + v] = *x;
                    }
                }
            }
        }
    });
    Ok(())
}

/// Emitters and views in a tile of [`place_view_blocks`]. An emitter's
/// views lie `V·W` samples apart, often a power of two: more than eight
/// such rows of a tile would share the L1 sets their lines map to.
const TILE_EMITTERS: usize = 8;
const TILE_VIEWS: usize = 64;

/// The digests of a full-parallax frame's views (spec §8, §7.1), fed emitter
/// row after emitter row (a whole frame, or band by band): each row's stored
/// bytes for every view built in one pass over the row, then hashed view by
/// view in parallel.
pub(crate) struct ViewDigests {
    g: Geometry,
    sample_type: SampleType,
    colours: Vec<usize>,
    digests: Vec<RowDigest>,
    rows: Vec<u8>,
}

impl ViewDigests {
    pub(crate) fn new(g: &Geometry, sample_type: SampleType) -> ViewDigests {
        let colours = colour_slots(g);
        let row_len = colours.len() * g.emitters * sample_type.bytes();
        ViewDigests {
            digests: (0..g.views_per_emitter()).map(|_| RowDigest::default()).collect(),
            rows: vec![0u8; g.views_per_emitter() * row_len],
            g: g.clone(),
            sample_type,
            colours,
        }
    }

    /// The next `lines` emitter rows: `samples` laid out as a [`Modulation`]
    /// of that many rows of the frame's geometry.
    pub(crate) fn push<T: FrameSample>(&mut self, samples: &[T], lines: usize) {
        use rayon::prelude::*;
        let (g, st) = (&self.g, self.sample_type);
        let views = g.views_per_emitter();
        let row_len = self.colours.len() * g.emitters * st.bytes();
        for j in 0..lines {
            for (slot, &c) in self.colours.iter().enumerate() {
                let line = &samples[(c * lines + j) * g.emitters * views..][..g.emitters * views];
                for e in 0..g.emitters {
                    for (v, x) in line[e * views..(e + 1) * views].iter().enumerate() {
                        let at = v * row_len + (slot * g.emitters + e) * st.bytes();
                        match st {
                            SampleType::F16 => {
                                self.rows[at..at + 2].copy_from_slice(&half::f16::from_f32(x.to_f32()).to_le_bytes())
                            }
                            SampleType::F32 => self.rows[at..at + 4].copy_from_slice(&x.to_f32().to_le_bytes()),
                        }
                    }
                }
            }
            self.digests.par_iter_mut().zip(self.rows.par_chunks(row_len)).for_each(|(d, row)| d.update(row));
        }
    }

    /// Every view's digest, in the order of [`Geometry::view_index`].
    pub(crate) fn finish(self) -> Vec<String> {
        self.digests.into_iter().map(RowDigest::finish).collect()
    }

    /// Every view's digest against the one its part stores, the first that
    /// differs an error naming the frame and view.
    pub(crate) fn check(self, info: &super::FileInfo, index: usize) -> Result<()> {
        let frame = &info.frames[index];
        let g = self.g.clone();
        for ((v, computed), view) in self.finish().into_iter().enumerate().zip(&frame.views) {
            if let Some(stored) = &view.digest {
                if &computed != stored {
                    return Err(view_damaged(&info.path, index, g.view_of_index(v), stored, &computed));
                }
            }
        }
        Ok(())
    }
}

/// A view of a full-parallax frame whose samples do not match its digest.
fn view_damaged(path: &Path, index: usize, (h, k): (usize, usize), stored: &str, computed: &str) -> Error {
    Error::invalid(
        path,
        format!(
            "frame {index}, view ({h} {k}): the samples do not match their digest (stored {stored}, computed {computed}): the file is damaged"
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Window;
    use crate::geometry::{rgb_channels, Views};
    use rand::seq::SliceRandom;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random full-parallax frame of `rows × emitters` and 11 × 6 views
    /// (not powers of two), each view lit only inside its own random window
    /// (as a writer that shrinks data windows stores it), with the windows.
    fn frame(rng: &mut ChaCha8Rng, rows: usize, emitters: usize) -> (Modulation, Vec<Window>) {
        let views = |count| Views { count, first_theta_rad: -0.2, last_theta_rad: 0.2, spacing: ViewSpacing::Tan };
        let g = Geometry::centred(rows, emitters, views(11), 5e-4, 5e-4, 0.0, 0.5, rgb_channels())
            .with_vertical_views(views(6));
        let windows: Vec<Window> = (0..g.views_per_emitter())
            .map(|_| {
                let (x, y) = (rng.gen_range(0..emitters / 3), rng.gen_range(0..rows / 3));
                let width = rng.gen_range(1..=emitters - x);
                let height = rng.gen_range(1..=rows - y);
                Window { x, y, width, height }
            })
            .collect();
        let m = Modulation::from_fn(g, |_, j, e, v| {
            let w = windows[v];
            let inside = (w.x..w.x + w.width).contains(&e) && (w.y..w.y + w.height).contains(&j);
            if inside {
                // f16 values, so f16 and f32 storage hold them exactly.
                half::f16::from_f32(rng.gen_range(0.0..4.0)).to_f32()
            } else {
                0.0
            }
        })
        .unwrap();
        (m, windows)
    }

    /// Each view's blocks as a file holds them: its window's rows, `lines`
    /// at a time, colour after colour, native-endian samples of `st`.
    fn blocks(m: &Modulation, windows: &[Window], lines: usize, st: SampleType) -> Vec<(usize, UncompressedBlock)> {
        let colours = colour_slots(m.geometry());
        let mut out = Vec::new();
        for (v, w) in windows.iter().enumerate() {
            for top in (w.y..w.y + w.height).step_by(lines) {
                let rows = lines.min(w.y + w.height - top);
                let mut data = Vec::new();
                for j in top..top + rows {
                    for &c in &colours {
                        for e in w.x..w.x + w.width {
                            let x = m.get(c, j, e, v);
                            match st {
                                SampleType::F16 => data.extend_from_slice(&half::f16::from_f32(x).to_ne_bytes()),
                                SampleType::F32 => data.extend_from_slice(&x.to_ne_bytes()),
                            }
                        }
                    }
                }
                let index = BlockIndex {
                    layer: v,
                    pixel_position: exr::math::Vec2(0, top - w.y),
                    pixel_size: exr::math::Vec2(w.width, rows),
                    level: exr::math::Vec2(0, 0),
                };
                out.push((v, UncompressedBlock { index, data }));
            }
        }
        out
    }

    /// The batched, tiled placement of full-parallax blocks equals placing
    /// them one by one ([`place_block`], the straightforward reference) and
    /// the samples themselves, for random windows, regions, block orders and
    /// batches, both stored types and both read types.
    #[test]
    fn view_blocks_placed_in_batches_are_the_blocks_placed_one_by_one() {
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let mut lit_rounds = 0;
        for round in 0..24 {
            let (rows, emitters) = (rng.gen_range(3..40), rng.gen_range(3..50));
            let (m, windows) = frame(&mut rng, rows, emitters);
            let g = m.geometry().clone();
            let st = if round % 2 == 0 { SampleType::F16 } else { SampleType::F32 };
            let mut all = blocks(&m, &windows, [1, 16, 32][round % 3], st);
            all.shuffle(&mut rng);
            let pick = |rng: &mut ChaCha8Rng, n: usize| {
                let a = rng.gen_range(0..n);
                a..rng.gen_range(a + 1..=n)
            };
            let region = if round < 2 {
                Region::all(&g)
            } else {
                Region {
                    hololines: pick(&mut rng, g.hololines),
                    emitters: pick(&mut rng, g.emitters),
                    views: pick(&mut rng, g.views.count),
                    vertical_views: pick(&mut rng, g.vertical_view_count()),
                }
            };
            let sub = sub_geometry(&g, &region);
            let colours = colour_slots(&g);
            // The region's views, as `Wanted` names them.
            let part_of = |v: usize| {
                let (h, k) = g.view_of_index(v);
                let inside = region.views.contains(&h) && region.vertical_views.contains(&k);
                inside.then(|| WantedPart {
                    window: windows[v],
                    sub_view: Some((k - region.vertical_views.start) * region.views.len() + h - region.views.start),
                })
            };
            let wanted: Vec<(WantedPart, &UncompressedBlock)> =
                all.iter().filter_map(|(v, b)| Some((part_of(*v)?, b))).collect();
            let len = sub.samples_per_frame() as usize;
            let (mut fast, mut reference) = (vec![0f32; len], vec![0f32; len]);
            // In two batches, split at random.
            let split = rng.gen_range(0..=wanted.len());
            for batch in [&wanted[..split], &wanted[split..]] {
                let batch: Vec<(&WantedPart, UncompressedBlock)> = batch
                    .iter()
                    .map(|(p, b)| (p, UncompressedBlock { index: b.index, data: b.data.clone() }))
                    .collect();
                place_view_blocks(&mut fast, &sub, &batch, &colours, st, &region).unwrap();
            }
            for (part, block) in &wanted {
                let v = part.sub_view.unwrap();
                let w = part.window;
                place_block(
                    &mut reference,
                    &sub,
                    block,
                    colours.len(),
                    |s| Some((colours[s], v)),
                    st,
                    w.x,
                    w.y,
                    &region,
                )
                .unwrap();
            }
            let direct: Vec<f32> = Modulation::from_fn(sub.clone(), |c, j, e, v| {
                let (h, k) = sub.view_of_index(v);
                let v = g.view_index(region.views.start + h, region.vertical_views.start + k);
                m.get(c, region.hololines.start + j, region.emitters.start + e, v)
            })
            .unwrap()
            .samples()
            .to_vec();
            lit_rounds += usize::from(direct.iter().any(|&x| x > 0.0));
            assert_eq!(fast, reference, "round {round}");
            assert_eq!(fast, direct, "round {round}");
            // Read as f16: the same values.
            let mut halves = vec![half::f16::ZERO; len];
            for batch in [&wanted[..split], &wanted[split..]] {
                let batch: Vec<(&WantedPart, UncompressedBlock)> = batch
                    .iter()
                    .map(|(p, b)| (p, UncompressedBlock { index: b.index, data: b.data.clone() }))
                    .collect();
                place_view_blocks(&mut halves, &sub, &batch, &colours, st, &region).unwrap();
            }
            assert!(halves.iter().map(|h| h.to_f32()).eq(fast.iter().copied()), "round {round}");
        }
        assert!(lit_rounds >= 10, "only {lit_rounds} regions held lit samples");
    }

    /// Each view's digest taken from its part's blocks, in any order and any
    /// batches, is the digest of its samples (spec §8, §7.1) as
    /// [`ViewDigests`] takes it from the frame.
    #[test]
    fn view_digests_from_blocks_are_the_digests_of_the_samples() {
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        for round in 0..6 {
            let (rows, emitters) = (rng.gen_range(3..40), rng.gen_range(3..50));
            let (m, windows) = frame(&mut rng, rows, emitters);
            let g = m.geometry().clone();
            let st = if round % 2 == 0 { SampleType::F16 } else { SampleType::F32 };
            let mut all = blocks(&m, &windows, [1, 16, 32][round % 3], st);
            all.shuffle(&mut rng);
            let digests = PartDigests::new(&g, st, windows.iter().copied());
            for batch in all.chunks(rng.gen_range(1..=all.len())) {
                let mut rows: Vec<PartBlock<'_>> = batch
                    .iter()
                    .map(|(v, b)| {
                        let top = windows[*v].y + b.index.pixel_position.1;
                        (*v, top, b.index.pixel_size.1, b.data.as_slice())
                    })
                    .collect();
                digests.push_batch(&mut rows);
            }
            let mut reference = ViewDigests::new(&g, st);
            reference.push(m.samples(), g.hololines);
            assert_eq!(digests.finish(), reference.finish(), "round {round}");
        }
    }

    /// F16C's conversion is the portable one, for every f16 value.
    #[test]
    fn halves_convert_alike_with_and_without_f16c() {
        let bytes: Vec<u8> = (0..=u16::MAX).flat_map(|b| b.to_ne_bytes()).collect();
        let (mut vector, mut portable) = (vec![0f32; 1 << 16], vec![0f32; 1 << 16]);
        // Odd lengths too: the groups of eight and the rest.
        for n in [1 << 16, 13, 8, 7] {
            halves_to_f32(&bytes[..2 * n], &mut vector[..n], crate::simd::Simd::Detect);
            halves_to_f32(&bytes[..2 * n], &mut portable[..n], crate::simd::Simd::Portable);
            for (i, (a, b)) in vector[..n].iter().zip(&portable[..n]).enumerate() {
                assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()), "{i:#06x}: {a} {b}");
                assert!(a.is_nan() || *a == half::f16::from_bits(i as u16).to_f32());
            }
        }
    }
}
