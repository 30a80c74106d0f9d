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

mod builtin;
mod fringe;
mod mark3_blanking;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::geometry::Geometry;
pub use builtin::{
    builtin, chimera, mark1, mark1_hogel, mark2, mark3, mark4, pluto2_hogels, segment_centre_views, BUILTIN,
};
pub use fringe::{
    Basis, BlankingGains, ChannelSlot, ColourSignals, EmitterPhases, FlatFieldGains, FrameBuffer, Fringe, Pixel,
    Quantization, SignalKind,
};

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
    /// A built-in layout's name, or a path to a `.toml` or `.json` profile,
    /// checked for its own consistency ([`Layout::problems`]). To assemble
    /// it, load it with [`crate::assemble::load_layout`], which also checks
    /// that its fringe side fits its geometry.
    pub fn load(name_or_path: &str) -> Result<Layout> {
        Layout::load_checked(name_or_path, Layout::problems)
    }

    /// [`Layout::load`] with the consistency check `problems`: a profile
    /// file for which it names any problem is refused with all of them.
    /// Built-in layouts are consistent and are not checked.
    pub(crate) fn load_checked(name_or_path: &str, problems: impl Fn(&Layout) -> Vec<String>) -> Result<Layout> {
        if let Some(l) = builtin(name_or_path) {
            return Ok(l);
        }
        let path = Path::new(name_or_path);
        let profile = matches!(path.extension().and_then(|e| e.to_str()), Some("toml" | "json"));
        // A name that is neither a built-in layout nor a profile's file name
        // is most likely a misspelt built-in; a profile that does not exist
        // is an I/O error naming it.
        if !profile && !path.exists() {
            return Err(Error::UnknownLayout { name: name_or_path.to_string(), builtin: &BUILTIN });
        }
        let bad = |why: String| Error::layout(path.display().to_string(), why);
        let text = std::fs::read_to_string(path).map_err(|e| match e.kind() {
            // A file that is not text (a `.holo` file given as the layout).
            std::io::ErrorKind::InvalidData => {
                bad("not a layout profile: a profile is a TOML or JSON text file".into())
            }
            _ => Error::io(path, e),
        })?;
        let layout: Layout = match path.extension().and_then(|e| e.to_str()) {
            Some("json") => serde_json::from_str(&text).map_err(|e| bad(format!("not a layout profile: {e}")))?,
            _ => toml::from_str(&text).map_err(|e| bad(format!("not a layout profile: {e}")))?,
        };
        let problems = problems(&layout);
        if !problems.is_empty() {
            return Err(bad(format!("inconsistent layout: {}", problems.join("; "))));
        }
        Ok(layout)
    }

    /// The profile as TOML. Blanking gains come last, one `[re, im]` pair a
    /// line (the pretty printer would give every number a line of its own).
    pub fn to_toml(&self) -> String {
        let mut rest = self.clone();
        let gains = rest.fringe.as_mut().and_then(|f| f.blanking_gains.take());
        let mut text = toml::to_string_pretty(&rest).expect("a layout is plain data");
        if let Some(g) = gains {
            // `{:?}` of a finite f64 is the shortest text that reads back to it, with a
            // decimal point: a TOML float. Gains that are not finite are refused on loading.
            let table = |text: &mut String, zones: &[Vec<[f64; 2]>]| {
                text.push_str("zones = [\n");
                for zone in zones {
                    text.push_str("    [\n");
                    for [re, im] in zone {
                        text.push_str(&format!("        [{re:?}, {im:?}],\n"));
                    }
                    text.push_str("    ],\n");
                }
                text.push_str("]\n");
            };
            text.push_str(&format!("\n[fringe.blanking_gains]\nsamples_each_side = {}\n", g.samples_each_side));
            table(&mut text, &g.zones);
            if let Some(f) = &g.flat_field {
                text.push_str(&format!(
                    "\n[fringe.blanking_gains.flat_field]\nmax_spread = {:?}\nsamples_each_side = {}\n",
                    f.max_spread, f.samples_each_side
                ));
                table(&mut text, &f.zones);
            }
        }
        text
    }

    /// Fringe signals per hololine (all colour channels).
    pub fn signals_per_hololine(&self) -> usize {
        self.fringe.as_ref().map_or(0, |f| match f.colours {
            ColourSignals::Separate => f.signals_per_colour() * self.geometry.channels.len(),
            ColourSignals::Summed => f.signals_per_colour(),
        })
    }

    /// Everything that makes the layout inconsistent in itself: its
    /// geometry's problems, or, when the geometry has none, a fringe side
    /// whose frame buffer cannot hold its signals or whose quantization is
    /// impossible ([`Layout::fringe_problems`]). Whether the fringe side's
    /// basis fits the geometry is assembly's question:
    /// [`crate::assemble::problems`] adds it.
    pub fn problems(&self) -> Vec<String> {
        let p = self.geometry.problems();
        if !p.is_empty() {
            return p;
        }
        self.fringe_problems()
    }

    /// The fringe side's problems in itself (none without a fringe side):
    /// a frame buffer that does not hold the signals of every hololine, an
    /// impossible quantization. Meaningful for a consistent geometry.
    pub fn fringe_problems(&self) -> Vec<String> {
        let Some(f) = &self.fringe else { return Vec::new() };
        if let Some(vertical) = &self.geometry.vertical_views {
            // spec/layouts.md §2: a full-parallax layout is a geometry only.
            return vec![format!(
                "a full-parallax geometry ({} × {} views) has no fringe side yet: holo assembles horizontal parallax only, so drop the [fringe] table",
                self.geometry.views.count, vertical.count
            )];
        }
        let mut p =
            f.frame_buffer.problems(self.geometry.hololines, self.signals_per_hololine(), f.samples_per_hololine);
        // The gains' checks walk the hololine's samples: only once the frame
        // buffer is known to hold them (a hostile sample count would take
        // forever, and its own problem is named already).
        let holds = p.is_empty();
        p.extend(f.quantization.problems());
        if holds {
            p.extend(f.blanking_gains_problems());
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_parallax_builtins_agree_with_their_sources_and_their_rays_with_their_views() {
        // PLUTO-2: 8 µm pixels, 16-pixel hogels; the outermost plane wave of a
        // hogel's transform inside the modulator's limit λ / 2p.
        let g = pluto2_hogels().geometry;
        let vertical = g.vertical_views.clone().unwrap();
        assert_eq!((g.emitters, g.hololines, g.views.count, vertical.count), (120, 67, 16, 16));
        assert!((g.emitter_pitch_m - 128e-6).abs() < 1e-15 && (g.hololine_pitch_m - 128e-6).abs() < 1e-15);
        let lambda = g.channels[0].wavelength_m;
        let step = lambda / (16.0 * 8e-6);
        for v in 0..16 {
            let want = (v as f64 - 7.5) * step;
            assert!((g.views.theta_rad(v).sin() - want).abs() < 1e-15, "view {v}");
            assert!((vertical.theta_rad(v).sin() - want).abs() < 1e-15, "vertical view {v}");
        }
        assert!(g.views.last_theta_rad.sin() < lambda / (2.0 * 8e-6));
        // CHIMERA: 120° across both axes (the views are centres of equal tan segments of ±60°).
        let g = chimera().geometry;
        let vertical = g.vertical_views.clone().unwrap();
        let t = 60f64.to_radians().tan();
        let half_step = t / 32.0;
        assert!((g.views.last_theta_rad.tan() - (t - half_step)).abs() < 1e-12);
        assert!((vertical.first_theta_rad.tan() + (t - half_step)).abs() < 1e-12);
        // Every ray leaves its hogel at its view's two angles.
        for l in [pluto2_hogels(), chimera()] {
            let g = &l.geometry;
            let vertical = g.vertical_views.as_ref().unwrap();
            assert!(l.problems().is_empty(), "{}: {:?}", l.name, l.problems());
            for (j, e, h, k) in
                [(0, 0, 0, 0), (g.hololines - 1, g.emitters - 1, g.views.count - 1, vertical.count - 1), (3, 5, 2, 7)]
            {
                let ray = g.ray(j, e, g.view_index(h, k));
                assert_eq!(ray.origin_m, [g.emitter_x_m(e), g.hololine_y_m(j), g.emitter_z_m]);
                assert!((ray.slope_x - g.views.theta_rad(h).tan()).abs() < 1e-15);
                assert!((ray.slope_y - vertical.theta_rad(k).tan()).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn a_full_parallax_layout_with_a_fringe_side_is_refused() {
        let mut l = mark3();
        l.geometry = l.geometry.clone().with_centred_vertical_views(4, None);
        assert!(l.problems().iter().any(|p| p.contains("full-parallax") && p.contains("fringe")), "{:?}", l.problems());
    }

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
        for l in [mark3(), mark1(), mark1_hogel(), mark2(), mark4()] {
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
    fn blanking_gains_that_do_not_fit_are_refused_with_every_reason() {
        assert!(mark3().problems().is_empty());
        let mut l = mark3();
        let f = l.fringe.as_mut().unwrap();
        let g = f.blanking_gains.as_mut().unwrap();
        g.zones[1].pop();
        let flat = g.flat_field.as_mut().unwrap();
        flat.max_spread = 1.0;
        flat.zones[2][5] = [0.0, 0.0];
        // Runs are 4080 samples apart: a flat-field table reaching 2041 each side overlaps the next run's.
        flat.samples_each_side = 2041;
        for zone in &mut flat.zones {
            zone.resize(2 * 2041, [1.0, 0.0]);
        }
        let p = l.problems().join("; ");
        for want in [
            "blanking gains of zone 2: 127 gains, not 2 · samples_each_side = 128",
            "max_spread 1 must be at least 0 and below 1",
            "flat-field blanking gains of zone 3: gain 0 + 0i must be finite and not zero",
            "closer than 2 · samples_each_side = 4082",
        ] {
            assert!(p.contains(want), "{want}: {p}");
        }
        let mut real = mark3();
        real.fringe.as_mut().unwrap().signal = SignalKind::Real;
        assert!(real.problems().join("; ").contains("they need I/Q signals"));
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
