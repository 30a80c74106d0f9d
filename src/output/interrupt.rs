//! The registry of live temporaries, and what SIGINT, SIGTERM and SIGHUP do
//! with it.
//!
//! A temporary is registered in the same critical section that creates it,
//! and leaves the registry in the same critical section that renames or
//! removes it. The cleanup takes the lock, marks the registry interrupted,
//! removes every file still registered and exits the process with the lock
//! held: a rename either happened before the cleanup began (the file is in
//! place and no longer registered) or never happens.

use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::error::{Error, OutputProblem, Result};

struct Registry {
    next_id: u64,
    live: BTreeMap<u64, PathBuf>,
    /// Folders a run writes into, cleaned up after the files.
    folders: BTreeMap<u64, Cleanup>,
    /// The outputs' locks this process holds (lock file, open and locked),
    /// with how many claims share each.
    locks: BTreeMap<PathBuf, (usize, File)>,
    /// Set once the cleanup has begun: no temporary is created or renamed after.
    interrupted: bool,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    next_id: 0,
    live: BTreeMap::new(),
    folders: BTreeMap::new(),
    locks: BTreeMap::new(),
    interrupted: false,
});

/// The registry, whatever a panicking holder left: its map stays
/// consistent because every update is a single insert or remove.
fn registry() -> MutexGuard<'static, Registry> {
    REGISTRY.lock().unwrap_or_else(PoisonError::into_inner)
}

fn interrupted(destination: &Path) -> Error {
    Error::Output { path: destination.to_path_buf(), problem: OutputProblem::Interrupted }
}

/// Create a temporary with `make` and register it, both under the lock.
pub(super) fn create_registered(
    destination: &Path,
    make: impl FnOnce() -> Result<(PathBuf, File)>,
) -> Result<(u64, PathBuf, File)> {
    let mut registry = registry();
    if registry.interrupted {
        return Err(interrupted(destination));
    }
    let (path, file) = make()?;
    let id = registry.next_id;
    registry.next_id += 1;
    registry.live.insert(id, path.clone());
    Ok((id, path, file))
}

/// Remove a temporary and forget it.
pub(super) fn remove_registered(id: u64, path: &Path) {
    let mut registry = registry();
    if registry.live.remove(&id).is_some() {
        // Nothing useful can be done about a temporary that cannot be
        // removed while unwinding from another error; it stays hidden.
        let _ = std::fs::remove_file(path);
    }
}

/// Rename temporary `id` at `from` to `to` and forget it, under the lock;
/// refused once the cleanup has begun. Without `overwrite` an existing `to`
/// is kept and the rename refused.
pub(super) fn rename_registered(id: u64, from: &Path, to: &Path, overwrite: bool) -> Result<()> {
    let mut registry = registry();
    if registry.interrupted {
        return Err(interrupted(to));
    }
    if overwrite {
        // A FIFO, a device or a socket at `to` is never replaced: whatever
        // checked it before the work, it may have appeared since.
        if let Some(kind) = std::fs::symlink_metadata(to).ok().as_ref().and_then(super::fs::special_kind) {
            return Err(Error::Output {
                path: to.to_path_buf(),
                problem: OutputProblem::NotRegular { kind, wanted: "a regular file" },
            });
        }
        std::fs::rename(from, to).map_err(|e| Error::io(to, e))?;
    } else {
        // An atomic no-replace rename (renameat2 where the file system has
        // it, else link and unlink); a failed attempt leaves the temporary.
        tempfile::TempPath::try_from_path(from).map_err(|e| Error::io(from, e))?.persist_noclobber(to).map_err(
            |e| {
                let _ = e.path.keep();
                if e.error.kind() == std::io::ErrorKind::AlreadyExists {
                    Error::Output { path: to.to_path_buf(), problem: OutputProblem::Exists }
                } else {
                    Error::io(to, e.error)
                }
            },
        )?;
    }
    registry.live.remove(&id);
    Ok(())
}

