//! `holo view`: what an eye sees of the display, by scalar diffraction.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use holo::format::HoloFile;
use holo::reconstruct::files::{is_fringe_dir, view_file, EyeAt};
use holo::reconstruct::light_field::{eye_view, EyePoint};

use holo::picture::White;

use super::{check_output, inputs_exist, Failure, Outcome};
use crate::args::{self, layout_help, load_layout, white_help};
use crate::out::say;
use crate::progress::Reporter;

/// Simulate the display by scalar diffraction and write the picture a
/// viewer at the given eye position sees (focused on the emitters); a
/// full-parallax file, which has no fringes yet, is seen from its own rays.
#[derive(Args)]
pub struct ViewArgs {
    /// A .holo file (assembled in memory) or a folder of fringes.
    input: PathBuf,
    #[arg(long, help = layout_help(" (default mark3; a fringe folder names its own)"))]
    layout: Option<String>,
    /// Eye position X[,Y] in millimetres on the viewer's side (X along the
    /// hololines, Y up, 0 = centre; Y matters for a full-parallax file).
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
    if !is_fringe_dir(&a.input) && a.input.is_file() {
        let file = HoloFile::open(&a.input)?;
        if file.geometry().vertical_views.is_some() {
            return full_parallax(a, file);
        }
    }
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

/// `holo view` of a full-parallax file: what an eye sees of its rays
/// ([`holo::reconstruct::light_field`]), with no layout or fringes.
fn full_parallax(a: ViewArgs, file: HoloFile) -> Outcome {
    let fringe_only =
        [(a.layout.is_some(), "--layout"), (a.coherent, "--coherent"), (a.blanking.raw_blanking, "--raw-blanking")];
    if let Some((_, flag)) = fringe_only.iter().find(|(given, _)| *given) {
        return Err(Failure(format!(
            "{}: a full-parallax file is seen from its own rays, with no fringes; {flag} is for horizontal-parallax files and fringe folders",
            a.input.display()
        )));
    }
    let _claim = check_output(&a.output, &[&a.input], a.force)?;
    let g = file.geometry().clone();
    let (x_m, y_m) = a.eye;
    let z_m = a.distance.unwrap_or(g.viewer_distance_m);
    let m = file.read_frame(a.frame)?;
    let eye = EyePoint { centre_m: [x_m, y_m, z_m], pupil_m: a.pupil };
    let (picture, unseen) = eye_view(&m, &eye)?;
    if unseen > 0 {
        crate::out::warn(format_args!(
            "an eye at ({}, {}) mm, {:.0} mm away, is beyond every view of {unseen} of the {} emitters: they are black",
            (x_m * 1e6).round() / 1e3,
            (y_m * 1e6).round() / 1e3,
            z_m * 1e3,
            g.emitters * g.hololines
        ));
    }
    let white = a.white.level(picture.data.iter().copied());
    picture.write_png(&a.output, white, a.force)?;
    say!(
        "wrote {}: what an eye at ({}, {}) mm sees of the full-parallax {} ({} × {} emitters, {} × {} views)",
        a.output.display(),
        (x_m * 1e6).round() / 1e3,
        (y_m * 1e6).round() / 1e3,
        a.input.display(),
        picture.emitters,
        picture.hololines,
        g.views.count,
        g.vertical_view_count()
    );
    Ok(ExitCode::SUCCESS)
}
