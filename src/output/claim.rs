//! One writer per output: a [`Claim`] is an advisory lock (`flock`) on a
//! hidden file beside the output (`.NAME.lock`), or in the folder of a set
//! (`.MANIFEST.lock`), taken before any work and held until the output is
//! in place. A second process that
//! asks for the same output is refused at once, naming the first; a lock
//! file whose process has died (the system released its lock) is no
//! obstacle. Within one process a claim is shared: the command's check and
//! the writer's file take the same lock.
//!
//! The first claim of an output in a process also removes the temporaries
//! beside it (or, for a set, in its folder) that a writer which no longer
//! runs left behind (a SIGKILL or a power cut gives it no chance to), and
//! says so through [`take_notices`].

use std::fs::File;
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use super::interrupt;
use super::naming::{file_lock, folder_lock, may_be_running, parse_temporary, stem_of};
use crate::error::{Error, OutputProblem, Result};

/// An output claimed by this process (see the module docs): the lock is
/// released, and its file removed, when the last claim of it is dropped.
#[derive(Debug)]
#[must_use = "the output is claimed only while the claim is held"]
pub struct Claim {
    /// The lock file; `None` where the system has no locks.
    lock: Option<PathBuf>,
}

/// What the lock protects, for the removal of stale temporaries.
#[derive(Clone, Copy)]
pub(super) enum Scope<'a> {
    /// A file: temporaries beside it with its stem.
    File(&'a Path),
    /// A folder a set (or a run) writes, named by its manifest (or the
    /// run's name): every temporary in it.
    Folder(&'a Path, &'a str),
}

impl Claim {
    /// Claim an output (a file, or the folder of a set or run) for this
    /// process; refused when another holds it.
    pub(super) fn take(scope: Scope<'_>) -> Result<Claim> {
        let (path, refused) = match scope {
            Scope::File(p) => (file_lock(p), p),
            Scope::Folder(p, name) => (folder_lock(p, name), p),
        };
        // Without its folder there is nothing to lock yet: a set's folder is
        // claimed once it is made; a file's is missing, which its writer
        // says, naming the folder.
        if !super::folder_of(&path).is_dir() {
            return Ok(Claim::none());
        }
        let mut guarded = false;
        let fresh = interrupt::take_lock(&path, || {
            let (file, locked) = lock(&path, refused)?;
            guarded = locked;
            Ok(file)
        })?;
        // Only under a lock that excludes other writers: where the file
        // system has no locks, a temporary whose writer is not running here
        // may be another machine's, being written.
        if fresh && guarded {
            remove_stale(&scope);
        }
        Ok(Claim { lock: Some(path) })
    }

    /// A claim that holds nothing (an output whose folder does not exist
    /// yet: it is claimed when its folder is made).
    pub(super) fn none() -> Claim {
        Claim { lock: None }
    }
}

impl Drop for Claim {
    fn drop(&mut self) {
        if let Some(path) = self.lock.take() {
            interrupt::release_lock(&path);
        }
    }
}

/// Open `path` and take its lock for this process, or say who holds it;
/// with whether the lock excludes other processes (not where the file
/// system has no locks). A failure to make the lock file names the output,
/// which cannot be written there either.
fn lock(path: &Path, output: &Path) -> Result<(File, bool)> {
    let io = |e| Error::io(output, e);
    loop {
        let mut file =
            std::fs::OpenOptions::new().read(true).write(true).create(true).truncate(false).open(path).map_err(io)?;
        let Some(guarded) = try_lock(&file).map_err(io)? else {
            let mut text = String::new();
            let _ = file.read_to_string(&mut text);
            let pid = text.trim().parse().ok();
            return Err(Error::Output { path: output.to_path_buf(), problem: OutputProblem::Locked { pid } });
        };
        // The holder before us may have removed the file between our open
        // and our lock: then the lock is on a file no one else will open.
        if !still_at(&file, path) {
            continue;
        }
        file.set_len(0).map_err(io)?;
        file.rewind().map_err(io)?;
        writeln!(file, "{}", std::process::id()).map_err(io)?;
        return Ok((file, guarded));
    }
}

/// Take `file`'s exclusive lock without waiting: `Some(true)` when taken,
/// `None` when another process holds it, `Some(false)` on a file system
/// that has no locks (some network file systems answer `ENOLCK`), which is
/// written as before locks: unguarded.
fn try_lock(file: &File) -> std::io::Result<Option<bool>> {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::io::AsRawFd;
        // SAFETY: the descriptor is open for as long as `file` lives.
        if unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } == 0 {
            return Ok(Some(true));
        }
        let e = std::io::Error::last_os_error();
        match e.raw_os_error() {
            Some(libc::EWOULDBLOCK) => Ok(None),
            Some(libc::ENOLCK | libc::EOPNOTSUPP | libc::ENOSYS) => Ok(Some(false)),
            _ => Err(e),
        }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = file;
        Ok(Some(false))
    }
}

/// Whether `path` still names the open `file`.
fn still_at(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), std::fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (file, path);
        true
    }
}

/// What the output module has to say that is no error (stale temporaries
/// removed), until [`take_notices`] takes it.
static NOTICES: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// The notices since the last call, oldest first: each a sentence saying
/// what holo did beside an output that the user did not ask for (a stale
/// temporary of a writer that no longer runs removed). A program shows
/// them as it shows warnings.
pub fn take_notices() -> Vec<String> {
    std::mem::take(&mut *NOTICES.lock().unwrap_or_else(PoisonError::into_inner))
}

/// Remove the temporaries of `scope` whose writer no longer runs, and say
/// so. Called with the output's lock held, so no other holo process is
/// writing it.
fn remove_stale(scope: &Scope<'_>) {
    let (folder, stem) = match scope {
        Scope::File(p) => (super::folder_of(p).to_path_buf(), Some(stem_of(p))),
        Scope::Folder(p, _) => (p.to_path_buf(), None),
    };
    let Ok(entries) = std::fs::read_dir(&folder) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some((found, pid)) = name.to_str().and_then(parse_temporary) else { continue };
        let ours = stem.as_deref().map_or(true, |s| s == found);
        if !ours || pid == std::process::id() || may_be_running(pid) {
            continue;
        }
        if entry.file_type().is_ok_and(|t| t.is_file()) && std::fs::remove_file(entry.path()).is_ok() {
            NOTICES.lock().unwrap_or_else(PoisonError::into_inner).push(format!(
                "removed {}, a temporary file left by holo process {pid}, which no longer runs",
                entry.path().display()
            ));
        }
    }
}
