//! `holo holoflick pack | unpack | info`: HoloFlicks (and Java 3D `.cg`
//! files) from meshes, back to meshes, and described.
//!
//! `pack` stores meshes as they are, one frame per file (an animated glTF:
//! one frame per `1/fps` of its animation): each object's colours are its
//! base colour at the vertices (factor × vertex colour × texture), its
//! normals its own (flat-shaded objects get one vertex per corner), its
//! specular reflectance and exponent a material, the scene's lights the
//! specular lights. Lighting and dicing are the converter's business
//! (`holo holoflick encode`). An object whose block comes out identical to
//! the last key frame's is stored as a reference to it (Deering, *HoloFlicks* §13).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::cg::{CgFile, EncodeOptions};
use super::container::{
    Binding, Frame, GeometryBlock, HoloFlickReader, KeyFrameReference, ObjectRecord, SpecularLight, SpecularMaterial,
    SpecularModel, ViewerCouch, IDENTITY,
};
use super::objects::{decode_object, encode_object};
use super::sink::HoloFlickSink;
use crate::error::{Error, Result};
use crate::frame_rate::stored_fraction;
use crate::math::{unit, widen};
use crate::mesh::load::SceneSource;
use crate::mesh::shade::sample;
use crate::mesh::{Light, Object, Scene};
use crate::pipeline::{self, Source, Warnings};
use crate::progress::Progress;

/// How to pack.
#[derive(Clone, Debug)]
pub struct PackOptions {
    /// Quantization.
    pub encode: EncodeOptions,
    /// Frame rate, and the rate animations are sampled at.
    pub frames_per_second: f64,
    /// Frames of an animated input to keep (all by default).
    pub frames: Option<std::ops::Range<usize>>,
    /// The viewer's couch; default: a box in front of the first frame (+z).
    pub couch: Option<ViewerCouch>,
    /// A key frame every this many frames (frame 0 always is one).
    pub key_interval: usize,
    /// Replace an existing output.
    pub overwrite: bool,
}

impl Default for PackOptions {
    fn default() -> Self {
        PackOptions {
            encode: EncodeOptions::default(),
            frames_per_second: 30.0,
            frames: None,
            couch: None,
            key_interval: 30,
            overwrite: false,
        }
    }
}

/// What packing did.
#[derive(Clone, Debug, Default)]
pub struct PackReport {
    /// The file written.
    pub path: PathBuf,
    /// Frames written.
    pub frames: usize,
    /// Objects stored (blocks written).
    pub stored: usize,
    /// Objects stored once in a key frame and referred to.
    pub references: usize,
    /// Triangles over all frames (references counted where they are shown).
    pub triangles: usize,
    /// Compressed stream bytes written.
    pub stream_bytes: usize,
    /// The file's size.
    pub file_bytes: u64,
    /// For `.cg` output, each object's `model = normalised × (1/scale) + centre`
    /// as (centre, 1/scale): a `.cg` file cannot hold it.
    pub cg_transforms: Vec<([f64; 3], f64)>,
    /// Things the user should know.
    pub warnings: Vec<String>,
}

/// One frame to pack: which file, at which animation time.
struct FrameSource {
    input: usize,
    time_s: f64,
}

/// A key frame every `interval` frames: at least every frame.
pub(crate) fn check_key_interval(interval: usize) -> Result<()> {
    if interval == 0 {
        return Err(Error::argument("key interval", "the key-frame interval must be 1 frame or more, not 0"));
    }
    Ok(())
}

