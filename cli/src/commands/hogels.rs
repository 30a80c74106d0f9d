//! `holo export-hogels` and `holo import-hogels`: one PNG per hogel, as
//! holographic-stereogram printers take them, and back.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use holo::hogels::{export_hogels_file, import_hogels_file, MANIFEST};
use holo::picture::White;

use super::{check_output, inputs_exist, wrote, Failure, Outcome};
use crate::args::{self, layout_geometry, white_help, PngBits, WriteArgs};
use crate::out::say;
use crate::progress::Reporter;

/// Write each hogel (emitter) of a frame as a PNG of its views, hogel_RRR_CCC.png in raster order
/// (row 0 at the top), plus holo-hogels.json: pixel column h is horizontal view h, the top pixel row the
/// highest vertical view.
#[derive(Args)]
pub struct ExportHogelsArgs {
    /// The .holo file.
    file: PathBuf,
    /// Folder for the PNGs and holo-hogels.json (created if needed).
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

pub fn run_export(a: ExportHogelsArgs) -> Outcome {
    inputs_exist(&[&a.file])?;
    let export = export_hogels_file(&a.file, a.frame, &a.output, a.white, a.bits.bits(), a.force)?;
    say!(
        "wrote {} hogel PNGs and {MANIFEST} to {}, white = {}",
        export.written.len() - 1,
        a.output.display(),
        export.tone.white
    );
    Ok(ExitCode::SUCCESS)
}

/// Build a .holo file from a folder of hogel PNGs (the inverse of export-hogels).
#[derive(Args)]
pub struct ImportHogelsArgs {
    /// Folder holding hogel_000_000.png, …
    dir: PathBuf,
    /// Geometry: a layout name, a layout profile or a geometry .json (default: DIR/holo-hogels.json).
    #[arg(long)]
    geometry: Option<String>,
    /// Sample value of full white, a positive number (default: the manifest's, else 1).
    #[arg(long, value_parser = args::white_number())]
    white: Option<f32>,
    #[command(flatten)]
    write: WriteArgs,
}

pub fn run_import(a: ImportHogelsArgs) -> Outcome {
    inputs_exist(&[&a.dir])?;
    let manifest = holo::hogels::folder_hogel_manifest(&a.dir)?;
    let g = match (&a.geometry, &manifest) {
        (Some(name), _) => layout_geometry(name)?,
        (None, Some(m)) => m.geometry.clone(),
        (None, None) => {
            return Err(Failure(format!(
                "{}: no {MANIFEST} here; say which geometry with --geometry LAYOUT|FILE.json",
                a.dir.display()
            )))
        }
    };
    // Every file of the folder counts as an input here, not only the pictures.
    let _claim = check_output(&a.write.output, &[a.dir.as_path()], a.write.force)?;
    let mut tone = manifest.map(|m| m.tone).unwrap_or_default();
    if let Some(w) = a.white {
        tone.white = w;
    }
    let options = a.write.options(String::new());
    let run = import_hogels_file(&a.dir, &g, &tone, &a.write.output, options, &Reporter::on_stderr())?;
    wrote(&run.written, &a.write)
}
