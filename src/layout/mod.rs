//! Display layouts: everything that ties a modulation to a display. This
//! issue gives each built-in layout its *modulation geometry* (counts,
//! pitches, emitter plane, viewer, view directions, wavelengths); the fringe
//! side (basis, zones, frame-buffer rows) is specified in spec/layouts.md.
//!
//! Every number states its source; numbers no source gives are marked
//! `assumption` here and in spec/layouts.md, with the reasoning.

use crate::geometry::{mono_channel, rgb_channels, Geometry, Views};

/// A display profile.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// Name used on the command line (`--layout NAME`).
    pub name: &'static str,
    /// One line on what display this is and where the numbers come from.
    pub description: &'static str,
    /// The modulation geometry the display expects.
    pub geometry: Geometry,
}

/// Names of the built-in layouts.
pub const BUILTIN: [&str; 2] = ["mark3", "mark1"];

/// A built-in layout by name.
pub fn builtin(name: &str) -> Option<Layout> {
    match name.to_ascii_lowercase().as_str() {
        "mark3" | "mark-iii" | "markiii" => Some(mark3()),
        "mark1" | "mark-i" | "marki" => Some(mark1()),
        _ => None,
    }
}

/// Views whose directions are the centres of `count` equal segments of
/// `tan θ` over a fan of ±`half_fan_rad`: a perspective camera's pixel
/// columns, and equal-length segments of an exact focusing chirp.
pub fn segment_centre_views(count: usize, half_fan_rad: f64) -> Views {
    let t = half_fan_rad.tan();
    let step = 2.0 * t / count as f64;
    Views::tan_spaced(count, (-t + step / 2.0).atan(), (t - step / 2.0).atan())
}

/// MIT Mark III (Smithwick et al. 2009, seed 004 §5.1).
///
/// Stated: 336 emitters × 440 hololines × 96 views, 80 mm × 60 mm, 24° field
/// of view in three 8° zones; 24576 samples per hololine, a chirp slot every
/// 64 samples, three 1024-sample zone chirps per emitter.
/// Derived: emitter pitch 80 mm / 336; hololine pitch 60 mm / 440; sample
/// pitch 80 mm / (336 · 64) = 3.72 µm; the emitter plane where one emitter's
/// three zone chirps (3 × 1024 samples) span the 24° fan:
/// z = 3072 · 3.72 µm / (2 tan 12°) = 26.9 mm.
/// Assumptions: emitters in front of the hologram (+z); viewer at 600 mm (the
/// Mark I figure, seed 000); one channel at 633 nm (a HeNe red; the paper
/// gives no wavelength, and its six video channels are zones and I/Q, not
/// colours).
pub fn mark3() -> Layout {
    let emitters = 336;
    let width_m = 0.080;
    let sample_pitch_m = width_m / (emitters as f64 * 64.0);
    let half_fan = 12f64.to_radians();
    let emitter_z_m = 3.0 * 1024.0 * sample_pitch_m / (2.0 * half_fan.tan());
    let mut geometry = Geometry::centred(
        440,
        emitters,
        segment_centre_views(96, half_fan),
        0.060 / 440.0,
        width_m / emitters as f64,
        emitter_z_m,
        0.600,
        mono_channel(),
    );
    // Emitter e is centred on sample 64e + 1536 of the 24576-sample hololine,
    // which is centred on x = 0: the grid sits half a slot left of symmetric.
    geometry.emitter_left_x_m = (1536.0 - 12288.0) * sample_pitch_m;
    Layout {
        name: "mark3",
        description: "MIT Mark III (Smithwick et al. 2009): 336 emitters × 440 hololines × 96 views, 80 × 60 mm, 24°",
        geometry,
    }
}

/// MIT Mark I in colour (Nelson 1993, seed 000 §1.1.2).
///
/// Stated: 64 RGB hololines of 32K samples, three colour layers, one view
/// zone of about 16°, viewed at about 600 mm, five discrete view directions
/// for occlusion and specular (seed 000 ch. 2, 4).
/// Assumptions: sample pitch 1.2 µm (a real-valued fringe must keep a 16°
/// band below half the sampling rate at 633 nm, PHYSICS.md §1), so a hololine
/// is 32768 · 1.2 µm = 39.3 mm; 256 emitters across it (one every 128
/// samples); hololines 0.4 mm apart (a 25.6 mm tall image, the "few
/// centimetres" of the seed); emitter plane 10 mm in front of the hologram;
/// wavelengths 633 / 532 / 445 nm.
pub fn mark1() -> Layout {
    let emitters = 256;
    let width_m = 32768.0 * 1.2e-6;
    Layout {
        name: "mark1",
        description: "MIT Mark I colour (Nelson 1993): 256 emitters × 64 hololines × 5 views, RGB, 16° zone, 600 mm",
        geometry: Geometry::centred(
            64,
            emitters,
            segment_centre_views(5, 8f64.to_radians()),
            0.4e-3,
            width_m / emitters as f64,
            0.010,
            0.600,
            rgb_channels(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mark3_numbers_agree_with_the_paper() {
        let g = mark3().geometry;
        assert_eq!((g.hololines, g.emitters, g.views.count), (440, 336, 96));
        assert!((g.emitter_pitch_m * 336.0 - 0.080).abs() < 1e-12);
        assert!((g.hololine_pitch_m * 440.0 - 0.060).abs() < 1e-12);
        // The outermost view segments end at ±12°.
        let t = 12f64.to_radians().tan();
        let step = 2.0 * t / 96.0;
        assert!((g.views.theta_rad(0).tan() - (-t + step / 2.0)).abs() < 1e-12);
        assert!((g.views.theta_rad(95).tan() - (t - step / 2.0)).abs() < 1e-12);
        assert!((g.emitter_z_m - 0.02688).abs() < 1e-4, "{}", g.emitter_z_m);
        assert!(g.problems().is_empty(), "{:?}", g.problems());
    }

    #[test]
    fn mark1_numbers_agree_with_the_thesis() {
        let g = mark1().geometry;
        assert_eq!((g.hololines, g.views.count, g.channels.len()), (64, 5, 3));
        assert!((g.views.theta_rad(4) - g.views.theta_rad(0)).to_degrees() < 16.0);
        assert_eq!(g.viewer_distance_m, 0.6);
        assert!(g.problems().is_empty(), "{:?}", g.problems());
    }
}
