//! Display layouts: everything that ties a modulation to a display, as
//! data. A layout is the *modulation geometry* the display expects (counts,
//! pitches, emitter plane, viewer, view directions, wavelengths) and its
//! *fringe* side (basis, frame buffer, quantization). Built-in layouts are
//! below; users give their own as TOML or JSON files with the same fields
//! (`holo layout mark3 --toml` prints one to start from). spec/layouts.md
//! is the normative description.
//!
//! Every number states its source; numbers no source gives are marked
//! `assumption` here and in spec/layouts.md, with the reasoning.

pub mod fringe;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::geometry::{mono_channel, rgb_channels, Geometry, Views};
use crate::{Error, Result};
pub use fringe::{Basis, ChannelSlot, FrameBuffer, Fringe, Quantization};

/// A display profile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Layout {
    /// Name used on the command line (`--layout NAME`).
    pub name: String,
    /// One line on what display this is and where the numbers come from.
    pub description: String,
    /// The modulation geometry the display expects.
    pub geometry: Geometry,
    /// How modulation becomes the display's signal; absent for a layout that
    /// only describes a modulation geometry.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fringe: Option<Fringe>,
}

impl Layout {
    /// A built-in layout's name, or a path to a `.toml` or `.json` profile.
    pub fn load(name_or_path: &str) -> Result<Layout> {
        if let Some(l) = builtin(name_or_path) {
            return Ok(l);
        }
        let path = Path::new(name_or_path);
        if !path.exists() {
            return Err(Error::Usage(format!(
                "unknown layout {name_or_path:?}: the built-in layouts are {}, or give a .toml or .json profile",
                BUILTIN.join(", ")
            )));
        }
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let bad = |why: String| Error::invalid(path, why);
        let layout: Layout = match path.extension().and_then(|e| e.to_str()) {
            Some("json") => serde_json::from_str(&text).map_err(|e| bad(format!("not a layout profile: {e}")))?,
            _ => toml::from_str(&text).map_err(|e| bad(format!("not a layout profile: {e}")))?,
        };
        let problems = layout.problems();
        if !problems.is_empty() {
            return Err(bad(format!("inconsistent layout: {}", problems.join("; "))));
        }
        Ok(layout)
    }

