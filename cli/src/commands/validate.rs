//! `holo validate`: every rule of the `.holo` spec; exit 1 if any is broken.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::Outcome;
use crate::out::{json, say};

/// Check every rule of the .holo spec, including each frame's digest;
/// exits 1 and lists the violations if any file breaks one.
#[derive(Args)]
pub struct ValidateArgs {
    /// The .holo files.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(a: ValidateArgs) -> Outcome {
    let mut all_valid = true;
    let mut reports = Vec::new();
    for f in &a.files {
        let (valid, violations, warnings) = match holo::validate(f) {
            Ok(v) => (v.is_valid(), v.violations, v.warnings),
            Err(e) => {
                // The line already names the file.
                let text = e.to_string();
                let text = text.strip_prefix(&format!("{}: ", f.display())).map_or(text.clone(), str::to_string);
                (false, vec![text], vec![])
            }
        };
        all_valid &= valid;
        if a.json {
            reports
                .push(serde_json::json!({ "file": f, "valid": valid, "violations": violations, "warnings": warnings }));
            continue;
        }
        if valid {
            say!("{}: valid", f.display());
        } else {
            say!("{}: INVALID, {} violation(s)", f.display(), violations.len());
        }
        for v in &violations {
            say!("  violation: {v}");
        }
        for w in &warnings {
            say!("  warning: {w}");
        }
    }
    if a.json {
        json(&reports)?;
    }
    Ok(if all_valid { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
