//! Exact provenance: which converter made a `.holo` file, from which input,
//! with every option it was given, recorded as the typed `holo.convert.*`
//! attributes (spec/holo-format.md §4.4) so that the same conversion can be
//! made again from the file alone.
//!
//! `holo.source` says the same for people, its numbers rounded; the record
//! is exact (every `f64` a `double`, every choice its command-line name).
//! A converter makes a [`Conversion`] after placing its input
//! ([`crate::pipeline::Source::conversion`]) and the writer stores its
//! [`Conversion::record`]; [`FileInfo::conversion`] reads it back, the
//! options complete with the file's own sample type, compression, version
//! and radiometry, ready to hand to the converter with the file's geometry
//! (and, for a scene, `holo.placement` as its matrix if wanted).

use std::ops::Range;
use std::path::Path;

use exr::meta::attribute::AttributeValue;
use serde::ser::{SerializeMap, Serializer};

use crate::cameras::convert::CameraConvertOptions;
use crate::cameras::read::{CameraHints, OpenOptions};
use crate::cameras::resample::{Blend, CameraOptions, Framing, Parallax, PlacementRequest, MAX_EMITTER_TAPS};
use crate::format::attributes::{self, name::convert as n, Attributes, ConversionRecord};
use crate::format::{FileInfo, WriteOptions};
use crate::holoflick::convert::HoloFlickConvertOptions;
use crate::mesh::convert::{ConvertOptions, SceneFramesOptions};
use crate::mesh::place::Placement;
use crate::mesh::render::{Engine, RenderOptions, Supersample};
use crate::mesh::shade::{Lighting, SpecularModel};
use crate::mesh::Light;
use crate::Result;

/// A conversion as a file records it.
#[derive(Clone, Debug, PartialEq)]
pub struct Conversion {
    /// The input as the converter was given it, without the folders above
    /// it: a scene or HoloFlick file, a rig file, a capture's folder.
    pub input: String,
    /// `sha256:` and the 64 lower-case hex digits of the SHA-256 of the
    /// input's bytes, when the input is a file: that file only, not the
    /// files it names (a glTF's buffers, an OBJ's materials, a rig's
    /// pictures).
    pub input_sha256: Option<String>,
    /// The converter, with every option it was given.
    pub options: ConverterOptions,
}

/// Which converter, with its options.
#[derive(Clone, Debug, PartialEq)]
pub enum ConverterOptions {
    /// A scene ([`crate::mesh::convert::convert_mesh`]).
    Mesh(ConvertOptions),
    /// A camera capture ([`crate::cameras::convert::convert_camera_files`]);
    /// what is recorded are the options that make the samples: not the
    /// unseen-ray picture or mask asked for beside them.
    Cameras(CameraConvertOptions),
    /// A HoloFlick ([`crate::holoflick::convert::convert_holoflick`]); of
    /// its render options only the supersampling and the engine, the only
    /// ones that converter uses (the lights come from the HoloFlick).
    HoloFlick(HoloFlickConvertOptions),
}

impl ConverterOptions {
    /// The converter's name, as `holo.convert.kind` stores it.
    pub fn kind(&self) -> &'static str {
        match self {
            ConverterOptions::Mesh(_) => "mesh",
            ConverterOptions::Cameras(_) => "cameras",
            ConverterOptions::HoloFlick(_) => "holoflick",
        }
    }
}

impl Conversion {
    /// The conversion of `input` with `options`: its name, and its SHA-256
    /// when it is a file (read once more; cheap beside any conversion).
    pub fn of_input(input: &Path, options: ConverterOptions) -> Result<Conversion> {
        let name = input.file_name().map_or_else(|| input.display().to_string(), |n| n.to_string_lossy().into_owned());
        let input_sha256 = if input.is_file() {
            Some(format!("{}{}", crate::format::digest::DIGEST_PREFIX, crate::output::file_sha256(input)?))
        } else {
            None
        };
        Ok(Conversion { input: name, input_sha256, options })
    }

