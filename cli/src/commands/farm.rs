//! `holo farm submit|status|gather`: a frame-making command split across a
//! Slurm cluster as a job array (the library's [`holo::farm`]). `submit`
//! checks everything and makes the whole-movie decisions before anything is
//! submitted; each array task runs `holo farm task` (hidden), which makes
//! its frames in this same process, one output per frame.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};
use holo::farm::slurm::{self, ArrayJob};
use holo::farm::{checked_frame_state, FarmOutput, FrameState, Manifest, Submission, MANIFEST_VERSION};
use serde::Serialize;

use super::assemble::AssembleArgs;
use super::convert::{CamerasArgs, ConvertCommand, HoloflickArgs, MeshArgs};
use super::frame_job::FrameJob;
use super::{Failure, Outcome};
use crate::args;
use crate::out::{say, warn};

#[derive(Subcommand)]
pub enum FarmCommand {
    Submit(SubmitArgs),
    Status(StatusArgs),
    Gather(GatherArgs),
    #[command(hide = true)]
    Task(TaskArgs),
}

pub fn run(command: FarmCommand) -> Outcome {
    match command {
        FarmCommand::Submit(a) => submit(a),
        FarmCommand::Status(a) => status(a),
        FarmCommand::Gather(a) => gather(a),
        FarmCommand::Task(a) => task(a),
    }
}

/// Split a frame-making command (convert mesh|cameras|holoflick, assemble)
/// across a Slurm cluster: one job array, each task a chunk of frames, one
/// output per frame (shot.holo → shot.0000.holo, …; fringes → fringes/0000/,
/// …). The same command again submits only the frames not done.
#[derive(Args)]
pub struct SubmitArgs {
    /// Frames per array task.
    #[arg(long, default_value = "10", value_parser = args::at_least(1))]
    chunk: usize,
    /// Options for sbatch (repeatable; split at spaces): --sbatch "--partition=long --time=2:00:00".
    #[arg(long = "sbatch", value_name = "OPTIONS", allow_hyphen_values = true)]
    sbatch: Vec<String>,
    /// The holo command to split, after --: convert mesh scene.glb --layout mark3 -o shot.holo …
    #[arg(last = true, required = true, value_name = "COMMAND")]
    command: Vec<String>,
}

/// The commands a farm splits, parsed as `holo` parses them (its own
/// parser: the farm is one of `holo`'s commands, and knows only these).
#[derive(Parser)]
#[command(name = "holo")]
struct Split {
    #[command(subcommand)]
    command: SplitCommand,
}

#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum SplitCommand {
    #[command(subcommand)]
    Convert(SplitConvert),
    Assemble(AssembleArgs),
}

#[derive(Subcommand)]
enum SplitConvert {
    Holoflick(HoloflickArgs),
    Mesh(MeshArgs),
    Cameras(CamerasArgs),
}

impl SplitCommand {
    /// What it is, in the words of its command line.
    fn kind(&self) -> &'static str {
        match self {
            SplitCommand::Convert(SplitConvert::Mesh(_)) => "convert mesh",
            SplitCommand::Convert(SplitConvert::Cameras(_)) => "convert cameras",
            SplitCommand::Convert(SplitConvert::Holoflick(_)) => "convert holoflick",
            SplitCommand::Assemble(_) => "assemble",
        }
    }

    /// Its [`FrameJob`].
    fn job(&mut self) -> &mut dyn FrameJob {
        match self {
            SplitCommand::Convert(SplitConvert::Mesh(a)) => a,
            SplitCommand::Convert(SplitConvert::Cameras(a)) => a,
            SplitCommand::Convert(SplitConvert::Holoflick(a)) => a,
            SplitCommand::Assemble(a) => a,
        }
    }

    /// Run it, as `holo` would.
    fn run(self) -> Outcome {
        match self {
            SplitCommand::Convert(SplitConvert::Mesh(a)) => super::convert::run(ConvertCommand::Mesh(a)),
            SplitCommand::Convert(SplitConvert::Cameras(a)) => super::convert::run(ConvertCommand::Cameras(a)),
            SplitCommand::Convert(SplitConvert::Holoflick(a)) => super::convert::run(ConvertCommand::Holoflick(a)),
            SplitCommand::Assemble(a) => super::assemble::run(a),
        }
    }
}

