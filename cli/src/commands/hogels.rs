//! `holo export-hogels` and `holo import-hogels`: one PNG per hogel, as
//! holographic-stereogram printers take them, and back.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use holo::hogels::{export_hogels_file, MANIFEST};
use holo::pictures::PictureSet;

use super::{inputs_exist, Outcome};
use crate::args::{PictureExportArgs, PictureImportArgs};
use crate::out::say;

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
    #[command(flatten)]
    export: PictureExportArgs,
}

pub fn run_export(a: ExportHogelsArgs) -> Outcome {
    inputs_exist(&[&a.file])?;
    let PictureExportArgs { frame, bits, white, force } = a.export;
    let export = export_hogels_file(&a.file, frame, &a.output, white, bits.bits(), force)?;
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
    /// Folder holding hogel_000_000.png, … and holo-hogels.json
    dir: PathBuf,
    #[command(flatten)]
    import: PictureImportArgs,
}

pub fn run_import(a: ImportHogelsArgs) -> Outcome {
    super::views::run_import_set(PictureSet::Hogels, &a.dir, &a.import)
}