    /// The same conversion of other frames (`None`: all): what a part of a
    /// movie made alone records, and what joining the parts records.
    pub fn with_frames(&self, frames: Option<Range<usize>>) -> Conversion {
        let mut c = self.clone();
        match &mut c.options {
            ConverterOptions::Mesh(o) => o.scene.frames = frames,
            ConverterOptions::HoloFlick(o) => o.frames = frames,
            ConverterOptions::Cameras(_) => {}
        }
        c
    }

    /// The `holo.convert.*` attributes that record it, for
    /// [`WriteOptions::conversion`].
    pub fn record(&self) -> ConversionRecord {
        let mut r = Record::default();
        r.text(n::KIND, self.options.kind());
        r.text(n::INPUT, &self.input);
        if let Some(digest) = &self.input_sha256 {
            r.text(n::INPUT_SHA256, digest);
        }
        match &self.options {
            ConverterOptions::Mesh(o) => {
                r.scene(&o.scene);
                r.render(&o.render);
            }
            ConverterOptions::Cameras(o) => r.cameras(o),
            ConverterOptions::HoloFlick(o) => {
                r.frames(&o.frames);
                r.supersample_and_engine(&o.render);
                r.flag(n::FIT, o.fit);
                if let Some(m) = &o.matrix {
                    r.put(n::MATRIX, attributes::matrix_attribute(m));
                }
            }
        }
        ConversionRecord(r.0)
    }

    /// The conversion `attrs` record; `None` when they hold no
    /// `holo.convert.*` attribute. The options' write part is `write` (what
    /// the file says of itself). An attribute of the wrong type or with a
    /// value its converter would refuse is a sentence naming it.
    pub(crate) fn from_attributes(
        attrs: &Attributes,
        write: WriteOptions,
    ) -> std::result::Result<Option<Conversion>, String> {
        if !attrs.holo_names().iter().any(|k| k.starts_with(n::PREFIX)) {
            return Ok(None);
        }
        let r = Reader(attrs);
        let input = attrs.string(n::INPUT)?;
        let input_sha256 = attrs.optional(n::INPUT_SHA256, Attributes::string)?;
        if let Some(digest) = &input_sha256 {
            if !crate::format::digest::is_well_formed(digest) {
                return Err(format!(
                    "attribute {} is {digest:?}; it must be `sha256:` and 64 hex digits",
                    n::INPUT_SHA256
                ));
            }
        }
        let options = match attrs.string(n::KIND)?.as_str() {
            "mesh" => ConverterOptions::Mesh(ConvertOptions { scene: r.scene()?, render: r.render()?, write }),
            "cameras" => ConverterOptions::Cameras(r.cameras(write)?),
            "holoflick" => {
                let (supersample, engine) = r.supersample_and_engine()?;
                ConverterOptions::HoloFlick(HoloFlickConvertOptions {
                    frames: r.frames()?,
                    render: RenderOptions { supersample, engine, ..RenderOptions::default() },
                    write,
                    fit: r.flag(n::FIT)?,
                    matrix: r.matrix()?,
                })
            }
            other => {
                return Err(format!(
                    "attribute {} is {other:?}; it must be \"mesh\", \"cameras\" or \"holoflick\"",
                    n::KIND
                ))
            }
        };
        Ok(Some(Conversion { input, input_sha256, options }))
    }
}

impl FileInfo {
    /// The conversion that made the file (`holo.convert.*`, spec §4.4),
    /// its options completed with the file's sample type, compression,
    /// version and radiometry: the same conversion is the same converter,
    /// on the same input, with these options and the file's geometry.
    /// `None` when the file records none; an error naming the attribute
    /// when the record cannot be read (the file's samples are still good).
    pub fn conversion(&self) -> Result<Option<&Conversion>> {
        match &self.conversion {
            None => Ok(None),
            Some(Ok(c)) => Ok(Some(c)),
            Some(Err(problem)) => Err(crate::Error::invalid(&self.path, problem.clone())),
        }
    }
}

/// Attributes as they are recorded, in the order made (the writer sorts
/// them by name).
#[derive(Default)]
struct Record(Vec<(String, AttributeValue)>);

