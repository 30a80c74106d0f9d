//! `holo convert cameras`: a rig's pictures to a `.holo` file.
//!
//! The pictures are loaded (in parallel, each checked against its camera);
//! the frame is resampled and written a band of hololines at a time, so
//! memory is the pictures plus one band, whatever the display's size.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::read::OpenOptions;
use super::resample::{CameraOptions, CameraReport, CameraView, RigResampler, Unseen};
use super::{Camera, Rig};
use crate::error::{Error, Result};
use crate::format::{ConversionRecord, RecordHead, WriteOptions, WriteReport};
use crate::geometry::Geometry;
use crate::modulation::Band;
use crate::output::Claim;
use crate::pipeline::{self, HoloSink, Source, Warnings};
use crate::progress::{Progress, Steps};

/// Everything `convert cameras` takes besides the rig, geometry and output.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CameraConvertOptions {
    /// Blending, placement, focus, depth.
    pub resample: CameraOptions,
    /// How a capture that does not record its whole geometry is read
    /// ([`convert_camera_files`]; a rig already read does not use them).
    pub open: OpenOptions,
    /// Also write a PNG (emitters × hololines) whose grey level is the
    /// fraction of each emitter's views that no camera sees.
    pub unseen_png: Option<PathBuf>,
    /// How to write the file.
    pub write: WriteOptions,
}

/// What a conversion did.
#[derive(Clone, Debug)]
pub struct CameraConvertReport {
    /// The output file.
    pub path: PathBuf,
    /// Cameras used.
    pub cameras: usize,
    /// The resampler's report (placement chosen, camera surface, unseen rays).
    pub resample: CameraReport,
    /// The writer's report.
    pub written: WriteReport,
    /// Where the time went (`decode`: the pictures; `render`: resampling;
    /// `write`).
    pub timings: crate::progress::Timings,
}

/// Load `rig`'s pictures with `load` (one camera's linear picture and
/// depth map), then resample and write `output` for `geometry`; the phases
/// of `progress` are `pictures` (cameras loaded) and `hololines`.
pub fn convert_cameras(
    rig: &Rig,
    load: &(dyn Fn(&Camera) -> Result<CameraView> + Sync),
    geometry: &Geometry,
    output: &Path,
    options: &CameraConvertOptions,
    progress: &dyn Progress,
) -> Result<CameraConvertReport> {
    convert(rig, None, load, geometry, output, options, progress)
}

/// [`convert_cameras`] of the rig read from `input`, when it was: its name
/// and digest are recorded (else the rig's own name).
fn convert(
    rig: &Rig,
    input: Option<&Path>,
    load: &(dyn Fn(&Camera) -> Result<CameraView> + Sync),
    geometry: &Geometry,
    output: &Path,
    options: &CameraConvertOptions,
    progress: &dyn Progress,
) -> Result<CameraConvertReport> {
    rig.check()?;
    // The rig's pictures and depth maps are inputs as much as its file.
    let mut read = rig.files();
    read.extend(input.map(Path::to_path_buf));
    let read_paths: Vec<&Path> = read.iter().map(PathBuf::as_path).collect();
    let _claims = check_outputs(output, options, &read_paths)?;
    let decoding = std::time::Instant::now();
    let loaded = Steps::begin(progress, "pictures", rig.cameras.len());
    let views: Vec<CameraView> = rig
        .cameras
        .par_iter()
        .map(|camera| {
            let view = load(camera);
            loaded.step();
            view
        })
        // Every item, then the first failure in order: rayon's own collect
        // into a Result returns whichever fails first in time, and an
        // error should name the same file every run.
        .collect::<Vec<Result<_>>>()
        .into_iter()
        .collect::<Result<_>>()?;
    for (cam, view) in rig.cameras.iter().zip(&views) {
        if view.picture.size() != (cam.width, cam.height) {
            let (w, h) = view.picture.size();
            return Err(Error::rig(
                &rig.source,
                format!("camera {}: the picture is {w}×{h}, the rig says {}×{}", cam.name, cam.width, cam.height),
            ));
        }
    }
    let decoding = decoding.elapsed();
    let mut resample_options = options.resample.clone();
    resample_options.want_mask |= options.unseen_png.is_some();
    let resampler = RigResampler::new(rig, &views, geometry, &resample_options)?;
    let mut source = CameraSource {
        rig,
        input: input.map(Path::to_path_buf),
        inputs: read,
        resampler: &resampler,
        options,
        unseen: Unseen::default(),
        mask: Vec::new(),
        unseen_grey: Vec::new(),
    };
    let sink = HoloSink::new(output, geometry, options.write.clone());
    let run = pipeline::run(&mut source, sink, None, progress)?;
    let CameraSource { unseen, mask, unseen_grey, .. } = source;
    if let Some(path) = &options.unseen_png {
        write_unseen_png(path, geometry, &unseen_grey, options.write.overwrite)?;
    }
    let report = resampler.report(unseen, options.resample.want_mask.then_some(mask));
    Ok(CameraConvertReport {
        path: output.to_path_buf(),
        cameras: rig.cameras.len(),
        resample: report,
        written: run.written,
        timings: {
            let mut t = crate::progress::Timings::default();
            t.add("decode", decoding);
            t.merge(&run.timings);
            t
        },
    })
}

