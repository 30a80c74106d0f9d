//! `holo view`: what an eye sees of the display, by scalar diffraction.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use holo::reconstruct::files::{is_fringe_dir, view_file, EyeAt};

use holo::picture::White;

use super::{check_output, inputs_exist, Outcome};
use crate::args::{self, layout_help, load_layout, white_help};
use crate::out::say;
use crate::progress::Reporter;

/// Simulate the display by scalar diffraction and write the picture a
/// viewer at the given eye position sees (focused on the emitters).
#[derive(Args)]
pub struct ViewArgs {
    /// A .holo file (assembled in memory) or a folder of fringes.
    input: PathBuf,
    #[arg(long, help = layout_help(" (default mark3; a fringe folder names its own)"))]
    layout: Option<String>,
    /// Eye position X[,Y] in millimetres on the viewer's side (X along the
    /// hololines, 0 = centre).
    #[arg(long, value_name = "X[,Y]", default_value = "0", value_parser = args::eye_millimetres(), allow_hyphen_values = true)]
    eye: (f64, f64),
    /// Viewer distance in millimetres (default: the layout's).
    #[arg(long, value_name = "MM", value_parser = args::positive_millimetres())]
    distance: Option<f64>,
    /// Pupil diameter in millimetres.
    #[arg(long, value_name = "MM", default_value = "4", value_parser = args::positive_millimetres())]
    pupil: f64,
    /// A coherent eye: the pupil images the emitter plane and the light of
    /// neighbouring emitters interferes (slower; default: each emitter's
    /// light added as power).
    #[arg(long)]
    coherent: bool,
    /// Frame index (in the source .holo file).
    #[arg(long, default_value = "0", value_parser = args::at_least(0))]
    frame: usize,
    #[arg(long, default_value = "1", value_parser = args::white(),
          help = white_help!("the samples are the picture's brightness, 1 for a fully lit emitter"))]
    white: White,
    /// Output PNG.
    #[arg(short, long)]
    output: PathBuf,
    /// Replace an existing file.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    blanking: args::BlankingArg,
}

pub fn run(a: ViewArgs) -> Outcome {
    inputs_exist(&[&a.input])?;
    let layout = match &a.layout {
        Some(name) => Some(a.blanking.apply(load_layout(name)?)),
        None if is_fringe_dir(&a.input) => None,
        None => Some(a.blanking.apply(load_layout("mark3")?)),
    };
    let _claim = check_output(&a.output, &[&a.input], a.force)?;
    let (x_m, y_m) = a.eye;
    let eye = EyeAt { x_m, y_m, distance_m: a.distance, pupil_m: a.pupil, coherent: a.coherent };
    let picture = view_file(&a.input, layout.as_ref(), a.frame, &[eye], &Reporter::on_stderr())?.remove(0);
    // A black picture from an eye no view reaches says why.
    if let Some(g) = layout.as_ref().map(|l| &l.geometry) {
        let z_m = a.distance.unwrap_or(g.viewer_distance_m);
        let (lo, hi) = g.reach_at_m(z_m);
        let outside = x_m + a.pupil / 2.0 < lo || x_m - a.pupil / 2.0 > hi;
        if outside && picture.data.iter().all(|v| *v == 0.0) {
            crate::out::warn(format_args!(
                "an eye at x = {} mm is outside the viewing zone and sees nothing: at {:.0} mm the views reach x = {:.0} … {:.0} mm",
                (x_m * 1e6).round() / 1e3,
                z_m * 1e3,
                lo * 1e3,
                hi * 1e3
            ));
        }
    }
    let white = a.white.level(picture.data.iter().copied());
    picture.write_png(&a.output, white, a.force)?;
    say!(
        "wrote {}: what an eye at x = {} mm sees of {} ({} × {} emitters × hololines)",
        a.output.display(),
        // Whole micrometres, so the millimetres typed come back as typed.
        (x_m * 1e6).round() / 1e3,
        a.input.display(),
        picture.emitters,
        picture.hololines
    );
    Ok(ExitCode::SUCCESS)
}
