//! `holo check`: recover a frame from its fringes and print the error.

use std::ops::Range;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use holo::reconstruct::files::{check_file, CheckOptions};

use super::Outcome;
use crate::args::{self, layout_help, load_layout};
use crate::out::{json, put};
use crate::progress::Reporter;

/// Recover a frame's modulation from its fringes (least squares, and
/// through the optics by scalar diffraction) and print the error against
/// the stored modulation.
#[derive(Args)]
pub struct CheckArgs {
    /// The .holo file.
    file: PathBuf,
    #[arg(long, help = layout_help(" (default: the fringes' own with --fringes, else mark3)"))]
    layout: Option<String>,
    /// Frame index in the file.
    #[arg(long, default_value = "0", value_parser = args::at_least(0))]
    frame: usize,
    /// Check fringes `holo assemble` already wrote to this folder instead
    /// of assembling them (8-bit, in memory).
    #[arg(long)]
    fringes: Option<PathBuf>,
    /// Hololines to check: N, A..B or A..=B (default: all).
    #[arg(long, value_parser = args::range())]
    hololines: Option<Range<usize>>,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(a: CheckArgs) -> Outcome {
    let layout = match (&a.layout, &a.fringes) {
        (Some(name), _) => Some(load_layout(name)?),
        (None, Some(_)) => None,
        (None, None) => Some(load_layout("mark3")?),
    };
    let options = CheckOptions { frame: a.frame, fringes: a.fringes, hololines: a.hololines };
    let checked = check_file(&a.file, layout.as_ref(), &options, &Reporter::on_stderr())?;
    if a.json {
        json(&checked)?;
    } else {
        put!("{checked}");
    }
    Ok(ExitCode::SUCCESS)
}