impl Record {
    fn put(&mut self, k: &str, v: AttributeValue) {
        self.0.push((k.to_string(), v));
    }
    fn text(&mut self, k: &str, v: &str) {
        self.put(k, attributes::text(v));
    }
    fn double(&mut self, k: &str, v: f64) {
        self.put(k, AttributeValue::F64(v));
    }
    fn optional_double(&mut self, k: &str, v: Option<f64>) {
        if let Some(v) = v {
            self.double(k, v);
        }
    }
    fn int(&mut self, k: &str, v: usize) {
        self.put(k, AttributeValue::I32(saturating_i32(v)));
    }
    fn flag(&mut self, k: &str, v: bool) {
        self.put(k, AttributeValue::I32(i32::from(v)));
    }
    fn v3d(&mut self, k: &str, v: [f64; 3]) {
        self.put(k, attributes::v3d_attribute(v));
    }
    fn v3f(&mut self, k: &str, [a, b, c]: [f32; 3]) {
        self.put(k, AttributeValue::FloatVec3((a, b, c)));
    }

    fn frames(&mut self, frames: &Option<Range<usize>>) {
        if let Some(f) = frames {
            self.put(
                n::FRAMES,
                AttributeValue::IntVec2(exr::math::Vec2(saturating_i32(f.start), saturating_i32(f.end))),
            );
        }
    }

    fn scene(&mut self, s: &SceneFramesOptions) {
        self.frames(&s.frames);
        self.double(n::FRAMES_PER_SECOND, s.frames_per_second);
        self.optional_double(n::SMOOTH_NORMALS_DEG, s.smooth_normals_deg);
        let p = &s.placement;
        self.v3d(n::ROTATE_DEG, p.rotate_deg);
        self.optional_double(n::SCALE, p.scale);
        self.v3d(n::TRANSLATE, p.translate_m);
        if let Some(m) = &p.matrix {
            self.put(n::MATRIX, attributes::matrix_attribute(m));
        }
    }

    fn supersample_and_engine(&mut self, render: &RenderOptions) {
        let s = render.supersample;
        let factors = (saturating_i32(s.emitter), saturating_i32(s.view), saturating_i32(s.hololine));
        self.put(n::SUPERSAMPLE, AttributeValue::IntVec3(factors));
        self.text(n::ENGINE, render.engine.name());
    }

    fn render(&mut self, render: &RenderOptions) {
        self.supersample_and_engine(render);
        self.text(n::SPECULAR, render.lighting.model.name());
        self.flag(n::SCENE_LIGHTS, render.scene_lights);
        self.flag(n::DEFAULT_LIGHTS, render.default_lights);
        self.int(n::LIGHT_COUNT, render.lighting.lights.len());
        for (i, light) in render.lighting.lights.iter().enumerate() {
            let k = |property: &str| n::light(i, property);
            self.text(&k("kind"), light.kind());
            match light {
                Light::Directional { direction, irradiance, name } => {
                    self.v3d(&k("direction"), *direction);
                    self.v3f(&k("irradiance"), *irradiance);
                    self.text(&k("name"), name);
                }
                Light::Point { position, intensity, name } => {
                    self.v3d(&k("position"), *position);
                    self.v3f(&k("intensity"), *intensity);
                    self.text(&k("name"), name);
                }
                Light::Ambient { radiance } => self.v3f(&k("radiance"), *radiance),
            }
        }
    }

    fn cameras(&mut self, o: &CameraConvertOptions) {
        let r = &o.resample;
        let p = &r.placement;
        self.text(n::BLEND, r.blend.name());
        self.text(n::ENGINE, if r.reference { Engine::Reference } else { Engine::Fast }.name());
        self.flag(n::DEPTH_MAPS, r.use_depth);
        self.optional_double(n::FOCUS, p.focus);
        self.optional_double(n::SCALE, p.scale);
        if let Some(c) = p.centre {
            self.v3d(n::CENTRE, c);
        }
        self.text(n::FRAMING, p.framing.name());
        self.text(n::PARALLAX, p.parallax.name());
        if let Some(taps) = r.emitter_taps {
            self.int(n::EMITTER_TAPS, taps);
        }
        let open = &o.open;
        self.optional_double(n::FOLDER_BASELINE, open.folder.baseline);
        self.hints([n::FOLDER_FOCAL_PX, n::FOLDER_H_FOV_DEG, n::FOLDER_FOCUS], &open.folder.camera);
        self.double(n::FOLDER_M_PER_UNIT, open.folder.metres_per_unit);
        self.hints([n::STANFORD_FOCAL_PX, n::STANFORD_H_FOV_DEG, n::STANFORD_FOCUS], &open.stanford.camera);
        self.double(n::STANFORD_M_PER_UNIT, open.stanford.metres_per_unit);
        self.double(n::QUILT_VIEW_CONE_DEG, open.quilt.view_cone_deg);
        self.double(n::QUILT_V_FOV_DEG, open.quilt.vertical_fov_deg);
    }

