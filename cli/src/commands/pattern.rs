//! `holo pattern`: a display-engineering test pattern for a layout.

use std::path::Path;

use clap::Args;
use holo::pattern::{write_pattern, Pattern};

use super::{check_output, wrote, Outcome};
use crate::args::{self, layout_help, ChannelsChoice, PatternChoice, WriteArgs};
use crate::progress::Reporter;

/// Write a display-engineering test pattern for a layout.
#[derive(Args)]
pub struct PatternArgs {
    #[arg(long, default_value = "mark3", help = layout_help(", or a geometry .json"))]
    layout: String,
    /// Which pattern.
    #[arg(long, value_enum)]
    kind: PatternChoice,
    /// Emitter lit by single-emitter (default: the centre).
    #[arg(long, value_parser = args::at_least(0))]
    emitter: Option<usize>,
    /// View lit by single-view (default: the centre).
    #[arg(long, value_parser = args::at_least(0))]
    view: Option<usize>,
    /// Full parallax: vertical view lit by single-view (default: the centre; 0 the lowest).
    #[arg(long, value_parser = args::at_least(0))]
    vertical_view: Option<usize>,
    /// Spacing of every-nth-emitter, in emitters.
    #[arg(long, default_value = "8", value_parser = args::at_least(1))]
    every: usize,
    /// Square size of checkerboard, in hololines and emitters.
    #[arg(long, default_value = "8", value_parser = args::at_least(1))]
    cell: usize,
    /// Radiance of a lit sample.
    #[arg(long, default_value = "1", value_parser = args::non_negative_f32())]
    level: f32,
    /// Colour channels instead of the layout's own.
    #[arg(long, value_enum)]
    channels: Option<ChannelsChoice>,
    #[command(flatten)]
    vertical: args::VerticalViewsArgs,
    #[command(flatten)]
    write: WriteArgs,
}

pub fn run(a: PatternArgs) -> Outcome {
    let mut geometry = a.vertical.geometry(&a.layout)?;
    let _claim = check_output(&a.write.output, &[Path::new(&a.layout)], a.write.force)?;
    if let Some(c) = a.channels {
        geometry.channels = c.channels();
    }
    let pattern = Pattern {
        kind: a.kind.0,
        emitter: a.emitter,
        view: a.view,
        vertical_view: a.vertical_view,
        every: a.every,
        cell: a.cell,
        level: a.level,
    };
    let options = a.write.options(format!("{} layout={}", pattern.describe(), a.layout));
    let run = write_pattern(&pattern, &geometry, &a.write.output, options, &Reporter::on_stderr())?;
    wrote(&run.written, &a.write)
}
