//! `holo holoflick encode`: the geometry shader of Deering, *HoloFlicks* §8 over a glTF
//! (or OBJ, PLY) scene, for one display. Every frame (an animated glTF: one
//! per `1/fps`) is placed in display metres as `holo convert mesh` places it
//! (fitted on the first frame, kept after), diced into micropolygons sized
//! for what the display resolves at their depth ([`super::shader::dice`],
//! far from the emitter plane they are larger, Deering, *HoloFlicks* §12), lit once
//! (ambient, diffuse and optionally shadows baked into vertex colours,
//! [`super::shader::bake`]), and compressed; specular reflectance and
//! exponent stay as materials, the scene's lights as specular lights. The
//! viewer's couch is a box around the display's viewing zone, so
//! `holo convert holoflick` draws the result as it is. Objects that do not
//! change between frames are stored once per key frame.

use std::ops::Range;
use std::path::{Path, PathBuf};

use super::cg::EncodeOptions;
use super::container::{Frame, ViewerCouch};
use super::shader::bake::BakeOptions;
use super::shader::dice::{display_budget, DiceOptions};
use super::shader::micro::micropolygons;
use super::sink::{frame_rate_fraction, HoloFlickSink};
use super::tools::{specular_light, KeyFrames, PackReport};
use crate::geometry::Geometry;
use crate::mesh::convert::PlacedScenes;
use crate::mesh::place::{Placed, Placement};
use crate::mesh::render::RenderOptions;
use crate::mesh::Scene;
use crate::pipeline::{self, Source, Warnings};
use crate::progress::Progress;
use crate::{Error, Result};

/// How to encode.
#[derive(Clone, Debug)]
pub struct HoloFlickEncodeOptions {
    /// Where the scene goes in the display.
    pub placement: Placement,
    /// Micropolygon edge as a multiple of what the display resolves at its
    /// depth (1: one display sample; smaller is finer).
    pub micropolygon: f64,
    /// Bend micropolygons onto the surface the normals describe.
    pub smooth: bool,
    /// Bake shadows of the scene's lights.
    pub shadows: bool,
    /// Quantization.
    pub encode: EncodeOptions,
    /// Animation sampling rate and frame rate.
    pub frames_per_second: f64,
    /// Frames to encode (animated scenes); default all.
    pub frames: Option<Range<usize>>,
    /// A key frame every this many frames.
    pub key_interval: usize,
    /// Replace an existing output.
    pub overwrite: bool,
}

impl Default for HoloFlickEncodeOptions {
    fn default() -> Self {
        HoloFlickEncodeOptions {
            placement: Placement::default(),
            micropolygon: 1.0,
            smooth: true,
            shadows: false,
            encode: EncodeOptions::default(),
            frames_per_second: 30.0,
            frames: None,
            key_interval: 30,
            overwrite: false,
        }
    }
}

/// What encoding did.
#[derive(Clone, Debug)]
pub struct HoloFlickEncodeReport {
    /// Frames, objects stored and referred to, triangles, bytes.
    pub pack: PackReport,
    /// The placement used for every frame.
    pub placed: Placed,
    /// Micropolygons over all frames.
    pub micropolygons: usize,
    /// (vertex, light) pairs found in shadow.
    pub shadowed: usize,
}

/// The couch for a display: its viewing zone (the viewer line's reach),
/// widened by the display's height and a little depth.
pub fn display_couch(g: &Geometry) -> ViewerCouch {
    let d = g.viewer_distance_m - g.emitter_z_m;
    let (lo, hi) = g.viewer_line_reach_m();
    let height = (g.hololine_y_m(0) - g.hololine_y_m(g.hololines.saturating_sub(1))).abs() + g.hololine_pitch_m;
    let margin = 0.05 * d.abs().max(1e-3);
    ViewerCouch {
        min_m: [lo - margin, g.viewer_height_m - height, g.viewer_distance_m - margin],
        max_m: [hi + margin, g.viewer_height_m + height, g.viewer_distance_m + margin],
    }
}