/// Pack `inputs` (glTF, OBJ or PLY) into `output`: a HoloFlick, or a Java 3D
/// `.cg` file (one frame's objects, no transforms) when its name ends in
/// `.cg`. `progress` counts the frames.
pub fn pack(inputs: &[PathBuf], output: &Path, options: &PackOptions, progress: &dyn Progress) -> Result<PackReport> {
    if inputs.is_empty() {
        return Err(Error::argument("meshes", "pack needs at least one mesh"));
    }
    check_key_interval(options.key_interval)?;
    let read: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    let _claim = crate::output::check_output(output, &read, options.overwrite)?;
    let mut source = PackSource::open(inputs, options)?;
    let sink = HoloFlickSink::new(output, options.overwrite);
    let run = pipeline::run(&mut source, sink, options.frames.clone(), progress)?;
    let mut report = PackReport { file_bytes: run.written.file_bytes, frames: run.frames.len(), ..Default::default() };
    if let Some(cg) = run.written.cg {
        for (name, scale) in source.names.iter().zip(&cg.radiance_scales) {
            if *scale != 1.0 {
                report.warnings.push(format!(
                    "object \"{name}\": colours above 1 were scaled by 1/{scale:.4} (a .cg file cannot hold the scale)"
                ));
            }
        }
        report.cg_transforms = cg.transforms;
    }
    report.warnings.extend(run.warnings);
    let counted = &source.report;
    report.path = output.to_path_buf();
    (report.stored, report.references) = (counted.stored, counted.references);
    (report.triangles, report.stream_bytes) = (counted.triangles, counted.stream_bytes);
    Ok(report)
}

/// Meshes as a [`Source`] of HoloFlick frames: one frame per file, or per
/// `1/fps` of an animated file's animation, stored as they are.
struct PackSource<'a> {
    inputs: &'a [PathBuf],
    scenes: Vec<SceneSource>,
    frames: Vec<FrameSource>,
    options: &'a PackOptions,
    /// The first frame run and the couch every frame gets.
    first: usize,
    couch: Option<ViewerCouch>,
    keys: KeyFrames,
    /// Objects stored and referred to, triangles and bytes, over the frames.
    report: PackReport,
    /// The last frame's object names, in order.
    names: Vec<String>,
}

impl<'a> PackSource<'a> {
    fn open(inputs: &'a [PathBuf], options: &'a PackOptions) -> Result<Self> {
        let fps = options.frames_per_second;
        pipeline::check_frame_rate(fps)?;
        let scenes: Vec<SceneSource> = inputs.iter().map(|p| SceneSource::open(p)).collect::<Result<_>>()?;
        // Counted (and refused past what a movie may have) before any is made.
        let counts = scenes
            .iter()
            .map(|s| match s.animation_duration_s() {
                Some(d) if d > 0.0 => pipeline::animation_frames(s.path(), d, fps),
                _ => Ok(1),
            })
            .collect::<Result<Vec<usize>>>()?;
        let total: u64 = counts.iter().map(|&c| c as u64).sum();
        if total > pipeline::MAX_SOURCE_FRAMES {
            return Err(Error::argument(
                "frame rate",
                format!(
                    "the meshes make {total} frames at {fps} frames per second, more than the {} a movie may have: \
                     lower the frame rate",
                    pipeline::MAX_SOURCE_FRAMES
                ),
            ));
        }
        let mut frames = Vec::new();
        for (input, (s, &count)) in scenes.iter().zip(&counts).enumerate() {
            match s.animation_duration_s() {
                Some(d) if d > 0.0 => {
                    frames.extend((0..count).map(|k| FrameSource { input, time_s: k as f64 / fps }));
                }
                _ => frames.push(FrameSource { input, time_s: 0.0 }),
            }
        }
        Ok(PackSource {
            inputs,
            scenes,
            frames,
            options,
            first: 0,
            couch: options.couch,
            keys: KeyFrames::default(),
            report: PackReport::default(),
            names: Vec::new(),
        })
    }
}

