//! A movie split across a Slurm cluster (`holo farm`): one job array whose
//! tasks each make a chunk of frames, one output per frame, so a task that
//! fails or is cancelled costs only its own frames and a resubmission makes
//! only the frames not done.
//!
//! The farm of an output keeps its state in a folder beside it
//! ([`FarmOutput::state_folder`]: `shot.farm/` for `shot.holo`,
//! `fringes.farm/` for the fringe folder `fringes`): the [`Manifest`] (the
//! command, the frames, the whole-movie decisions made before the split,
//! every submission), each submission's job script and the tasks' logs.
//!
//! What a frame's output is:
//!
//! - a conversion writes the numbered sequence of its output
//!   ([`crate::format::sequence`]): `shot.holo` → `shot.0000.holo`, …;
//! - an assembly writes one fringe set per frame, `fringes/0007/` (with its
//!   own `holo-fringes.json`), which [`join_fringes`] makes one set.
//!
//! A frame is done when its output is present and checks: a `.holo` member
//! read whole with its digest verified, a fringe set with every image's
//! size and SHA-256 ([`frame_state`]).

pub mod slurm;

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::format::sequence::member_path;
use crate::format::HoloFile;
use crate::math::Mat4;

/// The version of [`Manifest`] written.
pub const MANIFEST_VERSION: u32 = 1;

/// The manifest's name in the state folder.
pub const MANIFEST: &str = "manifest.json";

/// What a farm makes, one output per frame.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", content = "path", rename_all = "lowercase")]
pub enum FarmOutput {
    /// A numbered sequence named as its one file would be (`shot.holo`).
    Sequence(PathBuf),
    /// A folder of per-frame fringe sets (`fringes/0007/`).
    Fringes(PathBuf),
}

impl FarmOutput {
    /// The path the user named.
    pub fn path(&self) -> &Path {
        match self {
            FarmOutput::Sequence(p) | FarmOutput::Fringes(p) => p,
        }
    }

    /// Frame `n`'s output: the member file, or the fringe set's folder.
    pub fn frame_path(&self, n: usize) -> PathBuf {
        match self {
            FarmOutput::Sequence(name) => member_path(name, n),
            FarmOutput::Fringes(folder) => folder.join(format!("{n:04}")),
        }
    }

    /// The folder of the farm's state, beside the output: its name without
    /// `.holo`, plus `.farm`.
    pub fn state_folder(&self) -> PathBuf {
        let path = self.path();
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "output".into());
        let stem = name.strip_suffix(".holo").unwrap_or(&name);
        path.with_file_name(format!("{stem}.farm"))
    }

    /// The folder every frame's output is written in.
    pub fn folder(&self) -> PathBuf {
        match self {
            FarmOutput::Sequence(name) => crate::output::folder_of(name).to_path_buf(),
            FarmOutput::Fringes(folder) => folder.clone(),
        }
    }
}

/// One `sbatch` of a farm: a job array over `frames`, task `i` making
/// `frames[i·chunk .. (i+1)·chunk]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Submission {
    /// Slurm's job id of the array.
    pub job_id: String,
    /// The frames submitted, in task order.
    pub frames: Vec<usize>,
    /// Frames per task.
    pub chunk: usize,
    /// The user's own `sbatch` options.
    pub sbatch: Vec<String>,
    /// When, as seconds since the Unix epoch.
    pub submitted_unix_s: u64,
}

impl Submission {
    /// The number of array tasks.
    pub fn tasks(&self) -> usize {
        self.frames.len().div_ceil(self.chunk.max(1))
    }

    /// The frames of task `task`.
    pub fn task_frames(&self, task: usize) -> &[usize] {
        let chunk = self.chunk.max(1);
        let start = (task * chunk).min(self.frames.len());
        &self.frames[start..(start + chunk).min(self.frames.len())]
    }

    /// The task that makes frame `n`, if this submission has it.
    pub fn task_of(&self, n: usize) -> Option<usize> {
        self.frames.iter().position(|&f| f == n).map(|i| i / self.chunk.max(1))
    }
}

/// A farm's record of itself.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// [`MANIFEST_VERSION`].
    pub version: u32,
    /// The `holo` the tasks run (an absolute path every node must reach).
    pub holo: PathBuf,
    /// The folder the command was given in; the tasks run there, so its
    /// relative paths mean what they meant.
    pub working_folder: PathBuf,
    /// The command split, as given after `holo` (`convert mesh …`).
    pub command: Vec<String>,
    /// What it makes.
    pub output: FarmOutput,
    /// The movie's frames.
    pub frames: Range<usize>,
    /// The placement decided once for the whole movie (scene or world to
    /// display metres, row-major), given to every task.
    pub placement: Option<Mat4>,
    /// Every submission, oldest first.
    pub submissions: Vec<Submission>,
}

