//! How holo writes files: one discipline for every output.
//!
//! - Every file goes to a hidden temporary beside its destination
//!   (`.NAME.XXXXXX.partial`; a scratch file is `.NAME.XXXXXX.spool`), is
//!   flushed and synced, then renamed into place (never over an existing
//!   file unless replacing was asked), and the folder is synced:
//!   [`AtomicFile`], [`write_bytes_beside`]. Nothing is ever truncated under
//!   its final name; a temporary dropped without being put in place is
//!   removed.
//! - Every temporary is in a process-wide registry from its creation until
//!   it is renamed or removed. [`install_interrupt_cleanup`] makes SIGINT,
//!   SIGTERM and SIGHUP remove them all, leave every previous file as it
//!   was and exit with 128 + the signal (130, 143, 129).
//! - A multi-file output is a [`FileSet`]: all its files are written as
//!   temporaries first, then put in place together, and its manifest, which
//!   lists every file with its size and SHA-256, is written last.
//!   [`verify_set`] is what a reader of a set calls first.
//! - [`check_output`] and [`check_set_output`] find, before any work, an
//!   output that exists, whose folder is missing, or that is an input.

mod check;
mod interrupt;
mod set;
mod temporary;

use std::path::Path;

pub use check::{check_output, check_set_output, same_file};
pub use interrupt::{install_interrupt_cleanup, remove_temporaries};
pub use set::{check_set_complete, verify_set, FileSet, SetFile};
pub(crate) use set::{file_sha256, require_manifest};
pub use temporary::{AtomicFile, Spool};

use crate::Result;

/// Write a small file whole: `bytes` to a temporary beside `path`, synced and
/// renamed into place; an existing `path` is kept (and named in the error)
/// unless `overwrite`.
pub fn write_bytes_beside(path: &Path, bytes: &[u8], overwrite: bool) -> Result<()> {
    use std::io::Write;
    write_atomically(path, overwrite, |file| {
        file.write_all(bytes).map_err(|e| crate::Error::io(file.destination(), e))
    })?;
    Ok(())
}

/// Write `path` through `fill`, atomically: the bytes go to a temporary
/// beside it, which is synced and renamed into place only if `fill`
/// succeeds; an existing `path` is kept (and named in the error) unless
/// `overwrite`. Returns the file's size in bytes.
pub fn write_atomically(path: &Path, overwrite: bool, fill: impl FnOnce(&mut AtomicFile) -> Result<()>) -> Result<u64> {
    if !overwrite && path.exists() {
        return Err(crate::Error::Output { path: path.to_path_buf(), problem: crate::OutputProblem::Exists });
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