impl Source for PackSource<'_> {
    type Frame = Frame;

    /// The meshes and every file they refer to.
    fn inputs(&self) -> Vec<PathBuf> {
        self.scenes.iter().flat_map(|s| s.files().iter().cloned()).collect()
    }

    fn name(&self) -> String {
        self.inputs.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(" ")
    }

    fn frame_count(&self) -> usize {
        self.frames.len()
    }

    fn frames_per_second(&self) -> Option<(u32, u32)> {
        Some(stored_fraction(self.options.frames_per_second))
    }

    fn place(&mut self, frames: &std::ops::Range<usize>, _: &mut Warnings) -> Result<()> {
        self.first = frames.start;
        Ok(())
    }

    fn provenance(&self) -> String {
        let e = &self.options.encode;
        format!("holo holoflick pack {} ({}/{}/{} bits)", self.name(), e.position_bits, e.color_bits, e.normal_bits)
    }

    fn render(&mut self, number: usize, frame: &mut Frame, _: &dyn Progress, _: &mut Warnings) -> Result<()> {
        let f = &self.frames[number];
        let scene = self.scenes[f.input].scene_at(f.time_s)?;
        let couch = *self.couch.get_or_insert_with(|| couch_in_front(&scene));
        let is_key = self.keys.start_frame(number - self.first, self.options.key_interval);
        let lights = scene.lights.iter().filter_map(specular_light).collect();
        self.names = scene.objects.iter().map(|o| o.name.clone()).collect();
        let objects = scene.objects.iter().map(|o| coloured(&scene, o));
        *frame = self.keys.frame(is_key, couch, lights, objects, &self.options.encode, &mut self.report)?;
        Ok(())
    }
}

/// Key frames (Deering, *HoloFlicks* §13): an object whose block (and colour scale) is
/// the last key frame's is stored as a reference to it.
#[derive(Default)]
pub(crate) struct KeyFrames {
    blocks: HashMap<u32, (GeometryBlock, f64)>,
    key_frame: u32,
    is_key: bool,
}

impl KeyFrames {
    /// Begin frame `n`: a key frame every `interval` frames. Returns whether it is one.
    pub(crate) fn start_frame(&mut self, n: usize, interval: usize) -> bool {
        self.is_key = n % interval == 0;
        if self.is_key {
            self.blocks.clear();
            self.key_frame = n as u32;
        }
        self.is_key
    }

    /// A frame of `objects` (an object's id is its place in the frame: the
    /// k-th object of every frame is one object), each with its specular
    /// material (Blinn unless the material names Phong) bound to every
    /// light; objects unchanged since the key frame are references to it.
    pub(crate) fn frame(
        &mut self,
        is_key: bool,
        couch: ViewerCouch,
        lights: Vec<SpecularLight>,
        objects: impl Iterator<Item = Object>,
        encode: &EncodeOptions,
        report: &mut PackReport,
    ) -> Result<Frame> {
        let all_lights: Vec<u32> = (0..lights.len() as u32).collect();
        let mut frame = Frame {
            key_frame: is_key,
            couch,
            lights,
            materials: Vec::new(),
            bindings: Vec::new(),
            objects: Vec::new(),
        };
        for (k, o) in objects.enumerate() {
            let (g, stats) = encode_object(k as u32, &o, encode)?;
            report.triangles += stats.triangles;
            frame.materials.push(SpecularMaterial {
                specular: o.material.specular.map(f64::from),
                exponent: o.material.shininess.max(0.0) as f64,
                model: match o.material.specular_model {
                    Some(crate::mesh::shade::SpecularModel::Phong) => SpecularModel::Phong,
                    _ => SpecularModel::Blinn,
                },
            });
            frame.bindings.push(Binding {
                object_id: k as u32,
                material: (frame.materials.len() - 1) as u32,
                lights: all_lights.clone(),
            });
            self.place(&mut frame, g, report);
        }
        Ok(frame)
    }

    /// Put object `g` into `frame`: stored, or a reference to the key frame.
    fn place(&mut self, frame: &mut Frame, g: super::container::GeometryObject, report: &mut PackReport) {
        match self.blocks.get(&g.id) {
            Some((block, scale)) if !self.is_key && *block == g.block && *scale == g.radiance_scale => {
                report.references += 1;
                frame.objects.push(ObjectRecord::Reference(KeyFrameReference {
                    id: g.id,
                    key_frame: self.key_frame,
                    world_from_object: g.world_from_object,
                }));
            }
            _ => {
                report.stored += 1;
                report.stream_bytes += g.block.stream().len();
                if self.is_key {
                    self.blocks.insert(g.id, (g.block.clone(), g.radiance_scale));
                }
                frame.objects.push(ObjectRecord::Stored(g));
            }
        }
    }
}

