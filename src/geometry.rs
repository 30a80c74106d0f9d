//! The physical geometry of a modulation texture: where hololines and emitters
//! are, where the viewer is, which directions the views point in, and which
//! wavelength each colour channel carries. Coordinates follow DESIGN.md §2:
//! metres, `x` right along a hololine, `y` up, `z` toward the viewer, the
//! hologram plane at `z = 0`.

use serde::{Deserialize, Serialize};

/// How view directions are spaced between the first and the last view.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ViewSpacing {
    /// Uniform in `tan θ`: perspective-camera columns, or equal segments of an
    /// exact focusing chirp (Mark III).
    Tan,
    /// Uniform in `sin θ`: equal segments of a paraxial (linear-FM) chirp, or
    /// equal frequency steps of hogel gratings.
    Sin,
    /// Uniform in `θ` itself.
    Angle,
    /// One angle per view, in radians, strictly increasing.
    Explicit(Vec<f64>),
}

impl ViewSpacing {
    /// The name stored in the file.
    pub fn name(&self) -> &'static str {
        match self {
            ViewSpacing::Tan => "tan",
            ViewSpacing::Sin => "sin",
            ViewSpacing::Angle => "angle",
            ViewSpacing::Explicit(_) => "explicit",
        }
    }
}

/// The horizontal directions of the views of every emitter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Views {
    /// Number of views per emitter.
    pub count: usize,
    /// Direction of view 0, radians from the `z` axis, positive toward `+x`.
    pub first_theta_rad: f64,
    /// Direction of the last view, radians.
    pub last_theta_rad: f64,
    /// How the views in between are spaced.
    pub spacing: ViewSpacing,
}

impl Views {
    /// Direction of view `v` in radians.
    pub fn theta_rad(&self, v: usize) -> f64 {
        if let ViewSpacing::Explicit(list) = &self.spacing {
            return list[v];
        }
        if self.count <= 1 {
            return self.first_theta_rad;
        }
        let t = v as f64 / (self.count - 1) as f64;
        let lerp = |a: f64, b: f64| a + (b - a) * t;
        match self.spacing {
            ViewSpacing::Tan => lerp(self.first_theta_rad.tan(), self.last_theta_rad.tan()).atan(),
            ViewSpacing::Sin => lerp(self.first_theta_rad.sin(), self.last_theta_rad.sin()).asin(),
            ViewSpacing::Angle => lerp(self.first_theta_rad, self.last_theta_rad),
            ViewSpacing::Explicit(_) => unreachable!("handled above"),
        }
    }

    /// The fractional view index pointing at `theta_rad` by the spacing
    /// rule (the inverse of [`Views::theta_rad`]), extended beyond the first
    /// and last view (an explicit list by its end intervals); 0 for a
    /// single view.
    pub fn index_at(&self, theta_rad: f64) -> f64 {
        let n = self.count;
        if n <= 1 {
            return 0.0;
        }
        let (a, b) = (self.first_theta_rad, self.last_theta_rad);
        let t = match &self.spacing {
            ViewSpacing::Tan => (theta_rad.tan() - a.tan()) / (b.tan() - a.tan()),
            ViewSpacing::Sin => (theta_rad.sin() - a.sin()) / (b.sin() - a.sin()),
            ViewSpacing::Angle => (theta_rad - a) / (b - a),
            ViewSpacing::Explicit(list) => {
                let k = list.partition_point(|x| *x <= theta_rad).clamp(1, n - 1);
                let (lo, hi) = (list[k - 1], list[k]);
                return (k - 1) as f64 + (theta_rad - lo) / (hi - lo);
            }
        };
        t * (n - 1) as f64
    }

    /// Uniform-in-`tan θ` views spanning `[first, last]`.
    pub fn tan_spaced(count: usize, first_theta_rad: f64, last_theta_rad: f64) -> Self {
        Views { count, first_theta_rad, last_theta_rad, spacing: ViewSpacing::Tan }
    }
}

/// A colour channel: its suffix in channel names and the wavelength it is shown in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColourChannel {
    /// `R`, `G`, `B` or `Y` (one wavelength, monochrome).
    pub name: String,
    /// Vacuum wavelength in metres.
    pub wavelength_m: f64,
}

impl ColourChannel {
    /// A channel with this suffix and wavelength.
    pub fn new(name: &str, wavelength_m: f64) -> Self {
        ColourChannel { name: name.to_string(), wavelength_m }
    }
}