/// `words` (a command line after `holo`) as the frame-making command to split.
fn frame_job(words: &[String]) -> Result<SplitCommand, Failure> {
    let splits = matches!(
        words.iter().map(String::as_str).take(2).collect::<Vec<_>>().as_slice(),
        ["assemble", ..] | ["convert", "mesh" | "cameras" | "holoflick"]
    );
    if !splits {
        return Err(Failure(format!(
            "holo farm splits convert mesh, convert cameras, convert holoflick and assemble, not `{}`",
            words.iter().take(2).cloned().collect::<Vec<_>>().join(" ")
        )));
    }
    let argv = std::iter::once("holo".to_string()).chain(words.iter().cloned());
    let matches = args::negative_numbers(Split::command()).try_get_matches_from(argv);
    matches.and_then(|m| Split::from_arg_matches(&m)).map(|s| s.command).map_err(|e| {
        let text = e.to_string();
        let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("").trim();
        Failure(format!("the command to split: {}", first.strip_prefix("error: ").unwrap_or(first)))
    })
}

fn absolute(path: &Path) -> Result<PathBuf, Failure> {
    std::path::absolute(path).map_err(|e| Failure(format!("{}: {e}", path.display())))
}

fn submit(a: SubmitArgs) -> Outcome {
    let mut command = frame_job(&a.command)?;
    let kind = command.kind();
    let job = command.job();
    slurm::find("sbatch")?;
    let cwd = std::env::current_dir().map_err(|e| Failure(format!("the current folder: {e}")))?;
    let output = match job.output() {
        FarmOutput::Sequence(p) => FarmOutput::Sequence(absolute(&p)?),
        FarmOutput::Fringes(p) => FarmOutput::Fringes(absolute(&p)?),
    };
    // A sequence's files go in its folder; a fringe folder is made in its parent.
    let folder = match &output {
        FarmOutput::Sequence(name) => name.parent().map(Path::to_path_buf),
        FarmOutput::Fringes(folder) => folder.parent().map(Path::to_path_buf),
    }
    .unwrap_or_else(|| PathBuf::from("/"));
    if !folder.is_dir() {
        return Err(Failure(format!("{}: the folder {} does not exist", output.path().display(), folder.display())));
    }
    let decided = job.decide()?;
    let holo = std::env::current_exe().map_err(|e| Failure(format!("cannot find the holo program: {e}")))?;
    let state = output.state_folder();

    let mut manifest = match Manifest::read(&state) {
        Ok(m) => {
            if m.command != a.command || m.working_folder != cwd {
                return Err(Failure(format!(
                    "{} holds the farm of another command (`holo {}` in {}); give another output, or remove that folder",
                    state.display(),
                    m.command.join(" "),
                    m.working_folder.display()
                )));
            }
            Manifest { holo, ..m }
        }
        // A manifest that cannot be read (damaged, or of a newer holo) is said as it is.
        Err(e) if state.join(holo::farm::MANIFEST).exists() => return Err(e.into()),
        Err(_) if state.exists() => {
            return Err(Failure(format!(
                "{} exists but holds no farm manifest; not overwritten (remove it or give another output)",
                state.display()
            )))
        }
        Err(_) => {
            // Nothing the user had is replaced: a new farm starts on no frames.
            let present: Vec<usize> = decided.frames.clone().filter(|&n| output.frame_path(n).exists()).collect();
            if let Some(&n) = present.first() {
                return Err(Failure(format!(
                    "{} already exists ({} of the frames' outputs do) and no farm made it; not overwritten",
                    output.frame_path(n).display(),
                    present.len()
                )));
            }
            Manifest {
                version: MANIFEST_VERSION,
                holo,
                working_folder: cwd.clone(),
                command: a.command.clone(),
                output: output.clone(),
                frames: decided.frames.clone(),
                placement: decided.placement,
                submissions: vec![],
            }
        }
    };
    let fresh = manifest.submissions.is_empty();

    // The frames not done and not being made by a task Slurm still runs.
    let mut states: Vec<(String, std::collections::BTreeMap<usize, String>)> = Vec::new();
    let mut todo = Vec::new();
    let mut active = 0;
    for n in manifest.frames.clone() {
        if checked_frame_state(&output, n, false).is_done() {
            continue;
        }
        if task_state(&manifest, &mut states, n).and_then(|(_, _, s)| s).is_some_and(|s| slurm::is_active(&s)) {
            active += 1;
            continue;
        }
        todo.push(n);
    }
    let total = manifest.frames.len();
    if todo.is_empty() {
        say!(
            "{}: all {total} frames are done{}; nothing submitted",
            output.path().display(),
            if active > 0 {
                format!(" or being made ({active} by tasks still queued or running)")
            } else {
                String::new()
            }
        );
        return Ok(ExitCode::SUCCESS);
    }

    let sbatch: Vec<String> = a.sbatch.iter().flat_map(|o| o.split_whitespace().map(String::from)).collect();
    let index = manifest.submissions.len();
    let unix_s = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    manifest.submissions.push(Submission {
        job_id: String::new(),
        frames: todo.clone(),
        chunk: a.chunk,
        sbatch: sbatch.clone(),
        submitted_unix_s: unix_s,
    });
    let undo = |manifest: &mut Manifest| {
        if fresh {
            let _ = std::fs::remove_dir_all(&state);
        } else {
            manifest.submissions.pop();
            let _ = manifest.write();
        }
    };
    // The tasks read the manifest: it is in place before sbatch runs.
    manifest.write()?;
    let script = state.join(format!("submit-{index}.sh"));
    if let Err(e) = holo::output::write_bytes_beside(&script, holo::farm::job_script(&manifest, index).as_bytes(), true)
    {
        undo(&mut manifest);
        return Err(e.into());
    }
    let submission = manifest.submissions.last().expect("just pushed").clone();
    let name = format!("holo-{}", output.path().file_name().map(|n| n.to_string_lossy()).unwrap_or_default());
    let log = state.join("logs").join("%A_%a.out");
    let job = ArrayJob {
        script: &script,
        tasks: submission.tasks(),
        name: &name,
        log: &log,
        working_folder: &cwd,
        user_options: &sbatch,
    };
    let job_id = match slurm::submit(&job) {
        Ok(id) => id,
        Err(e) => {
            undo(&mut manifest);
            return Err(e.into());
        }
    };
    manifest.submissions.last_mut().expect("just pushed").job_id = job_id.clone();
    manifest.write()?;
    say!(
        "submitted job {job_id}: {kind} of {} frame(s) of {total} in {} task(s) of up to {} frame(s); \
         logs in {}; `holo farm status {}` says how it goes",
        todo.len(),
        submission.tasks(),
        a.chunk,
        state.join("logs").display(),
        output.path().display()
    );
    println!("{job_id}");
    Ok(ExitCode::SUCCESS)
}

