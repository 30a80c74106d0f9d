//! `holo demo`: the main job on built-in defaults.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

mod canvas;
mod chain;
mod eyes;
pub mod font;
mod fringe;
mod full_parallax;
mod movie;
mod text;

/// What the command line's tests check of the demo's drawing.
pub mod parts {
    pub use super::canvas::{apng, Canvas, WHITE};
    pub use super::chain::viewing_zone_eyes_x_m;
    pub use super::font;
    pub use super::fringe::{fringe_picture, label_height, line_chars, MARGIN, THUMBNAIL_SHRINK};
}

use super::Outcome;
use crate::out::put;
use crate::progress::Reporter;

/// Run the main job on built-in defaults and say where the results are.
#[derive(Args)]
pub struct DemoArgs {
    /// Folder for the demo's files: new, empty, or an earlier demo's (whose
    /// files are replaced); a folder of other files is refused.
    #[arg(short, long, alias = "out", default_value = "holo-demo")]
    output: PathBuf,
}

pub fn run(a: DemoArgs) -> Outcome {
    let demo = chain::demo(&a.output, &Reporter::on_stderr())?;
    put!("{demo}");
    Ok(ExitCode::SUCCESS)
}
