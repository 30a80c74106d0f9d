//! The `holo.*` header attributes of spec §4: their names, EXR types, and the
//! translation between them and [`Geometry`]. Reading reports the attribute
//! and the type it should have had.

use std::collections::HashMap;

use exr::math::Vec2;
use exr::meta::attribute::{AttributeValue, Text};

use crate::geometry::{ColourChannel, Geometry, Parallax, ViewSpacing, Views};

/// The newest format version this library reads and writes (full
/// parallax, spec §8; horizontal parallax is written as 1.2, which 1.3 did
/// not change).
pub const VERSION: (i32, i32) = (1, 3);

/// Attribute names (spec §4, table 1).
pub mod name {
    #![allow(missing_docs)]
    pub const VERSION: &str = "holo.version";
    pub const PARALLAX: &str = "holo.parallax";
    pub const HOLOLINES: &str = "holo.hololines";
    pub const EMITTERS: &str = "holo.emitters";
    pub const VIEWS: &str = "holo.views";
    pub const HOLOLINE_PITCH: &str = "holo.hololinePitch";
    pub const HOLOLINE_TOP_Y: &str = "holo.hololineTopY";
    pub const EMITTER_PITCH: &str = "holo.emitterPitch";
    pub const EMITTER_LEFT_X: &str = "holo.emitterLeftX";
    pub const EMITTER_Z: &str = "holo.emitterZ";
    pub const VIEWER_DISTANCE: &str = "holo.viewerDistance";
    pub const VIEWER_HEIGHT: &str = "holo.viewerHeight";
    pub const VIEW_SPACING: &str = "holo.viewSpacing";
    pub const VIEW_FIRST: &str = "holo.viewFirst";
    pub const VIEW_LAST: &str = "holo.viewLast";
    pub const VIEW_ANGLES: &str = "holo.viewAngles";
    pub const VIEWS_VERTICAL: &str = "holo.viewsVertical";
    pub const VIEW_SPACING_VERTICAL: &str = "holo.viewSpacingVertical";
    pub const VIEW_FIRST_VERTICAL: &str = "holo.viewFirstVertical";
    pub const VIEW_LAST_VERTICAL: &str = "holo.viewLastVertical";
    pub const VIEW_ANGLES_VERTICAL: &str = "holo.viewAnglesVertical";
    /// The vertical views' attributes (spec §8), which only full parallax has.
    pub const VERTICAL: [&str; 5] =
        [VIEWS_VERTICAL, VIEW_SPACING_VERTICAL, VIEW_FIRST_VERTICAL, VIEW_LAST_VERTICAL, VIEW_ANGLES_VERTICAL];
    /// Per part, full parallax: the view `(h, k)` the part holds.
    pub const VIEW: &str = "holo.view";
    pub const WAVELENGTH_PREFIX: &str = "holo.wavelength.";
    pub const RADIOMETRY: &str = "holo.radiometry";
    pub const SCALE: &str = "holo.scale";
    pub const UNIT: &str = "holo.unit";
    pub const FRAME: &str = "holo.frame";
    pub const FRAME_COUNT: &str = "holo.frameCount";
    pub const DIGEST: &str = "holo.digest";
    pub const HEADER_DIGEST: &str = "holo.headerDigest";
    pub const SOURCE: &str = "holo.source";
    pub const PLACEMENT: &str = "holo.placement";

