//! A display profile of one's own: a built-in layout changed, saved as TOML,
//! loaded back with every consistency check, and used to assemble fringes.
//!
//! ```text
//! cargo run --example 05_custom_layout
//! ```
//!
//! A layout is plain data: the modulation geometry a display expects and how
//! its fringes are laid out in its frame buffer. This example starts from the
//! MIT Mark I profile (what `holo layout mark1` prints), halves its hololines,
//! writes `half-mark1.toml` in a new folder under the system's temporary
//! folder (which it prints), loads it back, shows that a profile whose
//! numbers do not fit together is refused with its reasons, and assembles a
//! test pattern for the new display in memory.

use std::error::Error;
use std::path::{Path, PathBuf};

use holo::assemble::{load_layout, Assembler};
use holo::pattern::{Pattern, PatternKind};

fn main() -> Result<(), Box<dyn Error>> {
    // A new folder, kept after the run.
    let profile = run(&tempfile::Builder::new().prefix("holo-example-").tempdir()?.keep())?;
    println!("the profile is {}; `holo layout` prints it", profile.display());
    Ok(())
}

/// Write `folder/half-mark1.toml` (and a broken profile beside it), load
/// them and assemble a pattern with the first; returns the profile's path.
pub fn run(folder: &Path) -> Result<PathBuf, Box<dyn Error>> {
    let mut layout = holo::layout::mark1();
    layout.name = "half-mark1".into();
    layout.description = "MIT Mark I with its upper 32 hololines only".into();
    // Hololine `j` is at `y = hololine_top_y_m − j · hololine_pitch_m`
    // (metres): keep the top, drop the lower half.
    layout.geometry.hololines = 32;

    // Saved through holo's own writer: refused if the file exists.
    let profile = folder.join("half-mark1.toml");
    holo::output::write_bytes_beside(&profile, layout.to_toml().as_bytes(), false)?;

    // `load_layout` takes a built-in name or a profile's path, and refuses a
    // profile that cannot be assembled, naming every reason.
    let loaded = load_layout(&profile.to_string_lossy())?;
    assert_eq!(loaded, layout);
    println!("{}: {}", loaded.name, loaded.description);

    // The same display asked to show 200 hololines: its frame buffer holds 64.
    let mut too_tall = layout.clone();
    too_tall.geometry.hololines = 200;
    let broken = folder.join("too-tall.toml");
    holo::output::write_bytes_beside(&broken, too_tall.to_toml().as_bytes(), false)?;
    match load_layout(&broken.to_string_lossy()) {
        Ok(_) => return Err("a profile whose frame buffer cannot hold its hololines was accepted".into()),
        Err(e) => println!("refused as it should be: {e}"),
    }

    // Fringes for the new display, in memory: one 8-bit image per colour.
    let pattern = Pattern::new(PatternKind::Checkerboard).render(&loaded.geometry)?;
    let (images, stats) = Assembler::new(&loaded)?.assemble::<u8>(&pattern)?;
    println!(
        "{} images of {} × {} pixels ({} components), {} samples clipped",
        images.images.len(),
        images.width,
        images.height,
        images.components,
        stats.clipped
    );
    Ok(profile)
}