/// Remove a file in place (one of a replaced set's), under the lock and only
/// before the cleanup has begun, so an interrupt never finds a set half
/// taken apart by a step it did not see. A file already gone is no error.
pub(super) fn remove_in_place(path: &Path) -> Result<()> {
    let registry = registry();
    if registry.interrupted {
        return Err(interrupted(path));
    }
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::io(path, e)),
        _ => Ok(()),
    }
}

/// Hold the lock file `path` for one more claim: taken with `take` (which
/// opens and locks it, or says who holds it) when this process does not
/// hold it yet. Returns whether it was taken now. Refused once the cleanup
/// has begun.
pub(super) fn take_lock(path: &Path, take: impl FnOnce() -> Result<File>) -> Result<bool> {
    let mut registry = registry();
    if registry.interrupted {
        return Err(interrupted(path));
    }
    if let Some((claims, _)) = registry.locks.get_mut(path) {
        *claims += 1;
        return Ok(false);
    }
    let file = take()?;
    registry.locks.insert(path.to_path_buf(), (1, file));
    Ok(true)
}

/// One claim of the lock file `path` fewer: the last removes the file, then
/// closes it (which releases the lock), so a process that opened it in
/// between finds its lock on a file no longer there and opens again.
pub(super) fn release_lock(path: &Path) {
    let mut registry = registry();
    let Some((claims, _)) = registry.locks.get_mut(path) else { return };
    *claims -= 1;
    if *claims == 0 {
        let _ = std::fs::remove_file(path);
        registry.locks.remove(path);
    }
}

/// What becomes of a registered folder when its run does not finish.
#[derive(Debug)]
pub(super) enum Cleanup {
    /// Removed with everything in it (a [`super::RunFolder`] it made).
    Remove(PathBuf),
    /// Emptied (a [`super::RunFolder`] that was empty).
    Empty(PathBuf),
    /// Each removed in turn while empty, innermost first (the folders a
    /// [`super::FileSet`] made: its own and missing parents).
    RemoveEmpty(Vec<PathBuf>),
    /// An earlier run's files put back ([`super::RunFolder::take_over`]):
    /// of `names` in `folder`, those the earlier run had (`present`) come
    /// back from `aside`, the others are removed.
    Restore {
        /// The run's folder.
        folder: PathBuf,
        /// Where the earlier run's files were moved.
        aside: PathBuf,
        /// What the run writes.
        names: Vec<String>,
        /// What of it the earlier run had.
        present: Vec<String>,
    },
}

/// Register a folder a run writes into, under the lock; refused once the
/// cleanup has begun.
pub(super) fn register_folder(cleanup: Cleanup) -> Result<u64> {
    let mut registry = registry();
    if registry.interrupted {
        let path = match &cleanup {
            Cleanup::Remove(p) | Cleanup::Empty(p) => p.as_path(),
            Cleanup::RemoveEmpty(p) => p.first().map_or(Path::new("."), |p| p.as_path()),
            Cleanup::Restore { folder, .. } => folder.as_path(),
        };
        return Err(interrupted(path));
    }
    let id = registry.next_id;
    registry.next_id += 1;
    registry.folders.insert(id, cleanup);
    Ok(id)
}

/// Forget folder `id`: the run that wrote it succeeded.
pub(super) fn forget_folder(id: u64) {
    registry().folders.remove(&id);
}

/// Remove folder `id` (or what is in it) and forget it: the run failed.
pub(super) fn remove_folder(id: u64) {
    let mut registry = registry();
    if let Some(cleanup) = registry.folders.remove(&id) {
        clean_up(&cleanup);
    }
}

