//! `holo convert mesh`: a scene file to a `.holo` file, frame by frame.
//!
//! The scene is placed once (on the first frame converted) and that
//! placement is kept for every frame, so an animation does not jitter as its
//! bounding box changes ([`PlacedScenes`]). Frames are rendered one at a time
//! as the writer asks for them ([`MeshSource`] through [`crate::pipeline`]):
//! memory is one frame whatever the frame count.

use std::ops::Range;
use std::path::{Path, PathBuf};

use super::load::SceneSource;
use super::place::{apply, place, Placed, Placement};
use super::render::{render_into, RenderOptions, RenderStats};
use super::{Light, Scene};
use crate::format::{WriteOptions, WriteReport};
use crate::geometry::Geometry;
use crate::pipeline::{self, HoloSink, Source, Warnings};
use crate::progress::{Labelled, Progress};
use crate::{Band, Error, Result};

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

/// Convert `input` into `output` for `geometry`: a [`MeshSource`] through
/// [`crate::pipeline::run`]. A movie reports its frames to `progress`, a
/// single frame its hololines.
pub fn convert_mesh(
    input: &Path,
    geometry: &Geometry,
    output: &Path,
    options: &ConvertOptions,
    progress: &dyn Progress,
) -> Result<ConvertReport> {
    // Refused before the scene is even read.
    crate::output::check_output(output, &[input], options.write.overwrite)?;
    let mut source = MeshSource::open(input, geometry, options)?;
    let sink = HoloSink::new(output, geometry, options.write.clone());
    let run = pipeline::run(&mut source, sink, options.frames.clone(), progress)?;
    let first = source.first.ok_or_else(|| Error::Usage("internal: the scene was never placed".into()))?;
    Ok(ConvertReport {
        path: output.to_path_buf(),
        frames: run.frames,
        triangles: first.triangles,
        objects: first.objects,
        placed: first.placed,
        lights: first.lights,
        stats: source.stats,
        warnings: run.warnings,
        written: run.written,
    })
}

/// A scene file's frames in display metres: frame `i` is the scene at
/// `i / fps` seconds, placed as the first frame made was (so an animation
/// does not jitter as its bounding box changes). Mesh conversion and
/// HoloFlick encoding both take their scenes from it.
#[derive(Debug)]
pub struct PlacedScenes {
    source: SceneSource,
    frames_per_second: f64,
    /// The first frame made, kept from placement until it is asked for.
    first: Option<(usize, Scene)>,
    /// The placement, once decided.
    pub placed: Option<Placed>,
}

impl PlacedScenes {
    /// Open `input`, sampling an animation at `frames_per_second`.
    pub fn open(input: &Path, frames_per_second: f64) -> Result<PlacedScenes> {
        if !(frames_per_second.is_finite() && frames_per_second > 0.0) {
            return Err(Error::Usage(format!(
                "{}: the frame rate must be a positive number of frames per second, not {frames_per_second}",
                input.display()
            )));
        }
        Ok(PlacedScenes { source: SceneSource::open(input)?, frames_per_second, first: None, placed: None })
    }

    /// The file the scenes come from.
    pub fn path(&self) -> &Path {
        self.source.path()
    }

    /// The animation's frames at this rate (its first and last pose
    /// included), or one frame for a still scene.
    pub fn frame_count(&self) -> usize {
        match self.source.animation_duration_s() {
            Some(d) => (d * self.frames_per_second).floor() as usize + 1,
            None => 1,
        }
    }

    /// The frame rate in frames per second.
    pub fn frames_per_second(&self) -> f64 {
        self.frames_per_second
    }

    /// Place frame `first` in `geometry` and keep that placement for every
    /// frame; the placed scene is kept for [`PlacedScenes::scene`].
    pub fn place(&mut self, first: usize, geometry: &Geometry, placement: &Placement) -> Result<&Scene> {
        let mut scene = self.source.scene_at(first as f64 / self.frames_per_second)?;
        self.placed = Some(place(&mut scene, geometry, placement)?);
        let (_, scene) = self.first.insert((first, scene));
        Ok(scene)
    }

