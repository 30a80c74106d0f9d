//! Errors of the library. Each variant carries the file it concerns (when there
//! is one) and structured fields, so the CLI can print one clear sentence.

use std::path::PathBuf;

pub(crate) mod holoflick;

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
    #[error("{path}: frame {frame}, hololine {hololine}, emitter {emitter}, view {view_text}, channel {channel}: sample {value} is {why}", path = .path.display(), view_text = view_text(*.view, *.vertical_view))]
    BadSample {
        /// The file concerned (or the file being written).
        path: PathBuf,
        /// Frame index.
        frame: usize,
        /// Hololine index.
        hololine: usize,
        /// Emitter index.
        emitter: usize,
        /// View index (full parallax: the horizontal one).
        view: usize,
        /// Full parallax: the vertical view index (the view is then said as
        /// `(view vertical_view)`, as a view picture's name says it).
        vertical_view: Option<usize>,
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
    /// A HoloFlick (`.hflk`) file that breaks a rule of its spec, or a
    /// request it cannot answer (a frame past its end, an option the
    /// format cannot store).
    #[error(transparent)]
    HoloFlick(holoflick::ContainerError),
    /// A scene that cannot be used: a mesh file (glTF, OBJ, PLY), its
    /// materials, textures or lights file, or a scene built in memory
    /// whose parts disagree (no triangles, a normal per vertex missing,
    /// lights that do not fit it).
    #[error("{path}: {problem}", path = .path.display())]
    Scene {
        /// The scene's file (or the name it was given when built in memory).
        path: PathBuf,
        /// What is wrong with it, as one sentence.
        problem: String,
    },
    /// A camera capture that cannot be used: its rig file, image folder,
    /// quilt, pictures or depth maps, or cameras placed so that they cannot
    /// fill the display's views.
    #[error("{path}: {problem}", path = .path.display())]
    Rig {
        /// The rig's file or folder (or the name it was given when built in memory).
        path: PathBuf,
        /// What is wrong with it, as one sentence.
        problem: String,
    },
    /// A display layout that is unknown, unreadable as a profile, or
    /// inconsistent (in itself or with the fringe side assembly needs).
    #[error("layout {layout}: {problem}")]
    Layout {
        /// The layout's name, or the profile file it was read from.
        layout: String,
        /// What is wrong with it, as one sentence.
        problem: String,
    },
    /// A layout name that is neither a built-in layout nor a profile file.
    #[error("unknown layout {name:?}: the built-in layouts are {}, or give a .toml or .json profile", .builtin.join(", "))]
    UnknownLayout {
        /// The name asked for.
        name: String,
        /// The built-in layouts' names (the layouts know them; errors do not).
        builtin: &'static [&'static str],
    },
    /// Frames asked of a file (or a set of files) that does not hold them.
    #[error("{path}: {}", no_frame_text(.asked, .frames), path = .path.display())]
    NoFrame {
        /// The file or folder asked.
        path: PathBuf,
        /// The frames asked for (one frame `n` is `n..n + 1`).
        asked: std::ops::Range<usize>,
        /// How many frames it holds.
        frames: usize,
    },
    /// A value the caller passed that is out of range or does not fit the
    /// data: a negative frame rate, a region outside the frame, a
    /// modulation of another geometry, a window holding no sample...
    #[error("{problem}")]
    Argument {
        /// The value concerned (`"frame rate"`, `"white level"`,
        /// `"geometry"`, ...), for a caller that names its own options.
        what: &'static str,
        /// What is wrong with it, as one sentence that names the value.
        problem: String,
    },
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
/// [`Error::Set`](Error::Set).
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
    /// The manifest, or a file it lists, cannot be read as what the set
    /// says it is (not JSON, an image of another size, a missing channel).
    #[error("{0}")]
    Malformed(String),
}