    /// The conversion record (spec §4.4, version 1.1): which converter made
    /// the file, from which input, with every option it was given.
    pub mod convert {
        pub const PREFIX: &str = "holo.convert.";
        pub const KIND: &str = "holo.convert.kind";
        pub const INPUT: &str = "holo.convert.input";
        pub const INPUT_SHA256: &str = "holo.convert.inputSha256";
        pub const FRAMES: &str = "holo.convert.frames";
        pub const FRAMES_PER_SECOND: &str = "holo.convert.framesPerSecond";
        pub const SMOOTH_NORMALS_DEG: &str = "holo.convert.smoothNormalsDeg";
        pub const ROTATE_DEG: &str = "holo.convert.rotateDeg";
        pub const SCALE: &str = "holo.convert.scale";
        pub const TRANSLATE: &str = "holo.convert.translate";
        pub const MATRIX: &str = "holo.convert.matrix";
        pub const SUPERSAMPLE: &str = "holo.convert.supersample";
        pub const ENGINE: &str = "holo.convert.engine";
        pub const SPECULAR: &str = "holo.convert.specular";
        pub const SCENE_LIGHTS: &str = "holo.convert.sceneLights";
        pub const DEFAULT_LIGHTS: &str = "holo.convert.defaultLights";
        pub const LIGHT_COUNT: &str = "holo.convert.lightCount";
        /// Light `i`'s properties are `holo.convert.light<i>.<property>` ([`light`]).
        pub const LIGHT_PREFIX: &str = "holo.convert.light";
        pub const LIGHT_PROPERTIES: [&str; 7] =
            ["kind", "direction", "irradiance", "position", "intensity", "radiance", "name"];
        pub const BLEND: &str = "holo.convert.blend";
        pub const FOCUS: &str = "holo.convert.focus";
        pub const CENTRE: &str = "holo.convert.centre";
        pub const FRAMING: &str = "holo.convert.framing";
        pub const PARALLAX: &str = "holo.convert.parallax";
        pub const DEPTH_MAPS: &str = "holo.convert.depthMaps";
        pub const EMITTER_TAPS: &str = "holo.convert.emitterTaps";
        pub const FOLDER_BASELINE: &str = "holo.convert.folder.baseline";
        pub const FOLDER_FOCAL_PX: &str = "holo.convert.folder.focalPx";
        pub const FOLDER_H_FOV_DEG: &str = "holo.convert.folder.hFovDeg";
        pub const FOLDER_FOCUS: &str = "holo.convert.folder.focus";
        pub const FOLDER_M_PER_UNIT: &str = "holo.convert.folder.mPerUnit";
        pub const STANFORD_FOCAL_PX: &str = "holo.convert.stanford.focalPx";
        pub const STANFORD_H_FOV_DEG: &str = "holo.convert.stanford.hFovDeg";
        pub const STANFORD_FOCUS: &str = "holo.convert.stanford.focus";
        pub const STANFORD_M_PER_UNIT: &str = "holo.convert.stanford.mPerUnit";
        pub const QUILT_VIEW_CONE_DEG: &str = "holo.convert.quilt.viewConeDeg";
        pub const QUILT_V_FOV_DEG: &str = "holo.convert.quilt.vFovDeg";
        pub const FIT: &str = "holo.convert.fit";

        /// Every fixed name (the lights' are [`light`]'s).
        pub const ALL: [&str; 35] = [
            KIND,
            INPUT,
            INPUT_SHA256,
            FRAMES,
            FRAMES_PER_SECOND,
            SMOOTH_NORMALS_DEG,
            ROTATE_DEG,
            SCALE,
            TRANSLATE,
            MATRIX,
            SUPERSAMPLE,
            ENGINE,
            SPECULAR,
            SCENE_LIGHTS,
            DEFAULT_LIGHTS,
            LIGHT_COUNT,
            BLEND,
            FOCUS,
            CENTRE,
            FRAMING,
            PARALLAX,
            DEPTH_MAPS,
            EMITTER_TAPS,
            FOLDER_BASELINE,
            FOLDER_FOCAL_PX,
            FOLDER_H_FOV_DEG,
            FOLDER_FOCUS,
            FOLDER_M_PER_UNIT,
            STANFORD_FOCAL_PX,
            STANFORD_H_FOV_DEG,
            STANFORD_FOCUS,
            STANFORD_M_PER_UNIT,
            QUILT_VIEW_CONE_DEG,
            QUILT_V_FOV_DEG,
            FIT,
        ];

        /// `holo.convert.light<i>.<property>`.
        pub fn light(i: usize, property: &str) -> String {
            format!("{LIGHT_PREFIX}{i}.{property}")
        }

        /// Whether `attribute` names a light's property: `light`, a decimal
        /// index without leading zeros, `.`, one of [`LIGHT_PROPERTIES`].
        pub fn is_light(attribute: &str) -> bool {
            let Some((index, property)) = attribute.strip_prefix(LIGHT_PREFIX).and_then(|r| r.split_once('.')) else {
                return false;
            };
            let digits = !index.is_empty() && index.bytes().all(|b| b.is_ascii_digit());
            digits && (index == "0" || !index.starts_with('0')) && LIGHT_PROPERTIES.contains(&property)
        }
    }
}