/// Encode `input` for `geometry` into the HoloFlick `output`: an
/// [`EncodeSource`] through [`crate::pipeline::run`]. `progress` counts the
/// frames of a movie; of a single frame, its stages (dicing and baking, then
/// the objects compressed).
pub fn encode_holoflick(
    input: &Path,
    geometry: &Geometry,
    output: &Path,
    options: &HoloFlickEncodeOptions,
    progress: &dyn Progress,
) -> Result<HoloFlickEncodeReport> {
    if !(options.micropolygon.is_finite() && options.micropolygon > 0.0) {
        return Err(Error::Usage(format!(
            "the micropolygon size must be a positive multiple of what the display resolves, not {}",
            options.micropolygon
        )));
    }
    crate::output::check_output(output, &[input], options.overwrite)?;
    let mut source = EncodeSource {
        scenes: PlacedScenes::open(input, options.frames_per_second)?,
        geometry,
        options,
        budget: Box::new(display_budget(geometry, options.micropolygon)),
        couch: display_couch(geometry),
        first: 0,
        keys: KeyFrames::default(),
        report: PackReport::default(),
        micropolygons: 0,
        shadowed: 0,
    };
    let sink = HoloFlickSink::new(output, options.overwrite);
    let run = pipeline::run(&mut source, sink, options.frames.clone(), progress)?;
    let mut pack = source.report;
    (pack.path, pack.frames, pack.file_bytes) = (output.to_path_buf(), run.frames.len(), run.written.file_bytes);
    pack.warnings = run.warnings;
    let placed = source.scenes.placed.ok_or_else(|| Error::Usage("internal: the scene was never placed".into()))?;
    Ok(HoloFlickEncodeReport { pack, placed, micropolygons: source.micropolygons, shadowed: source.shadowed })
}

/// A scene file as a [`Source`] of HoloFlick frames for one display: each
/// frame placed, diced, baked and compressed.
pub struct EncodeSource<'a> {
    scenes: PlacedScenes,
    geometry: &'a Geometry,
    options: &'a HoloFlickEncodeOptions,
    /// The largest micropolygon edge at a point, in metres.
    budget: Box<dyn Fn([f64; 3]) -> f64 + Sync>,
    couch: ViewerCouch,
    /// The first frame of the run: key frames count from it.
    first: usize,
    keys: KeyFrames,
    report: PackReport,
    micropolygons: usize,
    shadowed: usize,
}

impl Source for EncodeSource<'_> {
    type Frame = Frame;

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
        Some(frame_rate_fraction(self.scenes.frames_per_second()))
    }

    fn place(&mut self, frames: &Range<usize>, warnings: &mut Warnings) -> Result<()> {
        self.first = frames.start;
        let scene = self.scenes.place(frames.start, self.geometry, &self.options.placement)?;
        warnings.merge_frame(&scene.warnings);
        Ok(())
    }

    fn provenance(&self) -> String {
        let o = self.options;
        format!(
            "holo holoflick encode {} (micropolygons {}× the display's resolution{}{}; {}/{}/{} bits)",
            self.scenes.path().display(),
            o.micropolygon,
            if o.smooth { ", smooth" } else { "" },
            if o.shadows { ", shadows" } else { "" },
            o.encode.position_bits,
            o.encode.color_bits,
            o.encode.normal_bits
        )
    }

    fn render(
        &mut self,
        number: usize,
        frame: &mut Frame,
        stages: &dyn Progress,
        warnings: &mut Warnings,
    ) -> Result<()> {
        if !self.scenes.is_kept(number) {
            // Seen at placement otherwise.
            let scene = self.scenes.scene(number)?;
            warnings.merge_frame(&scene.warnings);
            return self.encode(number, scene, frame, stages);
        }
        let scene = self.scenes.scene(number)?;
        self.encode(number, scene, frame, stages)
    }
}

impl EncodeSource<'_> {
    /// Dice, bake and compress `scene` as frame `number`.
    fn encode(&mut self, number: usize, scene: Scene, frame: &mut Frame, stages: &dyn Progress) -> Result<()> {
        let o = self.options;
        // Baked with the lights a render of the scene uses, as `convert mesh`
        // lights it.
        let lights = RenderOptions::default().lighting_for(&scene).lights;
        stages.phase("micropolygons (dice and bake)", 1);
        let dice = DiceOptions { smooth: o.smooth, ..DiceOptions::default() };
        let bake = BakeOptions { shadows: o.shadows };
        let (micro, specular_lights, micro_report) = micropolygons(&scene, &lights, &*self.budget, &dice, &bake)?;
        stages.advance(1);
        self.micropolygons += micro_report.dice.triangles_out;
        self.shadowed += micro_report.bake.shadowed;
        let is_key = self.keys.start_frame(number - self.first, o.key_interval);
        let lights = specular_lights.iter().filter_map(specular_light).collect();
        // Objects diced to nothing (wholly culled) are left out.
        let objects: Vec<_> = micro.objects.into_iter().filter(|o| !o.triangles.is_empty()).collect();
        let count = objects.len();
        stages.phase("objects compressed", count as u64);
        // The k-th object is handed out when the k before it are compressed.
        let objects = objects.into_iter().enumerate().map(|(k, o)| {
            stages.advance(k as u64);
            o
        });
        *frame = self.keys.frame(is_key, self.couch, lights, objects, &o.encode, &mut self.report)?;
        stages.advance(count as u64);
        Ok(())
    }
}