impl Manifest {
    /// The manifest's path.
    pub fn path(&self) -> PathBuf {
        self.output.state_folder().join(MANIFEST)
    }

    /// Read a farm's manifest from its state folder.
    pub fn read(state_folder: &Path) -> Result<Manifest> {
        let path = state_folder.join(MANIFEST);
        let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        let manifest: Manifest =
            serde_json::from_str(&text).map_err(|e| Error::invalid(&path, format!("not a holo farm manifest: {e}")))?;
        if manifest.version != MANIFEST_VERSION {
            return Err(Error::invalid(
                &path,
                format!(
                    "is a farm manifest of version {}; this holo reads version {MANIFEST_VERSION}",
                    manifest.version
                ),
            ));
        }
        Ok(manifest)
    }

    /// The manifest of the farm of `path`: the output as the command named
    /// it, or the farm's state folder.
    pub fn find(path: &Path) -> Result<Manifest> {
        if path.join(MANIFEST).is_file() {
            return Manifest::read(path);
        }
        // The output as named: its state folder is beside it.
        let folder = FarmOutput::Sequence(path.to_path_buf()).state_folder();
        if folder.join(MANIFEST).is_file() {
            return Manifest::read(&folder);
        }
        Err(Error::argument(
            "farm",
            format!(
                "{}: no farm here (looked for {} and {}); `holo farm submit` makes one",
                path.display(),
                path.join(MANIFEST).display(),
                folder.join(MANIFEST).display()
            ),
        ))
    }

    /// Write the manifest atomically (a task reading it sees the old one or
    /// the new one, whole).
    pub fn write(&self) -> Result<()> {
        let folder = self.output.state_folder();
        std::fs::create_dir_all(folder.join("logs")).map_err(|e| Error::io(&folder, e))?;
        let text = serde_json::to_string_pretty(self).expect("plain data");
        crate::output::write_bytes_beside(&self.path(), text.as_bytes(), true)
    }

    /// The newest submission that has frame `n`, and its task (one whose
    /// `sbatch` never answered, its job id empty, ran nothing).
    pub fn last_task_of(&self, n: usize) -> Option<(&Submission, usize)> {
        self.submissions.iter().rev().filter(|s| !s.job_id.is_empty()).find_map(|s| s.task_of(n).map(|t| (s, t)))
    }
}

/// What is on disk for one frame.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "state", rename_all = "lowercase")]
pub enum FrameState {
    /// Present and checked; the frame's digest.
    Done {
        /// `sha256:…` of the frame's samples (a fringe set: of its source frame).
        digest: Option<String>,
    },
    /// Not there.
    Missing,
    /// There but not whole, or not this frame: why.
    Damaged {
        /// One sentence.
        why: String,
    },
}

impl FrameState {
    /// Whether the frame needs making.
    pub fn is_done(&self) -> bool {
        matches!(self, FrameState::Done { .. })
    }
}

/// What a frame file was when it was last read whole and found good: its
/// size, modification time and digest. Kept in the state folder
/// (`verified/NNNN.json`), so that [`checked_frame_state`] need not read a
/// file again that has not changed since.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct Verified {
    bytes: u64,
    modified_ns: u128,
    digest: Option<String>,
}

impl Verified {
    fn of(path: &Path, digest: Option<String>) -> Option<Verified> {
        let meta = std::fs::metadata(path).ok()?;
        let modified_ns = meta.modified().ok()?.duration_since(std::time::UNIX_EPOCH).ok()?.as_nanos();
        Some(Verified { bytes: meta.len(), modified_ns, digest })
    }
}

/// [`frame_state`], except that a frame file (of a sequence) read whole and
/// found good before, whose size and modification time have not changed
/// since, is taken as done without reading it again; `verify` reads every
/// frame whatever its record says. A file damaged by a write changes its
/// time; damage that leaves both alone (a failing disk) needs `verify`.
/// Fringe sets are always checked whole.
pub fn checked_frame_state(output: &FarmOutput, n: usize, verify: bool) -> FrameState {
    let FarmOutput::Sequence(_) = output else { return frame_state(output, n) };
    let path = output.frame_path(n);
    let record = output.state_folder().join("verified").join(format!("{n:04}.json"));
    if !verify {
        let known: Option<Verified> = std::fs::read_to_string(&record).ok().and_then(|t| serde_json::from_str(&t).ok());
        if let (Some(known), Some(now)) = (known, Verified::of(&path, None)) {
            if known.bytes == now.bytes && known.modified_ns == now.modified_ns {
                return FrameState::Done { digest: known.digest };
            }
        }
    }
    let state = frame_state(output, n);
    // Best effort: without the record the next look reads the file again.
    match (&state, Verified::of(&path, None)) {
        (FrameState::Done { digest }, Some(v)) => {
            let v = Verified { digest: digest.clone(), ..v };
            let _ = std::fs::create_dir_all(record.parent().unwrap_or(Path::new(".")));
            let text = serde_json::to_string(&v).expect("plain data");
            let _ = crate::output::write_bytes_beside(&record, text.as_bytes(), true);
        }
        // Found not good: no record may vouch for it any more.
        _ => {
            let _ = std::fs::remove_file(&record);
        }
    }
    state
}

