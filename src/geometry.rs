//! The physical geometry of a modulation texture: where hololines and emitters
//! are, where the viewer is, which directions the views point in, and which
//! wavelength each colour channel carries. Coordinates follow docs/optics.md §1.2:
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

/// The directions of the views of every emitter along one axis: the
/// horizontal views (`θ`, positive toward `+x`), or a full-parallax
/// geometry's vertical views (`φ`, positive toward `+y`; spec §8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Views {
    /// Number of views per emitter along the axis.
    pub count: usize,
    /// Direction of view 0, radians from the `z` axis, positive toward `+x`
    /// (vertical views: toward `+y`).
    pub first_theta_rad: f64,
    /// Direction of the last view, radians.
    pub last_theta_rad: f64,
    /// How the views in between are spaced.
    pub spacing: ViewSpacing,
}

impl Views {
    /// Direction of view `v` in radians ([`Views::theta_at`] at `v`).
    pub fn theta_rad(&self, v: usize) -> f64 {
        self.theta_at(v as f64)
    }

    /// Direction in radians of the fractional view index `view_index`
    /// (view `v` at `v as f64`): the spacing rule, the one place it is
    /// written. Between views the rule is followed continuously (an explicit
    /// list linearly, exact at its own angles); beyond the first and last
    /// view it is extended (an explicit list by its end intervals). `sin θ`
    /// is clamped to ±1 before `asin`: a supersampled view half an interval
    /// beyond a last view near 90° is 90°, not NaN.
    pub fn theta_at(&self, view_index: f64) -> f64 {
        if let ViewSpacing::Explicit(list) = &self.spacing {
            return explicit_theta_at(list, view_index).unwrap_or(self.first_theta_rad);
        }
        if self.count <= 1 {
            return self.first_theta_rad;
        }
        let t = view_index / (self.count - 1) as f64;
        let lerp = |a: f64, b: f64| a + (b - a) * t;
        match self.spacing {
            ViewSpacing::Tan => lerp(self.first_theta_rad.tan(), self.last_theta_rad.tan()).atan(),
            ViewSpacing::Sin => lerp(self.first_theta_rad.sin(), self.last_theta_rad.sin()).clamp(-1.0, 1.0).asin(),
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

/// [`Views::theta_at`] for an explicit list: the listed angle at a whole
/// index, linear in between and beyond; `None` for an empty list.
fn explicit_theta_at(list: &[f64], view_index: f64) -> Option<f64> {
    let whole = view_index.floor();
    if whole == view_index && whole >= 0.0 && whole < list.len() as f64 {
        return Some(list[whole as usize]);
    }
    if list.len() < 2 {
        return list.first().copied();
    }
    let i = (whole.max(0.0) as usize).min(list.len() - 2);
    let t = view_index - i as f64;
    Some(list[i] + (list[i + 1] - list[i]) * t)
}

/// A ray of the display (spec/holo-format.md §2): the ray of a sample
/// `(hololine, emitter, view)`, or of a sub-sample between them. It leaves
/// the emitter plane at `origin_m` and travels toward the viewer, `+z`, with
/// direction `(slope_x, slope_y, 1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where it crosses the emitter plane, `(x, y, z_e)` in metres.
    pub origin_m: [f64; 3],
    /// `dx/dz`: `tan θ` of its view.
    pub slope_x: f64,
    /// `dy/dz`: toward the viewer line, which it crosses.
    pub slope_y: f64,
}

impl Ray {
    /// `(slope_x, slope_y, 1)`: its direction, not unit.
    pub fn direction(&self) -> [f64; 3] {
        [self.slope_x, self.slope_y, 1.0]
    }

    /// Its point at depth `z_m`: `origin + (z − z_e) · direction`.
    pub fn at_z(&self, z_m: f64) -> [f64; 3] {
        let dz = z_m - self.origin_m[2];
        [self.origin_m[0] + self.slope_x * dz, self.origin_m[1] + self.slope_y * dz, z_m]
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

/// Largest number of samples of one frame (or one region) holo will
/// allocate: 2³¹ f32 samples, 8 GiB. A geometry's own limit, which the
/// `.holo` reader and writer apply as well (the format module hands it on).
pub const MAX_SAMPLES_PER_FRAME: u64 = 1 << 31;

/// The allowed channel suffixes, in the order channels are kept in memory.
pub const CHANNEL_NAMES: [&str; 4] = ["R", "G", "B", "Y"];

/// Red, green and blue at the HeNe, frequency-doubled Nd:YAG and 445 nm diode
/// lines used by the MIT displays (the public MIT Mark IV code, spec/layouts.md §7.5).
pub fn rgb_channels() -> Vec<ColourChannel> {
    vec![ColourChannel::new("R", 633e-9), ColourChannel::new("G", 532e-9), ColourChannel::new("B", 445e-9)]
}

/// One channel at 633 nm.
pub fn mono_channel() -> Vec<ColourChannel> {
    vec![ColourChannel::new("Y", 633e-9)]
}

/// A length in metres as the millimetres a user types (lengths and scales
/// are typed in millimetres): four significant digits, trailing zeros
/// dropped, without an exponent from 0.001 mm to 10⁹ mm.
pub fn millimetres_text(length_m: f64) -> String {
    let mm = length_m * 1e3;
    if !(mm.abs() >= 1e-3 && mm.abs() < 1e9) {
        return format!("{mm:.3e}");
    }
    let decimals = (3 - mm.abs().log10().floor() as i32).clamp(0, 6) as usize;
    let text = format!("{mm:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
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

/// Horizontal parallax only, or full parallax (spec §8, format 1.3): a 2-D
/// emitter grid whose every emitter has a 2-D grid of views.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Parallax {
    /// One row of emitters per hololine; views vary in `θ` only.
    Horizontal,
    /// A 2-D emitter grid and 2-D views (spec §8): the geometry's
    /// [`Geometry::vertical_views`] are its vertical directions.
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
    /// View directions (horizontal).
    pub views: Views,
    /// Full parallax only: the vertical view directions (`φ`, from `+z`
    /// toward `+y`). `None` for horizontal parallax, whose one vertical
    /// direction is toward the viewer line.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical_views: Option<Views>,
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
    /// Vertical views per emitter, `W`: 1 for horizontal parallax.
    pub fn vertical_view_count(&self) -> usize {
        self.vertical_views.as_ref().map_or(1, |v| v.count)
    }
    /// Views per emitter, `V × W` (`V` for horizontal parallax): the length
    /// of an emitter's run of samples in a [`crate::Modulation`].
    pub fn views_per_emitter(&self) -> usize {
        self.views.count.saturating_mul(self.vertical_view_count())
    }
    /// The index among an emitter's views of horizontal view `h`, vertical
    /// view `k`: `k · V + h` (spec §8, "In memory").
    pub fn view_index(&self, h: usize, k: usize) -> usize {
        k * self.views.count + h
    }
    /// Horizontal and vertical view of an index among an emitter's views
    /// (the inverse of [`Geometry::view_index`]).
    pub fn view_of_index(&self, view: usize) -> (usize, usize) {
        (view % self.views.count, view / self.views.count)
    }
    /// `dy/dz` of every horizontal-parallax ray that leaves the emitter plane
    /// at height `y_m`: they all pass through the viewer line, so
    /// `(y_v − y)/(D − z_e)`.
    pub fn ray_slope_y(&self, y_m: f64) -> f64 {
        (self.viewer_height_m - y_m) / (self.viewer_distance_m - self.emitter_z_m)
    }
    /// `dx/dz` of the rays of a (fractional) view index: `tan θ` of
    /// [`Views::theta_at`].
    pub fn ray_slope_x(&self, view_index: f64) -> f64 {
        self.views.theta_at(view_index).tan()
    }
    /// `dx/dz` of the ray from `x_m` on the emitter plane to the eye at
    /// `eye_x_m` on the viewer line.
    pub fn ray_slope_x_toward(&self, x_m: f64, eye_x_m: f64) -> f64 {
        (eye_x_m - x_m) / (self.viewer_distance_m - self.emitter_z_m)
    }
    /// The ray of sample `(hololine, emitter, view)`: from the emitter, in
    /// the view's direction; toward the viewer line for horizontal parallax,
    /// at its vertical view's `φ` for full parallax (`view` then is
    /// [`Geometry::view_index`] of both).
    pub fn ray(&self, hololine: usize, emitter: usize, view: usize) -> Ray {
        let (h, k) = self.view_of_index(view);
        self.ray_at_views(self.emitter_x_m(emitter), self.hololine_y_m(hololine), h as f64, k as f64)
    }
    /// The ray leaving the emitter plane at `(x_m, y_m)` in the direction of
    /// the fractional horizontal view index `h` and vertical view index `k`
    /// (spec §8: slopes `tan θ_h`, `tan φ_k`); for horizontal parallax `k` is
    /// ignored and the ray goes toward the viewer line ([`Geometry::ray_at`]).
    pub fn ray_at_views(&self, x_m: f64, y_m: f64, h: f64, k: f64) -> Ray {
        match &self.vertical_views {
            None => self.ray_at(x_m, y_m, h),
            Some(vertical) => Ray {
                origin_m: [x_m, y_m, self.emitter_z_m],
                slope_x: self.ray_slope_x(h),
                slope_y: vertical.theta_at(k).tan(),
            },
        }
    }
    /// The horizontal-parallax ray leaving the emitter plane at `(x_m, y_m)`
    /// in the direction of the fractional view index `view_index`: a sub-ray
    /// across an emitter's aperture and a view's interval, toward the viewer
    /// line (full parallax: [`Geometry::ray_at_views`]).
    pub fn ray_at(&self, x_m: f64, y_m: f64, view_index: f64) -> Ray {
        Ray {
            origin_m: [x_m, y_m, self.emitter_z_m],
            slope_x: self.ray_slope_x(view_index),
            slope_y: self.ray_slope_y(y_m),
        }
    }
    /// The stretch of the viewer line the views reach, `(x_min, x_max)` in
    /// metres: where the rays of the first and last emitter in the first
    /// and last view cross it.
    pub fn viewer_line_reach_m(&self) -> (f64, f64) {
        self.reach_at_m(self.viewer_distance_m)
    }
    /// [`Geometry::viewer_line_reach_m`] at distance `z_m` instead of the
    /// viewer's: outside it no view of any emitter arrives.
    pub fn reach_at_m(&self, z_m: f64) -> (f64, f64) {
        let (last_e, last_v) = (self.emitters.saturating_sub(1), self.views.count.saturating_sub(1));
        let reach = [0, last_e].map(|e| [0, last_v].map(|v| self.ray(0, e, v).at_z(z_m)[0]));
        let reach = reach.iter().flatten().copied();
        (reach.clone().fold(f64::INFINITY, f64::min), reach.fold(f64::NEG_INFINITY, f64::max))
    }
    /// Full parallax: the heights `(y_min, y_max)` in metres that the views
    /// reach at distance `z_m`: where the rays of the top and bottom emitter
    /// rows in the lowest and highest vertical views cross it. `None` for
    /// horizontal parallax, whose rays all reach the viewer line's height.
    pub fn vertical_reach_at_m(&self, z_m: f64) -> Option<(f64, f64)> {
        let vertical = self.vertical_views.as_ref()?;
        let (last_j, last_w) = (self.hololines.saturating_sub(1), vertical.count.saturating_sub(1));
        let reach = [0, last_j].map(|j| [0, last_w].map(|w| self.ray(j, 0, self.view_index(0, w)).at_z(z_m)[1]));
        let reach = reach.iter().flatten().copied();
        Some((reach.clone().fold(f64::INFINITY, f64::min), reach.fold(f64::NEG_INFINITY, f64::max)))
    }
    /// Samples in one frame (all channels).
    pub fn samples_per_frame(&self) -> u64 {
        // Saturating: a hostile geometry's product must not wrap to something small.
        (self.channels.len() as u64)
            .saturating_mul(self.hololines as u64)
            .saturating_mul(self.emitters as u64)
            .saturating_mul(self.views.count as u64)
            .saturating_mul(self.vertical_view_count() as u64)
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
            vertical_views: None,
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

    /// This geometry made full parallax (spec §8), `vertical` its vertical
    /// view directions (`φ`, positive toward `+y`); its rays then leave each
    /// emitter in both directions of a view, no longer toward the viewer line.
    pub fn with_vertical_views(mut self, vertical: Views) -> Geometry {
        self.parallax = Parallax::Full;
        self.vertical_views = Some(vertical);
        self
    }

    /// This geometry made full parallax with `count` vertical views,
    /// tan-spaced and centred on the display's normal, over `cone_rad` from
    /// the lowest to the highest (by default the horizontal views' own cone):
    /// what `convert cameras --vertical-views N [--vertical-cone DEG]` asks for.
    pub fn with_centred_vertical_views(self, count: usize, cone_rad: Option<f64>) -> Geometry {
        let half_rad = match cone_rad {
            Some(cone) => 0.5 * cone,
            None => 0.5 * (self.views.theta_rad(self.views.count - 1) - self.views.theta_rad(0)).abs(),
        };
        self.with_vertical_views(Views::tan_spaced(count, -half_rad, half_rad))
    }

    /// [`Geometry::problems`], and a frame larger than a `.holo` frame may
    /// hold: what must hold before a frame of this geometry is allocated (it
    /// could not be written, and would exhaust memory).
    pub fn frame_problems(&self) -> Vec<String> {
        let mut problems = self.problems();
        let samples = self.samples_per_frame();
        if samples > MAX_SAMPLES_PER_FRAME {
            problems.push(format!(
                "a frame of {samples} samples is more than the {} a .holo frame may hold",
                MAX_SAMPLES_PER_FRAME
            ));
        }
        problems
    }

    /// Every rule of spec §4 that concerns the geometry alone; an empty list
    /// means the geometry is valid.
    pub fn problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        match (self.parallax, &self.vertical_views) {
            (Parallax::Full, None) => out.push("full parallax needs vertical view directions".into()),
            (Parallax::Horizontal, Some(_)) => {
                out.push("horizontal parallax has no vertical view directions, but some are given".into())
            }
            (Parallax::Full, Some(vertical)) => {
                if vertical.count == 0 {
                    out.push("vertical view count is zero".into());
                }
                out.extend(view_problems(vertical).into_iter().map(|p| format!("vertical {p}")));
            }
            (Parallax::Horizontal, None) => {}
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
        out.extend(view_problems(&self.views));
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
}

/// The rules of spec §4.1 for one axis of view directions.
fn view_problems(v: &Views) -> Vec<String> {
    let mut out = Vec::new();
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn lengths_are_said_in_the_millimetres_typed() {
        assert_eq!(millimetres_text(0.045), "45");
        assert_eq!(millimetres_text(0.0123456), "12.35");
        assert_eq!(millimetres_text(1.5e-5), "0.015");
        assert_eq!(millimetres_text(2.0), "2000");
        assert_eq!(millimetres_text(-0.25), "-250");
        assert_eq!(millimetres_text(1e-9), "1.000e-6");
        assert_eq!(millimetres_text(f64::NAN), "NaN");
    }

    /// View `v`'s direction from the definition of each spacing: equal
    /// steps of `tan θ`, `sin θ` or `θ` from the first view, or the list.
    fn theta_by_definition(views: &Views, v: usize) -> f64 {
        let n = views.count;
        let (a, b) = (views.first_theta_rad, views.last_theta_rad);
        let steps = |x: fn(f64) -> f64| x(a) + v as f64 * ((x(b) - x(a)) / (n - 1) as f64);
        match &views.spacing {
            ViewSpacing::Explicit(list) => list[v],
            _ if n == 1 => a,
            ViewSpacing::Tan => steps(f64::tan).atan(),
            ViewSpacing::Sin => steps(f64::sin).asin(),
            ViewSpacing::Angle => steps(|t| t),
        }
    }

    #[test]
    fn rays_agree_with_first_principles_on_every_builtin_layout() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(16);
        // (The full-parallax ones' rays: `full_parallax_builtins_…` in layout.)
        for name in crate::layout::BUILTIN {
            let g = crate::layout::builtin(name).unwrap().geometry;
            if g.vertical_views.is_some() {
                continue;
            }
            let (d, z_e) = (g.viewer_distance_m, g.emitter_z_m);
            for _ in 0..2000 {
                let (j, e, v) =
                    (rng.gen_range(0..g.hololines), rng.gen_range(0..g.emitters), rng.gen_range(0..g.views.count));
                let ray = g.ray(j, e, v);
                // It leaves the emitter ...
                let x_e = g.emitter_left_x_m + e as f64 * g.emitter_pitch_m;
                let y_j = g.hololine_top_y_m - j as f64 * g.hololine_pitch_m;
                for (got, want) in ray.origin_m.iter().zip([x_e, y_j, z_e]) {
                    assert!((got - want).abs() < 1e-15, "{name} ({j}, {e}, {v}): origin {:?}", ray.origin_m);
                }
                // ... in the view's direction, to the viewer line.
                let theta = theta_by_definition(&g.views, v);
                let on_viewer_line = [x_e + (d - z_e) * theta.tan(), g.viewer_height_m, d];
                let reached = ray.at_z(d);
                for (got, want) in reached.iter().zip(on_viewer_line) {
                    assert!(
                        (got - want).abs() < 1e-12,
                        "{name} ({j}, {e}, {v}): reaches {reached:?}, not {on_viewer_line:?}"
                    );
                }
                assert!((ray.slope_x.atan() - theta).abs() < 1e-12, "{name} view {v}");
                // A point halfway lies on the same line.
                let half = ray.at_z(0.5 * (z_e + d));
                let between = [0.5 * (x_e + on_viewer_line[0]), 0.5 * (y_j + g.viewer_height_m)];
                assert!((half[0] - between[0]).abs() < 1e-12 && (half[1] - between[1]).abs() < 1e-12);
                // Sub-rays between two views point between them.
                if v + 1 < g.views.count {
                    let f = v as f64 + rng.gen_range(0.0..1.0);
                    let s = g.ray_at(x_e, y_j, f).slope_x;
                    assert!(s >= g.ray_slope_x(v as f64) && s <= g.ray_slope_x((v + 1) as f64), "{name} view {f}");
                }
            }
        }
    }

    #[test]
    fn the_spacing_rule_is_exact_at_the_views_and_never_nan_beyond_them() {
        // The render's sub-views used to clamp sin θ before asin and the
        // views themselves did not: half a view beyond a last view at 89.9°
        // the extrapolated sine is above 1, 90° one way and NaN the other.
        let views =
            Views { count: 5, first_theta_rad: 0.0, last_theta_rad: 89.9f64.to_radians(), spacing: ViewSpacing::Sin };
        assert_eq!(views.theta_at(4.5), std::f64::consts::FRAC_PI_2);
        assert!(views.theta_at(-0.5) < 0.0);
        assert!((views.theta_rad(4) - views.last_theta_rad).abs() < 1e-12);
        // An explicit list: its own angles at whole indices (the last one
        // too, which the interpolation would round), linear between and
        // beyond, and no panic past the end.
        let list = vec![-0.5, -0.21, 0.0, 0.1, 0.3];
        let views = Views {
            count: 5,
            first_theta_rad: -0.5,
            last_theta_rad: 0.3,
            spacing: ViewSpacing::Explicit(list.clone()),
        };
        for (v, t) in list.iter().enumerate() {
            assert_eq!(views.theta_rad(v), *t);
        }
        assert!((views.theta_at(3.5) - 0.2).abs() < 1e-15);
        assert!((views.theta_rad(5) - 0.5).abs() < 1e-15);
        assert!((views.theta_at(-1.0) + 0.79).abs() < 1e-15);
    }
}
