//! Errors of the HoloFlick container: each names the file, the frame when
//! there is one, and the rule broken (spec/holoflick.md §11). They live with
//! the library's other errors (and the HoloFlick container hands them
//! on), so the error floor imports nothing above it.

use std::fmt;
use std::path::PathBuf;

/// Where in a file a problem is: the whole file, or one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct At(pub Option<u32>);

impl fmt::Display for At {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(n) => write!(f, ": frame {n}"),
            None => Ok(()),
        }
    }
}

/// Everything that can go wrong reading or writing a HoloFlick.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ContainerError {
    /// The operating system refused a read or write.
    #[error("{}: {source}", .path.display())]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// What the OS said.
        source: std::io::Error,
    },
    /// The file ends (or a chunk ends) before a structure it declares.
    #[error("{}{at}: truncated: {what}", .path.display())]
    Truncated {
        /// The file concerned.
        path: PathBuf,
        /// The frame, when the problem is inside one.
        at: At,
        /// What could not be read whole.
        what: String,
    },
    /// The bytes break a rule of the spec.
    #[error("{}{at}: {problem}", .path.display())]
    Invalid {
        /// The file concerned.
        path: PathBuf,
        /// The frame, when the problem is inside one.
        at: At,
        /// The rule broken, as one sentence.
        problem: String,
    },
    /// The bytes do not match the checksum written with them (spec §3.3):
    /// the file changed after it was written.
    #[error("{}{at}: damaged: {what} (the file changed after it was written)", .path.display())]
    Damaged {
        /// The file concerned.
        path: PathBuf,
        /// The frame, when the damage is inside one.
        at: At,
        /// What is damaged, as one sentence: the chunk, and the object id
        /// as stored when the chunk holds an object.
        what: String,
    },
    /// A declared count or size exceeds the format's limits (spec §10).
    #[error("{}{at}: {what} is {value}, more than the limit of {limit}", .path.display())]
    TooLarge {
        /// The file concerned.
        path: PathBuf,
        /// The frame, when the problem is inside one.
        at: At,
        /// Which quantity.
        what: &'static str,
        /// Its declared value.
        value: u64,
        /// The limit.
        limit: u64,
    },
    /// A version this reader does not read.
    #[error("{}: {what} version {found}; this reader reads {supported}", .path.display())]
    UnsupportedVersion {
        /// The file concerned.
        path: PathBuf,
        /// `HoloFlick` or `compressed geometry`.
        what: &'static str,
        /// The version in the file, as `major.minor[.minor-minor]`.
        found: String,
        /// What this reader reads.
        supported: &'static str,
    },
    /// A critical chunk this reader does not know (spec §3.2).
    #[error("{}{at}: critical chunk {tag:?} is unknown to this reader (a feature of a newer version)", .path.display())]
    UnknownChunk {
        /// The file concerned.
        path: PathBuf,
        /// The frame, when the chunk is inside one.
        at: At,
        /// The chunk's tag.
        tag: String,
    },
    /// A key-frame reference that does not resolve (spec §6.6).
    #[error("{}: frame {frame}: object {object} refers to frame {key_frame}: {problem}", .path.display())]
    BadReference {
        /// The file concerned.
        path: PathBuf,
        /// The frame holding the reference.
        frame: u32,
        /// The object id referred to.
        object: u32,
        /// The frame referred to.
        key_frame: u32,
        /// Why it does not resolve.
        problem: String,
    },
    /// A frame asked for past the file's end.
    #[error("{}: frame {frame} asked for; the file has {frames} frames", .path.display())]
    NoFrame {
        /// The file concerned.
        path: PathBuf,
        /// The frame asked for.
        frame: u32,
        /// How many frames the file holds.
        frames: usize,
    },
    /// A write option the format cannot store (a zero frame rate, too
    /// many or too long text entries, a key given twice).
    #[error("{}: {problem}", .path.display())]
    Unstorable {
        /// The file being written.
        path: PathBuf,
        /// Which option, and why it cannot be stored.
        problem: String,
    },
    /// The output cannot be written as asked (it exists, its folder is
    /// missing, the process is being interrupted).
    #[error("{}: {problem}", .path.display())]
    Output {
        /// The output concerned.
        path: PathBuf,
        /// What is wrong with writing it.
        problem: super::OutputProblem,
    },
}

impl ContainerError {
    /// An error of the atomic writer (the output module's) writing `path`, in
    /// the container's terms.
    pub(crate) fn from_output(path: &std::path::Path, e: super::Error) -> ContainerError {
        match e {
            super::Error::Io { path, source } => ContainerError::Io { path, source },
            super::Error::Output { path, problem } => ContainerError::Output { path, problem },
            // The atomic writer reports nothing else; an error it may one
            // day add keeps its sentence.
            other => ContainerError::Io { path: path.to_path_buf(), source: std::io::Error::other(other.to_string()) },
        }
    }
}

/// The container's error as the crate's: an operating-system or output
/// error as such, every other one as [`super::Error::HoloFlick`].
impl From<ContainerError> for super::Error {
    fn from(e: ContainerError) -> Self {
        match e {
            ContainerError::Io { path, source } => super::Error::Io { path, source },
            ContainerError::Output { path, problem } => super::Error::Output { path, problem },
            other => super::Error::HoloFlick(other),
        }
    }
}
