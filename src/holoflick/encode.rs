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
use std::path::Path;

use super::cg::EncodeOptions;
use super::container::{HoloFlickWriter, ViewerCouch};
use super::shader::bake::BakeOptions;
use super::shader::dice::{display_budget, DiceOptions};
use super::shader::micro::micropolygons;
use super::tools::{specular_light, writer_options, KeyFrames, PackReport};
use crate::geometry::Geometry;
use crate::mesh::load::SceneSource;
use crate::mesh::place::{apply, place, Placed, Placement};
use crate::mesh::render::RenderOptions;
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

/// Encode `input` for `geometry` into the HoloFlick `output`;
/// `progress(frames done, frames)`.
pub fn encode_holoflick(
    input: &Path,
    geometry: &Geometry,
    output: &Path,
    options: &HoloFlickEncodeOptions,
    progress: &dyn Fn(usize, usize),
) -> Result<HoloFlickEncodeReport> {
    if !(options.frames_per_second.is_finite() && options.frames_per_second > 0.0) {
        return Err(Error::argument(
            "frame rate",
            format!("--fps must be positive (got {})", options.frames_per_second),
        ));
    }
    if !(options.micropolygon.is_finite() && options.micropolygon > 0.0) {
        return Err(Error::argument(
            "micropolygon",
            format!("--micropolygon must be positive (got {})", options.micropolygon),
        ));
    }
    crate::output::check_output(output, &[input], options.overwrite)?;
    let source = SceneSource::open(input)?;
    let frames = match (&options.frames, source.animation_duration_s()) {
        (Some(r), Some(_)) => r.clone(),
        (Some(r), None) if *r == (0..1) => r.clone(),
        (Some(r), None) => {
            return Err(Error::argument(
                "frame range",
                format!(
                    "{}: the scene is not animated, so it has one frame (0); --frames asked for {}..{}",
                    input.display(),
                    r.start,
                    r.end
                ),
            ))
        }
        (None, Some(d)) => 0..((d * options.frames_per_second).floor() as usize + 1),
        (None, None) => 0..1,
    };
    if frames.is_empty() {
        return Err(Error::argument(
            "frame range",
            format!("the frame range {}..{} is empty", frames.start, frames.end),
        ));
    }
    let mut first = source.scene_at(frames.start as f64 / options.frames_per_second)?;
    let placed = place(&mut first, geometry, &options.placement)?;
    let provenance = format!(
        "holo holoflick encode {} (micropolygons {}× the display's resolution{}{}; {}/{}/{} bits)",
        input.display(),
        options.micropolygon,
        if options.smooth { ", smooth" } else { "" },
        if options.shadows { ", shadows" } else { "" },
        options.encode.position_bits,
        options.encode.color_bits,
        options.encode.normal_bits
    );
    let write = writer_options(options.frames_per_second, provenance, options.overwrite);
    let mut writer = HoloFlickWriter::create(output, &write)?;
    let budget = display_budget(geometry, options.micropolygon);
    let dice = DiceOptions { smooth: options.smooth, ..DiceOptions::default() };
    let bake = BakeOptions { shadows: options.shadows };
    let couch = display_couch(geometry);
    let mut keys = KeyFrames::default();
    let mut report = PackReport { path: output.to_path_buf(), ..PackReport::default() };
    let (mut micro_count, mut shadowed) = (0, 0);
    let mut first = Some(first);
    for (i, n) in frames.clone().enumerate() {
        let scene = match first.take() {
            Some(s) => s,
            None => {
                let mut s = source.scene_at(n as f64 / options.frames_per_second)?;
                apply(&mut s, &placed.matrix);
                s
            }
        };
        // Baked with the lights a render of the scene uses, as `convert mesh`
        // lights it.
        let lights = RenderOptions::default().lighting_for(&scene).lights;
        let (micro, specular_lights, micro_report) = micropolygons(&scene, &lights, &budget, &dice, &bake)?;
        micro_count += micro_report.dice.triangles_out;
        shadowed += micro_report.bake.shadowed;
        let is_key = keys.start_frame(i, options.key_interval);
        let lights = specular_lights.iter().filter_map(specular_light).collect();
        // Objects diced to nothing (wholly culled) are left out.
        let objects = micro.objects.into_iter().filter(|o| !o.triangles.is_empty());
        let frame = keys.frame(is_key, couch, lights, objects, &options.encode, &mut report)?;
        writer.add_frame(&frame)?;
        progress(i + 1, frames.len());
    }
    let written = writer.finish()?;
    report.frames = frames.len();
    report.file_bytes = written.file_bytes;
    Ok(HoloFlickEncodeReport { pack: report, placed, micropolygons: micro_count, shadowed })
}
