//! The codec's errors. Each says what is wrong in one sentence: where in the
//! stream (bit offset of the command) for a stream, which file for a file.

use std::fmt;
use std::path::PathBuf;

/// Everything the codec refuses.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A command stream the decoders refuse: where Java 3D 1.5.2 would throw
    /// or read garbage (the list is on [`decode`](crate::decode)).
    #[error("compressed geometry stream: at bit {bit}: {problem}")]
    Stream {
        /// Bit offset, from the start of the stream, of the faulty command's header.
        bit: u64,
        /// What is wrong.
        problem: StreamProblem,
    },
    /// A stream of a format version Java 3D 1.5.2 does not read.
    #[error(
        "compressed geometry format version {}.{}.{} is newer than 1.0.x, which Java 3D 1.5.2 and this decoder read",
        .version[0], .version[1], .version[2]
    )]
    UnsupportedVersion {
        /// (major, minor, minor-minor) as the header gives it.
        version: [u32; 3],
    },
    /// Encoder options outside the ranges the format can carry.
    #[error(
        "compressed geometry: bits must be position 1..=16, colour 2..=16, normal 0..=6 (got {position}, {color}, {normal})"
    )]
    BitsOutOfRange {
        /// [`EncodeOptions::position_bits`](crate::EncodeOptions::position_bits).
        position: u32,
        /// [`EncodeOptions::color_bits`](crate::EncodeOptions::color_bits).
        color: u32,
        /// [`EncodeOptions::normal_bits`](crate::EncodeOptions::normal_bits).
        normal: u32,
    },
    /// A per-vertex attribute array whose length is not the vertex count.
    #[error("compressed geometry: {positions} positions but {len} {attribute}")]
    AttributeLength {
        /// Number of positions (vertices).
        positions: usize,
        /// `"normals"` or `"colours"`.
        attribute: &'static str,
        /// Length of that array.
        len: usize,
    },
    /// More vertices than the encoder indexes.
    #[error("compressed geometry: {vertices} vertices is too many (at most {max})")]
    TooManyVertices {
        /// Vertices given.
        vertices: usize,
        /// The most the encoder takes.
        max: usize,
    },
    /// A triangle naming a vertex that does not exist.
    #[error("compressed geometry: triangle {index} {triangle:?} indexes past the {vertices} vertices")]
    IndexOutOfRange {
        /// Which triangle.
        index: usize,
        /// Its vertex indices.
        triangle: [u32; 3],
        /// Vertices given.
        vertices: usize,
    },
    /// A position with a NaN or infinite component.
    #[error("compressed geometry: the position of vertex {vertex} is not finite")]
    NonFinitePosition {
        /// Which vertex.
        vertex: usize,
    },
    /// The encoder contradicted itself: a bug in this crate, never the input's fault.
    #[error("compressed geometry encoder: inconsistent internal state (a bug)")]
    Internal,
    /// A `.cg` file whose layout is broken.
    #[error("{path}: {problem}", path = .path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong with its layout.
        problem: FileProblem,
    },
    /// An object of a `.cg` file that does not decode.
    #[error("{path}: object {object}: {source}", path = .path.display())]
    Object {
        /// The file.
        path: PathBuf,
        /// Index of the object in the file's directory.
        object: usize,
        /// Why it does not decode.
        source: Box<Error>,
    },
    /// The operating system refused to read a file.
    #[error("{path}: {source}", path = .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
}

/// Result with the codec's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Which of the three decompression tables (Java 3D's `gctables`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Table {
    /// Table 0.
    Position,
    /// Table 1.
    Color,
    /// Table 2.
    Normal,
}

impl fmt::Display for Table {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Table::Position => "position",
            Table::Color => "colour",
            Table::Normal => "normal",
        })
    }
}

