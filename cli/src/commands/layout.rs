//! `holo layout`: a layout as a profile, the start of a custom one.

use std::process::ExitCode;

use clap::Args;

use super::Outcome;
use crate::args::{layout_help, load_layout};
use crate::out::{json, put};

/// Print a layout profile (TOML, or JSON with --json): the numbers a
/// layout uses, and a starting point for a custom profile.
#[derive(Args)]
pub struct LayoutArgs {
    #[arg(help = layout_help(""))]
    name: String,
    /// Print JSON instead of TOML.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    blanking: crate::args::BlankingArg,
}

pub fn run(a: LayoutArgs) -> Outcome {
    let layout = a.blanking.apply(load_layout(&a.name)?);
    if a.json {
        json(&layout)?;
    } else {
        put!("{}", layout.to_toml());
    }
    Ok(ExitCode::SUCCESS)
}
