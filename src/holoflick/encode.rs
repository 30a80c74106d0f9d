//! `holo holoflick encode`: the geometry shader of Deering, *HoloFlicks* §8 over a glTF
//! (or OBJ, PLY) scene, for one display. Every frame (an animated glTF: one
//! per `1/fps`) is placed in display metres as `holo convert mesh` places it
//! (fitted on the first frame, kept after; or as the caller's placement
//! says, which the file's provenance then records), diced into micropolygons sized
//! for what the display resolves at their depth ([`super::shader::dice`],
//! far from the emitter plane they are larger, Deering, *HoloFlicks* §12), lit once
//! (ambient, diffuse and optionally shadows baked into vertex colours,
//! [`super::shader::bake`]), and compressed; specular reflectance and
//! exponent stay as materials, the scene's lights as specular lights. The
//! viewer's couch is a box around the display's viewing zone, so
//! `holo convert holoflick` draws the result as it is. Objects that do not
//! change between frames are stored once per key frame.

use std::path::Path;

use super::cg::EncodeOptions;
use super::container::{Frame, ViewerCouch};
use super::shader::bake::BakeOptions;
use super::shader::dice::{display_budget, DiceOptions};
use super::shader::micro::micropolygons;
use super::sink::HoloFlickSink;
use super::tools::{specular_light, KeyFrames, PackReport};
use crate::error::{Error, Result};
use crate::frame_rate::stored_fraction;
use crate::geometry::Geometry;
use crate::mesh::convert::{SceneFrames, SceneFramesOptions, SceneStage};
use crate::mesh::place::Placed;
use crate::mesh::render::RenderOptions;
use crate::mesh::{Light, Scene};
use crate::pipeline;
use crate::progress::Progress;

/// The default micropolygon edge, as a multiple of what the display
/// resolves at its depth: the knee of the measured error against size (the
/// bundled Spot on Mark III, BENCHMARKS.md "HoloFlick micropolygon size"):
/// from 4 to 2 the error halves for 3.7 times the bytes; from 2 to 1 it
/// falls by a third for 3.7 times the bytes again, near the floor the
/// codec's quantization sets.
pub const DEFAULT_MICROPOLYGON: f64 = 2.0;

/// How to encode.
#[derive(Clone, Debug)]
pub struct HoloFlickEncodeOptions {
    /// Placement, frames and frame rate.
    pub scene: SceneFramesOptions,
    /// Micropolygon edge as a multiple of what the display resolves at its
    /// depth (1: one display sample; smaller is finer).
    pub micropolygon: f64,
    /// Bend micropolygons onto the surface the normals describe.
    pub smooth: bool,
    /// Bake shadows of the scene's lights.
    pub shadows: bool,
    /// Quantization.
    pub encode: EncodeOptions,
    /// A key frame every this many frames.
    pub key_interval: usize,
    /// Replace an existing output.
    pub overwrite: bool,
}

