//! Numbered sequences of single-frame files, `NAME.NNNN.holo` (spec
//! holo-format §2.2): the form render farms split a long movie into, one
//! file per frame, where `holo.frame` of each file is its number.
//!
//! A sequence is named as the one file it stands for would be: `shot.holo`
//! names `shot.0000.holo`, `shot.0001.holo`, …. The number has four digits,
//! more when it needs them (`%04d`, the VFX convention): `shot.12345.holo`.
//! [`Frames`] opens either a file or a sequence, so a command that reads
//! frames takes both.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::read::HoloFile;
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::modulation::Modulation;

/// The file holding frame `number` of the sequence `name` (`shot.holo`,
/// 7 → `shot.0007.holo`).
pub fn member_path(name: &Path, number: usize) -> PathBuf {
    let stem = name.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    name.with_file_name(format!("{stem}.{number:04}.holo"))
}

/// The frame number `file` holds as a member of the sequence `name`, when it
/// is one (its number written as [`member_path`] writes it).
pub fn member_number(name: &Path, file: &Path) -> Option<usize> {
    let stem = name.file_stem()?.to_str()?;
    let rest = file.file_name()?.to_str()?.strip_prefix(stem)?.strip_prefix('.')?;
    let digits = rest.strip_suffix(".holo")?;
    let canonical = digits.len() == 4 || (digits.len() > 4 && !digits.starts_with('0'));
    if !canonical || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// Every member of the sequence `name` in its folder, by number (none when
/// the folder has none; an error when the folder cannot be read).
pub fn member_files(name: &Path) -> Result<BTreeMap<usize, PathBuf>> {
    let folder = match name.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let entries = std::fs::read_dir(folder).map_err(|e| Error::io(folder, e))?;
    let mut members = BTreeMap::new();
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(folder, e))?;
        let file = name.with_file_name(entry.file_name());
        if let Some(n) = member_number(name, &file) {
            members.insert(n, file);
        }
    }
    Ok(members)
}

/// Whether `name` can name a sequence: a `.holo` file name.
fn can_name_sequence(name: &Path) -> bool {
    name.extension().is_some_and(|e| e == "holo") && name.file_stem().is_some()
}

/// An open numbered sequence: every member's headers read and checked to be
/// one frame numbered as its name says, all of one geometry.
#[derive(Debug)]
pub struct Sequence {
    name: PathBuf,
    members: BTreeMap<usize, HoloFile>,
}

impl Sequence {
    /// Open the members of `name` (`shot.holo` for `shot.NNNN.holo`); a
    /// sequence without members is refused, naming the form looked for.
    pub fn open(name: &Path) -> Result<Self> {
        let files = member_files(name)?;
        if files.is_empty() {
            let example = member_path(name, 0);
            return Err(Error::io(
                name,
                std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    format!("no such file, nor a numbered sequence of them ({} …)", example.display()),
                ),
            ));
        }
        let mut members = BTreeMap::new();
        let mut first: Option<(PathBuf, Geometry)> = None;
        for (number, path) in files {
            let file = HoloFile::open(&path)?;
            let frames = &file.info().frames;
            if frames.len() != 1 {
                return Err(Error::invalid(
                    &path,
                    format!("holds {} frames; a member of a numbered sequence holds one", frames.len()),
                ));
            }
            if frames[0].number != number as i64 {
                return Err(Error::invalid(
                    &path,
                    format!(
                        "says it is frame {} (holo.frame); its name says frame {number}: it was renamed or belongs to another sequence",
                        frames[0].number
                    ),
                ));
            }
            match &first {
                None => first = Some((path.clone(), file.geometry().clone())),
                Some((first_path, g)) if g != file.geometry() => {
                    return Err(Error::invalid(
                        &path,
                        format!(
                            "has another geometry than {} (a sequence's frames share one geometry)",
                            first_path.display()
                        ),
                    ));
                }
                Some(_) => {}
            }
            members.insert(number, file);
        }
        Ok(Sequence { name: name.to_path_buf(), members })
    }

    /// The name the sequence was opened by.
    pub fn name(&self) -> &Path {
        &self.name
    }

    /// The members' geometry.
    pub fn geometry(&self) -> &Geometry {
        self.members.values().next().expect("a sequence has a member").geometry()
    }

    /// The frame numbers present, increasing.
    pub fn numbers(&self) -> impl Iterator<Item = usize> + '_ {
        self.members.keys().copied()
    }

    /// The member holding frame `number`, or the error naming the file
    /// that is missing.
    pub fn member(&self, number: usize) -> Result<&HoloFile> {
        self.members.get(&number).ok_or_else(|| {
            Error::io(
                member_path(&self.name, number),
                std::io::Error::new(std::io::ErrorKind::NotFound, "missing from its numbered sequence"),
            )
        })
    }
}

