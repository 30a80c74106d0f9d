//! How holo writes files: one discipline for every output.
//!
//! - Every file goes to a hidden temporary beside its destination
//!   (`.NAME.PID.XXXXXX.partial`; a scratch file is `.NAME.PID.XXXXXX.spool`;
//!   `NAME` shortened where the name leaves too little room), is flushed and
//!   synced, then renamed into place (never over an existing file unless
//!   replacing was asked, and never over a FIFO, a device or a socket), and
//!   the folder is synced: [`AtomicFile`], [`write_bytes_beside`]. Nothing is
//!   ever truncated under its final name; a temporary dropped without being
//!   put in place is removed.
//! - One writer per output: a [`Claim`] (a lock on `.NAME.lock` beside a
//!   file, or `.MANIFEST.lock` in a set's folder) is taken before any work
//!   and held until the output is in place; another process asking for it is refused, naming
//!   the first. The first claim also removes the temporaries that writers
//!   which no longer run left beside the output, said by [`take_notices`].
//! - Every temporary is in a process-wide registry from its creation until
//!   it is renamed or removed. [`install_interrupt_cleanup`] makes SIGINT,
//!   SIGTERM and SIGHUP remove them all, leave every previous file as it
//!   was and exit with 128 + the signal (130, 143, 129).
//! - A multi-file output is a [`FileSet`]: all its files are written as
//!   temporaries first, then put in place together, and its manifest, which
//!   lists every file with its size and SHA-256, is written last.
//!   [`verify_set`] is what a reader of a set calls first. The folders a
//!   set made for itself are removed again if it is not committed, on a
//!   signal too.
//! - [`check_output`] and [`check_set_output`] find, before any work, an
//!   output that exists, whose folder is missing, whose name is longer than
//!   its file system takes, that is not a regular file (or folder), that is
//!   an input, or that another process is writing.
//! - A run that fills a folder of its own (`holo demo`) claims it as a
//!   [`RunFolder`]: new or empty, and emptied again (a new one removed) if
//!   the run fails or is interrupted; or an earlier run's, whose files are
//!   moved aside and put back if the run fails or is interrupted
//!   ([`RunFolder::take_over`]).

mod check;
mod claim;
mod fs;
mod interrupt;
mod naming;
mod set;
mod temporary;

use std::path::Path;

pub(crate) use check::regular_file;
pub use check::{check_output, check_set_output, same_file};
pub use claim::{take_notices, Claim};
pub(crate) use fs::special_kind;
pub use interrupt::{install_interrupt_cleanup, remove_temporaries};
pub use set::{check_set_complete, verify_set, FileSet, SetFile};
pub(crate) use set::{file_sha256, require_manifest};
pub use temporary::{AtomicFile, Spool};

use crate::error::Result;

/// A folder a run fills with its files, new or empty when the run began:
/// if the run fails (the `RunFolder` is dropped without
/// [`keep`](Self::keep)) or is interrupted by a signal
/// ([`install_interrupt_cleanup`]), a folder the run created is removed with
/// everything in it, and a folder that was empty is emptied again. So a run
/// that does not finish leaves nothing, and never touches a file it did not
/// write.
#[derive(Debug)]
pub struct RunFolder {
    id: Option<u64>,
    path: std::path::PathBuf,
    /// The folder claimed for this process while the run writes it.
    _claim: Claim,
}

