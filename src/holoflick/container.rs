//! The HoloFlick container, `.hflk` (spec/holoflick.md): a holographic movie
//! as frames of compressed geometry objects with their specular lights,
//! materials, bindings and viewer's couch, a frame index for random access,
//! and key frames whose objects later frames reuse (Deering, *HoloFlicks* §10, §12, §13).
//!
//! Start at [`Frame`] (the data), then [`HoloFlickWriter`] (frames added one
//! at a time, written beside the destination and renamed into place) and
//! [`HoloFlickReader`] (`open`, `frame_count`, `read_frame(n)`). The geometry
//! blocks are opaque here: byte for byte the object records of Java 3D `.cg`
//! files, whose streams the compressed-geometry codec decodes.
//!
//! Invariants: the reader never panics and never allocates more than a
//! checked limit or the bytes the file has for it, whatever the bytes; the
//! writer checks every frame by the same rules the reader does, so it cannot
//! produce a file the reader refuses.

mod checksum;
mod chunk;
mod codec;
mod error;
mod model;
mod read;
mod write;

pub use crate::error::holoflick::{At, ContainerError};
pub use model::{
    Binding, BlockError, Descriptor, Frame, GeometryBlock, GeometryObject, Info, KeyFrameReference, Matrix4,
    ObjectRecord, Primitive, ResolvedFrame, ResolvedObject, SpecularLight, SpecularMaterial, SpecularModel,
    ViewerCouch, IDENTITY,
};
pub use read::HoloFlickReader;
pub use write::{write_cg_file, HoloFlickWriteOptions, HoloFlickWriter, WriteReport};

/// Result with the container's error.
pub type Result<T, E = ContainerError> = std::result::Result<T, E>;

/// The first 8 bytes of every HoloFlick (spec §4).
pub const MAGIC: [u8; 8] = crate::signature::HOLOFLICK;
/// Container major version this library reads and writes.
pub const VERSION_MAJOR: u16 = 1;
/// Container minor version this library writes.
pub const VERSION_MINOR: u16 = 1;
/// Version of the compressed geometry: Java 3D 1.5.2's format 1.0.2.
pub const GEOMETRY_VERSION: [u32; 3] = [1, 0, 2];

/// Most frames in a file.
pub const MAX_FRAMES: u64 = 1 << 20;
// A HoloFlick is the largest output a movie source writes: a source may make
// as many frames as it holds, and no more.
const _: () = assert!(MAX_FRAMES == crate::pipeline::MAX_SOURCE_FRAMES);
/// Most bytes of one frame's chunk.
pub const MAX_FRAME_BYTES: u64 = 1 << 30;
/// Most bytes of one compressed-geometry stream.
pub const MAX_BLOCK_STREAM_BYTES: u64 = 1 << 29;
/// Most objects in a frame (and bindings).
pub const MAX_OBJECTS: u64 = 1 << 16;
/// Most specular lights in a frame.
pub const MAX_LIGHTS: u64 = 1 << 10;
/// Most specular materials in a frame.
pub const MAX_MATERIALS: u64 = 1 << 16;
/// Most bytes of one text chunk.
pub const MAX_TEXT_BYTES: u64 = 1 << 16;
/// Most text chunks in a file.
pub const MAX_TEXT_ENTRIES: u64 = 256;
/// Most chunks before the first frame.
pub const MAX_FILE_CHUNKS: u64 = 4096;
/// Most bytes of geometry one resolved frame may gather from key frames.
pub const MAX_RESOLVED_BYTES: u64 = 1 << 32;

pub(crate) const TEXT_KEY_MAX: usize = 79;
pub(crate) const FILE_HEADER_BYTES: u64 = 32;
pub(crate) const HEAD_BYTES: usize = 24;
pub(crate) const COUCH_BYTES: usize = 48;
pub(crate) const LIGHT_RECORD: usize = 56;
pub(crate) const MATERIAL_RECORD: usize = 40;
pub(crate) const GEOM_HEADER: usize = 144;
pub(crate) const INDEX_ENTRY: u64 = 16;
pub(crate) const UNIT_TOLERANCE: f64 = 1e-6;
