//! The names of the hidden files holo keeps beside an output: its
//! temporaries (`.NAME.PID.XXXXXX.partial`, `.NAME.PID.XXXXXX.spool`) and
//! its lock (`.NAME.lock`).
//!
//! Each carries the output's name, so a user sees what it belongs to, and
//! the writer's process id, so a later run can tell a temporary whose
//! writer no longer runs (killed by SIGKILL or a power cut) from one being
//! written. A name the file system takes must never make a hidden name it
//! cannot: when the output's name leaves too little room, the hidden names
//! carry a shortened stem instead (the name's start, `~` and eight hex
//! digits of its SHA-256, the same for the same name every time).

use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

/// The longest file name (bytes) the file system holding `folder` takes:
/// `pathconf(_PC_NAME_MAX)` where the system answers, else 255 (ext4, XFS,
/// Btrfs, tmpfs, NFS, APFS and NTFS all take 255).
pub(super) fn name_max(folder: &Path) -> usize {
    const USUAL: usize = 255;
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::ffi::OsStrExt;
        let Ok(c) = std::ffi::CString::new(folder.as_os_str().as_bytes()) else { return USUAL };
        // SAFETY: `c` is a NUL-terminated path that outlives the call;
        // pathconf only reads it.
        let limit = unsafe { libc::pathconf(c.as_ptr(), libc::_PC_NAME_MAX) };
        if limit > 0 {
            return usize::try_from(limit).unwrap_or(USUAL);
        }
    }
    let _ = folder;
    USUAL
}

/// Bytes a temporary's name adds to its stem: `.`, `.`, the process id (at
/// most 10 digits), `.`, 6 random characters and the longest suffix
/// (`.partial`).
const TEMPORARY_EXTRA: usize = 1 + 1 + 10 + 1 + 6 + ".partial".len();

/// The stem of the hidden files beside an output named `name` in a folder
/// whose file system takes names of up to `limit` bytes: the name itself
/// when a temporary's name fits, else its start, `~` and eight hex digits
/// of its SHA-256.
pub(super) fn stem(name: &OsStr, limit: usize) -> String {
    let text = name.to_string_lossy();
    let room = limit.saturating_sub(TEMPORARY_EXTRA).max(16);
    if text.len() <= room {
        return text.into_owned();
    }
    let digest = Sha256::digest(name.as_encoded_bytes());
    let tag: String = digest.iter().take(4).map(|b| format!("{b:02x}")).collect();
    let mut keep = room - 1 - tag.len();
    while !text.is_char_boundary(keep) {
        keep -= 1;
    }
    format!("{}~{tag}", &text[..keep])
}

/// The stem of the hidden files beside the output `path`.
pub(super) fn stem_of(path: &Path) -> String {
    let name = path.file_name().unwrap_or(path.as_os_str());
    stem(name, name_max(super::folder_of(path)))
}

/// The start of a temporary's name for an output with stem `stem`, written
/// by this process: `.STEM.PID.` (the random part and suffix follow).
pub(super) fn temporary_prefix(stem: &str) -> String {
    format!(".{stem}.{}.", std::process::id())
}

/// The suffixes of holo's temporaries.
const SUFFIXES: [&str; 2] = [".partial", ".spool"];

/// A temporary's stem and writer, read from its file name:
/// `.STEM.PID.XXXXXX.partial` (or `.spool`). Anything else is `None`.
pub(super) fn parse_temporary(name: &str) -> Option<(&str, u32)> {
    let rest = name.strip_prefix('.')?;
    let rest = SUFFIXES.iter().find_map(|s| rest.strip_suffix(s))?;
    let (rest, random) = rest.rsplit_once('.')?;
    let (stem, pid) = rest.rsplit_once('.')?;
    let pid_ok = !pid.is_empty() && pid.len() <= 10 && pid.bytes().all(|b| b.is_ascii_digit());
    (random.len() == 6 && random.bytes().all(|b| b.is_ascii_alphanumeric()) && pid_ok && !stem.is_empty())
        .then(|| pid.parse().ok().map(|pid| (stem, pid)))
        .flatten()
}

/// The lock file of the output file `path`: `.STEM.lock` beside it (where
/// its temporaries go too).
pub(super) fn file_lock(path: &Path) -> PathBuf {
    super::folder_of(path).join(format!(".{}.lock", stem_of(path)))
}

/// The lock file of a set, or a run's files, in the folder `folder`:
/// `.NAME.lock` in it, `NAME` the set's manifest (`holo-fringes.json`) or
/// the run's name. In the folder, not beside it: writing a folder's files
/// needs no right to its parent (`-o .` in a home folder).
pub(super) fn folder_lock(folder: &Path, name: &str) -> PathBuf {
    folder.join(format!(".{name}.lock"))
}

/// Whether process `pid` may still be running: only a process the system
/// says does not exist is taken for gone (on systems where holo cannot ask,
/// every process may be running).
pub(super) fn may_be_running(pid: u32) -> bool {
    #[cfg(target_os = "linux")]
    {
        let Ok(pid) = libc::pid_t::try_from(pid) else { return false };
        if pid <= 0 {
            return true;
        }
        // SAFETY: signal 0 only checks that the process exists and may be
        // signalled; nothing is sent.
        let found = unsafe { libc::kill(pid, 0) };
        found == 0 || std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = pid;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_name_gets_a_short_stem_of_its_own_and_temporaries_parse_back() {
        let short = stem(OsStr::new("a.holo"), 255);
        assert_eq!(short, "a.holo");
        let long: String = "é".repeat(120);
        let s = stem(OsStr::new(&long), 255);
        assert!(s.len() + TEMPORARY_EXTRA <= 255 && s.contains('~'), "{s}");
        assert_eq!(s, stem(OsStr::new(&long), 255), "the same every time");
        assert_ne!(s, stem(OsStr::new(&format!("{long}x")), 255), "another name, another stem");
        let name = format!("{}123456.partial", temporary_prefix("out.0001.holo"));
        assert_eq!(parse_temporary(&name), Some(("out.0001.holo", std::process::id())));
        assert_eq!(parse_temporary(".a.holo.42.abcXYZ.spool"), Some(("a.holo", 42)));
        for not_ours in [".a.holo.abcXYZ.partial", "a.holo.42.abcXYZ.partial", ".a.holo.42.abc.partial", ".a.lock"] {
            assert_eq!(parse_temporary(not_ours), None, "{not_ours}");
        }
        assert!(may_be_running(std::process::id()));
    }
}
