//! The checks on an output that can fail before any work: a command calls
//! them first, so a refusal costs nothing.

use std::path::Path;

use super::folder_of;
use crate::{Error, OutputProblem, Result};

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

/// Whether the file `output` can be written, found before any work: its
/// folder exists, it is not a folder, it is none of `inputs` (refused even
/// when `overwrite`: the input would be gone before it was read), and it
/// does not exist unless `overwrite`.
pub fn check_output(output: &Path, inputs: &[&Path], overwrite: bool) -> Result<()> {
    let folder = folder_of(output);
    if !folder.is_dir() {
        return Err(refuse(output, OutputProblem::FolderMissing(folder.to_path_buf())));
    }
    if output.is_dir() {
        return Err(refuse(output, OutputProblem::WrongKind("is a folder; the output is a file")));
    }
    not_an_input(output, inputs)?;
    if !overwrite && output.exists() {
        return Err(refuse(output, OutputProblem::Exists));
    }
    Ok(())
}

/// Whether the set of files `names` with manifest `manifest` can be written
/// into `folder` (created later if missing), found before any work: the
/// folder is not a file, no file of the set is one of `inputs` or a
/// folder, and, unless `overwrite`, the folder holds no set (no manifest)
/// and none of the files.
pub fn check_set_output(
    folder: &Path,
    manifest: &str,
    names: &[String],
    inputs: &[&Path],
    overwrite: bool,
) -> Result<()> {
    if folder.exists() && !folder.is_dir() {
        return Err(refuse(folder, OutputProblem::WrongKind("is a file; the output is a folder")));
    }
    for name in names.iter().map(String::as_str).chain([manifest]) {
        let path = folder.join(name);
        if path.is_dir() {
            return Err(refuse(&path, OutputProblem::WrongKind("is a folder; the output is a file")));
        }
        not_an_input(&path, inputs)?;
    }
    if overwrite {
        return Ok(());
    }
    if folder.join(manifest).exists() {
        return Err(refuse(folder, OutputProblem::SetExists(manifest.to_string())));
    }
    match names.iter().map(|n| folder.join(n)).find(|p| p.exists()) {
        Some(path) => Err(refuse(&path, OutputProblem::Exists)),
        None => Ok(()),
    }
}