    /// A capture's camera hints under the names `[focal length, field of
    /// view, focus distance]`.
    fn hints(&mut self, [focal_px, fov_deg, focus]: [&str; 3], h: &CameraHints) {
        self.optional_double(focal_px, h.focal_length_px);
        self.optional_double(fov_deg, h.horizontal_fov_deg);
        self.optional_double(focus, h.focus_distance);
    }
}

/// Counts and indices as `int`: a value past `i32::MAX` cannot have been
/// converted (the format's limits are far below it), so saturating loses
/// nothing a file could hold.
fn saturating_i32(x: usize) -> i32 {
    i32::try_from(x).unwrap_or(i32::MAX)
}

/// Typed look-ups of the record, each value checked against what its
/// converter accepts; each failure one sentence naming the attribute.
struct Reader<'r, 'a>(&'r Attributes<'a>);

type Checked<T> = std::result::Result<T, String>;

impl Reader<'_, '_> {
    /// An `int` that is 0 or 1.
    fn flag(&self, k: &str) -> Checked<bool> {
        match self.0.int(k)? {
            0 => Ok(false),
            1 => Ok(true),
            other => Err(format!("attribute {k} is {other}; it must be 0 or 1")),
        }
    }

    /// An `int` in `lo..=hi`.
    fn whole(&self, k: &str, lo: usize, hi: usize) -> Checked<usize> {
        let v = self.0.int(k)?;
        usize::try_from(v)
            .ok()
            .filter(|v| (lo..=hi).contains(v))
            .ok_or_else(|| format!("attribute {k} is {v}; it must be from {lo} to {hi}"))
    }

    /// A `double` that passes `ok` (a rule such as `finite and positive`).
    fn double(&self, k: &str, ok: fn(f64) -> bool, rule: &str) -> Checked<f64> {
        let v = self.0.double(k)?;
        if ok(v) {
            Ok(v)
        } else {
            Err(format!("attribute {k} is {v}; it must be {rule}"))
        }
    }

    fn optional_double(&self, k: &str, ok: fn(f64) -> bool, rule: &str) -> Checked<Option<f64>> {
        self.0.optional(k, |_, k| self.double(k, ok, rule))
    }

    fn positive(&self, k: &str) -> Checked<f64> {
        self.double(k, |x| x.is_finite() && x > 0.0, "finite and positive")
    }

    fn optional_positive(&self, k: &str) -> Checked<Option<f64>> {
        self.optional_double(k, |x| x.is_finite() && x > 0.0, "finite and positive")
    }

    /// A `string` that is the name of one of `all`.
    fn choice<T: Copy>(&self, k: &str, all: &[T], name: fn(T) -> &'static str) -> Checked<T> {
        let v = self.0.string(k)?;
        all.iter().copied().find(|c| name(*c) == v).ok_or_else(|| {
            let names: Vec<String> = all.iter().map(|c| format!("{:?}", name(*c))).collect();
            format!("attribute {k} is {v:?}; it must be one of {}", names.join(", "))
        })
    }

    /// `holo.convert.matrix`, when recorded.
    fn matrix(&self) -> Checked<Option<crate::math::Mat4>> {
        Ok(self.0.optional(n::MATRIX, Attributes::m44d)?.map(|m| attributes::matrix_from_m44d(&m)))
    }

    fn frames(&self) -> Checked<Option<Range<usize>>> {
        let Some((start, end)) = self.0.optional(n::FRAMES, Attributes::v2i)? else {
            return Ok(None);
        };
        match (usize::try_from(start), usize::try_from(end)) {
            (Ok(s), Ok(e)) if s < e => Ok(Some(s..e)),
            _ => Err(format!(
                "attribute {} is ({start} {end}); it must be the first frame and one past the last, 0 ≤ first < last",
                n::FRAMES
            )),
        }
    }