    /// Whether frame `number` is the one placement kept (its warnings were
    /// seen then).
    pub fn is_kept(&self, number: usize) -> bool {
        self.first.as_ref().is_some_and(|(n, _)| *n == number)
    }

    /// Frame `number`, placed.
    pub fn scene(&mut self, number: usize) -> Result<Scene> {
        if let Some((n, scene)) = self.first.take() {
            if n == number {
                return Ok(scene);
            }
        }
        let placed =
            self.placed.as_ref().ok_or_else(|| Error::Usage("internal: scenes asked for before placement".into()))?;
        let mut scene = self.source.scene_at(number as f64 / self.frames_per_second)?;
        apply(&mut scene, &placed.matrix);
        Ok(scene)
    }
}

/// What the first frame made of a mesh conversion was.
#[derive(Clone, Debug)]
struct First {
    triangles: usize,
    objects: usize,
    placed: Placed,
    lights: Vec<Light>,
}

/// A scene file as a [`Source`] of `.holo` frames, each rendered by the
/// mesh renderer ([`render_into`]).
#[derive(Debug)]
pub struct MeshSource<'a> {
    scenes: PlacedScenes,
    geometry: &'a Geometry,
    placement: Placement,
    render: RenderOptions,
    first: Option<First>,
    /// Work counters summed over the frames rendered.
    pub stats: RenderStats,
}

impl<'a> MeshSource<'a> {
    /// Open `input` to render for `geometry` with `options` (its placement,
    /// render options and frame rate).
    pub fn open(input: &Path, geometry: &'a Geometry, options: &ConvertOptions) -> Result<MeshSource<'a>> {
        Ok(MeshSource {
            scenes: PlacedScenes::open(input, options.fps)?,
            geometry,
            placement: options.placement.clone(),
            render: options.render.clone(),
            first: None,
            stats: RenderStats::default(),
        })
    }
}

impl Source for MeshSource<'_> {
    type Frame = Band;

    fn name(&self) -> String {
        self.scenes.path().display().to_string()
    }

    fn inputs(&self) -> Vec<PathBuf> {
        vec![self.scenes.path().to_path_buf()]
    }

    fn frame_count(&self) -> usize {
        self.scenes.frame_count()
    }

    fn frames_per_second(&self) -> Option<(u32, u32)> {
        Some(((self.scenes.frames_per_second() * 1000.0).round() as u32, 1000))
    }

    fn place(&mut self, frames: &Range<usize>, warnings: &mut Warnings) -> Result<()> {
        let scene = self.scenes.place(frames.start, self.geometry, &self.placement)?;
        warnings.merge_frame(&scene.warnings);
        let (triangles, objects) = (scene.triangle_count(), scene.objects.len());
        let lights = self.render.lighting_for(scene).lights;
        let placed = self.scenes.placed.clone().ok_or_else(|| Error::Usage("internal: no placement".into()))?;
        self.first = Some(First { triangles, objects, placed, lights });
        Ok(())
    }

    fn provenance(&self) -> String {
        let path = self.scenes.path();
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let (triangles, objects, placed) = match &self.first {
            Some(f) => (f.triangles, f.objects, f.placed.to_string()),
            None => (0, 0, String::new()),
        };
        format!(
            "holo convert mesh {name} ({triangles} triangles, {objects} objects; {placed}; supersampling {}x{}, {} lobe)",
            self.render.supersample.emitter,
            self.render.supersample.view,
            self.render.lighting.model.name()
        )
    }

    fn render(
        &mut self,
        number: usize,
        frame: &mut Band,
        progress: &dyn Progress,
        warnings: &mut Warnings,
    ) -> Result<()> {
        let seen = self.scenes.is_kept(number);
        let scene = self.scenes.scene(number)?;
        if !seen {
            warnings.merge_frame(&scene.warnings);
        }
        let progress = Labelled::new(progress, format!("frame {number}"));
        let render = &self.render;
        self.stats += frame.as_frame(|m| render_into(&scene, render, &progress, m))??;
        Ok(())
    }
}
