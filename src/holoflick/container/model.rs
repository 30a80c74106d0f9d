//! The data of a HoloFlick: frames of geometry objects, specular lights and
//! materials, their bindings and the viewer's couch (spec/holoflick.md §5–§6).
//! Positions are world metres; transforms are named `world_from_object`.

use std::fmt;
use std::sync::Arc;

use super::{MAX_BLOCK_STREAM_BYTES, TEXT_KEY_MAX};

/// A 4×4 matrix, rows first: `p_world = M · (x, y, z, 1)ᵀ` (the crate's
/// one convention, [`crate::math::Mat4`]).
pub type Matrix4 = crate::math::Mat4;

/// The identity transform.
pub const IDENTITY: Matrix4 = crate::math::IDENTITY4;

/// Kind of primitive a compressed-geometry stream holds (the `.cg` block
/// descriptor's bits 0–1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Primitive {
    /// Points (descriptor type 1).
    Point,
    /// Lines (descriptor type 2).
    Line,
    /// Triangles (descriptor type 3).
    Triangle,
}

/// The 32-bit geometry data descriptor of a `.cg` object record: what the
/// stream holds. Spec §6.4.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Descriptor {
    /// Points, lines or triangles.
    pub primitive: Primitive,
    /// Per-vertex normals present (bit `0x04`).
    pub normals: bool,
    /// Per-vertex colours present (bit `0x08`).
    pub colours: bool,
    /// Colours carry alpha (bit `0x10`).
    pub alpha: bool,
}

impl Descriptor {
    /// Triangles with per-vertex normals and colours: what a geometry shader
    /// emits (Deering, *HoloFlicks* §9).
    pub const LIT_TRIANGLES: Descriptor =
        Descriptor { primitive: Primitive::Triangle, normals: true, colours: true, alpha: false };

    /// The descriptor word as stored.
    pub fn to_bits(self) -> u32 {
        let kind = match self.primitive {
            Primitive::Point => 1,
            Primitive::Line => 2,
            Primitive::Triangle => 3,
        };
        kind | (self.normals as u32) << 2 | (self.colours as u32) << 3 | (self.alpha as u32) << 4
    }

    /// The codec's header for a block of this descriptor (format 1.0.2).
    pub fn cg_header(self) -> crate::holoflick::cg::CgHeader {
        use crate::holoflick::cg::BlockKind;
        let kind = match self.primitive {
            Primitive::Point => BlockKind::Points,
            Primitive::Line => BlockKind::Lines,
            Primitive::Triangle => BlockKind::Triangles,
        };
        crate::holoflick::cg::CgHeader {
            kind,
            normals: self.normals,
            colors: self.colours,
            alpha: self.alpha,
            version: super::GEOMETRY_VERSION,
        }
    }

    /// The descriptor of a block the codec describes by `h`.
    pub fn from_cg_header(h: &crate::holoflick::cg::CgHeader) -> Descriptor {
        use crate::holoflick::cg::BlockKind;
        let primitive = match h.kind {
            BlockKind::Points => Primitive::Point,
            BlockKind::Lines => Primitive::Line,
            BlockKind::Triangles => Primitive::Triangle,
        };
        Descriptor { primitive, normals: h.normals, colours: h.colors, alpha: h.alpha }
    }

    /// Parse a stored descriptor word; `None` for type 0 or bits above 4 set.
    pub fn from_bits(bits: u32) -> Option<Descriptor> {
        if bits & !0x1F != 0 {
            return None;
        }
        let primitive = match bits & 3 {
            1 => Primitive::Point,
            2 => Primitive::Line,
            3 => Primitive::Triangle,
            _ => return None,
        };
        Some(Descriptor { primitive, normals: bits & 0x04 != 0, colours: bits & 0x08 != 0, alpha: bits & 0x10 != 0 })
    }
}

/// One compressed-geometry object, byte for byte the object record of a Java 3D
/// `.cg` file: an 8-byte big-endian header (stream size, descriptor) and the
/// Deering command stream (format 1.0.2). Cheap to clone (shared bytes).
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct GeometryBlock {
    record: Arc<[u8]>,
}