    /// The profile as TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("a layout is plain data")
    }

    /// Fringe signals per hololine (all colour channels).
    pub fn signals_per_hololine(&self) -> usize {
        self.fringe.as_ref().map_or(0, |f| f.basis.signal_names().len() * self.geometry.channels.len())
    }

    /// Everything that makes the layout inconsistent: its geometry's
    /// problems, and a fringe side that does not fit the geometry.
    pub fn problems(&self) -> Vec<String> {
        let g = &self.geometry;
        let mut p = g.problems();
        let Some(f) = &self.fringe else { return p };
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        if !(f.sample_pitch_m.is_finite() && f.sample_pitch_m > 0.0) {
            p.push(format!("sample_pitch_m {} must be positive", f.sample_pitch_m));
        }
        match f.basis {
            Basis::ZonedChirp { chirp_samples, slot_samples, zones, views_per_zone } => {
                let shape_ok = slot_samples > 0
                    && views_per_zone > 0
                    && zones > 0
                    && chirp_samples % slot_samples == 0
                    && chirp_samples % views_per_zone == 0
                    && slot_samples % (chirp_samples / views_per_zone).max(1) == 0;
                if !shape_ok {
                    p.push(format!(
                        "zoned chirp of {chirp_samples} samples, a slot every {slot_samples}, {views_per_zone} views \
                         per zone: the slot and the view segment must divide the chirp, and the segment the slot"
                    ));
                } else {
                    let abutting = f.samples_per_hololine / chirp_samples;
                    let emitters = abutting.saturating_sub(zones) * (chirp_samples / slot_samples);
                    if abutting * chirp_samples != f.samples_per_hololine || emitters != g.emitters {
                        p.push(format!(
                            "{} samples per hololine make {emitters} emitters of {zones} zone chirps; the geometry has {}",
                            f.samples_per_hololine, g.emitters
                        ));
                    }
                    if zones * views_per_zone != g.views.count {
                        p.push(format!("{zones} zones × {views_per_zone} views ≠ the geometry's {}", g.views.count));
                    }
                    if !close(slot_samples as f64 * f.sample_pitch_m, g.emitter_pitch_m) {
                        p.push(format!(
                            "a slot of {slot_samples} samples × {} m is not the emitter pitch {} m",
                            f.sample_pitch_m, g.emitter_pitch_m
                        ));
                    }
                    let first_centre = (zones * chirp_samples) as f64 / 2.0 - f.samples_per_hololine as f64 / 2.0;
                    if !close(first_centre * f.sample_pitch_m, g.emitter_left_x_m) {
                        p.push(format!(
                            "emitter 0's chirp is centred at {} m; the geometry puts emitter 0 at {} m",
                            first_centre * f.sample_pitch_m,
                            g.emitter_left_x_m
                        ));
                    }
                }
            }
        }
        let signals = self.signals_per_hololine();
        p.extend(f.frame_buffer.problems(g.hololines, signals, f.samples_per_hololine));
        p.extend(f.quantization.problems());
        p
    }
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
    // Six channels in signal order (zone1.cos, zone1.sin, zone2.cos, …):
    // "Head 1 RG channels produce the sine/cosine pair of zone 1. Head 1 B
    // channel produces the sine of zone 2. Head 2 RG channels produce the
    // sine/cosine pair of zone 3. Head 2 B channel produces cosine of zone 2."
    let slot = |image, component| ChannelSlot { image, component };
    let channels = vec![slot(0, 1), slot(0, 0), slot(1, 2), slot(0, 2), slot(1, 1), slot(1, 0)];
    let fringe = Fringe {
        sample_pitch_m,
        samples_per_hololine: 24576,
        basis: Basis::ZonedChirp { chirp_samples: 1024, slot_samples: 64, zones: 3, views_per_zone: 32 },
        frame_buffer: FrameBuffer {
            image_names: vec!["head1".into(), "head2".into()],
            width: 4080,
            height: 3386,
            components: 3,
            line_samples: 4096,
            rows_per_hololine: 6,
            // Assumption: hololines from the top row; the 746 rows below
            // them fall in the vertical mirror's flyback (80% duty cycle).
            first_row: 0,
            gap_rows: 0,
            channels,
            reverse_odd_lines: false,
        },
        // Assumption: a signed signal centred on code 128.
        quantization: Quantization { bits: 8, offset: 128.0, gain: 127.0 },
    };
    Layout {
        name: "mark3".into(),
        description: "MIT Mark III (Smithwick et al. 2009): 336 emitters × 440 hololines × 96 views, 80 × 60 mm, 24°"
            .into(),
        geometry,
        fringe: Some(fringe),
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
        name: "mark1".into(),
        description: "MIT Mark I colour (Nelson 1993): 256 emitters × 64 hololines × 5 views, RGB, 16° zone, 600 mm"
            .into(),
        fringe: None,
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
        assert!(mark3().problems().is_empty(), "{:?}", mark3().problems());
    }

    #[test]
    fn profiles_round_trip_through_toml_and_json_and_bad_ones_are_named() {
        let dir = tempfile::tempdir().unwrap();
        for l in [mark3(), mark1()] {
            let toml_path = dir.path().join(format!("{}.toml", l.name));
            std::fs::write(&toml_path, l.to_toml()).unwrap();
            assert_eq!(Layout::load(toml_path.to_str().unwrap()).unwrap(), l);
            let json_path = dir.path().join(format!("{}.json", l.name));
            std::fs::write(&json_path, serde_json::to_string(&l).unwrap()).unwrap();
            assert_eq!(Layout::load(json_path.to_str().unwrap()).unwrap(), l);
        }
        let mut broken = mark3();
        broken.fringe.as_mut().unwrap().frame_buffer.height = 2000;
        let path = dir.path().join("short.toml");
        std::fs::write(&path, broken.to_toml()).unwrap();
        let err = Layout::load(path.to_str().unwrap()).unwrap_err().to_string();
        assert!(err.contains("short.toml") && err.contains("2640 rows"), "{err}");
        let path = dir.path().join("typo.toml");
        std::fs::write(&path, mark3().to_toml().replace("gap_rows", "gap_rowz")).unwrap();
        let err = Layout::load(path.to_str().unwrap()).unwrap_err().to_string();
        assert!(err.contains("typo.toml") && err.contains("gap_rowz"), "{err}");
        let err = Layout::load("mark9").unwrap_err().to_string();
        assert!(err.contains("mark3, mark1"), "{err}");
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
