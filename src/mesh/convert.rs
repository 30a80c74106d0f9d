//! `holo convert mesh`: a scene file to a `.holo` file, frame by frame.
//!
//! The scene is placed once (on the first frame converted) and that
//! placement is kept for every frame, so an animation does not jitter as its
//! bounding box changes ([`SceneFrames`]). Frames are rendered one at a time
//! as the writer asks for them ([`MeshSource`] through [`crate::pipeline`]):
//! memory is one frame whatever the frame count.

use std::ops::Range;
use std::path::{Path, PathBuf};

use super::load::SceneSource;
use super::place::{apply, place, Placed, Placement};
use super::render::{render_band_into, RenderOptions, RenderStats};
use super::{Light, Scene};
use crate::error::{Error, Result};
use crate::format::{ConversionRecord, RecordHead, WriteOptions, WriteReport};
use crate::geometry::Geometry;
use crate::modulation::Band;
use crate::pipeline::{self, Source, Warnings};
use crate::progress::{Labelled, Progress};

/// Which moments of a scene file become frames, and where the scene goes:
/// what every command that makes frames of a scene (`convert mesh`,
/// `holoflick encode`) takes the same way ([`SceneFrames`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFramesOptions {
    /// Where the scene goes, decided on the first frame of the run.
    pub placement: Placement,
    /// Frames to make (animated glTF); default all. Frame `i` is the scene
    /// at `i / frames_per_second` seconds.
    pub frames: Option<Range<usize>>,
    /// The rate animations are sampled at, and the frame rate written.
    pub frames_per_second: f64,
    /// Objects without vertex normals get smooth ones by this angle
    /// threshold, degrees ([`crate::mesh::normals::smooth_normals`]);
    /// `None` shades them flat.
    pub smooth_normals_deg: Option<f64>,
}

impl Default for SceneFramesOptions {
    fn default() -> Self {
        SceneFramesOptions {
            placement: Placement::default(),
            frames: None,
            frames_per_second: 30.0,
            smooth_normals_deg: None,
        }
    }
}

/// Everything `convert mesh` takes besides the input, layout geometry and output.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ConvertOptions {
    /// Placement, frames and frame rate.
    pub scene: SceneFramesOptions,
    /// Renderer, supersampling, specular lobe and lights: its lights (in
    /// display metres, after placement) are added to the scene's own
    /// (see [`RenderOptions::lighting_for`]).
    pub render: RenderOptions,
    /// How to write the file.
    pub write: WriteOptions,
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
    /// Where the time went (`open`, `place`, `decode`, `render`, `write`).
    pub timings: crate::progress::Timings,
}

/// Convert `input` into `output` for `geometry`: a [`MeshSource`] through
/// [`crate::pipeline`]. A movie reports its frames to `progress`, a single
/// frame its hololines.
pub fn convert_mesh(
    input: &Path,
    geometry: &Geometry,
    output: &Path,
    options: &ConvertOptions,
    progress: &dyn Progress,
) -> Result<ConvertReport> {
    let open = |input: &Path| SceneFrames::open(input, geometry, &options.scene, MeshRender::new(options));
    let target = (output, geometry, &options.write);
    let (source, run) = pipeline::open_and_write(input, open, target, options.scene.frames.clone(), progress)?;
    let MeshRender { first, stats, .. } = source.stage;
    let first = first.ok_or_else(|| Error::argument("placement", "internal: the scene was never placed"))?;
    Ok(ConvertReport {
        path: output.to_path_buf(),
        frames: run.frames,
        triangles: first.triangles,
        objects: first.objects,
        placed: first.placed,
        lights: first.lights,
        stats,
        warnings: run.warnings,
        written: run.written,
        timings: run.timings,
    })
}

/// What is made of each scene of a [`SceneFrames`]: a rendered `.holo`
/// frame ([`MeshRender`]) or a HoloFlick frame
/// ([`crate::holoflick::encode::Encode`]).
pub trait SceneStage {
    /// The buffer a frame is made into.
    type Frame;
    /// The frame rate as written, for `frames_per_second`.
    fn frame_rate(&self, frames_per_second: f64) -> (u32, u32);
    /// The first scene, placed (`placed`), before any frame is made.
    fn placed(&mut self, scene: &Scene, placed: &Placed);
    /// What the frames are made from (`input`) and how.
    fn provenance(&self, input: &Path) -> String;
    /// The converter and its options, when the frames are a conversion
    /// recorded in its output (`holo.convert.*`); `scene` are the options
    /// the frames were taken with.
    fn converter(&self, scene: &SceneFramesOptions) -> Option<ConvertOptions> {
        let _ = scene;
        None
    }
    /// Make a single frame of `geometry` a band of this many hololines at a
    /// time ([`Source::band_hololines`]); `None`, the default, makes whole
    /// frames.
    fn band_hololines(&self, geometry: &Geometry) -> Option<usize> {
        let _ = geometry;
        None
    }
    /// Make frame `number` of `scene`; `index` is its place in the run
    /// (with bands, the band `frame` holds of it).
    fn make(
        &mut self,
        number: usize,
        index: usize,
        scene: &Scene,
        frame: &mut Self::Frame,
        progress: &dyn Progress,
    ) -> Result<()>;
}

