//! `holo info`: what `.holo` files hold, and whether they hold the same.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::Outcome;
use crate::out::{json, put, say};

/// Show geometry, channels, frames, size and value range of .holo files
/// (with two or more files, also whether they hold the same content).
#[derive(Args)]
pub struct InfoArgs {
    /// The .holo files.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Read headers only: skip the value range and digest check.
    #[arg(long)]
    headers_only: bool,
}

pub fn run(a: InfoArgs) -> Outcome {
    let infos = a.files.iter().map(|f| holo::report::info(f, !a.headers_only)).collect::<Result<Vec<_>, _>>()?;
    let same = (infos.len() > 1).then(|| infos.windows(2).all(|w| holo::report::same_content(&w[0], &w[1])));
    if a.json {
        json(&serde_json::json!({ "files": infos, "same_content": same }))?;
        return Ok(ExitCode::SUCCESS);
    }
    for i in &infos {
        put!("{i}");
    }
    if let Some(same) = same {
        say!("same content: {}", if same { "yes (equal geometry, sample type and frame digests)" } else { "no" });
    }
    Ok(ExitCode::SUCCESS)
}