/// What is wrong with a command stream ([`Error::Stream`] gives where).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum StreamProblem {
    /// A command's body runs past the last word.
    #[error("the stream ends inside a command")]
    EndsInsideCommand,
    /// Java 3D refills 4 bytes at a time: any other length reads past the buffer.
    #[error("the stream is {bytes} bytes long, not a whole number of 4-byte words")]
    Length {
        /// Stream length in bytes.
        bytes: usize,
    },
    /// setTable naming table 3 (Java 3D indexes past its three tables).
    #[error("setTable names table {table}; there are 3 (0 position, 1 colour, 2 normal)")]
    NoSuchTable {
        /// The table number sent.
        table: usize,
    },
    /// A table entry used with a right shift larger than its data length
    /// (Java 3D would read a negative number of bits).
    #[error("{table} table entry shifts by {shift} bits, more than its data length {data_len}")]
    ShiftExceedsLength {
        /// The table.
        table: Table,
        /// The entry's shift.
        shift: u8,
        /// The entry's data length.
        data_len: u8,
    },
    /// A position entry so short that the header's 6 bits would hold more
    /// than the 3 replace/push bits.
    #[error(
        "position table entry of tag length {tag_len} and {data_len} bits per component leaves {header_bits} bits of the header for the 3 replace/push bits"
    )]
    ReplaceBitsInHeader {
        /// The entry's tag length.
        tag_len: u32,
        /// Bits sent per component.
        data_len: u32,
        /// Header bits left after the tag and the three components.
        header_bits: u32,
    },
    /// The reference decoder computed a negative bit count from a table entry.
    #[error("negative bit count {bits}")]
    NegativeBitCount {
        /// The count.
        bits: i64,
    },
    /// An absolute normal outside the triangle `u, v >= 0, u + v <= 64`.
    #[error("normal (u, v) = ({u}, {v}) lies outside the 64-step grid")]
    NormalOutsideGrid {
        /// Grid coordinate u.
        u: i32,
        /// Grid coordinate v.
        v: i32,
    },
    /// A relative normal change that Java 3D's one reflection cannot bring back into the grid.
    #[error("relative normal change ({du}, {dv}) leaves both u and v negative")]
    NormalDeltaOutside {
        /// Change of u.
        du: i32,
        /// Change of v.
        dv: i32,
    },
    /// A global normal before any setState (Java 3D: null pointer).
    #[error("a global normal comes before any setState command")]
    NormalBeforeSetState,
    /// A global colour before any setState (Java 3D: null pointer).
    #[error("a global colour comes before any setState command")]
    ColorBeforeSetState,
    /// A vertex or mesh-buffer reference before any setState (Java 3D: null pointer).
    #[error("a vertex comes before any setState command")]
    VertexBeforeSetState,
    /// A mesh-buffer reference deeper than the pushes so far (Java 3D reads zeroed slots).
    #[error("mesh-buffer reference {depth} but only {pushes} vertices have been pushed")]
    MeshReferenceTooDeep {
        /// How far back the reference reaches (0 = most recent push).
        depth: usize,
        /// Pushes so far (at most 16 count).
        pushes: usize,
    },
    /// A triangle-strip restart without the two vertices that complete its first triangle.
    #[error("a strip restart is not followed by two more vertices")]
    UnfinishedStrip,
    /// A line-strip restart without the vertex that completes its first line.
    #[error("a line strip restart is not followed by another vertex")]
    UnfinishedLine,
}

/// What is wrong with a `.cg` file's layout ([`Error::File`] names the file).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FileProblem {
    /// Shorter than the fixed header.
    #[error("{bytes} bytes is too short for the 32-byte .cg header")]
    TooShort {
        /// File length in bytes.
        bytes: usize,
    },
    /// Not `CompressedGeometryFile.MAGIC_NUMBER`.
    #[error("magic number {magic:#010X} is not 0xBADDFAB4: not a Java 3D .cg file")]
    BadMagic {
        /// The first four bytes, big-endian.
        magic: u32,
    },
    /// The directory of object offsets does not lie inside the file.
    #[error("the directory of {objects} objects at offset {offset} does not fit in the file's {bytes} bytes")]
    DirectoryOutside {
        /// Object count from the header.
        objects: usize,
        /// Directory offset from the header.
        offset: u64,
        /// File length in bytes.
        bytes: u64,
    },
    /// An object that does not lie between the header and the next object (or the directory).
    #[error("object {object} at offset {offset} does not fit before the next one at {end}")]
    ObjectOutside {
        /// Index in the directory.
        object: usize,
        /// Its offset.
        offset: u64,
        /// Where the next object (or the directory) starts.
        end: u64,
    },
    /// An object whose stream is longer than its block.
    #[error("object {object} declares {size} bytes of geometry but its block holds {room}")]
    StreamOutside {
        /// Index in the directory.
        object: usize,
        /// Stream length the object's header gives.
        size: u64,
        /// Bytes the block has after its 8-byte header.
        room: u64,
    },
    /// An object whose descriptor names no primitive type.
    #[error("object {object} has geometry type 0 (1 point, 2 line, 3 triangle)")]
    NoPrimitive {
        /// Index in the directory.
        object: usize,
    },
}