/// The allowed channel suffixes, in the order channels are kept in memory.
pub const CHANNEL_NAMES: [&str; 4] = ["R", "G", "B", "Y"];

/// Red, green and blue at the HeNe, frequency-doubled Nd:YAG and 445 nm diode
/// lines used by the MIT displays (Mark IV source, DESIGN.md §4).
pub fn rgb_channels() -> Vec<ColourChannel> {
    vec![ColourChannel::new("R", 633e-9), ColourChannel::new("G", 532e-9), ColourChannel::new("B", 445e-9)]
}

/// One channel at 633 nm.
pub fn mono_channel() -> Vec<ColourChannel> {
    vec![ColourChannel::new("Y", 633e-9)]
}

/// How linear RGB radiance (a shader's, a camera picture's) becomes each
/// channel of a file: `R`, `G`, `B` take their component; `Y` (one
/// wavelength) takes the Rec. 709 luminance `0.2126 R + 0.7152 G + 0.0722 B`.
pub fn channel_weights(names: &[&str]) -> Vec<[f64; 3]> {
    names
        .iter()
        .map(|n| match *n {
            "R" => [1.0, 0.0, 0.0],
            "G" => [0.0, 1.0, 0.0],
            "B" => [0.0, 0.0, 1.0],
            _ => [0.2126, 0.7152, 0.0722],
        })
        .collect()
}

/// Horizontal parallax only (the only kind version 1 readers must handle), or
/// full parallax (reserved: layout specified, not yet produced).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Parallax {
    /// One row of emitters per hololine; views vary in `θ` only.
    Horizontal,
    /// A 2-D emitter grid and 2-D views (reserved, see spec §8).
    Full,
}

/// The complete geometry of one modulation texture.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Geometry {
    /// Parallax kind.
    pub parallax: Parallax,
    /// Number of hololines (rows).
    pub hololines: usize,
    /// Number of emitters per hololine (columns).
    pub emitters: usize,
    /// View directions.
    pub views: Views,
    /// Vertical distance between adjacent hololines, metres.
    pub hololine_pitch_m: f64,
    /// `y` of hololine 0 (the top one); hololine `j` is at `y0 − j·pitch`.
    pub hololine_top_y_m: f64,
    /// Horizontal distance between adjacent emitters, metres.
    pub emitter_pitch_m: f64,
    /// `x` of emitter 0 (the left one); emitter `e` is at `x0 + e·pitch`.
    pub emitter_left_x_m: f64,
    /// `z` of the emitter plane, metres (positive: in front of the hologram).
    pub emitter_z_m: f64,
    /// `z` of the viewer line, metres.
    pub viewer_distance_m: f64,
    /// `y` of the viewer line, metres.
    pub viewer_height_m: f64,
    /// Colour channels, in the order `R, G, B, Y` restricted to those present.
    pub channels: Vec<ColourChannel>,
}

impl Geometry {
    /// `x` of emitter `e`, metres.
    pub fn emitter_x_m(&self, e: usize) -> f64 {
        self.emitter_left_x_m + e as f64 * self.emitter_pitch_m
    }
    /// `y` of hololine `j`, metres.
    pub fn hololine_y_m(&self, j: usize) -> f64 {
        self.hololine_top_y_m - j as f64 * self.hololine_pitch_m
    }
    /// Samples in one frame (all channels).
    pub fn samples_per_frame(&self) -> u64 {
        self.channels.len() as u64 * self.hololines as u64 * self.emitters as u64 * self.views.count as u64
    }
    /// Index of the channel with this suffix.
    pub fn channel_index(&self, name: &str) -> Option<usize> {
        self.channels.iter().position(|c| c.name == name)
    }

    /// A centred horizontal-parallax geometry: the emitter grid is centred on
    /// `x = 0, y = 0` and the viewer line at `y = 0`.
    #[allow(clippy::too_many_arguments)]
    pub fn centred(
        hololines: usize,
        emitters: usize,
        views: Views,
        hololine_pitch_m: f64,
        emitter_pitch_m: f64,
        emitter_z_m: f64,
        viewer_distance_m: f64,
        channels: Vec<ColourChannel>,
    ) -> Self {
        Geometry {
            parallax: Parallax::Horizontal,
            hololines,
            emitters,
            views,
            hololine_pitch_m,
            hololine_top_y_m: hololines.saturating_sub(1) as f64 * hololine_pitch_m / 2.0,
            emitter_pitch_m,
            emitter_left_x_m: -(emitters.saturating_sub(1) as f64) * emitter_pitch_m / 2.0,
            emitter_z_m,
            viewer_distance_m,
            viewer_height_m: 0.0,
            channels,
        }
    }

