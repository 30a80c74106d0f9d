//! The checks on an output that can fail before any work: a command calls
//! them first, so a refusal costs nothing, and keeps the [`Claim`] they
//! return until its output is in place.

use std::path::Path;

use super::claim::{Claim, Scope};
use super::folder_of;
use super::fs::special_kind;
use super::naming::name_max;
use crate::error::{Error, OutputProblem, Result};

fn refuse(path: &Path, problem: OutputProblem) -> Error {
    Error::Output { path: path.to_path_buf(), problem }
}

/// Whether `a` and `b` are the same file: the same device and inode (so a
/// symbolic or hard link to a file is that file), or, where there are no
/// inodes, the same canonical path. A path that does not exist is no file.
pub fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
    }
}

fn not_an_input(output: &Path, inputs: &[&Path]) -> Result<()> {
    match inputs.iter().find(|input| same_file(output, input)) {
        Some(input) => Err(refuse(output, OutputProblem::IsAnInput(input.to_path_buf()))),
        None => Ok(()),
    }
}

/// Whether `path` (followed through links) is a regular file an input can
/// be read from: a phrase saying what it is when it is something else (a
/// FIFO, whose opening would wait for a writer, a device, a folder). A path
/// that is not there passes: opening it says so.
pub(crate) fn regular_file(path: &Path) -> std::result::Result<(), String> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => Err(format!("not a regular file ({})", special_kind(&m).unwrap_or("a folder"))),
        _ => Ok(()),
    }
}

/// Refuse `path` when it exists (following links) as something a file
/// cannot be written over: a FIFO, a device, a socket.
fn not_special(path: &Path, wanted: &'static str) -> Result<()> {
    match std::fs::metadata(path).ok().as_ref().and_then(special_kind) {
        Some(kind) => Err(refuse(path, OutputProblem::NotRegular { kind, wanted })),
        None => Ok(()),
    }
}

/// Refuse `path` when its name is longer than the file system holding
/// `folder` takes.
fn name_fits(path: &Path, folder: &Path) -> Result<()> {
    let Some(name) = path.file_name() else { return Ok(()) };
    let (bytes, limit) = (name.len(), name_max(folder));
    if bytes > limit {
        return Err(refuse(path, OutputProblem::NameTooLong { bytes, limit }));
    }
    Ok(())
}

/// Whether the file `output` can be written, found before any work: its
/// folder exists, its name fits the file system, it is not a folder nor
/// anything but a regular file (a FIFO, a device), it is none of `inputs`
/// (refused even when `overwrite`: the input would be gone before it was
/// read), it does not exist unless `overwrite`, and no other process is
/// writing it. The returned [`Claim`] keeps other processes from writing it
/// until it is dropped: hold it until the output is in place.
pub fn check_output(output: &Path, inputs: &[&Path], overwrite: bool) -> Result<Claim> {
    let folder = folder_of(output);
    if !folder.is_dir() {
        return Err(refuse(output, OutputProblem::FolderMissing(folder.to_path_buf())));
    }
    name_fits(output, folder)?;
    if output.is_dir() {
        return Err(refuse(output, OutputProblem::WrongKind("is a folder; the output is a file")));
    }
    not_special(output, "a regular file")?;
    not_an_input(output, inputs)?;
    if !overwrite && output.exists() {
        return Err(refuse(output, OutputProblem::Exists));
    }
    Claim::take(Scope::File(output))
}

/// Whether the set of files `names` with manifest `manifest` can be written
/// into `folder` (created later if missing), found before any work: the
/// folder is not a file, every name fits the file system, no file of the
/// set is one of `inputs`, a folder or anything but a regular file, unless
/// `overwrite` the folder holds no set (no manifest) and none of the
/// files, and no other process is writing a set there. The returned
/// [`Claim`] keeps other processes from writing the set until it is
/// dropped (a folder still to be made is claimed by
/// [`super::FileSet::create`], once made).
pub fn check_set_output(
    folder: &Path,
    manifest: &str,
    names: &[String],
    inputs: &[&Path],
    overwrite: bool,
) -> Result<Claim> {
    let parent = folder_of(folder);
    if parent.is_dir() {
        name_fits(folder, parent)?;
    }
    if folder.exists() && !folder.is_dir() {
        not_special(folder, "a folder")?;
        return Err(refuse(folder, OutputProblem::WrongKind("is a file; the output is a folder")));
    }
    let names_at = if folder.is_dir() { folder } else { parent };
    for name in names.iter().map(String::as_str).chain([manifest]) {
        let path = folder.join(name);
        if parent.is_dir() {
            name_fits(&path, names_at)?;
        }
        if path.is_dir() {
            return Err(refuse(&path, OutputProblem::WrongKind("is a folder; the output is a file")));
        }
        not_special(&path, "a regular file")?;
        not_an_input(&path, inputs)?;
    }
    if !overwrite {
        if folder.join(manifest).exists() {
            return Err(refuse(folder, OutputProblem::SetExists(manifest.to_string())));
        }
        if let Some(path) = names.iter().map(|n| folder.join(n)).find(|p| p.exists()) {
            return Err(refuse(&path, OutputProblem::Exists));
        }
    }
    if folder.is_dir() {
        Claim::take(Scope::Folder(folder, manifest))
    } else {
        Ok(Claim::none())
    }
}
