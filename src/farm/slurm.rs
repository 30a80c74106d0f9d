//! The Slurm commands a farm runs: `sbatch` to submit a job array,
//! `squeue` (and `sacct`, where the cluster keeps accounting) for the state
//! of its tasks. Each is found on `PATH` before anything is submitted.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::error::{Error, Result};

/// `tool` on `PATH`, or the sentence saying it is not there.
pub fn find(tool: &str) -> Result<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path).map(|folder| folder.join(tool)).find(|candidate| is_executable(candidate)).ok_or_else(
        || {
            Error::argument(
                "Slurm",
                format!(
                    "{tool} is not on PATH: holo farm submits to a Slurm cluster and needs its commands \
                     (run it on the cluster's login node, or load its module)"
                ),
            )
        },
    )
}

fn is_executable(path: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    path.metadata().is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

/// What an `sbatch` of a job array is given.
#[derive(Clone, Debug)]
pub struct ArrayJob<'a> {
    /// The job script.
    pub script: &'a Path,
    /// Tasks `0..tasks`.
    pub tasks: usize,
    /// The job's name in `squeue`.
    pub name: &'a str,
    /// Each task's log (`%A` the job, `%a` the task).
    pub log: &'a Path,
    /// The folder tasks start in.
    pub working_folder: &'a Path,
    /// The user's own options, after holo's (so they win).
    pub user_options: &'a [String],
}

/// Submit `job` with `sbatch`; its job id.
pub fn submit(job: &ArrayJob) -> Result<String> {
    let sbatch = find("sbatch")?;
    let output = Command::new(&sbatch)
        .arg("--parsable")
        .arg(format!("--array=0-{}", job.tasks.saturating_sub(1)))
        .arg(format!("--job-name={}", job.name))
        .arg(format!("--output={}", job.log.display()))
        .arg(format!("--chdir={}", job.working_folder.display()))
        .args(job.user_options)
        .arg(job.script)
        .output()
        .map_err(|e| Error::io(&sbatch, e))?;
    if !output.status.success() {
        return Err(refused("sbatch", &output.stderr));
    }
    let text = String::from_utf8_lossy(&output.stdout);
    // `--parsable` prints `ID` or `ID;CLUSTER`.
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() || !id.bytes().all(|b| b.is_ascii_digit()) {
        return Err(Error::argument("Slurm", format!("sbatch printed no job id: {:?}", text.trim())));
    }
    Ok(id)
}

/// What a Slurm command said when it refused, as one sentence.
fn refused(tool: &str, stderr: &[u8]) -> Error {
    let text = String::from_utf8_lossy(stderr);
    let line = text.lines().map(str::trim).find(|l| !l.is_empty()).unwrap_or("no reason given");
    let line = line.strip_prefix(&format!("{tool}: ")).unwrap_or(line);
    let line = line.strip_prefix("error: ").unwrap_or(line);
    Error::argument("Slurm", format!("{tool} refused the job: {line}"))
}

/// The state of every task of job array `job_id` that Slurm still knows
/// (`PENDING`, `RUNNING`, `COMPLETED`, `CANCELLED`, `FAILED`, …): `squeue`
/// for jobs it holds, then `sacct` for finished ones where the cluster keeps
/// accounting. Tasks neither knows are absent.
pub fn task_states(job_id: &str) -> BTreeMap<usize, String> {
    let mut states = BTreeMap::new();
    let sacct = ["--noheader", "--parsable2", "--allocations", "--format=JobID,State", "--jobs", job_id];
    let squeue = ["--noheader", "--array", "--states=all", "--format=%i|%T", "--jobs", job_id];
    // squeue second: what the scheduler holds now is the newer word.
    for (tool, args) in [("sacct", sacct), ("squeue", squeue)] {
        for (id, state) in lines_of(tool, &args) {
            if let Some(task) = array_index(&id, job_id) {
                states.insert(task, first_word(&state));
            }
        }
    }
    states
}

/// `ID|STATE` lines a Slurm command prints (none when it is missing or fails:
/// a cluster without accounting refuses `sacct`).
fn lines_of(tool: &str, args: &[&str]) -> Vec<(String, String)> {
    let Ok(program) = find(tool) else { return Vec::new() };
    match Command::new(program).args(args).output() {
        Ok(out) if out.status.success() => String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|l| l.trim().split_once('|').map(|(a, b)| (a.to_string(), b.to_string())))
            .collect(),
        _ => Vec::new(),
    }
}

/// Task `i` of `123_i`, when the id is of job `job_id`.
fn array_index(id: &str, job_id: &str) -> Option<usize> {
    id.trim().strip_prefix(job_id)?.strip_prefix('_')?.parse().ok()
}

/// `CANCELLED by 0` → `CANCELLED`.
fn first_word(state: &str) -> String {
    state.split_whitespace().next().unwrap_or("").to_string()
}

/// Whether a task in `state` may still make its frames.
pub fn is_active(state: &str) -> bool {
    matches!(state, "PENDING" | "RUNNING" | "CONFIGURING" | "COMPLETING" | "REQUEUED" | "RESIZING" | "SUSPENDED")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn array_task_ids_are_read_only_for_their_job() {
        assert_eq!(array_index("123_4", "123"), Some(4));
        assert_eq!(array_index("1234_4", "123"), None);
        assert_eq!(array_index("123_[4-7]", "123"), None);
        assert_eq!(array_index("123", "123"), None);
        assert_eq!(first_word("CANCELLED by 0"), "CANCELLED");
    }
}
