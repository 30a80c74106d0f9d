//! One module per command, each a function `run` from its checked
//! arguments to an outcome: call the library, print what it did.

pub mod assemble;
pub mod check;
pub mod convert;
pub mod demo;
pub mod farm;
pub mod frame_job;
pub mod hci;
pub mod hogels;
pub mod holoflick;
pub mod info;
pub mod layout;
pub mod pattern;
pub mod quilt;
pub mod recorded;
pub mod resample;
pub mod validate;
pub mod view;
pub mod views;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::args::WriteArgs;
use crate::out::{say, warn};

pub use crate::failure::{Failure, Outcome};

/// Refuse an input that is not there, naming it, before the output is looked
/// at: every argument is checked before the output, so a user who fixes one
/// problem is not then told of another that was already there.
fn inputs_exist(inputs: &[&Path]) -> Result<(), Failure> {
    for input in inputs {
        if let Err(e) = std::fs::metadata(input) {
            return Err(Failure(format!("{}: {e}", input.display())));
        }
    }
    Ok(())
}

/// Refuse, before any work, an output that exists (without `force`), whose
/// folder is missing, that is one of `inputs` (where an input folder
/// stands for itself and every file in it), that is not a regular file, or
/// that another process is writing; the claim keeps other processes from
/// writing it while it is held (hold it until the output is written).
fn check_output(output: &Path, inputs: &[&Path], force: bool) -> Result<holo::output::Claim, Failure> {
    let mut read: Vec<PathBuf> = Vec::new();
    for input in inputs {
        read.push(input.to_path_buf());
        if let Ok(entries) = std::fs::read_dir(input) {
            read.extend(entries.flatten().map(|e| e.path()));
        }
    }
    let read: Vec<&Path> = read.iter().map(PathBuf::as_path).collect();
    Ok(holo::output::check_output(output, &read, force)?)
}

/// What writing a `.holo` file did, said as every command that writes one says it.
fn wrote(report: &holo::format::WriteReport, args: &WriteArgs) -> Outcome {
    for w in &report.warnings {
        warn(format_args!("{}: {w}", args.output.display()));
    }
    say!("wrote {} ({} bytes, {})", report.path.display(), report.file_bytes, report.digests[0]);
    Ok(ExitCode::SUCCESS)
}