/// Every attribute name this version defines (wavelengths by prefix).
pub fn is_known(attribute: &str) -> bool {
    use name::*;
    [
        VERSION,
        PARALLAX,
        HOLOLINES,
        EMITTERS,
        VIEWS,
        HOLOLINE_PITCH,
        HOLOLINE_TOP_Y,
        EMITTER_PITCH,
        EMITTER_LEFT_X,
        EMITTER_Z,
        VIEWER_DISTANCE,
        VIEWER_HEIGHT,
        VIEW_SPACING,
        VIEW_FIRST,
        VIEW_LAST,
        VIEW_ANGLES,
        VIEWS_VERTICAL,
        VIEW_SPACING_VERTICAL,
        VIEW_FIRST_VERTICAL,
        VIEW_LAST_VERTICAL,
        VIEW_ANGLES_VERTICAL,
        VIEW,
        RADIOMETRY,
        SCALE,
        UNIT,
        FRAME,
        FRAME_COUNT,
        DIGEST,
        HEADER_DIGEST,
        SOURCE,
        PLACEMENT,
    ]
    .contains(&attribute)
        || attribute.strip_prefix(WAVELENGTH_PREFIX).is_some_and(|c| crate::geometry::CHANNEL_NAMES.contains(&c))
        || convert::ALL.contains(&attribute)
        || convert::is_light(attribute)
}

/// How to turn stored values into radiance (spec §5).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Radiometry {
    /// Always `linear` in version 1.
    pub encoding: String,
    /// Radiance = sample × scale.
    pub scale: f64,
    /// Unit of `sample × scale`: `relative`, or `W/(sr m^2)`.
    pub unit: String,
}

impl Default for Radiometry {
    fn default() -> Self {
        Radiometry { encoding: "linear".into(), scale: 1.0, unit: "relative".into() }
    }
}

pub(crate) fn text(s: &str) -> AttributeValue {
    AttributeValue::Text(Text::new_or_panic(ascii_only(s)))
}

/// Attribute text must be ASCII (spec §4): the typography holo's own
/// sentences use (`×`, `°`, `−`, `…`, dashes, `µ`, typographic quotes) is
/// spelled in ASCII, so provenance stays readable; anything else becomes `?`.
pub fn ascii_only(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '\0' => out.push('?'),
            c if c.is_ascii() => out.push(c),
            '×' => out.push('x'),
            '°' => out.push_str(" deg"),
            '−' | '–' | '—' => out.push('-'),
            '…' => out.push_str("..."),
            'µ' | 'μ' => out.push('u'),
            '‘' | '’' => out.push('\''),
            '“' | '”' => out.push('"'),
            _ => out.push('?'),
        }
    }
    out
}

/// A transform such as `holo.placement` (spec §4.4): `display_from_input`
/// (row-major, points as columns: translation in the last column) as
/// OpenEXR's `m44d`, whose layout follows Imath's row-vector convention
/// (translation in the last row): the transpose, 16 little-endian doubles.
pub fn matrix_attribute(display_from_input: &[[f64; 4]; 4]) -> AttributeValue {
    let bytes = crate::math::transpose(display_from_input).iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    AttributeValue::Custom { kind: Text::new_or_panic("m44d"), bytes }
}

/// The matrix [`matrix_attribute`] stores, back in the crate's convention
/// (points as columns).
pub fn matrix_from_m44d(stored: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    crate::math::transpose(stored)
}

/// OpenEXR's `v3d` (three little-endian doubles), which the `exr` crate
/// knows only as a custom type.
pub fn v3d_attribute(v: [f64; 3]) -> AttributeValue {
    AttributeValue::Custom { kind: Text::new_or_panic("v3d"), bytes: v.iter().flat_map(|x| x.to_le_bytes()).collect() }
}

