//! What the writers need of the file system beneath them: what kind of file
//! a path is, and making a rename durable. The lowest room of [`super`]:
//! it imports none of the others.

use std::fs::File;
use std::path::Path;

use crate::error::{Error, Result};

/// What a file that is neither a regular file nor a folder is, in words
/// (`None` for those two, and for a path that is not there).
pub(crate) fn special_kind(metadata: &std::fs::Metadata) -> Option<&'static str> {
    let t = metadata.file_type();
    if t.is_file() || t.is_dir() {
        return None;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a FIFO");
        }
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
        if t.is_socket() {
            return Some("a socket");
        }
    }
    Some("a special file")
}

/// Make a rename in `folder` durable. File systems that cannot sync a
/// folder say so with `InvalidInput` or `Unsupported`; there is nothing
/// more to do on them.
pub(crate) fn sync_folder(folder: &Path) -> Result<()> {
    match File::open(folder).and_then(|f| f.sync_all()) {
        Ok(()) => Ok(()),
        Err(e)
            if matches!(
                e.kind(),
                std::io::ErrorKind::InvalidInput
                    | std::io::ErrorKind::Unsupported
                    | std::io::ErrorKind::PermissionDenied
            ) =>
        {
            Ok(())
        }
        Err(e) => Err(Error::io(folder, e)),
    }
}
