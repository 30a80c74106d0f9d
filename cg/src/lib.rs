//! Deering compressed geometry, exactly as Java 3D 1.5.2 reads it (stream
//! format 1.0.2), and Java 3D's `.cg` resource files.
//!
//! The crate stands alone: it depends on nothing but `thiserror` and
//! `smallvec`, works on slices of plain arrays and bytes, and leaves writing
//! files to its caller (how bytes reach a disk safely is the application's
//! business).
//!
//! The format is Michael Deering's (M. Deering, "Geometry Compression",
//! SIGGRAPH 1995). A stream is a bit string of commands, each an 8-bit
//! header and a body; headers run one command ahead of their bodies
//! ("header forwarding"), and the first body belongs to an implicit no-op.
//! Positions, colours and normals are Huffman-coded deltas or absolute
//! values (the paper's sections on quantization, delta coding and its
//! modified Huffman tables); a 16-entry mesh buffer lets a vertex be sent
//! once and referenced later, and 2-bit replace codes on every vertex make
//! generalized triangle strips (the paper's "generalized triangle mesh");
//! normals are points of a sextant/octant/(u, v) grid on the unit sphere
//! (its section on normal compression). The paper leaves details open;
//! Java 3D 1.5.2 fixes them, and its decoder is the working definition this
//! crate follows bit for bit: *The Java 3D API Specification*, appendix B
//! "3D Geometry Compression", and its source (`GeometryDecompressor`,
//! `GeneralizedStrip`, `GeometryDecompressorShape3D` in `javax.media.j3d`;
//! `CompressionStream*` and `CompressedGeometryFile` in
//! `com.sun.j3d.utils.geometry.compression`).
//!
//! Where to start:
//! * [`encode`] a [`Mesh`] with [`EncodeOptions`] (bits for position, colour
//!   and normal) into an [`Encoded`] stream plus the centre and scale that map
//!   model space into the stream's normalised `[-1, 1)` frame;
//! * [`decode`] a stream into triangles exactly as Java 3D builds them, or
//!   [`decode_with`] to receive each primitive as it is decoded;
//!   [`decode_reference`] is the slow, literal twin of [`decode`];
//! * [`file`](mod@file) parses `.cg` files and lays them out
//!   ([`CgFile::parse`], [`CgFile::to_bytes`]); [`read_cg_file`] reads and
//!   decodes one in a call.
//!
//! ```
//! use holo_cg::{decode, encode, CgFile, EncodeOptions, Mesh};
//!
//! // A unit square in the z = 0 plane, two triangles counter-clockwise from +z.
//! let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
//! let triangles = [[0, 1, 2], [0, 2, 3]];
//! let mesh = Mesh { positions: &positions, normals: None, colors: None, triangles: &triangles };
//! let encoded = encode(&mesh, &EncodeOptions::default())?;
//! let decoded = decode(&encoded.header, &encoded.bytes)?;
//! assert_eq!(decoded.triangles.len(), 2);
//!
//! // 16 position bits: each corner comes back within half a step (2^-16 of
//! // the normalised frame) of an input vertex, once mapped to model units.
//! let tolerance = 0.5f64.powi(16) / encoded.scale * 1.001;
//! for corner in decoded.triangles.iter().flatten() {
//!     let p = encoded.model_from_normalised(corner.position);
//!     assert!(positions.iter().any(|q| (0..3).all(|k| (p[k] - q[k]).abs() <= tolerance)));
//! }
//!
//! // As a one-object `.cg` file, which Java 3D's CompressedGeometryFile reads.
//! let bytes = CgFile::from_encoded(&encoded).to_bytes();
//! let file = CgFile::parse(&bytes, std::path::Path::new("square.cg"))?;
//! assert_eq!(decode(&file.objects[0].header, &file.objects[0].bytes)?, decoded);
//! # Ok::<(), holo_cg::Error>(())
//! ```
//!
//! Decoded values are in Java 3D's normalised frame, computed with Java's
//! float arithmetic: a position is the 16-bit value / 32768, a colour
//! component the 16-bit value / 32768 (so 1.0 comes back as 1 − 2⁻¹⁵ at most),
//! a normal comes from Java's s1.14 table.
//!
//! Java 3D behaviours this codec reproduces, and the ones it refuses, are
//! listed on [`decode`].
//!
//! Safety on untrusted input: every decoder entry point returns an error,
//! never panics, on any bytes; output grows only with decoded vertices, of
//! which a stream of `n` bits holds at most `n / 9`. The crate has no
//! `unsafe` code: the fast decoder's reads without end-of-stream checks are
//! ordinary bounds-checked slice reads that a margin keeps in range (see
//! `decode.rs`), so a mistake there would be a panic, never undefined
//! behaviour.

