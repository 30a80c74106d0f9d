//! Open a `.holo` file, check it against the specification, and look at its
//! geometry and samples.
//!
//! ```text
//! cargo run --example 02_read_and_inspect
//! ```
//!
//! Reads the bundled test vector `fixtures/v1.0/frames-rgb-f32-zip.holo`
//! (nothing is written). For a file of your own, change `FILE`.

use std::error::Error;
use std::path::Path;

// The prelude: what a first program needs (`HoloFile`, `Region`, `validate`, …).
use holo::prelude::*;

/// The file to inspect.
pub const FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/v1.0/frames-rgb-f32-zip.holo");

fn main() -> Result<(), Box<dyn Error>> {
    run(Path::new(FILE))
}

/// Print what `path` holds.
pub fn run(path: &Path) -> Result<(), Box<dyn Error>> {
    // Every rule of the specification, all violations collected (a reader
    // that only wants the samples can skip this: opening checks what it
    // needs).
    let validation = validate(path)?;
    println!("valid: {} ({} warnings)", validation.is_valid(), validation.warnings.len());
    for violation in &validation.violations {
        println!("  violation: {violation}");
    }

    // Opening reads the headers only; samples are decoded frame by frame.
    let file = HoloFile::open(path)?;
    let info = file.info();
    let g = file.geometry();
    println!(
        "{} frames of {} hololines × {} emitters × {} views, channels {:?}, stored as {:?}, {:?} compression",
        info.frames.len(),
        g.hololines,
        g.emitters,
        g.views.count,
        g.channels.iter().map(|c| c.name.as_str()).collect::<Vec<_>>(),
        info.sample_type,
        info.compression,
    );
    // Lengths are metres and angles radians; the names say so.
    println!(
        "emitter pitch {:.3} mm, hololine pitch {:.3} mm, viewer at {:.0} mm, views from {:.2}° to {:.2}°",
        g.emitter_pitch_m * 1e3,
        g.hololine_pitch_m * 1e3,
        g.viewer_distance_m * 1e3,
        g.views.first_theta_rad.to_degrees(),
        g.views.last_theta_rad.to_degrees(),
    );
    if let Some(source) = &info.source {
        println!("made from: {source}");
    }

    for (index, frame_info) in info.frames.iter().enumerate() {
        // `read_frame` checks the frame's SHA-256 digest as it decodes.
        let frame = file.read_frame(index)?;
        let (lo, hi) = frame.value_range();
        println!("frame {} (number {}): linear radiance {lo} to {hi}", index, frame_info.number);
        // One sample: channel 0, the middle hololine, emitter and view.
        let (j, e, v) = (g.hololines / 2, g.emitters / 2, g.views.count / 2);
        println!(
            "  channel {} hololine {j} (y {:+.2} mm) emitter {e} (x {:+.2} mm) view {v} ({:+.2}°): {}",
            g.channels[0].name,
            g.hololine_y_m(j) * 1e3,
            g.emitter_x_m(e) * 1e3,
            g.views.theta_rad(v).to_degrees(),
            frame.get(0, j, e, v)
        );
    }

    // Only part of a frame: the first hololine, all emitters, view 0.
    let part =
        file.read_region(0, &Region { hololines: 0..1, emitters: 0..g.emitters, views: 0..1, vertical_views: 0..1 })?;
    println!("region: {} samples", part.samples().len());
    Ok(())
}