/// Frames to read: one `.holo` file (frame `i` is its `i`-th part) or a
/// numbered sequence (frame `n` is the member numbered `n`).
#[derive(Debug)]
pub enum Frames {
    /// One file (its headers boxed: they are large beside a sequence's map).
    File(Box<HoloFile>),
    /// A numbered sequence.
    Sequence(Sequence),
}

impl Frames {
    /// Open `path` as a file when it exists, else as the numbered sequence it
    /// names when it has members; else the error of opening the file.
    pub fn open(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        if path.exists() || !can_name_sequence(path) {
            return HoloFile::open(path).map(|f| Frames::File(Box::new(f)));
        }
        match member_files(path) {
            Ok(m) if !m.is_empty() => Sequence::open(path).map(Frames::Sequence),
            _ => HoloFile::open(path).map(|f| Frames::File(Box::new(f))),
        }
    }

    /// The path opened.
    pub fn path(&self) -> &Path {
        match self {
            Frames::File(f) => f.path(),
            Frames::Sequence(s) => s.name(),
        }
    }

    /// The geometry of every frame.
    pub fn geometry(&self) -> &Geometry {
        match self {
            Frames::File(f) => f.geometry(),
            Frames::Sequence(s) => s.geometry(),
        }
    }

    /// Every frame: a file's `0..parts`, a sequence's member numbers.
    pub fn numbers(&self) -> Vec<usize> {
        match self {
            Frames::File(f) => (0..f.info().frames.len()).collect(),
            Frames::Sequence(s) => s.numbers().collect(),
        }
    }

    /// The file holding frame `n` and the frame's index in it.
    fn locate(&self, n: usize) -> Result<(&HoloFile, usize)> {
        match self {
            Frames::File(f) => {
                let frames = f.info().frames.len();
                let missing = || Error::NoFrame { path: f.path().clone(), asked: n..n + 1, frames };
                (n < frames).then_some((&**f, n)).ok_or_else(missing)
            }
            Frames::Sequence(s) => s.member(n).map(|f| (f, 0)),
        }
    }

    /// Check that every frame of `frames` is present; the default is all.
    pub fn check_range(&self, frames: &std::ops::Range<usize>) -> Result<()> {
        let numbers = self.numbers();
        if frames.is_empty() {
            return Err(Error::NoFrame {
                path: self.path().to_path_buf(),
                asked: frames.clone(),
                frames: numbers.len(),
            });
        }
        if let Frames::File(_) = self {
            if frames.end > numbers.len() {
                return Err(Error::NoFrame {
                    path: self.path().to_path_buf(),
                    asked: frames.clone(),
                    frames: numbers.len(),
                });
            }
        }
        frames.clone().try_for_each(|n| self.locate(n).map(drop))
    }

    /// The frames when none are asked for: a file's parts, or a sequence's
    /// first member to its last (every one between must be present).
    pub fn all(&self) -> std::ops::Range<usize> {
        let numbers = self.numbers();
        match (numbers.first(), numbers.last()) {
            (Some(&a), Some(&b)) => a..b + 1,
            _ => 0..0,
        }
    }

    /// Read frame `n` whole and verify its digest.
    pub fn read_frame(&self, n: usize) -> Result<Modulation> {
        let (file, index) = self.locate(n)?;
        file.read_frame(index)
    }

    /// Frame `n`'s stored digest, when it has one.
    pub fn digest(&self, n: usize) -> Option<String> {
        let (file, index) = self.locate(n).ok()?;
        file.info().frames[index].digest.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn member_names_follow_the_vfx_convention_both_ways() {
        let name = Path::new("out/shot.holo");
        assert_eq!(member_path(name, 7), Path::new("out/shot.0007.holo"));
        assert_eq!(member_path(name, 12345), Path::new("out/shot.12345.holo"));
        for n in [0, 7, 9999, 10000, 12345] {
            assert_eq!(member_number(name, &member_path(name, n)), Some(n));
        }
        for other in [
            "out/shot.holo",
            "out/shot.007.holo",
            "out/shot.01234.holo",
            "out/shot.00a1.holo",
            "out/shots.0001.holo",
            "out/shot.0001.exr",
        ] {
            assert_eq!(member_number(name, Path::new(other)), None, "{other}");
        }
    }
}
