//! `holo check`: recover frames from their fringes, print the errors, and
//! judge them by the bounds spec/layouts.md §9.1 states.

use std::ops::Range;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use holo::reconstruct::files::{check_file, CheckOptions, FileCheck};

use super::{Failure, Outcome};
use crate::args::{self, layout_help, load_layout};
use crate::out::{json, put, say};
use crate::progress::Reporter;

/// Recover a frame's modulation from its fringes (least squares, and
/// through the optics by scalar diffraction), print the errors against the
/// stored modulation, and judge them by the bounds spec/layouts.md §9.1
/// states (pass or fail per figure and overall; exit 1 on a failure unless
/// --report-only).
#[derive(Args)]
pub struct CheckArgs {
    /// The .holo file.
    file: PathBuf,
    #[arg(long, help = layout_help(" (default: the fringes' own with --fringes, else mark3)"))]
    layout: Option<String>,
    /// Frame index in the file.
    #[arg(long, default_value = "0", value_parser = args::at_least(0), conflicts_with = "frames")]
    frame: usize,
    /// Frames to check, one after another: N, A..B or A..=B (a movie); the verdict is over all of them.
    #[arg(long, value_parser = args::range())]
    frames: Option<Range<usize>>,
    /// Check fringes `holo assemble` already wrote to this folder instead
    /// of assembling them (8-bit, in memory).
    #[arg(long)]
    fringes: Option<PathBuf>,
    /// Hololines to check: N, A..B or A..=B (default: all).
    #[arg(long, value_parser = args::range())]
    hololines: Option<Range<usize>>,
    /// Print JSON instead of text (with each figure's bound and verdict).
    #[arg(long)]
    json: bool,
    /// Print the figures and verdicts but exit 0 whatever they are (for scripts that collect figures);
    /// without it a figure outside its bound exits 1.
    #[arg(long)]
    report_only: bool,
}

pub fn run(a: CheckArgs) -> Outcome {
    let layout = match (&a.layout, &a.fringes) {
        (Some(name), _) => Some(load_layout(name)?),
        (None, Some(_)) => None,
        (None, None) => Some(load_layout("mark3")?),
    };
    let frames = match &a.frames {
        Some(range) => {
            let count = holo::HoloFile::open(&a.file)?.info().frames.len();
            if range.end > count {
                return Err(holo::Error::NoFrame { path: a.file.clone(), asked: range.clone(), frames: count }.into());
            }
            range.clone()
        }
        None => a.frame..a.frame + 1,
    };
    let mut checked: Vec<FileCheck> = Vec::with_capacity(frames.len());
    for frame in frames.clone() {
        let options = CheckOptions { frame, fringes: a.fringes.clone(), hololines: a.hololines.clone() };
        let one = check_file(&a.file, layout.as_ref(), &options, &Reporter::on_stderr())?;
        if !a.json {
            put!("{one}");
        }
        checked.push(one);
    }
    let failed: Vec<usize> = checked.iter().filter(|c| c.report.verdict.pass == Some(false)).map(|c| c.frame).collect();
    let pass = match (failed.is_empty(), checked.iter().any(|c| c.report.verdict.pass.is_some())) {
        (false, _) => Some(false),
        (true, true) => Some(true),
        (true, false) => None,
    };
    if a.json {
        match a.frames {
            Some(_) => json(&serde_json::json!({ "file": a.file, "frames": checked, "pass": pass }))?,
            None => json(&checked[0])?,
        }
    } else if a.frames.is_some() {
        let verdict = match pass {
            Some(true) => "pass",
            Some(false) => "FAIL",
            None => "none (no bound stated)",
        };
        say!("verdict over frames {}..{}: {verdict}", frames.start, frames.end);
    }
    match (pass, a.report_only) {
        (Some(false), false) => {
            let list: Vec<String> = failed.iter().map(usize::to_string).collect();
            Err(Failure(format!(
                "{}: frame(s) {} recovered outside the bounds of spec/layouts.md §9.1 (--report-only exits 0)",
                a.file.display(),
                list.join(", ")
            )))
        }
        _ => Ok(ExitCode::SUCCESS),
    }
}