/// Objects without normals from this many triangles on are said to be
/// shaded flat: a scan, rarely meant to show its facets. A box or a
/// low-polygon model below it usually is.
const FLAT_HINT_TRIANGLES: usize = 1000;

/// A scene file's frames in display metres as a [`Source`]: frame `i` is
/// the scene at `i / frames_per_second` seconds, placed as the first frame of the run was
/// (so an animation does not jitter as its bounding box changes), and made
/// into a frame by the stage `S`.
#[derive(Debug)]
pub struct SceneFrames<'a, S> {
    source: SceneSource,
    /// The animation's frames at the frame rate, or 1.
    frame_count: usize,
    geometry: &'a Geometry,
    options: SceneFramesOptions,
    /// The first frame of the run, kept from placement until it is made.
    first: Option<(usize, Scene)>,
    /// The scene of the frame being made band by band, kept for its
    /// next band.
    banded: Option<(usize, Scene)>,
    first_number: usize,
    placed: Option<Placed>,
    /// Time spent reading and posing scenes inside [`Source::render`].
    decoding: std::time::Duration,
    /// What is made of each scene.
    pub stage: S,
}

impl<'a, S: SceneStage> SceneFrames<'a, S> {
    /// Open `input` for `geometry`, placed and sampled as `options` say
    /// (its frame range is the run's: [`pipeline::run`]).
    pub fn open(input: &Path, geometry: &'a Geometry, options: &SceneFramesOptions, stage: S) -> Result<Self> {
        // The rate before the scene is read, the frame count it makes as
        // soon as the animation's length is known.
        pipeline::check_frame_rate(options.frames_per_second)?;
        let source = SceneSource::open(input)?;
        let frame_count = match source.animation_duration_s() {
            Some(d) => pipeline::animation_frames(input, d, options.frames_per_second)?,
            None => 1,
        };
        Ok(SceneFrames {
            source,
            frame_count,
            geometry,
            options: options.clone(),
            first: None,
            banded: None,
            first_number: 0,
            placed: None,
            decoding: std::time::Duration::ZERO,
            stage,
        })
    }

    /// The placement, once decided.
    pub fn placed(&self) -> Option<&Placed> {
        self.placed.as_ref()
    }

    /// The scene at `time_s`, its objects without normals given smooth ones
    /// when asked; large ones shaded flat are said.
    fn scene_at(&self, time_s: f64) -> Result<Scene> {
        let mut scene = self.source.scene_at(time_s)?;
        for o in &mut scene.objects {
            match self.options.smooth_normals_deg {
                Some(deg) => {
                    crate::mesh::normals::smooth_normals(o, deg);
                }
                None if o.normals.is_empty() && o.triangles.len() >= FLAT_HINT_TRIANGLES => {
                    scene.warnings.push(format!(
                        "{}: object \"{}\" has no normals: its {} triangles are shaded flat, each facet visible; \
                         smoothing by angle can give it smooth ones",
                        scene.source,
                        o.name,
                        o.triangles.len()
                    ));
                }
                None => {}
            }
        }
        Ok(scene)
    }
}