/// Why an output cannot be written: the problems of
/// [`Error::Output`](Error::Output).
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
    /// Something other than a regular file or a folder (a FIFO, a device,
    /// a socket) stands where the output goes: it is never replaced.
    #[error("is {kind}, not {wanted}")]
    NotRegular {
        /// What is there (`a FIFO`, `a character device`, ...).
        kind: &'static str,
        /// What the output is (`a regular file`, `a folder`).
        wanted: &'static str,
    },
    /// The output's name is longer than its file system takes.
    #[error("its name is {bytes} bytes long; the file system takes at most {limit}")]
    NameTooLong {
        /// The name's length in bytes.
        bytes: usize,
        /// The longest name the file system takes.
        limit: usize,
    },
    /// Another process is writing the same output (it holds the output's
    /// lock).
    #[error("is being written by another process{}; wait for it to finish, or stop it", .pid.map(|p| format!(" (pid {p})")).unwrap_or_default())]
    Locked {
        /// The process holding the lock, when its lock file says.
        pid: Option<u32>,
    },
    /// A folder already holds a set of files (its manifest names them) and
    /// replacing it was not asked for.
    #[error("already exists as a set of files ({0} lists them); not overwritten")]
    SetExists(String),
    /// The process is being interrupted: its temporary files are being
    /// removed, and nothing more is put in place.
    #[error("not put in place: the process is being interrupted")]
    Interrupted,
    /// The output's format cannot hold what is asked (a PNG of five
    /// components, a `.glb` over 4 GiB, a name whose format is unknown).
    #[error("{0}")]
    Unsupported(String),
    /// The encoder of the output's format refused the data.
    #[error("cannot write {format}: {message}")]
    Encode {
        /// The format (`PNG`, `JSON`, ...).
        format: &'static str,
        /// What the encoder said.
        message: String,
    },
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
    pub(crate) fn scene(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Error::Scene { path: path.into(), problem: problem.into() }
    }
    pub(crate) fn rig(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Error::Rig { path: path.into(), problem: problem.into() }
    }
    pub(crate) fn layout(layout: impl Into<String>, problem: impl Into<String>) -> Self {
        Error::Layout { layout: layout.into(), problem: problem.into() }
    }
    pub(crate) fn argument(what: &'static str, problem: impl Into<String>) -> Self {
        Error::Argument { what, problem: problem.into() }
    }
    /// An [`Error::BadSample`] found in memory (assembly of a frame read
    /// from `path`) said of that file and frame; any other error as it is.
    pub(crate) fn in_frame_of(self, path: &std::path::Path, frame: usize) -> Self {
        match self {
            Error::BadSample { hololine, emitter, view, vertical_view, channel, value, why, .. } => Error::BadSample {
                path: path.to_path_buf(),
                frame,
                hololine,
                emitter,
                view,
                vertical_view,
                channel,
                value,
                why,
            },
            other => other,
        }
    }
    /// An [`Error::Argument`] with the file it concerns put before its
    /// sentence; any other error as it is (it names its file already).
    pub(crate) fn naming(self, path: &std::path::Path) -> Self {
        match self {
            Error::Argument { what, problem } => {
                Error::Argument { what, problem: format!("{}: {problem}", path.display()) }
            }
            other => other,
        }
    }
    /// `frame` asked of `path`, which holds `frames`.
    pub(crate) fn no_frame(path: impl Into<PathBuf>, frame: usize, frames: usize) -> Self {
        Error::NoFrame { path: path.into(), asked: frame..frame + 1, frames }
    }
    /// An output whose format cannot hold what is asked.
    pub(crate) fn unsupported(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Error::Output { path: path.into(), problem: OutputProblem::Unsupported(problem.into()) }
    }
    /// An encoder's refusal to write `path` in `format`.
    pub(crate) fn encode(path: impl Into<PathBuf>, format: &'static str, message: impl std::fmt::Display) -> Self {
        Error::Output { path: path.into(), problem: OutputProblem::Encode { format, message: message.to_string() } }
    }
    pub(crate) fn exr(path: impl Into<PathBuf>, error: exr::error::Error) -> Self {
        let path = path.into();
        match error {
            exr::error::Error::Io(source) if source.kind() == std::io::ErrorKind::UnexpectedEof => {
                Error::Exr { path, message: "the file is truncated".into() }
            }
            exr::error::Error::Io(source) => Error::Io { path, source },
            // exrs's word for an offset table or chunk pointing past the end.
            exr::error::Error::Invalid(message) if message.contains("missing bytes") => {
                Error::Exr { path, message: format!("the file is truncated (invalid {message})") }
            }
            exr::error::Error::Invalid(message) => Error::Exr { path, message: format!("invalid {message}") },
            exr::error::Error::NotSupported(message) => {
                Error::Exr { path, message: format!("uses an unsupported feature: {message}") }
            }
            other => Error::Exr { path, message: other.to_string() },
        }
    }
}

/// The problem of [`Error::NoFrame`]: one frame, or a range.
fn no_frame_text(asked: &std::ops::Range<usize>, frames: &usize) -> String {
    if asked.len() == 1 {
        format!("has {frames} frame(s); there is no frame {}", asked.start)
    } else {
        format!("frames {}..{} asked for; it has frames 0..{frames}", asked.start, asked.end)
    }
}

/// A view as an error names it: its index, or for full parallax its
/// horizontal and vertical indices, `(h k)`.
fn view_text(view: usize, vertical_view: Option<usize>) -> String {
    match vertical_view {
        Some(k) => format!("({view} {k})"),
        None => view.to_string(),
    }
}
