//! `holo convert holoflick`: a HoloFlick's frames to `.holo` frames (Deering, *HoloFlicks*
//! §7: lit micropolygons drawn from every view, specular added per view).
//!
//! Per frame: each object's geometry is decoded (objects kept in key frames
//! are decoded once and reused while their key frame is current), placed
//! in display metres, and given its binding as bound (spec/holoflick.md
//! §6.5): the material's `k_s`, exponent and lobe, and only the lights the
//! binding lists; objects no ray of the display meets are not decoded at
//! all, triangles facing away from every allowed viewpoint are dropped,
//! and objects without a specular material do no specular work. The mesh
//! renderer then draws the pre-lit micropolygons under the frame's specular
//! lights, each object with its own lobe and lights
//! ([`crate::mesh::Material::specular_model`],
//! [`crate::mesh::Material::lights`]). Frames are made one at a time as the
//! writer asks for them: memory is one frame and the cache of key-frame
//! objects, whatever the frame count.
//!
//! Placement: a HoloFlick made for the display (`holo holoflick encode`)
//! is in display metres and its couch holds the display's viewing zone;
//! it is drawn as it is. Any other is fitted to the display on its first
//! frame converted, like `holo convert mesh`, and that placement kept.

use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use super::container::{HoloFlickReader, ResolvedFrame, SpecularModel, ViewerCouch};
use super::objects::{decode_block_into, mesh_light, to_world_into};
use super::shader::cull::{cull_back_faces, display_sees_box};
use crate::error::{Error, Result};
use crate::format::{
    attribute, Checked, ConversionRecord, RecordHead, RecordReader, RecordWriter, WriteOptions, WriteReport,
};
use crate::geometry::Geometry;
use crate::mesh::place::{apply, place, Placed, Placement};
use crate::mesh::render::{render_into, RenderOptions, RenderStats};
use crate::mesh::shade::{Lighting, SpecularModel as Lobe};
use crate::mesh::{Object, Scene};
use crate::modulation::Band;
use crate::pipeline::{self, Source, Warnings};
use crate::progress::Progress;

/// Everything `convert holoflick` takes besides input, geometry and output.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HoloFlickConvertOptions {
    /// Frames to convert (default all): split a movie across machines.
    pub frames: Option<Range<usize>>,
    /// Supersampling and engine (the lights come from the file).
    pub render: RenderOptions,
    /// How to write.
    pub write: WriteOptions,
    /// Fit the content to the display even when it was made for it.
    pub fit: bool,
    /// A placement given (world to display metres, row-major, points as
    /// columns) instead of one decided on the first frame converted: what a
    /// farm hands every chunk of a movie so each is placed as the whole
    /// movie was. The content is then drawn through it, as fitted content is.
    pub matrix: Option<crate::math::Mat4>,
}

impl HoloFlickConvertOptions {
    /// `holo.convert.kind` of a HoloFlick's conversion.
    pub const KIND: &'static str = "holoflick";

    /// The record of this conversion of the HoloFlick `head` names (spec
    /// §4.4): of the render options only the supersampling and the engine,
    /// the only ones this converter uses (the lights come from the file).
    pub fn record(&self, head: &RecordHead) -> ConversionRecord {
        let mut r = RecordWriter::new(head);
        r.frames(&self.frames);
        self.render.write_supersample_and_engine(&mut r);
        r.flag(attribute::convert::FIT, self.fit);
        if let Some(m) = &self.matrix {
            r.matrix(attribute::convert::MATRIX, m);
        }
        r.finish()
    }

    /// The options a record holds, with `write` as their write part.
    pub fn from_record(r: &RecordReader, write: WriteOptions) -> Checked<HoloFlickConvertOptions> {
        Ok(HoloFlickConvertOptions {
            frames: r.frames()?,
            render: RenderOptions::read_supersample_and_engine(r)?,
            write,
            fit: r.flag(attribute::convert::FIT)?,
            matrix: r.matrix()?,
        })
    }
}

/// Work done and skipped, over all frames converted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HoloFlickWork {
    /// Objects decoded.
    pub decoded: u64,
    /// Objects taken from the key-frame cache instead of decoded.
    pub reused: u64,
    /// Objects skipped without decoding: no display ray meets them.
    pub unseen_objects: u64,
    /// Triangles dropped: they face away from every allowed viewpoint.
    pub back_faces: u64,
    /// Objects drawn without specular work (no material bound, or `k_s` 0).
    pub without_specular: u64,
    /// The renderer's counters.
    pub render: RenderStats,
}

