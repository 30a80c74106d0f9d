//! `holo export-hci`: a full-parallax frame as an HCI 4D light field
//! benchmark folder.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use holo::cameras::hci::{export_hci_file, MANIFEST, PARAMETERS};
use holo::picture::White;

use super::{inputs_exist, Outcome};
use crate::args::{self, white_help};
use crate::out::{say, warn};

/// Write a full-parallax frame as an HCI 4D light field benchmark folder: input_CamNNN.png per view
/// (8-bit sRGB RGB; camera row 0 the highest vertical view, column 0 the leftmost horizontal view),
/// parameters.cfg, and holo-hci.json.
#[derive(Args)]
pub struct ExportHciArgs {
    /// The .holo file (full parallax).
    file: PathBuf,
    /// Folder for the pictures, parameters.cfg and holo-hci.json (created if needed).
    #[arg(short, long, alias = "out")]
    output: PathBuf,
    /// Frame (0-based, in file order).
    #[arg(long, default_value = "0", value_parser = args::at_least(0))]
    frame: usize,
    #[arg(long, default_value = "1", value_parser = args::white(), help = white_help!("the samples are every view of the frame"))]
    white: White,
    /// Replace existing files.
    #[arg(long)]
    force: bool,
}

pub fn run(a: ExportHciArgs) -> Outcome {
    inputs_exist(&[&a.file])?;
    let export = export_hci_file(&a.file, a.frame, &a.output, a.white, a.force)?;
    export.warnings.iter().for_each(warn);
    let p = &export.parameters;
    say!(
        "wrote {} cameras ({} × {}, {} mm apart, focused {} mm away), {PARAMETERS} and {MANIFEST} to {}, white = {}",
        export.written.len() - 2,
        p.num_cams_x,
        p.num_cams_y,
        holo::geometry::millimetres_text(p.baseline_mm * 1e-3),
        holo::geometry::millimetres_text(p.focus_distance_m),
        a.output.display(),
        export.tone.white
    );
    Ok(ExitCode::SUCCESS)
}
