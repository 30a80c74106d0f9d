//! The `holo` command: parses the command line and hands each subcommand to
//! its function in [`commands`], which calls the library and prints. Exit
//! codes: 0 ok, 1 error (one sentence), 2 usage (the command line is wrong:
//! clap's own errors and every value [`args`] refuses). Interrupted by
//! SIGINT, SIGTERM or SIGHUP, it removes what it had half written and exits
//! 130, 143 or 129.
//!
//! A library that `main.rs` calls, not a binary with unit tests of its own:
//! `cargo test` builds a binary's unit tests by compiling the whole command
//! line a second time, the longest step of a clean test build after the
//! `holo` library. Its tests are in `tests/cli/`, those of its parts through
//! [`parts`].

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

mod args;
mod commands;
mod failure;
mod out;
mod progress;

/// The parts of the command line its tests check one by one
/// (`tests/cli/parts.rs`): value parsers, and the demo's drawing.
#[doc(hidden)]
pub mod parts {
    pub use crate::args::*;
    pub use crate::commands::demo::parts::*;
    pub use crate::failure::Failure;
}

use commands::*;

#[derive(Parser)]
#[command(name = "holo", version, about = "The .holo modulation-texture file for holographic stereogram displays", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// Parsed once per run: the size of its largest variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    Info(info::InfoArgs),
    Validate(validate::ValidateArgs),
    Pattern(pattern::PatternArgs),
    Resample(resample::ResampleArgs),
    ExportViews(views::ExportViewsArgs),
    ExportQuilt(quilt::ExportQuiltArgs),
    ImportViews(views::ImportViewsArgs),
    ExportHogels(hogels::ExportHogelsArgs),
    ImportHogels(hogels::ImportHogelsArgs),
    ExportHci(hci::ExportHciArgs),
    Assemble(assemble::AssembleArgs),
    Check(check::CheckArgs),
    View(view::ViewArgs),
    Layout(layout::LayoutArgs),
    Demo(demo::DemoArgs),
    /// Convert content into a .holo file.
    #[command(subcommand)]
    Convert(convert::ConvertCommand),
    /// HoloFlicks (.hflk) and Java 3D compressed geometry (.cg): info, pack, encode, unpack.
    #[command(subcommand)]
    Holoflick(holoflick::HoloflickCommand),
    /// A movie across a Slurm cluster: submit a frame-making command as a job array, its status, gather.
    #[command(subcommand)]
    Farm(farm::FarmCommand),
}

/// The `holo` command, run on this process's arguments.
pub fn main() -> ExitCode {
    // First, so an interrupt at any later point removes what is half written.
    if let Err(e) = holo::output::install_interrupt_cleanup() {
        out::warn(format_args!(
            "cannot watch for interrupts ({e}); an interrupted write may leave hidden temporary files"
        ));
    }
    let matches = args::negative_numbers(Cli::command()).get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    // A panic is a bug; still, the user gets one sentence, not a backtrace.
    std::panic::set_hook(Box::new(|info| {
        eprintln!("holo: internal error ({info}); please report it");
    }));
    let outcome = std::panic::catch_unwind(|| run(cli.command));
    // What holo did beside the outputs unasked (stale temporaries removed).
    holo::output::take_notices().iter().for_each(out::warn);
    match outcome {
        Ok(Ok(code)) => code,
        Ok(Err(Failure(message))) => {
            eprintln!("holo: error: {message}");
            ExitCode::from(1)
        }
        Err(_) => ExitCode::from(1),
    }
}

fn run(command: Command) -> Outcome {
    match command {
        Command::Info(a) => info::run(a),
        Command::Validate(a) => validate::run(a),
        Command::Pattern(a) => pattern::run(a),
        Command::Resample(a) => resample::run(a),
        Command::ExportViews(a) => views::run_export(a),
        Command::ExportQuilt(a) => quilt::run(a),
        Command::ImportViews(a) => views::run_import(a),
        Command::ExportHogels(a) => hogels::run_export(a),
        Command::ImportHogels(a) => hogels::run_import(a),
        Command::ExportHci(a) => hci::run(a),
        Command::Convert(c) => convert::run(c),
        Command::Holoflick(c) => holoflick::run(c),
        Command::Assemble(a) => assemble::run(a),
        Command::Check(a) => check::run(a),
        Command::View(a) => view::run(a),
        Command::Layout(a) => layout::run(a),
        Command::Demo(a) => demo::run(a),
        Command::Farm(c) => farm::run(c),
    }
}
