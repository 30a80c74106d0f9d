//! Multi-file outputs as sets: every file is written as a temporary first;
//! only when all are complete is the old manifest removed, the new files
//! renamed into place, the files of the previous set that the new one does
//! not have removed, and the new manifest, listing every file with its size
//! and SHA-256, put in place last. A folder whose manifest is missing or
//! disagrees with its files is refused by [`verify_set`].

use std::collections::BTreeSet;
use std::fs::File;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::claim::{Claim, Scope};
use super::fs::sync_folder;
use super::interrupt::{forget_folder, register_folder, remove_folder, remove_in_place, Cleanup};
use super::temporary::{AtomicFile, ClosedFile};
use crate::error::{Error, OutputProblem, Result, SetProblem};

/// One file of a set, as its manifest lists it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SetFile {
    /// File name, relative to the set's folder.
    pub name: String,
    /// Size in bytes.
    pub bytes: u64,
    /// SHA-256 of the bytes, 64 lower-case hex digits.
    pub sha256: String,
}

/// A set of files being written into one folder (see the module docs).
/// Dropped without [`commit`](Self::commit), its temporaries are removed,
/// the folder is as it was, and the folders it created (the set's and any
/// missing parents) are removed while empty.
#[derive(Debug)]
pub struct FileSet {
    folder: PathBuf,
    manifest: String,
    /// The files written, each closed in its temporary until the commit.
    pending: Vec<(SetFile, ClosedFile)>,
    /// The folders `create` made (the set's folder and missing parents),
    /// registered to be removed again, while empty, if the set is dropped
    /// or the process interrupted before the commit.
    created: Option<u64>,
    /// The folder claimed for this process until the set is in place.
    claim: Option<Claim>,
}

/// Whether `name` is a plain file name: no folder part, not hidden.
fn plain_name(name: &str) -> bool {
    !name.is_empty()
        && !name.starts_with('.')
        && Path::new(name).file_name().is_some_and(|n| n == name)
        && !name.contains(['/', '\\'])
}

impl FileSet {
    /// A set to be written into `folder` (created, with its parents, if
    /// missing) under the manifest name `manifest`. Call it once the inputs
    /// are open and checked, so a refused input leaves no folder behind.
    /// Another process writing a set into the same folder is refused (see
    /// [`super::check_set_output`]).
    pub fn create(folder: &Path, manifest: &str) -> Result<FileSet> {
        let created = super::missing_folders(folder);
        // Registered before they are made, so a signal in between finds them.
        let created = if created.is_empty() { None } else { Some(register_folder(Cleanup::RemoveEmpty(created))?) };
        let mut set = FileSet {
            folder: folder.to_path_buf(),
            manifest: manifest.to_string(),
            pending: vec![],
            created,
            claim: None,
        };
        std::fs::create_dir_all(folder).map_err(|e| Error::io(folder, e))?;
        // Claimed once it is there (before anything is written into it).
        set.claim = Some(Claim::take(Scope::Folder(folder, manifest))?);
        Ok(set)
    }

    /// The folder.
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// Write file `name` of the set with `fill`, as a temporary until the commit.
    pub fn add(&mut self, name: &str, fill: impl FnOnce(&mut AtomicFile) -> Result<()>) -> Result<&SetFile> {
        if !plain_name(name) || name == self.manifest || self.pending.iter().any(|(f, _)| f.name == name) {
            return Err(Error::argument(
                "file name",
                format!(
                    "{}: {name:?} cannot be a file of this set (a plain, unique name is needed)",
                    self.folder.display()
                ),
            ));
        }
        let mut file = AtomicFile::create_claimed(&self.folder.join(name), None)?;
        fill(&mut file)?;
        let (file, bytes) = file.close()?;
        let sha256 = file_sha256(file.temporary_path())?;
        self.pending.push((SetFile { name: name.to_string(), bytes, sha256 }, file));
        Ok(&self.pending[self.pending.len() - 1].0)
    }

    /// Write file `name` of the set whole from `bytes`.
    pub fn add_bytes(&mut self, name: &str, bytes: &[u8]) -> Result<&SetFile> {
        self.add(name, |file| file.write_all(bytes).map_err(|e| Error::io(file.destination(), e)))
    }