    /// Every rule of spec §4 that concerns the geometry alone; an empty list
    /// means the geometry is valid.
    pub fn problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.parallax != Parallax::Horizontal {
            out.push("full parallax is reserved in format version 1 and not yet supported".into());
        }
        for (what, n) in
            [("hololine count", self.hololines), ("emitter count", self.emitters), ("view count", self.views.count)]
        {
            if n == 0 {
                out.push(format!("{what} is zero"));
            }
        }
        for (what, x) in [("hololine pitch", self.hololine_pitch_m), ("emitter pitch", self.emitter_pitch_m)] {
            if !(x.is_finite() && x > 0.0) {
                out.push(format!("{what} is {x} m; it must be finite and positive"));
            }
        }
        for (what, x) in [
            ("hololine 0 y", self.hololine_top_y_m),
            ("emitter 0 x", self.emitter_left_x_m),
            ("emitter plane z", self.emitter_z_m),
            ("viewer height", self.viewer_height_m),
        ] {
            if !x.is_finite() {
                out.push(format!("{what} is {x}; it must be finite"));
            }
        }
        if !(self.viewer_distance_m.is_finite() && self.viewer_distance_m > 0.0) {
            out.push(format!("viewer distance is {} m; it must be finite and positive", self.viewer_distance_m));
        } else if self.viewer_distance_m <= self.emitter_z_m {
            out.push(format!(
                "viewer distance {} m is not beyond the emitter plane at z = {} m",
                self.viewer_distance_m, self.emitter_z_m
            ));
        }
        out.extend(self.view_problems());
        if self.channels.is_empty() {
            out.push("there are no colour channels".into());
        }
        let mut last = None;
        for c in &self.channels {
            match CHANNEL_NAMES.iter().position(|n| *n == c.name) {
                None => out.push(format!("colour channel {:?} is not one of R, G, B, Y", c.name)),
                Some(i) if last.is_some_and(|l| i <= l) => {
                    out.push(format!("colour channel {} is repeated or out of the order R, G, B, Y", c.name))
                }
                Some(i) => last = Some(i),
            }
            if !(c.wavelength_m.is_finite() && c.wavelength_m > 100e-9 && c.wavelength_m < 20e-6) {
                out.push(format!("wavelength of channel {} is {} m, outside 100 nm – 20 µm", c.name, c.wavelength_m));
            }
        }
        if self.channels.iter().any(|c| c.name == "Y") && self.channels.len() > 1 {
            out.push("channel Y (one wavelength) cannot be combined with R, G or B".into());
        }
        out
    }

    fn view_problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        let v = &self.views;
        let half_pi = std::f64::consts::FRAC_PI_2;
        let in_range = |t: f64| t.is_finite() && t.abs() < half_pi;
        if let ViewSpacing::Explicit(list) = &v.spacing {
            if list.len() != v.count {
                out.push(format!("{} explicit view angles for {} views", list.len(), v.count));
            }
            if list.iter().any(|t| !in_range(*t)) {
                out.push("an explicit view angle is not finite or not inside (−90°, 90°)".into());
            }
            if list.windows(2).any(|w| w[1] <= w[0]) {
                out.push("explicit view angles are not strictly increasing".into());
            }
            if let (Some(first), Some(last)) = (list.first(), list.last()) {
                if *first != v.first_theta_rad || *last != v.last_theta_rad {
                    out.push("first/last view angle disagree with the explicit list".into());
                }
            }
            return out;
        }
        if !in_range(v.first_theta_rad) || !in_range(v.last_theta_rad) {
            out.push(format!(
                "view angles {} … {} rad are not finite or not inside (−π/2, π/2)",
                v.first_theta_rad, v.last_theta_rad
            ));
        } else if v.count > 1 && v.last_theta_rad <= v.first_theta_rad {
            out.push("the last view angle is not greater than the first".into());
        } else if v.count == 1 && v.last_theta_rad != v.first_theta_rad {
            out.push("a single view must have equal first and last angles".into());
        }
        out
    }
}