impl<S: SceneStage> Source for SceneFrames<'_, S> {
    type Frame = S::Frame;

    /// The scene file and every file it refers to.
    fn inputs(&self) -> Vec<PathBuf> {
        self.source.files().to_vec()
    }

    fn name(&self) -> String {
        self.source.path().display().to_string()
    }

    /// The animation's frames at the frame rate (its first and last pose
    /// included), or one frame for a still scene.
    fn frame_count(&self) -> usize {
        self.frame_count
    }

    fn frames_per_second(&self) -> Option<(u32, u32)> {
        Some(self.stage.frame_rate(self.options.frames_per_second))
    }

    fn band_hololines(&self) -> Option<usize> {
        self.stage.band_hololines(self.geometry)
    }

    fn place(&mut self, frames: &Range<usize>, warnings: &mut Warnings) -> Result<()> {
        let mut scene = self.scene_at(frames.start as f64 / self.options.frames_per_second)?;
        let placed = place(&mut scene, self.geometry, &self.options.placement)?;
        warnings.merge_frame(&scene.warnings);
        self.stage.placed(&scene, &placed);
        (self.placed, self.first, self.first_number) = (Some(placed), Some((frames.start, scene)), frames.start);
        Ok(())
    }

    fn provenance(&self) -> String {
        self.stage.provenance(self.source.path())
    }

    fn placement(&self) -> Option<crate::math::Mat4> {
        self.placed.as_ref().map(|p| p.matrix)
    }

    fn conversion(&self) -> Result<Option<ConversionRecord>> {
        match self.stage.converter(&self.options) {
            Some(options) => Ok(Some(options.record(&RecordHead::of_input(ConvertOptions::KIND, self.source.path())?))),
            None => Ok(None),
        }
    }

    fn stage_times(&self) -> crate::progress::Timings {
        let mut t = crate::progress::Timings::default();
        t.add("decode", self.decoding);
        t
    }

    fn render(
        &mut self,
        number: usize,
        frame: &mut S::Frame,
        progress: &dyn Progress,
        warnings: &mut Warnings,
    ) -> Result<()> {
        let decoding = std::time::Instant::now();
        let scene = match (self.first.take(), self.banded.take()) {
            // Its warnings were taken at placement.
            (Some((n, scene)), _) if n == number => scene,
            // The next band of the frame being made.
            (_, Some((n, scene))) if n == number => scene,
            _ => {
                let placed = self
                    .placed
                    .as_ref()
                    .ok_or_else(|| Error::argument("placement", "internal: the scene was not placed"))?;
                let mut scene = self.scene_at(number as f64 / self.options.frames_per_second)?;
                apply(&mut scene, &placed.matrix);
                warnings.merge_frame(&scene.warnings);
                scene
            }
        };
        self.decoding += decoding.elapsed();
        let made = self.stage.make(number, number - self.first_number, &scene, frame, progress);
        if self.stage.band_hololines(self.geometry).is_some() {
            self.banded = Some((number, scene));
        }
        made
    }
}

/// What the first frame of a mesh conversion was.
#[derive(Clone, Debug)]
struct First {
    triangles: usize,
    objects: usize,
    placed: Placed,
    lights: Vec<Light>,
}

/// Scenes rendered into `.holo` frames by the mesh renderer ([`render_band_into`]).
#[derive(Debug)]
pub struct MeshRender {
    render: RenderOptions,
    first: Option<First>,
    /// Work counters summed over the frames rendered.
    pub stats: RenderStats,
}

impl MeshRender {
    /// Rendering with `options`' render options.
    pub fn new(options: &ConvertOptions) -> Self {
        MeshRender { render: options.render.clone(), first: None, stats: RenderStats::default() }
    }
}

/// A scene file as a [`Source`] of `.holo` frames.
pub type MeshSource<'a> = SceneFrames<'a, MeshRender>;

impl SceneStage for MeshRender {
    type Frame = Band;

    fn frame_rate(&self, frames_per_second: f64) -> (u32, u32) {
        crate::frame_rate::stored_fraction(frames_per_second)
    }

    fn placed(&mut self, scene: &Scene, placed: &Placed) {
        let lights = self.render.lighting_for(scene).lights;
        let (triangles, objects) = (scene.triangle_count(), scene.objects.len());
        self.first = Some(First { triangles, objects, placed: placed.clone(), lights });
    }

    fn provenance(&self, input: &Path) -> String {
        let name = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let (triangles, objects, placed) = match &self.first {
            Some(f) => (f.triangles, f.objects, f.placed.to_string()),
            None => (0, 0, String::new()),
        };
        format!(
            "holo convert mesh {name} ({triangles} triangles, {objects} objects; {placed}; supersampling {}x{}{}, {} lobe)",
            self.render.supersample.emitter,
            self.render.supersample.view,
            match self.render.supersample.hololine {
                1 => String::new(),
                h => format!(", {h} lines per hololine"),
            },
            self.render.lighting.model.name()
        )
    }

    fn converter(&self, scene: &SceneFramesOptions) -> Option<ConvertOptions> {
        Some(ConvertOptions { scene: scene.clone(), render: self.render.clone(), write: WriteOptions::default() })
    }

    /// Full-parallax frames, `V·W` samples an emitter, by bands: a band of
    /// emitter rows and all their views is what memory holds (as
    /// `convert cameras` does). Horizontal parallax renders whole frames.
    fn band_hololines(&self, geometry: &Geometry) -> Option<usize> {
        geometry.vertical_views.as_ref().map(|_| 4 * rayon::current_num_threads().max(4))
    }

    fn make(
        &mut self,
        number: usize,
        _: usize,
        scene: &Scene,
        frame: &mut Band,
        progress: &dyn Progress,
    ) -> Result<()> {
        let progress = Labelled::new(progress, format!("frame {number}"));
        self.stats += render_band_into(scene, &self.render, &progress, frame)?;
        Ok(())
    }
}