    fn scene(&self) -> Checked<SceneFramesOptions> {
        let degrees = |x: f64| (0.0..=180.0).contains(&x);
        Ok(SceneFramesOptions {
            placement: Placement {
                rotate_deg: self.0.v3d(n::ROTATE_DEG)?,
                scale: self.optional_positive(n::SCALE)?,
                translate_m: self.0.v3d(n::TRANSLATE)?,
                matrix: self.matrix()?,
            },
            frames: self.frames()?,
            frames_per_second: self.positive(n::FRAMES_PER_SECOND)?,
            smooth_normals_deg: self.optional_double(n::SMOOTH_NORMALS_DEG, degrees, "from 0 to 180 (degrees)")?,
        })
    }

    fn supersample_and_engine(&self) -> Checked<(Supersample, Engine)> {
        let [emitter, view, hololine] = self.0.v3i(n::SUPERSAMPLE)?;
        let factor = |x: i32| usize::try_from(x).ok().filter(|x| (1..=64).contains(x));
        let supersample = match (factor(emitter), factor(view), factor(hololine)) {
            (Some(emitter), Some(view), Some(hololine)) => Supersample { emitter, view, hololine },
            _ => {
                return Err(format!(
                    "attribute {} is ({emitter} {view} {hololine}); each factor must be from 1 to 64",
                    n::SUPERSAMPLE
                ))
            }
        };
        Ok((supersample, self.choice(n::ENGINE, &Engine::ALL, Engine::name)?))
    }

    fn render(&self) -> Checked<RenderOptions> {
        let (supersample, engine) = self.supersample_and_engine()?;
        let count = self.whole(n::LIGHT_COUNT, 0, i32::MAX as usize)?;
        // Not allocated from the count: a hostile count fails at the first
        // light that is not there.
        let mut lights = Vec::new();
        for i in 0..count {
            lights.push(self.light(i)?);
        }
        Ok(RenderOptions {
            supersample,
            lighting: Lighting { lights, model: self.choice(n::SPECULAR, &SpecularModel::ALL, SpecularModel::name)? },
            scene_lights: self.flag(n::SCENE_LIGHTS)?,
            default_lights: self.flag(n::DEFAULT_LIGHTS)?,
            engine,
        })
    }

    fn light(&self, i: usize) -> Checked<Light> {
        let k = |property: &str| n::light(i, property);
        // Brightness as the renderer takes it: finite (the `v3f` look-up)
        // and not negative.
        let brightness = |property: &str| -> Checked<[f32; 3]> {
            let v = self.0.v3f(&k(property))?;
            if v.iter().all(|x| *x >= 0.0) {
                Ok(v)
            } else {
                Err(format!("attribute {} is {v:?}; no component may be negative", k(property)))
            }
        };
        match self.0.string(&k("kind"))?.as_str() {
            "directional" => {
                let direction = self.0.v3d(&k("direction"))?;
                if direction == [0.0; 3] {
                    return Err(format!("attribute {} is (0 0 0); a direction must not be zero", k("direction")));
                }
                Ok(Light::Directional {
                    direction,
                    irradiance: brightness("irradiance")?,
                    name: self.0.string(&k("name"))?,
                })
            }
            "point" => Ok(Light::Point {
                position: self.0.v3d(&k("position"))?,
                intensity: brightness("intensity")?,
                name: self.0.string(&k("name"))?,
            }),
            "ambient" => Ok(Light::Ambient { radiance: brightness("radiance")? }),
            other => Err(format!(
                "attribute {} is {other:?}; it must be \"directional\", \"point\" or \"ambient\"",
                k("kind")
            )),
        }
    }

