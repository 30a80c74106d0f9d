//! `holo export-quilt`: a frame as a Looking Glass quilt.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use holo::cameras::quilt::{export_quilt, quilt_file_name, view_cone_deg_for, QuiltOptions};

use holo::picture::White;

use super::{check_output, inputs_exist, Failure, Outcome};
use crate::args::{self, white_help, PresetChoice};
use crate::out::{say, warn};

/// Write a frame as a Looking Glass quilt (8-bit sRGB PNG): one view per
/// camera on a horizontal rail facing the display, view 0 (leftmost) in the
/// bottom-left tile, named NAME_qsCxRaA.png for the Looking Glass software.
#[derive(Args)]
pub struct ExportQuiltArgs {
    /// The .holo file.
    file: PathBuf,
    /// Output PNG (default: the quilt's conventional name next to FILE).
    #[arg(short, long, conflicts_with = "output_dir")]
    output: Option<PathBuf>,
    /// Folder for the quilt, under its conventional name (created if needed).
    #[arg(long)]
    output_dir: Option<PathBuf>,
    /// Frame (0-based, in file order).
    #[arg(long, default_value = "0", value_parser = args::at_least(0))]
    frame: usize,
    /// Quilt settings of a Looking Glass.
    #[arg(long, value_enum, default_value = "portrait")]
    preset: PresetChoice,
    /// Tiles per row, instead of the preset's.
    #[arg(long, value_parser = args::at_least(1))]
    columns: Option<usize>,
    /// Rows of tiles, instead of the preset's.
    #[arg(long, value_parser = args::at_least(1))]
    rows: Option<usize>,
    /// Tile size in pixels, WxH, instead of the preset's.
    #[arg(long, value_parser = args::by(usize::MAX, false))]
    tile: Option<(usize, usize)>,
    /// Width/height of a view as the display shows it, instead of the preset's.
    #[arg(long, value_parser = args::positive())]
    aspect: Option<f64>,
    /// Angle between the outermost views, degrees (default: the file's own
    /// view range; HoloPlay renders with 35). The outer tiles see the
    /// display's far side from beyond the file's views, black there: which
    /// tiles is said, with the cone that shows every tile whole.
    #[arg(long, value_name = "DEG", value_parser = args::angle_below_180_degrees())]
    view_cone: Option<f64>,
    #[arg(long, default_value = "auto", value_parser = args::white(), help = white_help!("the samples are the quilt's pixels"))]
    white: White,
    /// Replace an existing file.
    #[arg(long)]
    force: bool,
}

pub fn run(a: ExportQuiltArgs) -> Outcome {
    inputs_exist(&[&a.file])?;
    let mut spec = a.preset.spec()?;
    spec.columns = a.columns.unwrap_or(spec.columns);
    spec.rows = a.rows.unwrap_or(spec.rows);
    if let Some((w, h)) = a.tile {
        (spec.tile_width, spec.tile_height) = (w, h);
    }
    spec.aspect = a.aspect.unwrap_or(spec.aspect);
    spec.view_cone_deg = match a.view_cone {
        Some(deg) => deg,
        None => view_cone_deg_for(&holo::HoloFile::open(&a.file)?.info().geometry.views),
    };
    let name = || {
        let stem = a.file.file_stem().map_or("quilt".into(), |s| s.to_string_lossy().into_owned());
        quilt_file_name(&stem, &spec)
    };
    let out = match (&a.output, &a.output_dir) {
        (Some(path), _) => path.clone(),
        (None, Some(dir)) => {
            // The folder is made only for an input that opens.
            holo::HoloFile::open(&a.file)?;
            std::fs::create_dir_all(dir).map_err(|e| Failure(format!("{}: {e}", dir.display())))?;
            dir.join(name())
        }
        (None, None) => a.file.with_file_name(name()),
    };
    let _claim = check_output(&out, &[&a.file], a.force)?;
    let report = export_quilt(&a.file, a.frame, &spec, &out, &QuiltOptions { white: a.white, overwrite: a.force })?;
    report.warnings.iter().for_each(warn);
    say!(
        "wrote {}: a {}×{} quilt of {} views ({}×{} tiles of {}×{}, a {:.1}° view cone) of frame {} of {}, white = {}",
        report.path.display(),
        report.width,
        report.height,
        report.views,
        spec.columns,
        spec.rows,
        spec.tile_width,
        spec.tile_height,
        spec.view_cone_deg,
        a.frame,
        a.file.display(),
        report.white
    );
    Ok(ExitCode::SUCCESS)
}
