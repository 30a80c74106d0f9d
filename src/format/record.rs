//! The conversion record as the file holds it (spec §4.4): the
//! `holo.convert.*` attributes, raw, with the typed, checked ways to write
//! and read them. What each attribute means belongs to its converter: each
//! converter's options write and read their own part of the record beside
//! the options (the provenance module ties the converters together), so the
//! format knows the record's names and types, and no converter.

use std::ops::Range;
use std::path::Path;

use exr::meta::attribute::AttributeValue;
use serde::ser::{SerializeMap, Serializer};

use super::attributes::{self, name::convert as n, Attributes};
use super::digest::{is_well_formed, DIGEST_PREFIX};
use crate::error::Result;

/// The `holo.convert.*` attributes of a conversion (spec §4.4), as written
/// or as read, sorted by name when read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ConversionRecord(pub(crate) Vec<(String, AttributeValue)>);

/// A record's look-ups fail with one sentence naming the attribute.
pub type Checked<T> = std::result::Result<T, String>;

/// Who made a file, from what: the head of every record.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordHead {
    /// The converter's name (`holo.convert.kind`).
    pub kind: String,
    /// The input as the converter was given it, without the folders above
    /// it: a scene or HoloFlick file, a rig file, a capture's folder.
    pub input: String,
    /// `sha256:` and the 64 lower-case hex digits of the SHA-256 of the
    /// input's bytes, when the input is a file: that file only, not the
    /// files it names (a glTF's buffers, an OBJ's materials, a rig's
    /// pictures).
    pub input_sha256: Option<String>,
}

impl RecordHead {
    /// The head for `input` read by converter `kind`: its name, and its
    /// SHA-256 when it is a file (read once more; cheap beside any
    /// conversion).
    pub fn of_input(kind: &str, input: &Path) -> Result<RecordHead> {
        let name = input.file_name().map_or_else(|| input.display().to_string(), |n| n.to_string_lossy().into_owned());
        let input_sha256 =
            if input.is_file() { Some(format!("{DIGEST_PREFIX}{}", crate::output::file_sha256(input)?)) } else { None };
        Ok(RecordHead { kind: kind.to_string(), input: name, input_sha256 })
    }
}

impl ConversionRecord {
    /// The record's attributes, for typed look-ups.
    fn attributes(&self) -> Attributes<'_> {
        Attributes::from_pairs(&self.0)
    }

    /// The record's head; `None` when it holds no attribute at all.
    pub fn head(&self) -> Checked<Option<RecordHead>> {
        if self.0.is_empty() {
            return Ok(None);
        }
        let a = self.attributes();
        let input_sha256 = a.optional(n::INPUT_SHA256, Attributes::string)?;
        if let Some(digest) = &input_sha256 {
            if !is_well_formed(digest) {
                return Err(format!(
                    "attribute {} is {digest:?}; it must be `sha256:` and 64 hex digits",
                    n::INPUT_SHA256
                ));
            }
        }
        Ok(Some(RecordHead { kind: a.string(n::KIND)?, input: a.string(n::INPUT)?, input_sha256 }))
    }

    /// Typed, checked look-ups of the record's values.
    pub fn reader(&self) -> RecordReader<'_> {
        RecordReader(self.attributes())
    }

    /// The `holo.convert.*` attributes among a header's.
    pub(crate) fn from_attributes(attrs: &Attributes) -> Option<ConversionRecord> {
        let names: Vec<&str> = attrs.holo_names().into_iter().filter(|k| k.starts_with(n::PREFIX)).collect();
        if names.is_empty() {
            return None;
        }
        Some(ConversionRecord(
            names.into_iter().filter_map(|k| Some((k.to_string(), attrs.value(k)?.clone()))).collect(),
        ))
    }
}

/// A record as it is made, in the order made (the writer sorts the
/// attributes by name).
#[derive(Default)]
pub struct RecordWriter(Vec<(String, AttributeValue)>);

impl RecordWriter {
    /// A record that begins with `head`.
    pub fn new(head: &RecordHead) -> RecordWriter {
        let mut r = RecordWriter::default();
        r.text(n::KIND, &head.kind);
        r.text(n::INPUT, &head.input);
        if let Some(digest) = &head.input_sha256 {
            r.text(n::INPUT_SHA256, digest);
        }
        r
    }
    /// The record made.
    pub fn finish(self) -> ConversionRecord {
        ConversionRecord(self.0)
    }

