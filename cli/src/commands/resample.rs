//! `holo resample`: a `.holo` file with the other parallax.

use clap::{Args, ValueEnum};
use holo::parallax::resample_parallax;

use super::{check_output, inputs_exist, wrote, Failure, Outcome};
use crate::args::{self, WriteArgs};
use crate::out::warn;
use crate::progress::Reporter;

/// Make a .holo file's frames again with the other parallax: full → horizontal
/// as a viewer on the viewer line sees them, horizontal → full with every
/// vertical view a copy of the views.
#[derive(Args)]
pub struct ResampleArgs {
    /// The .holo file.
    input: std::path::PathBuf,
    /// The parallax the output has.
    #[arg(long, value_enum)]
    parallax: ParallaxChoice,
    #[command(flatten)]
    vertical: args::VerticalViewsArgs,
    #[command(flatten)]
    write: WriteArgs,
}

/// `--parallax`: the kind of parallax to make.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ParallaxChoice {
    /// One row of views per emitter, toward the viewer line.
    Horizontal,
    /// A grid of views per emitter (give --vertical-views).
    Full,
}

pub fn run(a: ResampleArgs) -> Outcome {
    inputs_exist(&[&a.input])?;
    let file = holo::HoloFile::open(&a.input)?;
    let g = file.geometry().clone();
    drop(file);
    // A file that has the parallax asked for is refused by the library, naming it.
    let vertical = match (a.parallax, a.vertical.vertical_views) {
        (ParallaxChoice::Horizontal, None) => None,
        (ParallaxChoice::Horizontal, Some(_)) => return Err(Failure("--vertical-views is for --parallax full".into())),
        (ParallaxChoice::Full, None) => {
            return Err(Failure("--parallax full needs --vertical-views N (2 to 64)".into()));
        }
        (ParallaxChoice::Full, Some(count)) => {
            g.with_centred_vertical_views(count, a.vertical.vertical_cone_deg.map(f64::to_radians)).vertical_views
        }
    };
    let _claim = check_output(&a.write.output, &[&a.input], a.write.force)?;
    let run =
        resample_parallax(&a.input, vertical, &a.write.output, a.write.options(String::new()), &Reporter::on_stderr())?;
    run.warnings.iter().for_each(warn);
    wrote(&run.written, &a.write)
}