/// What a conversion did.
#[derive(Clone, Debug)]
pub struct HoloFlickConvertReport {
    /// The output.
    pub path: PathBuf,
    /// Frames converted (file frame numbers).
    pub frames: Range<usize>,
    /// The placement, when the content was fitted; `None`: drawn as stored.
    pub placed: Option<Placed>,
    /// Work done and skipped.
    pub work: HoloFlickWork,
    /// Things the user should know.
    pub warnings: Vec<String>,
    /// The writer's report.
    pub written: WriteReport,
    /// Where the time went (`open`, `place`, `decode`, `render`, `write`).
    pub timings: crate::progress::Timings,
}

/// The box of the display's viewing zone: every point of the viewer line a
/// view reaches (spec/holo-format.md §1), as a flat box; for full parallax
/// the rectangle at the viewer's distance that the views reach.
fn viewing_zone(g: &Geometry) -> ([f64; 3], [f64; 3]) {
    let (lo, hi) = g.viewer_line_reach_m();
    let (y_lo, y_hi) = g.vertical_reach_at_m(g.viewer_distance_m).unwrap_or((g.viewer_height_m, g.viewer_height_m));
    ([lo, y_lo, g.viewer_distance_m], [hi, y_hi, g.viewer_distance_m])
}

fn couch_holds(c: &ViewerCouch, lo: [f64; 3], hi: [f64; 3]) -> bool {
    c.contains(lo) && c.contains(hi)
}

/// Convert `input` for `geometry` into `output`: a [`HoloFlickSource`]
/// through [`crate::pipeline::run`]. `progress` counts the frames of a
/// movie; of a single frame, its hololines.
pub fn convert_holoflick(
    input: &Path,
    geometry: &Geometry,
    output: &Path,
    options: &HoloFlickConvertOptions,
    progress: &dyn Progress,
) -> Result<HoloFlickConvertReport> {
    let open = |input: &Path| HoloFlickSource::open(input, geometry, options);
    let target = (output, geometry, &options.write);
    let (source, mut run) = pipeline::open_and_write(input, open, target, options.frames.clone(), progress)?;
    if !source.outside.is_empty() {
        let list: Vec<String> = source.outside.iter().map(|n| n.to_string()).collect();
        run.warnings.push(format!(
            "{}: frames {}: the viewer's couch does not hold the display's viewing zone; views from outside it may show holes",
            input.display(),
            list.join(", ")
        ));
    }
    Ok(HoloFlickConvertReport {
        path: output.to_path_buf(),
        frames: run.frames,
        placed: source.state.placed,
        work: source.state.work,
        warnings: run.warnings,
        written: run.written,
        timings: run.timings,
    })
}

/// A HoloFlick as a [`Source`] of `.holo` frames: each frame's objects
/// decoded (or taken from the key-frame cache), placed, bound and drawn by
/// the mesh renderer under the frame's own lights.
pub struct HoloFlickSource<'a> {
    input: PathBuf,
    reader: HoloFlickReader,
    geometry: &'a Geometry,
    render: RenderOptions,
    fit: bool,
    /// The placement given, if any.
    matrix: Option<crate::math::Mat4>,
    /// The frames asked for (`None`: all), as the conversion records them.
    frames_asked: Option<Range<usize>>,
    /// Drawn as stored: made for the display (decided on the first frame).
    made_for_display: bool,
    state: State,
    /// The frames to convert.
    frames: Range<usize>,
    /// Frames whose couch does not hold the display's viewing zone.
    outside: Vec<usize>,
    /// Time spent reading frames and decoding their objects.
    decoding: std::time::Duration,
}

impl<'a> HoloFlickSource<'a> {
    /// Open `input` to draw for `geometry` with `options`' render options
    /// and fitting.
    pub fn open(input: &Path, geometry: &'a Geometry, options: &HoloFlickConvertOptions) -> Result<Self> {
        Ok(HoloFlickSource {
            input: input.to_path_buf(),
            reader: HoloFlickReader::open(input)?,
            geometry,
            render: options.render.clone(),
            fit: options.fit,
            matrix: options.matrix,
            frames_asked: options.frames.clone(),
            made_for_display: true,
            state: State { cache: HashMap::new(), work: HoloFlickWork::default(), placed: None, spare: Vec::new() },
            frames: 0..0,
            outside: Vec::new(),
            decoding: std::time::Duration::ZERO,
        })
    }
}

