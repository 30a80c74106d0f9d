//! `holo export-views` and `holo import-views`: one PNG per view, and back;
//! the import of every set of pictures (`import-hogels` too).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use holo::pictures::{import_pictures_file, PictureSet};
use holo::views::{ToneMapping, SIDECAR};

use super::{check_output, inputs_exist, wrote, Failure, Outcome};
use crate::args::{layout_geometry, PictureExportArgs, PictureImportArgs};
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
    #[command(flatten)]
    export: PictureExportArgs,
}

pub fn run_export(a: ExportViewsArgs) -> Outcome {
    let PictureExportArgs { frame, bits, white, force } = a.export;
    let holo_file = holo::HoloFile::open(&a.file)?;
    let g = holo_file.geometry();
    let names: Vec<String> = (0..g.views_per_emitter()).map(|v| holo::views::view_file_name_of(g, v)).collect();
    let _claim = holo::output::check_set_output(&a.output, SIDECAR, &names, &[&a.file], force)?;
    let m = holo_file.read_frame(frame)?;
    let white = white.level(m.samples().iter().copied());
    let tone = ToneMapping { white, bits: bits.bits() };
    let written = holo::views::export_views(&m, &a.output, &tone, force)?;
    say!("wrote {} view PNGs and {} to {}, white = {white}", written.len() - 1, SIDECAR, a.output.display());
    Ok(ExitCode::SUCCESS)
}

/// Build a .holo file from a folder of view PNGs (the inverse of export-views).
#[derive(Args)]
pub struct ImportViewsArgs {
    /// Folder holding view_000.png, … and holo-views.json
    dir: PathBuf,
    #[command(flatten)]
    import: PictureImportArgs,
}

pub fn run_import(a: ImportViewsArgs) -> Outcome {
    run_import_set(PictureSet::Views, &a.dir, &a.import)
}

/// `import-views` and `import-hogels`: the pictures of kind `set` in `dir`
/// into a `.holo` file, their geometry and tone from the folder's manifest
/// unless the arguments say them.
pub(super) fn run_import_set(set: PictureSet, dir: &Path, a: &PictureImportArgs) -> Outcome {
    let (geometry, white, write) = (a.geometry.as_deref(), a.white, &a.write);
    inputs_exist(&[dir])?;
    let manifest = set.folder_manifest(dir)?;
    let g = match (geometry, &manifest) {
        (Some(name), _) => layout_geometry(name)?,
        (None, Some((g, _))) => g.clone(),
        (None, None) => {
            return Err(Failure(format!(
                "{}: no {} here; say which geometry with --geometry LAYOUT|FILE.json",
                dir.display(),
                set.manifest()
            )))
        }
    };
    // Every file of the folder counts as an input here, not only the pictures.
    let _claim = check_output(&write.output, &[dir], write.force)?;
    let mut tone = manifest.map(|(_, tone)| tone).unwrap_or_default();
    if let Some(w) = white {
        tone.white = w;
    }
    let options = write.options(String::new());
    let run = import_pictures_file(set, dir, &g, &tone, &write.output, options, &Reporter::on_stderr())?;
    wrote(&run.written, write)
}