    fn cameras(&self, write: WriteOptions) -> Checked<CameraConvertOptions> {
        let hints = |[focal_px, fov_deg, focus]: [&str; 3]| -> Checked<CameraHints> {
            Ok(CameraHints {
                focal_length_px: self.optional_positive(focal_px)?,
                horizontal_fov_deg: self.optional_double(fov_deg, below_180_degrees, BELOW_180_DEGREES)?,
                focus_distance: self.optional_positive(focus)?,
            })
        };
        let resample = CameraOptions {
            blend: self.choice(n::BLEND, &Blend::ALL, Blend::name)?,
            placement: PlacementRequest {
                scale: self.optional_positive(n::SCALE)?,
                centre: self.0.optional(n::CENTRE, Attributes::v3d)?,
                focus: self.optional_positive(n::FOCUS)?,
                framing: self.choice(n::FRAMING, &Framing::ALL, Framing::name)?,
                parallax: self.choice(n::PARALLAX, &Parallax::ALL, Parallax::name)?,
            },
            use_depth: self.flag(n::DEPTH_MAPS)?,
            want_mask: false,
            reference: self.choice(n::ENGINE, &Engine::ALL, Engine::name)? == Engine::Reference,
            emitter_taps: self.0.optional(n::EMITTER_TAPS, |_, k| self.whole(k, 1, MAX_EMITTER_TAPS))?,
        };
        let mut open = OpenOptions::default();
        open.folder.baseline = self.optional_positive(n::FOLDER_BASELINE)?;
        open.folder.camera = hints([n::FOLDER_FOCAL_PX, n::FOLDER_H_FOV_DEG, n::FOLDER_FOCUS])?;
        open.folder.metres_per_unit = self.positive(n::FOLDER_M_PER_UNIT)?;
        open.stanford.camera = hints([n::STANFORD_FOCAL_PX, n::STANFORD_H_FOV_DEG, n::STANFORD_FOCUS])?;
        open.stanford.metres_per_unit = self.positive(n::STANFORD_M_PER_UNIT)?;
        open.quilt.view_cone_deg = self.double(n::QUILT_VIEW_CONE_DEG, below_180_degrees, BELOW_180_DEGREES)?;
        open.quilt.vertical_fov_deg = self.double(n::QUILT_V_FOV_DEG, below_180_degrees, BELOW_180_DEGREES)?;
        Ok(CameraConvertOptions { resample, open, unseen_png: None, write })
    }
}

/// Fields of view and view cones: an angle strictly between 0 and 180
/// degrees (what a camera's picture can span).
fn below_180_degrees(x: f64) -> bool {
    x > 0.0 && x < 180.0
}

const BELOW_180_DEGREES: &str = "between 0 and 180 (degrees)";

/// The record in JSON (`holo info --json`): each attribute by name, its
/// value as a number, a string or a list (a matrix as rows, points as
/// columns, as `placement` is given); or, when unreadable, why.
pub(crate) fn serialize<S: Serializer>(
    conversion: &Option<std::result::Result<Conversion, String>>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde_json::{json, Value};
    let record = match conversion {
        None => return s.serialize_none(),
        Some(Err(problem)) => return s.serialize_some(&json!({ "unreadable": problem })),
        Some(Ok(c)) => c.record(),
    };
    let doubles = |bytes: &[u8]| -> Vec<f64> {
        bytes.chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8]))).collect()
    };
    let mut map = s.serialize_map(Some(record.0.len()))?;
    for (k, v) in &record.0 {
        let value = match v {
            AttributeValue::I32(x) => json!(x),
            AttributeValue::F64(x) => json!(x),
            AttributeValue::Text(t) => json!(String::from_utf8_lossy(t.as_slice())),
            AttributeValue::IntVec2(v) => json!([v.0, v.1]),
            AttributeValue::IntVec3((a, b, c)) => json!([a, b, c]),
            AttributeValue::FloatVec3((a, b, c)) => json!([a, b, c]),
            AttributeValue::Custom { kind, bytes } if kind.as_slice() == b"m44d" => {
                let d = doubles(bytes);
                let stored: [[f64; 4]; 4] =
                    std::array::from_fn(|i| std::array::from_fn(|j| d.get(4 * i + j).copied().unwrap_or(0.0)));
                json!(attributes::matrix_from_m44d(&stored))
            }
            AttributeValue::Custom { bytes, .. } => json!(doubles(bytes)),
            _ => Value::Null,
        };
        map.serialize_entry(k, &value)?;
    }
    map.end()
}