/// The geometry and radiometry attributes shared by every part of a file.
pub fn geometry_attributes(
    g: &Geometry,
    radiometry: &Radiometry,
    version: (i32, i32),
) -> HashMap<Text, AttributeValue> {
    use name::*;
    let mut a = HashMap::new();
    let mut put = |k: &str, v: AttributeValue| {
        a.insert(Text::new_or_panic(k), v);
    };
    put(VERSION, AttributeValue::IntVec2(Vec2(version.0, version.1)));
    put(
        PARALLAX,
        text(match g.parallax {
            Parallax::Horizontal => "horizontal",
            Parallax::Full => "full",
        }),
    );
    put(HOLOLINES, AttributeValue::I32(g.hololines as i32));
    put(EMITTERS, AttributeValue::I32(g.emitters as i32));
    put(VIEWS, AttributeValue::I32(g.views.count as i32));
    put(HOLOLINE_PITCH, AttributeValue::F64(g.hololine_pitch_m));
    put(HOLOLINE_TOP_Y, AttributeValue::F64(g.hololine_top_y_m));
    put(EMITTER_PITCH, AttributeValue::F64(g.emitter_pitch_m));
    put(EMITTER_LEFT_X, AttributeValue::F64(g.emitter_left_x_m));
    put(EMITTER_Z, AttributeValue::F64(g.emitter_z_m));
    put(VIEWER_DISTANCE, AttributeValue::F64(g.viewer_distance_m));
    put(VIEWER_HEIGHT, AttributeValue::F64(g.viewer_height_m));
    let mut axis = |views: &Views, [spacing, first, last, angles]: [&str; 4]| {
        put(spacing, text(views.spacing.name()));
        put(first, AttributeValue::F64(views.first_theta_rad));
        put(last, AttributeValue::F64(views.last_theta_rad));
        if let ViewSpacing::Explicit(list) = &views.spacing {
            let joined: Vec<String> = list.iter().map(|t| format!("{t:e}")).collect();
            put(angles, text(&joined.join(" ")));
        }
    };
    axis(&g.views, [VIEW_SPACING, VIEW_FIRST, VIEW_LAST, VIEW_ANGLES]);
    if let Some(vertical) = &g.vertical_views {
        axis(vertical, [VIEW_SPACING_VERTICAL, VIEW_FIRST_VERTICAL, VIEW_LAST_VERTICAL, VIEW_ANGLES_VERTICAL]);
        put(VIEWS_VERTICAL, AttributeValue::I32(vertical.count as i32));
    }
    for c in &g.channels {
        put(&format!("{WAVELENGTH_PREFIX}{}", c.name), AttributeValue::F64(c.wavelength_m));
    }
    put(RADIOMETRY, text(&radiometry.encoding));
    put(SCALE, AttributeValue::F64(radiometry.scale));
    put(UNIT, text(&radiometry.unit));
    a
}

/// Typed look-ups into a header's attributes; each failure is one sentence.
pub struct Attributes<'a> {
    map: HashMap<&'a str, &'a AttributeValue>,
}

fn type_name(v: &AttributeValue) -> String {
    String::from_utf8_lossy(v.kind_name()).into_owned()
}

