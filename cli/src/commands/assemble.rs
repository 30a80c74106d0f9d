//! `holo assemble`: hologram fringes for a layout's frame buffer.

use std::ops::Range;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use holo::assemble::output::{assemble_file, AssembleOptions, FRINGE_SIDECAR};

use super::frame_job::{Decided, FrameJob};
use super::{Failure, Outcome};
use crate::args::{self, layout_help, load_layout, FringeFormatChoice};
use crate::out::{say, warn};
use crate::progress::Reporter;
use holo::farm::FarmOutput;
use holo::math::Mat4;

/// Assemble hologram fringes: one image per head (or colour layer) per
/// frame, laid out as the layout's frame buffer expects.
#[derive(Args)]
pub struct AssembleArgs {
    /// The .holo file, or a numbered sequence named as its one file would be
    /// (shot.holo for shot.0000.holo, shot.0001.holo, …).
    file: PathBuf,
    #[arg(long, default_value = "mark3", help = layout_help(""))]
    layout: String,
    /// Folder for the images and holo-fringes.json (created if needed).
    #[arg(short, long, alias = "out")]
    output: PathBuf,
    /// Frames to assemble: N, A..B (B excluded) or A..=B; default all.
    #[arg(long, value_parser = args::range())]
    frames: Option<Range<usize>>,
    /// How the images are stored.
    #[arg(long, value_enum, default_value = "png")]
    format: FringeFormatChoice,
    /// When the file's geometry is not the layout's, resample it onto the
    /// layout (ray by ray) instead of refusing.
    #[arg(long)]
    resample: bool,
    /// Replace existing files.
    #[arg(long)]
    force: bool,
    /// Print where the time went: seconds in each stage (read, resample, assemble, encode), and per frame.
    #[arg(long)]
    timings: bool,
    #[command(flatten)]
    blanking: args::BlankingArg,
}

pub fn run(a: AssembleArgs) -> Outcome {
    let layout = a.blanking.apply(load_layout(&a.layout)?);
    let options =
        AssembleOptions { frames: a.frames, format: a.format.into(), overwrite: a.force, resample: a.resample };
    let started = Instant::now();
    let report = assemble_file(&a.file, &layout, &a.output, &options, &Reporter::on_stderr())?;
    say!(
        "assembled {} frame(s) of {} for {} in {:.2} s: {} files and {FRINGE_SIDECAR} in {}",
        report.frames.len(),
        a.file.display(),
        layout.name,
        started.elapsed().as_secs_f64(),
        report.files.len() - 1,
        a.output.display()
    );
    if let Some(r) = report.resampled {
        say!(
            "resampled onto {} by rays: {} of {} samples had no ray in the file and are black",
            layout.name,
            r.outside,
            r.total
        );
    }
    if a.timings {
        say!("timings: {}", report.timings.line(report.frames.len()));
    }
    if report.stats.clipped > 0 {
        warn(format_args!(
            "{} samples clipped by the 8-bit quantization (the modulation is brighter than the layout's gain \
             allows; scale it down)",
            report.stats.clipped
        ));
    }
    Ok(ExitCode::SUCCESS)
}

/// An assembly as `holo farm` splits it: one fringe set per frame.
impl FrameJob for AssembleArgs {
    fn output(&self) -> FarmOutput {
        FarmOutput::Fringes(self.output.clone())
    }

    fn decide(&self) -> Result<Decided, Failure> {
        load_layout(&self.layout)?;
        let frames = holo::format::Frames::open(&self.file)?;
        let range = self.frames.clone().unwrap_or_else(|| frames.all());
        frames.check_range(&range)?;
        Ok(Decided { frames: range, placement: None })
    }

    fn for_frame(&mut self, n: usize, output: PathBuf, _: Option<Mat4>) {
        self.frames = Some(n..n + 1);
        self.output = output;
        self.force = true;
    }
}