impl GeometryBlock {
    /// A block from a descriptor and a command stream. The stream's length
    /// must be a multiple of 4 (the Java decoder reads 32-bit words) and at
    /// most [`MAX_BLOCK_STREAM_BYTES`].
    pub fn new(descriptor: Descriptor, stream: &[u8]) -> Result<GeometryBlock, BlockError> {
        check_stream_len(stream.len() as u64)?;
        let mut record = Vec::with_capacity(8 + stream.len());
        record.extend_from_slice(&(stream.len() as u32).to_be_bytes());
        record.extend_from_slice(&descriptor.to_bits().to_be_bytes());
        record.extend_from_slice(stream);
        Ok(GeometryBlock { record: record.into() })
    }

    /// A block from a whole `.cg` object record (header and stream), as found
    /// in a Java 3D `.cg` file; checks the header against the length.
    pub fn from_cg_record(record: &[u8]) -> Result<GeometryBlock, BlockError> {
        let (size, bits) = match record {
            [a, b, c, d, e, f, g, h, ..] => {
                (u32::from_be_bytes([*a, *b, *c, *d]), u32::from_be_bytes([*e, *f, *g, *h]))
            }
            _ => return Err(BlockError::NoHeader { bytes: record.len() }),
        };
        if Descriptor::from_bits(bits).is_none() {
            return Err(BlockError::BadDescriptor(bits));
        }
        if size as u64 != record.len() as u64 - 8 {
            return Err(BlockError::SizeDisagrees { header: size, found: record.len() as u64 - 8 });
        }
        check_stream_len(size as u64)?;
        Ok(GeometryBlock { record: record.into() })
    }

    /// What the stream holds.
    pub fn descriptor(&self) -> Descriptor {
        let bits = u32::from_be_bytes([self.record[4], self.record[5], self.record[6], self.record[7]]);
        // Checked on construction.
        Descriptor::from_bits(bits).unwrap_or(Descriptor::LIT_TRIANGLES)
    }

    /// The Deering command stream (what Java 3D's decompressor reads).
    pub fn stream(&self) -> &[u8] {
        &self.record[8..]
    }

    /// The whole `.cg` object record: copy it into a `.cg` file unchanged.
    pub fn cg_record(&self) -> &[u8] {
        &self.record
    }
}

impl fmt::Debug for GeometryBlock {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GeometryBlock")
            .field("descriptor", &self.descriptor())
            .field("stream_bytes", &self.stream().len())
            .finish()
    }
}

fn check_stream_len(len: u64) -> Result<(), BlockError> {
    if len % 4 != 0 {
        return Err(BlockError::NotWholeWords { bytes: len });
    }
    if len > MAX_BLOCK_STREAM_BYTES {
        return Err(BlockError::TooLong { bytes: len, limit: MAX_BLOCK_STREAM_BYTES });
    }
    Ok(())
}

/// Why bytes cannot make a [`GeometryBlock`]: a phrase for the caller to put
/// after the file and object it names.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BlockError {
    /// The stream is not whole 32-bit words.
    #[error("a compressed-geometry stream is whole 32-bit words; {bytes} bytes is not a multiple of 4")]
    NotWholeWords {
        /// The stream's length.
        bytes: u64,
    },
    /// The stream is longer than [`MAX_BLOCK_STREAM_BYTES`].
    #[error("a compressed-geometry stream of {bytes} bytes exceeds the limit of {limit}")]
    TooLong {
        /// The stream's length.
        bytes: u64,
        /// The limit.
        limit: u64,
    },
    /// A record shorter than its 8-byte header.
    #[error("a geometry block needs its 8-byte header; {bytes} bytes given")]
    NoHeader {
        /// The record's length.
        bytes: usize,
    },
    /// The header's descriptor is not one of the defined ones.
    #[error("geometry descriptor {0:#010x} is not valid (type 1–3, bits above 0x10 clear)")]
    BadDescriptor(u32),
    /// The header's stream size disagrees with the bytes that follow it.
    #[error("geometry block header says {header} stream bytes, but {found} follow it")]
    SizeDisagrees {
        /// The size in the header.
        header: u32,
        /// The bytes that follow the header.
        found: u64,
    },
}