impl<'a> Attributes<'a> {
    /// Merge several attribute maps (later ones win).
    pub fn new(maps: &[&'a HashMap<Text, AttributeValue>]) -> Self {
        let mut map = HashMap::new();
        for m in maps {
            for (k, v) in m.iter() {
                if let Ok(k) = std::str::from_utf8(k.as_slice()) {
                    map.insert(k, v);
                }
            }
        }
        Attributes { map }
    }
    /// Look-ups into a list of named values (a conversion record).
    pub(crate) fn from_pairs(pairs: &'a [(String, AttributeValue)]) -> Self {
        Attributes { map: pairs.iter().map(|(k, v)| (k.as_str(), v)).collect() }
    }
    /// An attribute's value as stored, when present.
    pub(crate) fn value(&self, k: &str) -> Option<&'a AttributeValue> {
        self.map.get(k).copied()
    }
    /// All attribute names starting with `holo.`.
    pub fn holo_names(&self) -> Vec<&'a str> {
        let mut v: Vec<&str> = self.map.keys().copied().filter(|k| k.starts_with("holo.")).collect();
        v.sort();
        v
    }
    /// Whether the attribute is present.
    pub fn has(&self, k: &str) -> bool {
        self.map.contains_key(k)
    }
    fn get(&self, k: &str) -> Result<&'a AttributeValue, String> {
        self.map.get(k).copied().ok_or_else(|| format!("required attribute {k} is missing"))
    }
    fn wrong(k: &str, want: &str, got: &AttributeValue) -> String {
        format!("attribute {k} has type {}; the spec requires {want}", type_name(got))
    }
    /// An `int` attribute.
    pub fn int(&self, k: &str) -> Result<i32, String> {
        match self.get(k)? {
            AttributeValue::I32(x) => Ok(*x),
            other => Err(Self::wrong(k, "int", other)),
        }
    }
    /// A `double` attribute. A `float` is refused: positions and wavelengths
    /// need double precision, and widening would hide the loss.
    pub fn double(&self, k: &str) -> Result<f64, String> {
        match self.get(k)? {
            AttributeValue::F64(x) => Ok(*x),
            other => Err(Self::wrong(k, "double", other)),
        }
    }
    /// A `string` attribute.
    pub fn string(&self, k: &str) -> Result<String, String> {
        match self.get(k)? {
            AttributeValue::Text(t) => Ok(String::from_utf8_lossy(t.as_slice()).into_owned()),
            other => Err(Self::wrong(k, "string", other)),
        }
    }
    /// A `v2i` attribute.
    pub fn v2i(&self, k: &str) -> Result<(i32, i32), String> {
        match self.get(k)? {
            AttributeValue::IntVec2(v) => Ok((v.0, v.1)),
            other => Err(Self::wrong(k, "v2i", other)),
        }
    }
    /// A `v3i` attribute.
    pub fn v3i(&self, k: &str) -> Result<[i32; 3], String> {
        match self.get(k)? {
            AttributeValue::IntVec3((a, b, c)) => Ok([*a, *b, *c]),
            other => Err(Self::wrong(k, "v3i", other)),
        }
    }
    /// A `v3f` attribute, every value finite.
    pub fn v3f(&self, k: &str) -> Result<[f32; 3], String> {
        match self.get(k)? {
            AttributeValue::FloatVec3((a, b, c)) if [a, b, c].iter().all(|x| x.is_finite()) => Ok([*a, *b, *c]),
            AttributeValue::FloatVec3(_) => Err(Self::not_finite(k)),
            other => Err(Self::wrong(k, "v3f", other)),
        }
    }
    /// A `v3d` attribute (which the `exr` crate reads as a custom type),
    /// every value finite.
    pub fn v3d(&self, k: &str) -> Result<[f64; 3], String> {
        let [v] = self.doubles::<3, 1>(k, "v3d")?;
        Ok(v)
    }
    /// An `m44d` attribute (OpenEXR's 4×4 double matrix, which the `exr`
    /// crate reads as a custom type): the 16 doubles as stored, row by row,
    /// every value finite.
    pub fn m44d(&self, k: &str) -> Result<[[f64; 4]; 4], String> {
        self.doubles::<4, 4>(k, "m44d")
    }
    /// A custom attribute of type `kind` holding `R × C` little-endian
    /// doubles, row by row, every one finite.
    fn doubles<const C: usize, const R: usize>(&self, k: &str, kind: &str) -> Result<[[f64; C]; R], String> {
        match self.get(k)? {
            AttributeValue::Custom { kind: found, bytes } if found.as_slice() == kind.as_bytes() => {
                if bytes.len() != 8 * R * C {
                    return Err(format!("attribute {k} holds {} bytes; a {kind} holds {}", bytes.len(), 8 * R * C));
                }
                let mut m = [[0.0; C]; R];
                for (i, chunk) in bytes.chunks_exact(8).enumerate() {
                    m[i / C][i % C] = f64::from_le_bytes(chunk.try_into().unwrap_or([0; 8]));
                }
                if m.iter().flatten().all(|x| x.is_finite()) {
                    Ok(m)
                } else {
                    Err(Self::not_finite(k))
                }
            }
            other => Err(Self::wrong(k, kind, other)),
        }
    }
    fn not_finite(k: &str) -> String {
        format!("attribute {k} holds a value that is not finite")
    }

    /// An optional attribute: `Ok(None)` when absent.
    pub fn optional<T>(&self, k: &str, f: impl Fn(&Self, &str) -> Result<T, String>) -> Result<Option<T>, String> {
        if self.has(k) {
            f(self, k).map(Some)
        } else {
            Ok(None)
        }
    }

    /// The geometry, given the colour suffixes found in the channel list
    /// (already in R, G, B, Y order).
    pub fn geometry(&self, colours: &[String]) -> Result<Geometry, String> {
        use name::*;
        let count = |k: &str| -> Result<usize, String> {
            let n = self.int(k)?;
            usize::try_from(n).map_err(|_| format!("attribute {k} is {n}; it must not be negative"))
        };
        let parallax = match self.string(PARALLAX)?.as_str() {
            "horizontal" => Parallax::Horizontal,
            "full" => Parallax::Full,
            other => return Err(format!("attribute {PARALLAX} is {other:?}; it must be \"horizontal\" or \"full\"")),
        };
        let axis = |[views, spacing, first, last, angles]: [&str; 5]| -> Result<Views, String> {
            let spacing = match self.string(spacing)?.as_str() {
                "tan" => ViewSpacing::Tan,
                "sin" => ViewSpacing::Sin,
                "angle" => ViewSpacing::Angle,
                "explicit" => {
                    let list = self.string(angles)?;
                    let parsed: Result<Vec<f64>, _> = list.split_ascii_whitespace().map(str::parse::<f64>).collect();
                    ViewSpacing::Explicit(
                        parsed.map_err(|_| format!("attribute {angles} is not a list of decimal numbers"))?,
                    )
                }
                other => {
                    return Err(format!(
                        "attribute {spacing} is {other:?}; it must be \"tan\", \"sin\", \"angle\" or \"explicit\""
                    ))
                }
            };
            Ok(Views {
                count: count(views)?,
                first_theta_rad: self.double(first)?,
                last_theta_rad: self.double(last)?,
                spacing,
            })
        };
        let views = axis([VIEWS, VIEW_SPACING, VIEW_FIRST, VIEW_LAST, VIEW_ANGLES])?;
        let vertical_views = match parallax {
            Parallax::Full => Some(axis([
                VIEWS_VERTICAL,
                VIEW_SPACING_VERTICAL,
                VIEW_FIRST_VERTICAL,
                VIEW_LAST_VERTICAL,
                VIEW_ANGLES_VERTICAL,
            ])?),
            Parallax::Horizontal => {
                if let Some(k) = VERTICAL.iter().find(|k| self.has(k)) {
                    return Err(format!(
                        "attribute {k} is for full parallax; this file's {PARALLAX} is \"horizontal\""
                    ));
                }
                None
            }
        };
        let mut channels = Vec::new();
        for c in colours {
            channels.push(ColourChannel {
                name: c.clone(),
                wavelength_m: self.double(&format!("{WAVELENGTH_PREFIX}{c}"))?,
            });
        }
        Ok(Geometry {
            parallax,
            hololines: count(HOLOLINES)?,
            emitters: count(EMITTERS)?,
            views,
            vertical_views,
            hololine_pitch_m: self.double(HOLOLINE_PITCH)?,
            hololine_top_y_m: self.double(HOLOLINE_TOP_Y)?,
            emitter_pitch_m: self.double(EMITTER_PITCH)?,
            emitter_left_x_m: self.double(EMITTER_LEFT_X)?,
            emitter_z_m: self.double(EMITTER_Z)?,
            viewer_distance_m: self.double(VIEWER_DISTANCE)?,
            viewer_height_m: self.double(VIEWER_HEIGHT)?,
            channels,
        })
    }

    /// The radiometry (spec §5); absent attributes take their defaults.
    pub fn radiometry(&self) -> Result<Radiometry, String> {
        use name::*;
        let d = Radiometry::default();
        let r = Radiometry {
            encoding: self.optional(RADIOMETRY, Self::string)?.unwrap_or(d.encoding),
            scale: self.optional(SCALE, Self::double)?.unwrap_or(d.scale),
            unit: self.optional(UNIT, Self::string)?.unwrap_or(d.unit),
        };
        if r.encoding != "linear" {
            return Err(format!("attribute {RADIOMETRY} is {:?}; version 1 defines only \"linear\"", r.encoding));
        }
        if !(r.scale.is_finite() && r.scale > 0.0) {
            return Err(format!("attribute {SCALE} is {}; it must be finite and positive", r.scale));
        }
        Ok(r)
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn attribute_text_spells_holos_typography_in_ascii() {
        assert_eq!(
            super::ascii_only("0.24 × 0.18 units, span 329°, x −76 … +76 mm – 5 µm “a” é\0"),
            "0.24 x 0.18 units, span 329 deg, x -76 ... +76 mm - 5 um \"a\" ??"
        );
    }
}