/// The object with its base colour at every vertex as vertex colours.
fn coloured(scene: &Scene, o: &Object) -> Object {
    let m = &o.material;
    let mut out = o.clone();
    let texture = m.base_colour_texture.as_ref().and_then(|r| {
        let uv = o.uv_sets.get(r.uv_set).filter(|s| s.len() == o.positions.len())?;
        Some((scene.textures.get(r.texture)?, uv, r.transform))
    });
    if o.colours.is_empty() && texture.is_none() && m.base_colour == [1.0; 4] {
        return out;
    }
    out.colours = (0..o.positions.len())
        .map(|i| {
            let v = o.colours.get(i).copied().unwrap_or([1.0; 4]);
            let t = texture.map_or([1.0; 4], |(tex, uv, tr)| sample(tex, tr.apply(uv[i])));
            std::array::from_fn(|k| m.base_colour[k] * v[k] * t[k])
        })
        .collect();
    out
}

pub(crate) fn specular_light(l: &Light) -> Option<SpecularLight> {
    match l {
        Light::Directional { direction, irradiance, .. } => {
            unit(*direction).map(|direction| SpecularLight::Directional { direction, irradiance: widen(*irradiance) })
        }
        Light::Point { position, intensity, .. } => {
            Some(SpecularLight::Point { position_m: *position, intensity: intensity.map(f64::from) })
        }
        Light::Ambient { .. } => None,
    }
}

/// A box in front of the scene (+z, where glTF's viewers are): as wide and
/// tall as the scene plus its size each side, from one to four sizes in
/// front of it.
fn couch_in_front(scene: &Scene) -> ViewerCouch {
    let (lo, hi) = scene.bounds().unwrap_or(([-1.0; 3], [1.0; 3]));
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max).max(1e-3);
    ViewerCouch {
        min_m: [lo[0] - size, lo[1] - size, hi[2] + size],
        max_m: [hi[0] + size, hi[1] + size, hi[2] + 4.0 * size],
    }
}

/// The objects of frame `frame` of a HoloFlick (world metres, pre-lit
/// colours) or of a `.cg` file (its normalised frame; `frame` must be 0).
pub fn frame_objects(input: &Path, frame: usize) -> Result<Vec<Object>> {
    if input.extension().is_some_and(|e| e.eq_ignore_ascii_case("cg")) {
        if frame != 0 {
            return Err(Error::argument("frame", format!("{}: a .cg file has one frame, 0", input.display())));
        }
        let file = CgFile::read(input)?;
        return file
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| {
                let descriptor = super::container::Descriptor::from_cg_header(&o.header);
                let block = GeometryBlock::new(descriptor, &o.bytes)
                    .map_err(|m| stored_object_error(input, format!("object {i}: {m}")))?;
                decode_object(&format!("object {i}"), &block, &IDENTITY, 1.0).map(|(o, _)| o)
            })
            .collect::<Result<Vec<_>>>()
            .map_err(|e| named(input, e));
    }
    let mut reader = HoloFlickReader::open(input)?;
    let count = reader.frame_count() as usize;
    if frame >= count {
        return Err(Error::no_frame(input, frame, count));
    }
    let resolved = reader.read_frame(frame as u32)?;
    resolved
        .objects
        .iter()
        .map(|o| {
            decode_object(&format!("id {}", o.id), &o.block, &o.world_from_object, o.radiance_scale).map(|(o, _)| o)
        })
        .collect::<Result<Vec<_>>>()
        .map_err(|e| named(input, e))
}

/// A stored object that cannot be decoded, as the error of the file that holds it.
fn named(path: &Path, e: Error) -> Error {
    match e {
        Error::Argument { problem, .. } => stored_object_error(path, problem),
        other => other,
    }
}

/// `problem` with a stored object of the HoloFlick or `.cg` file `path`.
fn stored_object_error(path: &Path, problem: String) -> Error {
    use super::container::{At, ContainerError};
    Error::HoloFlick(ContainerError::Invalid { path: path.to_path_buf(), at: At(None), problem })
}