// No unsafe code at all; should some ever be needed, each unsafe operation
// must still sit in its own `unsafe` block with a `// SAFETY:` comment.
#![forbid(unsafe_code)]
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(missing_docs)]

mod bits;
mod decode;
mod encode;
mod error;
pub mod file;
mod huffman;
mod meshify;
mod normals;
mod reference;
mod state;
mod strip;

pub use encode::{encode, EncodeOptions, EncodeStats, Encoded, Mesh};
pub use error::{Error, FileProblem, Result, StreamProblem, Table};
pub use file::{read_cg_file, CgFile, CgObject};
pub use normals::{normal_error_bound_rad, NormalCode};
pub use strip::Primitive;

/// What a compressed-geometry block holds (Java 3D's bufferType).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlockKind {
    /// Points (`POINT_BUFFER` = 0; `.cg` type code 1).
    Points,
    /// Line strips (`LINE_BUFFER` = 1; `.cg` type code 2).
    Lines,
    /// Generalized triangle strips (`TRIANGLE_BUFFER` = 2; `.cg` type code 3).
    Triangles,
}

/// The description that travels beside a stream (Java 3D's
/// `CompressedGeometryHeader` without bounds, which no file stores).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CgHeader {
    /// Points, lines or triangles.
    pub kind: BlockKind,
    /// Vertices carry normals.
    pub normals: bool,
    /// Vertices carry colours.
    pub colors: bool,
    /// Colours carry alpha.
    pub alpha: bool,
    /// Format version (major, minor, minor-minor); the encoder writes 1.0.2.
    pub version: [u32; 3],
}

impl CgHeader {
    /// A triangle block of format 1.0.2 with the given data.
    pub fn triangles(normals: bool, colors: bool, alpha: bool) -> Self {
        CgHeader { kind: BlockKind::Triangles, normals, colors, alpha, version: [1, 0, 2] }
    }

    /// Java 3D's `checkVersion`: major below 1, or 1 with minor 0 (minor-minor is not checked).
    pub fn version_supported(&self) -> bool {
        self.version[0] < 1 || (self.version[0] == 1 && self.version[1] == 0)
    }
}

/// A decoded vertex in Java 3D's normalised frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vertex {
    /// Position, each component in [-1, 1).
    pub position: [f32; 3],
    /// Unit normal, when the vertex list has normals.
    pub normal: Option<[f32; 3]>,
    /// RGBA colour, when the list has colours (alpha 1 when the stream has none).
    pub color: Option<[f32; 4]>,
}

/// A decoded vertex as the integers the stream carries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct QuantizedVertex {
    /// Position as signed 16-bit fixed point (value / 32768).
    pub position: [i16; 3],
    /// Normal code, when present.
    pub normal: Option<NormalCode>,
    /// RGBA as signed 16-bit fixed point (value / 32768); alpha is the
    /// decoder's current alpha (0 unless the stream sends alpha).
    pub color: Option<[i16; 4]>,
}