/// The viewer's couch (Deering, *HoloFlicks* §12): the box, in world metres, that every
/// playback viewpoint of the frame lies in. Spec §6.1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewerCouch {
    /// Lowest corner, metres.
    pub min_m: [f64; 3],
    /// Highest corner, metres.
    pub max_m: [f64; 3],
}

impl ViewerCouch {
    /// Whether a viewpoint lies in the box (boundary included).
    pub fn contains(&self, point_m: [f64; 3]) -> bool {
        (0..3).all(|k| self.min_m[k] <= point_m[k] && point_m[k] <= self.max_m[k])
    }

    /// The eight corners.
    pub fn corners(&self) -> [[f64; 3]; 8] {
        let (a, b) = (self.min_m, self.max_m);
        std::array::from_fn(|i| {
            [
                if i & 1 == 0 { a[0] } else { b[0] },
                if i & 2 == 0 { a[1] } else { b[1] },
                if i & 4 == 0 { a[2] } else { b[2] },
            ]
        })
    }

    /// Whether the front of a surface through `point_m` with outward normal
    /// `normal` can be seen from some viewpoint in the couch (spec §6.1: a
    /// one-sided surface for which this is false may be culled).
    pub fn sees_front(&self, point_m: [f64; 3], normal: [f64; 3]) -> bool {
        self.corners().iter().any(|c| (0..3).map(|k| (c[k] - point_m[k]) * normal[k]).sum::<f64>() > 0.0)
    }
}

/// A specular light (Deering, *HoloFlicks* §10): it adds highlights at playback, after the
/// diffuse light baked into the vertex colours. Spec §6.2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpecularLight {
    /// Parallel light travelling along `direction`; a surface facing it
    /// receives irradiance `irradiance` (linear RGB).
    Directional {
        /// Direction the light travels in, world frame, unit length.
        direction: [f64; 3],
        /// Irradiance `E` on a surface facing the light, linear RGB.
        irradiance: [f64; 3],
    },
    /// Light from a point: irradiance `intensity / d²` at distance `d` metres.
    Point {
        /// Position, world metres.
        position_m: [f64; 3],
        /// Intensity `I`, linear RGB (irradiance times metres squared).
        intensity: [f64; 3],
    },
}

/// Which specular lobe (the same two as `holo::mesh::shade::SpecularModel`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpecularModel {
    /// `(n + 2)/(2π) · (R·V)^n`.
    Phong,
    /// `(n + 8)/(8π) · (N·H)^n`.
    Blinn,
}

/// A specular material (Deering, *HoloFlicks* §9–§10). Spec §6.3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecularMaterial {
    /// Specular reflectance `k_s`, linear RGB, ≥ 0.
    pub specular: [f64; 3],
    /// Exponent `n` of the lobe, ≥ 0.
    pub exponent: f64,
    /// The lobe.
    pub model: SpecularModel,
}

/// Which material and which lights give an object its highlights. Spec §6.5.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Binding {
    /// The object's id.
    pub object_id: u32,
    /// Index into the frame's material list.
    pub material: u32,
    /// Indices into the frame's light list.
    pub lights: Vec<u32>,
}

/// A geometry object stored in this frame. Spec §6.4.
#[derive(Clone, Debug, PartialEq)]
pub struct GeometryObject {
    /// The object's id, stable across frames.
    pub id: u32,
    /// Maps the stream's normalised frame (positions in [−1, 1)) to world metres.
    pub world_from_object: Matrix4,
    /// Linear radiance of a stream colour component of 1.
    pub radiance_scale: f64,
    /// The compressed geometry.
    pub block: GeometryBlock,
}

/// An object whose geometry is stored in an earlier key frame (Deering, *HoloFlicks* §13).
/// Spec §6.6.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyFrameReference {
    /// The object's id, the same as in the key frame.
    pub id: u32,
    /// The key frame that stores the geometry.
    pub key_frame: u32,
    /// This frame's transform (a rigid moving object is stored once).
    pub world_from_object: Matrix4,
}

/// One object of a frame: stored here, or named in a key frame.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectRecord {
    /// Geometry stored in this frame.
    Stored(GeometryObject),
    /// Geometry stored in an earlier key frame.
    Reference(KeyFrameReference),
}