/// Do `cleanup`. Nothing useful can be done about an entry that cannot be
/// removed while another error is reported or the process exits on a
/// signal.
fn clean_up(cleanup: &Cleanup) {
    match cleanup {
        Cleanup::Remove(path) => {
            let _ = std::fs::remove_dir_all(path);
        }
        Cleanup::Empty(path) => {
            // The run's own lock goes with its claim, which is still held.
            let lock = format!(".{}.lock", super::RUN_LOCK);
            for entry in std::fs::read_dir(path).into_iter().flatten().flatten().filter(|e| e.file_name() != *lock) {
                let p = entry.path();
                let _ = if entry.file_type().is_ok_and(|t| t.is_dir()) {
                    std::fs::remove_dir_all(&p)
                } else {
                    std::fs::remove_file(&p)
                };
            }
        }
        // Stops at the first that is not empty (or not there).
        Cleanup::RemoveEmpty(folders) => {
            let _ = folders.iter().try_for_each(std::fs::remove_dir);
        }
        Cleanup::Restore { folder, aside, names, present } => restore_aside(folder, aside, names, present),
    }
}

/// Put back what [`super::RunFolder::take_over`] moved from `folder` into
/// `aside`: each entry of `aside` replaces what the run made under its name,
/// and what the run made under the other `names` that the earlier run did
/// not have (`present`) is removed; then `aside` goes. (With `names` empty,
/// only the entries of `aside` come back: an aside left by a run killed
/// outright, which said nothing of what it had.)
pub(super) fn restore_aside(folder: &Path, aside: &Path, names: &[String], present: &[String]) {
    let remove = |p: &Path| {
        let _ = match std::fs::symlink_metadata(p) {
            Ok(m) if m.is_dir() => std::fs::remove_dir_all(p),
            Ok(_) => std::fs::remove_file(p),
            Err(_) => Ok(()),
        };
    };
    for name in names {
        let was_aside = aside.join(name).exists();
        // Not moved yet (the run stopped while moving): still the earlier run's.
        if was_aside || !present.contains(name) {
            remove(&folder.join(name));
        }
    }
    for entry in std::fs::read_dir(aside).into_iter().flatten().flatten() {
        let to = folder.join(entry.file_name());
        remove(&to);
        let _ = std::fs::rename(entry.path(), &to);
    }
    let _ = std::fs::remove_dir_all(aside);
    let _ = super::fs::sync_folder(folder);
}

/// Remove every registered temporary (and what the unfinished runs wrote
/// into their [`super::RunFolder`]s) now and refuse to create or rename any
/// from here on. For a program that handles signals itself and is about to
/// exit; [`install_interrupt_cleanup`] calls it. Returns how many files were
/// removed.
pub fn remove_temporaries() -> usize {
    let mut registry = registry();
    remove_all(&mut registry)
}

fn remove_all(registry: &mut Registry) -> usize {
    registry.interrupted = true;
    let live = std::mem::take(&mut registry.live);
    let removed = live.values().filter(|path| std::fs::remove_file(path).is_ok()).count();
    // The locks before the folders, so a folder they are in can be empty;
    // each removed before it is closed (see `release_lock`). Nothing is put
    // in place from here on, so no output needs them any more.
    for path in std::mem::take(&mut registry.locks).into_keys() {
        let _ = std::fs::remove_file(path);
    }
    for cleanup in std::mem::take(&mut registry.folders).into_values() {
        clean_up(&cleanup);
    }
    removed
}

/// On SIGINT, SIGTERM or SIGHUP: remove every temporary file and spool this
/// process has open (and what unfinished runs wrote into their
/// [`super::RunFolder`]s), leave every existing file as it was, and exit with
/// 128 + the signal's number (130, 143, 129). A dedicated thread waits for
/// the signals; calling this again does nothing. A program that does not
/// call it keeps the default behaviour of these signals.
pub fn install_interrupt_cleanup() -> std::io::Result<()> {
    static INSTALLED: Mutex<bool> = Mutex::new(false);
    let mut installed = INSTALLED.lock().unwrap_or_else(PoisonError::into_inner);
    if *installed {
        return Ok(());
    }
    use signal_hook::consts::signal::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::Builder::new().name("holo-interrupt".into()).spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let mut registry = registry();
            remove_all(&mut registry);
            // Exit with the lock held, so no other thread renames a file in
            // place between the cleanup and the end of the process.
            std::process::exit(128 + signal);
        }
    })?;
    *installed = true;
    Ok(())
}