/// A decoded block.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Decoded {
    /// Triangles (triangle blocks), counter-clockwise from the front, in Java
    /// 3D's `TriangleArray` order: per vertex list, strips' triangles then fans'.
    pub triangles: Vec<[Vertex; 3]>,
    /// The same triangles as stream integers.
    pub quantized: Vec<[QuantizedVertex; 3]>,
    /// Line segments (line blocks).
    pub lines: Vec<[Vertex; 2]>,
    /// Points (point blocks).
    pub points: Vec<Vertex>,
}

fn check_version(header: &CgHeader) -> Result<()> {
    if !header.version_supported() {
        return Err(Error::UnsupportedVersion { version: header.version });
    }
    Ok(())
}

/// Decode a stream into the primitives Java 3D 1.5.2 builds from it
/// (`GeometryDecompressorShape3D` with `TriangleArray` output).
///
/// What decides the output, as in Java 3D:
/// * setState starts a new vertex list; so does a global (unbundled) colour
///   change after any vertex, and a global normal when the list had no
///   normals. Strips never continue across lists.
/// * A global normal, once set, replaces every later vertex's normal
///   (Java's back end keeps `curNormal`); a global colour gives the
///   vertices of lists without bundled colours that colour (Java puts it in
///   the Shape3D's Material), alpha 1.
/// * A mesh-buffer reference takes the slot's normal and colour unless a
///   setNormal / setColor came since the last vertex (`meshState`).
/// * Colour alpha that would lie inside the 6-bit header (tag + 3 × length
///   < 6) decodes as 0, Java's `processSetColor` masking bug.
/// * A regular normal with `u + v > 64` (both within 0..=64) decodes to the
///   zero vector, Java's unfilled table entries.
/// * Replace codes of the two vertices after a restart are ignored; the first
///   vertex of a list is a restart whatever its code.
///
/// Where Java 3D fails with an exception or reads garbage, this returns an
/// error naming the bit offset of the command: a length that is not a whole
/// number of 4-byte words, a command running past the end, a vertex,
/// global colour or global normal before any setState (Java: null
/// pointer), a setTable naming table 3 (Java indexes past its 3 tables),
/// a mesh-buffer reference deeper than the pushes so far (Java
/// reads zeroed slots), a table entry whose shift exceeds its length, a
/// position entry too short to hold the replace bits, a normal outside the
/// grid, a restart without two following vertices. An empty vertex list
/// gives no triangles (Java throws).
///
/// Safe on untrusted input.
pub fn decode(header: &CgHeader, bytes: &[u8]) -> Result<Decoded> {
    check_version(header)?;
    let mut sink = strip::JavaOrder::for_stream(header.kind, bytes.len());
    decode::run(bytes, &mut sink).map_err(Error::from)?;
    let c = sink.out;
    Ok(Decoded { triangles: c.triangles, quantized: c.quantized, lines: c.lines, points: c.points })
}

/// [`decode`] by the slow reference decoder (bit-by-bit reads, table lookups
/// by searching the setTable commands, Java's branch structure). Same
/// output and same errors as [`decode`]; for tests and fuzzing.
pub fn decode_reference(header: &CgHeader, bytes: &[u8]) -> Result<Decoded> {
    check_version(header)?;
    let mut sink = strip::JavaOrder::derived(header.kind);
    reference::run(bytes, &mut sink).map_err(Error::from)?;
    let c = sink.out;
    Ok(Decoded { triangles: c.triangles, quantized: c.quantized, lines: c.lines, points: c.points })
}

/// Decode a stream, handing each primitive to `f` as soon as its last vertex
/// is decoded; memory stays constant. The primitives are those of
/// [`decode`] with the same orientation, in stream order (Java 3D's
/// `TriangleArray` lists a vertex list's strip triangles before its fan
/// triangles, and may start a triangle at another vertex). On error, `f`
/// has seen the primitives before the faulty command.
///
/// Safe on untrusted input.
pub fn decode_with(header: &CgHeader, bytes: &[u8], f: impl FnMut(Primitive)) -> Result<()> {
    check_version(header)?;
    let mut sink = strip::Streaming::new(header.kind, f);
    decode::run(bytes, &mut sink).map_err(Error::from)
}