/// The newest task that had frame `n` and its state in Slurm (queried once
/// per job and kept in `cache`): job id, task, state.
fn task_state(
    manifest: &Manifest,
    cache: &mut Vec<(String, std::collections::BTreeMap<usize, String>)>,
    n: usize,
) -> Option<(String, usize, Option<String>)> {
    let (submission, task) = manifest.last_task_of(n)?;
    let id = submission.job_id.clone();
    if !cache.iter().any(|(j, _)| *j == id) {
        cache.push((id.clone(), slurm::task_states(&id)));
    }
    let states = &cache.iter().find(|(j, _)| *j == id)?.1;
    // None: Slurm no longer lists it (finished long enough ago, and the
    // cluster keeps no accounting).
    Some((id, task, states.get(&task).cloned()))
}

/// Per frame of a farm: done (its output present and whole), missing or
/// damaged, with the state Slurm gives the task that last had it.
#[derive(Args)]
pub struct StatusArgs {
    /// The output the command named (shot.holo, or the fringe folder), or its .farm folder.
    output: PathBuf,
    /// Print JSON: one entry per frame.
    #[arg(long)]
    json: bool,
    /// Read every frame whole, even one unchanged (size and time) since it was last read and found good.
    #[arg(long)]
    verify: bool,
}

/// One frame in `holo farm status --json`.
#[derive(Serialize)]
struct FrameStatus {
    frame: usize,
    #[serde(flatten)]
    state: FrameState,
    /// Slurm's job id, task and its state, when a submission had the frame.
    job: Option<String>,
    task: Option<usize>,
    slurm: Option<String>,
}

