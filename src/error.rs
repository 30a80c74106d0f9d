//! Errors of the library. Each variant carries the file it concerns (when there
//! is one) and structured fields, so the CLI can print one clear sentence.

use std::path::PathBuf;

/// Everything that can go wrong in `holo`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The caller asked, through its [`crate::progress::Progress`], for the
    /// work to stop; nothing was written.
    #[error("cancelled; nothing was written")]
    Cancelled,
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
    /// An output that cannot be written as asked, found before any work
    /// (it exists, its folder is missing, it is one of the inputs) or when
    /// a set of files is replaced.
    #[error("{path}: {problem}", path = .path.display())]
    Output {
        /// The output concerned.
        path: PathBuf,
        /// What is wrong with writing it.
        problem: OutputProblem,
    },
    /// A set of files (fringes, views) that does not agree with its
    /// manifest, or has none: part of it is missing, mixed with other
    /// files, or was never completed.
    #[error("{path}: {problem}", path = .path.display())]
    Set {
        /// The file or folder concerned.
        path: PathBuf,
        /// How it disagrees.
        problem: SetProblem,
    },
}

/// How a set of files disagrees with its manifest: the problems of
/// [`Error::Set`](crate::Error::Set).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SetProblem {
    /// The folder has no manifest: not a set, or one whose writing was interrupted.
    #[error("has no {0}: not a complete set of files (its writing was interrupted, or the files come from elsewhere)")]
    NoManifest(String),
    /// The manifest lists no files with their digests (written before
    /// manifests did); `remedy` says how to make the set again.
    #[error("lists no files with their sizes and digests, so the set cannot be checked; {remedy}")]
    NoFileList {
        /// What to do, e.g. "assemble the fringes again".
        remedy: &'static str,
    },
    /// The manifest lists a name that is not a plain file name.
    #[error("lists {0:?}, which is not the name of a file in its folder")]
    BadName(String),
    /// A listed file is missing.
    #[error("listed in {0} but missing: the set is incomplete")]
    Missing(String),
    /// A listed file has another size.
    #[error("is {found} bytes; {manifest} lists {listed}: not the file of this set")]
    Size {
        /// The manifest's name.
        manifest: String,
        /// Bytes listed.
        listed: u64,
        /// Bytes found.
        found: u64,
    },
    /// A listed file has another SHA-256.
    #[error("its SHA-256 differs from the one {0} lists: not the file of this set")]
    Digest(String),
    /// The folder's set was being replaced when the writing stopped: its
    /// files may be of two sets (`remedy` says how to make it again).
    #[error("holds a set whose replacement was interrupted: its files may be of two sets; {remedy}")]
    Interrupted {
        /// What to do, e.g. "export the views again".
        remedy: &'static str,
    },
}

/// Why an output cannot be written: the problems of
/// [`Error::Output`](crate::Error::Output).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum OutputProblem {
    /// The file exists and replacing it was not asked for.
    #[error("already exists; not overwritten")]
    Exists,
    /// The folder the file would go in does not exist.
    #[error("the folder {} does not exist", .0.display())]
    FolderMissing(PathBuf),
    /// The output is one of the command's inputs (the same path, or another
    /// name of the same file); replacing it would destroy what is read.
    #[error("is the input {}; an output never replaces one of its inputs", .0.display())]
    IsAnInput(PathBuf),
    /// A file is wanted where a folder is, or a folder where a file is.
    #[error("{0}")]
    WrongKind(&'static str),
    /// A folder already holds a set of files (its manifest names them) and
    /// replacing it was not asked for.
    #[error("already exists as a set of files ({0} lists them); not overwritten")]
    SetExists(String),
    /// The process is being interrupted: its temporary files are being
    /// removed, and nothing more is put in place.
    #[error("not put in place: the process is being interrupted")]
    Interrupted,
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