/// `holo holoflick unpack`: frame `frame` of `input` as a `.glb` or `.ply` mesh.
pub fn unpack(input: &Path, frame: usize, output: &Path, overwrite: bool) -> Result<usize> {
    let _claim = crate::output::check_output(output, &[input], overwrite)?;
    let objects = frame_objects(input, frame)?;
    crate::mesh::write::write_mesh(output, &objects, overwrite)?;
    Ok(objects.iter().map(|o| o.triangles.len()).sum())
}

/// `holo holoflick info`: a description of a HoloFlick or `.cg` file, every
/// frame decoded (so counts are triangles, not promises).
pub fn info(input: &Path) -> Result<String> {
    use std::fmt::Write;
    let mut out = String::new();
    let bytes = std::fs::metadata(input).map_err(|e| Error::io(input, e))?.len();
    if input.extension().is_some_and(|e| e.eq_ignore_ascii_case("cg")) {
        let file = CgFile::read(input)?;
        let [a, b, c] = file.version;
        let _ = writeln!(
            out,
            "{}: Java 3D compressed geometry {a}.{b}.{c}, {} objects, {bytes} bytes",
            input.display(),
            file.objects.len()
        );
        let objects = frame_objects(input, 0)?;
        for (o, raw) in objects.iter().zip(&file.objects) {
            let h = raw.header;
            let _ = writeln!(
                out,
                "  {}: {:?}, normals {}, colours {}{}, {} bytes, {} triangles, {:.2} bytes/triangle",
                o.name,
                h.kind,
                h.normals,
                h.colors,
                if h.alpha { " with alpha" } else { "" },
                raw.bytes.len(),
                o.triangles.len(),
                raw.bytes.len() as f64 / o.triangles.len().max(1) as f64
            );
        }
        return Ok(out);
    }
    let mut reader = HoloFlickReader::open(input)?;
    let info = reader.info().clone();
    let (n, d) = info.frames_per_second;
    let frames = reader.frame_count();
    let _ = writeln!(
        out,
        "{}: HoloFlick {}.{}, {frames} frames at {}, geometry {}.{}.{}, {bytes} bytes",
        input.display(),
        info.version.0,
        info.version.1,
        crate::report::frame_rate_text(n.into(), d.into()),
        info.geometry_version[0],
        info.geometry_version[1],
        info.geometry_version[2]
    );
    for (k, v) in &info.text {
        let _ = writeln!(out, "  {k}: {v}");
    }
    let (mut all_triangles, mut all_stream) = (0usize, 0usize);
    for f in 0..frames {
        let stored = reader.read_stored_frame(f)?;
        let resolved = reader.read_frame(f)?;
        let mut triangles = 0;
        let mut stream = 0;
        for (record, o) in stored.objects.iter().zip(&resolved.objects) {
            let (mesh, _) = decode_object(&format!("id {}", o.id), &o.block, &o.world_from_object, o.radiance_scale)
                .map_err(|e| named(input, e))?;
            triangles += mesh.triangles.len();
            if matches!(record, ObjectRecord::Stored(_)) {
                stream += o.block.stream().len();
            }
        }
        let references = stored.objects.iter().filter(|o| matches!(o, ObjectRecord::Reference(_))).count();
        all_triangles += triangles;
        all_stream += stream;
        let c = stored.couch;
        let _ = writeln!(
            out,
            "  frame {f}{}: {} objects ({references} from key frames), {triangles} triangles, {stream} stream bytes, {} lights, {} materials, couch [{:.3}, {:.3}, {:.3}]..[{:.3}, {:.3}, {:.3}] m",
            if stored.key_frame { " (key)" } else { "" },
            stored.objects.len(),
            stored.lights.len(),
            stored.materials.len(),
            c.min_m[0],
            c.min_m[1],
            c.min_m[2],
            c.max_m[0],
            c.max_m[1],
            c.max_m[2]
        );
    }
    let _ = writeln!(
        out,
        "  total: {all_triangles} triangles shown, {all_stream} stream bytes stored ({:.2} bytes/triangle shown)",
        all_stream as f64 / all_triangles.max(1) as f64
    );
    Ok(out)
}