fn status(a: StatusArgs) -> Outcome {
    let manifest = Manifest::find(&a.output)?;
    let mut cache = Vec::new();
    let frames: Vec<FrameStatus> = manifest
        .frames
        .clone()
        .map(|n| {
            let state = checked_frame_state(&manifest.output, n, a.verify);
            let (job, task, slurm) = match task_state(&manifest, &mut cache, n) {
                Some((j, t, s)) => (Some(j), Some(t), s),
                None => (None, None, None),
            };
            FrameStatus { frame: n, state, job, task, slurm }
        })
        .collect();
    let count = |f: fn(&FrameState) -> bool| frames.iter().filter(|s| f(&s.state)).count();
    let done = count(|s| matches!(s, FrameState::Done { .. }));
    let missing = count(|s| matches!(s, FrameState::Missing));
    let damaged = count(|s| matches!(s, FrameState::Damaged { .. }));
    if a.json {
        let doc = serde_json::json!({
            "output": manifest.output.path(),
            "command": manifest.command,
            "frames": frames,
            "done": done, "missing": missing, "damaged": damaged,
        });
        println!("{}", serde_json::to_string_pretty(&doc).expect("plain data"));
        return Ok(ExitCode::SUCCESS);
    }
    say!(
        "{}: {} frames ({}..{}): {done} done, {missing} missing, {damaged} damaged",
        manifest.output.path().display(),
        frames.len(),
        manifest.frames.start,
        manifest.frames.end
    );
    // Runs of frames alike, one line each.
    let describe = |s: &FrameStatus| {
        let what = match &s.state {
            FrameState::Done { .. } => "done",
            // A task still at it: its output is not there yet, or half written.
            _ if s.slurm.as_deref().is_some_and(slurm::is_active) => "not done yet",
            FrameState::Missing => "missing",
            FrameState::Damaged { .. } => "damaged",
        };
        match (&s.job, s.task, &s.slurm) {
            (Some(j), Some(t), Some(st)) => format!("{what} (job {j}, task {t}: {st})"),
            (Some(j), Some(t), None) => format!("{what} (job {j}, task {t}: no longer in Slurm's queue)"),
            _ => format!("{what} (never submitted)"),
        }
    };
    let mut i = 0;
    while i < frames.len() {
        let line = describe(&frames[i]);
        let mut k = i + 1;
        while k < frames.len() && describe(&frames[k]) == line && !matches!(frames[k].state, FrameState::Damaged { .. })
        {
            k += 1;
        }
        let range = if k - i == 1 {
            format!("frame {}", frames[i].frame)
        } else {
            format!("frames {}..{}", frames[i].frame, frames[k - 1].frame + 1)
        };
        say!("  {range}: {line}");
        if let (FrameState::Damaged { why }, "damaged") = (&frames[i].state, line.split(' ').next().unwrap_or("")) {
            say!("    {why}");
        }
        i = k;
    }
    let stopped =
        frames.iter().filter(|s| !s.state.is_done() && !s.slurm.as_deref().is_some_and(slurm::is_active)).count();
    if stopped > 0 {
        say!(
            "{stopped} frame(s) are not done and no task is at them: submit the same command again to make them \
             (holo farm submit -- {})",
            manifest.command.join(" ")
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Check a farm's frames as one movie (all present and whole; a sequence:
/// one geometry, one placement, one conversion), and join them on request.
#[derive(Args)]
pub struct GatherArgs {
    /// The output the command named (shot.holo, or the fringe folder), or its .farm folder.
    output: PathBuf,
    /// Also join the frames: a sequence into one multi-part .holo file, fringe sets into one fringe folder.
    #[arg(long, value_name = "PATH")]
    join: Option<PathBuf>,
    /// Replace an existing joined output.
    #[arg(long)]
    force: bool,
}

fn gather(a: GatherArgs) -> Outcome {
    let manifest = Manifest::find(&a.output)?;
    let frames = manifest.frames.clone();
    // Gathering is the last look before the movie is used: every frame is read.
    let not_done: Vec<usize> =
        frames.clone().filter(|&n| !checked_frame_state(&manifest.output, n, true).is_done()).collect();
    if let Some(&first) = not_done.first() {
        return Err(Failure(format!(
            "{}: {} of {} frames are not done (the first: frame {first}, {}); `holo farm status` lists them, \
             and submitting the same command again makes them",
            manifest.output.path().display(),
            not_done.len(),
            frames.len(),
            manifest.output.frame_path(first).display()
        )));
    }
    match &manifest.output {
        FarmOutput::Sequence(name) => {
            holo::farm::check_sequence(name, frames.clone())?;
            say!(
                "{}: frames {}..{} present and whole, of one geometry, placement and conversion",
                name.display(),
                frames.start,
                frames.end
            );
            if let Some(join) = &a.join {
                let report = holo::farm::join_sequence(name, frames.clone(), join, a.force)?;
                for w in &report.warnings {
                    warn(format_args!("{}: {w}", join.display()));
                }
                say!("joined {} frames into {} ({} bytes)", frames.len(), join.display(), report.file_bytes);
            }
        }
        FarmOutput::Fringes(folder) => {
            say!("{}: the fringes of frames {}..{} present and whole", folder.display(), frames.start, frames.end);
            if let Some(join) = &a.join {
                let files = holo::farm::join_fringes(folder, frames.clone(), join, a.force)?;
                say!("joined {} frames into {} ({} files)", frames.len(), join.display(), files.len());
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// One array task of a farm (run by the job script).
#[derive(Args)]
pub struct TaskArgs {
    /// The farm's manifest.
    manifest: PathBuf,
    /// Which submission.
    submission: usize,
    /// Which task of its array.
    task: usize,
}

fn task(a: TaskArgs) -> Outcome {
    let folder = a.manifest.parent().unwrap_or(Path::new("."));
    let manifest = Manifest::read(folder)?;
    let submission = manifest
        .submissions
        .get(a.submission)
        .ok_or_else(|| Failure(format!("{}: has no submission {}", a.manifest.display(), a.submission)))?;
    let frames = submission.task_frames(a.task).to_vec();
    say!("task {} of submission {}: frames {:?}", a.task, a.submission, frames);
    let mut failed = Vec::new();
    for n in frames {
        let output = manifest.output.frame_path(n);
        match checked_frame_state(&manifest.output, n, false) {
            FrameState::Done { .. } => {
                say!("frame {n}: done already ({})", output.display());
                continue;
            }
            FrameState::Damaged { why } => warn(format_args!("frame {n}: made again: {why}")),
            FrameState::Missing => {}
        }
        let mut command = frame_job(&manifest.command)?;
        command.job().for_frame(n, output, manifest.placement);
        match command.run() {
            Ok(_) => {}
            Err(Failure(message)) => {
                eprintln!("holo: error: frame {n}: {message}");
                failed.push(n);
            }
        }
    }
    if failed.is_empty() {
        Ok(ExitCode::SUCCESS)
    } else {
        Err(Failure(format!("frames {failed:?} failed")))
    }
}
