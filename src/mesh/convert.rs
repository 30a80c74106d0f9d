//! `holo convert mesh`: a scene file to a `.holo` file, frame by frame.
//!
//! The scene is placed once (on the first frame converted) and that
//! placement is kept for every frame, so an animation does not jitter as its
//! bounding box changes. Frames are rendered one at a time as the writer asks
//! for them: memory is one frame whatever the frame count.

use std::borrow::Cow;
use std::ops::Range;
use std::path::{Path, PathBuf};

use super::load::SceneSource;
use super::place::{apply, place, Placed, Placement};
use super::render::{render, RenderOptions, RenderStats};
use super::Light;
use crate::format::{write_frames, WriteOptions, WriteReport};
use crate::geometry::Geometry;
use crate::{Error, Result};

/// Everything `convert mesh` takes besides the input, layout geometry and output.
#[derive(Clone, Debug)]
pub struct ConvertOptions {
    /// Where the scene goes.
    pub placement: Placement,
    /// Renderer, supersampling, specular lobe and lights: its lights (in
    /// display metres, after placement) are added to the scene's own
    /// (see [`RenderOptions::lighting_for`]).
    pub render: RenderOptions,
    /// Frames to convert (animated glTF): frame `i` is the scene at `i / fps`.
    pub frames: Option<Range<usize>>,
    /// Frame rate for sampling animations.
    pub fps: f64,
    /// How to write the file.
    pub write: WriteOptions,
}

impl Default for ConvertOptions {
    fn default() -> Self {
        ConvertOptions {
            placement: Placement::default(),
            render: RenderOptions::default(),
            frames: None,
            fps: 30.0,
            write: WriteOptions::default(),
        }
    }
}

/// What a conversion did.
#[derive(Clone, Debug)]
pub struct ConvertReport {
    /// The output file.
    pub path: PathBuf,
    /// Frames written.
    pub frames: Range<usize>,
    /// Triangles in the first frame.
    pub triangles: usize,
    /// Objects in the first frame.
    pub objects: usize,
    /// The placement used for every frame.
    pub placed: Placed,
    /// Lights used (after placement).
    pub lights: Vec<Light>,
    /// Work counters summed over frames.
    pub stats: RenderStats,
    /// Warnings from loading and rendering.
    pub warnings: Vec<String>,
    /// The writer's report.
    pub written: WriteReport,
}

/// Convert `input` into `output` for `geometry`. `progress(frame, hololines_done, hololines)`.
pub fn convert_mesh(
    input: &Path,
    geometry: &Geometry,
    output: &Path,
    options: &ConvertOptions,
    progress: &(dyn Fn(usize, usize, usize) + Sync),
) -> Result<ConvertReport> {
    if !(options.fps.is_finite() && options.fps > 0.0) {
        return Err(Error::argument("frame rate", format!("--fps must be a positive number, not {}", options.fps)));
    }
    crate::output::check_output(output, &[input], options.write.overwrite)?;
    let source = SceneSource::open(input)?;
    let frames = match (&options.frames, source.animation_duration_s()) {
        (Some(r), _) => r.clone(),
        (None, Some(d)) => 0..((d * options.fps).floor() as usize + 1),
        (None, None) => 0..1,
    };
    if frames.is_empty() {
        return Err(Error::argument(
            "frame range",
            format!("the frame range {}..{} is empty", frames.start, frames.end),
        ));
    }
    if source.animation_duration_s().is_none() && frames != (0..1) {
        return Err(Error::argument(
            "frame range",
            format!(
                "{}: the scene is not animated, so it has one frame (0); --frames asked for {}..{}",
                input.display(),
                frames.start,
                frames.end
            ),
        ));
    }
    let mut first = source.scene_at(frames.start as f64 / options.fps)?;
    let placed = place(&mut first, geometry, &options.placement)?;
    let mut warnings = first.warnings.clone();
    let (triangles, objects) = (first.triangle_count(), first.objects.len());
    let lights = options.render.lighting_for(&first).lights;
    let mut stats = RenderStats::default();
    let mut first = Some(first);
    let mut write = options.write.clone();
    if write.frames_per_second.is_none() && frames.len() > 1 {
        write.frames_per_second = Some(((options.fps * 1000.0).round() as i32, 1000));
    }
    write.first_frame_number = frames.start as i32;
    if write.source.is_empty() {
        write.source = format!(
            "holo convert mesh {} ({} triangles, {} objects; {}; supersampling {}x{}, {} lobe)",
            input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
            triangles,
            objects,
            placed,
            options.render.supersample.emitter,
            options.render.supersample.view,
            options.render.lighting.model.name()
        );
    }
    let frame_count = frames.len();
    let start = frames.start;
    let written = write_frames(output, geometry, frame_count, &write, |i| {
        let scene = match first.take() {
            Some(s) => s,
            None => {
                let mut s = source.scene_at((start + i) as f64 / options.fps)?;
                apply(&mut s, &placed.matrix);
                for w in &s.warnings {
                    if !warnings.contains(w) {
                        warnings.push(w.clone());
                    }
                }
                s
            }
        };
        let (m, s) = render(&scene, geometry, &options.render, &|done, total| progress(i, done, total))?;
        stats += s;
        Ok(Cow::Owned(m))
    })?;
    Ok(ConvertReport {
        path: output.to_path_buf(),
        frames,
        triangles,
        objects,
        placed,
        lights,
        stats,
        warnings,
        written,
    })
}