/// The state of frame `n` of `output`: a member read whole with its digest
/// checked, or a fringe set with every image checked.
pub fn frame_state(output: &FarmOutput, n: usize) -> FrameState {
    let path = output.frame_path(n);
    let damaged = |e: Error| FrameState::Damaged { why: e.to_string() };
    match output {
        FarmOutput::Sequence(_) => {
            if !path.exists() {
                return FrameState::Missing;
            }
            let file = match HoloFile::open(&path) {
                Ok(f) => f,
                Err(e) => return damaged(e),
            };
            let frames = &file.info().frames;
            if frames.len() != 1 || frames[0].number != n as i64 {
                return FrameState::Damaged { why: format!("{}: is not frame {n} alone (holo.frame)", path.display()) };
            }
            match file.read_frame(0) {
                Ok(_) => FrameState::Done { digest: frames[0].digest.clone() },
                Err(e) => damaged(e),
            }
        }
        FarmOutput::Fringes(_) => {
            if !path.exists() {
                return FrameState::Missing;
            }
            match crate::assemble::output::read_sidecar(&path) {
                Ok(s) if s.frames.len() == 1 && s.frames[0].index == n => {
                    FrameState::Done { digest: s.frames[0].source_digest.clone() }
                }
                Ok(_) => FrameState::Damaged {
                    why: format!("{}: does not hold the fringes of frame {n} alone", path.display()),
                },
                Err(e) => damaged(e),
            }
        }
    }
}

/// The job script of submission `index`: the task reads the manifest and
/// makes its frames (`holo farm task`). Options go on `sbatch`'s command
/// line, so the user's own come after and win.
pub fn job_script(manifest: &Manifest, index: usize) -> String {
    let quote = |p: &Path| shell_quote(&p.to_string_lossy());
    format!(
        "#!/bin/sh\n# holo farm: submission {index} of {output}; task $SLURM_ARRAY_TASK_ID makes its chunk of frames\nexec {holo} farm task {manifest} {index} \"$SLURM_ARRAY_TASK_ID\"\n",
        output = manifest.output.path().display(),
        holo = quote(&manifest.holo),
        manifest = quote(&manifest.path()),
    )
}

/// `text` quoted for a POSIX shell.
fn shell_quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', r"'\''"))
}

/// Check a farm's numbered sequence as one movie: every frame of `frames`
/// present and whole (read with its digest checked), one geometry
/// ([`crate::format::Sequence::open`]), and one provenance: the same
/// placement and the same conversion but for the frames. The frames'
/// digests, in order.
pub fn check_sequence(name: &Path, frames: Range<usize>) -> Result<Vec<Option<String>>> {
    let sequence = crate::format::Sequence::open(name)?;
    let mut digests = Vec::new();
    let mut first: Option<(PathBuf, Option<Mat4>, Option<crate::provenance::Conversion>)> = None;
    for n in frames {
        let file = sequence.member(n)?;
        file.read_frame(0)?;
        let info = file.info();
        let conversion = info.conversion()?.map(|c| c.with_frames(None));
        match &first {
            None => first = Some((file.path().clone(), info.placement, conversion)),
            Some((path, placement, recorded)) => {
                let differs = if info.placement != *placement {
                    Some("placement (holo.placement)")
                } else if conversion != *recorded {
                    Some("conversion (holo.convert.*)")
                } else {
                    None
                };
                if let Some(what) = differs {
                    return Err(Error::invalid(
                        file.path(),
                        format!("has another {what} than {}: the frames are not of one movie", path.display()),
                    ));
                }
            }
        }
        digests.push(info.frames[0].digest.clone());
    }
    Ok(digests)
}