impl Source for HoloFlickSource<'_> {
    type Frame = Band;

    fn inputs(&self) -> Vec<PathBuf> {
        vec![self.input.clone()]
    }

    fn frame_count(&self) -> usize {
        self.reader.frame_count() as usize
    }

    fn frames_per_second(&self) -> Option<(u32, u32)> {
        Some(self.reader.info().frames_per_second)
    }

    fn place(&mut self, frames: &Range<usize>, warnings: &mut Warnings) -> Result<()> {
        self.frames = frames.clone();
        let (zone_lo, zone_hi) = viewing_zone(self.geometry);
        let frame = self.reader.read_frame(frames.start as u32)?;
        self.made_for_display = couch_holds(&frame.frame.couch, zone_lo, zone_hi) && !self.fit && self.matrix.is_none();
        if !self.made_for_display {
            let (mut scene, _) = self.state.scene(&frame, None, self.geometry, false)?;
            let placement = Placement { matrix: self.matrix, ..Placement::default() };
            let placed = place(&mut scene, self.geometry, &placement)?;
            if self.matrix.is_none() {
                warnings.add(format!(
                    "{}: the viewer's couch does not hold this display's viewing zone: the content is fitted to the display ({placed})",
                    self.input.display(),
                ));
            }
            self.state.placed = Some(placed);
            self.state.work = HoloFlickWork::default();
            self.state.cache.clear();
        }
        Ok(())
    }

    fn provenance(&self) -> String {
        format!("holo convert holoflick {} (frames {}..{})", self.input.display(), self.frames.start, self.frames.end)
    }

    fn conversion(&self) -> Result<Option<ConversionRecord>> {
        let options = HoloFlickConvertOptions {
            frames: self.frames_asked.clone(),
            render: self.render.clone(),
            write: WriteOptions::default(),
            fit: self.fit,
            matrix: self.matrix,
        };
        Ok(Some(options.record(&RecordHead::of_input(HoloFlickConvertOptions::KIND, &self.input)?)))
    }

    /// World metres to display metres: the fit when the file was fitted,
    /// else the identity (a HoloFlick made for the display is in its frame).
    fn placement(&self) -> Option<crate::math::Mat4> {
        Some(self.state.placed.as_ref().map_or(crate::math::IDENTITY4, |p| p.matrix))
    }

    fn stage_times(&self) -> crate::progress::Timings {
        let mut t = crate::progress::Timings::default();
        t.add("decode", self.decoding);
        t
    }

    fn render(&mut self, number: usize, band: &mut Band, progress: &dyn Progress, _: &mut Warnings) -> Result<()> {
        let decoding = std::time::Instant::now();
        let frame = self.reader.read_frame(number as u32)?;
        let (zone_lo, zone_hi) = viewing_zone(self.geometry);
        let holds = couch_holds(&frame.frame.couch, zone_lo, zone_hi);
        if self.made_for_display && !holds {
            self.outside.push(number);
        }
        let (scene, lighting) =
            self.state.frame_scene(&frame, self.geometry, self.made_for_display && holds).map_err(|e| match e {
                Error::Argument { what, problem } => {
                    Error::Argument { what, problem: format!("{}: frame {number}: {problem}", self.input.display()) }
                }
                other => other,
            })?;
        self.decoding += decoding.elapsed();
        // The frame's own lights, exactly: its colours are pre-lit, so a
        // frame without lights shows them as they are.
        let options = RenderOptions {
            supersample: self.render.supersample,
            engine: self.render.engine,
            ..RenderOptions::lit_exactly(lighting)
        };
        self.state.work.render += band.as_frame(|m| render_into(&scene, &options, progress, m))??;
        self.state.spare.extend(scene.objects);
        Ok(())
    }
}

struct State {
    /// Decoded blocks of key frames: (frame stored in, object id) → object in
    /// its normalised frame.
    cache: HashMap<(u32, u32), Object>,
    work: HoloFlickWork,
    placed: Option<Placed>,
    /// The last frame's objects, drawn and done with: the next frame decodes
    /// into their lists ([`decode_block_into`]).
    spare: Vec<Object>,
}

