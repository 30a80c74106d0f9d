//! Temporary files beside their destination: created and removed through the
//! process-wide registry, so an interrupt can remove them, and put in place
//! by a rename that the interrupt cannot race.

use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use super::claim::{Claim, Scope};
use super::folder_of;
use super::fs::sync_folder;
use super::interrupt;
use super::naming::{stem_of, temporary_prefix};
use crate::error::{Error, Result};

/// Bytes gathered before a write reaches the operating system.
const BUFFER_BYTES: usize = 1 << 20;

/// A registered temporary file: removed when dropped unless it was renamed
/// into place.
#[derive(Debug)]
struct Temporary {
    path: PathBuf,
    /// The registry's key; `None` once renamed into place.
    id: Option<u64>,
}

impl Temporary {
    /// A new hidden file `.NAME.PID.XXXXXX{suffix}` beside `destination`
    /// (`NAME` shortened when the name leaves too little room, see
    /// [`super::naming`]), registered before anything can interrupt between
    /// its creation and its registration.
    fn create(destination: &Path, suffix: &str) -> Result<(Temporary, File)> {
        let folder = folder_of(destination);
        let prefix = temporary_prefix(&stem_of(destination));
        let (id, path, file) = interrupt::create_registered(destination, || {
            let mut builder = tempfile::Builder::new();
            builder.prefix(&prefix).suffix(suffix);
            // tempfile creates 0600 files; an output gets the usual 0666 less the umask.
            #[cfg(unix)]
            builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
            let (file, path) = builder.tempfile_in(folder).map_err(|e| Error::io(folder, e))?.into_parts();
            // From here on the registry, not tempfile, decides when the file goes.
            let path = path.keep().map_err(|e| Error::io(folder, e.error))?;
            Ok((path, file))
        })?;
        Ok((Temporary { path, id: Some(id) }, file))
    }
}

impl Temporary {
    /// Rename it to `destination` (refused when that exists, unless
    /// `overwrite`); a failed rename leaves it registered, to be removed
    /// when it is dropped. The folder is not synced.
    fn rename_into_place(&mut self, destination: &Path, overwrite: bool) -> Result<()> {
        let id = self.id.take().expect("a temporary is renamed once");
        let renamed = interrupt::rename_registered(id, &self.path, destination, overwrite);
        if renamed.is_err() {
            // Still ours: dropping it removes it.
            self.id = Some(id);
        }
        renamed
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if let Some(id) = self.id.take() {
            interrupt::remove_registered(id, &self.path);
        }
    }
}

/// A file being written: bytes go to a hidden temporary beside the
/// destination (`.NAME.PID.XXXXXX.partial`), and [`commit`](Self::commit) puts
/// it in place whole. Dropped without a commit, the temporary is removed and
/// the destination is untouched.
#[derive(Debug)]
pub struct AtomicFile {
    destination: PathBuf,
    out: BufWriter<File>,
    temp: Temporary,
    /// The destination claimed for this process until the file is in place
    /// (`None` for a file of a set, whose folder is claimed).
    _claim: Option<Claim>,
}

impl AtomicFile {
    /// Start writing `destination`, claimed for this process (another
    /// process writing it is refused; see [`super::check_output`]). Whether
    /// it may be replaced is decided at [`commit`](Self::commit).
    pub fn create(destination: impl AsRef<Path>) -> Result<AtomicFile> {
        let destination = destination.as_ref();
        let claim = Claim::take(Scope::File(destination))?;
        Self::create_claimed(destination, Some(claim))
    }

    /// [`AtomicFile::create`] for a file whose claim is held elsewhere (a
    /// file of a set: the set's folder is claimed).
    pub(super) fn create_claimed(destination: &Path, claim: Option<Claim>) -> Result<AtomicFile> {
        let (temp, file) = Temporary::create(destination, ".partial")?;
        Ok(AtomicFile {
            destination: destination.to_path_buf(),
            out: BufWriter::with_capacity(BUFFER_BYTES, file),
            temp,
            _claim: claim,
        })
    }

    /// Where the file goes.
    pub fn destination(&self) -> &Path {
        &self.destination
    }

    /// Where its bytes are until the commit.
    pub fn temporary_path(&self) -> &Path {
        &self.temp.path
    }

    /// Flush and sync the temporary; its size in bytes.
    pub(crate) fn finish(&mut self) -> Result<u64> {
        let at = |e| Error::io(&self.destination, e);
        self.out.flush().map_err(at)?;
        let file = self.out.get_ref();
        file.sync_all().map_err(at)?;
        Ok(file.metadata().map_err(at)?.len())
    }

    /// Rename the finished temporary to the destination (refused when the
    /// destination exists, unless `overwrite`). The folder is not synced.
    pub(crate) fn rename_into_place(mut self, overwrite: bool) -> Result<()> {
        self.temp.rename_into_place(&self.destination, overwrite)
    }

    /// Flush and sync the temporary, then close it: its file and buffer
    /// are let go while it waits to be put in place, so a set of more files
    /// than the process may hold open (a folder of hogels: tens of
    /// thousands) can be written. Returns it closed, and its size in bytes.
    pub(crate) fn close(mut self) -> Result<(ClosedFile, u64)> {
        let bytes = self.finish()?;
        let AtomicFile { destination, out, temp, _claim } = self;
        drop(out);
        Ok((ClosedFile { destination, temp }, bytes))
    }

    /// Flush, sync, rename into place and sync the folder: the file is
    /// whole at the destination, or the destination is as it was. An
    /// existing destination is replaced only when `overwrite`. Returns the
    /// file's size in bytes.
    pub fn commit(mut self, overwrite: bool) -> Result<u64> {
        let bytes = self.finish()?;
        let destination = self.destination.clone();
        self.rename_into_place(overwrite)?;
        sync_folder(folder_of(&destination))?;
        Ok(bytes)
    }
}

/// A finished [`AtomicFile`], closed ([`AtomicFile::close`]): its bytes are
/// synced in its temporary, which is removed when it is dropped unless it
/// was put in place.
#[derive(Debug)]
pub(crate) struct ClosedFile {
    destination: PathBuf,
    temp: Temporary,
}

impl ClosedFile {
    /// Where the file goes.
    pub(crate) fn destination(&self) -> &Path {
        &self.destination
    }

    /// Where its bytes are until it is put in place.
    pub(crate) fn temporary_path(&self) -> &Path {
        &self.temp.path
    }

    /// [`AtomicFile::rename_into_place`].
    pub(crate) fn rename_into_place(mut self, overwrite: bool) -> Result<()> {
        self.temp.rename_into_place(&self.destination, overwrite)
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.out.write(buf)
    }
    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        self.out.write_all(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

impl Seek for AtomicFile {
    fn seek(&mut self, position: SeekFrom) -> std::io::Result<u64> {
        self.out.seek(position)
    }
}

/// A scratch file beside an output (`.NAME.PID.XXXXXX.spool`) that is never put
/// in place: removed when dropped, or by the interrupt cleanup.
#[derive(Debug)]
pub struct Spool {
    file: File,
    temp: Temporary,
}

impl Spool {
    /// A new empty scratch file beside `destination`, open for reading and writing.
    pub fn create(destination: impl AsRef<Path>) -> Result<Spool> {
        let (temp, file) = Temporary::create(destination.as_ref(), ".spool")?;
        Ok(Spool { file, temp })
    }

    /// Its path.
    pub fn path(&self) -> &Path {
        &self.temp.path
    }

    /// The open file.
    pub fn file(&self) -> &File {
        &self.file
    }
}