/// Join frames `frames` of the numbered sequence `name` into the one
/// multi-part file `output` (spec holo-format §2.2): the samples as stored,
/// so every frame keeps its digest; written as the first member was
/// (sample type, compression, radiometry, provenance), the conversion
/// recorded for the frames joined.
pub fn join_sequence(
    name: &Path,
    frames: Range<usize>,
    output: &Path,
    overwrite: bool,
) -> Result<crate::format::WriteReport> {
    let sequence = crate::format::Sequence::open(name)?;
    let members: Vec<&HoloFile> = frames.clone().map(|n| sequence.member(n)).collect::<Result<_>>()?;
    let inputs: Vec<&Path> = members.iter().map(|m| m.path().as_path()).collect();
    let _claim = crate::output::check_output(output, &inputs, overwrite)?;
    let info = members[0].info();
    let options = crate::format::WriteOptions {
        sample_type: info.sample_type,
        compression: info.compression,
        radiometry: info.radiometry.clone(),
        source: info.source.clone().unwrap_or_default(),
        frames_per_second: info.frames_per_second,
        first_frame_number: i32::try_from(frames.start)
            .map_err(|_| Error::argument("frame number", format!("frame {} is too large", frames.start)))?,
        overwrite,
        version: crate::format::FormatVersion::for_number(info.version),
        placement: info.placement,
        conversion: info.conversion()?.map(|c| c.with_frames(Some(frames.clone())).record()),
    };
    crate::format::write_frames(output, sequence.geometry(), members.len(), &options, |i| {
        members[i].read_frame(0).map(std::borrow::Cow::Owned)
    })
}

/// The fringe sets of `frames` in `output`'s folder, made one fringe set in
/// `folder` (images copied, one `holo-fringes.json` listing every frame).
pub fn join_fringes(output: &Path, frames: Range<usize>, folder: &Path, overwrite: bool) -> Result<Vec<PathBuf>> {
    use crate::assemble::output::{read_sidecar, FRINGE_SIDECAR};
    let mut sidecars = Vec::new();
    let mut names = Vec::new();
    for n in frames.clone() {
        let set = output.join(format!("{n:04}"));
        let sidecar = read_sidecar(&set)?;
        names.extend(sidecar.frames.iter().flat_map(|f| f.files.clone()));
        sidecars.push((set, sidecar));
    }
    let _claim = crate::output::check_set_output(folder, FRINGE_SIDECAR, &names, &[output], overwrite)?;
    let mut joined = sidecars[0].1.clone();
    joined.frames.clear();
    let mut set = crate::output::FileSet::create(folder, FRINGE_SIDECAR)?;
    for (from, sidecar) in &sidecars {
        if sidecar.layout != joined.layout || sidecar.format != joined.format || sidecar.source != joined.source {
            return Err(Error::invalid(
                from.join(FRINGE_SIDECAR),
                format!(
                    "was assembled from another source, layout or format than {}",
                    sidecars[0].0.join(FRINGE_SIDECAR).display()
                ),
            ));
        }
        for name in sidecar.frames.iter().flat_map(|f| &f.files) {
            let bytes = std::fs::read(from.join(name)).map_err(|e| Error::io(from.join(name), e))?;
            set.add_bytes(name, &bytes)?;
        }
        joined.frames.extend(sidecar.frames.iter().cloned());
    }
    set.commit(overwrite, |listed| {
        joined.files = listed.to_vec();
        Ok(serde_json::to_string_pretty(&joined).expect("plain data").into_bytes())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tasks_cover_every_frame_once_in_chunks() {
        let s = Submission {
            job_id: "7".into(),
            frames: vec![3, 4, 5, 9, 10, 11, 12],
            chunk: 3,
            sbatch: vec![],
            submitted_unix_s: 0,
        };
        assert_eq!(s.tasks(), 3);
        assert_eq!(s.task_frames(0), [3, 4, 5]);
        assert_eq!(s.task_frames(2), [12]);
        assert_eq!(s.task_frames(3), [] as [usize; 0]);
        assert_eq!(s.task_of(10), Some(1));
        assert_eq!(s.task_of(6), None);
    }

    #[test]
    fn the_state_folder_is_beside_the_output() {
        let seq = FarmOutput::Sequence(PathBuf::from("out/shot.holo"));
        assert_eq!(seq.state_folder(), Path::new("out/shot.farm"));
        assert_eq!(seq.frame_path(7), Path::new("out/shot.0007.holo"));
        let fringes = FarmOutput::Fringes(PathBuf::from("out/fringes"));
        assert_eq!(fringes.state_folder(), Path::new("out/fringes.farm"));
        assert_eq!(fringes.frame_path(12), Path::new("out/fringes/0012"));
    }

    #[test]
    fn job_scripts_quote_paths_for_the_shell() {
        assert_eq!(shell_quote("a b'c"), r"'a b'\''c'");
    }
}