impl State {
    /// The frame's objects in display metres (placed), culled, and their ids; `couch`
    /// viewpoints for back faces when given.
    fn scene(
        &mut self,
        frame: &ResolvedFrame,
        couch: Option<&[[f64; 3]]>,
        g: &Geometry,
        cull_unseen: bool,
    ) -> Result<(Scene, Vec<u32>)> {
        // Keep only the current key frames' objects in the cache; the rest
        // are spare lists for this frame's objects.
        let current: std::collections::HashSet<u32> = frame.objects.iter().map(|o| o.stored_in_frame).collect();
        let leaving: Vec<(u32, u32)> =
            self.cache.keys().filter(|k| !(current.contains(&k.0) && k.0 != frame.number)).copied().collect();
        for key in leaving {
            self.spare.extend(self.cache.remove(&key));
        }
        let mut scene = Scene { source: format!("frame {}", frame.number), ..Scene::default() };
        // The id of each object kept, in order.
        let mut ids = Vec::new();
        let placement = self.placed.as_ref().map(|p| p.matrix);
        for o in &frame.objects {
            // Skip what no ray meets, before decoding: the stream's frame is
            // [−1, 1]³, its corners placed bound the object.
            if cull_unseen {
                let mut corners = Vec::with_capacity(8);
                for k in 0..8 {
                    let p = [k & 1, k >> 1 & 1, k >> 2 & 1].map(|b| if b == 1 { 1.0 } else { -1.0 });
                    let m = o.world_from_object;
                    let mut w: [f64; 3] =
                        std::array::from_fn(|r| m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3]);
                    if let Some(t) = placement {
                        w = std::array::from_fn(|r| t[r][0] * w[0] + t[r][1] * w[1] + t[r][2] * w[2] + t[r][3]);
                    }
                    corners.push(w);
                }
                let lo = std::array::from_fn(|k| corners.iter().map(|c| c[k]).fold(f64::INFINITY, f64::min));
                let hi = std::array::from_fn(|k| corners.iter().map(|c| c[k]).fold(f64::NEG_INFINITY, f64::max));
                if !display_sees_box(g, lo, hi) {
                    self.work.unseen_objects += 1;
                    continue;
                }
            }
            let key = (o.stored_in_frame, o.id);
            let reusable = o.stored_in_frame != frame.number;
            let mut world = self.spare.pop().unwrap_or_default();
            match self.cache.get(&key) {
                Some(local) => {
                    self.work.reused += 1;
                    to_world_into(local, &o.world_from_object, o.radiance_scale, &mut world)?;
                }
                None => {
                    let mut local = self.spare.pop().unwrap_or_default();
                    decode_block_into(&format!("id {}", o.id), &o.block, &mut local)?;
                    self.work.decoded += 1;
                    to_world_into(&local, &o.world_from_object, o.radiance_scale, &mut world)?;
                    if reusable || frame.frame.key_frame {
                        self.cache.insert(key, local);
                    } else {
                        self.spare.push(local);
                    }
                }
            }
            if let Some(t) = placement {
                let mut one = Scene { objects: vec![world], ..Scene::default() };
                apply(&mut one, &t);
                world = one.objects.pop().unwrap_or_default();
            }
            scene.objects.push(world);
            ids.push(o.id);
        }
        if let Some(viewpoints) = couch {
            self.work.back_faces += cull_back_faces(&mut scene.objects, viewpoints);
        }
        Ok((scene, ids))
    }

    /// The frame ready to render: objects with their bound materials (each
    /// with its lobe and the lights it is bound to), and the lights.
    fn frame_scene(&mut self, frame: &ResolvedFrame, g: &Geometry, cull_with_couch: bool) -> Result<(Scene, Lighting)> {
        // Back faces against the couch only when it holds the display's
        // viewpoints, in display metres (otherwise the display may see what
        // the couch cannot).
        let couch = cull_with_couch.then(|| frame.frame.couch.corners().to_vec());
        let (mut scene, ids) = self.scene(frame, couch.as_deref(), g, true)?;
        // Materials by binding; objects were pushed in frame order, minus the culled.
        let bindings: HashMap<u32, &super::container::Binding> =
            frame.frame.bindings.iter().map(|b| (b.object_id, b)).collect();
        let lobe = |m: SpecularModel| match m {
            SpecularModel::Phong => Lobe::Phong,
            SpecularModel::Blinn => Lobe::Blinn,
        };
        // The render's own lobe: any would do, as every bound material
        // names its own; the first's keeps a frame of one lobe, bound to
        // every light, in the renderer's one light group.
        let mut model = None;
        for (o, id) in scene.objects.iter_mut().zip(ids) {
            let bound = bindings.get(&id).and_then(|b| Some((b, frame.frame.materials.get(b.material as usize)?)));
            match bound {
                Some((b, m)) if m.specular.iter().any(|&k| k > 0.0) => {
                    o.material.specular = m.specular.map(|k| k as f32);
                    o.material.shininess = m.exponent as f32;
                    o.material.specular_model = Some(lobe(m.model));
                    o.material.lights = Some(b.lights.clone());
                    model.get_or_insert(lobe(m.model));
                }
                _ => {
                    o.material.specular = [0.0; 3];
                    self.work.without_specular += 1;
                }
            }
        }
        let model = model.unwrap_or(Lobe::Blinn);
        let placement = self.placed.as_ref().map(|p| p.matrix);
        let lights = frame
            .frame
            .lights
            .iter()
            .map(|l| {
                let mut light = mesh_light(l);
                if let Some(t) = placement {
                    let mut one = Scene { lights: vec![light.clone()], ..Scene::default() };
                    apply(&mut one, &t);
                    light = one.lights.pop().unwrap_or(light);
                }
                light
            })
            .collect();
        Ok((scene, Lighting { lights, model }))
    }
}