    /// The files written so far, in order.
    pub fn files(&self) -> Vec<SetFile> {
        self.pending.iter().map(|(f, _)| f.clone()).collect()
    }

    /// Put the set in place: its manifest is `manifest(files)`, which must
    /// list the files it is given. An existing set (or any file of this one)
    /// is replaced only when `overwrite`; files of the previous set that
    /// this one does not have are removed, and no other file is touched.
    /// Returns every file's path, the manifest last.
    pub fn commit(
        mut self,
        overwrite: bool,
        manifest: impl FnOnce(&[SetFile]) -> Result<Vec<u8>>,
    ) -> Result<Vec<PathBuf>> {
        let manifest_path = self.folder.join(&self.manifest);
        let pending = std::mem::take(&mut self.pending);
        let (files, temporaries): (Vec<SetFile>, Vec<ClosedFile>) = pending.into_iter().unzip();
        if !overwrite {
            if manifest_path.exists() {
                return Err(Error::Output {
                    path: self.folder.clone(),
                    problem: OutputProblem::SetExists(self.manifest.clone()),
                });
            }
            if let Some(existing) = files.iter().map(|f| self.folder.join(&f.name)).find(|p| p.exists()) {
                return Err(Error::Output { path: existing, problem: OutputProblem::Exists });
            }
        }
        let mut new_manifest = AtomicFile::create_claimed(&manifest_path, None)?;
        new_manifest.write_all(&manifest(&files)?).map_err(|e| Error::io(new_manifest.destination(), e))?;
        new_manifest.finish()?;
        let previous = previous_names(&manifest_path, &self.manifest);
        // From here until the new manifest is in place the folder may hold
        // files of two sets; the marker says so to every reader, even one
        // that would read the files without a manifest. Interrupted, it stays.
        let marker = mark_incomplete(&self.folder, &self.manifest)?;
        remove_in_place(&manifest_path)?;
        sync_folder(&self.folder)?;
        let mut placed: Vec<PathBuf> = Vec::new();
        for file in temporaries {
            let destination = file.destination().to_path_buf();
            if let Err(e) = file.rename_into_place(overwrite) {
                // Not replacing, every file put in place was new: taken
                // out again, the folder holds no file of this set.
                if !overwrite {
                    placed.iter().for_each(|p| drop(remove_in_place(p)));
                    let _ = remove_in_place(&marker);
                }
                return Err(e);
            }
            placed.push(destination);
        }
        let kept: BTreeSet<&str> = files.iter().map(|f| f.name.as_str()).collect();
        for name in previous.iter().filter(|n| !kept.contains(n.as_str())) {
            let path = self.folder.join(name);
            if std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
                remove_in_place(&path)?;
            }
        }
        new_manifest.rename_into_place(overwrite)?;
        sync_folder(&self.folder)?;
        remove_in_place(&marker)?;
        sync_folder(&self.folder)?;
        if let Some(id) = self.created.take() {
            forget_folder(id);
        }
        let mut paths: Vec<PathBuf> = files.iter().map(|f| self.folder.join(&f.name)).collect();
        paths.push(manifest_path);
        Ok(paths)
    }
}

impl Drop for FileSet {
    fn drop(&mut self) {
        // Temporaries and the lock first, so the folder can be empty.
        self.pending.clear();
        self.claim.take();
        // Fails, as it should, when anything else is in the folder.
        if let Some(id) = self.created.take() {
            remove_folder(id);
        }
    }
}

/// The SHA-256 of a file's bytes as 64 lower-case hex digits.
pub(crate) fn file_sha256(path: &Path) -> Result<String> {
    let at = |e| Error::io(path, e);
    let mut file = File::open(path).map_err(at)?;
    let mut hasher = Sha256::new();
    let mut buffer = vec![0u8; 1 << 20];
    loop {
        let n = file.read(&mut buffer).map_err(at)?;
        if n == 0 {
            break;
        }
        hasher.update(&buffer[..n]);
    }
    Ok(hasher.finalize().iter().map(|b| format!("{b:02x}")).collect())
}