impl ObjectRecord {
    /// The object's id.
    pub fn id(&self) -> u32 {
        match self {
            ObjectRecord::Stored(o) => o.id,
            ObjectRecord::Reference(r) => r.id,
        }
    }

    /// The object's transform in this frame.
    pub fn world_from_object(&self) -> &Matrix4 {
        match self {
            ObjectRecord::Stored(o) => &o.world_from_object,
            ObjectRecord::Reference(r) => &r.world_from_object,
        }
    }
}

/// One frame as stored (spec §6).
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// A key frame: holds no references; its objects may be referred to.
    pub key_frame: bool,
    /// Where the viewer may be.
    pub couch: ViewerCouch,
    /// Specular lights.
    pub lights: Vec<SpecularLight>,
    /// Specular materials.
    pub materials: Vec<SpecularMaterial>,
    /// Which material and lights apply to which object.
    pub bindings: Vec<Binding>,
    /// The objects, in drawing order.
    pub objects: Vec<ObjectRecord>,
}

/// An object of a frame with its geometry found (a reference resolved).
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedObject {
    /// The object's id.
    pub id: u32,
    /// Its transform in this frame.
    pub world_from_object: Matrix4,
    /// Linear radiance of a stream colour component of 1 (as stored).
    pub radiance_scale: f64,
    /// The compressed geometry.
    pub block: GeometryBlock,
    /// The frame the geometry is stored in (this frame, or a key frame).
    pub stored_in_frame: u32,
}

/// A frame read with every key-frame reference resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedFrame {
    /// Frame number (0-based).
    pub number: u32,
    /// The frame as stored.
    pub frame: Frame,
    /// One entry per `frame.objects` entry, in the same order.
    pub objects: Vec<ResolvedObject>,
}

/// What a HoloFlick says about itself (spec §5).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Info {
    /// Container version (major, minor) of the file.
    pub version: (u16, u16),
    /// Frame rate, numerator / denominator (frames per second).
    pub frames_per_second: (u32, u32),
    /// Version of the compressed geometry (major, minor, minor-minor): 1.0.2.
    pub geometry_version: [u32; 3],
    /// Text entries (`title`, `source`, `software`, ...), in file order.
    pub text: Vec<(String, String)>,
}

/// Check a text entry (spec §5.2).
pub(crate) fn text_problem(key: &str, value: &str) -> Option<String> {
    if key.is_empty() || key.len() > TEXT_KEY_MAX || !key.bytes().all(|b| b.is_ascii_graphic()) {
        return Some(format!("text key {key:?} must be 1 to {TEXT_KEY_MAX} printable ASCII characters without spaces"));
    }
    if value.contains('\0') {
        return Some(format!("text value of {key:?} contains a NUL"));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn descriptor_bits_round_trip() {
        for bits in 0..64u32 {
            match Descriptor::from_bits(bits) {
                Some(d) => assert_eq!(d.to_bits(), bits),
                None => assert!(bits & 3 == 0 || bits >= 0x20, "{bits:#x}"),
            }
        }
        assert_eq!(Descriptor::LIT_TRIANGLES.to_bits(), 0x0F);
    }

    #[test]
    fn couch_culling_is_exact_on_corners() {
        let couch = ViewerCouch { min_m: [-1.0, -1.0, 1.0], max_m: [1.0, 1.0, 2.0] };
        // A surface at the origin facing +z is seen; facing −z it is not.
        assert!(couch.sees_front([0.0; 3], [0.0, 0.0, 1.0]));
        assert!(!couch.sees_front([0.0; 3], [0.0, 0.0, -1.0]));
        // Grazing: facing +x from x = 1 is seen from no point of the box (only its face, at zero).
        assert!(!couch.sees_front([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]));
        // Tilted: seen from the corner (1, 1, 1) only.
        assert!(couch.sees_front([0.0, 0.0, 0.0], [1.0, 1.0, -0.99]));
        assert!(couch.contains([1.0, -1.0, 1.5]) && !couch.contains([0.0, 0.0, 0.5]));
    }
}
