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
use half::slice::HalfFloatSliceExt;

use super::digest::{frame_digest, row_bytes, stored_row, BlockDigest, RowDigest};
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
        let mut samples: Vec<T> = self.read_blocks(index, &Region::all(&self.info.geometry), digest.as_mut())?;
        let frame = &self.info.frames[index];
        if !frame.views.is_empty() {
            self.check_view_digests(index, &samples)?;
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
        let mut samples = self.read_blocks(index, region, None)?;
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
        let mut view_digests = (!frame.views.is_empty()).then(|| ViewDigests::new(g, sample_type));
        let order = ChannelOrder::new(g);
        let mut row = vec![0u8; row_bytes(g, sample_type)];
        let mut digest = frame.digest.as_ref().map(|_| RowDigest::default());
        for top in (0..g.hololines).step_by(band_rows.max(1)) {
            let rows = top..(top + band_rows.max(1)).min(g.hololines);
            let region = Region { hololines: rows.clone(), ..Region::all(g) };
            // As decoded (a lossy file's undershoot included), as the digests are.
            let mut band = self.read_decoded(index, &region)?;
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
        let samples = self.read_blocks::<f32>(index, region, None)?;
        Modulation::from_samples(sub_geometry(&self.info.geometry, region), samples)
    }

    /// Each view's digest (spec §8, §7.1) against the samples of a whole
    /// full-parallax frame as read.
    fn check_view_digests<T: FrameSample>(&self, index: usize, samples: &[T]) -> Result<()> {
        let mut digests = ViewDigests::new(&self.info.geometry, self.info.sample_type);
        digests.push(samples, self.info.geometry.hololines);
        digests.check(&self.info, index)
    }

    /// The samples of a region as decoded (see [`HoloFile::read_decoded`]),
    /// handing every decoded block's bytes to `digest` too (whole frames
    /// only).
    fn read_blocks<T: FrameSample>(
        &self,
        index: usize,
        region: &Region,
        mut digest: Option<&mut BlockDigest>,
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
        let mut place = |block: UncompressedBlock| -> Result<()> {
            let Some(part) = wanted.part(block.index.layer) else { return Ok(()) };
            let dw = part.window;
            let st = self.info.sample_type;
            match part.sub_view {
                None => {
                    let target = |slot| {
                        let (v, c) = order.pair_at(slot);
                        region.views.contains(&v).then(|| (c, v - region.views.start))
                    };
                    place_block(&mut out, &sub, &block, order.len(), target, st, dw.x, dw.y, region)
                }
                Some(v) => place_block(
                    &mut out,
                    &sub,
                    &block,
                    colours.len(),
                    |slot| Some((colours[slot], v)),
                    st,
                    dw.x,
                    dw.y,
                    region,
                ),
            }
            .map_err(|problem| Error::invalid(path, problem))?;
            if let Some(digest) = digest.as_deref_mut() {
                digest.push(dw.y + block.index.pixel_position.1, block.index.pixel_size.1, block.data);
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
    /// `stride`-th place of `dest`, from its first; `scratch` is the
    /// caller's, reused from run to run.
    #[doc(hidden)]
    fn scatter(run: &[u8], stored: SampleType, dest: &mut [Self], stride: usize, scratch: &mut Vec<f32>);
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
    fn scatter(run: &[u8], stored: SampleType, dest: &mut [f32], stride: usize, scratch: &mut Vec<f32>) {
        let values: &[f32] = match stored {
            SampleType::F16 => {
                // Converted as a slice (F16C where the processor has it),
                // then spread with the stride.
                let halves: Vec<half::f16> =
                    run.chunks_exact(2).map(|b| half::f16::from_ne_bytes([b[0], b[1]])).collect();
                scratch.resize(halves.len(), 0.0);
                halves.convert_to_f32_slice(scratch);
                scratch
            }
            SampleType::F32 => {
                scratch.clear();
                scratch.extend(run.chunks_exact(4).map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]])));
                scratch
            }
        };
        for (x, d) in values.iter().zip(dest.iter_mut().step_by(stride)) {
            *d = *x;
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
    fn scatter(run: &[u8], stored: SampleType, dest: &mut [half::f16], stride: usize, _: &mut Vec<f32>) {
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
    /// (absolute), handing each decoded block to `place`: in file order
    /// within a batch, the batches decoded on every core for a file of a
    /// megabyte or more.
    fn decode(
        &self,
        path: &Path,
        wanted: &Wanted,
        rows: &Range<usize>,
        place: &mut dyn FnMut(UncompressedBlock) -> Result<()>,
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
                let decoded: Vec<Result<UncompressedBlock>> = if parallel && batch.len() > 1 {
                    use rayon::prelude::*;
                    std::mem::take(&mut batch).into_par_iter().map(decode).collect()
                } else {
                    std::mem::take(&mut batch).into_iter().map(decode).collect()
                };
                for block in decoded {
                    place(block?)?;
                }
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
    let mut scratch = Vec::with_capacity(w);
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
            T::scatter(run, sample_type, &mut dest[first * views + vv..], views, &mut scratch);
        }
    }
    Ok(())
}

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
