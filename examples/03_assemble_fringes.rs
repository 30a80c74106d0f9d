//! A `.holo` file to the fringes a display shows, and a check of what they
//! reconstruct.
//!
//! ```text
//! cargo run --example 03_assemble_fringes
//! ```
//!
//! Makes a colour-bar test pattern for the MIT Mark I display, writes it as
//! `bars.holo`, assembles it into the display's frame buffer (three 8-bit PNG
//! colour layers and the `holo-fringes.json` manifest, in `fringes/`), then
//! recovers the modulation from those fringes by least squares and prints how
//! close it comes. Everything goes into a new folder under the system's
//! temporary folder, which it prints.

use std::error::Error;
use std::path::{Path, PathBuf};

use holo::assemble::output::{assemble_file, AssembleOptions, FringeFormat};
use holo::pattern::{Pattern, PatternKind};
use holo::progress::Silent;
use holo::reconstruct::files::{check_file, CheckOptions};

fn main() -> Result<(), Box<dyn Error>> {
    // The folder is new and kept: look at the fringes after the run.
    let folder = tempfile::Builder::new().prefix("holo-example-").tempdir()?.keep();
    let fringes = run(&folder)?;
    println!("the fringe set is {}", fringes.display());
    Ok(())
}

/// Write `folder/bars.holo` and its fringes in `folder/fringes`; returns
/// the fringe folder.
pub fn run(folder: &Path) -> Result<PathBuf, Box<dyn Error>> {
    let layout = holo::layout::mark1();

    // Any modulation on the layout's geometry will do; a test pattern is the
    // quickest. Samples are linear radiance, 1 = full white.
    let bars = Pattern::new(PatternKind::ColourBars).render(&layout.geometry)?;
    let holo_file = folder.join("bars.holo");
    holo::write(&holo_file, &bars, &holo::WriteOptions::default())?;

    // The fringes: the images are written beside their final names and put
    // in place together, the manifest (names, sizes, SHA-256) last. Without
    // `overwrite`, an existing set in `fringes/` is refused before any work.
    let fringes = folder.join("fringes");
    let options = AssembleOptions { frames: None, format: FringeFormat::Png, overwrite: false, resample: false };
    let report = assemble_file(&holo_file, &layout, &fringes, &options, &Silent)?;
    for file in &report.files {
        println!("{}", file.display());
    }
    println!("{} samples clipped by the 8-bit quantization", report.stats.clipped);

    // Read the fringes back (the manifest is checked against every image)
    // and recover the modulation of the first eight hololines from them.
    let check = CheckOptions { frame: 0, fringes: Some(fringes.clone()), hololines: Some(0..8) };
    let result = check_file(&holo_file, None, &check, &Silent)?;
    println!(
        "recovered from the fringes: relative L2 error {:.2e}, PSNR {:.1} dB",
        result.report.signal.relative_l2, result.report.signal.psnr_db
    );
    Ok(fringes)
}