/// A rig's loaded pictures as a [`Source`] of one `.holo` frame, resampled a
/// band of hololines at a time: memory is the pictures plus a band (and,
/// for the unseen picture, a byte per emitter), never the whole frame.
struct CameraSource<'a> {
    rig: &'a Rig,
    /// The rig's file or folder, when it was read from one.
    input: Option<PathBuf>,
    /// Every file read: the rig's and its pictures and depth maps.
    inputs: Vec<PathBuf>,
    resampler: &'a RigResampler<'a>,
    options: &'a CameraConvertOptions,
    /// Rays no camera sees, over the bands done.
    unseen: Unseen,
    /// Per ray, unseen (when asked for).
    mask: Vec<bool>,
    /// The unseen picture's grey levels, over the bands done.
    unseen_grey: Vec<u8>,
}

impl Source for CameraSource<'_> {
    type Frame = Band;

    fn name(&self) -> String {
        self.rig.source.clone()
    }

    fn inputs(&self) -> Vec<PathBuf> {
        self.inputs.clone()
    }

    fn frame_count(&self) -> usize {
        1
    }

    fn provenance(&self) -> String {
        let (rig, resample) = (self.rig, &self.options.resample);
        let words = self.resampler.report(Unseen::default(), None);
        let depth = resample.use_depth && rig.cameras.iter().any(|c| c.depth.is_some());
        format!(
            "holo convert cameras {} ({}; {} blending{}; {})",
            rig.source,
            words.surface,
            resample.blend.name(),
            if depth { ", depth maps" } else { "" },
            words.placement
        )
    }

    fn placement(&self) -> Option<crate::math::Mat4> {
        Some(self.resampler.display_from_capture())
    }

    fn conversion(&self) -> Result<Option<ConversionRecord>> {
        let head = match &self.input {
            Some(input) => RecordHead::of_input(CameraConvertOptions::KIND, input)?,
            None => RecordHead {
                kind: CameraConvertOptions::KIND.to_string(),
                input: self.rig.source.clone(),
                input_sha256: None,
            },
        };
        // The record holds what makes the samples, not the outputs asked
        // for beside them (the unseen-ray picture, the mask).
        Ok(Some(self.options.record(&head)))
    }

    fn band_hololines(&self) -> Option<usize> {
        Some(4 * rayon::current_num_threads().max(4))
    }

    fn render(&mut self, _number: usize, band: &mut Band, progress: &dyn Progress, _: &mut Warnings) -> Result<()> {
        let g = band.geometry().clone();
        if band.hololines().start == 0 {
            progress.phase("hololines", g.hololines as u64);
        }
        let (n, band_mask) = self.resampler.fill(band, progress);
        self.unseen += n;
        if self.options.unseen_png.is_some() {
            self.unseen_grey.extend(unseen_fraction_grey(&g, &band_mask));
        }
        if self.options.resample.want_mask {
            self.mask.extend(band_mask);
        }
        Ok(())
    }
}

/// Grey = fraction of the emitter's views unseen, one byte per (hololine,
/// emitter) of a band's per-ray mask.
fn unseen_fraction_grey<'m>(g: &Geometry, mask: &'m [bool]) -> impl Iterator<Item = u8> + 'm {
    let v = g.views_per_emitter();
    mask.chunks_exact(v)
        .map(move |views| (255.0 * views.iter().filter(|&&u| u).count() as f64 / v as f64).round() as u8)
}

/// The unseen picture: one pixel per (emitter, hololine), its grey linear
/// in the fraction unseen (a mask, not a tone-mapped picture).
fn write_unseen_png(path: &Path, g: &Geometry, grey: &[u8], overwrite: bool) -> Result<()> {
    let samples = crate::picture::Samples::Eight(grey);
    let png = crate::picture::encode_png_samples(
        g.emitters,
        g.hololines,
        crate::picture::Colour::Grey,
        samples,
        crate::picture::PngTags { srgb: false, pixel_size_m: Some([g.emitter_pitch_m, g.hololine_pitch_m]) },
    )
    .map_err(|e| e.naming(path))?;
    crate::output::write_bytes_beside(path, &png, overwrite)
}

/// The outputs (the `.holo` file and the unseen picture) checked before any
/// work against each other's rules and the inputs.
fn check_outputs(output: &Path, options: &CameraConvertOptions, inputs: &[&Path]) -> Result<Vec<Claim>> {
    let overwrite = options.write.overwrite;
    let mut claims = vec![crate::output::check_output(output, inputs, overwrite)?];
    if let Some(png) = &options.unseen_png {
        let mut read = inputs.to_vec();
        read.push(output);
        claims.push(crate::output::check_output(png, &read, overwrite)?);
    }
    Ok(claims)
}

/// A camera's picture (linear) and, when `use_depth` and the
/// rig gives one, its depth map as camera `z`.
pub fn load_view(camera: &Camera, linear: bool, use_depth: bool) -> Result<CameraView> {
    let picture = super::image::load_picture(camera, linear)?;
    let depth_z = if use_depth { super::pfm::load_depth(camera)? } else { None };
    Ok(CameraView { picture, depth_z })
}

/// `holo convert cameras`: open `input` (a rig file, an HCI or Stanford
/// folder, a Middlebury `_par.txt`, a Looking Glass quilt or a folder of
/// images, read with [`CameraConvertOptions::open`], see
/// [`super::open_rig_with`]) and convert it.
pub fn convert_camera_files(
    input: &Path,
    geometry: &Geometry,
    output: &Path,
    options: &CameraConvertOptions,
    progress: &dyn Progress,
) -> Result<CameraConvertReport> {
    let _claims = check_outputs(output, options, &[input])?;
    let rig = super::open_rig_with(input, &options.open)?;
    let (linear, use_depth) = (rig.linear, options.resample.use_depth);
    let load = |cam: &Camera| load_view(cam, linear, use_depth);
    convert(&rig, Some(input), &load, geometry, output, options, progress)
}