    fn put(&mut self, k: &str, v: AttributeValue) {
        self.0.push((k.to_string(), v));
    }
    /// A `string`.
    pub fn text(&mut self, k: &str, v: &str) {
        self.put(k, attributes::text(v));
    }
    /// A `double`.
    pub fn double(&mut self, k: &str, v: f64) {
        self.put(k, AttributeValue::F64(v));
    }
    /// A `double`, when there is one.
    pub fn optional_double(&mut self, k: &str, v: Option<f64>) {
        if let Some(v) = v {
            self.double(k, v);
        }
    }
    /// A count or an index, as `int`.
    pub fn int(&mut self, k: &str, v: usize) {
        self.put(k, AttributeValue::I32(saturating_i32(v)));
    }
    /// A yes or no, as the `int` 0 or 1.
    pub fn flag(&mut self, k: &str, v: bool) {
        self.put(k, AttributeValue::I32(i32::from(v)));
    }
    /// Three `int`s (`v3i`).
    pub fn ints3(&mut self, k: &str, [a, b, c]: [usize; 3]) {
        self.put(k, AttributeValue::IntVec3((saturating_i32(a), saturating_i32(b), saturating_i32(c))));
    }
    /// A `v3d`.
    pub fn v3d(&mut self, k: &str, v: [f64; 3]) {
        self.put(k, attributes::v3d_attribute(v));
    }
    /// A `v3f`.
    pub fn v3f(&mut self, k: &str, [a, b, c]: [f32; 3]) {
        self.put(k, AttributeValue::FloatVec3((a, b, c)));
    }
    /// A placement matrix (`m44d`, stored as spec §4.3 says).
    pub fn matrix(&mut self, k: &str, m: &[[f64; 4]; 4]) {
        self.put(k, attributes::matrix_attribute(m));
    }
    /// `holo.convert.frames`, when a range was asked.
    pub fn frames(&mut self, frames: &Option<Range<usize>>) {
        if let Some(f) = frames {
            self.put(
                n::FRAMES,
                AttributeValue::IntVec2(exr::math::Vec2(saturating_i32(f.start), saturating_i32(f.end))),
            );
        }
    }
}

/// Counts and indices as `int`: a value past `i32::MAX` cannot have been
/// converted (the format's limits are far below it), so saturating loses
/// nothing a file could hold.
fn saturating_i32(x: usize) -> i32 {
    i32::try_from(x).unwrap_or(i32::MAX)
}

/// Typed look-ups of a record, each value checked against a rule; each
/// failure one sentence naming the attribute.
pub struct RecordReader<'a>(Attributes<'a>);

impl RecordReader<'_> {
    /// The look-ups of any attribute (`string`, `v3d`, `optional`, …).
    pub fn attributes(&self) -> &Attributes<'_> {
        &self.0
    }

    /// An `int` that is 0 or 1.
    pub fn flag(&self, k: &str) -> Checked<bool> {
        match self.0.int(k)? {
            0 => Ok(false),
            1 => Ok(true),
            other => Err(format!("attribute {k} is {other}; it must be 0 or 1")),
        }
    }

    /// An `int` in `lo..=hi`.
    pub fn whole(&self, k: &str, lo: usize, hi: usize) -> Checked<usize> {
        let v = self.0.int(k)?;
        usize::try_from(v)
            .ok()
            .filter(|v| (lo..=hi).contains(v))
            .ok_or_else(|| format!("attribute {k} is {v}; it must be from {lo} to {hi}"))
    }

    /// Three `int`s (`v3i`), each in `lo..=hi`.
    pub fn wholes3(&self, k: &str, lo: usize, hi: usize) -> Checked<[usize; 3]> {
        let v = self.0.v3i(k)?;
        let each = v.map(|x| usize::try_from(x).ok().filter(|x| (lo..=hi).contains(x)));
        match each {
            [Some(a), Some(b), Some(c)] => Ok([a, b, c]),
            _ => Err(format!("attribute {k} is ({} {} {}); each must be from {lo} to {hi}", v[0], v[1], v[2])),
        }
    }

    /// A `double` that passes `ok` (a rule such as `finite and positive`).
    pub fn double(&self, k: &str, ok: fn(f64) -> bool, rule: &str) -> Checked<f64> {
        let v = self.0.double(k)?;
        if ok(v) {
            Ok(v)
        } else {
            Err(format!("attribute {k} is {v}; it must be {rule}"))
        }
    }

    /// [`RecordReader::double`], when recorded.
    pub fn optional_double(&self, k: &str, ok: fn(f64) -> bool, rule: &str) -> Checked<Option<f64>> {
        self.0.optional(k, |_, k| self.double(k, ok, rule))
    }

    /// A finite, positive `double`.
    pub fn positive(&self, k: &str) -> Checked<f64> {
        self.double(k, |x| x.is_finite() && x > 0.0, "finite and positive")
    }

    /// A finite, positive `double`, when recorded.
    pub fn optional_positive(&self, k: &str) -> Checked<Option<f64>> {
        self.optional_double(k, |x| x.is_finite() && x > 0.0, "finite and positive")
    }

    /// A `string` that is the name of one of `all`.
    pub fn choice<T: Copy>(&self, k: &str, all: &[T], name: fn(T) -> &'static str) -> Checked<T> {
        let v = self.0.string(k)?;
        all.iter().copied().find(|c| name(*c) == v).ok_or_else(|| {
            let names: Vec<String> = all.iter().map(|c| format!("{:?}", name(*c))).collect();
            format!("attribute {k} is {v:?}; it must be one of {}", names.join(", "))
        })
    }

    /// `holo.convert.matrix`, when recorded.
    pub fn matrix(&self) -> Checked<Option<crate::math::Mat4>> {
        Ok(self.0.optional(n::MATRIX, Attributes::m44d)?.map(|m| attributes::matrix_from_m44d(&m)))
    }

    /// `holo.convert.frames`, when recorded.
    pub fn frames(&self) -> Checked<Option<Range<usize>>> {
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
}

/// The record in JSON (`holo info --json`): each attribute by name, its
/// value as a number, a string or a list (a matrix as rows, points as
/// columns, as `placement` is given).
pub(crate) fn serialize<S: Serializer>(
    record: &Option<ConversionRecord>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde_json::{json, Value};
    let Some(record) = record else {
        return s.serialize_none();
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
