//! Errors of the library. Each variant carries the file it concerns (when there
//! is one) and structured fields, so the CLI can print one clear sentence.

use std::path::PathBuf;

/// Everything that can go wrong in `holo`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The operating system refused a read or write.
    #[error("{path}: {source}", path = .path.display())]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// What the OS said.
        source: std::io::Error,
    },
    /// The bytes are not a well-formed OpenEXR file (truncated, bad magic, ...).
    #[error("{path}: not a readable OpenEXR file: {message}", path = .path.display())]
    Exr {
        /// The file concerned.
        path: PathBuf,
        /// What the EXR decoder said.
        message: String,
    },
    /// A well-formed EXR file that breaks a rule of the `.holo` spec.
    #[error("{path}: {problem}", path = .path.display())]
    Invalid {
        /// The file concerned.
        path: PathBuf,
        /// The rule broken, as one sentence.
        problem: String,
    },
    /// The file was written by a newer major version of the format.
    #[error("{path}: written with .holo format version {major}.{minor}; this reader understands major version {supported} only", path = .path.display())]
    NewerMajorVersion {
        /// The file concerned.
        path: PathBuf,
        /// Major version in the file.
        major: i32,
        /// Minor version in the file.
        minor: i32,
        /// Major version this library reads.
        supported: i32,
    },
    /// A declared size exceeds what this reader will allocate.
    #[error("{path}: {what} is {value}, more than the limit of {limit}", path = .path.display())]
    TooLarge {
        /// The file concerned.
        path: PathBuf,
        /// Which quantity.
        what: &'static str,
        /// Its declared value.
        value: u64,
        /// The limit.
        limit: u64,
    },
    /// A sample is NaN, infinite, negative or out of the stored type's range.
    #[error("{path}: frame {frame}, hololine {hololine}, emitter {emitter}, view {view}, channel {channel}: sample {value} is {why}", path = .path.display())]
    BadSample {
        /// The file concerned (or the file being written).
        path: PathBuf,
        /// Frame index.
        frame: usize,
        /// Hololine index.
        hololine: usize,
        /// Emitter index.
        emitter: usize,
        /// View index.
        view: usize,
        /// Channel suffix (`R`, `G`, `B`, `Y`).
        channel: String,
        /// The value found.
        value: f32,
        /// Why it is refused.
        why: &'static str,
    },
    /// The samples do not hash to the digest stored in the file.
    #[error("{path}: frame {frame}: samples do not match the stored digest (stored {stored}, computed {computed}); the file is damaged", path = .path.display())]
    DigestMismatch {
        /// The file concerned.
        path: PathBuf,
        /// Frame index.
        frame: usize,
        /// Digest in the header.
        stored: String,
        /// Digest of the samples read.
        computed: String,
    },
    /// The compressed-geometry codec refused a `.cg` file, a stream or a mesh
    /// (its message names the file when there is one).
    #[error(transparent)]
    CompressedGeometry(#[from] holo_cg::Error),
    /// A request that does not fit the data (bad frame index, region, geometry mismatch, ...).
    #[error("{0}")]
    Usage(String),
}

/// Result with the library's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io { path: path.into(), source }
    }
    pub(crate) fn invalid(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Error::Invalid { path: path.into(), problem: problem.into() }
    }
    pub(crate) fn exr(path: impl Into<PathBuf>, error: exr::error::Error) -> Self {
        let path = path.into();
        match error {
            exr::error::Error::Io(source) if source.kind() == std::io::ErrorKind::UnexpectedEof => {
                Error::Exr { path, message: "the file is truncated".into() }
            }
            exr::error::Error::Io(source) => Error::Io { path, source },
            exr::error::Error::Invalid(message) => Error::Exr { path, message: format!("invalid {message}") },
            exr::error::Error::NotSupported(message) => {
                Error::Exr { path, message: format!("uses an unsupported feature: {message}") }
            }
            other => Error::Exr { path, message: other.to_string() },
        }
    }
}
