//! How a command ends when it fails: one sentence for the user (exit code
//! 1). Below every other module of the command line, so that parsing,
//! printing and the commands can all say why they failed.

use std::process::ExitCode;

/// Why a command failed: one sentence (exit code 1).
#[derive(Debug)]
pub struct Failure(pub String);

/// A library error as the one sentence the user reads; a refusal to
/// replace something says how to ask for it, a set left half replaced how
/// to repair it, and a value the user typed names its flag.
impl From<holo::Error> for Failure {
    fn from(e: holo::Error) -> Self {
        match &e {
            holo::Error::Output {
                problem: holo::OutputProblem::Exists | holo::OutputProblem::SetExists(_), ..
            } => Failure(format!("{e} (use --force to replace it)")),
            holo::Error::Set { problem: holo::SetProblem::Interrupted { .. }, .. } => {
                Failure(format!("{e}, replacing them with --force"))
            }
            holo::Error::Argument { what: "frame rate", .. } => Failure(format!("{e} (--fps)")),
            holo::Error::Argument { what: "pupil", .. } => Failure(format!("{e} (--pupil, in millimetres)")),
            _ => Failure(e.to_string()),
        }
    }
}

impl From<String> for Failure {
    fn from(message: String) -> Self {
        Failure(message)
    }
}

/// What a command ends with: its exit code, or why it failed.
pub type Outcome = Result<ExitCode, Failure>;
