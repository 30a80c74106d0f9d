//! `holo export-views` and `holo import-views`: one PNG per view, and back.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use holo::views::{import_views_file, ToneMapping, SIDECAR};

use holo::picture::White;

use super::{check_output, inputs_exist, wrote, Failure, Outcome};
use crate::args::{self, layout_geometry, white_help, PngBits, WriteArgs};
use crate::out::say;
use crate::progress::Reporter;

/// Write each view of a frame as a PNG (view_000.png, …) plus holo-views.json.
#[derive(Args)]
pub struct ExportViewsArgs {
    /// The .holo file.
    file: PathBuf,
    /// Folder for the PNGs and holo-views.json (created if needed).
    #[arg(short, long, alias = "out")]
    output: PathBuf,
    /// Frame (0-based, in file order).
    #[arg(long, default_value = "0", value_parser = args::at_least(0))]
    frame: usize,
    /// Bits per component.
    #[arg(long, value_enum, default_value = "16")]
    bits: PngBits,
    #[arg(long, default_value = "1", value_parser = args::white(), help = white_help!("the samples are every view of the frame"))]
    white: White,
    /// Replace existing PNGs.
    #[arg(long)]
    force: bool,
}

pub fn run_export(a: ExportViewsArgs) -> Outcome {
    let holo_file = holo::HoloFile::open(&a.file)?;
    let g = holo_file.geometry();
    let names: Vec<String> = (0..g.views_per_emitter()).map(|v| holo::views::view_file_name_of(g, v)).collect();
    let _claim = holo::output::check_set_output(&a.output, SIDECAR, &names, &[&a.file], a.force)?;
    let m = holo_file.read_frame(a.frame)?;
    let white = a.white.level(m.samples().iter().copied());
    let tone = ToneMapping { white, bits: a.bits.bits() };
    let written = holo::views::export_views(&m, &a.output, &tone, a.force)?;
    say!("wrote {} view PNGs and {} to {}, white = {white}", written.len() - 1, SIDECAR, a.output.display());
    Ok(ExitCode::SUCCESS)
}

/// Build a .holo file from a folder of view PNGs (the inverse of export-views).
#[derive(Args)]
pub struct ImportViewsArgs {
    /// Folder holding view_000.png, …
    dir: PathBuf,
    /// Geometry: a layout name, a layout profile or a geometry .json (default: DIR/holo-views.json).
    #[arg(long)]
    geometry: Option<String>,
    /// Sample value of full white, a positive number (default: the sidecar's, else 1).
    #[arg(long, value_parser = args::white_number())]
    white: Option<f32>,
    #[command(flatten)]
    write: WriteArgs,
}

pub fn run_import(a: ImportViewsArgs) -> Outcome {
    inputs_exist(&[&a.dir])?;
    let sidecar = holo::views::folder_sidecar(&a.dir)?;
    let g = match (&a.geometry, &sidecar) {
        (Some(name), _) => layout_geometry(name)?,
        (None, Some(s)) => s.geometry.clone(),
        (None, None) => {
            return Err(Failure(format!(
                "{}: no {SIDECAR} here; say which geometry with --geometry LAYOUT|FILE.json",
                a.dir.display()
            )))
        }
    };
    // Every file of the folder counts as an input here, not only the pictures.
    let _claim = check_output(&a.write.output, &[a.dir.as_path()], a.write.force)?;
    let mut tone = sidecar.map(|s| s.tone).unwrap_or_default();
    if let Some(w) = a.white {
        tone.white = w;
    }
    let options = a.write.options(String::new());
    let run = import_views_file(&a.dir, &g, &tone, &a.write.output, options, &Reporter::on_stderr())?;
    wrote(&run.written, &a.write)
}