/// The file names an existing manifest lists: every string, or object's
/// `name`, in any array called `files` (manifests written before they
/// listed digests kept their names in such arrays too). Only plain names
/// other than the manifest's own count; an unreadable manifest lists none.
fn previous_names(manifest_path: &Path, manifest: &str) -> Vec<String> {
    fn walk(value: &serde_json::Value, under_files: bool, out: &mut Vec<String>) {
        match value {
            serde_json::Value::Array(items) => items.iter().for_each(|v| walk(v, under_files, out)),
            serde_json::Value::String(s) if under_files => out.push(s.clone()),
            serde_json::Value::Object(map) => {
                if let (true, Some(serde_json::Value::String(name))) = (under_files, map.get("name")) {
                    out.push(name.clone());
                }
                map.iter().for_each(|(k, v)| walk(v, k == "files", out));
            }
            _ => {}
        }
    }
    let Ok(text) = std::fs::read_to_string(manifest_path) else { return vec![] };
    let Ok(value) = serde_json::from_str::<serde_json::Value>(&text) else { return vec![] };
    let mut names = Vec::new();
    walk(&value, false, &mut names);
    names.retain(|n| plain_name(n) && n != manifest);
    names
}

/// Check the set in `folder` against the files its manifest (named
/// `manifest`, for messages) lists: each a plain name, present, with the
/// listed size and SHA-256. The first disagreement is the error, naming the
/// file. An empty list is refused with `remedy` (how to make the set again).
pub fn verify_set(folder: &Path, manifest: &str, files: &[SetFile], remedy: &'static str) -> Result<()> {
    check_set_complete(folder, manifest, remedy)?;
    let manifest_path = folder.join(manifest);
    if files.is_empty() {
        return Err(Error::Set { path: manifest_path, problem: SetProblem::NoFileList { remedy } });
    }
    for file in files {
        if !plain_name(&file.name) || file.name == manifest {
            return Err(Error::Set { path: manifest_path, problem: SetProblem::BadName(file.name.clone()) });
        }
        let path = folder.join(&file.name);
        let set_error = |problem| Error::Set { path: path.clone(), problem };
        let found = match std::fs::metadata(&path) {
            Ok(m) if m.is_file() => m.len(),
            Ok(_) => return Err(set_error(SetProblem::Missing(manifest.to_string()))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(set_error(SetProblem::Missing(manifest.to_string())))
            }
            Err(e) => return Err(Error::io(&path, e)),
        };
        if found != file.bytes {
            return Err(set_error(SetProblem::Size { manifest: manifest.to_string(), listed: file.bytes, found }));
        }
        if file_sha256(&path)? != file.sha256 {
            return Err(set_error(SetProblem::Digest(manifest.to_string())));
        }
    }
    Ok(())
}

/// The marker of a set being replaced: `.MANIFEST.incomplete` beside it.
fn incomplete_marker(folder: &Path, manifest: &str) -> PathBuf {
    folder.join(format!(".{manifest}.incomplete"))
}

/// Put the marker of a set being replaced in place (synced, so it is there
/// before any file of the old set is touched).
fn mark_incomplete(folder: &Path, manifest: &str) -> Result<PathBuf> {
    let path = incomplete_marker(folder, manifest);
    let mut marker = AtomicFile::create_claimed(&path, None)?;
    marker
        .write_all(b"a set of files is being replaced here; if this file remains, the replacement was interrupted\n")
        .map_err(|e| Error::io(marker.destination(), e))?;
    marker.finish()?;
    marker.rename_into_place(true)?;
    sync_folder(folder)?;
    Ok(path)
}

/// Whether the set with manifest `manifest` in `folder` was left half
/// replaced by an interrupted [`FileSet::commit`]: an error naming the
/// folder, with `remedy`, when it was. Every reader of the folder's files
/// asks, with a manifest or without one.
pub fn check_set_complete(folder: &Path, manifest: &str, remedy: &'static str) -> Result<()> {
    if incomplete_marker(folder, manifest).exists() {
        return Err(Error::Set { path: folder.to_path_buf(), problem: SetProblem::Interrupted { remedy } });
    }
    Ok(())
}

/// Whether `folder` holds a manifest called `manifest`; an error naming
/// the folder when it does not.
pub(crate) fn require_manifest(folder: &Path, manifest: &str) -> Result<PathBuf> {
    let path = folder.join(manifest);
    if path.is_file() {
        Ok(path)
    } else {
        Err(Error::Set { path: folder.to_path_buf(), problem: SetProblem::NoManifest(manifest.to_string()) })
    }
}
