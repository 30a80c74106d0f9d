//! `holo info`: what `.holo` files hold, and whether they hold the same.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::recorded::command_line;
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
        conversion(&i.file);
    }
    if let Some(same) = same {
        say!("same content: {}", if same { "yes (equal geometry, sample type and frame digests)" } else { "no" });
    }
    Ok(ExitCode::SUCCESS)
}

/// The conversion a file records, as the command line that makes it again
/// (what it cannot give said), and the input it was made from.
fn conversion(info: &holo::format::FileInfo) {
    match info.conversion() {
        Ok(None) => {}
        Ok(Some(c)) => {
            let line = command_line(&c, info);
            say!("  conversion    {}", line.line);
            if !line.unsaid.is_empty() {
                say!("                (not given exactly by these flags: {})", line.unsaid.join("; "));
            }
            say!("                or exactly: holo convert like {} -o OUT.holo", info.path.display());
            match &c.input_sha256 {
                Some(digest) => say!("  input         {}, {digest}", c.input),
                None => say!("  input         {}", c.input),
            }
        }
        Err(e) => say!("  conversion    not readable: {e}"),
    }
}
