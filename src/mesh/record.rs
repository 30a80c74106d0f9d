//! The options of `convert mesh` as a file records them (spec §4.4): each
//! written beside what it means, and read back checked against what the
//! converter accepts. The HoloFlick converter records its supersampling and
//! engine the same way ([`RenderOptions::write_supersample_and_engine`]).

use crate::format::attribute::convert as n;
use crate::format::{Checked, ConversionRecord, RecordHead, RecordReader, RecordWriter, WriteOptions};

use super::convert::{ConvertOptions, SceneFramesOptions};
use super::place::Placement;
use super::render::{Engine, RenderOptions, Supersample};
use super::shade::{Lighting, SpecularModel};
use super::Light;

/// Most supersampling along each axis a record may hold.
const MAX_SUPERSAMPLE: usize = 64;

impl ConvertOptions {
    /// `holo.convert.kind` of a scene's conversion.
    pub const KIND: &'static str = "mesh";

    /// The record of this conversion of the input `head` names.
    pub fn record(&self, head: &RecordHead) -> ConversionRecord {
        let mut r = RecordWriter::new(head);
        self.scene.write_record(&mut r);
        self.render.write_record(&mut r);
        r.finish()
    }

    /// The options a record holds, with `write` as their write part.
    pub fn from_record(r: &RecordReader, write: WriteOptions) -> Checked<ConvertOptions> {
        Ok(ConvertOptions { scene: SceneFramesOptions::read_record(r)?, render: RenderOptions::read_record(r)?, write })
    }
}

impl SceneFramesOptions {
    fn write_record(&self, r: &mut RecordWriter) {
        r.frames(&self.frames);
        r.double(n::FRAMES_PER_SECOND, self.frames_per_second);
        r.optional_double(n::SMOOTH_NORMALS_DEG, self.smooth_normals_deg);
        let p = &self.placement;
        r.v3d(n::ROTATE_DEG, p.rotate_deg);
        r.optional_double(n::SCALE, p.scale);
        r.v3d(n::TRANSLATE, p.translate_m);
        if let Some(m) = &p.matrix {
            r.matrix(n::MATRIX, m);
        }
    }

    fn read_record(r: &RecordReader) -> Checked<SceneFramesOptions> {
        let degrees = |x: f64| (0.0..=180.0).contains(&x);
        let a = r.attributes();
        Ok(SceneFramesOptions {
            placement: Placement {
                rotate_deg: a.v3d(n::ROTATE_DEG)?,
                scale: r.optional_positive(n::SCALE)?,
                translate_m: a.v3d(n::TRANSLATE)?,
                matrix: r.matrix()?,
            },
            frames: r.frames()?,
            frames_per_second: r.positive(n::FRAMES_PER_SECOND)?,
            smooth_normals_deg: r.optional_double(n::SMOOTH_NORMALS_DEG, degrees, "from 0 to 180 (degrees)")?,
        })
    }
}

impl RenderOptions {
    /// The supersampling and the engine: all of the render options that a
    /// converter whose lights come from its input records.
    pub(crate) fn write_supersample_and_engine(&self, r: &mut RecordWriter) {
        let s = self.supersample;
        r.ints3(n::SUPERSAMPLE, [s.emitter, s.view, s.hololine]);
        r.text(n::ENGINE, self.engine.name());
    }

    /// The render options of a converter whose lights come from its input:
    /// the supersampling and engine recorded, the rest the defaults.
    pub(crate) fn read_supersample_and_engine(r: &RecordReader) -> Checked<RenderOptions> {
        let [emitter, view, hololine] = r.wholes3(n::SUPERSAMPLE, 1, MAX_SUPERSAMPLE)?;
        Ok(RenderOptions {
            supersample: Supersample { emitter, view, hololine },
            engine: r.choice(n::ENGINE, &Engine::ALL, Engine::name)?,
            ..RenderOptions::default()
        })
    }

    fn write_record(&self, r: &mut RecordWriter) {
        self.write_supersample_and_engine(r);
        r.text(n::SPECULAR, self.lighting.model.name());
        r.flag(n::SCENE_LIGHTS, self.scene_lights);
        r.flag(n::DEFAULT_LIGHTS, self.default_lights);
        r.int(n::LIGHT_COUNT, self.lighting.lights.len());
        for (i, light) in self.lighting.lights.iter().enumerate() {
            light.write_record(i, r);
        }
    }

    fn read_record(r: &RecordReader) -> Checked<RenderOptions> {
        let RenderOptions { supersample, engine, .. } = RenderOptions::read_supersample_and_engine(r)?;
        let count = r.whole(n::LIGHT_COUNT, 0, i32::MAX as usize)?;
        // Not allocated from the count: a hostile count fails at the first
        // light that is not there.
        let mut lights = Vec::new();
        for i in 0..count {
            lights.push(Light::read_record(i, r)?);
        }
        Ok(RenderOptions {
            supersample,
            lighting: Lighting { lights, model: r.choice(n::SPECULAR, &SpecularModel::ALL, SpecularModel::name)? },
            scene_lights: r.flag(n::SCENE_LIGHTS)?,
            default_lights: r.flag(n::DEFAULT_LIGHTS)?,
            engine,
        })
    }
}

impl Light {
    /// Light `i` of the record.
    fn write_record(&self, i: usize, r: &mut RecordWriter) {
        let k = |property: &str| n::light(i, property);
        r.text(&k("kind"), self.kind());
        match self {
            Light::Directional { direction, irradiance, name } => {
                r.v3d(&k("direction"), *direction);
                r.v3f(&k("irradiance"), *irradiance);
                r.text(&k("name"), name);
            }
            Light::Point { position, intensity, name } => {
                r.v3d(&k("position"), *position);
                r.v3f(&k("intensity"), *intensity);
                r.text(&k("name"), name);
            }
            Light::Ambient { radiance } => r.v3f(&k("radiance"), *radiance),
        }
    }

    fn read_record(i: usize, r: &RecordReader) -> Checked<Light> {
        let k = |property: &str| n::light(i, property);
        let a = r.attributes();
        // Brightness as the renderer takes it: finite (the `v3f` look-up)
        // and not negative.
        let brightness = |property: &str| -> Checked<[f32; 3]> {
            let v = a.v3f(&k(property))?;
            if v.iter().all(|x| *x >= 0.0) {
                Ok(v)
            } else {
                Err(format!("attribute {} is {v:?}; no component may be negative", k(property)))
            }
        };
        match a.string(&k("kind"))?.as_str() {
            "directional" => {
                let direction = a.v3d(&k("direction"))?;
                if direction == [0.0; 3] {
                    return Err(format!("attribute {} is (0 0 0); a direction must not be zero", k("direction")));
                }
                Ok(Light::Directional { direction, irradiance: brightness("irradiance")?, name: a.string(&k("name"))? })
            }
            "point" => Ok(Light::Point {
                position: a.v3d(&k("position"))?,
                intensity: brightness("intensity")?,
                name: a.string(&k("name"))?,
            }),
            "ambient" => Ok(Light::Ambient { radiance: brightness("radiance")? }),
            other => Err(format!(
                "attribute {} is {other:?}; it must be \"directional\", \"point\" or \"ambient\"",
                k("kind")
            )),
        }
    }
}