impl Default for HoloFlickEncodeOptions {
    fn default() -> Self {
        HoloFlickEncodeOptions {
            scene: SceneFramesOptions::default(),
            micropolygon: DEFAULT_MICROPOLYGON,
            smooth: true,
            shadows: false,
            encode: EncodeOptions::default(),
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
/// widened by the display's height and a little depth; for full parallax
/// the rectangle the views reach at the viewer's distance, widened alike
/// (Deering's viewer couch is a region of eye positions; a full-parallax
/// display's eyes move up and down as well).
pub fn display_couch(g: &Geometry) -> ViewerCouch {
    let d = g.viewer_distance_m - g.emitter_z_m;
    let (lo, hi) = g.viewer_line_reach_m();
    let height = (g.hololine_y_m(0) - g.hololine_y_m(g.hololines.saturating_sub(1))).abs() + g.hololine_pitch_m;
    let margin = 0.05 * d.abs().max(1e-3);
    let (y_lo, y_hi) = match g.vertical_reach_at_m(g.viewer_distance_m) {
        Some((y_lo, y_hi)) => (y_lo - margin, y_hi + margin),
        None => (g.viewer_height_m - height, g.viewer_height_m + height),
    };
    ViewerCouch {
        min_m: [lo - margin, y_lo, g.viewer_distance_m - margin],
        max_m: [hi + margin, y_hi, g.viewer_distance_m + margin],
    }
}

/// Encode `input` for `geometry` into the HoloFlick `output`: scenes
/// through [`Encode`] and [`crate::pipeline`]. `progress` counts the frames
/// of a movie and, within each, its stages: input triangles diced, vertices
/// lit, objects compressed.
pub fn encode_holoflick(
    input: &Path,
    geometry: &Geometry,
    output: &Path,
    options: &HoloFlickEncodeOptions,
    progress: &dyn Progress,
) -> Result<HoloFlickEncodeReport> {
    super::tools::check_key_interval(options.key_interval)?;
    if !(options.micropolygon.is_finite() && options.micropolygon > 0.0) {
        return Err(Error::argument(
            "micropolygon size",
            format!(
                "the micropolygon size must be a positive multiple of what the display resolves, not {}",
                options.micropolygon
            ),
        ));
    }
    let stage = Encode {
        options,
        budget: Box::new(display_budget(geometry, options.micropolygon)),
        couch: display_couch(geometry),
        keys: KeyFrames::default(),
        report: PackReport::default(),
        micropolygons: 0,
        shadowed: 0,
        placed: None,
    };
    let open = |input: &Path| SceneFrames::open(input, geometry, &options.scene, stage);
    let sink = HoloFlickSink::new(output, options.overwrite);
    let (source, run) = pipeline::open_and_run(input, open, sink, options.scene.frames.clone(), progress)?;
    let placed =
        source.placed().cloned().ok_or_else(|| Error::argument("placement", "internal: the scene was never placed"))?;
    let Encode { mut report, micropolygons, shadowed, .. } = source.stage;
    (report.path, report.frames, report.file_bytes) = (output.to_path_buf(), run.frames.len(), run.written.file_bytes);
    report.warnings = run.warnings;
    Ok(HoloFlickEncodeReport { pack: report, placed, micropolygons, shadowed })
}

/// Scenes made into HoloFlick frames for one display: each placed scene
/// diced, baked and compressed (the [`SceneStage`] of `holoflick encode`).
pub struct Encode<'a> {
    options: &'a HoloFlickEncodeOptions,
    /// The largest micropolygon edge at a point, in metres.
    budget: Box<dyn Fn([f64; 3]) -> f64 + Sync + 'a>,
    couch: ViewerCouch,
    keys: KeyFrames,
    report: PackReport,
    micropolygons: usize,
    shadowed: usize,
    /// The placement in words, when the caller chose it (a fitted one
    /// follows from the scene alone and is not said).
    placed: Option<String>,
}

impl SceneStage for Encode<'_> {
    type Frame = Frame;

    fn frame_rate(&self, frames_per_second: f64) -> (u32, u32) {
        stored_fraction(frames_per_second)
    }

    fn placed(&mut self, _: &Scene, placed: &Placed) {
        let chosen = self.options.scene.placement != crate::mesh::place::Placement::default();
        self.placed = chosen.then(|| placed.to_string());
    }

    fn provenance(&self, input: &Path) -> String {
        let o = self.options;
        format!(
            "holo holoflick encode {} (micropolygons {}× the display's resolution{}{}; {}/{}/{} bits{})",
            input.display(),
            o.micropolygon,
            if o.smooth { ", smooth" } else { "" },
            if o.shadows { ", shadows" } else { "" },
            o.encode.position_bits,
            o.encode.color_bits,
            o.encode.normal_bits,
            self.placed.as_ref().map_or(String::new(), |p| format!("; {p}"))
        )
    }

    fn make(&mut self, _: usize, index: usize, scene: &Scene, frame: &mut Frame, stages: &dyn Progress) -> Result<()> {
        let o = self.options;
        // Baked with the lights a render of the scene uses, as `convert mesh`
        // lights it.
        let lights = RenderOptions::default().lighting_for(scene).lights;
        // Directional and ambient light without shadows is affine across a
        // flat untextured triangle: such triangles need no dicing.
        let affine_shading =
            !o.shadows && lights.iter().all(|l| matches!(l, Light::Directional { .. } | Light::Ambient { .. }));
        let dice = DiceOptions { smooth: o.smooth, affine_shading, ..DiceOptions::default() };
        let bake = BakeOptions { shadows: o.shadows };
        let (micro, specular_lights, micro_report) =
            micropolygons(scene, &lights, &*self.budget, &dice, &bake, stages)?;
        self.micropolygons += micro_report.dice.triangles_out;
        self.shadowed += micro_report.bake.shadowed;
        let is_key = self.keys.start_frame(index, o.key_interval);
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