impl RunFolder {
    /// Claim `path` for a run: created (with its parents) if missing; an
    /// existing folder must be empty, anything else is refused. A run that
    /// does not finish removes the parents it created too.
    pub fn claim(path: &Path) -> Result<RunFolder> {
        use crate::error::{Error, OutputProblem};
        let wrong =
            |what: &'static str| Error::Output { path: path.to_path_buf(), problem: OutputProblem::WrongKind(what) };
        let existed = match std::fs::metadata(path) {
            Ok(m) if !m.is_dir() => return Err(wrong("is a file; a folder is needed here")),
            Ok(_) => {
                let mut entries = std::fs::read_dir(path).map_err(|e| Error::io(path, e))?;
                if entries.next().is_some() {
                    return Err(wrong("holds files already; a new or empty folder is needed here"));
                }
                true
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => false,
            Err(e) => return Err(Error::io(path, e)),
        };
        // What the run makes: the folder and any missing parents, the
        // outermost of them removed again. Registered before it is made, so
        // a signal in between finds it.
        let id = interrupt::register_folder(match missing_folders(path).pop() {
            Some(outermost) => interrupt::Cleanup::Remove(outermost),
            None => interrupt::Cleanup::Empty(path.to_path_buf()),
        })?;
        let mut folder = RunFolder { id: Some(id), path: path.to_path_buf(), _claim: Claim::none() };
        if !existed {
            std::fs::create_dir_all(path).map_err(|e| Error::io(path, e))?;
        }
        folder._claim = claim_folder(path)?;
        Ok(folder)
    }

    /// Claim `path`, a folder an earlier run filled, for a new run: what
    /// of it is named `names` (the files and folders the run writes) is
    /// moved aside into a hidden folder in it. If the run does not finish
    /// (dropped without [`keep`](Self::keep), or interrupted by a signal),
    /// what it made under those names is removed and the earlier ones are
    /// put back, so the folder is as the earlier run left it; when it
    /// finishes, the earlier ones are removed. Nothing else in the folder is
    /// touched. What a run killed outright (SIGKILL) had moved aside is put
    /// back first.
    pub fn take_over(path: &Path, names: &[&str]) -> Result<RunFolder> {
        use crate::error::Error;
        let claim = claim_folder(path)?;
        let aside = path.join(PREVIOUS_RUN);
        if aside.is_dir() {
            interrupt::restore_aside(path, &aside, &[], &[]);
        }
        let names: Vec<String> = names.iter().map(|n| n.to_string()).collect();
        let present: Vec<String> =
            names.iter().filter(|n| std::fs::symlink_metadata(path.join(n)).is_ok()).cloned().collect();
        // Registered before anything moves, so a signal at any point puts
        // back what had moved.
        let id = interrupt::register_folder(interrupt::Cleanup::Restore {
            folder: path.to_path_buf(),
            aside: aside.clone(),
            names,
            present: present.clone(),
        })?;
        let folder = RunFolder { id: Some(id), path: path.to_path_buf(), _claim: claim };
        std::fs::create_dir(&aside).map_err(|e| Error::io(&aside, e))?;
        for name in &present {
            std::fs::rename(path.join(name), aside.join(name)).map_err(|e| Error::io(path.join(name), e))?;
        }
        fs::sync_folder(path)?;
        Ok(folder)
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The run succeeded: its files stay (and what an earlier run's were
    /// moved aside for is removed).
    pub fn keep(mut self) {
        if let Some(id) = self.id.take() {
            interrupt::forget_folder(id);
        }
        let aside = self.path.join(PREVIOUS_RUN);
        if aside.is_dir() {
            // Nothing useful can be done about an earlier run's files that
            // cannot be removed: they stay hidden, and the next run puts
            // them back before it begins.
            let _ = std::fs::remove_dir_all(&aside);
        }
    }
}

/// The hidden folder in an earlier run's folder where [`RunFolder::take_over`]
/// keeps its files while a new run writes.
const PREVIOUS_RUN: &str = ".holo-previous-run";

impl Drop for RunFolder {
    fn drop(&mut self) {
        if let Some(id) = self.id.take() {
            interrupt::remove_folder(id);
        }
    }
}

/// Claim the folder `path` for this process's run (another process
/// writing into it is refused): its lock ([`RUN_LOCK`]) in it.
fn claim_folder(path: &Path) -> Result<Claim> {
    Claim::take(claim::Scope::Folder(path, RUN_LOCK))
}

/// The name of a run folder's lock (`.holo-run.lock` in it), which a
/// failed run's emptying leaves to its claim.
pub(crate) const RUN_LOCK: &str = "holo-run";

/// The folders `create_dir_all(path)` would make: `path` and its missing
/// parents, innermost first (none when `path` exists).
fn missing_folders(path: &Path) -> Vec<std::path::PathBuf> {
    let mut missing = Vec::new();
    let mut at = Some(path);
    while let Some(folder) = at.filter(|f| !f.as_os_str().is_empty() && !f.exists()) {
        missing.push(folder.to_path_buf());
        at = folder.parent();
    }
    missing
}

/// Write a small file whole: `bytes` to a temporary beside `path`, synced and
/// renamed into place; an existing `path` is kept (and named in the error)
/// unless `overwrite`.
pub fn write_bytes_beside(path: &Path, bytes: &[u8], overwrite: bool) -> Result<()> {
    use std::io::Write;
    write_atomically(path, overwrite, |file| {
        file.write_all(bytes).map_err(|e| crate::error::Error::io(file.destination(), e))
    })?;
    Ok(())
}

/// Write `path` through `fill`, atomically: the bytes go to a temporary
/// beside it, which is synced and renamed into place only if `fill`
/// succeeds; an existing `path` is kept (and named in the error) unless
/// `overwrite`. Returns the file's size in bytes.
pub fn write_atomically(path: &Path, overwrite: bool, fill: impl FnOnce(&mut AtomicFile) -> Result<()>) -> Result<u64> {
    if !overwrite && path.exists() {
        return Err(crate::error::Error::Output {
            path: path.to_path_buf(),
            problem: crate::error::OutputProblem::Exists,
        });
    }
    let mut file = AtomicFile::create(path)?;
    fill(&mut file)?;
    file.commit(overwrite)
}

/// The folder a file is written in (`.` for a bare name).
pub(crate) fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_folder_is_removed_or_emptied_unless_kept_and_must_be_new_or_empty() {
        let dir = tempfile::tempdir().unwrap();
        let write = |folder: &Path| {
            std::fs::create_dir(folder.join("sub")).unwrap();
            std::fs::write(folder.join("sub/a.txt"), b"a").unwrap();
            write_bytes_beside(&folder.join("b.txt"), b"b", false).unwrap();
        };
        // New (with a missing parent): removed when the run fails.
        let new = dir.path().join("parent/new");
        let folder = RunFolder::claim(&new).unwrap();
        write(folder.path());
        drop(folder);
        assert!(!dir.path().join("parent").exists(), "the parent it made is gone too");
        assert!(dir.path().is_dir());
        // Empty: emptied again, the folder itself kept.
        let empty = dir.path().join("empty");
        std::fs::create_dir(&empty).unwrap();
        let folder = RunFolder::claim(&empty).unwrap();
        write(&empty);
        drop(folder);
        assert!(empty.is_dir() && std::fs::read_dir(&empty).unwrap().next().is_none());
        // Kept: the files stay, and the folder is no longer the run's.
        let folder = RunFolder::claim(&new).unwrap();
        write(&new);
        folder.keep();
        assert!(new.join("sub/a.txt").is_file() && new.join("b.txt").is_file());
        // A folder with files in it, or a file, is refused and left alone.
        for taken in [new.clone(), new.join("b.txt")] {
            let e = RunFolder::claim(&taken).unwrap_err();
            assert!(matches!(e, crate::error::Error::Output { ref path, .. } if *path == taken), "{e}");
        }
        assert!(new.join("sub/a.txt").is_file() && new.join("b.txt").is_file());
    }

    #[test]
    fn a_run_over_an_earlier_one_puts_the_earlier_files_back_unless_kept() {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("run");
        std::fs::create_dir_all(folder.join("sub")).unwrap();
        for (name, text) in [("sub/a.txt", "earlier a"), ("b.txt", "earlier b"), ("yours.txt", "yours")] {
            std::fs::write(folder.join(name), text).unwrap();
        }
        let read = |name: &str| std::fs::read_to_string(folder.join(name)).ok();
        let names = ["sub", "b.txt", "c.txt"];
        // Moved aside while the run writes; a run that fails leaves the
        // earlier files (and yours) as they were, and nothing of its own.
        let run = RunFolder::take_over(&folder, &names).unwrap();
        assert_eq!((read("sub/a.txt"), read("b.txt")), (None, None));
        std::fs::create_dir(folder.join("sub")).unwrap();
        write_bytes_beside(&folder.join("sub/a.txt"), b"new a", false).unwrap();
        write_bytes_beside(&folder.join("c.txt"), b"new c", false).unwrap();
        drop(run);
        assert_eq!(read("sub/a.txt").as_deref(), Some("earlier a"));
        assert_eq!(read("b.txt").as_deref(), Some("earlier b"));
        assert_eq!((read("c.txt"), read("yours.txt").as_deref()), (None, Some("yours")));
        // Kept: the run's files stay, the earlier ones are gone, yours stay.
        let run = RunFolder::take_over(&folder, &names).unwrap();
        write_bytes_beside(&folder.join("c.txt"), b"new c", false).unwrap();
        run.keep();
        assert_eq!((read("sub/a.txt"), read("b.txt")), (None, None));
        assert_eq!((read("c.txt").as_deref(), read("yours.txt").as_deref()), (Some("new c"), Some("yours")));
        let mut left: Vec<String> =
            std::fs::read_dir(&folder).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
        left.sort();
        assert_eq!(left, ["c.txt", "yours.txt"]);
        let beside: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(beside, ["run"]);
    }
}
